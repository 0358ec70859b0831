"""The studio's panels: the caster to build, a caster's card, the fixes of my caster (Dash components).

Each function turns the plain records of :mod:`designer.studio.view` (numbers read from the study records) into
components; the callbacks of :mod:`designer.studio.app` put them on the page.  Every number is written by
:mod:`designer.display` in the problem's unit system (``problem.units``: a millimetre problem answers in mm).
"""

from __future__ import annotations

import base64
import math

from dash import dcc, html

from designer import display
from designer.studies.acceptance import box_short
import designer.studio.figures as figures
import designer.studio.view as view
from designer.studio.layout import CSS, MAX_CARD_BUTTONS

ROLE_NAMES = {"recommended": "the caster to build"}
"""A caster's name on the page by its role; the other roles are the recommendation's own words ("easiest to
turn", "easiest over the sill", "between the ends")."""


def role_name(role: str | None) -> str:
    """What a caster is for, in words: "the caster to build", "easiest to turn", …"""
    return ROLE_NAMES.get(role or "", role or "a caster of the front")


def design_text(d: dict, units: str) -> str:
    """A design as one line in ``units``: "T 63.50 mm, d 177.80 mm, B 19.05 mm, c_f 1.30 N·m/rad"."""
    return ", ".join(
        f"{symbol} {display.shown(d[name], name, units)}"
        for symbol, name in (("T", "trail"), ("d", "diameter"), ("B", "groove"), ("c_f", "damping"))
    )


def _value(n: dict, name: str, units: str, element_id: str | None = None):
    """Quantity ``name`` of the numbers ``n`` with its unit, as a span with ``element_id`` (for the tests)."""
    text = display.shown(n.get(name), name, units)
    return html.Span(text, id=element_id, style=CSS["num"]) if element_id else text


def _level(problem) -> str:
    """ "95 %" for ``problem``'s α 0.05 (the probability the speed is reached with; α 0.05 without a risk bound)."""
    return display.percent(1 - (0.05 if problem.risk is None else problem.risk.probability))


def caster_sentences(n: dict, problem, prefix: str) -> list:
    """The plain-words first lines of a caster: how hard it turns and climbs the sill, its chance of shimmy at
    the target speed, and the speed it reaches; each number a span ``<prefix>-turning``, ``-threshold``,
    ``-probability``, ``-vc``, ``-confident``."""
    units = problem.units
    alpha = None if problem.risk is None else problem.risk.probability
    allowed = "" if alpha is None else f" (allowed: {display.percent(alpha)})"
    return [
        html.Div(
            [
                "Turning it takes ",
                _value(n, "turning_effort", units, f"{prefix}-turning"),
                "; climbing the sill ",
                _value(n, "threshold_force", units, f"{prefix}-threshold"),
                ".",
            ]
        ),
        html.Div(
            [
                f"Chance of shimmy at {display.shown(problem.target_speed, 'target_speed', units)}: ",
                _value(n, "shimmy_probability", units, f"{prefix}-probability"),
                allowed,
                ".",
            ]
        ),
        html.Div(
            [
                f"Speed reached without shimmy ({_level(problem)} sure): ",
                _value(n, "confident_speed", units, f"{prefix}-confident"),
                "; shimmy speed V_c (Eq. 7) ",
                _value(n, "critical_speed", units, f"{prefix}-vc"),
                ".",
            ]
        ),
    ]


def alternative_buttons(fronts: view.Fronts | None) -> list[str]:
    """The label of each of the :data:`~designer.studio.layout.MAX_CARD_BUTTONS` card buttons of the other casters
    (the page's own, filled in by each answer; a longer list's casters are on the chart): "card: easiest to turn
    (d 5.000 in)" for alternative i, "" where there is none (the page hides that button)."""
    rec = None if fronts is None else view.recommendation_record(fronts.recommendation)
    alternatives = [] if rec is None else rec["alternatives"][:MAX_CARD_BUTTONS]
    units = "in" if fronts is None else fronts.problem.units
    labels = [
        f"card: {role_name(alt['role'])} (d {display.shown(alt['design']['diameter'], 'diameter', units)})"
        for alt in alternatives
    ]
    return labels + [""] * (MAX_CARD_BUTTONS - len(labels))


