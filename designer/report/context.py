"""The Pareto report's page context: every table of :class:`designer.pipeline.ReportData` as display strings.

:func:`build_context` turns the data into the dict that both templates (``index.html.j2`` and
``report.md.j2``) render: the "Build this" card, the problem and model tables, the solver's optimum, the
checks, the front's points and indicators, the groove/damper trade-off and the figure captions.  Strings
only (SI and inches, formatted once, :mod:`designer.report.formatting`); :mod:`designer.report.writer`
draws the figures and writes the files.
"""

from __future__ import annotations

import math
from typing import Any
from dataclasses import dataclass, field

import numpy as np

from designer.units import COMMON_UNITS, INCH
from designer import display, parameters
from designer.display import percent
from designer.parameters import VARIABLES
from designer.reportdata import ReportData
import designer.report.figures as _figures
from designer.plots.caster import caster_svg
from designer.plots.fronts import MARK_WORDS
from designer.report.formatting import fmt, length, size
from designer.report.text import build_lines, caster_sentence, front_count_sentence, lead_sentence, summary_lines
from designer.plots.figures import is_bare_fork
from designer.physics.uncertainty import TABLE1_LOG_RMS_ERROR

FIGURE_INFO = {
    "front": (
        "Pareto front",
        "Turning effort against threshold force on the exact front, coloured by the mechanism that stops shimmy",
    ),
    "variables": (
        "Design variables along the front",
        "Trail, diameter and groove width (mm, inches on the right) and spindle damping along the front, "
        "as the threshold force falls; dotted lines are the bounds, dashed lines family switches.",
    ),
    "trail": (
        "Critical speed vs trail (cf. paper Fig. 14)",
        "Eq. 7 for each Table 1 wheel in the bare test fork (B = 0, c_f = 1.3 N·m/rad, K_s = 1250 N); "
        "points: measured critical speeds at 2 in trail; arrows: wheels A and B, stable up to 3.8 m/s.",
    ),
    "inertia": (
        "Critical speed vs wheel inertia (cf. paper Fig. 15)",
        "Eq. 7 at 2 in trail, B = 0, c_f = 1.3 N·m/rad against Table 1's measured critical speeds "
        "(letters); A and B did not shimmy up to the treadmill's 3.8 m/s.",
    ),
    "threshold": (
        "Threshold force per unit load vs diameter (cf. paper Fig. 2A)",
        "Exact Eq. 4A and approximate Eq. 5A for this problem's sill height; right axis: P for this "
        "problem's load; shaded: the diameter bounds; dots: the diameters on the front.",
    ),
    "groove_damper": (
        "Groove against damper",
        "Left: least turning effort reaching V_req at each diameter with the groove alone (bare fork), "
        "the damper alone (no groove) and the optimum mix, each solved exactly with the trail free. "
        "Right: at the weighted optimum's trail and diameter, turning-effort contours and iso-V_c "
        "lines in the (groove, damping) plane; bold: V_c = V_req.",
    ),
}


@dataclass(frozen=True)
class PanelTable:
    """A table of a first-screen :class:`Panel`: display strings, one list per row."""

    header: list[str]
    rows: list[list[str]]
    numeric: list[bool] = field(default_factory=list)
    """Per column: right-aligned numbers (HTML) / right-aligned column (Markdown)."""
    first_row_marked: bool = False
    """Highlight the first row (the caster to build), as the card's table does."""


@dataclass(frozen=True)
class Panel:
    """One block of the first screen ("Build this"), below the card's table, in index.html and report.md alike.

    The templates render every panel of ``build["panels"]`` with one macro each (``_panels.html.j2``,
    ``_panels.md.j2``): a heading, a sentence, a table, an SVG drawing (inline in the page, written to
    ``figures/<id>.svg`` for report.md), a caption; each part optional.  New first-screen content (the risk's
    sources, the purchasing spec, "if you measure the wheel") is a panel built in :func:`_panels`: no
    template change.  Strings are escaped by the templates; ``svg`` must be SVG this package drew.
    """

    id: str
    title: str = ""
    text: str = ""
    table: PanelTable | None = None
    svg: str = ""
    caption: str = ""


def _panels(data: ReportData) -> list[Panel]:
    """The first screen's panels under the card's table, in order (none yet: the card itself is the rest; the
    panels under the card are :func:`_after_panels`)."""
    return []


def _check_row(c) -> dict:
    return {**c.to_dict(), "expected": fmt(c.expected), "got": fmt(c.got)}


