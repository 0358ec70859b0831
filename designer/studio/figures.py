"""Plotly figures of the studio: records in (from :mod:`designer.studio.view`), figures out.

Plotly is imported by the functions (the studio's dependency, not the package's).
"""

from __future__ import annotations

import functools
import math

from designer import display


FONT = 13
"""Font size of the charts' text [px]: read on a phone's 390 px screen (at least 11 px)."""

COLOURS = {
    "continuous": "#9aa0a6",
    "risk": "#1f6fb2",
    "buildable": "#e07b00",
    "recommendation": "#1a9641",
    "mine": "#d7191c",
    "fix": "#7b3294",
}


def _template(name: str, value: str, units: str) -> str:
    """A plotly format of quantity ``name`` (``value``: "x", "customdata[3]") with the precision and the unit
    :mod:`designer.display` gives it in ``units`` ("%{x:.2f} N", "%{customdata[4]:.2f} mm")."""
    entry = display.quantity(name)
    unit = display.unit(entry.dimension, units)
    digits = entry.digits if entry.digits is not None and entry.dimension != "length" else unit.digits
    return f"%{{{value}:.{digits}f}} {unit.text}"


@functools.lru_cache(maxsize=4)
def hover(units: str) -> str:
    """Each point's hover box in ``units``: its name, P, F_turn, V_c and the design (customdata [2] to [7],
    lengths already in ``units``, :func:`_custom`); numbers formatted by plotly to :mod:`designer.display`'s
    precision, so the page carries numbers, not one text per point."""
    return (
        f"<b>%{{customdata[2]}}</b><br>P {_template('threshold_force', 'x', units)}<br>"
        f"F_turn {_template('turning_effort', 'y', units)}<br>"
        f"V_c {_template('critical_speed', 'customdata[3]', units)}<br>"
        f"T {_template('trail', 'customdata[4]', units)}, d {_template('diameter', 'customdata[5]', units)}<br>"
        f"B {_template('groove', 'customdata[6]', units)}, c_f {_template('damping', 'customdata[7]', units)}"
        "<extra></extra>"
    )


def _custom(p: dict, part: str, index: int, name: str, units: str) -> list:
    """A point's ``customdata``: [part, index, name, V_c, T, d, B (in ``units``), c_f]; a click opens the card of
    record ``index`` of ``part`` (:func:`designer.studio.view.card_record`), a hover shows :func:`hover`."""
    d = p["design"]
    factor = display.unit("length", units).factor
    vc = p.get("critical_speed")
    lengths = [d[key] * factor for key in ("trail", "diameter", "groove")]
    return [part, index, name, vc if vc is not None and math.isfinite(vc) else None, *lengths, d["damping"]]


def front_figure(
    continuous: list,
    risk: list,
    buildable: list,
    recommendation: dict | None,
    mine: dict | None = None,
    title: str = "",
    units: str = "in",
) -> dict:
    """The trade-off chart as a plotly figure dict: every front with the threshold force P across and the turning
    effort F_turn up (as the report and ``Front.plot()`` draw it), the recommendation, my caster
    (:func:`front_traces` and :func:`front_layout`).

    Each point carries in ``customdata`` the record it shows (its part and index), which the card callback reads
    on a click, and its hover text in ``units``.
    """
    traces = front_traces(continuous, risk, buildable, recommendation, mine, units)
    return {"data": traces, "layout": with_ranges(front_layout(title), axis_ranges(traces))}


def front_traces(
    continuous: list, risk: list, buildable: list, recommendation: dict | None, mine: dict | None, units: str = "in"
) -> list:
    """The chart's traces as plain plotly dicts, in drawing order: the non-empty fronts (continuous, risk-bounded,
    buildable), the recommendation, my caster; each names its part in ``meta``.

    Plain dicts, not ``plotly.graph_objects``: validating them costs about 20 ms of CPU per redraw, and they are
    the dicts ``go.Scatter(...).to_plotly_json()`` gives (tests/studio/test_studio_app.py checks that).
    """
    traces = _front_traces(continuous, risk, buildable, units)
    if recommendation is not None:
        traces.append(_recommendation_trace(recommendation, units))
    if mine is not None:
        traces.append(_mine_trace(mine, units))
    return traces


PAD = 0.06
"""Room around the points on each axis, as a fraction of their span (the markers are not cut at the edge)."""


def with_ranges(layout: dict, ranges: dict) -> dict:
    """A copy of ``layout`` with the axes' ``ranges`` (:func:`axis_ranges`) merged into its axes."""
    return {**layout, **{axis: {**layout.get(axis, {}), **value} for axis, value in ranges.items()}}


def axis_ranges(traces: list) -> dict:
    """The chart's axes fitted to ``traces``' points: ``{"xaxis": {"range": [lo, hi], ...}, "yaxis": ...}``, each
    range holding every finite point with :data:`PAD` of room, so a change of the fronts moves the axes with
    them (an axis left as it was shows an empty chart when the fronts move off it)."""
    out = {}
    for axis, key in (("xaxis", "x"), ("yaxis", "y")):
        values = [float(v) for t in traces for v in t.get(key, ()) if v is not None and math.isfinite(float(v))]
        if not values:
            continue
        lo, hi = min(values), max(values)
        pad = PAD * (hi - lo) if hi > lo else 0.05 * abs(hi) + 1.0
        out[axis] = {"range": [lo - pad, hi + pad], "autorange": False}
    return out


