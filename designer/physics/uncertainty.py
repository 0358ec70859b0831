"""Scatter of the shimmy model and the probability of shimmy (robust design).

Eq. 7 rests on fitted constants with scatter: M_f/θ0 = 1.3 is a fit to
scattered data (Fig. 2C), Table 1 shows Eq. 7 within about ±15 % of the
measured critical speeds (RMS 10.3 %), and K_s, I_w vary from tyre to tyre.
Model each as an independent lognormal factor with a relative standard
deviation σ (the standard deviation of its logarithm):

    V_c,true = V_c(x) · e^{ξ_m} · (elasticity-weighted factors of c_f, K_s, I_w)

To first order in the log factors (exact for the model error and I_w, whose
elasticities are constant), log V_c is normal with standard deviation

    σ_V(x)² = σ_m² + Σ_p (∂log V_c/∂log p · σ_p)²

(elasticities from :func:`designer.physics.shimmy.critical_speed_log_sensitivities`),
and the risk bound P(V_c,true < V_req) <= α becomes

    V_c(x) · exp(−z_{1−α} σ_V(x)) >= V_req,

smooth in x, so the NLP and the Pareto sweeps use it directly.
:func:`shimmy_probability_mc` estimates the probability by vectorised Monte
Carlo on the exact Eq. 7 with the sampled constants (seeded, reproducible).

Only ``scipy.special`` is used (normal quantiles): ``scipy.stats`` costs
0.7 s of import time and is not needed here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr, ndtri

from designer.physics.shimmy import critical_shimmy_speed, critical_speed_log_sensitivities

TABLE1_RMS_ERROR = 0.103
"""RMS relative error of Eq. 7 against Table 1 wheels C–G (computed in check 2: 10.3 %)."""


@dataclass(frozen=True)
class Uncertainty:
    """Scatter of the shimmy model's constants and the allowed probability of shimmy.

    Attributes
    ----------
    probability : α, the largest allowed probability that V_c < V_req [-]
    model_error : σ of log(V_c,measured / V_c,Eq.7) [-]; default the Table 1 RMS error, 0.103
    damping : σ of log(M_f/θ0) [-] (scatter of the Eq. 11C fit)
    slip_coefficient : σ of log K_s [-]
    inertia : σ of log I_w [-] (wheel-to-wheel variation around the inertia model)
    samples : Monte Carlo sample size for the check
    seed : Monte Carlo seed (reproducible estimates)
    """

    probability: float = 0.05
    model_error: float = TABLE1_RMS_ERROR
    damping: float = 0.10
    slip_coefficient: float = 0.20
    inertia: float = 0.10
    samples: int = 20000
    seed: int = 0

    @property
    def z(self) -> float:
        """Standard normal quantile z_{1−α}."""
        return float(ndtri(1 - self.probability))


def log_speed_std(trail, inertia, groove, damping, slip_coefficient, uncertainty: Uncertainty):
    """σ_V: standard deviation of log V_c to first order in the log factors [-]."""
    e = critical_speed_log_sensitivities(trail, inertia, groove, damping, slip_coefficient)
    u = uncertainty
    variance = (u.model_error**2 + (e["damping"] * u.damping) ** 2 + (e["slip_coefficient"] * u.slip_coefficient) ** 2
                + (e["inertia"] * u.inertia) ** 2)
    return np.sqrt(variance)


def shimmy_speed_quantile(trail, inertia, groove, damping, slip_coefficient, uncertainty: Uncertainty):
    """The α-quantile of the true critical speed, V_c(x) exp(−z_{1−α} σ_V(x)) [m/s].

    The robust constraint is ``shimmy_speed_quantile >= V_req``: then
    P(V_c,true < V_req) <= α to first order.  Works on floats, arrays and CasADi symbols.
    """
    v = critical_shimmy_speed(trail, inertia, groove, damping, slip_coefficient)
    return v * np.exp(-uncertainty.z * log_speed_std(trail, inertia, groove, damping, slip_coefficient, uncertainty))


def shimmy_probability_first_order(trail, inertia, groove, damping, slip_coefficient, speed,
                                   uncertainty: Uncertainty) -> float:
    """First-order P(V_c,true < speed) = Φ((log speed − log V_c)/σ_V) [-]."""
    v = float(critical_shimmy_speed(trail, inertia, groove, damping, slip_coefficient))
    sigma = float(log_speed_std(trail, inertia, groove, damping, slip_coefficient, uncertainty))
    return float(ndtr((math.log(speed) - math.log(v)) / sigma))


def shimmy_probability_mc(trail, inertia, groove, damping, slip_coefficient, speed,
                          uncertainty: Uncertainty) -> tuple[float, float]:
    """Monte Carlo P(V_c,true < speed) on the exact Eq. 7 with sampled constants.

    Samples lognormal factors of c_f, K_s, I_w and of the model error
    (``uncertainty.samples`` draws, ``uncertainty.seed``), evaluates Eq. 7
    vectorised, and returns (probability, its standard error).
    """
    u = uncertainty
    rng = np.random.default_rng(u.seed)
    n = u.samples
    factors = {k: np.exp(rng.normal(0.0, s, n)) for k, s in
               (("model", u.model_error), ("damping", u.damping), ("slip", u.slip_coefficient), ("inertia", u.inertia))}
    v = critical_shimmy_speed(trail, inertia * factors["inertia"], groove, damping * factors["damping"],
                              slip_coefficient * factors["slip"]) * factors["model"]
    p = float(np.mean(v < speed))
    return p, float(math.sqrt(max(p * (1 - p), 1e-12) / n))