def _design_cells(design) -> dict:
    cells = {"c_f": display.shown(design.damping, "damping")}
    for key, variable in (("T", "trail"), ("d", "diameter"), ("B", "groove")):
        cells[f"{key}_mm"], cells[f"{key}_in"] = length(getattr(design, variable))
    return cells


OTHER_UNITS = {"force": "lbf", "speed": "mph", "angle": "deg"}
"""The problem table's other column for a dimension the unit systems show in SI only (display only)."""


def _entry(name: str, value, label: str | None = None, symbol: str | None = None) -> tuple:
    """(quantity, symbol, SI, other) of the parameter table's entry ``name``: its description and symbol (or
    ``label``, ``symbol``), the value through :mod:`designer.display` (lengths in mm), and in inches (a length)
    or in lbf, mph or degrees (:data:`OTHER_UNITS`)."""
    entry = display.quantity(name)
    other = ""
    if entry.dimension == "length":
        other = display.shown(value, name, "in")
    elif entry.dimension in OTHER_UNITS:
        unit = OTHER_UNITS[entry.dimension]
        other = f"{display.number(value / COMMON_UNITS[unit][1], name)} {unit}"
    return (
        label or entry.description,
        entry.symbol if symbol is None else symbol,
        display.shown(value, name, "mm"),
        other,
    )


def _problem_rows(problem) -> list[dict]:
    """The problem table: its use (load, sill, speeds, θ0, K_s, I_w, risk), its bounds (the swept-radius limit,
    the catalog wheels), then the weights, the turning model's constants and the problem's source."""
    c, t = problem.conditions, problem.conditions.turning
    rows = [
        ("name", "", problem.name, ""),
        ("title", "", problem.title, ""),
        _entry("load", c.load),
        _entry("threshold_height", c.threshold_height),
        ("surface", "", c.surface, ""),
        ("turning mode", "", c.turning_mode, f"m_mode = {c.turning.mode_factor(c.turning_mode):g}"),
        _entry("target_speed", problem.target_speed),
        _entry("margin", problem.margin)[:2] + (display.percent(problem.margin), ""),
        _entry("target_speed", problem.required_speed, "required critical speed", "V_req = (1 + m_V) V_target"),
        _entry("disturbance_angle", c.disturbance_angle),
        _entry("slip_coefficient", c.slip_coefficient),
        ("inertia model", "I_w(d)", c.inertia.describe(), ""),
    ]
    u = getattr(c, "uncertainty", None)
    if u is not None:
        sigmas = f"model {u.model_error:g}, c_f {u.damping:g}, K_s {u.slip_coefficient:g}, I_w {u.inertia:g}"
        rows.append(
            ("robust design: allowed shimmy probability", "α = P(V_c,true < V_req)", display.percent(u.probability))
            + (f"σ of log: {sigmas}",)
        )
    for var in VARIABLES:
        b = problem.bounds[var]
        low, high = _entry(var, b.low), _entry(var, b.high)
        cells = low[2:] if b.fixed else (f"{low[2]} – {high[2]}", f"{low[3]} – {high[3]}" if low[3] else "")
        rows.append((f"{var} (fixed)" if b.fixed else f"{var} bounds", low[1], *cells))
    if problem.swept_radius_max is not None:
        rows.append(_entry("swept_radius_max", problem.swept_radius_max, symbol="R_s = T + d/2 <= R_max"))
    else:
        rows.append(("swept-radius limit", "R_max", "none", ""))
    if problem.wheels:
        rows.append(("catalog wheels (Table 1)", "", ", ".join(problem.wheels), ""))
    w = problem.weights
    rows += [
        ("objective weights", "J = w_turn F_turn + w_threshold P", f"{w[0]:g}, {w[1]:g}", ""),
        ("front points requested", "", str(problem.pareto_points), ""),
        _entry("tile_moment_per_load", t.tile_moment_per_load),
        _entry("carpet_factor", t.carpet_factor),
        _entry("groove_coefficient", t.groove_coefficient)[:3]
        + (f"{t.groove_coefficient * 9 / 16 * INCH:.0%} per 9/16 in",),
        _entry("bare_fork_damping", t.bare_fork_damping)[:3] + ("Eq. 11C",),
        ("problem digest", "", problem.digest(), ""),
        ("source file", "", str(problem.source or "(built in Python)"), ""),
    ]
    return [{"quantity": q, "symbol": s, "si": si, "other": other} for q, s, si, other in rows]