@functools.lru_cache(maxsize=8)
def front_layout(title: str = "") -> dict:
    """The chart's layout (axes, the plotly_white template, legend, click and hover modes) as a plotly dict;
    the same for every state of the studio (built once: the template alone is about 7 kB).  Read-only."""
    import plotly.graph_objects as go  # the studio's dependency

    return go.Layout(
        title=title,
        xaxis_title=display.axis("threshold_force"),  # P across, F_turn up: the report's and front.plot()'s
        yaxis_title=display.axis("turning_effort"),
        template="plotly_white",
        font={"size": FONT},
        height=520,
        margin={"l": 60, "r": 20, "t": 40, "b": 50},
        # its top edge well under the x-axis title (anchored by its middle, a legend wrapped to two rows
        # covered the title); the bottom margin grows to hold it
        legend={"orientation": "h", "x": 0, "xanchor": "left", "y": -0.17, "yanchor": "top"},
        hovermode="closest",
        clickmode="event",
        uirevision="front",  # no layout.transition: with one, plotly.js redraws through an animation frame and
    ).to_plotly_json()  # a second full redraw (about 40 % of the browser's work per answer)


FRONT_NAMES = {
    "continuous": "best possible (no scatter)",
    "risk": "best within the shimmy risk",
    "buildable": "buildable from stock",
}
"""Each front's name in the legend, in plain words: the continuous front of the nominal model (Eq. 7 without
scatter), the continuous front whose casters keep P(shimmy) within α, and the stock's front."""


def _trace(part: str, name: str, mode: str, points: list, customdata: list, units: str, **style) -> dict:
    """A scatter trace of ``points`` (P across, F_turn up) as a plain plotly dict, naming its ``part`` in ``meta``
    and each point's record in ``customdata`` (:func:`_custom`); ``style``: its marker, line and text."""
    return {
        "customdata": customdata,
        "hovertemplate": hover(units),
        **style,
        "meta": part,
        "mode": mode,
        "name": name,
        "x": [p["threshold_force"] for p in points],
        "y": [p["turning_effort"] for p in points],
        "type": "scatter",
    }


def _front_traces(continuous: list, risk: list, buildable: list, units: str) -> list:
    """One line (or markers) per non-empty front: continuous, risk-bounded, buildable; each point names its record."""
    traces = []
    for key, points, mode, symbol, size in (
        ("continuous", continuous, "lines+markers", "circle", 6),
        ("risk", risk, "lines+markers", "circle", 8),
        ("buildable", buildable, "markers", "square", 10),
    ):
        if not points:
            continue
        name = FRONT_NAMES[key]
        custom = [
            _custom(p, key, i, f"{name} #{i + 1}" + (f" {p['label']}" if p.get("label") else ""), units)
            for i, p in enumerate(points)
        ]
        line = {"color": COLOURS[key], "width": 1.5}
        marker = {"color": COLOURS[key], "size": size, "symbol": symbol}
        traces.append(_trace(key, name, mode, points, custom, units, line=line, marker=marker))
    return traces


def _recommendation_trace(recommendation: dict, units: str) -> dict:
    """The caster to build: a green star; a click opens its card (the recommendation's own record)."""
    name = "the caster to build"
    marker = {"color": COLOURS["recommendation"], "line": {"color": "white", "width": 1}, "size": 18, "symbol": "star"}
    custom = [_custom(recommendation, "recommendation", 0, name, units)]
    return _trace("recommendation", name, "markers", [recommendation], custom, units, marker=marker)


def _mine_trace(mine: dict, units: str) -> dict:
    """My caster: a red cross labelled with its chance of shimmy."""
    n = mine["numbers"]
    risk_text = f"{display.shown(n.get('shimmy_probability'), 'shimmy_probability', units)} shimmy"
    custom = [_custom(n, "mine", 0, "my caster", units)]
    marker = {"color": COLOURS["mine"], "size": 14, "symbol": "x"}
    text = {"text": [f"my caster {risk_text}"], "textposition": "top left", "textfont": {"size": 13}}
    return _trace("mine", "my caster", "markers+text", [n], custom, units, marker=marker, **text)


def sweeps_figure(sweeps: dict, target: float, alpha: float | None, units: str = "in"):
    """V_c against trail and against diameter around a design (two panels, lengths in ``units``)."""
    import plotly.graph_objects as go  # the studio's dependency
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=1, cols=2, subplot_titles=("V_c vs trail", "V_c vs diameter"))
    for col, name in ((1, "trail"), (2, "diameter")):
        s = sweeps[name]
        factor = display.unit("length", units).factor
        x = [v * factor for v in s["x"]]
        curves = [("critical_speed", "V_c (Eq. 7)", "continuous")]
        if alpha is not None:
            curves.append(("confident_speed", f"speed reached ({display.percent(1 - alpha)} sure)", "risk"))
        for key, label, colour in curves:
            line = {"color": COLOURS[colour]}
            fig.add_trace(go.Scatter(x=x, y=list(s[key]), name=label, showlegend=col == 1, line=line), row=1, col=col)
        fig.add_vline(x=s["value"] * factor, line={"dash": "dot", "color": "black"}, row=1, col=col)
        fig.add_hline(y=target, line={"dash": "dash", "color": COLOURS["mine"]}, row=1, col=col)
        fig.update_xaxes(title_text=f"{name} {display.header(name, units)}", row=1, col=col)
    fig.update_yaxes(title_text="speed [m/s]", row=1, col=1)
    fig.update_annotations(font_size=FONT + 1)  # the subplot titles
    fig.update_layout(
        template="plotly_white",
        font={"size": FONT},
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
        font={"size": FONT},
        xaxis_title="t [s]",
        yaxis_title="θ [deg]",
        height=280,
        margin={"l": 50, "r": 10, "t": 40, "b": 40},
    )
    return fig
