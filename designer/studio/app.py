"""The studio's Dash app: its callbacks, a thin view on :mod:`designer.studio.view`.

The page is built by :mod:`designer.studio.layout`, the panels the callbacks return by
:mod:`designer.studio.panels` (both re-exported here).

One callback owns the trade-off: it reads the controls (or, on load, the URL), validates them
with the problem loader (:func:`designer.studio.state.build_problem`), recomputes the fronts and
the recommendation, redraws, and writes the state back into the URL.  A bad value leaves the last
valid chart on the page and puts the loader's one-line message beside the control.  The recommended
caster's acceptance limits (about a third of the computation) are left out of it: a second callback,
chained to the first, computes them and fills them into the card a moment after the chart.

Dash and plotly are imported here (and by layout and panels): these modules are loaded only by ``designer studio``.
"""

from __future__ import annotations

import hashlib
import logging
import json
from collections import OrderedDict
from pathlib import Path

import dash
import flask
from dash import ALL, Input, Output, Patch, State, ctx, html, no_update
from dash.exceptions import PreventUpdate

from designer.errors import DesignerError
from designer.model import Design
from designer.output import signed, signed_kind, write_file
import designer.studio.figures as figures
import designer.studio.state as state
import designer.studio.view as view
from designer.problem import problem_from_dict
from designer.studio.layout import CSS, build_layout
from designer.studio.panels import (
    LIMITS_FAILED,
    alternative_buttons,
    card_panel,
    fixes_panel,
    limits_text,
    numbers_table,
    recommendation_panel,
    role_name,
)
from designer.units import parse_quantity_text as quantity_option

__all__ = [
    "build_layout",
    "card_panel",
    "create_app",
    "fixes_panel",
    "limits_text",
    "numbers_table",
    "recommendation_panel",
]


# --------------------------------------------------------------------------- the app


SAVE_WRITER = "designer studio"
"""The first line of a problem file "Save problem" writes names this writer (:func:`designer.output.signed`)."""

SAVED_PROBLEM = signed_kind(SAVE_WRITER, "a problem file saved by designer studio")
"""What "Save problem" may replace: a problem file it saved, unchanged since (never one the user wrote)."""


STYLE = """
.waiting { opacity: 0.45; }
#answer-box { will-change: opacity; }
.studio-button { min-height: 44px; min-width: 44px; font-size: 15px; margin: 4px 4px 0 0; padding: 4px 12px; }
summary { min-height: 44px; box-sizing: border-box; padding: 12px 0; cursor: pointer; }
.control { position: relative; width: 170px; }
.control-error.overlay { position: absolute; top: 100%; left: 0; width: 100%; z-index: 10; background: #fff;
  box-shadow: 0 1px 4px rgba(0, 0, 0, 0.3); padding: 2px 4px; box-sizing: border-box; }
.control-error:empty { display: none; }
@media (min-width: 601px) {
  details .control-error.overlay { top: 0; left: 100%; margin-left: 8px; width: 260px; }
}
@media (max-width: 600px) {
  input[type=text] { min-height: 44px; font-size: 16px; }
  .dash-dropdown { min-height: 44px; }
  .dash-slider-thumb { width: 44px; height: 44px; border: 10px solid transparent; background-clip: padding-box;
    box-shadow: none; box-sizing: border-box; }
  .slider-box { padding-top: 58px !important; }
}
"""
"""The page's own style sheet: the answer greyed while it is not the answer to the controls shown (on a layer of its
own: toggling its opacity then redraws nothing else, a sixth of the browser's CPU a change); buttons and folded
sections a finger can hit (44 px; on a phone the text boxes, menus and the slider's handle too: a 24 px disc in a
transparent 44 px ring); a control's message shown over the page below it (beside it in the folded groups of a
wide page, where the controls stand in one column), so it never moves another control."""

NATIVE = "[parseInt, parseFloat, ...['trim', 'trimStart', 'trimEnd', 'trimLeft', 'trimRight'].map(k => ''[k])]"
"""The browser's own functions that Dash's Babel polyfill (core-js 2) replaces, taking them for broken (a whitespace
rule of ES5): the page puts them back after Dash's scripts, since plotly.js's colour parsing calls parseInt and
trim for every point it styles (about a tenth of the browser's work per answer, through the polyfill's)."""

