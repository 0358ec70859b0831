"""The posynomials of the GP, written once: parameters, series order, and every term of the model.

Part of :mod:`designer.solvers.gp._solve` (the method is in its docstring): the
parameter values of a problem (:func:`_parameters`, from :mod:`designer.parameters`), the constants the
terms need, the order of the threshold-force series (:func:`series_order`) and :func:`gp_terms`, the one
function every GP, condensation and sensitivity is built from.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from designer import parameters
from designer.model import Conditions
from designer.physics.geometry import swept_radius
from designer.physics.inertia import Catalog, Disc, Fixed, InertiaModel, PowerLaw, disc_inertia, power_law_inertia
from designer.physics.threshold import (
    threshold_force_ratio,
    threshold_series_coefficients,
    threshold_series_remainder_bound,
)
from designer.physics.turning import sliding_turning_moment
from designer.problem import Problem
from designer.physics.scatter import inertia_prediction
from designer.physics.uncertainty import law_quantile, log_speed_quantile


SERIES_TOLERANCE = 1e-9
"""Target bound on the relative truncation error of the P series over the diameter range [-]."""
MAX_ORDER = 400
"""Highest series order used (reached only for d close to 2h)."""


# --------------------------------------------------------------------------- parameters


def _parameters(problem: Problem) -> dict[str, Any]:
    """The fixed parameters of a continuous problem, named as in :mod:`designer.parameters`."""
    if not isinstance(problem.conditions.inertia, (PowerLaw, Disc, Catalog, Fixed)):  # pragma: no cover
        raise TypeError(f"inertia model {type(problem.conditions.inertia).__name__}: not expressible as a GP")
    return parameters.solver_values(problem)


@dataclass(frozen=True)
class _Constants:
    """Everything fixed in the GP: the conditions, V_req and R_max."""

    conditions: Conditions
    required_speed: float
    swept_radius_max: float | None


def robust_speed_factor(problem: Problem, groove: bool) -> tuple[float, bool]:
    """Factor on V_req that makes the GP's shimmy constraint imply the robust one, and whether it is exact.

    A problem with an uncertainty (``[robust]``, :mod:`designer.studies.robust`)
    requires V_c(x) exp(−Q_{1−α}(σ_m, σ_r(x))) >= V_req (Q the quantile of σ_m t_ν + σ_r Z,
    :func:`designer.physics.uncertainty.log_speed_quantile`), with σ_r² =
    (e_c σ_c)² + (e_K σ_K)² + (σ_I/2)² and elasticities e_c = a/(2(a+b)),
    e_K = b/(2(a+b)) of Eq. 7 (a the damping term, b the groove term).  σ_V
    depends on x, which no GP can express, so the GP uses its largest value:
    e_c + e_K = 1/2 and the convex sum of squares peaks at a vertex, so
    σ_V <= sqrt(σ_m² + max(σ_c, σ_K)²/4 + σ_I²/4), conservative (every GP
    point meets the robust constraint).  Without a groove term (b = 0)
    e_c = 1/2 exactly and the factor is exact.  For a wheel known by its
    diameter the I_w term is Table 1's Student-t prediction, scale σ_P(d)/2,
    taken at its largest over the diameter bounds (exact only for a fixed d).

    Returns
    -------
    (factor, exact) : factor >= 1 on V_req [-]; True if it is not a bound.
    """
    u = getattr(problem.conditions, "uncertainty", None)
    if u is None:
        return 1.0, True

    e2 = (max(u.damping, u.slip_coefficient) if groove else u.damping) ** 2 / 4
    exact = not groove or u.slip_coefficient <= u.damping
    if not getattr(problem.conditions.inertia, "measured", False):
        # a wheel known by its diameter: Table 1's prediction of I_w, a Student-t whose scale depends on d; the
        # quantile grows with it, and the scale is convex in log d, so its largest value is at an end of the box
        rest = math.sqrt(e2)
        b = problem.bounds["diameter"]
        scale = max(float(inertia_prediction().scale(b.low)), float(inertia_prediction().scale(b.high))) / 2
        q = float(law_quantile(u.model_error, scale, rest, u))
        return math.exp(q), exact and b.low == b.high
    rest = math.sqrt(e2 + u.inertia**2 / 4)  # the quantile grows with the normal part: its largest value bounds it
    return math.exp(float(log_speed_quantile(u.model_error, rest, u))), exact


def _constants(problem: Problem, params: dict[str, Any], speed_factor: float = 1.0) -> _Constants:
    """Conditions rebuilt from ``params`` (so a parameter can be perturbed)."""
    conditions = parameters.with_solver_values(problem, params)
    return _Constants(
        conditions=conditions,
        required_speed=(1 + problem.margin) * params["target_speed"] * speed_factor,
        swept_radius_max=params.get("swept_radius_max"),
    )


def series_order(problem: Problem, tolerance: float = SERIES_TOLERANCE) -> tuple[int, float]:
    """Smallest order N of the P series with relative truncation error below ``tolerance``.

    The bound (:func:`threshold_series_remainder_bound`, over the exact Eq. 4A)
    grows with s = h/d, so it is evaluated at the smallest diameter of the
    problem (of its catalog wheels, for a catalog problem).

    Returns
    -------
    (N, bound) : the order and the relative error bound at the smallest diameter [-]
        (N is capped at :data:`MAX_ORDER`; the bound then tells how far off it is).
    """
    d_min = min(v.bounds["diameter"].low for v in problem.variants())
    h = problem.conditions.threshold_height
    s = h / d_min
    exact = float(threshold_force_ratio(d_min, h))
    for order in range(0, MAX_ORDER + 1):
        bound = float(threshold_series_remainder_bound(s, order)) / exact
        if bound < tolerance:
            return order, bound
    return MAX_ORDER, bound


# --------------------------------------------------------------------------- the posynomials (ONE place)


def _is_zero(x: Any) -> bool:
    return isinstance(x, (int, float)) and x == 0


def _inertia(diameter: Any, model: InertiaModel) -> Any:
    """I_w(d) through the physics functions: monomial, posynomial or constant (docs/model.md#wheel-inertia)."""
    if isinstance(model, PowerLaw):
        c, n = model.constants()
        return power_law_inertia(diameter, c, n)
    if isinstance(model, Disc):
        return disc_inertia(diameter, model.tyre_width, model.density)
    if isinstance(model, (Catalog, Fixed)):  # a measured wheel: its I_w, a constant
        return model.parameters()["wheel_inertia"]
    raise TypeError(f"inertia model {type(model).__name__}: not expressible as a GP")


def gp_terms(
    trail: Any, diameter: Any, groove: Any, added_damping: Any, constants: _Constants, order: int, s_max: float
) -> dict[str, Any]:
    """The posynomials of the GP, written once; works on cvxpy, float and complex values.

    Parameters
    ----------
    trail : T [m]
    diameter : d [m]
    groove : B [m]; the number 0 drops its terms (fixed-at-zero family)
    added_damping : c_d = c_f − c_0 [N·m/rad]; the number 0 drops its term
    constants : conditions, V_req [m/s], R_max [m]
    order : order N of the threshold series
    s_max : largest s = h/d of the problem (for the remainder monomial)

    Returns
    -------
    dict with
        ``turning_effort`` F_turn [N] (Eq. 9, docs/model.md#turning-effort; calls
        :func:`sliding_turning_moment`; the added damper moment
        (c_f − c_0) θ0 of :func:`added_damper_moment` is c_d θ0);
        ``threshold_force`` P [N], Eq. 4A series to order N (underestimates);
        ``threshold_remainder`` monomial upper bound of the omitted terms [N],
        L · 2 s^½ (2s)^(N+1) / (1 − 2 s_max);
        ``inertia`` I_w [kg·m²];
        ``shimmy_lhs`` V_req² I_w [N·m²/... = kg·m⁴/s²];
        ``shimmy_rhs`` list of the monomials of (4/π)(c_0 + c_d) T² + K_s B² T/2
        (Eq. 7 multiplied by I_w) [kg·m⁴/s²];
        ``swept_radius`` T + d/2 [m].
    """
    c = constants.conditions
    moment = sliding_turning_moment(c.load, groove, c.surface, c.turning_mode, c.turning)
    if not _is_zero(added_damping):
        moment = moment + added_damping * c.disturbance_angle
    s = c.threshold_height * diameter**-1
    coefficients = threshold_series_coefficients(order)
    ratio = sum(2 * float(ck) * s ** (k + 0.5) for k, ck in enumerate(coefficients))
    inertia = _inertia(diameter, c.inertia)
    rhs = [4 / np.pi * c.turning.bare_fork_damping * trail**2]
    if not _is_zero(added_damping):
        rhs.append(4 / np.pi * added_damping * trail**2)
    if not _is_zero(groove):
        rhs.append(c.slip_coefficient * groove**2 * trail / 2)
    return {
        "turning_effort": moment / trail,
        "threshold_force": c.load * ratio,
        "threshold_remainder": c.load * 2 * s**0.5 * (2 * s) ** (order + 1) / (1 - 2 * s_max),
        "inertia": inertia,
        "shimmy_lhs": constants.required_speed**2 * inertia,
        "shimmy_rhs": rhs,
        "swept_radius": swept_radius(trail, diameter),
    }


def _objective(terms: Mapping[str, Any], weights: Sequence[float]) -> Any:
    """J = w_turn F_turn + w_threshold P from the terms (a zero weight drops its term)."""
    parts: list[Any] = []
    if weights[0] > 0:
        parts.append(weights[0] * terms["turning_effort"])
    if weights[1] > 0:
        parts.append(weights[1] * terms["threshold_force"])
    return parts[0] if len(parts) == 1 else parts[0] + parts[1]
