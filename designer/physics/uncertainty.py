"""Scatter of the shimmy model and the probability of shimmy (the risk bound).

Eq. 7 rests on fitted constants with scatter: M_f/θ0 = 1.3 is a fit to
scattered data (Fig. 2C), Table 1 shows Eq. 7 within about ±15 % of the
measured critical speeds (RMS 10.3 %), and K_s, I_w vary from tyre to tyre.
The true critical speed is modelled as

    log V_c,true = log V_c(x; c_f e^{ξ_c}, K_s e^{ξ_K}, I_w e^{ξ_I}) + σ_m t_ν

with ξ_p ~ N(0, σ_p²) independent (σ of the log of each constant) and the
model error σ_m t_ν a Student-t with ν degrees of freedom and scale σ_m.

Why Student-t: σ_m = 0.103 is the RMS error of Eq. 7 over the five Table 1
wheels C–G, which were not used to fit Eq. 7 (its constants come from Fig. 2C
and Appendix C), so the residuals have a known mean of zero and the RMS is an
estimate of σ on ν = 5 degrees of freedom.  With the usual non-informative
prior the predictive distribution of the next wheel's log error is then
σ̂ t_5 (scale = the RMS): a 95 % quantile 2.015 σ̂ instead of 1.645 σ̂ for
a normal.  ``model_error_dof = 0`` gives the normal model error.

The deterministic bound.  log V_c,true − log V_c(x) is, to first order in
the ξ_p, X = σ_m t_ν + σ_r Z with Z standard normal and

    σ_r(x)² = (e_c σ_c)² + (e_K σ_K)² + (σ_I/2)²

(elasticities e of Eq. 7, :func:`designer.physics.shimmy.critical_speed_log_sensitivities`).
This is exact for I_w and the model error (log V_c is linear in their logs)
and conservative for c_f and K_s: log V_c = ½ log(a e^{ξ_c} + b e^{ξ_K}) is
convex in (ξ_c, ξ_K) (log-sum-exp), so it lies above its tangent plane and the
true speed is never lower than the first-order one.  The risk bound
P(V_c,true < V_req) <= α therefore holds when

    V_q(x) = V_c(x) · exp(−Q_{1−α}(σ_m, σ_r(x))) >= V_req,

Q the exact (1 − α)-quantile of X (a t-plus-normal convolution computed by
quadrature once per (α, ν) and represented by a Chebyshev fit in the normal
share s = σ_r²/(σ_m² + σ_r²), shifted up by its largest fit error so it never
lies below the exact quantile).  V_q works on floats, NumPy arrays and CasADi
symbols, so the NLP, the GP's bound and the stock screening use the same
function.  (The simpler root-sum-square of the t and normal quantiles is up to
0.7 % too small in Q for s ≈ 0.7: not conservative.)

:func:`shimmy_probability_mc` samples exactly this distribution (Student-t
model error, lognormal c_f, K_s, I_w) on the exact Eq. 7 with its own seed.

Only ``scipy.special`` is used: ``scipy.stats`` costs 0.7 s of import time.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

from designer.physics.types import Array, Numeric, Scalar
from designer.physics.shimmy import critical_shimmy_speed, critical_speed_log_sensitivities
from numpy.polynomial.hermite_e import hermegauss
from numpy.polynomial.legendre import leggauss
from numpy.polynomial import chebyshev as C


def _special() -> ModuleType:
    # late import: scipy.special costs about 0.3 s of CPU, paid at the first quantile, not by `import designer`
    import scipy.special

    module: ModuleType = scipy.special
    return module


def ndtr(x: Numeric) -> Numeric:
    """Standard normal CDF (scipy.special.ndtr, loaded on first use)."""
    value: Numeric = _special().ndtr(x)
    return value


def ndtri(p: Numeric) -> Numeric:
    """Standard normal quantile (scipy.special.ndtri, loaded on first use)."""
    value: Numeric = _special().ndtri(p)
    return value


def stdtr(dof: int, t: Numeric) -> Numeric:
    """Student-t CDF (scipy.special.stdtr, loaded on first use)."""
    value: Numeric = _special().stdtr(dof, t)
    return value


def stdtrit(dof: int, p: Numeric) -> Numeric:
    """Student-t quantile (scipy.special.stdtrit, loaded on first use)."""
    value: Numeric = _special().stdtrit(dof, p)
    return value


TABLE1_RMS_ERROR = 0.103
"""RMS relative error of Eq. 7 against Table 1 wheels C–G (computed in check 2: 10.3 %)."""

TABLE1_DOF = 5
"""Degrees of freedom of the model-error estimate: 5 wheels (C–G), zero mean known (Eq. 7 not fitted to them)."""

MC_SEED = 20111
"""Seed of the reported Monte Carlo estimate (separate from anything that ranks or screens designs)."""

MC_SAMPLES = 50_000
"""Least Monte Carlo sample of a reported P(shimmy) (SE 0.097 percentage points at 5 %)."""

MC_TARGET_SE = 0.001
"""Standard error [-] a reported P(shimmy) must reach: more samples are drawn until it does (0.1 pp)."""

MC_MAX_SAMPLES = 4_000_000
"""Largest Monte Carlo sample drawn to reach :data:`MC_TARGET_SE` (memory grows with it)."""


@dataclass(frozen=True)
class Uncertainty:
    """Scatter of the shimmy model's constants and the allowed probability of shimmy.

    Attributes
    ----------
    probability : α, the largest allowed probability that V_c,true < V_req [-]
    model_error : scale σ_m of the model error log(V_c,measured / V_c,Eq.7) [-]; default the Table 1 RMS, 0.103
    damping : σ of log(M_f/θ0) [-] (scatter of the Eq. 11C fit)
    slip_coefficient : σ of log K_s [-]
    inertia : σ of log I_w [-] (wheel-to-wheel variation around the inertia model)
    model_error_dof : ν of the Student-t model error (5: Table 1 wheels C–G); 0 = normal
    samples : least Monte Carlo sample of a reported probability (more are drawn for SE <= 0.1 pp)
    seed : seed of the reported Monte Carlo estimate
    """

    probability: float = 0.05
    model_error: float = TABLE1_RMS_ERROR
    damping: float = 0.10
    slip_coefficient: float = 0.20
    inertia: float = 0.10
    model_error_dof: int = TABLE1_DOF
    samples: int = MC_SAMPLES
    seed: int = MC_SEED

    @property
    def z(self) -> float:
        """Standard normal quantile z_{1−α} [-]."""
        return float(ndtri(1 - self.probability))

    @property
    def t(self) -> float:
        """Quantile t_{ν,1−α} of the model error's Student-t (z_{1−α} when ν = 0) [-]."""
        return self.z if not self.model_error_dof else float(stdtrit(self.model_error_dof, 1 - self.probability))

    def describe(self) -> str:
        """One line: α and the scatter (for reports and messages)."""
        dist = f"Student-t ν = {self.model_error_dof}" if self.model_error_dof else "normal"
        return (
            f"P(shimmy) <= {self.probability:.3g}; σ of the log: model error {self.model_error:g} ({dist}), "
            f"M_f/θ0 {self.damping:g}, K_s {self.slip_coefficient:g}, I_w {self.inertia:g}"
        )


