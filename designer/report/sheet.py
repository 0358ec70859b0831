"""The inspection sheet: one print-ready page (A4 or Letter) a factory inspects a caster against.

``designer spec PROBLEM`` writes it: the caster drawn to scale with its dimensions
(:func:`designer.plots.caster.caster_svg`), a table of each part's nominal value, tolerance, acceptance limit
and how to measure it (:meth:`designer.studies.spec.Spec.parts`), P(shimmy) at nominal and at the worst
corner, and the problem it was designed for.  Render only: every number comes from the
:class:`~designer.studies.recommend.Recommendation` and its :class:`~designer.studies.spec.Spec`.
"""

from __future__ import annotations

import math
from typing import Any

from markupsafe import Markup

from designer.display import percent, shown
from designer.plots.caster import caster_svg
from designer.report.context import SPEC_COLUMNS, acceptance_text, corner_sentence, limit_notes, spec_rows
from designer.report.formatting import size
from designer.report.text import plain_rule
from designer.report.writer import _render

SHEET_HEAD = "<!DOCTYPE html><!-- inspection sheet written by caster-designer's designer spec -->"
"""The sheet's first line: how ``designer spec`` recognises a sheet of its own it may replace."""

SHEET_SCALE = 19.2
"""Pixels per inch of the sheet's drawing: CSS prints 96 px to the inch, so the drawing is 1:5 at 100 %."""


def enforce_sentence(rec: Any) -> str:
    """How the caster was chosen with respect to its tolerances (``[tolerances] enforce``), from the record: among
    the casters that hold the bound at their worst corner (and whether that changed the rule's pick), or at
    nominal with the worst corner reported only, or at nominal with no tolerances given."""
    tol = getattr(rec.problem, "tolerances", None)
    if tol is None:
        return (
            "Chosen at nominal: the problem gives no [tolerances], so no worst corner was required "
            "([tolerances] enforce = true would choose among the casters that hold the bound at their worst corner)."
        )
    if rec.enforced is not None:
        return "Chosen among the casters that hold the bound at their worst corner: " + rec.enforced_sentence()
    return (
        "[tolerances] enforce = false: the caster was chosen at nominal among those that meet the risk bound; "
        "its worst corner above is reported, not required (enforce = true would choose among the casters that "
        "hold the bound at their worst corner)."
    )


def sheet_html(rec: Any) -> str:
    """The one-page inspection sheet of the recommended caster ``rec`` (needs its spec and problem) as HTML."""
    problem, spec, d = rec.problem, rec.spec, rec.design
    units = getattr(problem, "units", "in")
    sizes = d.trail, d.diameter, d.groove, problem.conditions.threshold_height, problem.swept_radius_max
    drawing = caster_svg(*sizes, scale=SHEET_SCALE, label=f"caster for {problem.name}, drawn 1:5", units=units)
    wheel = f" (wheel {rec.wheel})" if rec.wheel else ""
    kind = "measured" if spec.measured else "known by its diameter (Table 1's power law and its scatter)"
    context = {
        "head": Markup(SHEET_HEAD),
        "title": f"Inspection sheet: caster for {problem.name}",
        "designed_for": f"Designed for: {problem.title}; {shown(problem.conditions.load, 'load')} per caster, sill "
        f"{size(problem.conditions.threshold_height, units)}, no shimmy below "
        f"{shown(problem.required_speed, 'critical_speed')} with probability {percent(1 - spec.alpha)}. Chosen as "
        f"{plain_rule(problem, rec)}.",
        "drawing": Markup(drawing),
        "build": f"Build: trail {size(d.trail, units)}, wheel {size(d.diameter, units)}{wheel} ({kind}, I_w "
        f"{shown(spec.inertia, 'inertia')}), groove {size(d.groove, units)}, bearing friction moment M_f = "
        f"{shown(spec.friction_moment, dimension='moment')} (c_f = {shown(d.damping, 'damping')} at θ0 = "
        f"{math.degrees(spec.disturbance_angle):.0f}°).",
        "columns": SPEC_COLUMNS,
        "rows": spec_rows(spec, units),
        "legend": acceptance_text(spec),
        "notes": limit_notes(spec, units),
        # P(shimmy) at nominal (exact, and the Monte Carlo check) and at the worst corner
        "nominal": Markup(
            "P(shimmy at {}) at nominal: <b>{}</b> by the exact law (Monte Carlo check: {} ± {}, {:,} draws, seed {}); "
            "bound α = {}."
        ).format(
            shown(spec.target_speed, "target_speed"),
            percent(spec.probability),
            percent(spec.mc_probability),
            percent(spec.mc_se),
            spec.mc_samples,
            spec.mc_seed,
            percent(spec.alpha),
        ),
        "corner": corner_sentence(spec),
        "corner_fails": spec.corner is not None and not spec.corner["holds"],
        "enforce": enforce_sentence(rec),
    }
    return _render("sheet.html.j2", context, autoescape=True)