def _model_rows(problem) -> list[dict]:
    inertia = problem.conditions.inertia
    note = ""
    rng = inertia.data_range()
    b = problem.bounds["diameter"]
    if rng is not None and (b.low < rng[0] * 0.999 or b.high > rng[1] * 1.001):
        note = (
            f" The fit rests on Table 1's {display.number(rng[0], 'diameter', 'in', digits=0)}–"
            f"{display.shown(rng[1], 'diameter', 'in', digits=0)} wheels; this problem's diameters "
            f"{display.number(b.low, 'diameter', 'in')}–{display.shown(b.high, 'diameter', 'in')} extrapolate it."
        )
    rows = [
        ("critical shimmy speed", "V_c = sqrt( 4 c_f T² / (π I_w) + K_s B² T / (2 I_w) )", "Eq. 7 (= Eq. 10C)"),
        ("shimmy constraint", "V_c(T, d, B, c_f) >= V_req = (1 + margin) V_target", "docs/model.md#problems"),
    ]
    if getattr(problem.conditions, "uncertainty", None) is not None:
        rows.append(
            (
                "robust shimmy constraint (replaces the nominal one)",
                "V_c · exp(−z_(1−α) σ_V) >= V_req, σ_V² = σ_model² + Σ (∂log V_c/∂log p · σ_p)²",
                "first-order quantile, designer.studies.robust",
            )
        )
    rows += [
        ("wheel inertia", inertia.describe() + "." + note, "docs/model.md#wheel-inertia, Table 1"),
        ("threshold force", "P = L · 2 sqrt(d/h − 1) / (d/h − 2), valid for d/h > 2", "Eq. 4A (= Eq. 1)"),
        ("threshold force, approximate (figure only)", "P/L ≈ 2 sqrt(h/d)", "Eq. 5A"),
        (
            "sliding turning moment",
            "M_turn = m_mode · k_surface · L · (1 + κ B)",
            "docs/model.md#turning-effort, Fig. 7",
        ),
        ("added damper moment", "M_d = (c_f − c_0) θ0", "docs/model.md#turning-effort, Eq. 11C"),
        ("turning effort", "F_turn = (M_turn + M_d) / T", "Eq. 9 (moment = F_c × trail)"),
        ("swept radius", "R_s = T + d/2", "docs/model.md#shimmy"),
        (
            "assumption: dynamics",
            "linear, small-angle two-degree-of-freedom caster on a lateral frame spring; "
            "no tyre lateral slip of a single tread",
            "Appendix B",
        ),
        (
            "assumption: friction damping",
            "Coulomb spindle friction M_f replaced by an equivalent viscous damper at "
            "the amplitude of Eq. 4/29B after a design knock θ0 = "
            f"{math.degrees(problem.conditions.disturbance_angle):.0f}°: V_c depends on θ0 and the time-domain "
            "simulation (results/simulation) puts the onset −18 % to +13 % from Eq. 7 for single-tread casters",
            "Eq. 6, Eq. 29B, Appendix C",
        ),
        (
            "assumption: constants",
            f"K_s = {problem.conditions.slip_coefficient:g} N independent of load, speed and "
            "tyre; c_0 = M_f/θ0 = 1.3 N·m/rad for the bare fork; the load does not enter the shimmy model",
            "Appendix C, Eq. 11C–12C",
        ),
        (
            "assumption: turning model",
            "the groove (+10 % per 9/16 in) and carpet (×2) factors are the paper's "
            "measurements built into the model, so checks 3 and 4 confirm the implementation, not the physics; "
            "calibrate them from your own rig with designer calibrate",
            "Figs. 7–12",
        ),
    ]
    return [{"quantity": q, "equation": e, "source": s} for q, e, s in rows]


def _point_row(i, p, marks="") -> dict:
    row = {
        "index": i,
        "P": display.number(p.threshold_force, "threshold_force"),
        "P_lbf": display.number(p.threshold_force / COMMON_UNITS["lbf"][1], "threshold_force"),
        "F": display.number(p.turning_effort, "turning_effort"),
        "F_lbf": display.number(p.turning_effort / COMMON_UNITS["lbf"][1], "turning_effort"),
        "V_c": display.number(p.critical_speed, "critical_speed"),
        "family": p.family,
        "wheel": p.wheel or "",
        "marks": marks,
        "epsilon": fmt(p.epsilon, ".4g"),
        "status": p.status,
    }
    row.update(_design_cells(p.design))
    row["c_f"] = display.number(p.design.damping, "damping")
    return row


def _parameter_info(name: str) -> str:
    info = parameters.PARAMETERS.get(name)  # the one parameter table (designer/parameters.py)
    if info:
        return info.description
    if "." in name:
        var, side = name.split(".", 1)
        return f"{'upper' if side == 'max' else 'lower'} bound of {var}"
    return name.replace("_", " ")


