"""Scatter of the shimmy model and the probability of shimmy (the risk bound).

Eq. 7 rests on fitted constants with scatter: M_f/θ0 = 1.3 is a fit to
scattered data (Fig. 2C), Table 1 shows Eq. 7 within about ±15 % of the
measured critical speeds, and K_s, I_w vary from tyre to tyre.
The true critical speed is modelled as

    log V_c,true = log V_c(x; c_f e^{ξ_c}, K_s e^{ξ_K}, I_w e^{ι}) + σ_m t_ν

with ξ_p ~ N(0, σ_p²) independent (σ of the log of each constant), the
model error σ_m t_ν a Student-t with ν degrees of freedom and scale σ_m, and ι
the scatter of the wheel's inertia about the value used:

- a measured wheel (``diameter=None`` in the functions below): ι ~ N(0, σ_I²);
- a wheel known by its diameter d only (``diameter=d``, I_w the power law's value
  at d): ι = σ_P(d) t_νP, the Student-t prediction interval of Table 1's power law
  (:mod:`designer.physics.scatter`: 0.3647 at 7 in on 5 degrees of freedom,
  widening outside Table 1's 4–8 in).

The default :class:`Uncertainty` (= :func:`data_law`) is the law computed from the
data (every scale's provenance in :mod:`designer.physics.scatter`):
σ_m = 0.10751, the log RMS of Eq. 7 over Table 1's wheels C–G, on ν = 5; σ_I = 0.05
for a measured wheel; M_f/θ0 0.10 and K_s 0.20 assumed.

Why Student-t: Table 1's wheels C–G were not used to fit Eq. 7 (its constants
come from Fig. 2C and Appendix C), so the residuals have a known mean of zero and
the RMS is an estimate of σ on ν = 5 degrees of freedom.  With the usual
non-informative prior the predictive distribution of the next wheel's log error
is then σ̂ t_5 (scale = the RMS): a 95 % quantile 2.015 σ̂ instead of 1.645 σ̂ for
a normal.  ``model_error_dof = 0`` gives the normal model error.  The same holds
for a new wheel about the power law (n − 2 = 5 degrees of freedom).

The deterministic bound.  log V_c,true − log V_c(x) is, to first order in
the ξ_p, X = σ_m t_ν + σ_r Z (measured wheel) or X = σ_m t_ν + ½ σ_P(d) t_νP + σ_r Z
(wheel known by its diameter), Z standard normal and

    σ_r(x)² = (e_c σ_c)² + (e_K σ_K)² [+ (σ_I/2)² for a measured wheel]

(elasticities e of Eq. 7, :func:`designer.physics.shimmy.critical_speed_log_sensitivities`;
that of I_w is −1/2 whatever B).  This is exact for I_w and the model error
(log V_c is linear in their logs) and conservative for c_f and K_s:
log V_c = ½ log(a e^{ξ_c} + b e^{ξ_K}) is convex in (ξ_c, ξ_K) (log-sum-exp),
so it lies above its tangent plane and the true speed is never lower than the
first-order one.  The risk bound P(V_c,true < V_req) <= α therefore holds when

    V_q(x) = V_c(x) · exp(−Q_{1−α}(x)) >= V_req,

Q the exact (1 − α)-quantile of X, represented by a Chebyshev fit shifted up by
its largest fit error so it never lies below the exact quantile: for one t and a
normal a fit in the normal share s = σ_r²/(σ_m² + σ_r²) (quadrature, as before);
for two t's and a normal a 2-D fit in u = σ_I²/(σ_m² + σ_I²) and
r = σ_r²/(σ_m² + σ_I² + σ_r²), its reference the characteristic-function inversion
of :mod:`designer.physics._sums`.  V_q works on floats, NumPy arrays and CasADi
symbols (the diameter may be a symbol), so the NLP, the GP's bound and the stock
screening use the same function.  (The simpler root-sum-square of the t and
normal quantiles is up to 0.7 % too small in Q for s ≈ 0.7; one t of scale
√(σ_m² + σ_I²) for the two t's is up to 2.1 % too small: neither is conservative.)

:func:`shimmy_probability_exact_many` integrates the exact law for many casters at once (the linear part by
inversion, c_f and K_s through Eq. 7 itself by Gauss–Hermite on one axis shared by all of them, the other normal
folded into the linear part), :func:`shimmy_probability_exact` for one;
:func:`shimmy_probability_mc_many` samples it for many casters and speeds with its
own seed (the sampler behind the model's reported Monte Carlo, :func:`designer.model.shimmy_probability`);
:func:`risk_record` says where a caster's risk comes from.

Only ``scipy.special`` is used: ``scipy.stats`` costs 0.7 s of import time.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
import operator
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from designer.errors import InputError
from designer.units import parse_quantity, whole_number

from designer.physics.roots import bracketed_root
from designer.physics.types import Array, Numeric, Scalar, batch_or_symbol
from designer.physics.shimmy import critical_shimmy_speed, critical_speed_log_sensitivities, critical_speed_terms
from designer.physics.scatter import (
    ASSUMED_DAMPING_SCATTER,
    ASSUMED_SLIP_SCATTER,
    MEASURED_INERTIA_SCATTER,
    InertiaPrediction,
    Source,
    damping_source,
    inertia_prediction,
    measured_inertia_source,
    model_error,
    model_error_source,
    predicted_inertia_source,
    slip_coefficient_source,
)
from designer.physics._sums import SumDistribution, _special, tabled_cdf
from designer.physics._quantile_fits import STORED_PAIR_FITS, STORED_SUM_FITS
from numpy.polynomial.hermite_e import hermegauss
from numpy.polynomial.legendre import leggauss
from numpy.polynomial import chebyshev as C


TABLE1_LOG_RMS_ERROR = model_error().scale
"""Log RMS of V_measured / V_Eq.7 over Table 1 wheels C–G (0.10751; :func:`designer.physics.scatter.model_error`,
computed from the table): the model error's scale.  (The RMS *relative* error of check 2 is 0.103.)"""

