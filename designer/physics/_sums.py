"""A sum of independent scaled Student-t and normal variables: CDF, density and quantile, numerically exact.

    X = Σ_k a_k T_{ν_k} + c Z        (T_ν standard Student-t, Z standard normal, a_k, c >= 0)

The characteristic function of T_ν is φ_ν(s) = 2^{1−ν/2}/Γ(ν/2) · y^{ν/2} K_{ν/2}(y), y = √ν |s|
(K the modified Bessel function of the second kind; e^{−s²/2} for the normal), so X's is the product
φ(s) = Π_k φ_{ν_k}(a_k s) · e^{−c² s²/2}, real and even.  Gil-Pelaez inversion gives

    F(x) = 1/2 + (1/π) ∫_0^∞ sin(s x) φ(s) / s ds,      f(x) = (1/π) ∫_0^∞ cos(s x) φ(s) ds,

integrated by Gauss–Legendre on [0, L] with L where the slowest-decaying factor of φ is below 1e-17
(the integrand is analytic there for odd ν and has an s^ν log s term at 0 for even ν; 512 nodes give
the CDF to about 1e-13, tests/physics/test_uncertainty.py compares with 1024 nodes and with sampling).
The quantile is found by Newton steps on F − p inside a bracket (bisection when a step leaves it).

Only ``scipy.special`` is used (``kve``, ``gammaln`` for an even or large ν; ``stdtrit``, ``ndtri`` for the
quantile's bracket), loaded on first use; an odd ν up to 41 has an elementary φ (:func:`_odd_t_characteristic`).
"""

from __future__ import annotations

import functools
import math
from types import ModuleType
from typing import Sequence

import numpy as np
from numpy.polynomial.legendre import leggauss

from designer.physics.types import Array, Numeric

NODES = 512
"""Gauss–Legendre nodes of the inversion integral."""

_TAIL = 45.0
"""−log of the size below which φ's factor is dropped: the range ends where √ν a s = 45 (t) ..."""
_TAIL_NORMAL = 9.5
"""... or c s = 9.5 (normal: e^{−45}); for a t with large ν the normal-like range c s = 9.5 is kept."""


def _special() -> ModuleType:
    import scipy.special

    module: ModuleType = scipy.special
    return module


@functools.lru_cache(maxsize=4)
def _legendre(nodes: int) -> tuple[Array, Array]:
    x, w = leggauss(nodes)
    return (x + 1) / 2, w / 2


def t_characteristic(y: Numeric, dof: int) -> Array:
    """Characteristic function of the standard Student-t_ν at y >= 0 (ν = 0: the standard normal) [-]."""
    y = np.abs(np.asarray(y, dtype=float))
    if dof == 0:
        out: Array = np.exp(-0.5 * y**2)
        return out
    z = math.sqrt(dof) * y
    if dof % 2 == 1 and dof <= ODD_CLOSED_FORM:
        return _odd_t_characteristic(np.asarray(z, dtype=float), dof)
    sp = _special()
    half = dof / 2
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        log_phi = (1 - half) * math.log(2) - sp.gammaln(half) + half * np.log(z) + np.log(sp.kve(half, z)) - z
        phi = np.exp(log_phi)
    out = np.where(z == 0, 1.0, np.nan_to_num(phi, nan=0.0, posinf=0.0))
    return out


ODD_CLOSED_FORM = 41
"""Largest odd ν whose characteristic function is written in closed form (its factorials stay well inside a
float; larger or even ν go through scipy.special's Bessel function)."""


