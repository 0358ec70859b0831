"""Plotly figures of the studio: records in (from :mod:`designer.studio.view`), figures out.

Plotly is imported by the functions (the studio's dependency, not the package's).
"""

from __future__ import annotations

import functools
import math
from designer.display import axis
from designer.units import INCH


COLOURS = {
    "continuous": "#9aa0a6",
    "risk": "#1f6fb2",
    "buildable": "#e07b00",
    "recommendation": "#1a9641",
    "mine": "#d7191c",
    "fix": "#7b3294",
}

HOVER = (
    "<b>%{customdata[4]}</b><br>P %{x:.2f} N<br>F_turn %{y:.3f} N<br>V_c %{customdata[5]:.3f} m/s<br>"
    "T %{customdata[6]:.3f} in, d %{customdata[7]:.3f} in<br>B %{customdata[8]:.3f} in, "
    "c_f %{customdata[3]:.3f} N·m/rad<extra></extra>"
)


def _custom(p: dict, name: str) -> list:
    d = p["design"]
    return [
        d["trail"],
        d["diameter"],
        d["groove"],
        d["damping"],
        name,
        p.get("critical_speed", math.nan),
        d["trail"] / INCH,
        d["diameter"] / INCH,
        d["groove"] / INCH,
        p.get("inertia"),
    ]


def front_figure(
    continuous: list,
    risk: list,
    buildable: list,
    recommendation: dict | None,
    mine: dict | None = None,
    title: str = "",
) -> dict:
    """The trade-off chart as a plotly figure dict: every front with the threshold force P across and the turning
    effort F_turn up (as the report and ``Front.plot()`` draw it), the recommendation, my caster
    (:func:`front_traces` and :func:`front_layout`).

    Each point carries its design in ``customdata`` (T, d, B, c_f [SI], name, V_c, T, d, B [in], the wheel's
    own I_w [kg·m²] or None), which the card callback reads on a click.
    """
    return {"data": front_traces(continuous, risk, buildable, recommendation, mine), "layout": front_layout(title)}


def front_traces(continuous: list, risk: list, buildable: list, recommendation: dict | None, mine: dict | None) -> list:
    """The chart's traces as plain plotly dicts, in drawing order: the non-empty fronts (continuous, risk-bounded,
    buildable), the recommendation, my caster; each names its part in ``meta``.

    Plain dicts, not ``plotly.graph_objects``: validating them costs about 20 ms of CPU per redraw, and they are
    the dicts ``go.Scatter(...).to_plotly_json()`` gives (tests/studio/test_studio_app.py checks that).
    """
    traces = _front_traces(continuous, risk, buildable)
    if recommendation is not None:
        traces.append(_recommendation_trace(recommendation))
    if mine is not None:
        traces.append(_mine_trace(mine))
    return traces


@functools.lru_cache(maxsize=8)
def front_layout(title: str = "") -> dict:
    """The chart's layout (axes, the plotly_white template, legend, click and hover modes) as a plotly dict;
    the same for every state of the studio (built once: the template alone is about 7 kB).  Read-only."""
    import plotly.graph_objects as go  # the studio's dependency

    return go.Layout(
        title=title,
        xaxis_title=axis("threshold_force"),  # P across, F_turn up: the report's and front.plot()'s (the table's)
        yaxis_title=axis("turning_effort"),
        template="plotly_white",
        height=520,
        margin={"l": 60, "r": 20, "t": 40, "b": 50},
        # its top edge well under the x-axis title (anchored by its middle, a legend wrapped to two rows
        # covered the title); the bottom margin grows to hold it
        legend={"orientation": "h", "x": 0, "xanchor": "left", "y": -0.17, "yanchor": "top"},
        hovermode="closest",
        clickmode="event",
        uirevision="front",
        transition={"duration": 0},
    ).to_plotly_json()


def _front_traces(continuous: list, risk: list, buildable: list) -> list:
    """One line (or markers) per non-empty front: continuous, risk-bounded, buildable; each point names its design."""
    traces = []
    for key, points, name, mode, symbol, size in (
        ("continuous", continuous, "continuous front (nominal V_c)", "lines+markers", "circle", 6),
        ("risk", risk, "risk-bounded front (P(shimmy) ≤ α)", "lines+markers", "circle", 8),
        ("buildable", buildable, "buildable front (stock)", "markers", "square", 10),
    ):
        if not points:
            continue
        traces.append(
            {
                "customdata": [
                    _custom(p, f"{name.split(' (')[0]} #{i + 1}" + (f" {p['label']}" if p.get("label") else ""))
                    for i, p in enumerate(points)
                ],
                "hovertemplate": HOVER,
                "line": {"color": COLOURS[key], "width": 1.5},
                "marker": {"color": COLOURS[key], "size": size, "symbol": symbol},
                "meta": key,
                "mode": mode,
                "name": name,
                "x": [p["threshold_force"] for p in points],
                "y": [p["turning_effort"] for p in points],
                "type": "scatter",
            }
        )
    return traces