INDEX = (
    "<!DOCTYPE html><html><head>{%metas%}<title>{%title%}</title>{%favicon%}{%css%}"
    f"<style>{STYLE}</style></head><body>{{%app_entry%}}<footer>{{%config%}}<script>window.studioNative = {NATIVE};"
    "</script>{%scripts%}<script>(n => { window.parseInt = Number.parseInt = n[0]; window.parseFloat = "
    "Number.parseFloat = n[1]; ['trim', 'trimStart', 'trimEnd', 'trimLeft', 'trimRight'].forEach((k, i) => "
    "{ String.prototype[k] = n[i + 2]; }); })(window.studioNative);</script>{%renderer%}</footer></body></html>"
)
"""Dash's page with :data:`STYLE` in its head and the :data:`NATIVE` functions put back after its scripts."""


RENDERER = (
    "var renderer = new DashRenderer({request_pre: p => { p.studio = [window.studioPage ||= Math.random() + '',"
    " window.studioSeq = (window.studioSeq || 0) + 1]; }});"
)
"""Dash's renderer, which numbers each request of the page as it sends it (``studio``: [the page, the number]):
the order the server must answer in, whatever order the requests arrive in."""


def _sequence() -> tuple[str, int]:
    """(page, number) of the callback request being answered (:data:`RENDERER`); ("", 0) for one without them."""
    tag = (flask.request.get_json(silent=True) or {}).get("studio")
    ok = isinstance(tag, list) and len(tag) == 2 and isinstance(tag[0], str) and tag[0] != "" and type(tag[1]) is int
    return (tag[0], tag[1]) if ok else ("", 0)


def create_app(data: dict, name: str, out_dir: Path, debug: bool = False):
    """The Dash app for problem-file ``data`` (dict) named ``name``; saves and reports go to ``out_dir``;
    ``debug``: a failure a callback logs itself carries its traceback (``designer --debug studio``)."""
    defaults = state.control_values(data)
    app = dash.Dash(__name__, title=f"studio · {name}", update_title=None, serve_locally=True, assets_ignore=".*")
    app.index_string = INDEX
    app.renderer = RENDERER
    app.layout = build_layout(name, defaults, problem_from_dict(data).units)
    # the card's limits (rec-limits) are in the recommendation panel, which the trade-off's callback returns
    app.validation_layout = html.Div([app.layout, html.Div(id="rec-limits")])
    # the problems whose limits a card waits for, by their change's number
    pending: OrderedDict = OrderedDict()
    _trade_off_callback(app, data, defaults, pending)
    _request_callbacks(app)
    _fan_out_callbacks(app)
    _limits_callback(app, pending, debug)
    _card_callback(app)
    _mine_callback(app, out_dir)
    _save_callback(app, out_dir)
    return app


