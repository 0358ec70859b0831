"""The studio's page layout: the controls, the chart and its panels, my caster, the card (static: no callbacks).

The ids given here are the ones the callbacks of :mod:`designer.studio.app` read and write.
"""

from __future__ import annotations

from dash import dcc, html

import designer.studio.state as state

CSS = {
    "page": {"fontFamily": "system-ui, sans-serif", "margin": "0 auto", "maxWidth": "1500px", "padding": "8px 16px"},
    "row": {"display": "flex", "gap": "16px", "alignItems": "flex-start"},
    "panel": {"border": "1px solid #ddd", "borderRadius": "6px", "padding": "8px 10px", "marginBottom": "8px"},
    "label": {"fontSize": "13px", "color": "#333", "display": "block", "marginTop": "4px"},
    "input": {"width": "150px", "fontSize": "13px"},
    "error": {"color": "#b00020", "fontSize": "12px", "whiteSpace": "normal"},
    "num": {"fontVariantNumeric": "tabular-nums"},
}


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
    left, middle, right = _controls_column(defaults), _middle_column(), _card_column()
    return html.Div(
        [
            dcc.Location(id="url", refresh=False),
            dcc.Store(id="problem-data"),
            dcc.Store(id="mine-store"),
            dcc.Store(id="front-shown"),  # what the chart shows: [part, digest] per trace (app._chart)
            html.H2(f"caster-designer studio: {name}", style={"margin": "4px 0"}),
            html.Div([left, middle, right], style=CSS["row"]),
        ],
        style=CSS["page"],
    )


def _controls_column(defaults: dict):
    """The problem's controls in folding groups (use, risk, bounds, stock), filled with ``defaults``."""
    controls = state.all_controls()
    groups = [
        ("Use: load, sill, surface, target", "use"),
        ("Risk: α and the scatter σ", "risk"),
        ("Bounds and swept radius", "bounds"),
        ("Stock (buildable front)", "stock"),
    ]
    return html.Div(
        [
            _group(title, [c for c in controls if c.group == g], defaults, g != "stock")
            for title, g in groups
            if any(c.group == g for c in controls)
        ],
        style={"width": "300px", "flex": "0 0 300px"},
    )


def _mine_inputs():
    """The four text boxes of "My caster" (trail, diameter, groove, damping) with their starting values."""
    return html.Div(
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


def _middle_column():
    """Status and errors, the trade-off chart, the recommendation, my caster, save and report buttons."""
    mine_inputs = _mine_inputs()
    return html.Div(
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


def _card_column():
    """The card of the clicked point (empty until a click)."""
    return html.Div(
        dcc.Loading(
            html.Div(
                id="card", children=html.P("Click a point of the chart to open its card.", style={"color": "#666"})
            )
        ),
        style={"flex": "0 0 440px", "width": "440px"},
    )
