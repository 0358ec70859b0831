"""The studio's Dash app: layout and callbacks, a thin view on :mod:`designer.studio.view`.

One callback owns the trade-off: it reads the controls (or, on load, the URL), validates them
with the problem loader (:func:`designer.studio.state.build_problem`), recomputes the fronts and
the recommendation, redraws, and writes the state back into the URL.  A bad value leaves the last
valid chart on the page and puts the loader's one-line message beside the control.

Dash and plotly are imported here: this module is loaded only by ``designer studio``.
"""

from __future__ import annotations

import base64
import json
import math
from pathlib import Path

import dash
from dash import ALL, Input, Output, State, ctx, dcc, html, no_update
from dash.exceptions import PreventUpdate

from designer.errors import DesignerError
from designer.model import Design
import designer.studio.figures as figures
import designer.studio.state as state
import designer.studio.view as view
from designer.problem import problem_from_dict
from designer.units import parse_quantity_text as quantity_option

INCH = 0.0254

CSS = {
    "page": {"fontFamily": "system-ui, sans-serif", "margin": "0 auto", "maxWidth": "1500px", "padding": "8px 16px"},
    "row": {"display": "flex", "gap": "16px", "alignItems": "flex-start"},
    "panel": {"border": "1px solid #ddd", "borderRadius": "6px", "padding": "8px 10px", "marginBottom": "8px"},
    "label": {"fontSize": "13px", "color": "#333", "display": "block", "marginTop": "4px"},
    "input": {"width": "150px", "fontSize": "13px"},
    "error": {"color": "#b00020", "fontSize": "12px", "whiteSpace": "normal"},
    "num": {"fontVariantNumeric": "tabular-nums"},
}


def _fmt(value, spec=".4g", unit=""):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    return f"{value:{spec}}{(' ' + unit) if unit else ''}"


def _design_text(d: dict) -> str:
    return (
        f"T {d['trail'] / INCH:.3f} in, d {d['diameter'] / INCH:.3f} in, B {d['groove'] / INCH:.3f} in, "
        f"c_f {d['damping']:.3f} N·m/rad"
    )


# --------------------------------------------------------------------------- layout


def _control(c: state.Control, value):
    cid = {"type": "ctl", "key": c.key}
    if c.kind == "choice":
        widget = dcc.Dropdown(
            id=cid, options=list(c.options), value=value, clearable=False, style={"width": "150px", "fontSize": "13px"}
        )
    elif c.kind == "slider":
        # the value's tooltip sits above the track, in room kept free under the label: below the track it
        # covered the tick labels
        widget = html.Div(
            dcc.Slider(
                id=cid,
                value=value,
                updatemode="mouseup",
                marks={v: f"{v:g}" for v in (1, 2, 3, 4, 5, 6)},
                tooltip={"placement": "top", "always_visible": True},
                **state.SLIDER,
            ),
            style={"width": "260px", "paddingTop": "46px"},
        )
    else:
        widget = dcc.Input(id=cid, value=value, type="text", debounce=True, style=CSS["input"])
    return html.Div(
        [
            html.Label(c.label, style=CSS["label"]),
            widget,
            html.Div(id={"type": "err", "key": c.key}, className="control-error", style=CSS["error"]),
        ],
        className="control",
        **{"data-key": c.key},
    )


def _group(title: str, controls: list, values: dict, open_: bool = True):
    return html.Details(
        [html.Summary(title, style={"fontWeight": "600"}), *[_control(c, values[c.key]) for c in controls]],
        open=open_,
        style=CSS["panel"],
    )