def _odd_t_characteristic(z: Array, dof: int) -> Array:
    """φ_ν at z = √ν |s| for odd ν = 2m + 1, where K_{m+1/2} is elementary [-]:

        φ_ν = 2^m m! / (2m)! · e^{−z} Σ_{k=0}^{m} (m + k)! / (k! (m − k)!) 2^{−k} z^{m−k}

    (ν = 1: e^{−z}, the Cauchy's; ν = 3: e^{−z} (1 + z); ν = 5: e^{−z} (1 + z + z²/3)), so the main job's
    t_5 laws need no Bessel function and no scipy import (tests/physics compare with scipy.special.kve)."""
    m = (dof - 1) // 2
    lead = 2.0**m * math.factorial(m) / math.factorial(2 * m)
    poly = np.zeros_like(z)
    for k in range(m + 1):  # Horner in z from the highest power z^m (k = 0) down
        coefficient = math.factorial(m + k) / (math.factorial(k) * math.factorial(m - k)) / 2.0**k
        poly = poly * z + coefficient
    out: Array = lead * poly * np.exp(-z)
    return out


def _as_terms(t_terms: Sequence[tuple[Numeric, int]], normal: Numeric) -> tuple[list[tuple[Array, int]], Array]:
    """Normals among the t terms (ν = 0) merged into c; arrays broadcast to one shape."""
    arrays = [np.asarray(a, dtype=float) for a, _ in t_terms] + [np.asarray(normal, dtype=float)]
    shape = np.broadcast_shapes(*(a.shape for a in arrays))
    c2 = np.broadcast_to(arrays[-1], shape) ** 2
    terms = []
    for (_, dof), a in zip(t_terms, arrays[:-1]):
        a = np.broadcast_to(a, shape)
        if dof == 0:
            c2 = c2 + a**2
        else:
            terms.append((a, int(dof)))
    return terms, np.sqrt(c2)


def _range(terms: list[tuple[Array, int]], c: Array) -> Array:
    """Upper end L of the inversion integral per row: where the fastest-decaying factor is negligible."""
    with np.errstate(divide="ignore"):
        ends = [np.where(c > 0, _TAIL_NORMAL / c, np.inf)]
        for a, dof in terms:
            ends.append(np.where(a > 0, max(_TAIL / math.sqrt(dof), _TAIL_NORMAL) / a, np.inf))
    end: Array = np.min(np.stack(ends), axis=0)
    return end


def _characteristic(s: Array, terms: list[tuple[Array, int]], c: Array) -> Array:
    """φ(s) of the sum on the nodes s (rows × nodes)."""
    phi = np.exp(-0.5 * (c[..., None] * s) ** 2)
    for a, dof in terms:
        phi = phi * t_characteristic(a[..., None] * s, dof)
    return phi


