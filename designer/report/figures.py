"""The report's figures: pick each figure's arguments out of the report data and draw it as SVG.

Render only.  :mod:`designer.plots.figures` draws from arrays and plain records on the SVG canvas
(:mod:`designer.plots.svg`); this module says which parts of a :class:`designer.reportdata.ReportData` each
figure shows (the front, its marked designs, the problem's bounds, the groove/damper rows) and what a point
says on hover (its numbers).  The front and the design variables are drawn by the same functions as
:meth:`Front.plot` and :meth:`Front.plot_variables`.  To add a figure: a ``figure_<name>`` in
:mod:`designer.plots.figures`, its name in ``FIGURES``, its arguments in :func:`arguments` and its title and
caption in :data:`designer.report.context.FIGURE_INFO`.
"""

from __future__ import annotations

import numpy as np

from designer.display import percent
from designer.plots import figures as _figures
from designer.plots.figures import FIGURES
from designer.display import quantity, shown
from designer.parameters import VARIABLES

__all__ = ["FIGURES", "arguments", "draw", "point_text", "svg"]


def _values(record, names, units: str = "si") -> str:
    """``record``'s quantities ``names`` as "P 106.96 N, F_turn 7.942 N" (symbols, units and precisions from the
    parameter table, lengths in ``units``)."""
    return ", ".join(f"{quantity(name).symbol} {shown(getattr(record, name), name, units)}" for name in names)


def point_text(p, units: str = "in") -> str:
    """What a front point says on hover: its objectives, V_c and design (lengths in the problem's ``units``)."""
    wheel = f", wheel {p.wheel}" if getattr(p, "wheel", None) else ""
    return (
        f"{_values(p, ('threshold_force', 'turning_effort', 'critical_speed'))}; "
        f"{_values(p.design, VARIABLES, units)} ({p.family}{wheel})"
    )


def _at(record) -> str:
    """A marked design's place on the front figure: "P 106.96 N, F_turn 7.942 N"."""
    return _values(record, ("threshold_force", "turning_effort"))


def mark(kind: str, label: str, threshold_force, turning_effort) -> dict:
    """A curve (arrays) or a marked design (numbers) of a front figure: its P and F_turn [N], its ``kind`` (the
    style :func:`designer.plots.fronts.draw_fronts` draws it in) and its legend ``label``."""
    return {"threshold_force": threshold_force, "turning_effort": turning_effort, "kind": kind, "label": label}


def curve(kind: str, label: str, objectives) -> dict:
    """A front's (F_turn, P) rows [N] (``Front.objectives()``) as a curve of the front figure (:func:`mark`)."""
    return mark(kind, label, objectives[:, 1], objectives[:, 0])


def _front_marks(data) -> tuple[list, list]:
    """The buildable front (with [stock]) and the marked designs: recommendation, alternatives, knee, optimum."""
    front, problem, rec = data.front, data.problem, getattr(data, "recommendation", None)
    curves, marks = [], []
    stocked = getattr(problem, "stock", None) is not None  # without [stock] the buildable front is this one
    if stocked and rec is not None and getattr(rec, "buildable", None) is not None and len(rec.buildable.points):
        b = rec.buildable.objectives()
        curves.append(
            curve("buildable", f"buildable front (stock parts): {len(b)} point{'s' if len(b) != 1 else ''}", b)
        )
    if rec is not None:
        marks.append(mark("recommended", f"build this: {_at(rec)}", rec.threshold_force, rec.turning_effort))
        for alt in rec.alternatives:
            marks.append(mark("alternative", f"{alt.role}: {_at(alt)}", alt.threshold_force, alt.turning_effort))
    knee = front.knee() if len(front) >= 3 else None
    at_knee = _at(knee) if knee is not None else ""
    if knee is not None:
        marks.append(
            mark("knee", f"knee of the continuous front: {at_knee}", knee.threshold_force, knee.turning_effort)
        )
    if data.solution is not None:  # the exact optimum, not only the nearest front point
        w = np.asarray(problem.weights, float)
        label = f"weighted optimum (w = {w[0]:g}, {w[1]:g}; not the recommendation)"
        objectives = data.solution.objectives
        weighted = mark("weighted", label, objectives["threshold_force"], objectives["turning_effort"])
        span, keys = COINCIDENT * np.ptp(front.objectives(), axis=0), ("turning_effort", "threshold_force")
        if knee is not None and all(abs(marks[-1][k] - weighted[k]) <= s for k, s in zip(keys, span)):
            # one spot, one legend entry: the cross is drawn inside the knee's circle
            marks[-1]["label"] = f"knee of the continuous front = weighted optimum (w = {w[0]:g}, {w[1]:g}): {at_knee}"
            weighted["label"] = ""
        marks.append(weighted)
    return curves, marks