TABLE1_DOF = model_error().dof
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
    model_error : scale σ_m of the model error log(V_c,measured / V_c,Eq.7) [-]; default Table 1's log RMS over
        wheels C–G, 0.10751 (:data:`TABLE1_LOG_RMS_ERROR`)
    damping : σ of log(M_f/θ0) [-] (assumed: the paper gives no scatter for Eq. 11C's fit)
    slip_coefficient : σ of log K_s [-] (assumed)
    inertia : σ of log I_w [-] of a measured wheel (default 0.05, a pendulum measurement); a wheel known by its
        diameter only, passed as ``diameter`` to the functions of this module, gets Table 1's Student-t
        prediction instead
    model_error_dof : ν of the Student-t model error (5: Table 1 wheels C–G); 0 = normal
    samples : least Monte Carlo sample of a reported probability (more are drawn for SE <= 0.1 pp)
    seed : seed of the reported Monte Carlo estimate
    """

    probability: float = 0.05
    model_error: float = TABLE1_LOG_RMS_ERROR
    damping: float = ASSUMED_DAMPING_SCATTER
    slip_coefficient: float = ASSUMED_SLIP_SCATTER
    inertia: float = MEASURED_INERTIA_SCATTER
    model_error_dof: int = TABLE1_DOF
    samples: int = MC_SAMPLES
    seed: int = MC_SEED

    def __post_init__(self) -> None:
        # the API's boundary (designer.units.parse_quantity / whole_number, as every record): np.float32(0.05) is a
        # number, True is not; the problem file's [robust] ranges are checked where it is read
        for name in ("probability", "model_error", "damping", "slip_coefficient", "inertia"):
            value = getattr(self, name)
            if batch_or_symbol(value):
                continue  # a solver's or a vectorised study's own values
            value = parse_quantity(value, "dimensionless", name)  # a number, or "5 %"
            if name == "probability" and not 0 < value < 1:
                raise InputError(f"probability = {value:g}: a probability of shimmy α is between 0 and 1, e.g. 0.05")
            if name != "probability" and value < 0:
                raise InputError(f"{name} = {value:g}: a standard deviation of the log is 0 or more")
            object.__setattr__(self, name, value)
        for name, low, high in (("model_error_dof", 0, 1000), ("samples", 1, None), ("seed", 0, 2**32 - 1)):
            object.__setattr__(self, name, whole_number(getattr(self, name), name, low, high))

    def describe(self) -> str:
        """One line: α and the scatter (for reports and messages)."""
        dist = f"Student-t ν = {self.model_error_dof}" if self.model_error_dof else "normal"
        return (
            f"P(shimmy) <= {self.probability:.3g}; σ of the log: model error {self.model_error:.4g} ({dist}), "
            f"M_f/θ0 {self.damping:g}, K_s {self.slip_coefficient:g}, I_w {self.inertia:g} if measured (else "
            f"Table 1's prediction from the diameter, Student-t ν = {inertia_prediction().dof})"
        )


# --------------------------------------------------------------------------- t + normal quantile

_NODES = 64


@functools.lru_cache(maxsize=8)
def _quadrature(dof: int) -> tuple[Array, Array, Numeric, Array]:
    un, uw = leggauss(4 * _NODES)
    return *_hermite_nodes(_NODES), _special().stdtrit(dof, (un + 1) / 2), uw / 2


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
        out[lo] = (zw * _special().stdtr(dof, (x[lo, None] - b[lo, None] * zn) / a[lo, None])).sum(-1)
    hi = ~lo
    if hi.any():  # integrate over t (in probability space): the normal CDF is smooth in it
        out[hi] = (tw * _special().ndtr((x[hi, None] - a[hi, None] * tn) / b[hi, None])).sum(-1)
    return out


def exact_sum_quantile(share: Numeric, probability: float, dof: int) -> Array:
    """(1 − α)-quantile of √(1−s) t_ν + √s Z, by quadrature and bisection [-] (numeric only).

    The reference for :func:`log_speed_quantile`'s fit (and its tests).
    """
    s = np.atleast_1d(np.asarray(share, float))
    level = 1 - probability
    lo = np.full(s.shape, float(_special().ndtri(level)) * 0.5)
    hi = np.full(s.shape, float(_special().stdtrit(dof, level)) + float(_special().ndtri(level)))
    for _ in range(48):
        mid = (lo + hi) / 2
        below = _sum_cdf(mid, s, dof) < level
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    quantile: Array = (lo + hi) / 2
    return quantile


_DEGREE = 14


def _clenshaw(coef: Any, x: Scalar, y: Scalar | None = None) -> Any:
    """Σ_j c_j T_j(x), or Σ_jk c_jk T_j(x) T_k(y) for 2-D coefficients (floats, arrays, CasADi symbols).

    NumPy's Chebyshev evaluation for numbers in one variable, Clenshaw's recurrence for symbols.  Numbers and arrays
    in two variables: T_j(x), T_k(y) by their recurrence, the terms summed smallest first in C (half NumPy's
    chebval2d time, 1.8e-16 relative where it errs by 2.6e-16; one number as an array of one, so a batch gives
    each design's value bit for bit).  Symbols in two variables: each column's series in x on T_j(x), smallest
    terms first, then Clenshaw's in y over the columns (as accurate; the NLP's Hessian takes 4.8k operations a
    block where nesting Clenshaw's recurrences took 12.7k)."""
    numeric = (float, int, np.floating, np.ndarray)
    if y is None and isinstance(x, numeric):
        return C.chebval(x, coef)
    c = np.asarray(coef, dtype=float)
    if isinstance(x, numeric) and isinstance(y, numeric):
        shape = np.broadcast(x, y).shape
        xy = np.stack(np.broadcast_arrays(np.atleast_1d(x).astype(float), np.atleast_1d(y).astype(float)))
        t, twice = np.empty((max(2, *c.shape), *xy.shape)), 2 * xy
        t[0], t[1] = 1.0, xy
        for k in range(2, len(t)):
            np.multiply(twice, t[k - 1], out=t[k])
            t[k] -= t[k - 2]
        columns = np.einsum("jk,j...->k...", c[::-1, ::-1], t[c.shape[0] - 1 :: -1, 0])
        return np.einsum("k...,k...->...", columns, t[c.shape[1] - 1 :: -1, 1]).reshape(shape)[()]
    rows = c.tolist()
    if y is None:
        return _recurrence(rows, x)
    tx: list[Any] = [1, x]
    while len(tx) < len(rows):
        tx.append(2 * x * tx[-1] - tx[-2])
    return _recurrence([sum(a * tj for a, tj in zip(col[:0:-1], tx[:0:-1])) + col[0] for col in zip(*rows)], y)


def _recurrence(values: list[Any], x: Any) -> Any:
    """Σ v_k T_k(x) by Clenshaw's recurrence, with coefficients that may be expressions."""
    b1 = b2 = 0 * x
    x2 = 2 * x
    for c in values[:0:-1]:
        b1, b2 = x2 * b1 - b2 + c, b1
    return x * b1 - b2 + values[0]


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
    sm, dof, alpha = float(sigma_model), int(uncertainty.model_error_dof), float(uncertainty.probability)
    if not dof or sm == 0:
        return float(_special().ndtri(1 - alpha)) * np.sqrt(sm**2 + sigma_rest**2)
    return _one_t_quantile(sm, dof, sigma_rest, alpha)


def rest_log_std(
    trail: Scalar,
    inertia: Scalar,
    groove: Scalar,
    damping: Scalar,
    slip_coefficient: Scalar,
    uncertainty: Uncertainty,
    measured: bool = True,
) -> Scalar:
    """σ_r: standard deviation of the first-order normal part of log V_c,true (c_f, K_s, and I_w if
    ``measured``: a wheel known by its diameter only has a Student-t inertia term instead) [-]."""
    e = critical_speed_log_sensitivities(trail, inertia, groove, damping, slip_coefficient)
    u = uncertainty
    variance = (e["damping"] * u.damping) ** 2 + (e["slip_coefficient"] * u.slip_coefficient) ** 2
    if measured:
        variance = variance + (e["inertia"] * u.inertia) ** 2
    return np.sqrt(variance)


def inertia_log_scale(
    trail: Scalar,
    inertia: Scalar,
    groove: Scalar,
    damping: Scalar,
    slip_coefficient: Scalar,
    diameter: Scalar,
    prediction: InertiaPrediction | None = None,
) -> Scalar:
    """Scale of the Student-t inertia term of log V_c,true for a wheel known by its diameter d [m] [-]:

    |∂ log V_c/∂ log I_w| (= 1/2 for Eq. 7) times the prediction scale of log I_w at d (Table 1's power
    law unless ``prediction`` is given).  Floats, arrays, CasADi symbols.
    """
    e = critical_speed_log_sensitivities(trail, inertia, groove, damping, slip_coefficient)
    p = inertia_prediction() if prediction is None else prediction
    return np.sqrt(e["inertia"] ** 2) * p.scale(diameter)


def law_quantile(
    sigma_model: float,
    sigma_inertia: Scalar | None,
    sigma_rest: Scalar,
    uncertainty: Uncertainty,
    inertia_dof: int | None = None,
) -> Scalar:
    """Q_{1−α}(σ_m t_νm + σ_I t_νI + σ_r Z): how far log V_c must exceed log V_req [-].

    ``sigma_inertia`` None: a measured wheel (its scatter is inside σ_r), :func:`log_speed_quantile`.
    Otherwise the two Student-t terms (model error, inertia predicted from the diameter with
    ``inertia_dof`` = ν_I, default Table 1's 5) and the normal rest, by the 2-D fit of
    :func:`_fit` in the shares u = σ_I²/(σ_m² + σ_I²) and r = σ_r²/(σ_m² + σ_I² + σ_r²), shifted up by
    its largest error so that it never lies below the exact quantile.  Floats, arrays, CasADi symbols.
    """
    u = uncertainty
    if sigma_inertia is None:
        return log_speed_quantile(sigma_model, sigma_rest, u)
    nu_i = inertia_prediction().dof if inertia_dof is None else int(inertia_dof)
    sm = float(sigma_model)
    if not u.model_error_dof or sm == 0:  # one t (the inertia): the model error joins the normal rest
        return _one_t_quantile(sigma_inertia, nu_i, np.sqrt(sm**2 + sigma_rest**2), float(u.probability))
    pair = sm**2 + sigma_inertia**2
    total = pair + sigma_rest**2
    coef, _ = _fit(float(u.probability), int(u.model_error_dof), nu_i)
    quantile: Scalar = np.sqrt(total) * _clenshaw(coef, 2 * sigma_inertia**2 / pair - 1, 2 * sigma_rest**2 / total - 1)
    return quantile


def _one_t_quantile(t_scale: Scalar, dof: int, normal: Scalar, probability: float) -> Scalar:
    """Q_{1−α}(a t_ν + c Z) from the stored or computed 1-D fit in the normal share s = c²/(a² + c²) [-] (a t_ν
    with ν > 0 and a scale a that is never zero, a number or an expression)."""
    total = t_scale**2 + normal**2
    coef, _ = _fit(float(probability), int(dof))
    quantile: Scalar = np.sqrt(total) * _clenshaw(coef, 2 * normal**2 / total - 1)
    return quantile


def shimmy_speed_quantile(
    trail: Scalar,
    inertia: Scalar,
    groove: Scalar,
    damping: Scalar,
    slip_coefficient: Scalar,
    uncertainty: Uncertainty,
    diameter: Scalar | None = None,
    prediction: InertiaPrediction | None = None,
    measured: Any = None,
) -> Scalar:
    """The speed reached with probability 1 − α: V_q = V_c(x) exp(−Q_{1−α}(x)) [m/s].

    Eq. 7 for V_c; the risk bound is ``V_q >= V_req`` and then P(V_c,true < V_req) <= α
    (exact for model error and I_w, conservative for c_f and K_s: see the module text).
    ``diameter`` None: the wheel's inertia ``inertia`` was measured (lognormal σ ``uncertainty.inertia``);
    a diameter d [m]: ``inertia`` is the power law's value at d and the wheel is known by its diameter only
    (Student-t prediction of :func:`inertia_log_scale`).  ``measured`` (with a diameter): True, False, or one
    flag per caster (numeric) saying which wheels were measured after all.  Works on floats, NumPy arrays and
    CasADi symbols.
    """
    args = (trail, inertia, groove, damping, slip_coefficient)
    if measured is not None and diameter is not None:  # True, False or one flag per caster
        mask = np.asarray(measured, dtype=bool)
        if mask.all():
            diameter = None
        elif mask.any():
            both = (
                shimmy_speed_quantile(*args, uncertainty),
                shimmy_speed_quantile(*args, uncertainty, diameter, prediction),
            )
            return np.where(mask, *both)
    p = inertia_prediction() if prediction is None else prediction
    rest = rest_log_std(*args, uncertainty, measured=diameter is None)
    sigma_i = None if diameter is None else inertia_log_scale(*args, diameter, p)  # None: a measured wheel
    return critical_shimmy_speed(*args) * np.exp(
        -law_quantile(uncertainty.model_error, sigma_i, rest, uncertainty, p.dof)
    )


# --------------------------------------------------------------------------- two Student-t terms and a normal

_DEGREE2 = (12, 16)
"""Chebyshev degrees of the 2-D quantile fit in (u, r)."""


def exact_pair_quantile(u: Numeric, r: Numeric, probability: float, dof_model: int, dof_inertia: int) -> Array:
    """(1 − α)-quantile of √((1−r)(1−u)) t_νm + √((1−r)u) t_νI + √r Z by characteristic-function inversion [-].

    The reference for :func:`law_quantile`'s 2-D fit (numeric only; :mod:`designer.physics._sums`).
    """
    u_, r_ = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(r, dtype=float))
    a = np.sqrt((1 - r_) * (1 - u_))
    b = np.sqrt((1 - r_) * u_)
    quantile: Array = SumDistribution([(a, dof_model), (b, dof_inertia)], np.sqrt(r_)).quantile(1 - probability)
    return quantile


def _compute_fit(probability: float, *dofs: int) -> tuple[Array, float]:
    """Chebyshev coefficients of the quantile, interpolated at Chebyshev nodes and shifted up by the largest fit
    error on a grid four times as fine (ends included); and the shift.  One Student-t and a normal for ``dofs`` =
    (ν,): a fit on s ∈ [0, 1] (:func:`exact_sum_quantile`); two and a normal for (ν_m, ν_I): a 2-D fit on u, r ∈
    [0, 1]² (:func:`exact_pair_quantile`)."""
    degrees = (_DEGREE,) if len(dofs) == 1 else _DEGREE2

    def exact(*shares: Any) -> Array:
        if len(dofs) == 1:
            return exact_sum_quantile(shares[0], probability, dofs[0])
        return exact_pair_quantile(shares[0], shares[1], probability, dofs[0], dofs[1])

    nodes = [(np.cos(np.pi * (np.arange(d + 1) + 0.5) / (d + 1))[::-1] + 1) / 2 for d in degrees]  # Chebyshev
    coef: Any = exact(*np.meshgrid(*nodes, indexing="ij"))
    for axis in reversed(range(len(degrees))):  # solve along each axis: the interpolant through the nodes
        vander = C.chebvander(2 * nodes[axis] - 1, degrees[axis])
        coef = np.moveaxis(np.linalg.solve(vander, np.moveaxis(coef, axis, 0)), 0, axis)
    check = np.meshgrid(*(np.linspace(0, 1, 4 * d + 1) for d in degrees), indexing="ij")
    error = exact(*check) - _clenshaw(coef, *(2 * x - 1 for x in check))
    shift = max(0.0, float(error.max())) + 1e-9
    coef[(0,) * len(degrees)] += shift
    return coef, shift


@functools.lru_cache(maxsize=32)
def _fit(probability: float, *dofs: int) -> tuple[Array, float]:
    """The quantile's Chebyshev fit and its shift: of one Student-t and a normal for ``dofs`` = (ν,)
    (:func:`_compute_fit`), of two and a normal for (ν_m, ν_I); read from the stored fits
    for the default α and ν (the same numbers)."""
    one = len(dofs) == 1
    table: dict[Any, Any] = STORED_SUM_FITS if one else STORED_PAIR_FITS
    stored = table.get((probability, *dofs, _NODES, _DEGREE) if one else (probability, *dofs, _DEGREE2))
    if stored is None:
        coef, shift = _compute_fit(probability, *dofs)
    else:
        coef, shift = (
            np.array(stored[0], dtype=float).reshape((_DEGREE + 1,) if one else np.add(_DEGREE2, 1)),
            stored[1],
        )
    coef.setflags(write=False)
    return coef, shift


# --------------------------------------------------------------------------- the data law: exact probability


def data_law(**changes: Any) -> Uncertainty:
    """The risk law computed from the data: the default :class:`Uncertainty` with ``changes``.

    Model error: Table 1's log RMS of Eq. 7 over wheels C–G, Student-t on 5 degrees of freedom
    (:func:`designer.physics.scatter.model_error`, 0.10751); a measured wheel inertia: σ = 0.05 of its log;
    M_f/θ0 0.10 and K_s 0.20 (assumed).  A wheel known by its diameter only gets the Student-t prediction
    of Table 1's power law: pass its ``diameter`` to the functions of this module.  ``changes`` replace
    fields (α, samples, seed, a configured scatter).
    """
    return dataclasses.replace(Uncertainty(), **changes)


def _linear_part(
    trail: float,
    inertia: float,
    groove: float,
    damping: float,
    slip_coefficient: float,
    uncertainty: Uncertainty,
    diameter: float | None,
    prediction: InertiaPrediction | None,
) -> SumDistribution:
    """The part of log V_c,true − log V_c that is exactly linear: model error and the wheel's inertia
    (Eq. 7's log V_c is linear in log I_w, slope −1/2, whatever B)."""
    u = uncertainty
    e = critical_speed_log_sensitivities(trail, inertia, groove, damping, slip_coefficient)
    slope = abs(float(e["inertia"]))
    terms: list[tuple[Numeric, int]] = [(float(u.model_error), int(u.model_error_dof))]
    if diameter is None:
        return SumDistribution(terms, slope * float(u.inertia))
    p = inertia_prediction() if prediction is None else prediction
    terms.append((slope * float(p.scale(diameter)), p.dof))
    return SumDistribution(terms, 0.0)


@functools.lru_cache(maxsize=4)
def _hermite_nodes(nodes: int) -> tuple[Array, Array]:
    """Gauss–Hermite nodes and weights for the standard normal (weights sum to 1), computed once per count."""
    zn, zw = hermegauss(nodes)
    zn.setflags(write=False)
    weights = zw / math.sqrt(2 * math.pi)
    weights.setflags(write=False)
    return zn, weights


def shimmy_probability_exact(
    trail: float,
    inertia: float,
    groove: float,
    damping: float,
    slip_coefficient: float,
    speed: Numeric,
    uncertainty: Uncertainty,
    diameter: float | None = None,
    prediction: InertiaPrediction | None = None,
    nodes: int = 32,
) -> Numeric:
    """P(V_c,true < speed) under the exact law, by quadrature [-] (one caster; one or several speeds).

    log V_c,true = log V_c,Eq.7(I_w e^ι, c_f e^{ξc}, K_s e^{ξK}) + e_m: the model error e_m (Student-t) and the
    inertia's ι (Student-t prediction for a wheel known by its ``diameter``, else lognormal σ
    ``uncertainty.inertia`` about a measured ``inertia``) enter linearly, so their sum's CDF is exact
    (:class:`~designer.physics._sums.SumDistribution`); ξc, ξK ~ N(0, σ²) are integrated through Eq. 7 itself
    by Gauss–Hermite with ``nodes`` points: :func:`shimmy_probability_exact_many` of one caster.
    """
    p = shimmy_probability_exact_many(
        trail, inertia, groove, damping, slip_coefficient, speed, uncertainty, diameter, None, prediction, nodes
    )
    return float(p) if p.ndim == 0 else p


# long: the batch's law in one pass (each caster's linear part, the one quadrature axis shared by all)
def shimmy_probability_exact_many(
    trail: Numeric,
    inertia: Numeric,
    groove: Numeric,
    damping: Numeric,
    slip_coefficient: Numeric,
    speed: Numeric,
    uncertainty: Uncertainty,
    diameter: Numeric | None = None,
    measured: Numeric | None = None,
    prediction: InertiaPrediction | None = None,
    nodes: int = 24,
) -> Array:
    """P(V_c,true < speed) under the exact law for many casters at once, by quadrature [-].

    Every argument
    broadcasts with the others (SI: trail T [m], inertia I_w [kg·m²], groove B [m], damping c_f [N·m/rad],
    slip_coefficient K_s [N], speed V [m/s]).  ``diameter`` d [m] of a wheel known by its diameter only (I_w is
    then the power law's value at d and the inertia scatters by Table 1's Student-t prediction,
    :func:`inertia_log_scale`); None, or nan for one caster, or ``measured`` True: a measured wheel (lognormal
    σ ``uncertainty.inertia`` about I_w).

    The law: log V_c,true = log V_c,Eq.7(T, I_w e^ι, B, c_f e^{ξc}, K_s e^{ξK}) + σ_m t_νm, Eq. 7
    V_c² = 4 c_f T²/(π I_w) + K_s B² T/(2 I_w) = a e^{ξc} + b e^{ξK} with the scattered constants.  The model
    error and ι enter linearly (V_c ∝ I_w^−1/2: slope −1/2 whatever B), as does one normal combination of ξc and
    ξK: with D = ξc − ξK and E = ξK − βD, β = −σ_K²/(σ_c² + σ_K²), two independent normals (var D = σ_c² + σ_K²,
    var E = σ_c² σ_K²/(σ_c² + σ_K²)),

        log V_c = ½ E + ½ β D + ½ log(a e^D + b),

    so ½ E joins the linear part.  Its CDF F is exact (characteristic-function inversion,
    :class:`~designer.physics._sums.SumDistribution`), and the remaining normal D is integrated by Gauss–Hermite
    with ``nodes`` points shared by every caster: P = Σ_j w_j F(log V − log V_c(D_j)).  A caster with b = 0 (no
    groove) or a = 0 is linear in ξc or ξK alone: ½ ξc (or ½ ξK) joins the normal term, no quadrature.  1 where
    Eq. 7's V_c is 0 (no trail, or neither friction nor groove).  Returns an array of the broadcast shape.
    """
    cols = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (trail, inertia, groove, damping, slip_coefficient, speed))
    )
    shape = cols[0].shape
    t, i_w, b, c, k, v = (np.ascontiguousarray(x).reshape(-1) for x in cols)
    # the scale of each caster's Student-t inertia term (inertia_log_scale), nan for a measured wheel
    d = np.broadcast_to(np.asarray(np.nan if diameter is None else diameter, dtype=float), shape).reshape(-1)
    flags = (
        np.isnan(d) | np.broadcast_to(np.asarray(False if measured is None else measured, dtype=bool), shape).ravel()
    )
    with np.errstate(invalid="ignore"):
        scale = np.asarray(inertia_log_scale(t, i_w, b, c, k, np.where(flags, 1.0, d), prediction), dtype=float)
    scale = np.where(flags, np.nan, np.broadcast_to(scale, t.shape))
    p_law = inertia_prediction() if prediction is None else prediction
    u = uncertainty
    sc, sk = float(u.damping), float(u.slip_coefficient)
    friction, tread = (np.asarray(x, dtype=float) for x in critical_speed_terms(t, i_w, b, c, k))  # a and b
    with np.errstate(invalid="ignore"):
        alive = (t > 0) & (friction + tread > 0)
    var_d = sc**2 + sk**2
    beta = -(sk**2) / var_d if var_d > 0 else 0.0
    var_e = sc**2 * sk**2 / var_d if var_d > 0 else 0.0
    both = alive & (friction > 0) & (tread > 0) & (var_d > 0)
    line = alive & ~both
    order = np.concatenate([np.flatnonzero(both), np.flatnonzero(line)])  # the casters with V_c > 0, D's first
    out = np.ones(t.size)
    if not order.size:
        return out.reshape(shape)
    # the normal part beside the integrated term: E's half, or ξc's (b = 0) or ξK's (a = 0) half
    normal2 = np.where(both, var_e, np.where(tread > 0, sk**2, sc**2)) / 4
    flags = np.isnan(scale)  # measured wheels: σ_I/2 joins the normal term
    normal2 = (normal2 + np.where(flags, (0.5 * float(u.inertia)) ** 2, 0.0))[order]
    terms: list[tuple[Numeric, int]] = [(float(u.model_error), int(u.model_error_dof))]
    if not flags[order].all():
        terms.append((np.where(flags, 0.0, scale)[order], p_law.dof))
    zn, zw = _hermite_nodes(nodes)
    dn = math.sqrt(var_d) * zn
    n_d = int(both.sum())
    log_v = np.zeros((order.size, nodes if n_d else 1))  # log V_c [log m/s] at the nodes of D
    weights = np.zeros_like(log_v)
    if n_d:
        log_v[:n_d] = 0.5 * (beta * dn + np.log(friction[both][:, None] * np.exp(dn) + tread[both][:, None]))
        weights[:n_d] = zw
    log_v[n_d:, 0] = 0.5 * np.log(friction[line] + tread[line])
    weights[n_d:, 0] = 1.0
    dist = SumDistribution(terms, np.sqrt(normal2))  # casters that share a linear law share its tabulated CDF
    out[order] = np.sum(weights * tabled_cdf(dist, np.log(v[order])[:, None] - log_v), axis=-1)
    return out.reshape(shape)


