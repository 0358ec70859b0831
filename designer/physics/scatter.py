"""The scatter of the shimmy model, derived from Table 1, each scale with its provenance.

The risk law (:mod:`designer.physics.uncertainty`) is

    log V_c,true = log V_c,Eq.7(I_true, c_f,true, K_s,true; T, B) + e_m

and this module says where each of its scales comes from:

``model error e_m``   The log of V_measured / V_Eq.7 over Table 1's wheels C–G, with their measured I_w,
                      c_f = 1.3 (Eq. 11C), K_s = 1250 N, B = 0, T = 2 in.  Eq. 7's constants were not
                      fitted to these wheels (c_f comes from Fig. 2C, K_s from Fig. 3C), so the mean is
                      taken as zero and the scale is the RMS about zero, on as many degrees of freedom as
                      wheels (5): a Student-t predictive for the next wheel (:func:`model_error`).
``I_w from d``        A wheel known by its diameter only: the least-squares fit log I_w = log C + n log d
                      over Table 1's seven wheels, and its prediction interval for a new wheel,
                      a Student-t on n_w − 2 = 5 degrees of freedom with scale
                      s √(1 + 1/n_w + (log d − mean log d)² / S_xx), s = √(SSR / (n_w − 2))
                      (:class:`InertiaPrediction`, :func:`inertia_prediction`).  It widens by itself
                      outside Table 1's 4–8 in.
``I_w measured``      A wheel whose inertia was measured (bifilar or trifilar pendulum): lognormal,
                      σ = 0.05 of the log by default (:data:`MEASURED_INERTIA_SCATTER`), configurable.
``M_f/θ0, K_s``       No scatter in the paper: lognormal σ 0.10 and 0.20 of the log, assumptions
                      (:data:`ASSUMED_DAMPING_SCATTER`, :data:`ASSUMED_SLIP_SCATTER`), configurable.

Everything is computed from :mod:`designer.data.paper` (nothing typed in); every function takes the
wheels as an argument so that the leave-one-out check refits without one of them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from designer.data.paper import (
    BARE_FORK_DAMPING,
    DAMPING_SOURCE,
    SLIP_COEFFICIENT,
    SLIP_COEFFICIENT_SOURCE,
    TABLE1,
    TABLE1_SOURCE,
    TABLE1_TRAIL,
    Wheel,
)
from designer.physics.shimmy import critical_shimmy_speed
from designer.physics.types import Numeric, Scalar
from designer.reprs import Keyed
from designer.units import INCH

KINDS = ("data", "assumed", "measured")
"""Where a scale comes from: derived from the paper's tables, assumed, or the scatter of a measurement."""

MEASURED_INERTIA_SCATTER = 0.05
"""σ of log I_w of a wheel whose inertia was measured [-]: a bifilar or trifilar pendulum (default)."""

ASSUMED_DAMPING_SCATTER = 0.10
"""σ of log(M_f/θ0) [-]: an assumption (the paper fits 1.3 to Fig. 2C and gives no scatter)."""

ASSUMED_SLIP_SCATTER = 0.20
"""σ of log K_s [-]: an assumption (the paper measured one tyre, Fig. 3C)."""

MEASURED_INERTIA_SOURCE = (
    "a wheel whose moment of inertia about a diameter was measured (bifilar or trifilar pendulum): "
    "lognormal scatter of the measurement about the value given"
)
"""Provenance of the measured-inertia scatter."""


@dataclass(frozen=True)
class Source(Keyed):
    """Provenance of one scale of the risk law.

    ``to_dict()`` (:class:`designer.reprs.Keyed`): name, distribution, scale, dof, kind, source, caveats.

    Attributes
    ----------
    name : what scatters ("model error", "wheel inertia (diameter only)", ...)
    distribution : "Student-t" or "normal", of the log of the quantity
    scale : scale of that log [-] (σ for a normal; the t's scale, not its standard deviation)
    dof : degrees of freedom ν of a Student-t; None for a normal
    kind : one of :data:`KINDS`
    source : where it comes from (the paper's sentence or table, or the assumption)
    caveats : what the derivation takes for granted
    """

    name: str
    distribution: str
    scale: float
    dof: int | None
    kind: str
    source: str
    caveats: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"source {self.name}: kind {self.kind!r} is not one of {', '.join(KINDS)}")
        if self.distribution not in ("Student-t", "normal"):
            raise ValueError(f"source {self.name}: distribution {self.distribution!r} unknown")

    @property
    def variance(self) -> float:
        """Variance of the log [-]: scale² for a normal, scale² ν/(ν − 2) for a t_ν (inf for ν <= 2)."""
        if self.dof is None:
            return self.scale**2
        if self.dof <= 2:
            return math.inf
        return self.scale**2 * self.dof / (self.dof - 2)


# --------------------------------------------------------------------------- model error