# long: one callback, 11 outputs
def _trade_off_callback(app, data: dict, defaults: dict, pending: OrderedDict) -> None:
    """The callback that owns the trade-off: controls (or the URL) -> problem -> fronts -> chart, panel, URL.

    Only what changed goes to the browser: the chart's traces that differ from the ones it shows (a Dash
    ``Patch``, :func:`_chart`; the layout is sent with the first chart only, then its axes), and the messages,
    card buttons, URL and problem data where they differ from the page's.  The messages, the buttons' labels and
    the controls' values read from the URL go as one store each (``messages``, ``alt-labels``, ``url-values``),
    which the browser fans out to the page (:func:`_fan_out_callbacks`): each output of this callback costs Dash's
    renderer work on every change (its loading state at the request and the answer).  ``rec-pending`` is the
    number of the change whose card waits for its limits (computed later: ``pending`` maps it to its problem and key,
    :func:`_limits_callback`), None when the card has them.

    Never a stale answer: the page numbers its requests (:data:`RENDERER`); one that a newer request of the page
    has overtaken is not computed (the renderer drops its answer), and every answer names the controls it answers
    (``answered``), so the page says "computing…" while the controls shown differ (:func:`_request_callbacks`)."""
    keys = [c.key for c in state.all_controls()]
    # the server's count of answers; of the URL's values sent; the newest request of each page
    newest = {"generation": 0, "url": 0}
    pages: dict[str, int] = {}

    @app.callback(
        Output("url-values", "data"),
        Output("messages", "data"),
        Output("front", "figure"),
        Output("front-shown", "data"),
        Output("recommendation", "children"),
        Output("status", "children"),
        Output("url", "search"),
        Output("problem-data", "data"),
        Output("rec-pending", "data"),
        Output("answered", "data"),
        Output("alt-labels", "data"),
        Input("url", "search"),
        Input({"type": "ctl", "key": ALL}, "value"),
        Input("mine-store", "data"),
        State("problem-data", "data"),
        State("front-shown", "data"),
        State("messages", "data"),
        State("alt-labels", "data"),
    )
    def update(search, values, mine, last, shown, messages_shown, labels_shown):
        page, n = _sequence()
        pages[page] = max(pages.get(page, 0), n)  # on arrival: an older request waiting for the lock sees it
        from_url = ctx.triggered_id in (None, "url")
        if not from_url:
            if not isinstance(values, list) or len(values) != len(keys):
                raise PreventUpdate
            current = dict(zip(keys, values))
        else:
            current = state.from_query(search, defaults)
        with view.LOCK:
            newest["url"] += from_url  # numbered: going back to a URL sets its values again
            values_out = {"n": newest["url"], "values": [current[k] for k in keys]} if from_url else no_update
        answered = {"values": [current[k] for k in keys], "valid": True}
        try:
            problem, merged = state.build_problem(data, current)
            canonical = json.dumps(merged, sort_keys=True)
            with view.LOCK:
                if n < pages[page] and view.cached(canonical) is None:
                    raise PreventUpdate  # overtaken by a newer change, which the browser waits for instead
                fronts = view.compute_fronts(problem, key=canonical)
                newest["generation"] += 1
                generation = newest["generation"]
        except DesignerError as exc:
            errors, general = _messages(exc, data, current, defaults, keys)
            # the last valid chart stays; only the messages change (and the page says it shows the last valid answer)
            return (
                values_out,
                _changed({"errors": errors, "general": general}, messages_shown),
                *[no_update] * 4,  # the chart, what it shows, the recommendation, the status
                no_update if from_url else state.to_query(current, defaults),
                *[no_update] * 2,  # the problem data, the card's pending limits
                {**answered, "valid": False},
                no_update,  # the card buttons' labels
            )
        figure, shown_now = _chart(fronts, mine, shown)
        query = state.to_query(current, defaults)
        waiting = fronts.recommendation is not None and fronts.recommendation.spec is None
        if waiting:
            pending[generation] = (problem, canonical)
            while len(pending) > 16:
                pending.popitem(last=False)
        return (
            values_out,
            _changed({"errors": [""] * len(keys), "general": ""}, messages_shown),
            figure,
            shown_now,
            recommendation_panel(fronts),
            _status(problem, fronts),
            no_update if from_url and query == (search or "") else query,
            no_update if merged == last else merged,
            generation if waiting else None,
            answered,
            _changed(alternative_buttons(fronts), labels_shown),
        )


COMPUTING = "computing…"
"""What the page says while the answer shown is not the answer to the controls shown."""

LAST_VALID = "shown: the answer to the last valid values"
"""What the page says when the controls shown have no answer (a value the loader refuses)."""


def _request_callbacks(app) -> None:
    """In the browser: compare the controls shown with the ones the answer on the page is for (``answered``):
    while they differ the panel is greyed and the line above the chart says :data:`COMPUTING` (or
    :data:`LAST_VALID`).  Once as the controls change, once as an answer comes: a callback with the answer as
    input would wait for the trade-off's request to end."""
    compare = (
        "function (values, answered) {"
        " if (!answered || JSON.stringify(values) !== JSON.stringify(answered.values)) { return ["
        + json.dumps(COMPUTING)
        + ", 'waiting']; }"
        " return answered.valid ? ['', 'answered'] : [" + json.dumps(LAST_VALID) + ", 'answered invalid']; }"
    )
    app.clientside_callback(
        compare,
        Output("computing", "children"),
        Output("answer-box", "className"),
        Input({"type": "ctl", "key": ALL}, "value"),
        State("answered", "data"),
    )
    app.clientside_callback(
        compare.replace("function (values, answered)", "function (answered, values)"),
        Output("computing", "children", allow_duplicate=True),
        Output("answer-box", "className", allow_duplicate=True),
        Input("answered", "data"),
        State({"type": "ctl", "key": ALL}, "value"),
        prevent_initial_call=True,
    )


