"""What the studio recomputes and sends per change (issue 29.2): fronts kept by what they depend on, the chart
sent as the traces that changed (a Dash Patch), the traces plain plotly dicts.

The callbacks run over HTTP (Flask's test client), as the page posts them; tests/studio/test_studio_browser.py
checks the same chart in Chromium against the API.
"""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

pytest.importorskip("dash")
go = pytest.importorskip("plotly.graph_objects")

from designer.studies.front import pareto_front  # noqa: E402
from designer.studio import figures, state, view  # noqa: E402
from designer.studio.app import create_app  # noqa: E402
from designer.studio.layout import MAX_CARD_BUTTONS  # noqa: E402

PROBLEM = state.default_problem_path()


def _post(
    client,
    keys: list,
    values: dict,
    changed: str,
    shown,
    mine=None,
    last=None,
    search="",
    messages=None,
    labels=None,
    studio=None,
) -> dict:
    """POST the trade-off callback as the page does (the controls' ``values``, the URL query ``search``, the chart
    showing ``shown``, the page's ``messages`` and card-button ``labels`` stores, its [page, number] ``studio``)."""
    body = {
        "output": "..url-values.data...messages.data"
        "...front.figure...front-shown.data...recommendation.children...status.children...url.search...problem-data.data"
        "...rec-pending.data...answered.data...alt-labels.data..",
        "outputs": [
            {"id": "url-values", "property": "data"},
            {"id": "messages", "property": "data"},
            {"id": "front", "property": "figure"},
            {"id": "front-shown", "property": "data"},
            {"id": "recommendation", "property": "children"},
            {"id": "status", "property": "children"},
            {"id": "url", "property": "search"},
            {"id": "problem-data", "property": "data"},
            {"id": "rec-pending", "property": "data"},
            {"id": "answered", "property": "data"},
            {"id": "alt-labels", "property": "data"},
        ],
        "inputs": [
            {"id": "url", "property": "search", "value": search},
            [{"id": {"type": "ctl", "key": k}, "property": "value", "value": values[k]} for k in keys],
            {"id": "mine-store", "property": "data", "value": mine},
        ],
        "changedPropIds": [changed],
        "state": [
            {"id": "problem-data", "property": "data", "value": last},
            {"id": "front-shown", "property": "data", "value": shown},
            {"id": "messages", "property": "data", "value": messages},
            {"id": "alt-labels", "property": "data", "value": labels},
        ],
        **({} if studio is None else {"studio": studio}),
    }
    response = client.post("/_dash-update-component", json=body)
    if response.status_code == 204:  # PreventUpdate: nothing sent
        return {}
    assert response.status_code == 200, response.data[:500]
    return json.loads(response.data)["response"]


def _apply(figure: dict, patch: dict) -> dict:
    """A figure with a Dash Patch's Assign operations applied (the only ones the studio sends)."""
    out = copy.deepcopy(figure)
    assert patch["__dash_patch_update"] == "__dash_patch_update"
    for op in patch["operations"]:
        assert op["operation"] == "Assign"
        *path, last = op["location"]
        node = out
        for key in path:
            node = node[key]
        node[last] = op["params"]["value"]
    return out


def _mine(problem) -> dict:
    """The mine-store the "Check my caster" button writes for a 1 in trail, 8 in wheel, bare fork."""
    numbers = view.numbers_of(view.mine_record(problem, view.Design(0.0254, 0.2032, 0.0, 1.3)))
    return json.loads(json.dumps({"numbers": numbers}, default=float))


def _locations(patch: dict) -> list:
    return [op["location"] for op in patch["operations"]]


@pytest.fixture(scope="module")
def studio(tmp_path_factory):
    data, name = state.read_problem_data(PROBLEM)
    app = create_app(data, name, tmp_path_factory.mktemp("studio"))
    return app.server.test_client(), [c.key for c in state.all_controls()], state.control_values(data)


