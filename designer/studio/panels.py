"""The studio's panels: the recommendation, a design's numbers, its card, the fixes of my caster (Dash components).

Each function turns records of :mod:`designer.studio.view` into components; the callbacks of
:mod:`designer.studio.app` put them on the page.
"""

from __future__ import annotations

import base64
import math

from dash import dcc, html

from designer.model import Design
import designer.studio.figures as figures
import designer.studio.view as view
from designer.studio.layout import CSS
from designer.units import INCH


def _fmt(value, spec=".4g", unit=""):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    return f"{value:{spec}}{(' ' + unit) if unit else ''}"


def _design_text(d: dict) -> str:
    return (
        f"T {d['trail'] / INCH:.3f} in, d {d['diameter'] / INCH:.3f} in, B {d['groove'] / INCH:.3f} in, "
        f"c_f {d['damping']:.3f} N·m/rad"
    )


def recommendation_panel(fronts: view.Fronts):
    rec = view.recommendation_record(fronts.recommendation)
    if rec is None:
        best = fronts.risk if fronts.risk is not None else fronts.continuous
        knee = best.weighted_best() if best is not None and len(best) else None
        notes = [html.P(n, style={"color": "#666", "fontSize": "12px"}) for n in fronts.notes]
        if knee is None:
            return notes
        return [
            html.H4("Weighted optimum on the front (no recommendation in this version)", style={"margin": 0}),
            html.Div(_design_text(knee.design.to_dict()), id="rec-design"),
            html.Div(
                [
                    "F_turn ",
                    html.Span(_fmt(knee.turning_effort), id="rec-turning"),
                    " N, P ",
                    html.Span(_fmt(knee.threshold_force), id="rec-threshold"),
                    " N",
                ],
                style=CSS["num"],
            ),
            *notes,
        ]
    alpha = fronts.problem.risk
    p = rec.get("shimmy_probability")
    rows = [
        html.H4("Recommendation", style={"margin": 0}),
        html.Div(_design_text(rec["design"]), id="rec-design"),
        html.Div(
            [
                "F_turn ",
                html.Span(_fmt(rec["turning_effort"]), id="rec-turning"),
                " N · P ",
                html.Span(_fmt(rec["threshold_force"]), id="rec-threshold"),
                " N · V_c ",
                html.Span(_fmt(rec["critical_speed"]), id="rec-vc"),
                " m/s",
            ],
            style=CSS["num"],
        ),
        html.Div(
            [
                f"speed reached w.p. {1 - alpha.probability:.0%}: " if alpha is not None else "speed reached: ",
                html.Span(_fmt(rec.get("confident_speed")), id="rec-confident"),
                " m/s · P(shimmy at target) ",
                html.Span("–" if p is None else f"{100 * p:.2f} %", id="rec-probability"),
                " · swept radius ",
                _fmt((rec.get("swept_radius") or math.nan) / INCH, ".3f", "in"),
            ],
            style=CSS["num"],
        ),
    ]
    # the spec goods-in inspects against (each limit with the other parts at nominal); filled in a moment after
    # the chart when the fronts were computed without it (app._limits_callback)
    rows.append(html.Div(limits_text(rec), id="rec-limits", style={"fontSize": "12px"}))
    if rec.get("rule"):
        rows.append(html.Div(str(rec["rule"]), style={"fontSize": "12px", "color": "#555"}))
    for alt in rec["alternatives"]:
        rows.append(
            html.Div(
                f"{alt['label']}: {_design_text(alt['design'])}; F_turn {alt['turning_effort']:.3f} N,"
                f" P {alt['threshold_force']:.2f} N",
                style={"fontSize": "12px"},
            )
        )
    return rows


LIMITS_PENDING = "acceptance limits: computing…"
"""What the card says while the recommended caster's limits are being computed."""

LIMITS_FAILED = "acceptance limits: not computed (the studio's console says why; `designer spec` gives them)"
"""What the card says when computing the limits failed in a way the model does not explain (an internal error)."""


def limits_text(rec: dict | None) -> str:
    """The recommended caster's acceptance limits and worst corner as one line, from
    :func:`designer.studio.view.recommendation_record` (:data:`LIMITS_PENDING` before its spec is computed,
    "" when it has no limit)."""
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
        else f"; worst corner P(shimmy) {100 * corner[0]:.2f} %" + ("" if corner[1] else " (does NOT hold)")
    )
    return "acceptance limits: " + "; ".join(rec["limits"]) + worst


