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
import threading
from types import ModuleType
from typing import Any, Sequence

import numpy as np

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


def gauss_legendre(nodes: int) -> tuple[Array, Array]:
    """Gauss–Legendre nodes and weights on [−1, 1], as numpy's ``leggauss`` gives them, by Newton's iteration on
    P_n from the asymptotic guesses x_k = cos(π (k − 1/4)/(n + 1/2)), all nodes at once (the three-term
    recurrence): about 2 ms for 512 nodes where ``leggauss``'s eigensolver takes 0.3-0.6 s of CPU on its threads.
    w_k = 2/((1 − x_k²) P_n'(x_k)²); nodes within a few ulps of ``leggauss``'s, weights to 1e-15 of them."""

    def legendre(x: Array) -> tuple[Array, Array]:  # P_n(x) and P_n'(x)
        p0, p1 = np.ones_like(x), x.copy()
        for j in range(2, nodes + 1):
            p0, p1 = p1, ((2 * j - 1) * x * p1 - (j - 1) * p0) / j
        return p1, nodes * (x * p1 - p0) / (x * x - 1)

    x = np.cos(np.pi * (np.arange(1, nodes + 1) - 0.25) / (nodes + 0.5))
    for _ in range(100):
        value, slope = legendre(x)
        step = value / slope
        x = x - step
        if np.max(np.abs(step)) < 1e-16:
            break
    slope = legendre(x)[1]
    weights: Array = 2 / ((1 - x * x) * slope**2)
    nodes_: Array = x[::-1].copy()
    return nodes_, weights[::-1].copy()


@functools.lru_cache(maxsize=4)
def _legendre(nodes: int) -> tuple[Array, Array]:
    x, w = gauss_legendre(nodes)
    return (x + 1) / 2, w / 2


def t_characteristic(y: Numeric, dof: int) -> Array:
    """Characteristic function of the standard Student-t_ν (ν >= 1) at y >= 0 [-] (a normal term is the sum's c)."""
    z = math.sqrt(dof) * np.abs(np.asarray(y, dtype=float))
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


class SumDistribution:
    """X = Σ a_k T_{ν_k} + c Z for a batch of rows (the a_k and c arrays broadcast together).

    Parameters
    ----------
    t_terms : [(a_k, ν_k)], scale (float or array) and degrees of freedom (0: a normal term)
    normal : c, scale of the normal term (float or array)
    nodes : Gauss–Legendre nodes of the inversion
    """

    def __init__(self, t_terms: Sequence[tuple[Numeric, int]], normal: Numeric = 0.0, nodes: int = NODES):
        arrays = [np.asarray(a, dtype=float) for a, _ in t_terms] + [np.asarray(normal, dtype=float)]
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
        c2 = np.broadcast_to(arrays[-1], shape) ** 2  # normals among the t terms (ν = 0) merged into c
        c2 = sum((np.broadcast_to(a, shape) ** 2 for (_, v), a in zip(t_terms, arrays) if v == 0), c2)
        self.terms = [(np.broadcast_to(a, shape), int(v)) for (_, v), a in zip(t_terms, arrays) if v != 0]
        self.normal = np.sqrt(c2)
        self.shape = self.normal.shape
        self.degenerate = np.broadcast_to(self.total_scale == 0, self.shape)
        with np.errstate(divide="ignore"):  # upper end L of the integral: the fastest-decaying factor negligible
            ends = [np.where(self.normal > 0, _TAIL_NORMAL / self.normal, np.inf)]
            ends += [np.where(a > 0, max(_TAIL / math.sqrt(v), _TAIL_NORMAL) / a, np.inf) for a, v in self.terms]
        end = np.where(self.degenerate, 1.0, np.min(np.stack(ends), axis=0))
        u, w = _legendre(nodes)
        self.s = end[..., None] * u  # rows × nodes
        self.w = end[..., None] * w
        self.phi = np.exp(-0.5 * (self.normal[..., None] * self.s) ** 2)  # φ(s) of the sum on the nodes
        for a, dof in self.terms:
            self.phi = self.phi * t_characteristic(a[..., None] * self.s, dof)

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
        inner = (p > 0) & (p < 1)
        q = np.where(inner, p, 0.5)  # the ends' rows are searched at the median, then replaced
        sp = _special()
        k = len(self.terms) + 1
        # P(X > x) <= Σ P(term_k > x_k) with Σ x_k = x: each term at its 1 − (1 − p)/k quantile
        tail = np.minimum(q, 1 - q)
        hi = self.normal * sp.ndtri(1 - tail / k)
        for a, dof in self.terms:
            hi = hi + a * sp.stdtrit(dof, 1 - tail / k)
        lo = -hi
        x = np.zeros(self.shape)
        for _ in range(100):
            f = self.cdf(x) - q
            lo, hi = np.where(f < 0, x, lo), np.where(f < 0, hi, x)
            step = f / np.maximum(self.pdf(x), 1e-300)
            new = x - step
            outside = ~((new > lo) & (new < hi))
            new = np.where(outside, (lo + hi) / 2, new)
            done = (np.abs(new - x) <= tol * np.maximum(1.0, np.abs(x))) | (hi - lo <= tol)
            x = new
            if np.all(done | self.degenerate | ~inner):
                break
        out: Array = np.where(self.degenerate, 0.0, x)
        edge = np.where((p < 0) | (p > 1) | ~np.isfinite(p), np.nan, np.where(p >= 1, np.inf, -np.inf))
        return np.where(inner, out, edge)


