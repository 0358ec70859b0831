"""The studio's page layout: the controls, the chart and its panels, my caster, the card (static: no callbacks).

The ids given here are the ones the callbacks of :mod:`designer.studio.app` read and write.
"""

from __future__ import annotations

from dash import dcc, html

import designer.studio.state as state

MAX_CARD_BUTTONS = 6
"""Card buttons of the other casters (:func:`designer.studio.panels.alternative_buttons` fills them in)."""

CSS = {
    "page": {
        "fontFamily": "system-ui, sans-serif",
        "margin": "0 auto",
        "maxWidth": "1500px",
        "padding": "8px 12px",
        "boxSizing": "border-box",
    },
    "row": {"display": "flex", "flexWrap": "wrap", "gap": "16px", "alignItems": "flex-start"},
    "panel": {"border": "1px solid #ddd", "borderRadius": "6px", "padding": "8px 10px", "marginBottom": "8px"},
    "label": {"fontSize": "13px", "color": "#333", "display": "block", "marginTop": "4px"},
    "input": {"width": "160px", "fontSize": "14px", "boxSizing": "border-box"},
    "error": {"color": "#b00020", "fontSize": "13px", "whiteSpace": "normal", "overflowWrap": "anywhere"},
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
            className="slider-box",
            style={"width": "260px", "paddingTop": "46px"},
        )
    else:
        widget = dcc.Input(id=cid, value=value, type="text", debounce=True, style=CSS["input"])
    return html.Div(
        [
            html.Label(c.label, style=CSS["label"]),
            widget,
            html.Div(id={"type": "err", "key": c.key}, className="control-error overlay", style=CSS["error"]),
        ],
        className="control",
        style={"width": "270px", "maxWidth": "100%"} if c.kind == "slider" else None,
        **{"data-key": c.key},
    )


FIRST = ("load", "sill", "surface", "target", "alpha")
"""The controls a user changes first, on top of the page (the rest fold away under "More controls")."""


def _group(title: str, controls: list, values: dict, open_: bool = False):
    return html.Details(
        [html.Summary(title, style={"fontWeight": "600"}), *[_control(c, values[c.key]) for c in controls]],
        open=open_,
        style=CSS["panel"],
    )


def build_layout(name: str, defaults: dict, units: str = "in"):
    """The page: the first controls on top; the chart (the largest thing) with the recommendation and the card
    beside it; my caster, saving and the other controls (folded) below.  Columns wrap under each other on a
    narrow screen (a phone, 390 px wide) instead of scrolling sideways."""
    return html.Div(
        [
            dcc.Location(id="url", refresh=False),
            dcc.Store(id="problem-data"),
            dcc.Store(id="mine-store"),
            dcc.Store(id="front-shown"),  # what the chart shows: [part, digest] per trace (app._chart)
            # the card's limits, which come after the chart (app._limits_callback): the change whose card waits
            # for them, the same once the browser has painted the chart, and the server's answer
            dcc.Store(id="rec-pending"),
            dcc.Store(id="rec-go"),
            dcc.Store(id="rec-answer"),
            # the controls the answer shown is for
            dcc.Store(id="answered"),
            # the trade-off's messages, card-button labels and URL values, which the browser fans out (app._fan_out_callbacks)
            dcc.Store(id="messages"),
            dcc.Store(id="alt-labels"),
            dcc.Store(id="url-values"),
            html.H2(f"caster-designer studio: {name}", style={"margin": "4px 0", "fontSize": "1.3em"}),
            _first_controls(defaults),
            html.Div([_chart_column(), _card_column()], style=CSS["row"]),
            html.Div([_more_controls(defaults), _tools_column(units)], style=CSS["row"]),
        ],
        style=CSS["page"],
    )


def _first_controls(defaults: dict):
    """Load, sill, surface, target speed and α in one row (wrapping on a narrow screen)."""
    controls = {c.key: c for c in state.all_controls()}
    return html.Div(
        [_control(controls[k], defaults[k]) for k in FIRST],
        id="first-controls",
        style={**CSS["panel"], "display": "flex", "flexWrap": "wrap", "gap": "4px 18px", "alignItems": "flex-end"},
    )