# --------------------------------------------------------------------------- t + normal quantile

_NODES = 64


@functools.lru_cache(maxsize=8)
def _quadrature(dof: int) -> tuple[Array, Array, Numeric, Array]:

    zn, zw = hermegauss(_NODES)
    un, uw = leggauss(4 * _NODES)
    u = (un + 1) / 2
    return zn, zw / math.sqrt(2 * math.pi), stdtrit(dof, u), uw / 2


def _sum_cdf(x: Numeric, share: Numeric, dof: int) -> Array:
    """P(√(1−s) t_ν + √s Z <= x) by quadrature (numeric arrays of equal shape) [-]."""
    x = np.asarray(x, float)
    s = np.asarray(share, float)
    a, b = np.sqrt(1 - s), np.sqrt(s)
    zn, zw, tn, tw = _quadrature(dof)
    out = np.empty(np.broadcast(x, s).shape)
    x, a, b, s = np.broadcast_arrays(x, a, b, s)
    lo = s <= 0.5
    if lo.any():  # integrate over Z: the t CDF is smooth in it
        out[lo] = (zw * stdtr(dof, (x[lo, None] - b[lo, None] * zn) / a[lo, None])).sum(-1)
    hi = ~lo
    if hi.any():  # integrate over t (in probability space): the normal CDF is smooth in it
        out[hi] = (tw * ndtr((x[hi, None] - a[hi, None] * tn) / b[hi, None])).sum(-1)
    return out


def exact_sum_quantile(share: Numeric, probability: float, dof: int) -> Array:
    """(1 − α)-quantile of √(1−s) t_ν + √s Z, by quadrature and bisection [-] (numeric only).

    The reference for :func:`log_speed_quantile`'s fit (and its tests).
    """
    s = np.atleast_1d(np.asarray(share, float))
    level = 1 - probability
    lo = np.full(s.shape, float(ndtri(level)) * 0.5)
    hi = np.full(s.shape, float(stdtrit(dof, level)) + float(ndtri(level)))
    for _ in range(48):
        mid = (lo + hi) / 2
        below = _sum_cdf(mid, s, dof) < level
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    quantile: Array = (lo + hi) / 2
    return quantile


_DEGREE = 14