LOG = logging.getLogger("designer.studio")
"""The studio's console (the logger :mod:`designer.studio.server` writes its one-line messages to)."""


def _limits_callback(app, pending: OrderedDict, debug: bool = False) -> None:
    """The second step of a change: the recommended caster's acceptance limits and worst corner
    (:func:`designer.studio.view.compute_spec`, about 0.1 s) into the card's ``rec-limits``.

    The trade-off's answer sets ``rec-pending`` (the change's number); the browser passes it on to ``rec-go``
    once it has painted the chart (after the next frame: the computation then does not compete with the redraw
    for the cores); the server answers ``{"n", "text"}`` in ``rec-answer``, which goes into the card only if it
    is still the card of change ``n`` (a newer card meanwhile takes no older answer)."""

    app.clientside_callback(
        "function (n) { return n == null ? window.dash_clientside.no_update"
        " : new Promise(done => requestAnimationFrame(() => setTimeout(() => done(n), 0))); }",
        Output("rec-go", "data"),
        Input("rec-pending", "data"),
        prevent_initial_call=True,
    )
    app.clientside_callback(
        "function (answer, n) { return answer && answer.n === n ? answer.text : window.dash_clientside.no_update; }",
        Output("rec-limits", "children"),
        Input("rec-answer", "data"),
        State("rec-pending", "data"),
        prevent_initial_call=True,
    )

    @app.callback(Output("rec-answer", "data"), Input("rec-go", "data"), prevent_initial_call=True)
    def fill_limits(generation):
        with view.LOCK:
            if generation is None or generation not in pending:
                raise PreventUpdate
            problem, key = pending[generation]
            try:
                fronts = view.compute_spec(problem, key=key)
            except DesignerError as exc:
                return {"n": generation, "text": str(exc)}
            except Exception as exc:  # noqa: BLE001 - the card must not keep "computing…": it says so, the console why
                first = str(exc).splitlines()[0] if str(exc) else ""
                LOG.error("acceptance limits: %s: %s", type(exc).__name__, first, exc_info=exc if debug else None)
                return {"n": generation, "text": LIMITS_FAILED}
            return {
                "n": generation,
                "text": limits_text(view.recommendation_record(fronts.recommendation), fronts.problem.units),
            }


def _changed(new, shown):
    """``new`` where it differs from what the page ``shown``, else ``no_update``."""
    return no_update if new == shown else new


def _fan_out_callbacks(app) -> None:
    """In the browser: the trade-off's ``messages`` (``{"errors": one per control, "general"}``) into the
    message beside each control and above the chart, its ``alt-labels`` into the card buttons of the
    alternatives (a button without a label hidden), and its ``url-values`` (``{"n", "values"}``: the controls a
    URL sets, on the page's load and on Back or Forward) into the controls (by ``set_props``: were the controls an
    output, Dash would hold every callback they feed until the trade-off answers).  They run only when the server
    sent a change, so none is on the path of a key press."""
    keys = json.dumps([c.key for c in state.all_controls()])
    app.clientside_callback(
        f"function (v) {{ {keys}.forEach((key, i) => window.dash_clientside.set_props("
        "{type: 'ctl', key: key}, {value: v.values[i]})); }",
        Input("url-values", "data"),
        prevent_initial_call=True,
    )
    app.clientside_callback(
        "function (m) { return [m.errors, m.general]; }",
        Output({"type": "err", "key": ALL}, "children"),
        Output("general-error", "children"),
        Input("messages", "data"),
        prevent_initial_call=True,
    )
    app.clientside_callback(
        "function (labels) { return [labels, labels.map(label => !label)]; }",
        Output({"type": "alt-card", "index": ALL}, "children"),
        Output({"type": "alt-card", "index": ALL}, "hidden"),
        Input("alt-labels", "data"),
        prevent_initial_call=True,
    )