def max_measured_inertia(
    trail: float, groove: float, damping: float, slip_coefficient: float, speed: float, uncertainty: Uncertainty
) -> float:
    """The largest measured wheel inertia I* [kg·m²] at which the caster still meets the risk bound.

    The I* whose exact law, with the measurement's lognormal scatter (σ ``uncertainty.inertia``) about I*, gives
    P(V_c,true < speed) = α (:func:`shimmy_probability_exact`; P rises with I*): the purchasing spec's acceptance
    limit for a wheel measured before it is fitted, one caster at a time (the specs find it for many casters in one
    batch, :func:`designer.physics.acceptance.acceptance_limits_many`).  A root in log I (to 1e-11) between the I_w
    at which Eq. 7's V_c equals the speed (P about 1/2 there, V_c ∝ I_w^−1/2) and e^−12 of it (P ≈ 0), by
    :func:`designer.physics.roots.bracketed_root`.
    """
    top = 2 * math.log(float(critical_shimmy_speed(trail, 1.0, groove, damping, slip_coefficient)) / speed)

    def excess(log_i: float) -> float:
        args = (trail, math.exp(log_i), groove, damping, slip_coefficient, speed, uncertainty)
        return float(shimmy_probability_exact(*args, nodes=24)) - float(uncertainty.probability)

    return math.exp(bracketed_root(excess, top - 12.0, top, xtol=1e-11, rtol=0.0))