def _tradeoff_rows(problem, rows) -> list[dict]:
    """Table rows of the groove/damper trade-off; consecutive diameters where the trail alone suffices are merged."""

    out: list[dict] = []
    firsts: list[tuple[str, str] | None] = []  # each row's first (mm, in) diameter when the trail alone suffices
    for r in rows:
        d_mm, d_in = length(r.diameter)
        row = {"d_mm": d_mm, "d_in": d_in, "wheel": r.wheel or ""}
        for key, mech in (("groove", "groove alone"), ("damper", "damper alone"), ("mix", "optimum mix")):
            v = r.effort.get(mech)
            row[key] = "cannot reach V_req" if v is None else display.shown(v, "turning_effort")
        mix = r.designs.get("optimum mix")
        bare = mix is not None and is_bare_fork(problem.bounds, mix) and not problem.wheels
        if bare and firsts and firsts[-1] and out[-1]["mix"] == row["mix"]:
            out[-1].update(d_mm=f"{firsts[-1][0]} – {d_mm}", d_in=f"{firsts[-1][1]} – {d_in}")
            continue
        out.append(row)
        firsts.append((d_mm, d_in) if bare else None)
    for row, first in zip(out, firsts):
        if first:
            row["mix"] += " (trail alone suffices)"
    return out


CARD_HEADER = [
    "trail T",
    "diameter d",
    "groove B",
    "damping c_f",
    display.label("turning_effort"),
    display.label("threshold_force"),
    "V_q: speed held with prob. {level}",
    "P(shimmy): exact (Monte Carlo ± SE)",
    display.label("swept_radius"),
]
"""The columns of the caster to build (one row): sizes as the user writes them, then what it does (the names of
the quantities from the parameter table)."""


def _caster_cells(rec, units: str) -> list[str]:
    """One caster's row of the first screen (display strings, sizes in ``units``)."""
    d = rec.design
    limit = f" (limit {size(rec.swept_radius_max, units)})" if rec.swept_radius_max is not None else " (no limit)"
    return [
        size(d.trail, units),
        size(d.diameter, units) + (f" ({rec.wheel})" if rec.wheel else ""),
        size(d.groove, units),
        display.shown(d.damping, "damping"),
        display.shown(rec.turning_effort, "turning_effort"),
        display.shown(rec.threshold_force, "threshold_force"),
        display.shown(rec.confident_speed, "confident_speed"),
        f"{display.percent(rec.shimmy_probability)} ({display.percent(rec.shimmy_probability_mc)} ± "
        f"{display.percent(rec.shimmy_probability_se)})",
        size(rec.swept_radius, units) + limit,
    ]


GLOSSARY = [
    (
        "best balance (knee)",
        "the caster of a front farthest from the straight line between its two ends, both forces scaled to the "
        "front's range: on either side of it, easing one force costs much more of the other",
    ),
    ("front (Pareto front)", "the casters for which neither force can be lowered without raising the other"),
    ("buildable front", "the front among the casters that the parts of [stock] can make"),
    (
        "risk-bounded front",
        "a front whose every caster shimmies below V_target with probability at most α (Eq. 7 with the scatter "
        "of its constants and of the model); the continuous one lets every size vary freely",
    ),
    ("V_q", "the speed the caster stays free of shimmy up to with probability 1 − α"),
    ("P(shimmy) ± SE", "the probability of shimmy at V_target, estimated by Monte Carlo, ± its standard error"),
    (
        "α + 2 SE",
        "a Monte Carlo estimate within the bound α up to twice its standard error is within the bound: the "
        "estimate's own noise is not counted against the caster",
    ),
    (
        "weighted optimum",
        "the continuous caster that minimises J = w_turn F_turn + w_threshold P; it is not the recommendation",
    ),
    ("swept radius", "T + d/2, the circle the caster sweeps about its swivel; the footrest must clear it"),
]
"""The first screen's terms, in plain words (the "Terms" panel)."""


