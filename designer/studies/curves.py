"""The curves the figures draw, computed by the model: the report's paper figures (Fig. 14, Fig. 15, Fig. 2A), the
groove–damper plane of a design, and the docs' tilted stem.

:mod:`designer.plots` draws arrays and computes nothing; the pipeline calls :func:`report_curves` once (into
``ReportData.curves``) and the docs' figure script calls :func:`stem_curves`.  Every value comes from the
model's functions (:func:`designer.model.critical_speed`, :func:`designer.model.evaluate`,
:func:`designer.model.performance`) or the physics' geometry; SI units throughout.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from designer.data.paper import (
    BARE_FORK_DAMPING,
    INCH,
    SLIP_COEFFICIENT,
    TABLE1,
    TABLE1_TRAIL,
)
from designer.errors import InertiaExtrapolationWarning
from designer.model import Conditions, critical_speed, evaluate, performance
from designer.physics.geometry import effective_trail, ground_trail
from designer.physics.threshold import threshold_force_ratio_approx

PLANE_POINTS = 161
"""Grid points along each axis of the groove–damper plane."""


def _bare_fork_speed(trail, inertia) -> Any:
    """V_c of Eq. 7 [m/s] at ``trail`` [m] of a plain tyre (B = 0) on the bare fork (c_f = 1.3 N·m/rad)."""
    return critical_speed(trail, inertia, 0.0, BARE_FORK_DAMPING, SLIP_COEFFICIENT)


def _wheel(w: Any) -> dict[str, Any]:
    """A Table 1 wheel of the figures: ``key``, ``name``, ``inertia`` [kg·m²], ``measured`` (its V_c at 2 in
    [m/s], None: stable to the treadmill's limit) and ``eq7`` (Eq. 7's V_c at 2 in [m/s])."""
    eq7 = float(_bare_fork_speed(TABLE1_TRAIL, w.inertia))
    return {"key": w.key, "name": w.name, "inertia": w.inertia, "measured": w.critical_speed, "eq7": eq7}


def trail_curves() -> dict[str, Any]:
    """Fig. 14: V_c [m/s] against trail T [m] (0.5–3 in) for each Table 1 wheel, B = 0, bare fork.

    ``{"trail": [m], "wheels": [{"key", "name", "inertia" [kg·m²], "measured" (V_c measured at 2 in [m/s] or
    None: stable to the treadmill's limit), "speeds" [m/s] along ``trail``, "eq7" (Eq. 7 at 2 in [m/s])}]}``.
    """
    trail = np.linspace(0.5, 3.0, 200) * INCH
    return {"trail": trail, "wheels": [_wheel(w) | {"speeds": _bare_fork_speed(trail, w.inertia)} for w in TABLE1]}


def inertia_curve() -> dict[str, Any]:
    """Fig. 15: V_c [m/s] against wheel inertia I_w [kg·m²] (0.1e-3 to 3.8e-3) at 2 in trail, B = 0, bare fork,
    with the Table 1 wheels (as in :func:`trail_curves`, without the curves of each)."""
    inertia = np.linspace(0.1e-3, 3.8e-3, 300)
    return {
        "inertia": inertia,
        "speeds": _bare_fork_speed(TABLE1_TRAIL, inertia),
        "wheels": [_wheel(w) for w in TABLE1],
    }


def sill_ratio(diameter, height: float) -> np.ndarray:
    """P/L of Eq. 4A [-] for wheels of ``diameter`` [m] (a number or an array, the shape kept) at a sill of
    ``height`` [m], by the model's evaluator: what the tool uses (check 7 verifies it)."""
    d = np.asarray(diameter, float)
    design = {"trail": np.full(d.shape, 0.05), "diameter": d, "groove": np.zeros(d.shape), "damping": np.ones(d.shape)}
    ratio: np.ndarray = evaluate(
        design, Conditions(load=1.0, threshold_height=height), inertia=1e-3
    ).threshold_force_ratio
    return ratio


def threshold_curves(sill_height: float, diameter_high: float, front_diameters=()) -> dict[str, Any]:
    """Fig. 2A: P/L [-] against wheel diameter d [m], exact (Eq. 4A) and approximate (Eq. 5A), at the sill
    height h = ``sill_height`` [m], and at the paper's ½ in when h differs; d from max(2.6 h, 1 in) to
    max(10 in, 1.1 × ``diameter_high``) [m].

    ``{"diameter", "exact", "approximate", "paper_diameter", "paper_exact" (None when h is ½ in),
    "front_diameters", "front_ratio" (P/L of the front's designs)}``.
    """
    h = sill_height
    d = np.linspace(max(2.6 * h, 1 * INCH), max(10 * INCH, diameter_high * 1.1), 400)
    paper = None
    if abs(h - 0.5 * INCH) > 1e-9:
        paper = d[d > 2.6 * 0.5 * INCH]
    front = np.asarray(front_diameters, float)
    return {
        "diameter": d,
        "exact": sill_ratio(d, h),
        "approximate": threshold_force_ratio_approx(d, h),
        "paper_diameter": paper,
        "paper_exact": None if paper is None else sill_ratio(paper, 0.5 * INCH),
        "front_diameters": front,
        "front_ratio": sill_ratio(front, h) if len(front) else np.zeros(0),
    }


def groove_damper_plane(design, conditions: Conditions, bounds) -> dict[str, Any]:
    """F_turn [N] and V_c [m/s] over the (B, c_f) plane at ``design``'s trail and diameter, by
    :func:`designer.model.performance` under ``conditions``: the groove from 0 to max(its upper bound,
    1.2 B, ¼ in), the damping from min(its lower bound, c_f) to max(its upper bound, 1.2 c_f, that + 1).

    ``{"groove": (n, n) [m], "damping": (n, n) [N·m/rad], "turning_effort", "critical_speed"}`` with n =
    :data:`PLANE_POINTS`; ``bounds``: the problem's, by variable name.
    """
    gb, cb = bounds["groove"], bounds["damping"]
    c_lo = min(cb.low, design.damping)
    g = np.linspace(0.0, max(gb.high, design.groove * 1.2, 0.25 * INCH), PLANE_POINTS)
    c = np.linspace(c_lo, max(cb.high, design.damping * 1.2, c_lo + 1.0), PLANE_POINTS)
    G, C = np.meshgrid(g, c)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaExtrapolationWarning)
        values = performance(design.trail, design.diameter, G, C, conditions)
    return {"groove": G, "damping": C, **{k: values[k] for k in ("turning_effort", "critical_speed")}}


def report_curves(problem, front, design=None, conditions=None) -> dict[str, Any]:
    """The curves of a Pareto report's figures: ``trail`` (:func:`trail_curves`), ``inertia``
    (:func:`inertia_curve`), ``threshold`` (:func:`threshold_curves` for the problem's sill, its diameter bounds
    and the front's diameters) and ``plane`` (:func:`groove_damper_plane` of ``design`` under ``conditions``,
    the weighted optimum's; None without a design)."""
    return {
        "trail": trail_curves(),
        "inertia": inertia_curve(),
        "threshold": threshold_curves(
            problem.conditions.threshold_height,
            problem.bounds["diameter"].high,
            [p.design.diameter for p in front.points],
        ),
        "plane": None if design is None else groove_damper_plane(design, conditions, problem.bounds),
    }


EQ8_CASTER = {
    "offset": 1.5 * INCH,
    "diameter": 7.75 * INCH,
    "groove": 0.5625 * INCH,
    "damping": 1.3,
    "inertia": 0.00127,
}
"""The Eq. 8 wheel (I_w = 0.00127 kg·m², 9/16 in groove, c_f 1.3) on a 1.5 in fork: the docs' example."""


def stem_curves(caster: dict = EQ8_CASTER, tilt_degrees: float = 5.0, drawn_degrees: float = 15.0) -> dict[str, Any]:
    """The tilted stem of ``caster`` (``offset``, ``diameter``, ``groove`` [m], ``damping`` [N·m/rad],
    ``inertia`` [kg·m²]): V_c of Eq. 7 at the effective trail of Eq. 8 against the stem angle (−10° to 10°,
    ±``tilt_degrees`` and 0 marked), and the side view drawn at ``drawn_degrees`` (x forward, z up [m]).

    ``{"angles" [deg], "speeds" [m/s], "marks": [(angle [deg], V_c [m/s])], "geometry": {"angle" [rad],
    "offset", "radius", "axle", "contact", "foot" (of the fork on the axis), "projection" (of the contact on
    the axis), "top" (of the drawn stem) [m], "ground_trail", "effective_trail" [m]}}``.
    """
    c = caster
    radius = c["diameter"] / 2

    def speed(angle_degrees):
        t_eff = effective_trail(c["offset"], radius, np.radians(angle_degrees))
        return critical_speed(t_eff, c["inertia"], c["groove"], c["damping"], SLIP_COEFFICIENT)

    angles = np.linspace(-10, 10, 201)
    phi = math.radians(drawn_degrees)
    u = np.array([-math.sin(phi), math.cos(phi)])  # the stem axis, top leaning back by phi
    n = np.array([-math.cos(phi), -math.sin(phi)])
    foot = (radius + c["offset"] * math.sin(phi)) / math.cos(phi) * u
    axle = foot + c["offset"] * n
    contact = axle - np.array([0.0, radius])
    return {
        "angles": angles,
        "speeds": speed(angles),
        "marks": [(a, float(speed(a))) for a in (-tilt_degrees, 0.0, tilt_degrees)],
        "geometry": {
            "angle": phi,
            "offset": c["offset"],
            "radius": radius,
            "axle": axle,
            "contact": contact,
            "foot": foot,
            "projection": float(np.dot(contact, u)) * u,
            "top": (2 * radius + 1.0 * INCH) / math.cos(phi) * u,
            "ground_trail": float(ground_trail(c["offset"], radius, phi)),
            "effective_trail": float(effective_trail(c["offset"], radius, phi)),
        },
    }


__all__ = [
    "EQ8_CASTER",
    "groove_damper_plane",
    "inertia_curve",
    "report_curves",
    "sill_ratio",
    "stem_curves",
    "threshold_curves",
    "trail_curves",
]