def build_layout(name: str, defaults: dict):
    """The page: controls on the left, chart + recommendation in the middle, my caster and the card below."""
    controls = state.all_controls()
    groups = [
        ("Use: load, sill, surface, target", "use"),
        ("Risk: α and the scatter σ", "risk"),
        ("Bounds and swept radius", "bounds"),
        ("Stock (buildable front)", "stock"),
    ]
    left = html.Div(
        [
            _group(title, [c for c in controls if c.group == g], defaults, g != "stock")
            for title, g in groups
            if any(c.group == g for c in controls)
        ],
        style={"width": "300px", "flex": "0 0 300px"},
    )
    mine_inputs = html.Div(
        [
            html.Div(
                [
                    html.Label(label, style=CSS["label"]),
                    dcc.Input(id=f"mine-{key}", value=value, type="text", debounce=True, style=CSS["input"]),
                ]
            )
            for key, label, value in (
                ("trail", "trail", "1 in"),
                ("diameter", "diameter", "8 in"),
                ("groove", "groove", "0 in"),
                ("damping", "damping", "1.3 N*m/rad"),
            )
        ],
        style={"display": "flex", "gap": "8px", "flexWrap": "wrap"},
    )
    middle = html.Div(
        [
            html.Div(id="status", style={"fontSize": "12px", "color": "#555"}),
            html.Div(id="general-error", className="control-error", style=CSS["error"]),
            dcc.Graph(id="front", config={"displaylogo": False, "responsive": True}),
            html.Div(
                [
                    html.Div(id="recommendation"),
                    html.Button(
                        "Recommendation's card (with its knock-safe speed)",
                        id="rec-card",
                        n_clicks=0,
                        style={"marginTop": "6px", "fontSize": "12px"},
                    ),
                ],
                style=CSS["panel"],
            ),
            html.Div(
                [
                    html.H4("My caster", style={"margin": "2px 0"}),
                    mine_inputs,
                    html.Button("Check my caster", id="mine-go", n_clicks=0, style={"marginTop": "6px"}),
                    html.Div(id="mine-error", className="control-error", style=CSS["error"]),
                    html.Div(id="mine-result"),
                ],
                style=CSS["panel"],
            ),
            html.Div(
                [
                    html.Button("Save problem", id="save", n_clicks=0),
                    html.Button("Write report", id="report", n_clicks=0, style={"marginLeft": "8px"}),
                    dcc.Loading(html.Div(id="save-result", style={"fontSize": "13px", "marginTop": "4px"})),
                    dcc.Download(id="download"),
                ],
                style=CSS["panel"],
            ),
        ],
        style={"flex": "1 1 600px", "minWidth": "500px"},
    )
    right = html.Div(
        dcc.Loading(
            html.Div(
                id="card", children=html.P("Click a point of the chart to open its card.", style={"color": "#666"})
            )
        ),
        style={"flex": "0 0 440px", "width": "440px"},
    )
    return html.Div(
        [
            dcc.Location(id="url", refresh=False),
            dcc.Store(id="problem-data"),
            dcc.Store(id="mine-store"),
            html.H2(f"caster-designer studio: {name}", style={"margin": "4px 0"}),
            html.Div([left, middle, right], style=CSS["row"]),
        ],
        style=CSS["page"],
    )


# --------------------------------------------------------------------------- panels


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
            html.Div(_design_text(knee.design.as_dict()), id="rec-design"),
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
    alpha = view.risk_of(fronts.problem)
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
    risk = view.risk_of(problem)
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


# --------------------------------------------------------------------------- the app