def _more_controls(defaults: dict):
    """Every other control in folded groups (use, risk, bounds, stock), filled with ``defaults``."""
    controls = [c for c in state.all_controls() if c.key not in FIRST]
    groups = [
        ("Turning mode", "use"),
        ("Risk: the scatter σ", "risk"),
        ("Bounds and swept radius", "bounds"),
        ("Stock (buildable front)", "stock"),
    ]
    return html.Div(
        [
            html.H4("More controls", style={"margin": "2px 0 6px"}),
            *[
                _group(title, [c for c in controls if c.group == g], defaults)
                for title, g in groups
                if any(c.group == g for c in controls)
            ],
        ],
        id="more-controls",
        style={"flex": "1 1 300px", "minWidth": "0"},
    )


def _mine_inputs(units: str):
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
                ("trail", "trail", "25.4 mm" if units == "mm" else "1 in"),
                ("diameter", "diameter", "203.2 mm" if units == "mm" else "8 in"),
                ("groove", "groove", "0 mm" if units == "mm" else "0 in"),
                ("damping", "damping", "1.3 N*m/rad"),
            )
        ],
        style={"display": "flex", "gap": "8px", "flexWrap": "wrap"},
    )


def _chart_column():
    """Status and errors above the trade-off chart."""
    return html.Div(
        [
            html.Div(id="status", style={"fontSize": "12px", "color": "#555"}),
            # one line of fixed height: its message never moves what is below it
            html.Div(
                id="computing",
                className="computing",
                style={
                    "fontSize": "13px",
                    "color": "#8a5a00",
                    "height": "18px",
                    "overflow": "hidden",
                    "whiteSpace": "nowrap",
                    "textOverflow": "ellipsis",
                },
            ),
            html.Div(id="general-error", className="control-error", style=CSS["error"]),
            dcc.Graph(id="front", config={"displayModeBar": False, "responsive": True}),
        ],
        style={"flex": "3 1 560px", "minWidth": "0"},
    )


def _tools_column(units: str):
    """My caster (its numbers and fixes), save and report buttons."""
    return html.Div(
        [
            html.Div(
                [
                    html.H4("My caster", style={"margin": "2px 0"}),
                    _mine_inputs(units),
                    html.Div(
                        [
                            html.Button("Check my caster", id="mine-go", n_clicks=0, className="studio-button"),
                            html.Div(id="mine-error", className="control-error overlay", style=CSS["error"]),
                        ],
                        className="control",
                    ),
                    html.Div(id="mine-result"),
                ],
                style=CSS["panel"],
            ),
            html.Div(
                [
                    html.Button("Save problem", id="save", n_clicks=0, className="studio-button"),
                    html.Button("Write report", id="report", n_clicks=0, className="studio-button"),
                    dcc.Loading(html.Div(id="save-result", style={"fontSize": "13px", "marginTop": "4px"})),
                    dcc.Download(id="download"),
                ],
                style=CSS["panel"],
            ),
        ],
        style={"flex": "2 1 400px", "minWidth": "0"},
    )


def _card_column():
    """Beside the chart: the recommendation, then the card of the clicked point (or of the recommendation)."""
    return html.Div(
        [
            html.Div(
                [
                    html.Div(id="recommendation", style={"fontSize": "14px"}),
                    # the card buttons are the page's own (an answer fills in their labels): buttons drawn anew
                    # with each answer would each ask the server for a card
                    html.Div(
                        [
                            html.Button(
                                "Card of the caster to build", id="rec-card", n_clicks=0, className="studio-button"
                            ),
                            *[
                                html.Button(
                                    "",
                                    id={"type": "alt-card", "index": i},
                                    n_clicks=0,
                                    hidden=True,
                                    className="studio-button alt-card",
                                )
                                for i in range(MAX_CARD_BUTTONS)
                            ],
                        ],
                        id="card-buttons",
                    ),
                ],
                # greyed while its answer is not the one to the controls shown (app._request_callbacks): the
                # panel only, a small part of the page to restyle
                id="answer-box",
                className="waiting",
                style=CSS["panel"],
            ),
            dcc.Loading(
                html.Div(
                    id="card",
                    children=html.P(
                        "Click a point of the chart (or the button above) for its card.",
                        style={"color": "#666", "fontSize": "13px"},
                    ),
                )
            ),
        ],
        style={"flex": "1 1 340px", "minWidth": "0", "maxWidth": "100%", "overflowWrap": "anywhere"},
    )