def numbers_table(n: dict, prefix: str):
    rows = [
        ("F_turn (turning effort)", _fmt(n["turning_effort"], ".4g", "N")),
        ("P (threshold force)", _fmt(n["threshold_force"], ".4g", "N")),
        ("V_c (Eq. 7)", _fmt(n["critical_speed"], ".4g", "m/s")),
        ("target speed", _fmt(n["target_speed"], ".3g", "m/s")),
    ]
    if n.get("shimmy_probability") is not None:
        rows += [
            (
                "P(shimmy) at target",
                f"{100 * n['shimmy_probability']:.2f} % (± {100 * n['shimmy_probability_se']:.2f})",
            ),
            (f"speed reached w.p. {1 - n['alpha']:.0%}", _fmt(n["confident_speed"], ".4g", "m/s")),
        ]
    rows += [
        (
            "swept radius T + d/2",
            _fmt(n["swept_radius"] / INCH, ".3f", "in")
            + ("" if n.get("swept_radius_max") is None else f" (max {n['swept_radius_max'] / INCH:.3g} in)"),
        ),
        ("I_w", _fmt(n["inertia"], ".3g", "kg·m²")),
    ]
    keys = ["turning", "threshold", "vc", "target", "probability", "confident", "swept", "inertia"]
    if n.get("shimmy_probability") is None:
        keys = ["turning", "threshold", "vc", "target", "swept", "inertia"]
    if "knock_safe_speed" in n:  # beside V_c: simulated, so only on the card (a click)
        theta0 = math.degrees(n["knock_angle"])
        rows.insert(
            3,
            (
                f"knock-safe speed, {theta0:.0f}° / {2 * theta0:.0f}° knock",
                f"{_fmt(n['knock_safe_speed'], '.3g')} / {_fmt(n['knock_safe_speed_double'], '.3g')} m/s",
            ),
        )
        keys.insert(3, "knocksafe")
    return html.Table(
        [html.Tr([html.Td(k), html.Td(v, id=f"{prefix}-{key}", style=CSS["num"])]) for (k, v), key in zip(rows, keys)],
        style={"fontSize": "13px"},
    )


def card_panel(problem, design: Design, name: str, inertia: float | None = None):
    data = view.card(problem, design, inertia=inertia)
    n = data["numbers"]
    parts = [
        html.H4(f"Card: {name}", id="card-title", style={"margin": "2px 0"}),
        html.Div(_design_text(n["design"]), style={"fontSize": "13px"}),
    ]
    if data["svg"]:
        src = "data:image/svg+xml;base64," + base64.b64encode(data["svg"].encode()).decode()
        parts.append(html.Img(src=src, id="card-drawing", style={"maxWidth": "100%", "maxHeight": "260px"}))
    else:
        parts.append(
            html.Div(
                "drawing: designer.plots.caster is not in this version",
                id="card-drawing",
                style={"color": "#666", "fontSize": "12px"},
            )
        )
    parts.append(numbers_table(n, "card"))
    risk = problem.risk
    parts.append(
        dcc.Graph(
            id="card-sweeps",
            figure=figures.sweeps_figure(
                data["sweeps"], problem.target_speed, None if risk is None else risk.probability
            ),
            config={"displayModeBar": False},
        )
    )
    if data.get("knock") is not None:
        parts.append(
            dcc.Graph(
                id="card-knock",
                figure=figures.knock_figure(data["knock"], problem.target_speed),
                config={"displayModeBar": False},
            )
        )
    elif data.get("knock_error"):
        parts.append(html.Div(data["knock_error"], style=CSS["error"]))
    return parts


def fixes_panel(result: dict):
    n = result["numbers"]
    p = n.get("shimmy_probability")
    head = html.Div(
        [
            html.B("my caster: "),
            f"V_c {n['critical_speed']:.3f} m/s, ",
            html.Span(
                "–" if p is None else f"P(shimmy at {n['target_speed']:.3g} m/s) {100 * p:.1f} %", id="mine-probability"
            ),
            f", F_turn {n['turning_effort']:.3f} N, P {n['threshold_force']:.2f} N",
        ],
        style={"fontSize": "13px"},
    )
    if result["fixes"] is None:
        return [head, html.Div(result["fix_note"], style={"color": "#666", "fontSize": "12px"})]
    summary = html.Div(result.get("summary") or "", id="fix-summary", style={"fontSize": "12px"})
    if not result["fixes"]:
        return [head, summary, html.Div("no fix listed", id="fixes")]
    items = []
    for row in result["fixes"]:
        text = row.get("description") or row.get("action") or row.get("label") or row.get("change") or ""
        extra = []
        if "shimmy_probability" in row:
            extra.append(f"P(shimmy) {100 * row['shimmy_probability']:.2f} %")
        if "confident_speed" in row:
            extra.append(f"reaches {row['confident_speed']:.3f} m/s w.p. 1 − α")
        for key, label, unit, spec in (("turning_effort", "F_turn", "N", ".3f"), ("threshold_force", "P", "N", ".2f")):
            if key in row:
                extra.append(f"{label} {row[key]:{spec}} {unit}")
        items.append(
            html.Li(
                [
                    html.Span(str(text), style={"fontWeight": "600"}),
                    html.Span(" · " + "; ".join(extra) if extra else ""),
                ],
                className="fix",
                style={"fontSize": "12px"},
            )
        )
    found = result.get("found") or len(items)
    parts = [head, summary]
    if found > len(items):
        parts.append(html.H5(f"Ranked fixes: the top {len(items)} of {found} found", style={"margin": "4px 0"}))
        parts.append(
            html.Div(
                ["the full list: ", html.Code(result.get("command") or "designer fix")],
                id="fixes-more",
                style={"fontSize": "12px"},
            )
        )
    else:
        parts.append(html.H5(f"Ranked fixes: all {found} found, best first", style={"margin": "4px 0"}))
    parts.append(html.Ol(items, id="fixes", style={"maxHeight": "320px", "overflowY": "auto", "margin": "2px 0"}))
    return parts
