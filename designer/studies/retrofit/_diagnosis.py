"""The numbers of a caster as it is and of every candidate: the diagnosis side of a retrofit.

Part of :mod:`designer.studies.retrofit._retrofit`: the risk model every caster of a retrofit is judged with
(the problem's, and :func:`_calibrated` by an observed onset), the numbers of candidate arrays and their
Monte Carlo P(shimmy) from the model's evaluator (:func:`_evaluate`: V_c on the effective trail, the speed
reached with probability 1 − α, turning effort, sill force, the limits met), and the current wheel's I_w.
"""

from __future__ import annotations

import dataclasses
import warnings


from designer.display import shown
from designer.errors import InputError
from designer.model import VARIABLES, Casters, Conditions, Design, evaluate
from designer.physics.inertia import Catalog
from designer.physics.uncertainty import Uncertainty


def _calibrated(u: Uncertainty, scatter: float) -> Uncertainty:
    """The risk model of one calibrated caster: the model error becomes the onset's scatter (normal)."""
    return dataclasses.replace(u, model_error=scatter, model_error_dof=0)  # a stated σ, not one from a few wheels


def _evaluate(
    arrays: dict,
    conditions: Conditions,
    stem_angle: float,
    factor: float,
    bound: Uncertainty | None,
    limits: tuple[float, float | None] | None = None,
    monte_carlo: tuple[float, Uncertainty, int, int] | None = None,
    exact: bool = False,
) -> Casters:
    """The model's numbers of candidates {trail, diameter, groove, damping, inertia} (arrays): V_c on the
    effective trail, the bound's speed times the calibration ``factor``, F_turn, P, R_s; with ``limits``
    (V_req, R_max) the limits met, with ``monte_carlo`` (V_target, scatter, samples, seed) P(shimmy) and its SE
    by Monte Carlo, or with ``exact`` P(shimmy) by the exact law (quadrature; SE 0)."""
    speed, scatter, samples, seed = monte_carlo if monte_carlo is not None else (None, None, None, None)
    if exact:
        samples, seed = None, None
    return evaluate(
        {name: arrays[name] for name in VARIABLES},
        conditions.replace(uncertainty=bound),
        inertia=arrays["inertia"],
        measured=arrays.get("measured", True),
        stem_angle=stem_angle,
        calibration=factor,
        required_speed=None if limits is None else limits[0],
        swept_radius_max=None if limits is None else limits[1],
        risk=speed,
        exact=exact,
        scatter=scatter,
        samples=samples,
        seed=seed,
    )


def _current_inertia(problem, current: Design) -> tuple[float, bool]:
    """I_w of the current wheel when it was not given, and whether that I_w is a measured one.

    A catalogue or fixed-inertia problem describes particular wheels, measured: the current wheel must be one
    of them (same diameter), else InputError asks for ``--inertia``.  Otherwise the problem's inertia model at
    its diameter: a wheel known by its diameter only (the risk law's prediction interval), unless the model
    itself is a measured one.
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
            return float(same[0].inertia), True
        if same:
            raise InputError(
                f"inertia: the problem has {len(same)} wheels of d = {shown(current.diameter, 'diameter', 'in')} "
                f"({', '.join(w.key for w in same)}) with different I_w; give the current wheel's "
                f"measured I_w with --inertia"
            )
        if (
            getattr(model, "name", "") == "fixed"
            and problem.bounds["diameter"].fixed
            and abs(problem.bounds["diameter"].low - current.diameter) <= 1e-6
        ):
            return float(model(current.diameter)), True
        raise InputError(
            f"inertia: the current wheel (d = {shown(current.diameter, 'diameter', 'in')}) is not one of the "
            f"problem's wheels ({model.describe()}); give its measured I_w with --inertia"
        )
    with warnings.catch_warnings(action="ignore"):  # extrapolation of the inertia fit: docs/retrofit.md
        return float(model(current.diameter)), bool(getattr(model, "measured", False))