_STORED_FITS: dict[tuple[float, int, int, int], tuple[tuple[float, ...], float]] = {
    # (α, ν, _NODES, _DEGREE): the Chebyshev coefficients and the shift _compute_fit returns, written out with
    # repr (exact round trip) so the main job needn't redo the quadrature (about 0.1-0.3 s of CPU, mostly
    # the threaded eigensolver of leggauss(256)); tests/physics/test_uncertainty.py recomputes them
    (0.05, 5, 64, 14): (
        (
            1.8398610952279133,
            -0.18098169715082657,
            -0.009025512044237132,
            -0.003897747202272107,
            -0.0007983692780797318,
            -0.0001956947453690319,
            -7.673162625049496e-05,
            -2.440348703130868e-05,
            -7.955245488684818e-06,
            -2.37014651708665e-06,
            -2.7185077619810214e-08,
            7.931278508456347e-07,
            9.74699486609848e-07,
            8.165543077358258e-07,
            4.564530635257894e-07,
        ),
        5.740555803074836e-06,
    ),
}


def _compute_fit(probability: float, dof: int) -> tuple[npt.NDArray[np.floating[Any]], float]:
    """Chebyshev coefficients (on s ∈ [0, 1]) of the quantile, shifted up by its fit error; and the shift."""

    k = np.arange(_DEGREE + 1)
    nodes = (np.cos(np.pi * (k + 0.5) / (_DEGREE + 1))[::-1] + 1) / 2
    check = np.linspace(0, 1, 4 * _DEGREE + 1)
    s = np.concatenate([nodes, check])
    q = exact_sum_quantile(s, probability, dof)
    q[s == 1.0] = float(ndtri(1 - probability))
    coef = C.chebfit(2 * nodes - 1, q[: len(nodes)], _DEGREE)
    error = q - C.chebval(2 * s - 1, coef)
    shift = max(0.0, float(error.max())) + 1e-9
    coef = coef.copy()
    coef[0] += shift
    return coef, shift


@functools.lru_cache(maxsize=32)
def _fit(probability: float, dof: int) -> tuple[npt.NDArray[np.floating[Any]], float]:
    """:func:`_compute_fit`, read from :data:`_STORED_FITS` for the default α and ν (the same numbers)."""
    stored = _STORED_FITS.get((probability, dof, _NODES, _DEGREE))
    if stored is None:
        return _compute_fit(probability, dof)
    coef = np.array(stored[0], dtype=float)
    coef.setflags(write=False)
    return coef, stored[1]


def _clenshaw(coef: npt.NDArray[np.floating[Any]], x: Scalar) -> Scalar:
    """Σ c_k T_k(x) by Clenshaw's recurrence (floats, arrays, CasADi symbols)."""
    b1 = 0 * x
    b2 = 0 * x
    for c in coef[:0:-1]:
        b1, b2 = 2 * x * b1 - b2 + float(c), b1
    return x * b1 - b2 + float(coef[0])


def log_speed_quantile(sigma_model: float, sigma_rest: Scalar, uncertainty: Uncertainty) -> Scalar:
    """Q_{1−α}(σ_m t_ν + σ_r Z): how far log V_c must exceed log V_req for the risk bound [-].

    Parameters
    ----------
    sigma_model : σ_m, scale of the Student-t model error [-] (a number)
    sigma_rest : σ_r of the normal first-order rest [-] (float, array or CasADi symbol)
    uncertainty : α and ν

    Exact up to the fit, never below the exact quantile (the fit is shifted up by its error,
    ≈1e-7).  Increasing in σ_r.  ν = 0 or σ_m = 0: the normal quantile z √(σ_m² + σ_r²).
    """
    u = uncertainty
    sm = float(sigma_model)
    if not u.model_error_dof or sm == 0:
        return u.z * np.sqrt(sm**2 + sigma_rest**2)
    total = sm**2 + sigma_rest**2
    share = sigma_rest**2 / total
    coef, _ = _fit(float(u.probability), int(u.model_error_dof))
    return np.sqrt(total) * _clenshaw(coef, 2 * share - 1)


def rest_log_std(
    trail: Scalar, inertia: Scalar, groove: Scalar, damping: Scalar, slip_coefficient: Scalar, uncertainty: Uncertainty
) -> Scalar:
    """σ_r: standard deviation of the first-order normal part of log V_c,true (c_f, K_s, I_w) [-]."""
    e = critical_speed_log_sensitivities(trail, inertia, groove, damping, slip_coefficient)
    u = uncertainty
    variance = (
        (e["damping"] * u.damping) ** 2
        + (e["slip_coefficient"] * u.slip_coefficient) ** 2
        + (e["inertia"] * u.inertia) ** 2
    )
    return np.sqrt(variance)