def _law_panels(data: ReportData, units: str) -> list[Panel]:
    """The risk law's panels under the card, in order: a diameter outside Table 1, where the risk comes from, the
    purchasing spec and what measuring the wheel is worth (sizes in ``units``)."""
    rec = data.recommendation
    if rec is None:
        return []
    out = []
    outside = [r for r in (rec, *rec.alternatives) if r.extrapolated]
    if outside:
        text = "; ".join(f"the {r.role} caster's d = {size(r.design.diameter, units)}" for r in outside)
        text += (
            " lies outside Table 1's 4–8 in: the inertia fit and Eq. 7's check are extrapolated (the risk "
            "law's prediction interval of I_w widens with it)."
        )
        out.append(Panel("extrapolated", "Outside Table 1", text))
    risk = rec.risk
    if risk is not None:
        text = (
            f"P(shimmy at {display.shown(rec.target_speed, 'target_speed')}) = {percent(risk['probability'])} "
            f"(the law below, by quadrature; its Monte Carlo: {percent(risk['monte_carlo'])} ± "
            f"{percent(risk['se'])}). {risk['dominant']}"
        )
        law = [src["distribution"] + (f", ν = {src['dof']}" if src["dof"] else "") for src in risk["sources"]]
        rows = [
            [s["name"], d, f"{s['scale']:.4g}", s["kind"], percent(s["share"])] for s, d in zip(risk["sources"], law)
        ]
        header = ["source", "distribution of its log", "scale", "kind", "share of var log V_c"]
        caption = (
            "Model error and the inertia of a wheel known by its diameter come from Table 1 (data); "
            "M_f/θ0 and K_s scatters are assumptions; a measured wheel's is the measurement's. Caveats: "
            + "; ".join(f"{src['name']}: {'; '.join(src.get('caveats', []))}" for src in risk["sources"])
            + "."
        )
        table = PanelTable(header, rows, [False, False, True, False, True])
        out.append(Panel("risk", "Where the risk comes from", text, table, caption=caption))
    if rec.spec is not None:
        out.append(spec_panel(rec, units))
    if rec.if_measured is not None:
        out.append(Panel("if_measured", "If you measure the wheel", rec.headline(lambda x: size(x, units))))
    return out


def spec_rows(spec, units: str) -> list[list[str]]:
    """The spec's table: each inspectable part's nominal, tolerance (± from ``[tolerances]``), acceptance limit
    (others at nominal) and how to measure it (display strings of ``spec.parts()``; sizes in ``units``)."""

    def shown(value: Any, part: str) -> str:
        if value is None or isinstance(value, str):
            return value or "none"
        dimension = PART_DIMENSIONS[part]
        return size(value, units) if dimension == "length" else display.shown(value, dimension=dimension)

    box = {} if spec.joint is None else spec.joint.cells(units)
    rows = []
    for row in spec.parts():
        tol = row["tolerance"]
        if tol is None:
            spread = "—"
        elif row["part"] == "friction_moment":
            spread = f"± {percent(tol)}"
        elif row["part"] == "wheel_inertia":
            spread = tol if isinstance(tol, str) else f"≤ {display.shown(tol, dimension='inertia')} measured"
        else:  # a spread is finer than the sizes' 1/16 in: always to 0.01 mm
            spread = "± " + " (".join(length(tol)[:: -1 if units == "in" else 1]) + ")"
        limit = "; ".join(  # in the problem's unit first, with what it protects ("min 56.11 mm (2.209 in) [risk]")
            f"{lim.side} none"
            if lim.value is None
            else f"{lim.side} {lim.shown_in(units)} [{lim.protects}" + ("; no window" if lim.no_window else "") + "]"
            for lim in row["limits"]
        )
        limit = limit or "—"
        joint = box.get(row["part"], "—")
        rows.append([row["label"], shown(row["nominal"], row["part"]), spread, joint, limit, row["measure"]])
    return rows


def limit_notes(spec, units: str = "mm") -> list[str]:
    """Sentences for the limits that leave no window, with the fix they suggest (one-at-a-time and joint box),
    lengths in the problem's ``units`` first."""
    out = []
    for lim in spec.limits:
        if lim.no_window and lim.protects == "footrest":
            out.append(
                f"The trail maximum {lim.shown_in(units)} is the footrest limit T + d/2 ≤ R_max, not a risk limit, and it "
                "leaves no window above the nominal trail: fix: a shorter trail step or a smaller wheel."
            )
    joint = spec.joint
    if joint is not None:
        out += [
            f"Joint box, {key.replace('_', ' ')}: {text}." for key, text in joint.notes.items() if key != "trail_max"
        ]
    return out


PART_DIMENSIONS = {
    "trail": "length",
    "diameter": "length",
    "groove": "length",
    "friction_moment": "moment",
    "wheel_inertia": "inertia",
}
"""The dimension of each inspectable part of a spec (its worst corner's edges and its table's nominal values)."""