def test_chart_is_sent_as_the_traces_that_changed(studio):
    """First chart: the whole figure (layout included), no message, the card buttons' labels, the URL's control
    values (numbered; a change of a control sends none: the page has them). The same state again:
    no figure, messages or labels at all (a load without a number: its message beside the load, nothing else). A new target:
    a Patch of the four traces that changed, the axes' ranges and the layout's datarevision, which applied to the first
    chart gives exactly the chart a fresh page draws for that target. My caster added: the data alone. α changed: the nominal front's
    trace is not sent (it does not depend on α), the risk-bounded one is."""
    client, keys, defaults = studio
    first = _post(client, keys, defaults, "url.search", None)
    figure, shown = first["front"]["figure"], first["front-shown"]["data"]
    assert set(figure) == {"data", "layout"} and "template" in figure["layout"] and figure["layout"]["datarevision"]
    assert "transition" not in figure["layout"]  # with one, plotly.js redraws each answer twice
    assert [m for m, _ in shown] == ["continuous", "risk", "buildable", "recommendation"]
    assert [t["meta"] for t in figure["data"]] == [m for m, _ in shown]

    messages, labels = first["messages"]["data"], first["alt-labels"]["data"]
    assert messages == {"errors": [""] * len(keys), "general": ""}
    assert len(labels) == MAX_CARD_BUTTONS and labels[0].startswith("card: ")
    again = _post(
        client,
        keys,
        defaults,
        '{"key":"target","type":"ctl"}.value',
        shown,
        last=first["problem-data"]["data"],
        messages=messages,
        labels=labels,
    )
    assert "front" not in again and "front-shown" not in again and "problem-data" not in again
    assert "messages" not in again and "alt-labels" not in again  # the page shows them already
    assert first["url-values"]["data"]["values"] == [defaults[k] for k in keys] and "url-values" not in again
    wrong = _post(client, keys, dict(defaults, load="abc"), '{"key":"load","type":"ctl"}.value', shown, labels=labels)
    errors = wrong["messages"]["data"]["errors"]
    assert "a unit without a number" in errors[keys.index("load")] and sum(map(bool, errors)) == 1
    assert wrong["answered"]["data"]["valid"] is False and "front" not in wrong and "alt-labels" not in wrong

    moved = dict(defaults, target=3.0)
    patch = _post(client, keys, moved, '{"key":"target","type":"ctl"}.value', shown)
    axes = [["layout", axis, key] for axis in ("xaxis", "yaxis") for key in ("range", "autorange")]
    assert _locations(patch["front"]["figure"]) == [["data", i] for i in range(4)] + axes + [["layout", "datarevision"]]
    from_url = _post(client, keys, moved, "url.search", None, search=state.to_query(moved, defaults))
    fresh, values = from_url["front"]["figure"], from_url["url-values"]["data"]
    assert _apply(figure, patch["front"]["figure"]) == fresh and "url-values" not in patch
    # the controls a URL sets go to the page numbered, so a second visit of one URL sets them again
    assert values["values"][keys.index("target")] == 3.0 and values["n"] > first["url-values"]["data"]["n"]
    figure, shown = fresh, patch["front-shown"]["data"]

    problem, _ = state.build_problem(state.read_problem_data(PROBLEM)[0], moved)
    mine = _mine(problem)
    with_mine = _post(client, keys, moved, "mine-store.data", shown, mine=mine)
    assert _locations(with_mine["front"]["figure"]) == [["data"], *axes, ["layout", "datarevision"]]
    figure = _apply(figure, with_mine["front"]["figure"])
    assert [t["meta"] for t in figure["data"]][-1] == "mine"
    shown = with_mine["front-shown"]["data"]

    alpha = dict(moved, alpha=0.02)
    risk_only = _post(client, keys, alpha, '{"key":"alpha","type":"ctl"}.value', shown, mine=mine)
    sent = _locations(risk_only["front"]["figure"])
    assert ["data", 0] not in sent and ["data", 1] in sent and ["data", 4] not in sent
    fresh = _post(client, keys, alpha, "url.search", None, mine=mine, search=state.to_query(alpha, defaults))
    fresh = fresh["front"]["figure"]
    assert _apply(figure, risk_only["front"]["figure"]) == fresh


