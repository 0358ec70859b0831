"""The inspection sheet: one print-ready page (A4 or Letter) a factory inspects a caster against.

``designer spec PROBLEM`` writes it: the caster drawn to scale with its dimensions
(:func:`designer.plots.caster.caster_svg`), a table of each part's nominal value, tolerance, acceptance limit
and how to measure it (:meth:`designer.studies.spec.Spec.parts`), P(shimmy) at nominal and at the worst
corner, and the problem it was designed for.  Render only: every number comes from the
:class:`~designer.studies.recommend.Recommendation` and its :class:`~designer.studies.spec.Spec`.
"""

from __future__ import annotations

import math
from html import escape
from typing import Any

from designer.units import percent
from designer.plots.caster import caster_svg
from designer.report.context import corner_sentence, limit_notes, spec_rows
from designer.report.formatting import size
from designer.report.text import plain_rule

SHEET_HEAD = "<!DOCTYPE html><!-- inspection sheet written by caster-designer's designer spec -->"
"""The sheet's first line: how ``designer spec`` recognises a sheet of its own it may replace."""

COLUMNS = (
    "part",
    "nominal",
    "tolerance",
    "joint box: accept when every part is inside",
    "one part at a time (others at nominal)",
    "how to measure",
)
"""The headings of the sheet's table (on a phone each cell is one line under its part, named by its heading)."""

SHEET_SCALE = 19.2
"""Pixels per inch of the sheet's drawing: CSS prints 96 px to the inch, so the drawing is 1:5 at 100 %."""

CSS = """
@page { size: auto; margin: 12mm; }
* { box-sizing: border-box; }
body { font-family: sans-serif; font-size: 8.5pt; color: #111; margin: 0; max-width: 186mm; }
h1 { font-size: 14pt; margin: 0 0 2mm 0; }
p { margin: 1.2mm 0; }
.meta { color: #444; font-size: 8.5pt; }
table { border-collapse: collapse; width: 100%; margin: 2mm 0; }
th, td { border: 0.3mm solid #999; padding: 0.7mm 1.2mm; text-align: left; vertical-align: top; }
th { background: #eee; }
td.num { white-space: nowrap; font-variant-numeric: tabular-nums; }
td.how { font-size: 7pt; color: #333; }
td.box { font-variant-numeric: tabular-nums; font-weight: bold; }
table.parts { table-layout: fixed; }
table.parts td.num { white-space: normal; }
.risk { border: 0.5mm solid #333; padding: 1.5mm 2mm; margin: 2mm 0; }
.fail { color: #b00; font-weight: bold; }
.drawing svg { display: block; }
.sign { margin-top: 4mm; display: flex; gap: 10mm; font-size: 8.5pt; }
.sign span { flex: 1; border-top: 0.3mm solid #333; padding-top: 1mm; }
@media print { body { max-width: none; } .sheet { page-break-inside: avoid; break-inside: avoid; } }
@media screen and (max-width: 640px) {
  body { padding: 0 10px; font-size: 12px; }
  .meta, td.how, .sign { font-size: 11px; }
  .drawing { overflow-x: auto; }
  table, tbody, tr, td { display: block; width: auto; }
  tr:first-child { display: none; }
  tr { border: 0.3mm solid #999; margin: 0 0 3mm; }
  td, td.num { border: none; border-bottom: 1px solid #eee; white-space: normal; }
  td.part { font-weight: bold; background: #eee; }
  td:not(.part)::before { content: attr(data-label) ": "; color: #444; }
}
"""
"""The sheet's stylesheet: one column, print margins, no page break inside; on a phone's screen (390 px) the page
fits the width, its text at least 11 px, the 1:5 drawing and the table scrolling sideways in their frames."""


def _risk_lines(rec: Any) -> list[str]:
    """P(shimmy) at nominal (exact, and the Monte Carlo check) and at the worst corner, as HTML paragraphs."""
    spec = rec.spec
    nominal = (
        f"P(shimmy at {spec.target_speed:.3g} m/s) at nominal: <b>{spec.probability:.2%}</b> by the exact law "
        f"(Monte Carlo check: {spec.mc_probability:.2%} ± {spec.mc_se:.2%}, {spec.mc_samples:,} draws, seed "
        f"{spec.mc_seed}); bound α = {percent(spec.alpha)}."
    )
    corner = escape(corner_sentence(spec))
    if spec.corner is not None and not spec.corner["holds"]:
        corner = f'<span class="fail">{corner}</span>'
    return [f"<p>{nominal}</p>", f"<p>{corner}</p>", f"<p>{escape(enforce_sentence(rec))}</p>"]