@dataclass(frozen=True)
class ModelError:
    """Eq. 7's error against measured critical speeds: the residuals and the scale derived from them.

    Attributes
    ----------
    wheels : the Table 1 letters used
    residuals : log(V_measured / V_Eq.7) per wheel [-]
    scale : RMS of the residuals about zero (the Student-t scale) [-]
    dof : degrees of freedom (one per wheel: the mean is known, zero)
    mean, mean_se : the sample mean and its standard error s/√n [-] (for the caveat)
    """

    wheels: tuple[str, ...]
    residuals: tuple[float, ...]
    scale: float
    dof: int
    mean: float
    mean_se: float


def model_error_residuals(wheels: tuple[Wheel, ...] = TABLE1) -> dict[str, float]:
    """log(V_measured / V_Eq.7) of each wheel with a measured critical speed [-].

    Eq. 7 at Table 1's conditions: T = 2 in, the wheel's measured I_w, B = 0, c_f = 1.3 N·m/rad
    (Eq. 11C), K_s = 1250 N (irrelevant at B = 0).
    """
    speeds = {w.key: (w.critical_speed, w.inertia) for w in wheels if w.critical_speed is not None}
    law = (0.0, BARE_FORK_DAMPING, SLIP_COEFFICIENT)  # B = 0, c_f, K_s
    return {key: math.log(v / float(critical_shimmy_speed(TABLE1_TRAIL, i, *law))) for key, (v, i) in speeds.items()}


@lru_cache(maxsize=32)
def model_error(wheels: tuple[Wheel, ...] = TABLE1) -> ModelError:
    """The model-error scale of the risk law: the log RMS of Eq. 7 over the measured wheels, mean zero.

    Over Table 1's C–G: scale 0.10751 on 5 degrees of freedom (the sample mean is +0.034 ± 0.051).
    """
    r = model_error_residuals(wheels)
    e = np.array(list(r.values()))
    if e.size < 2:
        raise ValueError(f"model error: {e.size} measured wheel(s); at least 2 are needed")
    return ModelError(
        wheels=tuple(r),
        residuals=tuple(float(x) for x in e),
        scale=float(math.sqrt(np.mean(e**2))),
        dof=int(e.size),
        mean=float(e.mean()),
        mean_se=float(e.std(ddof=1) / math.sqrt(e.size)),
    )


# --------------------------------------------------------------------------- inertia from the diameter


@dataclass(frozen=True)
class InertiaPrediction:
    """The least-squares power law log I_w = log C + n log d and its prediction interval for a new wheel.

    Attributes
    ----------
    log_coefficient : log C (d in m, I_w in kg·m²)
    exponent : n [-]
    residual_scale : s = √(SSR / (n_w − 2)) [-]
    wheels : n_w, the number of wheels fitted
    mean_log_diameter : mean of log d (d in m)
    sxx : Σ (log d − mean log d)²
    low, high : the smallest and largest diameter fitted [m] (outside them the fit extrapolates)
    """

    log_coefficient: float
    exponent: float
    residual_scale: float
    wheels: int
    mean_log_diameter: float
    sxx: float
    low: float
    high: float

    @property
    def dof(self) -> int:
        """Degrees of freedom of the prediction's Student-t: n_w − 2."""
        return self.wheels - 2

    def median(self, diameter: Scalar) -> Scalar:
        """The power law's I_w = C dⁿ at diameter d [m] (the median of the prediction) [kg·m²]."""
        return np.exp(self.log_coefficient + self.exponent * np.log(diameter))

    def scale(self, diameter: Scalar) -> Scalar:
        """Scale of the Student-t prediction of log I_w at diameter d [m] [-].

        s √(1 + 1/n_w + (log d − mean log d)² / S_xx): floats, arrays and CasADi symbols.
        """
        x = np.log(diameter) - self.mean_log_diameter
        return self.residual_scale * np.sqrt(1 + 1 / self.wheels + x**2 / self.sxx)

    def extrapolated(self, diameter: Numeric) -> Any:
        """True where d [m] lies outside the fitted diameters (0.1 % slack for inch rounding): numeric, a bool
        or a boolean array."""
        d = np.asarray(diameter, dtype=float)
        return (d < self.low * 0.999) | (d > self.high * 1.001)


@lru_cache(maxsize=32)
def inertia_prediction(wheels: tuple[Wheel, ...] = TABLE1) -> InertiaPrediction:
    """Least-squares fit of log I_w on log d over ``wheels`` and its prediction scale.

    Over Table 1's seven wheels: n = 3.496, s = 0.3403 on 5 degrees of freedom; the prediction scale
    is 0.3647 at 7 in and 0.534 at 3 in.
    """
    d = np.array([w.diameter for w in wheels])
    y = np.log(np.array([w.inertia for w in wheels]))
    x = np.log(d)
    if len(set(d)) < 2 or len(d) < 3:
        raise ValueError(f"inertia prediction: {len(d)} wheels, {len(set(d))} diameters; need 3 and 2")
    xm = float(x.mean())
    sxx = float(np.sum((x - xm) ** 2))
    slope = float(np.sum((x - xm) * (y - y.mean())) / sxx)
    intercept = float(y.mean() - slope * xm)
    ssr = float(np.sum((y - intercept - slope * x) ** 2))
    return InertiaPrediction(
        log_coefficient=intercept,
        exponent=slope,
        residual_scale=math.sqrt(ssr / (len(d) - 2)),
        wheels=len(d),
        mean_log_diameter=xm,
        sxx=sxx,
        low=float(d.min()),
        high=float(d.max()),
    )