def create_app(data: dict, name: str, out_dir: Path):  # noqa: C901 - the app's callbacks are closures over its state, defined here together
    """The Dash app for problem-file ``data`` (dict) named ``name``; saves and reports go to ``out_dir``."""
    defaults = state.control_values(data)
    app = dash.Dash(__name__, title=f"studio · {name}", update_title=None, serve_locally=True, assets_ignore=".*")
    app.layout = build_layout(name, defaults)
    keys = [c.key for c in state.all_controls()]
    latest = {"n": 0}  # the newest change wins: changes that queued behind a computation are skipped

    @app.callback(
        Output({"type": "ctl", "key": ALL}, "value"),
        Output({"type": "err", "key": ALL}, "children"),
        Output("general-error", "children"),
        Output("front", "figure"),
        Output("recommendation", "children"),
        Output("status", "children"),
        Output("url", "search"),
        Output("problem-data", "data"),
        Input("url", "search"),
        Input({"type": "ctl", "key": ALL}, "value"),
        Input("mine-store", "data"),
        State("problem-data", "data"),
    )
    def update(search, values, mine, last):
        latest["n"] += 1
        generation = latest["n"]
        from_url = ctx.triggered_id in (None, "url")
        if from_url:
            current = state.from_query(search, defaults)
            values_out = [current[k] for k in keys]
        else:
            current = dict(zip(keys, values))
            values_out = [no_update] * len(keys)
        errors = [""] * len(keys)
        try:
            problem, merged = state.build_problem(data, current)
            canonical = json.dumps(merged, sort_keys=True)
            with view.LOCK:
                if generation != latest["n"] and view.cached(canonical) is None:
                    raise PreventUpdate  # a newer change is waiting: compute that one instead
                fronts = view.compute_fronts(problem, key=canonical)
        except DesignerError as exc:
            key = getattr(exc, "key", None)
            if key is None:  # the problem is valid but out of reach: say it beside the control just moved
                moved = ctx.triggered_id.get("key") if isinstance(ctx.triggered_id, dict) else None
                key = moved or state.blame(str(exc))
            messages = state.control_errors(data, current, defaults)
            if not messages:  # only the combination is wrong (e.g. a target out of reach)
                messages = {key: str(exc)}
            general = ""
            for k, message in messages.items():
                if k in keys:
                    errors[keys.index(k)] = message
                else:
                    general = message
            # the last valid chart stays; only the messages change
            return (
                values_out,
                errors,
                general,
                no_update,
                no_update,
                no_update,
                no_update if from_url else state.to_query(current, defaults),
                no_update,
            )
        rec = view.recommendation_record(fronts.recommendation)
        fig = figures.front_figure(
            view.front_points(fronts.continuous),
            view.front_points(fronts.risk),
            view.front_points(fronts.buildable),
            rec,
            mine,
        )
        status = (
            f"{problem.name}: {len(fronts.continuous)} continuous, "
            f"{0 if fronts.risk is None else len(fronts.risk)} risk-bounded, "
            f"{0 if fronts.buildable is None else len(fronts.buildable)} buildable points; "
            f"computed in {1000 * fronts.seconds:.0f} ms ({1000 * fronts.cpu_seconds:.0f} ms CPU)"
        )
        query = state.to_query(current, defaults)
        return (
            values_out,
            errors,
            "",
            fig,
            recommendation_panel(fronts),
            status,
            no_update if from_url and query == (search or "") else query,
            merged,
        )

    @app.callback(
        Output("card", "children"),
        Input("front", "clickData"),
        Input("rec-card", "n_clicks"),
        State("problem-data", "data"),
        prevent_initial_call=True,
    )
    def open_card(click, _n, merged):
        if not merged:
            return no_update
        try:
            problem = problem_from_dict(merged)
            if ctx.triggered_id == "rec-card":  # the fronts of this state are cached: only the card is computed
                rec = view.compute_fronts(problem, key=json.dumps(merged, sort_keys=True)).recommendation
                if rec is None:
                    return html.Div("no recommendation for this problem", style=CSS["error"])
                return card_panel(problem, rec.design, "recommendation", getattr(rec, "inertia", None))
            if not click:
                return no_update
            custom = click["points"][0].get("customdata")
            if not custom:
                return no_update
            return card_panel(problem, Design(*custom[:4]), custom[4], custom[9] if len(custom) > 9 else None)
        except DesignerError as exc:
            return html.Div(str(exc), style=CSS["error"])

    @app.callback(
        Output("mine-store", "data"),
        Output("mine-result", "children"),
        Output("mine-error", "children"),
        Input("mine-go", "n_clicks"),
        Input("mine-trail", "n_submit"),
        Input("mine-diameter", "n_submit"),
        Input("mine-groove", "n_submit"),
        Input("mine-damping", "n_submit"),
        State("mine-trail", "value"),
        State("mine-diameter", "value"),
        State("mine-groove", "value"),
        State("mine-damping", "value"),
        State("problem-data", "data"),
        prevent_initial_call=True,
    )
    def check_mine(_n, _a, _b, _c, _d, trail, diameter, groove, damping, merged):

        try:
            design = Design(
                quantity_option(str(trail), "length", "--trail"),
                quantity_option(str(diameter), "length", "--diameter"),
                quantity_option(str(groove), "length", "--groove"),
                quantity_option(str(damping), "damping", "--damping"),
            )
            problem = problem_from_dict(merged)
            result = view.my_caster(problem, design)
            result["command"] = "Save problem, then " + view.fix_command(out_dir / f"{problem.name}.toml", design)
        except DesignerError as exc:
            return no_update, no_update, str(exc)
        store = {"numbers": {k: v for k, v in result["numbers"].items()}, "fixes": result["fixes"]}
        return json.loads(json.dumps(store, default=float)), fixes_panel(result), ""

    @app.callback(
        Output("save-result", "children"),
        Output("download", "data"),
        Input("save", "n_clicks"),
        Input("report", "n_clicks"),
        State("problem-data", "data"),
        prevent_initial_call=True,
    )
    def save(_s, _r, merged):
        if not merged:
            return "nothing valid to save yet", no_update

        out_dir.mkdir(parents=True, exist_ok=True)
        problem = problem_from_dict(merged)
        if ctx.triggered_id == "save":
            path = out_dir / f"{problem.name}.toml"
            text = state.to_toml(merged)
            path.write_text(text, encoding="utf-8")
            return html.Span([f"saved {path.resolve()} (run it: designer run {path})"], id="saved-path"), {
                "content": text,
                "filename": path.name,
            }
        from designer.report.build import compute_and_write  # the same report as `designer pareto`; loads matplotlib

        try:
            summary = view._quiet(compute_and_write, problem, out=out_dir / problem.name)
        except DesignerError as exc:
            return html.Span(str(exc), style=CSS["error"]), no_update
        return html.Span(f"report written: {Path(summary['index_html']).resolve()}", id="report-path"), no_update

    return app