def test_a_request_overtaken_by_a_newer_one_is_not_computed(tmp_path, monkeypatch):
    """Changes reach the server while it computes (its lock held), each numbered by its page: the defaults
    (computed before), then two new targets, then another page's first change. The older target is not computed
    (204: the browser has dropped its answer, having called the callback again); the newer is answered, with the
    controls it was sent with; the defaults, though overtaken, from the cache; the other page's (a second tab, a
    reload), though its number is lower."""
    import threading

    data, name = state.read_problem_data(PROBLEM)
    client = create_app(data, name, tmp_path).server.test_client()
    keys, defaults = [c.key for c in state.all_controls()], state.control_values(data)
    _post(client, keys, defaults, "url.search", None)  # the defaults computed (and cached)

    class Lock:  # view.LOCK, counting the requests that wait for it
        def __init__(self):
            self.inner, self.waiting = threading.RLock(), 0

        def __enter__(self):
            self.waiting += 1
            return self.inner.__enter__()

        def __exit__(self, *exc):
            return self.inner.__exit__(*exc)

    lock = Lock()
    monkeypatch.setattr(view, "LOCK", lock)
    answers: dict = {}
    sent = {
        "cached": (defaults, ["page", 1]),
        "older": (dict(defaults, target=3.1), ["page", 2]),
        "newer": (dict(defaults, target=3.2), ["page", 3]),
        "other page": (dict(defaults, target=3.3), ["other", 1]),
    }

    def change(label):
        values, studio = sent[label]
        answers[label] = _post(client, keys, values, '{"key":"target","type":"ctl"}.value', None, studio=studio)

    threads = [threading.Thread(target=change, args=(label,), daemon=True) for label in sent]
    with lock.inner:
        for i, t in enumerate(threads):
            t.start()
            while lock.waiting < i + 1:  # each has arrived before the next is sent
                threading.Event().wait(0.005)
    for t in threads:
        t.join(60)
    assert answers["older"] == {}
    for label in ("cached", "newer", "other page"):
        assert answers[label]["answered"]["data"]["values"] == [sent[label][0][k] for k in keys], label


def test_a_request_without_a_well_formed_number_is_answered_unnumbered(studio):
    """A request whose ``studio`` tag is not [a page, a whole number] (a bool, a string, three items, no page, a
    fraction) is answered as a request without a number, each at a target not computed before: a page that has
    sent 50 requests, or a tag of the empty page, does not make it count as overtaken."""
    client, keys, defaults = studio
    change = '{"key":"target","type":"ctl"}.value'
    assert _post(client, keys, dict(defaults, target=2.55), change, None, studio=["page", 50])["answered"]
    tags = (["page", True], ["page", "51"], ["page", 1, 2], ["", 99], [None, 3], ["page", 2.5], "page", None)
    for i, tag in enumerate(tags):
        values = dict(defaults, target=round(2.65 + 0.1 * i, 2))
        answer = _post(client, keys, values, change, None, studio=tag)
        assert answer["answered"]["data"]["values"] == [values[k] for k in keys], tag


def test_chart_traces_are_what_plotly_would_build(studio):
    """The chart's plain-dict traces and layout are valid plotly (go.Figure accepts them) and unchanged by
    plotly's validation: the same JSON as the graph objects built from them."""
    data, _ = state.read_problem_data(PROBLEM)
    problem, _ = state.build_problem(data, state.control_values(data))
    fronts = view.compute_fronts(problem)
    fig = figures.front_figure(
        view.front_points(fronts.continuous),
        view.front_points(fronts.risk),
        view.front_points(fronts.buildable),
        view.recommendation_record(fronts.recommendation),
        _mine(problem),
    )
    assert [t["meta"] for t in fig["data"]] == ["continuous", "risk", "buildable", "recommendation", "mine"]
    built = go.Figure(fig).to_plotly_json()
    assert json.dumps(built, sort_keys=True, default=float) == json.dumps(fig, sort_keys=True, default=float)


