"""The numbers of a caster as it is and of every candidate: the diagnosis side of a retrofit.

Part of :mod:`designer.studies.retrofit._retrofit`: V_c (Eq. 7 on the effective trail), the speed reached with
probability 1 - alpha, turning effort and sill force of candidate arrays (:func:`_evaluate`), the risk
model and its calibration by an observed onset, the Monte Carlo P(shimmy), the current wheel's I_w and
the feasibility screen.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from designer.data.paper import INCH
from designer.errors import InputError
from designer.model import Conditions, Design, performance
from designer.physics.geometry import effective_trail, swept_radius
from designer.physics.inertia import Catalog, InertiaModel
from designer.physics.shimmy import critical_shimmy_speed
from designer.physics.uncertainty import Uncertainty, sample_log_factors, shimmy_probability_mc, shimmy_speed_quantile


class _Given(InertiaModel):
    """I_w given per candidate (arrays), whatever the diameter."""

    name = "given"

    def __init__(self, values):
        self.values = values

    def __call__(self, diameter):
        return self.values + 0 * diameter

    def describe(self) -> str:
        return "I_w given per candidate"


def _risk_of(problem) -> tuple[Uncertainty | None, Uncertainty]:
    """(the bound's uncertainty or None for the nominal bound, the scatter for reporting P(shimmy))."""
    risk = problem.risk
    return risk, (risk if risk is not None else Uncertainty())


def _calibrated(u: Uncertainty, scatter: float) -> Uncertainty:
    """The risk model of one calibrated caster: the model error becomes the onset's scatter (normal)."""
    changes: dict = {"model_error": scatter}
    names = {f.name for f in dataclasses.fields(u)}
    if "model_error_dof" in names:
        changes["model_error_dof"] = 0  # a stated σ, not one estimated from a few wheels: normal
    return dataclasses.replace(u, **changes)


def _evaluate(
    arrays: dict, conditions: Conditions, stem_angle: float, factor: float, bound: Uncertainty | None
) -> dict:
    """Vectorised numbers of candidates {trail, diameter, groove, damping, inertia} (arrays)."""
    t, d, b, c, i = (np.asarray(arrays[k], dtype=float) for k in ("trail", "diameter", "groove", "damping", "inertia"))
    t_eff = effective_trail(t, d / 2, stem_angle)
    values = performance(t_eff, d, b, c, conditions.replace(inertia=_Given(i), uncertainty=None))
    v = np.asarray(values["critical_speed"], dtype=float)
    if bound is None:
        confident = factor * v
    else:
        confident = factor * np.asarray(
            shimmy_speed_quantile(t_eff, i, b, c, conditions.slip_coefficient, bound), dtype=float
        )
    return {
        "effective_trail": t_eff,
        "critical_speed": v,
        "calibrated_critical_speed": factor * v,
        "confident_speed": confident,
        "turning_effort": np.asarray(values["turning_effort"], dtype=float),
        "threshold_force": np.asarray(values["threshold_force"], dtype=float),
        "swept_radius": np.asarray(swept_radius(t, d), dtype=float),
    }


def _mc_many(
    trail, inertia, groove, damping, slip_coefficient, speed, u: Uncertainty, samples: int, seed: int
) -> tuple[np.ndarray, np.ndarray]:
    """P(V_c,true < speed) and its SE for many casters at once [-].

    The same ``samples`` draws of :func:`~designer.physics.uncertainty.sample_log_factors` with ``seed`` as
    :func:`shimmy_probability_mc` takes first, applied to every caster (vectorised, in chunks), so each
    estimate equals that function's without its top-up; a caster whose SE is still above 0.1 percentage
    point is topped up one by one by the caller.
    """

    m = len(trail)
    if m == 0:
        return np.array([]), np.array([])
    f = sample_log_factors(u, samples, np.random.default_rng(seed))
    e_i, e_c, e_k, e_m = (np.exp(f[k])[None, :] for k in ("inertia", "damping", "slip", "model"))
    hits = np.empty(m)
    step = max(1, 1_000_000 // samples)  # about 8 MB per array
    for a in range(0, m, step):
        b = slice(a, min(m, a + step))
        v = (
            critical_shimmy_speed(
                np.asarray(trail)[b, None],
                np.asarray(inertia)[b, None] * e_i,
                np.asarray(groove)[b, None],
                np.asarray(damping)[b, None] * e_c,
                slip_coefficient * e_k,
            )
            * e_m
        )
        hits[b] = np.count_nonzero(v < speed, axis=1)
    p = hits / samples
    return p, np.sqrt(np.maximum(p * (1 - p), 1.0 / samples) / samples)


def _mc(state_args, conditions, speed, factor, u: Uncertainty, samples: int, seed: int) -> tuple[float, float]:
    t_eff, inertia, groove, damping = state_args
    u = dataclasses.replace(u, samples=samples, seed=seed)
    p, se = shimmy_probability_mc(t_eff, inertia, groove, damping, conditions.slip_coefficient, speed / factor, u)
    return float(p), float(se)


def _current_inertia(problem, current: Design) -> float:
    """I_w of the current wheel when it was not measured: the problem's inertia model at its diameter.

    A catalogue or fixed-inertia problem describes particular wheels: the current wheel must be one of
    them (same diameter), else InputError asks for ``--inertia``.
    """

    model = problem.conditions.inertia
    wheels = [Catalog.from_key(k).wheel for k in problem.wheels]
    if wheels or model.fixed_diameter is not None or getattr(model, "name", "") == "fixed":
        same = [
            w
            for w in wheels or [getattr(model, "wheel", None)]
            if w is not None and abs(w.diameter - current.diameter) <= 1e-6
        ]
        if len({w.inertia for w in same}) == 1:
            return float(same[0].inertia)
        if same:
            raise InputError(
                f"inertia: the problem has {len(same)} wheels of d = {current.diameter / INCH:.4g} in "
                f"({', '.join(w.key for w in same)}) with different I_w; give the current wheel's "
                f"measured I_w with --inertia"
            )
        if (
            getattr(model, "name", "") == "fixed"
            and problem.bounds["diameter"].fixed
            and abs(problem.bounds["diameter"].low - current.diameter) <= 1e-6
        ):
            return float(model(current.diameter))
        raise InputError(
            f"inertia: the current wheel (d = {current.diameter / INCH:.4g} in) is not one of the "
            f"problem's wheels ({model.describe()}); give its measured I_w with --inertia"
        )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # extrapolation of the inertia fit: docs/retrofit.md
        return float(model(current.diameter))


def _feasible(values: dict, v_req: float, r_max: float | None) -> np.ndarray:
    ok = values["confident_speed"] >= v_req * (1 - 1e-12)
    if r_max is not None:
        ok &= values["swept_radius"] <= r_max * (1 + 1e-12)
    return ok
