"""The report's figures: pick each figure's arguments out of the report data and draw it.

Render only.  :mod:`designer.plots.figures` draws from arrays and plain records; this module says which
parts of a :class:`designer.pipeline.ReportData` each figure shows (the front, its marked designs, the
problem's bounds, the groove/damper rows).  The front and the design variables are drawn by the same
functions as :meth:`Front.plot` and :meth:`Front.plot_variables`.
"""

from __future__ import annotations

import numpy as np

from designer.plots import figures as _figures
from designer.plots.figures import FIGURES, png_bytes

__all__ = ["FIGURES", "arguments", "draw", "png_bytes"]


def _front_marks(data) -> tuple[list, list]:
    """The buildable front (with [stock]) and the marked designs: recommendation, alternatives, knee, optimum."""
    front, problem, rec = data.front, data.problem, getattr(data, "recommendation", None)
    curves, marks = [], []
    stocked = getattr(problem, "stock", None) is not None  # without [stock] the buildable front is this one
    if stocked and rec is not None and getattr(rec, "buildable", None) is not None and len(rec.buildable.points):
        b = rec.buildable.objectives()
        curves.append(
            {
                "threshold_force": b[:, 1],
                "turning_effort": b[:, 0],
                "kind": "buildable",
                "label": f"buildable front (stock parts): {len(b)} point{'s' if len(b) != 1 else ''}",
            }
        )
    if rec is not None:
        marks.append(
            {
                "threshold_force": rec.threshold_force,
                "turning_effort": rec.turning_effort,
                "kind": "recommended",
                "label": f"build this: P {rec.threshold_force:.1f} N, F {rec.turning_effort:.2f} N",
            }
        )
        for alt in rec.alternatives:
            marks.append(
                {
                    "threshold_force": alt.threshold_force,
                    "turning_effort": alt.turning_effort,
                    "kind": "alternative",
                    "label": f"{alt.role}: P {alt.threshold_force:.1f} N, F {alt.turning_effort:.2f} N",
                }
            )
    knee = front.knee()
    if knee is not None and len(front) >= 3:
        marks.append(
            {
                "threshold_force": knee.threshold_force,
                "turning_effort": knee.turning_effort,
                "kind": "knee",
                "label": f"knee of the continuous front: P {knee.threshold_force:.1f} N, F {knee.turning_effort:.2f} N",
            }
        )
    if data.solution is not None:  # the exact optimum, not only the nearest front point
        w = np.asarray(problem.weights, float)
        marks.append(
            {
                "threshold_force": data.solution.objectives["threshold_force"],
                "turning_effort": data.solution.objectives["turning_effort"],
                "kind": "weighted",
                "label": f"weighted optimum (w = {w[0]:g}, {w[1]:g}; not the recommendation)",
            }
        )
    return curves, marks


def _front(data) -> dict:
    front, problem = data.front, data.problem
    f = front.objectives()
    tighter = None
    if data.tighter is not None and len(data.tighter.points):
        t = data.tighter.objectives()
        tighter = {
            "threshold_force": t[:, 1],
            "turning_effort": t[:, 0],
            "label": f"front for V_req = {data.tighter.problem.required_speed:.2f} m/s (V_target × 1.1, check 8c)",
        }
    curves, marks = _front_marks(data) if len(f) else ([], [])
    ends = [front.points[0], front.points[-1]] if len(f) > 1 else front.points[:1]
    risk = problem.conditions.uncertainty
    bound = (
        f"P(V_c < {problem.required_speed:.2f} m/s) <= {risk.probability:.0%}"
        if risk is not None
        else f"V_c >= {problem.required_speed:.2f} m/s"
    )
    return {
        "front": {"turning_effort": f[:, 0], "threshold_force": f[:, 1], "family": [p.family for p in front.points]},
        "title": f"Pareto front: {problem.name} ({bound})",
        "tighter": tighter,
        "curves": curves,
        "marks": marks,
        "ends": [
            {
                "threshold_force": p.threshold_force,
                "turning_effort": p.turning_effort,
                "trail": p.design.trail,
                "diameter": p.design.diameter,
                "groove": p.design.groove,
            }
            for p in ends
        ],
        "note": data.degenerate_reason_short if len(f) == 1 else None,
    }


def _variables(data) -> dict:
    front = data.front
    return {
        "threshold_force": [p.threshold_force for p in front.points],
        "designs": front.designs(),
        "families": [p.family for p in front.points],
        "bounds": [data.problem.bounds[k] for k in ("trail", "diameter", "groove", "damping")],
        "gaps": data.gaps,
    }


def _groove_damper(data) -> dict:
    problem = data.problem
    best = data.front.weighted_best()
    design = conditions = None
    if data.solution is not None:
        design, conditions = data.solution.design, data.solution.problem.conditions
    elif best is not None:
        design, conditions = best.design, problem.conditions
    return {
        "name": problem.name,
        "required_speed": problem.required_speed,
        "bounds": problem.bounds,
        "tradeoff": data.tradeoff,
        "design": design,
        "conditions": conditions,
        "catalog": bool(problem.wheels),
    }


def arguments(name: str, data) -> dict:
    """The keyword arguments of ``figure_<name>`` (:mod:`designer.plots.figures`) for the report ``data``."""
    problem = data.problem
    if name == "front":
        return _front(data)
    if name == "variables":
        return _variables(data)
    if name == "trail":
        return {"required_speed": problem.required_speed}
    if name == "inertia":
        return {}
    if name == "threshold":
        return {
            "sill_height": problem.conditions.threshold_height,
            "load": problem.conditions.load,
            "diameter_bounds": problem.bounds["diameter"],
            "front_diameters": [p.design.diameter for p in data.front.points],
        }
    if name == "groove_damper":
        return _groove_damper(data)
    raise ValueError(f"figure {name!r}: expected one of {', '.join(FIGURES)}")


def draw(name: str, data):
    """Draw figure ``name`` (one of :data:`FIGURES`) for the report ``data``; returns the Figure.

    ``figure_<name>`` is looked up at call time, so a test can replace it.
    """
    return getattr(_figures, f"figure_{name}")(**arguments(name, data))