def test_fronts_are_kept_by_what_they_depend_on():
    """front_key ignores the names, the stock and the objective's weights and caps, and nothing else: the front of
    a problem differing only there is the same front (recomputed here to the bit); a change of α keeps the
    nominal front's key and changes the risk-bounded one's; compute_fronts then reuses the nominal front."""
    data, _ = state.read_problem_data(PROBLEM)
    defaults = state.control_values(data)
    problem, _ = state.build_problem(data, defaults)
    other = problem.replace(name="other", title="t", stock=None, weights=(2.0, 1.0), max_turning_effort=50.0)
    assert view.front_key(other) == view.front_key(problem)
    a, b = pareto_front(problem), pareto_front(other)
    assert np.array_equal(a.objectives(), b.objectives()) and np.array_equal(a.designs(), b.designs())

    riskier, _ = state.build_problem(data, dict(defaults, alpha=0.1))
    assert view.front_key(riskier.nominal()) == view.front_key(problem.nominal())
    assert view.front_key(riskier) != view.front_key(problem)
    for changed in (dict(defaults, target=2.6), dict(defaults, load="180 N"), dict(defaults, swept="6.5 in")):
        p, _ = state.build_problem(data, changed)
        assert view.front_key(p.nominal()) != view.front_key(problem.nominal())

    first = view.compute_fronts(problem)
    second = view.compute_fronts(riskier)
    assert second.continuous.points is first.continuous.points  # reused, not recomputed
    assert second.continuous.problem == riskier.nominal()
    assert not np.array_equal(second.risk.objectives(), first.risk.objectives())


HELPER_RUN = r"""
import json, os, signal, sys, time
import numpy as np
from designer.studies.front import pareto_front
from designer.studio import helper, state, view

def same(a, b):
    return bool(np.array_equal(a.objectives(), b.objectives()) and np.array_equal(a.designs(), b.designs()))

if __name__ == "__main__":
    helper.expand_batches()  # as designer studio's process does: the helper's solvers are built the same way
    data, _ = state.read_problem_data()
    defaults = state.control_values(data)
    problem, _ = state.build_problem(data, dict(defaults, target=2.2))
    helper.start(warm=problem.nominal())
    first = helper.pid()
    with_helper = view.compute_fronts(problem)
    out = {"helper": same(with_helper.risk, pareto_front(problem))
                     and same(with_helper.continuous, pareto_front(problem.nominal())),
           "helper_cpu": with_helper.cpu_seconds}
    os.kill(first, signal.SIGKILL)  # a helper that dies: the next change is computed here, the helper dropped
    time.sleep(1)
    other, _ = state.build_problem(data, dict(defaults, target=2.3))
    fallback = view.compute_fronts(other)
    out["fallback"] = same(fallback.risk, pareto_front(other)) and same(fallback.continuous, pareto_front(other.nominal()))
    out["dropped"] = helper.pid() is None
    helper.start()
    out["second"] = helper.pid()
    print(json.dumps(out), flush=True)
    time.sleep(300)  # killed by the test
"""


def _running(pid: int) -> bool:
    """Whether process ``pid`` runs (an exited one that nobody reaped yet, a zombie, does not)."""
    from pathlib import Path

    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    except OSError:  # no /proc: ask the kernel
        import os

        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        return True
    return stat.rsplit(")", 1)[1].split()[0] not in ("Z", "X")


def test_helper_process_computes_the_same_front_and_ends_with_the_studio(tmp_path):
    """designer studio's helper process (helper.start) computes the risk-bounded front to the bit as pareto_front
    does here (both with the studio's expanded batches); when it dies the change is computed in the server's process and the helper dropped; when the server
    is killed (SIGKILL: no clean-up of its own), its helper ends within seconds."""
    import os
    import signal
    import subprocess
    import sys
    import time

    script = tmp_path / "run_helper.py"
    script.write_text(HELPER_RUN)
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert line, proc.stderr.read()[-3000:]
        out = json.loads(line)
        assert out["helper"] and out["fallback"] and out["dropped"]
        assert out["helper_cpu"] > 0
        helper_pid = out["second"]
        assert _running(helper_pid)
        proc.kill()
        proc.wait(30)
        deadline = time.monotonic() + 20
        while _running(helper_pid):
            if time.monotonic() > deadline:
                os.kill(helper_pid, signal.SIGKILL)
                raise AssertionError("the helper outlived its killed server by 20 s")
            time.sleep(0.2)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait(30)