class SumDistribution:
    """X = Σ a_k T_{ν_k} + c Z for a batch of rows (the a_k and c arrays broadcast together).

    Parameters
    ----------
    t_terms : [(a_k, ν_k)], scale (float or array) and degrees of freedom (0: a normal term)
    normal : c, scale of the normal term (float or array)
    nodes : Gauss–Legendre nodes of the inversion
    """

    def __init__(self, t_terms: Sequence[tuple[Numeric, int]], normal: Numeric = 0.0, nodes: int = NODES):
        self.terms, self.normal = _as_terms(t_terms, normal)
        self.shape = self.normal.shape
        self.degenerate = np.broadcast_to(self.total_scale == 0, self.shape)
        end = np.where(self.degenerate, 1.0, _range(self.terms, self.normal))
        u, w = _legendre(nodes)
        self.s = end[..., None] * u  # rows × nodes
        self.w = end[..., None] * w
        self.phi = _characteristic(self.s, self.terms, self.normal)

    @property
    def total_scale(self) -> Array:
        """√(Σ a_k² + c²) [-] (not the standard deviation: a t's variance is a² ν/(ν − 2))."""
        total: Array = np.sqrt(sum((a**2 for a, _ in self.terms), self.normal**2))
        return total

    @functools.cached_property
    def _sine_weights(self) -> Array:
        """w φ(s) / (π s) on the nodes (rows × nodes): F(x) = 1/2 + Σ_k sin(s_k x) · this."""
        weights: Array = self.phi * self.w / (math.pi * self.s)
        return weights

    def cdf(self, x: Numeric, rows: slice | None = None) -> Array:
        """P(X <= x) per row: ``x`` broadcasts with the rows, or has one more trailing axis (several x per row).

        ``rows``: a slice of the first axis of a batch (``x`` then goes with those rows only)."""
        x = np.asarray(x, dtype=float)
        degenerate, s, weights = self.degenerate, self.s, self._sine_weights
        if rows is not None:
            degenerate, s, weights = degenerate[rows], s[rows], weights[rows]
        several = x.ndim > degenerate.ndim
        xs = x if several else np.broadcast_to(x, degenerate.shape)[..., None]
        s, weights = s[..., None, :], weights[..., :, None]
        value = 0.5 + np.matmul(np.sin(s * xs[..., None]), weights)[..., 0]
        value = np.where(degenerate[..., None], (xs >= 0).astype(float), value)
        out: Array = np.clip(value if several else value[..., 0], 0.0, 1.0)
        return out

    def pdf(self, x: Numeric) -> Array:
        """Density of X at x per row (rows without scatter: nan)."""
        x = np.asarray(x, dtype=float)
        value = np.sum(np.cos(self.s * x[..., None]) * self.phi * self.w, axis=-1) / math.pi
        out: Array = np.where(self.degenerate, np.nan, value)
        return out

    def quantile(self, probability: Numeric, tol: float = 1e-13) -> Array:
        """x with P(X <= x) = probability per row, Newton in a bisection bracket (±inf at probability 1 or 0, which
        a probability within 1e-16 of either end rounds to; nan for one outside [0, 1])."""
        p = np.broadcast_to(np.asarray(probability, dtype=float), self.shape)
        ends = (p <= 0) | (p >= 1) | ~np.isfinite(p)
        if np.any(ends):
            edge: Array = np.where(p >= 1, np.inf, -np.inf)
            edge = np.where((p < 0) | (p > 1) | ~np.isfinite(p), np.nan, edge)
            inner = ~ends
            if np.any(inner):
                sub = SumDistribution.__new__(SumDistribution)
                sub.terms = [(np.broadcast_to(a, self.shape)[inner], dof) for a, dof in self.terms]
                sub.normal = np.broadcast_to(self.normal, self.shape)[inner]
                sub.shape = sub.normal.shape
                sub.degenerate = self.degenerate[inner]
                sub.s, sub.w, sub.phi = self.s[inner], self.w[inner], self.phi[inner]
                edge[inner] = sub.quantile(p[inner], tol)
            return edge
        sp = _special()
        k = len(self.terms) + 1
        # P(X > x) <= Σ P(term_k > x_k) with Σ x_k = x: each term at its 1 − (1 − p)/k quantile
        tail = np.minimum(p, 1 - p)
        hi = self.normal * sp.ndtri(1 - tail / k)
        for a, dof in self.terms:
            hi = hi + a * sp.stdtrit(dof, 1 - tail / k)
        lo = -hi
        x = np.zeros(self.shape)
        for _ in range(100):
            f = self.cdf(x) - p
            lo, hi = np.where(f < 0, x, lo), np.where(f < 0, hi, x)
            step = f / np.maximum(self.pdf(x), 1e-300)
            new = x - step
            outside = ~((new > lo) & (new < hi))
            new = np.where(outside, (lo + hi) / 2, new)
            done = (np.abs(new - x) <= tol * np.maximum(1.0, np.abs(x))) | (hi - lo <= tol)
            x = new
            if np.all(done | self.degenerate):
                break
        out: Array = np.where(self.degenerate, 0.0, x)
        return out


def sum_cdf(x: Numeric, t_terms: Sequence[tuple[Numeric, int]], normal: Numeric = 0.0) -> Array:
    """P(Σ a_k T_{ν_k} + c Z <= x) (arrays broadcast) [-]."""
    return SumDistribution(t_terms, normal).cdf(x)


def sum_quantile(probability: Numeric, t_terms: Sequence[tuple[Numeric, int]], normal: Numeric = 0.0) -> Array:
    """The ``probability``-quantile of Σ a_k T_{ν_k} + c Z (arrays broadcast) [-]."""
    return SumDistribution(t_terms, normal).quantile(probability)