def _chart(fronts, mine, shown) -> tuple:
    """(the chart's update, what it then shows) for ``fronts`` and my caster ``mine``.

    ``shown`` is what the chart shows: a [part, digest] pair per trace (``meta`` and a hash of the trace), as
    this function returned it last time (None before the first chart).  The update is the whole figure the
    first time; a ``Patch`` of the traces whose digest changed when the same parts are drawn (no_update
    if none did); otherwise a ``Patch`` of the data alone.  Of the layout only the axes' ranges (fitted to the
    points, :func:`designer.studio.figures.axis_ranges`) and ``datarevision`` (a digest of the traces drawn)
    change after the first chart.
    """
    traces = figures.front_traces(
        view.front_points(fronts.continuous),
        view.front_points(fronts.risk),
        view.front_points(fronts.buildable),
        view.recommendation_record(fronts.recommendation),
        mine,
        fronts.problem.units,
    )
    ranges = figures.axis_ranges(traces)
    now = [[t["meta"], _digest(t)] for t in traces]
    # layout.datarevision names the data drawn: plotly.js then redraws from the new traces without comparing
    # them with the old ones (about half its time per redraw in Chromium)
    revision = _digest({"traces": now})
    if not shown:
        return {
            "data": traces,
            "layout": {**figures.with_ranges(figures.front_layout(), ranges), "datarevision": revision},
        }, now
    patch = Patch()
    if [m for m, _ in shown] != [m for m, _ in now]:
        patch["data"] = traces
    else:
        changed = [i for i, (old, new) in enumerate(zip(shown, now)) if old[1] != new[1]]
        if not changed:
            return no_update, no_update
        for i in changed:
            patch["data"][i] = traces[i]
    for axis, value in ranges.items():  # the axes follow the data
        patch["layout"][axis]["range"] = value["range"]
        patch["layout"][axis]["autorange"] = False
    patch["layout"]["datarevision"] = revision
    return patch, now


def _digest(trace: dict) -> str:
    """A short hash of a trace's content (its JSON), to tell which traces changed."""
    text = json.dumps(trace, sort_keys=True, default=float, allow_nan=True)
    return hashlib.blake2b(text.encode(), digest_size=8).hexdigest()


def _messages(exc: DesignerError, data: dict, current: dict, defaults: dict, keys: list) -> tuple[list, str]:
    """(message beside each control, general message) for a problem the loader refused or cannot reach."""
    key = getattr(exc, "key", None)
    if key is None:  # the problem is valid but out of reach: say it beside the control just moved
        moved = ctx.triggered_id.get("key") if isinstance(ctx.triggered_id, dict) else None
        key = moved or state.blame(str(exc))
    messages = state.control_errors(data, current, defaults)
    if not messages:  # only the combination is wrong (e.g. a target out of reach)
        messages = {key: str(exc)}
    errors = [""] * len(keys)
    general = ""
    for k, message in messages.items():
        if k in keys:
            errors[keys.index(k)] = message
        else:
            general = message
    return errors, general


def _status(problem, fronts) -> str:
    """The line above the chart: how many casters the chart shows, and the time they took."""
    return (
        f"{problem.name}: {len(fronts.continuous)} best possible, "
        f"{0 if fronts.risk is None else len(fronts.risk)} within the shimmy risk, "
        f"{0 if fronts.buildable is None else len(fronts.buildable)} from stock; "
        f"computed in {1000 * fronts.seconds:.0f} ms ({1000 * fronts.cpu_seconds:.0f} ms CPU)"
    )


CARDS = 16
"""Cards kept by (problem, record): opening one again shows it at once."""