def corner_sentence(spec) -> str:
    """P(shimmy) at the worst corner of the tolerance box, whether the caster holds there (or: no tolerances)."""
    c = spec.corner
    if c is None:
        return "No [tolerances] in the problem: the worst corner is not computed."
    edges = ", ".join(
        f"{k.replace('_', ' ')} {display.shown(v, dimension=PART_DIMENSIONS[k], units='mm')}"
        for k, v in c["edges"].items()
    )
    return (
        f"At the worst corner of the tolerances (every part at its own worst edge at once: {edges}; the law's "
        f"scatter on top), P(shimmy at {display.shown(spec.required_speed, 'critical_speed')}) = "
        f"{c['probability']:.2%} against {c['nominal_probability']:.2%} at nominal: the caster "
        + ("holds" if c["holds"] else "does NOT hold")
        + f" the bound α = {percent(spec.alpha)}."
    )


SPEC_COLUMNS = (
    "part",
    "nominal",
    "tolerance",
    "joint box: accept when every part is inside",
    "one part at a time (others at nominal)",
    "how to measure",
)
"""The headings of the spec's table, in the report's panel and on the inspection sheet (on a phone each cell of
the sheet is one line under its part, named by its heading)."""


def spec_panel(rec, units: str) -> Panel:
    """The spec a factory inspects against: nominal, tolerance, acceptance limit and how to measure each part."""
    spec = rec.spec
    no_limit = [f"{lim.part} {lim.side}: {lim.reason}" for lim in spec.limits if lim.value is None]
    text = f"{acceptance_text(spec)} {corner_sentence(spec)}"
    text += f" {rec.enforced_sentence()}" if rec.enforced is not None else ""
    caption = f"M_f = c_f θ0 with θ0 = {math.degrees(spec.disturbance_angle):.0f}° (Eq. 7). "
    caption += "No limit inside the model's range: " + "; ".join(no_limit) + ". " if no_limit else ""
    table = PanelTable(list(SPEC_COLUMNS), spec_rows(spec, units), [False, True, True, True, True, False])
    caption += " ".join(limit_notes(spec, units))
    return Panel("spec", "The spec to inspect against", text, table, caption=caption)


def acceptance_text(spec) -> str:
    """What the two kinds of limits mean: the joint box (any caster inside passes) and the one-at-a-time limits
    (each at α with the others at nominal: parts inside them can fail together); risk against footrest."""
    joint = "" if spec.joint is None else spec.joint.sentence() + " "
    return (
        joint + "The one-part-at-a-time limits are each where, with every OTHER part at nominal, the exact law gives "
        f"P(shimmy) = α = {percent(spec.alpha)}: a part beyond one fails, but parts each inside them can together "
        "exceed α, so accept by the joint box. [risk] marks a limit set by P = α, [footrest] the swept radius "
        "T + d/2 ≤ R_max (geometry, with the diameter at its tolerance's upper edge; P falls as the trail grows)."
    )


def caster_panel(caster, units: str) -> Panel:
    """Every listed quantity of the caster to build (:data:`designer.parameters.OUTPUT_TABLE`) from its record's
    :class:`~designer.model.Caster`: label, value, unit and precision from the table, lengths in ``units``.  A
    quantity added to the table (and to the evaluator) appears here with no other edit."""
    rows = [
        [display.label(p.name), display.shown(caster[p.name], p.name, units)]
        for p in parameters.OUTPUT_TABLE
        if p.listed and p.name in caster and caster[p.name] is not None
    ]
    table = PanelTable(["quantity", "value"], rows, [False, True])
    return Panel("numbers", "The numbers of the caster to build", table=table)


def _after_panels(data: ReportData, units: str, level: str) -> list[Panel]:
    """The panels under the card: the other casters from the same parts, the knock-safe speed as a second
    opinion, the terms."""
    rec = data.recommendation
    out = [caster_panel(rec.caster, units), *_law_panels(data, units)]
    casters = [rec, *rec.alternatives]
    if rec.alternatives:
        header = ["caster", *(h.format(level=level) for h in CARD_HEADER)]
        rows = [[c.role, *_caster_cells(c, units)] for c in casters]
        table = PanelTable(header, rows, [False] + [True] * len(CARD_HEADER), first_row_marked=True)
        out.append(Panel("alternatives", "Other casters from the same parts", front_count_sentence(rec), table))
    if data.knock_safe:
        theta0 = math.degrees(float(data.problem.conditions.disturbance_angle))
        knocks = list(data.knock_safe) + [None] * (1 + len(rec.alternatives))
        text = (
            "The design criterion is the risk bound on Eq. 7 above. The knock-safe speed is the highest "
            "speed at which a knock of that size dies out instead of growing into shimmy, simulated with the "
            "paper's time-domain model (Appendix B: rolling tyre, Coulomb friction; as designer evaluate "
            f"--knock-safe), to {100 * float((data.knock_safe[0] or {}).get('knock_safe_rtol', 0.005)):.1f} %; "
            "V_c (Eq. 7) is the threshold for the design knock θ0, and a bigger knock starts shimmy at a lower "
            "speed. " + _knock_band(data)
        )
        header = ["caster", "V_c (Eq. 7)", f"{theta0:.0f}° knock", f"{2 * theta0:.0f}° knock"]
        keys = ("knock_safe_speed", "knock_safe_speed_double")
        rows = [  # knock-safe speeds shown as V_c is, MISSING where not computed
            [
                c.role,
                *(display.shown(v, "critical_speed") for v in (c.critical_speed, *((k or {}).get(x) for x in keys))),
            ]
            for c, k in zip(casters, knocks)
        ]
        table = PanelTable(header, rows, [False, True, True, True], first_row_marked=True)
        out.append(Panel("knock-safe", "Knock-safe speed: a second opinion", text, table))
    out.append(Panel("terms", "Terms", table=PanelTable(["term", "meaning"], [list(row) for row in GLOSSARY])))
    return out