def log_speed_std(
    trail: Scalar, inertia: Scalar, groove: Scalar, damping: Scalar, slip_coefficient: Scalar, uncertainty: Uncertainty
) -> Scalar:
    """Standard deviation of log V_c,true to first order [-] (the t part counted by its scale σ_m)."""
    rest = rest_log_std(trail, inertia, groove, damping, slip_coefficient, uncertainty)
    return np.sqrt(uncertainty.model_error**2 + rest**2)


def shimmy_speed_quantile(
    trail: Scalar, inertia: Scalar, groove: Scalar, damping: Scalar, slip_coefficient: Scalar, uncertainty: Uncertainty
) -> Scalar:
    """The speed reached with probability 1 − α: V_q = V_c(x) exp(−Q_{1−α}(σ_m, σ_r(x))) [m/s].

    Eq. 7 for V_c; the risk bound is ``V_q >= V_req`` and then P(V_c,true < V_req) <= α
    (exact for model error and I_w, conservative for c_f and K_s: see the module text).
    Works on floats, NumPy arrays and CasADi symbols.
    """
    v = critical_shimmy_speed(trail, inertia, groove, damping, slip_coefficient)
    rest = rest_log_std(trail, inertia, groove, damping, slip_coefficient, uncertainty)
    return v * np.exp(-log_speed_quantile(uncertainty.model_error, rest, uncertainty))


def shimmy_probability_first_order(
    trail: float,
    inertia: float,
    groove: float,
    damping: float,
    slip_coefficient: float,
    speed: float,
    uncertainty: Uncertainty,
) -> float:
    """P(log V_c + σ_m t_ν + σ_r Z < log speed): the probability the deterministic bound controls [-]."""
    u = uncertainty
    v = float(critical_shimmy_speed(trail, inertia, groove, damping, slip_coefficient))
    rest = float(rest_log_std(trail, inertia, groove, damping, slip_coefficient, u))
    gap = math.log(speed) - math.log(v)
    total = math.sqrt(u.model_error**2 + rest**2)
    if total == 0:
        return float(gap > 0)
    if not u.model_error_dof or u.model_error == 0:
        return float(ndtr(gap / total))
    return float(_sum_cdf(np.array([gap / total]), np.array([rest**2 / total**2]), int(u.model_error_dof))[0])


def sample_log_factors(uncertainty: Uncertainty, n: int, rng: np.random.Generator) -> dict[str, Array]:
    """``n`` draws of the log factors: model (σ_m t_ν), damping, slip, inertia (normal) [-]."""
    u = uncertainty
    if u.model_error_dof:
        model = u.model_error * rng.standard_t(u.model_error_dof, n)
    else:
        model = rng.normal(0.0, u.model_error, n)
    return {
        "model": model,
        "damping": rng.normal(0.0, u.damping, n),
        "slip": rng.normal(0.0, u.slip_coefficient, n),
        "inertia": rng.normal(0.0, u.inertia, n),
    }


def shimmy_probability_mc(
    trail: float,
    inertia: float,
    groove: float,
    damping: float,
    slip_coefficient: float,
    speed: float,
    uncertainty: Uncertainty,
    samples: int | None = None,
    seed: int | None = None,
    target_se: float | None = MC_TARGET_SE,
) -> tuple[float, float]:
    """Monte Carlo P(V_c,true < speed) on the exact Eq. 7 with sampled constants: (p, standard error) [-].

    Samples the distribution the bound assumes (Student-t model error, lognormal c_f, K_s, I_w):
    ``samples`` (default ``uncertainty.samples``) draws with ``seed`` (default ``uncertainty.seed``),
    then more from the same stream until the standard error is at most ``target_se`` (0.1 percentage
    point; None: no top-up), up to :data:`MC_MAX_SAMPLES`.  The design is one caster (floats).
    """
    u = uncertainty
    n = int(u.samples if samples is None else samples)
    rng = np.random.default_rng(u.seed if seed is None else seed)
    hits = 0
    drawn = 0
    want = n
    while True:
        chunk = min(want - drawn, 1_000_000)
        f = sample_log_factors(u, chunk, rng)
        v = critical_shimmy_speed(
            trail,
            inertia * np.exp(f["inertia"]),
            groove,
            damping * np.exp(f["damping"]),
            slip_coefficient * np.exp(f["slip"]),
        ) * np.exp(f["model"])
        hits += int(np.count_nonzero(v < speed))
        drawn += chunk
        if drawn < want:
            continue
        p = hits / drawn
        if target_se is None or drawn >= MC_MAX_SAMPLES:
            break
        needed = math.ceil(max(p * (1 - p), 1.0 / drawn) / target_se**2)
        if needed <= drawn:
            break
        want = min(MC_MAX_SAMPLES, needed + needed // 50)
    return p, float(math.sqrt(max(p * (1 - p), 1.0 / drawn) / drawn))