def inertia_model_error_correlation(wheels: tuple[Wheel, ...] = TABLE1) -> float:
    """Sample correlation of the power law's log residual and Eq. 7's log error over the measured wheels [-]

    (0.39 over C–G: the risk law treats the two as independent, a caveat it states)."""
    p = inertia_prediction(wheels)
    r = model_error_residuals(wheels)
    by_key = {w.key: w for w in wheels}
    inertia_residual = [math.log(by_key[k].inertia / p.median(by_key[k].diameter)) for k in r]
    return float(np.corrcoef(inertia_residual, list(r.values()))[0, 1])


# --------------------------------------------------------------------------- the provenance records


def model_error_source(scale: float | None = None, dof: int | None = None) -> Source:
    """Provenance of the model error; ``scale``/``dof`` other than Table 1's make it an assumption."""
    m = model_error()
    rho = inertia_model_error_correlation()
    derived = (scale is None or math.isclose(scale, m.scale, rel_tol=1e-9)) and (dof is None or dof == m.dof)
    value = m.scale if scale is None else float(scale)
    nu = m.dof if dof is None else int(dof)
    caveats = (
        f"the mean is taken as zero: the sample mean is {m.mean:+.3f} ± {m.mean_se:.3f}, "
        "so this is mildly conservative",
        f"treated as independent of the inertia's scatter (sample correlation {rho:.2f} over {m.dof} wheels)",
    )
    if derived:
        text = (
            f"{TABLE1_SOURCE}. Log RMS of V_measured / V_Eq.7 over wheels {', '.join(m.wheels)} with their "
            f"measured I_w, c_f = {BARE_FORK_DAMPING} N·m/rad, B = 0 (Eq. 7's constants were not fitted to "
            f"them), on {m.dof} degrees of freedom"
        )
        kind = "data"
    else:
        text = f"set by the problem (Table 1 gives scale {m.scale:.4g} on {m.dof} degrees of freedom)"
        kind = "assumed"
    return Source("model error", "Student-t" if nu else "normal", value, nu or None, kind, text, caveats)


def predicted_inertia_source(diameter: float, prediction: InertiaPrediction | None = None) -> Source:
    """Provenance of the inertia of a wheel known by its diameter only, at that diameter [m]."""
    p = inertia_prediction() if prediction is None else prediction
    caveats = [
        "a wheel bought by its size: any wheel of that diameter, scattered as Table 1's wheels are about the power law",
        "treated as independent of the model error",
    ]
    if bool(p.extrapolated(diameter)):
        caveats.append(
            f"d = {diameter / INCH:.2f} in lies outside Table 1's {p.low / INCH:.0f}–{p.high / INCH:.0f} in: "
            "an extrapolation; the prediction interval widens with it"
        )
    text = (
        f"{TABLE1_SOURCE}. Prediction interval of the least-squares fit log I_w = log C + n log d "
        f"(n = {p.exponent:.3f}, s = {p.residual_scale:.4f}, {p.wheels} wheels, {p.dof} degrees of freedom) "
        f"at d = {diameter / INCH:.3g} in"
    )
    return Source(
        "wheel inertia (diameter only)", "Student-t", float(p.scale(diameter)), p.dof, "data", text, tuple(caveats)
    )


def measured_inertia_source(sigma: float = MEASURED_INERTIA_SCATTER) -> Source:
    """Provenance of a measured wheel inertia (lognormal σ of the measurement)."""
    default = math.isclose(sigma, MEASURED_INERTIA_SCATTER, rel_tol=1e-12)
    text = MEASURED_INERTIA_SOURCE + (
        f" (σ = {MEASURED_INERTIA_SCATTER:g}, the default)" if default else f" (σ = {sigma:g}, set by the problem)"
    )
    caveats = ("a supplier's catalogue value is not a measurement of the wheel delivered",)
    return Source("wheel inertia (measured)", "normal", float(sigma), None, "measured", text, caveats)


def _assumed(name: str, sigma: float, source: str, caveat: str) -> Source:
    """Provenance of an assumed lognormal scatter σ of a constant: its ``source`` and one ``caveat``."""
    return Source(
        name, "normal", float(sigma), None, "assumed", f"{source}; σ = {sigma:g} of the log is assumed", (caveat,)
    )


def damping_source(sigma: float = ASSUMED_DAMPING_SCATTER) -> Source:
    """Provenance of the scatter of M_f/θ0 (an assumption)."""
    caveat = "the bare-fork value 1.3 and a friction washer's rating are both taken at face value, scattered by σ"
    return _assumed("M_f/θ0", sigma, DAMPING_SOURCE, caveat)


def slip_coefficient_source(sigma: float = ASSUMED_SLIP_SCATTER) -> Source:
    """Provenance of the scatter of K_s (an assumption)."""
    return _assumed(
        "K_s", sigma, SLIP_COEFFICIENT_SOURCE, "matters only with a groove (B > 0); zero sensitivity at B = 0"
    )