def _build_context(data: ReportData) -> dict:
    """The first screen: ONE caster to build (in plain words, drawn, its numbers), then the panels under it."""
    rec = data.recommendation
    if rec is None:
        return {"available": False, "error": data.recommendation_error or "no recommendation"}
    d, units = rec.design, data.problem.units
    sizes = d.trail, d.diameter, d.groove, data.problem.conditions.threshold_height, rec.swept_radius_max
    level = f"{percent(1 - rec.alpha)}" if rec.alpha is not None else f"{percent(0.95)} (default scatter)"
    return {
        "available": True,
        "lead": lead_sentence(data),
        "lines": build_lines(data),
        "headline": f"Build this: {caster_sentence(rec, units)}",
        "header": [h.format(level=level) for h in CARD_HEADER],
        "row": _caster_cells(rec, units),
        "level": level,
        "svg": caster_svg(*sizes, label=f"{data.problem.name}: the recommended caster to scale", units=units),
        "rule": rec.rule,
        "panels": _panels(data),
        "after": _after_panels(data, units, level),
    }


def front_caption(data: ReportData) -> str:
    """Figure 1's caption, from the marks its legend shows (:data:`designer.plots.fronts.MARK_WORDS` names each
    marker as drawn): the star is the caster to build."""
    kinds = [m["kind"] for m in _figures.arguments("front", data).get("marks", [])] if len(data.front) else []
    marked = [MARK_WORDS[k] for k in dict.fromkeys(kinds)]
    text = FIGURE_INFO["front"][1]
    if marked:
        text += "; marked: " + ", ".join(marked)
    if data.tighter is not None and len(data.tighter.points):
        text += "; grey dashes: the front for a 10 % higher target speed (check 8c)"
    return text + "."


def _knock_band(data: ReportData) -> str:
    """The knock-safe speed's Table 1 error at the problem's knock θ0: the log RMS and the bias of the simulated
    onsets of wheels C–G (T = 2 in) against their measured onsets, beside Eq. 7's model error."""
    band = data.knock_safe_band
    if band is None:
        return ""
    return (
        f"Against Table 1's wheels C–G (T = 2 in, {math.degrees(band['angle']):.0f}° knock) the simulated onsets "
        f"have a log RMS error of {band['log_rms']:.3f} and a bias of {band['bias']:+.3f}; Eq. 7's model error is "
        f"a log RMS of {TABLE1_LOG_RMS_ERROR:.4f}."
    )


def _objectives(turning_effort: float, threshold_force: float) -> str:
    """The two objectives [N] as one cell, "F_turn 7.942 N, P 106.96 N" (symbols and precisions from the table)."""
    return ", ".join(
        f"{display.quantity(name).symbol} {display.shown(value, name)}"
        for name, value in (("turning_effort", turning_effort), ("threshold_force", threshold_force))
    )