# --------------------------------------------------------------------------- the data law: Monte Carlo

MC_BLOCK = 10_000
"""Draws per block of the data law's Monte Carlo stream: samples are whole blocks, so an estimate is the
same whichever other casters are evaluated beside it."""

_CELLS = 1_000_000
"""Casters × draws evaluated at once (about 8 MB per array)."""


def _blocks(n: int) -> int:
    return max(1, math.ceil(n / MC_BLOCK)) * MC_BLOCK


def law_draws(uncertainty: Uncertainty, rng: np.random.Generator, inertia_dof: int) -> dict[str, Array]:
    """One block of standard draws of the data law, in a fixed order: model (t_νm, or normal when ν = 0),
    inertia_t (t_νI, for wheels known by their diameter), inertia_z, damping, slip (standard normal) [-]."""
    u = uncertainty
    n = MC_BLOCK
    model = rng.standard_t(u.model_error_dof, n) if u.model_error_dof else rng.standard_normal(n)
    return {
        "model": model,
        "inertia_t": rng.standard_t(inertia_dof, n),
        "inertia_z": rng.standard_normal(n),
        "damping": rng.standard_normal(n),
        "slip": rng.standard_normal(n),
    }


_KEPT_BLOCKS = 8
"""Blocks of draws kept per seeded stream (:func:`_draw_stream`; 0.4 MB each): the 10 000 to 80 000 draws of
a typical estimate are drawn once per process, on first use, and reused by every later estimate of the stream."""