COINCIDENT = 0.02
"""Two marked designs closer than this fraction of the front's range in both P and F_turn are drawn on one
spot (the knee's circle, 170 pt², has a radius of about 2 % of the front figure's axes): they share one legend
entry."""


def _front(data) -> dict:
    front, problem = data.front, data.problem
    f = front.objectives()
    tighter = None
    if data.tighter is not None and len(data.tighter.points):
        speed = shown(data.tighter.problem.required_speed, "critical_speed")
        tighter = curve("reference", f"front for V_req = {speed} (V_target × 1.1, check 8c)", data.tighter.objectives())
    curves, marks = _front_marks(data) if len(f) else ([], [])
    ends = [front.points[0], front.points[-1]] if len(f) > 1 else front.points[:1]
    risk = problem.conditions.uncertainty
    speed = shown(problem.required_speed, "critical_speed")
    bound = f"P(V_c < {speed}) <= {percent(risk.probability)}" if risk is not None else f"V_c >= {speed}"
    return {
        "front": {"turning_effort": f[:, 0], "threshold_force": f[:, 1], "family": [p.family for p in front.points]},
        "title": f"Pareto front: {problem.name} ({bound})",
        "tighter": tighter,
        "curves": curves,
        "marks": marks,
        "ends": [
            {"threshold_force": p.threshold_force, "turning_effort": p.turning_effort, **p.design.to_dict()}
            for p in ends
        ],
        "note": data.degenerate_reason_short if len(f) == 1 else None,
        "hover": [point_text(p, data.problem.units) for p in front.points],
    }


def arguments(name: str, data) -> dict:
    """The keyword arguments of ``figure_<name>`` (:mod:`designer.plots.figures`) for the report ``data``."""
    problem = data.problem
    if name == "front":
        return _front(data)
    if name == "variables":
        return {
            "threshold_force": [p.threshold_force for p in data.front.points],
            "designs": data.front.designs(),
            "families": [p.family for p in data.front.points],
            "bounds": [problem.bounds[k] for k in ("trail", "diameter", "groove", "damping")],
            "gaps": data.gaps,
            "hover": [point_text(p, problem.units) for p in data.front.points],
        }
    if name == "trail":
        return {"required_speed": problem.required_speed, "curves": data.curves["trail"]}
    if name == "inertia":
        return {"curves": data.curves["inertia"]}
    if name == "threshold":
        return {
            "sill_height": problem.conditions.threshold_height,
            "load": problem.conditions.load,
            "diameter_bounds": problem.bounds["diameter"],
            "curves": data.curves["threshold"],
        }
    if name == "groove_damper":
        best = data.front.weighted_best()
        design = data.solution.design if data.solution is not None else best.design if best is not None else None
        solved = data.solution.problem if data.solution is not None else problem
        return {
            "name": problem.name,
            "required_speed": problem.required_speed,
            "bounds": problem.bounds,
            "tradeoff": data.tradeoff,
            "design": design,
            "plane": data.curves.get("plane"),
            "robust": solved.conditions.uncertainty is not None,
            "catalog": bool(problem.wheels),
        }
    raise ValueError(f"figure {name!r}: expected one of {', '.join(FIGURES)}")


def draw(name: str, data):
    """Draw figure ``name`` (one of :data:`FIGURES`) for the report ``data``; returns the Figure.

    ``figure_<name>`` is looked up at call time, so a test can replace it.
    """
    return getattr(_figures, f"figure_{name}")(**arguments(name, data))


def svg(name: str, data, title: str | None = None) -> str:
    """Figure ``name`` of the report ``data`` as SVG text (ids prefixed ``fig-<name>``, ``title`` its tooltip)."""
    return draw(name, data).to_svg(f"fig-{name}", title)