def recommendation_panel(fronts: view.Fronts):
    """The caster to build in plain words (its numbers from :func:`designer.recommend`'s record), its acceptance
    limits, the other casters you can build, and how it was chosen (folded).  The card buttons are the page's
    own (:func:`alternative_buttons`)."""
    problem = fronts.problem
    units = problem.units
    rec = view.recommendation_record(fronts.recommendation)
    if rec is None:
        return [html.P(n, style={"color": "#666", "fontSize": "13px"}) for n in fronts.notes] or [
            html.P("No caster to build for these controls.", style={"fontSize": "13px"})
        ]
    rows = [
        html.H4("The caster to build", style={"margin": 0}),
        html.Div(design_text(rec["design"], units), id="rec-design", style={"fontWeight": "600"}),
        *caster_sentences(rec, problem, "rec"),
        html.Div(
            [
                "It sweeps a circle of radius ",
                _value(rec, "swept_radius", units),
                ""
                if problem.swept_radius_max is None
                else f" (room: {display.shown(problem.swept_radius_max, 'swept_radius', units)})",
                ".",
            ]
        ),
        # the spec goods-in inspects against; filled in a moment after the chart when the fronts were computed
        # without it (app._limits_callback)
        html.Div(limits_text(rec, units), id="rec-limits", style={"fontSize": "13px", "marginTop": "4px"}),
    ]
    if rec["alternatives"]:
        rows.append(html.H5("Other casters you can build", style={"margin": "8px 0 2px"}))
    for alt in rec["alternatives"]:
        rows.append(
            html.Div(
                [
                    html.B(f"{role_name(alt['role'])}: "),
                    design_text(alt["design"], units),
                    f"; turning {display.shown(alt['turning_effort'], 'turning_effort', units)}, sill "
                    f"{display.shown(alt['threshold_force'], 'threshold_force', units)}, chance of shimmy "
                    f"{display.shown(alt['shimmy_probability'], 'shimmy_probability', units)} ",
                ],
                className="alternative",
                style={"fontSize": "13px", "marginTop": "2px"},
            )
        )
    if rec.get("rule"):
        rows.append(
            html.Details(
                [html.Summary("How it was chosen"), html.Div(str(rec["rule"]))],
                style={"fontSize": "13px", "color": "#555", "marginTop": "4px"},
            )
        )
    return rows


LIMITS_PENDING = "acceptance limits: computing…"
"""What the panel says while the recommended caster's limits are being computed."""

LIMITS_FAILED = "acceptance limits: not computed (the studio's console says why; `designer spec` gives them)"
"""What the panel says when computing the limits failed in a way the model does not explain (an internal error)."""


def limits_text(rec: dict | None, units: str = "in") -> str:
    """The recommended caster's acceptance limits and worst corner as one line, lengths in the problem's
    ``units``, from :func:`designer.studio.view.recommendation_record` (:data:`LIMITS_PENDING` before its spec is
    computed, "" when it has no limit): the joint box (a caster whose parts are all inside passes) where the
    spec has one, else the limits of one part at a time, labelled as such."""
    if rec is None:
        return ""
    if rec.get("limits") is None:
        return LIMITS_PENDING
    if not rec["limits"]:
        return ""
    corner = rec.get("corner")
    worst = (
        ""
        if corner is None
        else f"; worst corner: chance of shimmy {display.percent(corner[0])}" + ("" if corner[1] else " (too high)")
    )
    joint = rec.get("joint")
    if joint is not None:
        return "acceptance limits: accept a caster when every part is inside: " + box_short(joint, units) + worst
    parts = [f"{lim.part.replace('_', ' ')} {lim.side} {lim.shown_in(units)}" for lim in rec["limits"]]
    return "acceptance limits, one part at a time (the others at nominal): " + "; ".join(parts) + worst


def numbers_table(n: dict, problem, prefix: str):
    """A caster's numbers as a table, each in ``problem``'s units; the values' ids ``<prefix>-<key>`` (the table's
    other listed quantities, ``n["more"]``, by their own names: label and precision from the parameter table)."""
    units = problem.units
    rows = [
        ("turning", "turning effort F_turn", _value(n, "turning_effort", units)),
        ("threshold", "sill force P", _value(n, "threshold_force", units)),
        ("vc", "shimmy speed V_c (Eq. 7)", _value(n, "critical_speed", units)),
    ]
    if "knock_safe_speed" in n:  # beside V_c: simulated, so only on the card (a click)
        theta0 = math.degrees(n["knock_angle"])
        rows.append(
            (
                "knocksafe",
                f"knock-safe speed, {theta0:.0f}° / {2 * theta0:.0f}° knock",
                f"{display.number(n['knock_safe_speed'], 'critical_speed', units)} / "
                f"{display.shown(n['knock_safe_speed_double'], 'critical_speed', units)}",
            )
        )
    room = problem.swept_radius_max
    room_text = "" if room is None else f" (room {display.shown(room, 'swept_radius', units)})"
    rows += [
        ("target", "target speed", display.shown(problem.target_speed, "target_speed", units)),
        ("probability", "chance of shimmy at the target", _value(n, "shimmy_probability", units)),
        ("confident", f"speed reached ({_level(problem)} sure)", _value(n, "confident_speed", units)),
        ("swept", "swept radius T + d/2", _value(n, "swept_radius", units) + room_text),
        ("inertia", "wheel inertia I_w" + (" (measured)" if n.get("measured") else ""), _value(n, "inertia", units)),
    ]
    rows += [(key, display.label(key), display.shown(value, key, units)) for key, value in n.get("more", {}).items()]
    return html.Table(
        [
            html.Tr(
                [html.Td(label, style={"paddingRight": "8px"}), html.Td(value, id=f"{prefix}-{key}", style=CSS["num"])]
            )
            for key, label, value in rows
        ],
        style={"fontSize": "13px"},
    )