def _card_callback(app) -> None:
    """A click on a point of the chart, on the card button of the caster to build or of an alternative, opens
    that caster's card: the record the chart or the panel shows (:func:`designer.studio.view.card_record`), never
    a caster evaluated again."""

    cards: OrderedDict = OrderedDict()

    @app.callback(
        Output("card", "children"),
        Input("front", "clickData"),
        Input("rec-card", "n_clicks"),
        Input({"type": "alt-card", "index": ALL}, "n_clicks"),
        State("problem-data", "data"),
        State("mine-store", "data"),
        prevent_initial_call=True,
    )
    def open_card(click, _n, _alts, merged, mine):
        if not merged or not ctx.triggered or not ctx.triggered[0].get("value"):
            raise PreventUpdate  # a button drawn anew (n_clicks 0), not a click
        trigger = ctx.triggered_id
        if trigger == "rec-card":
            part, index, name = "recommendation", 0, "the caster to build"
        elif isinstance(trigger, dict) and trigger.get("type") == "alt-card":
            part, index, name = "alternative", trigger.get("index"), None
        else:
            point = (click or {}).get("points", [{}])[0] if isinstance(click, dict) else {}
            custom = point.get("customdata") if isinstance(point, dict) else None
            if not isinstance(custom, list) or len(custom) < 3:
                raise PreventUpdate
            part, index, name = custom[0], custom[1], custom[2]
        try:
            problem = problem_from_dict(merged)
            if part == "mine":
                if not mine:
                    raise PreventUpdate
                design = Design(**mine["numbers"]["design"])
                return card_panel(problem, view.mine_record(problem, design), "my caster")
            if part not in view.CARD_PARTS or not isinstance(index, int) or isinstance(index, bool):
                raise PreventUpdate
            key = json.dumps(merged, sort_keys=True)
            with view.LOCK:  # a card opened before: its sweeps and simulations are not redone
                if (key, part, index) in cards:
                    cards.move_to_end((key, part, index))
                    return cards[(key, part, index)]
            # the fronts of this state are cached: only the card is computed
            fronts = view.compute_fronts(problem, key=key)
            try:
                record = view.card_record(fronts, part, index)
            except (KeyError, IndexError):
                raise PreventUpdate from None
            if name is None:
                name = role_name(getattr(record, "role", None))
            panel = card_panel(problem, record, name)
            with view.LOCK:
                cards[(key, part, index)] = panel
                while len(cards) > CARDS:
                    cards.popitem(last=False)
            return panel
        except DesignerError as exc:
            return html.Div(str(exc), style=CSS["error"])


def _mine_callback(app, out_dir: Path) -> None:
    """The "Check my caster" button: its numbers on the chart and its fixes ranked, with the command to run them."""

    boxes = (("trail", "length"), ("diameter", "length"), ("groove", "length"), ("damping", "damping"))

    @app.callback(
        Output("mine-store", "data"),
        Output("mine-result", "children"),
        Output("mine-error", "children"),
        Input("mine-go", "n_clicks"),
        *[Input(f"mine-{key}", "n_submit") for key, _ in boxes],
        *[State(f"mine-{key}", "value") for key, _ in boxes],
        State("problem-data", "data"),
        prevent_initial_call=True,
    )
    def check_mine(_n, _a, _b, _c, _d, *texts_and_data):
        *texts, merged = texts_and_data
        try:
            design = Design(*(quantity_option(str(t), dim, f"--{key}") for t, (key, dim) in zip(texts, boxes)))
            problem = problem_from_dict(merged)
            result = view.my_caster(problem, design)
            result["command"] = "Save problem, then " + view.fix_command(
                out_dir / f"{problem.name}.toml", design, problem.units
            )
        except DesignerError as exc:
            return no_update, no_update, str(exc)
        store = {"numbers": result["numbers"]}
        return json.loads(json.dumps(store, default=float)), fixes_panel(result, problem), ""


def _save_callback(app, out_dir: Path) -> None:
    """The "Save problem" button writes the problem file (and downloads it), "Write report" the Pareto report."""

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
        try:
            return _save_or_report(ctx.triggered_id, merged, out_dir)
        except DesignerError as exc:  # a refused folder, a full disk: one line on the page (designer.output)
            return html.Span(str(exc), style=CSS["error"]), no_update
        except OSError as exc:  # pragma: no cover - designer.output turns write failures into DesignerError
            return html.Span(f"{out_dir}: cannot write ({exc.strerror or exc})", style=CSS["error"]), no_update


def _save_or_report(trigger, merged: dict, out_dir: Path):
    """ "Save problem": the problem file ``<out>/<name>.toml`` (replaced atomically) and its download; "Write
    report": the Pareto report ``<out>/<name>/``, as `designer pareto` writes it (only the report's own files)."""
    problem = problem_from_dict(merged)
    if trigger == "save":
        path = out_dir / f"{problem.name}.toml"
        text = signed(state.to_toml(merged), SAVE_WRITER)
        write_file(path, text, "--out", example=path.name, kind=SAVED_PROBLEM)
        return html.Span([f"saved {path.resolve()} (run it: designer run {path})"], id="saved-path"), {
            "content": text,
            "filename": path.name,
        }
    from designer.jobs import compute_and_write  # the same report as `designer pareto`; loads matplotlib

    summary = view._quiet(compute_and_write, problem, out=out_dir / problem.name)
    return html.Span(f"report written: {Path(summary['index_html']).resolve()}", id="report-path"), no_update