TABLE_NODES = 1024
"""Intervals of a tabulated CDF (:class:`CdfTable`): quintic Hermite on them is within 1e-15 of the inversion."""

TABLE_REACH = 20.0
"""A tabulated CDF covers |x| <= this many total scales (beyond it, and for a few points, the inversion itself)."""

TABLE_MIN_POINTS = 256
"""Points of one law in one call from which its table is built (the table costs about 2000 points' inversions,
repaid within a root search's dozen calls); a table built once serves every later call (:func:`tabled_cdf`)."""


class CdfTable:
    """The CDF of one sum X = Σ a_k T_{ν_k} + c Z tabulated for fast evaluation at many points [-].

    F, F' and F'' in θ = arctan(x/λ) (λ the total scale, :attr:`SumDistribution.total_scale`) on
    :data:`TABLE_NODES` equal intervals of |x| <= :data:`TABLE_REACH` λ, from the inversion (F, the density f and
    its slope f' = −(1/π) ∫ s sin(s x) φ(s) ds); quintic Hermite interpolation between them.  The map packs the
    nodes where F bends; on the laws of the shipped problems the table is within 1e-15 of the inversion
    (tests/physics/test_batched_law.py), the inversion's own accuracy being about 1e-13.
    """

    def __init__(self, dist: SumDistribution):
        if dist.shape != ():
            raise ValueError(f"CdfTable: one law at a time, got {dist.shape} rows")
        self.scale = float(dist.total_scale)
        self.top = math.atan(TABLE_REACH)
        # X is symmetric (every term is): F(−x) = 1 − F(x), so the nodes θ >= 0 are inverted and mirrored
        theta = np.linspace(0.0, self.top, TABLE_NODES // 2 + 1)
        x = self.scale * np.tan(theta)
        sx = x[:, None] * dist.s
        sine, cosine = np.sin(sx), np.cos(sx)
        f = cosine @ (dist.phi * dist.w) / math.pi
        slope = -(sine @ (dist.s * dist.phi * dist.w)) / math.pi
        dx = self.scale / np.cos(theta) ** 2  # dx/dθ
        d2x = 2 * x / np.cos(theta) ** 2  # d²x/dθ²
        self.step = 2 * self.top / TABLE_NODES
        values = np.clip(0.5 + sine @ dist._sine_weights, 0.0, 1.0)
        first = f * dx * self.step  # F' h (even in θ)
        second = (slope * dx**2 + f * d2x) * self.step**2  # F'' h² (odd in θ)
        self.values = np.concatenate([1.0 - values[:0:-1], values])
        self.first = np.concatenate([first[:0:-1], first])
        self.second = np.concatenate([-second[:0:-1], second])

    def __call__(self, x: Array) -> Array:
        """F at points ``x`` the table covers [-] (quintic Hermite in θ)."""
        t = (np.arctan(x / self.scale) + self.top) / self.step
        k = np.clip(t.astype(int), 0, TABLE_NODES - 1)
        s = t - k
        s2 = s * s
        s3 = s2 * s
        r = 1 - s
        r3 = r * r * r
        # the quintic Hermite basis on [0, 1] (values, slopes, curvatures at both ends)
        h0 = r3 * (1 + 3 * s + 6 * s2)
        h1 = r3 * s * (1 + 3 * s)
        h2 = 0.5 * r3 * s2
        g0 = s3 * (10 - 15 * s + 6 * s2)
        g1 = s3 * (-4 + 7 * s - 3 * s2)
        g2 = 0.5 * s3 * r * r
        v, d1, d2 = self.values, self.first, self.second
        out: Array = h0 * v[k] + h1 * d1[k] + h2 * d2[k] + g0 * v[k + 1] + g1 * d1[k + 1] + g2 * d2[k + 1]
        return out


_TABLES: dict[tuple[Any, ...], CdfTable] = {}
"""The tables built so far, by law (:func:`tabled_cdf`; a few dozen at most: one per wheel size and kind)."""

_TABLES_KEPT = 64
_TABLES_LOCK = threading.Lock()


def tabled_cdf(dist: SumDistribution, x: Array, min_points: int = TABLE_MIN_POINTS) -> Array:
    """F_i(x_ij) of each row i of ``dist`` (1-D rows) at its points x_ij (rows × points) [-].

    Rows that share a law share a :class:`CdfTable` when they bring at least ``min_points`` points or the law's
    table exists already; other rows, and points beyond a table's reach, are inverted directly
    (:meth:`SumDistribution.cdf`).  The same values as the inversion to about 1e-15.
    """
    rows, points = x.shape
    out = np.empty((rows, points))
    params = np.stack([a for a, _ in dist.terms] + [dist.normal], axis=-1).reshape(rows, -1)
    dofs = tuple(dof for _, dof in dist.terms)
    laws, which = np.unique(params, axis=0, return_inverse=True)
    which = which.reshape(-1)
    direct = np.zeros(x.shape, dtype=bool)
    for g, law in enumerate(laws):
        members = np.flatnonzero(which == g)
        key = (dofs, *law.tolist())
        table = _TABLES.get(key)
        if table is None and members.size * points >= min_points and not dist.degenerate[members[0]]:
            one = SumDistribution(list(zip(law[:-1].tolist(), dofs)), float(law[-1]))
            table = CdfTable(one)
            with _TABLES_LOCK:  # the studio's threads share the tables
                while len(_TABLES) >= _TABLES_KEPT:
                    _TABLES.pop(next(iter(_TABLES)))
                _TABLES[key] = table
        if table is None:
            direct[members] = True
            continue
        mine = x[members]
        covered = np.abs(mine) <= TABLE_REACH * table.scale  # the points the table covers
        out[members] = np.where(covered, table(np.where(covered, mine, 0.0)), 0.0)
        direct[members] = ~covered
    i, j = np.nonzero(direct)
    step = max(1, (1 << 20) // dist.s.shape[-1])
    for start in range(0, i.size, step):
        part = slice(start, start + step)
        out[i[part], j[part]] = dist.cdf(x[i[part], j[part]], rows=i[part])  # type: ignore[arg-type]
    return out