def card_panel(problem, record, name: str):
    """The card of one caster: its record's numbers (:func:`designer.studio.view.card`), drawing, sweeps and
    θ(t) after a knock."""
    data = view.card(problem, record)
    n = data["numbers"]
    units = problem.units
    parts = [
        html.H4(f"Card: {name}", id="card-title", style={"margin": "2px 0"}),
        html.Div(design_text(n["design"], units), id="card-design", style={"fontSize": "13px"}),
    ]
    if data["svg"]:
        src = "data:image/svg+xml;base64," + base64.b64encode(data["svg"].encode()).decode()
        # at its own size (its text 11 px), in a box that scrolls sideways on a phone rather than shrink it
        parts.append(html.Div(html.Img(src=src, id="card-drawing"), style={"overflowX": "auto", "maxWidth": "100%"}))
    parts.append(numbers_table(n, problem, "card"))
    alpha = None if problem.risk is None else problem.risk.probability
    sweeps = figures.sweeps_figure(data["sweeps"], problem.target_speed, alpha, units)
    parts.append(dcc.Graph(id="card-sweeps", figure=sweeps, config={"displayModeBar": False}))
    if data.get("knock") is not None:
        knock = figures.knock_figure(data["knock"], problem.target_speed)
        parts.append(dcc.Graph(id="card-knock", figure=knock, config={"displayModeBar": False}))
    elif data.get("knock_error"):
        parts.append(html.Div(data["knock_error"], style=CSS["error"]))
    return parts


def fixes_panel(result: dict, problem):
    """My caster's numbers and its ranked fixes (records of :func:`designer.fix`), in ``problem``'s units."""
    units = problem.units
    n = result["numbers"]
    head = html.Div(
        [
            html.B("my caster: "),
            f"shimmy speed V_c {display.shown(n['critical_speed'], 'critical_speed', units)}, ",
            html.Span(
                f"chance of shimmy at {display.shown(problem.target_speed, 'target_speed', units)} "
                f"{display.shown(n['shimmy_probability'], 'shimmy_probability', units)}",
                id="mine-probability",
            ),
            f", turning {display.shown(n['turning_effort'], 'turning_effort', units)}, "
            f"sill {display.shown(n['threshold_force'], 'threshold_force', units)}",
        ],
        style={"fontSize": "13px"},
    )
    summary = html.Div(result.get("summary") or "", id="fix-summary", style={"fontSize": "13px"})
    if not result["fixes"]:
        return [head, summary, html.Div("no fix listed", id="fixes")]
    items = []
    for row in result["fixes"]:
        extra = [
            f"chance of shimmy {display.shown(row['shimmy_probability'], 'shimmy_probability', units)}",
            f"reaches {display.shown(row['confident_speed'], 'confident_speed', units)} ({_level(problem)} sure)",
            f"turning {display.shown(row['turning_effort'], 'turning_effort', units)}",
            f"sill {display.shown(row['threshold_force'], 'threshold_force', units)}",
        ]
        items.append(
            html.Li(
                [
                    html.Span(str(row.get("description") or ""), style={"fontWeight": "600"}),
                    html.Span(" · " + "; ".join(extra)),
                ],
                className="fix",
                style={"fontSize": "13px"},
            )
        )
    found = result.get("found") or len(items)
    which = f"the top {len(items)} of {found} found" if found > len(items) else f"all {found} found, best first"
    parts = [head, summary, html.H5(f"Ranked fixes: {which}", style={"margin": "4px 0"})]
    if found > len(items):
        parts.append(
            html.Div(
                ["the full list: ", html.Code(result.get("command") or "designer fix")],
                id="fixes-more",
                style={"fontSize": "13px"},
            )
        )
    parts.append(html.Ol(items, id="fixes", style={"maxHeight": "320px", "overflowY": "auto", "margin": "2px 0"}))
    return parts