def _indicators(front, problem, knee, best) -> list[dict]:
    """The front's indicators (hypervolume, reference, ideal and nadir points, knee, best J); none for an empty front."""
    if not front.points:
        return []
    ideal, nadir = front.ideal_nadir()
    w = np.asarray(problem.weights, float)
    normalised = (
        "objectives normalised by (f − ideal)/(nadir − ideal) with this front's ideal and nadir; reference point "
        "(1.1, 1.1) in normalised units"
    )
    if len(front) == 1:
        normalised += "; a single point in its own normalisation always gives 1.1² = 1.21: no information"
    rows = [
        ("hypervolume (normalised)", fmt(front.hypervolume(), ".5f"), normalised),
        (
            "hypervolume reference point",
            _objectives(*front.reference_point()),
            "nadir + 10 % of the front's extent (1 N where the extent is zero)",
        ),
        ("ideal point", _objectives(*ideal), "best value of each objective on the front"),
        ("nadir point", _objectives(*nadir), "worst value of each objective on the front"),
        (
            "knee",
            ("solved on the continuous front" if knee not in front.points else f"point {front.points.index(knee)}")
            + f": {_objectives(knee.turning_effort, knee.threshold_force)}; {knee.design.describe()}",
            "farthest from the chord between the two ends, in normalised objectives",
        ),
        (
            "best J on the front",
            f"point {front.points.index(best)}: {_objectives(best.turning_effort, best.threshold_force)}, J = "
            f"{display.shown(best.caster.J(w) if best.caster else None, 'weighted')}; {best.design.describe()}",
            f"front point minimising J = {w[0]:g} F_turn + {w[1]:g} P (the exact optimum is in the solver section)",
        ),
    ]
    return [{"name": n, "value": v, "note": note} for n, v, note in rows]


_SOLUTION_OBJECTIVES = {"F": "turning_effort", "P": "threshold_force", "J": "weighted"}
"""The solver section's objective cells and their quantities."""


def _solution(s) -> dict | None:
    """The solver section: the exact weighted optimum, its cross-check and its largest sensitivities."""
    if s is None:
        return None
    cross = [{"solver": k, "J": fmt(v, ".8f", "N")} for k, v in s.cross_check.items()]
    missing = [k for k in ("casadi-ipopt", "cvxpy-gp", "scipy-slsqp") if k not in s.cross_check]
    return {
        "design": _design_cells(s.design),
        "describe": s.design.describe(),
        "wheel": s.wheel,
        **{key: display.shown(s.objectives[name], name) for key, name in _SOLUTION_OBJECTIVES.items()},
        "V_c": display.shown(s.critical_speed, "critical_speed"),
        "active": ", ".join(s.active) or "none",
        "cross_check": cross,
        "missing": ", ".join(missing),
        "agreement": fmt(s.agreement(), ".1e"),
        "sensitivities": [
            {"name": k, "value": fmt(v, "+.4f"), "what": _parameter_info(k)}
            for k, v in sorted(s.sensitivities.items(), key=lambda kv: -abs(kv[1]))[:8]
        ],
    }


def build_context(data: ReportData) -> dict:
    """Every table of the report as display strings (SI and inches), shared by the HTML and Markdown templates."""
    problem, front = data.problem, data.front
    knee, best = front.knee(), front.weighted_best()
    marked = (("knee", knee), ("best J on the front", best))
    points = [_point_row(i, p, ", ".join(m for m, q in marked if q is p)) for i, p in enumerate(front.points)]
    figures = [
        {
            "name": n,
            "title": FIGURE_INFO[n][0],
            "caption": front_caption(data) if n == "front" else FIGURE_INFO[n][1],
            "file": f"figures/{n}.svg",
        }
        for n in _figures.FIGURES
    ]

    all_checks = data.paper_checks + data.front_checks
    return {
        "problem": problem,
        "title": f"{problem.title} ({problem.name})",
        "summary": summary_lines(data),
        "build": _build_context(data),
        "degenerate": data.degenerate_reason,
        "problem_rows": _problem_rows(problem),
        "model_rows": _model_rows(problem),
        "solution": _solution(data.solution),
        "solution_error": data.solution_error,
        "paper_checks": [_check_row(c) for c in data.paper_checks if c.kind != "identity"],
        "identity_checks": [_check_row(c) for c in data.paper_checks if c.kind == "identity"],
        "front_checks": [_check_row(c) for c in data.front_checks],
        "checks_summary": data.checks_summary,
        "checks_passed": sum(bool(c.passed) for c in all_checks),
        "checks_total": len(all_checks),
        "points": points,
        "catalog": bool(problem.wheels),
        "failed": [_point_row(i, p) for i, p in enumerate(front.failed)],
        "gaps": [{"index": i, "what": what} for i, what in data.gaps],
        "indicators": _indicators(front, problem, knee, best),
        "tradeoff": _tradeoff_rows(problem, data.tradeoff),
        "figures": figures,
        "run": data.run,
        "versions": ", ".join(f"{k} {v}" for k, v in data.run.get("versions", {}).items() if v),
        "front_method": front.meta.get("method", ""),
        "front_solver": front.meta.get("solver", ""),
    }