def _legend(spec: Any) -> str:
    """The table's legend: what the joint box guarantees, what the one-at-a-time limits do not, [risk] and
    [footrest] (the long form is the report's :func:`~designer.report.context.acceptance_text`)."""
    joint = spec.joint
    box = ""
    if joint is not None:
        scale = (
            f"the stated tolerances × {joint.scale:.3g}"
            if joint.shape == "tolerances"
            else f"{joint.scale:.1%} of nominal each"
        )
        box = (
            "Accept a caster when every part is inside the joint box: then P(shimmy) ≤ α at every corner "
            f"(worst-case stack, exact law, all {joint.corners} corners; the wheel's I_w measured). Its risk windows "
            f"are {scale}. "
        )
    return (
        box + "One part at a time: each limit is P = α with every other part at nominal; parts each inside them can "
        "together exceed α. [risk]: set by P = α; [footrest]: T + d/2 ≤ R_max with d at its upper edge. "
        "Printed limits are rounded toward the safe side."
    )


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
    drawing = caster_svg(
        d.trail,
        d.diameter,
        d.groove,
        problem.conditions.threshold_height,
        problem.swept_radius_max,
        scale=SHEET_SCALE,
        label=f"caster for {problem.name}, drawn 1:5",
        units=units,
    )
    rows = "".join(
        "<tr>"
        + "".join(
            f'<td class="{cls}" data-label="{label}">{escape(cell)}</td>'
            for cls, label, cell in zip(("part", "num", "num", "box", "num", "how"), COLUMNS, row)
        )
        + "</tr>"
        for row in spec_rows(spec, units)
    )
    wheel = f" (wheel {rec.wheel})" if rec.wheel else ""
    kind = "measured" if spec.measured else "known by its diameter (Table 1's power law and its scatter)"
    title = f"Inspection sheet: caster for {problem.name}"
    return "\n".join(
        [
            SHEET_HEAD,
            '<html lang="en"><head><meta charset="utf-8">'
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>{escape(title)}</title><style>{CSS}</style></head>",
            '<body><div class="sheet">',
            f"<h1>{escape(title)}</h1>",
            f'<p class="meta">Designed for: {escape(problem.title)}; {problem.conditions.load:.4g} N per caster, '
            f"sill {escape(size(problem.conditions.threshold_height, units))}, no shimmy below "
            f"{problem.required_speed:.3g} m/s with probability {percent(1 - spec.alpha)}. Chosen as "
            f"{escape(plain_rule(problem, rec))}.</p>",
            f'<div class="drawing">{drawing}</div>',
            '<p class="meta">Drawn to scale, 1:5 when printed at 100 %.</p>',
            f"<p>Build: trail {escape(size(d.trail, units))}, wheel {escape(size(d.diameter, units))}{escape(wheel)}"
            f" ({escape(kind)}, I_w {spec.inertia:.3g} kg·m²), groove {escape(size(d.groove, units))}, bearing friction "
            f"moment M_f = {spec.friction_moment:.3f} N·m (c_f = {d.damping:.3g} N·m/rad at θ0 = "
            f"{math.degrees(spec.disturbance_angle):.0f}°).</p>",
            '<table class="parts"><colgroup><col style="width:12%"><col style="width:9%"><col style="width:12%">'
            '<col style="width:24%"><col style="width:20%"><col style="width:23%"></colgroup>'
            "<tr>" + "".join(f"<th>{c}</th>" for c in COLUMNS) + f"</tr>{rows}</table>",
            f'<p class="meta">{escape(_legend(spec))}</p>',
            *(f'<p class="meta fail">{escape(note)}</p>' for note in limit_notes(spec, units)),
            '<div class="risk">',
            *_risk_lines(rec),
            "</div>",
            '<div class="sign"><span>inspected by</span><span>date</span><span>batch / serial</span></div>',
            "</div></body></html>",
        ]
    )