class _DrawStream:
    """The seeded stream of :func:`law_draws` blocks, its first :data:`_KEPT_BLOCKS` kept (read-only).

    Iterating gives the blocks in the stream's order, the same as drawing them from ``default_rng(seed)`` one
    after another: the kept ones, then new ones from a copy of the generator where the kept ones end.
    """

    def __init__(self, seed: int, model_error_dof: Any, inertia_dof: Any):
        self._law = Uncertainty(model_error_dof=model_error_dof)  # law_draws reads its model_error_dof only
        self._dof = inertia_dof
        self._seed = seed

    @functools.cached_property
    def _kept(self) -> tuple[list[dict[str, Array]], np.random.Generator]:
        """The kept blocks and the generator after them, drawn on first use: an interrupt half-way through
        (Ctrl-C in a notebook) keeps nothing, and the next reading draws them again from the seed."""
        rng = np.random.default_rng(self._seed)
        blocks = [law_draws(self._law, rng, self._dof) for _ in range(_KEPT_BLOCKS)]
        for values in (v for block in blocks for v in block.values()):
            values.setflags(write=False)
        return blocks, rng

    def __iter__(self) -> Iterator[dict[str, Array]]:
        blocks, rng = self._kept
        yield from (dict(kept) for kept in blocks)  # a caller's own dict of the shared read-only arrays
        rng = copy.deepcopy(rng)
        while True:
            yield law_draws(self._law, rng, self._dof)