def _recommendation_trace(recommendation: dict) -> dict:
    """The recommendation: a green star carrying its design (and its wheel's I_w) for the card."""
    rec = {
        "design": recommendation["design"],
        "turning_effort": recommendation["turning_effort"],
        "threshold_force": recommendation["threshold_force"],
        "critical_speed": recommendation.get("critical_speed") or math.nan,
        "inertia": recommendation.get("inertia"),
    }
    return {
        "customdata": [_custom(rec, "recommendation")],
        "hovertemplate": HOVER,
        "marker": {
            "color": COLOURS["recommendation"],
            "line": {"color": "white", "width": 1},
            "size": 18,
            "symbol": "star",
        },
        "meta": "recommendation",
        "mode": "markers",
        "name": "recommendation",
        "x": [rec["threshold_force"]],
        "y": [rec["turning_effort"]],
        "type": "scatter",
    }


def _mine_trace(mine: dict) -> dict:
    """My caster: a red cross labelled with its P(shimmy) when known."""
    n = mine["numbers"]
    risk_text = "" if n.get("shimmy_probability") is None else f"P(shimmy) {100 * n['shimmy_probability']:.1f} %"
    p = {
        "design": n["design"],
        "turning_effort": n["turning_effort"],
        "threshold_force": n["threshold_force"],
        "critical_speed": n["critical_speed"],
    }
    return {
        "customdata": [_custom(p, "my caster")],
        "hovertemplate": HOVER,
        "marker": {"color": COLOURS["mine"], "size": 14, "symbol": "x"},
        "meta": "mine",
        "mode": "markers+text",
        "name": "my caster",
        "text": [f"my caster {risk_text}"],
        "textposition": "top left",
        "x": [p["threshold_force"]],
        "y": [p["turning_effort"]],
        "type": "scatter",
    }


def sweeps_figure(sweeps: dict, target: float, alpha: float | None):
    """V_c against trail and against diameter around a design (two panels, lengths in inches)."""
    import plotly.graph_objects as go  # the studio's dependency
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=1, cols=2, subplot_titles=("V_c vs trail", "V_c vs diameter"))
    for col, name in ((1, "trail"), (2, "diameter")):
        s = sweeps[name]
        x = [v / INCH for v in s["x"]]
        fig.add_trace(
            go.Scatter(
                x=x,
                y=list(s["critical_speed"]),
                name="V_c (Eq. 7)",
                showlegend=col == 1,
                line={"color": COLOURS["continuous"]},
            ),
            row=1,
            col=col,
        )
        if alpha is not None:
            fig.add_trace(
                go.Scatter(
                    x=x,
                    y=list(s["confident_speed"]),
                    name=f"speed reached w.p. {1 - alpha:.0%}",
                    showlegend=col == 1,
                    line={"color": COLOURS["risk"]},
                ),
                row=1,
                col=col,
            )
        fig.add_vline(x=s["value"] / INCH, line={"dash": "dot", "color": "black"}, row=1, col=col)
        fig.add_hline(y=target, line={"dash": "dash", "color": COLOURS["mine"]}, row=1, col=col)
        fig.update_xaxes(title_text=f"{name} [in]", row=1, col=col)
    fig.update_yaxes(title_text="speed [m/s]", row=1, col=1)
    fig.update_layout(
        template="plotly_white",
        height=300,
        margin={"l": 50, "r": 10, "t": 30, "b": 40},
        legend={"orientation": "h", "y": -0.3},
    )
    return fig


def knock_figure(knock: dict, target: float):
    """θ(t) [deg] after the 20° knock at the target speed."""
    import plotly.graph_objects as go  # the studio's dependency

    fig = go.Figure(
        go.Scatter(
            x=list(knock["t"]),
            y=[math.degrees(v) for v in knock["theta"]],
            mode="lines",
            line={"color": COLOURS["mine"] if knock["grows"] else COLOURS["recommendation"]},
        )
    )
    verdict = "grows: shimmy" if knock["grows"] else "decays"
    fig.update_layout(
        title=f"θ(t) after a 20° knock at {target:.3g} m/s ({verdict})",
        template="plotly_white",
        xaxis_title="t [s]",
        yaxis_title="θ [deg]",
        height=280,
        margin={"l": 50, "r": 10, "t": 40, "b": 40},
    )
    return fig