@functools.lru_cache(maxsize=8)
def _draw_stream(seed: int, model_error_dof: Any, inertia_dof: Any) -> _DrawStream:
    """The :class:`_DrawStream` of a seed and the two Student-t degrees of freedom (one per process)."""
    return _DrawStream(seed, model_error_dof, inertia_dof)


# long: one loop over the stream's blocks of draws (the shared exponentials, the counts, the top-up rule)
def shimmy_probability_mc_many(
    trail: Numeric,
    inertia: Numeric,
    groove: Numeric,
    damping: Numeric,
    slip_coefficient: Numeric,
    speed: Numeric,
    uncertainty: Uncertainty,
    diameter: Numeric | None = None,
    measured: Numeric | None = None,
    prediction: InertiaPrediction | None = None,
    samples: int | None = None,
    seed: int | None = None,
    target_se: float | None = MC_TARGET_SE,
) -> tuple[Array, Array]:
    """Monte Carlo P(V_c,true < speed) and its standard error for many casters and speeds [-].

    The exact law: V_c,true = V_c,Eq.7(T, I_w e^ι, B, c_f e^{σc Zc}, K_s e^{σK ZK}) e^{σm t_νm}, with ι the
    Student-t prediction σ_I(d) t_νI of a wheel known by its ``diameter`` or σ Z about a measured ``inertia``
    (``measured``: True/False per caster; default: measured when ``diameter`` is None, else not).

    One seeded stream (``seed``, default ``uncertainty.seed``) of blocks of :data:`MC_BLOCK` draws
    (:func:`law_draws`) is applied to every caster: at least ``samples`` draws (default
    ``uncertainty.samples``, rounded up to whole blocks), then more blocks for a caster whose standard error is
    above ``target_se`` (0.1 percentage point; None: no top-up), up to :data:`MC_MAX_SAMPLES`, each speed of
    each caster stopping on its own.  An estimate therefore does not depend on the other casters or speeds
    evaluated with it: it is the one the caster gets alone.  ``speed`` broadcasts with the casters,
    or has one more trailing axis (several speeds per caster).  Returns arrays (p, se) of the speeds' shape.
    """
    u = uncertainty
    cols = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (trail, inertia, groove, damping, slip_coefficient))
    )
    shape = cols[0].shape
    t, i_w, b, c, k = (np.asarray(x).reshape(-1) for x in cols)
    n = t.size
    speeds = np.asarray(speed, dtype=float)
    several = speeds.ndim > len(shape)
    v_req = (speeds if several else np.broadcast_to(speeds, shape)[..., None]).reshape(n, -1)
    p_law = inertia_prediction() if prediction is None else prediction
    flags = True if diameter is None else (False if measured is None else measured)  # every wheel measured
    is_measured = np.broadcast_to(np.asarray(flags, dtype=bool), shape).reshape(-1)
    d = np.broadcast_to(np.asarray(np.nan if diameter is None else diameter, dtype=float), shape).reshape(-1)
    scale_i = np.where(is_measured, float(u.inertia), np.asarray(p_law.scale(d), dtype=float))
    blocks = iter(_draw_stream(operator.index(u.seed if seed is None else seed), u.model_error_dof, p_law.dof))
    want = np.full(v_req.shape, _blocks(int(u.samples if samples is None else samples)))  # per caster and speed
    hits = np.zeros(v_req.shape)
    drawn = 0
    active = np.arange(n)
    # V_c,true < V  <=>  (a e^{σc Zc} + b e^{σK ZK}) e^{2 σm t} e^{−ι} < V²  (Eq. 7 squared, a and b its two terms
    # at the nominal constants): the exponentials of a draw are shared by every caster, those of ι by the casters
    # of one inertia law (a wheel size, or measured)
    friction, groove_term = (np.asarray(x, dtype=float) for x in critical_speed_terms(t, i_w, b, c, k))
    v_req2 = v_req**2
    laws, law_of = np.unique(np.stack([is_measured.astype(float), scale_i], axis=1), axis=0, return_inverse=True)
    law_of = law_of.reshape(-1)
    while active.size:
        f = next(blocks)
        model = 2 * u.model_error * f["model"]
        with_friction = np.exp(u.damping * f["damping"] + model)
        with_groove = np.exp(u.slip_coefficient * f["slip"] + model)
        step = max(1, _CELLS // MC_BLOCK)
        for start in range(0, active.size, step):
            j = active[start : start + step]
            here, which = np.unique(law_of[j], return_inverse=True)
            spread = np.exp(
                -laws[here, 1, None] * np.where(laws[here, 0, None] > 0, f["inertia_z"], f["inertia_t"])
            )  # e^{−ι}, one row per inertia law
            v2 = (friction[j, None] * with_friction + groove_term[j, None] * with_groove) * spread[which.reshape(-1)]
            counts = np.count_nonzero(v2[:, None, :] < v_req2[j, :, None], axis=-1)
            hits[j] += np.where(want[j] > drawn, counts, 0)  # a speed that stopped keeps its count
        drawn += MC_BLOCK
        reached = want == drawn
        if reached.any() and target_se is not None and drawn < MC_MAX_SAMPLES:
            p = hits[reached] / drawn
            needed = np.ceil(np.maximum(p * (1 - p), 1.0 / drawn) / target_se**2)
            more = needed > drawn
            raised = [min(MC_MAX_SAMPLES, _blocks(int(x + x // 50))) for x in needed[more]]
            idx = np.argwhere(reached)[more]
            want[idx[:, 0], idx[:, 1]] = raised
        if drawn >= MC_MAX_SAMPLES:
            break
        active = np.flatnonzero(np.any(want > drawn, axis=1))
    total = np.minimum(want, drawn).astype(float)
    p = hits / total
    se = np.sqrt(np.maximum(p * (1 - p), 1.0 / total) / total)
    out_shape = shape + (v_req.shape[1],) if several else shape
    return p.reshape(out_shape), se.reshape(out_shape)


# --------------------------------------------------------------------------- where the risk comes from

_PHRASES = {
    "model error": "Eq. 7's own error against Table 1",
    "wheel inertia (diameter only)": "the inertia of a wheel known by its diameter only (Table 1's scatter "
    "about the power law)",
    "wheel inertia (measured)": "the scatter of the measured wheel inertia",
    "M_f/θ0": "the assumed scatter of the bearing friction M_f/θ0",
    "K_s": "the assumed scatter of the slip coefficient K_s",
}


def law_sources(
    trail: float,
    inertia: float,
    groove: float,
    damping: float,
    slip_coefficient: float,
    uncertainty: Uncertainty,
    diameter: float | None = None,
    prediction: InertiaPrediction | None = None,
) -> list[dict[str, Any]]:
    """The sources of the law at one caster, each with its share of the variance of log V_c,true [-].

    Share = (∂ log V_c/∂ log p)² × var(log p) / Σ, a Student-t_ν's variance being scale² ν/(ν − 2) (a source
    with ν <= 2 has infinite variance: it takes the whole share); the shares add up to 1.  Each entry is
    :meth:`Source.to_dict` (name, distribution, scale, dof, kind, source, caveats) plus ``share``.
    """
    u = uncertainty
    e = critical_speed_log_sensitivities(trail, inertia, groove, damping, slip_coefficient)
    wheel = measured_inertia_source(u.inertia) if diameter is None else predicted_inertia_source(diameter, prediction)
    rows: list[tuple[Source, Any]] = [
        (model_error_source(u.model_error, u.model_error_dof), 1.0),
        (wheel, e["inertia"]),
        (damping_source(u.damping), e["damping"]),
        (slip_coefficient_source(u.slip_coefficient), e["slip_coefficient"]),
    ]
    parts = [src.variance * float(sens) ** 2 if sens else 0.0 for src, sens in rows]
    if any(math.isinf(x) for x in parts):
        shares = [float(math.isinf(x)) / sum(math.isinf(y) for y in parts) for x in parts]
    else:
        total = sum(parts)
        shares = [x / total if total else 0.0 for x in parts]
    return [src.to_dict() | {"share": share} for (src, _), share in zip(rows, shares)]


def dominant_sentence(sources: list[dict[str, Any]]) -> str:
    """One sentence: which source dominates the variance of log V_c,true, and the next one."""
    ranked = sorted(sources, key=lambda s: -s["share"])
    first, second = ranked[0], ranked[1]
    text = f"{_PHRASES.get(first['name'], first['name'])} dominates the risk: {100 * first['share']:.0f} % of the variance of log V_c"
    if second["share"] >= 0.005:
        text += f", then {_PHRASES.get(second['name'], second['name'])} ({100 * second['share']:.0f} %)"
    return text[0].upper() + text[1:] + "."


def risk_record(
    trail: float,
    inertia: float,
    groove: float,
    damping: float,
    slip_coefficient: float,
    speed: float,
    uncertainty: Uncertainty,
    diameter: float | None = None,
    prediction: InertiaPrediction | None = None,
    samples: int | None = None,
    seed: int | None = None,
) -> dict[str, Any]:
    """Where one caster's risk comes from: {"probability", "se", "sources", "dominant"}.

    ``probability``, ``se``: P(V_c,true < speed) by the exact law's Monte Carlo with its own seed
    (:func:`shimmy_probability_mc_many`, SE <= 0.1 pp); ``sources``: :func:`law_sources` (provenance and
    share of the variance of log V_c); ``dominant``: :func:`dominant_sentence`.  ``diameter`` None: the
    wheel's ``inertia`` was measured; else it is the power law's value at that diameter [m].
    """
    caster = (trail, inertia, groove, damping, slip_coefficient)
    law: dict[str, Any] = {"diameter": diameter, "prediction": prediction}
    p, se = shimmy_probability_mc_many(*caster, speed, uncertainty, samples=samples, seed=seed, **law)
    sources = law_sources(*caster, uncertainty, **law)
    return {"probability": float(p), "se": float(se), "sources": sources, "dominant": dominant_sentence(sources)}
