"""The studio's Dash app without a browser: its callbacks over HTTP (Flask's test client) and its panels.

The browser session is tests/studio/test_studio_browser.py; these check what needs no rendering, faster.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dash")

from designer import display  # noqa: E402
from designer.cli import main  # noqa: E402
from designer.model import Design  # noqa: E402
from designer.problem import problem_from_dict  # noqa: E402
from designer.studio import state, view  # noqa: E402
from designer.studio.app import create_app, fixes_panel, numbers_table  # noqa: E402

PROBLEM = state.default_problem_path()
POINTS = 5
"""Front points of the report test (the problem's [pareto] points): small, the test writes two reports."""


def _callback(
    client,
    outputs: list[tuple[str, str]],
    inputs: list,
    changed: str,
    states: list[tuple[str, str, object]],
) -> dict:
    """POST one Dash callback as the page does; returns the response's outputs by component id."""
    single = len(outputs) == 1
    body = {
        "output": f"{outputs[0][0]}.{outputs[0][1]}"
        if single
        else ".." + "...".join(f"{i}.{p}" for i, p in outputs) + "..",
        "outputs": {"id": outputs[0][0], "property": outputs[0][1]}
        if single
        else [{"id": i, "property": p} for i, p in outputs],
        "inputs": [{"id": x[0], "property": x[1], "value": x[2]} if isinstance(x, tuple) else x for x in inputs],
        "changedPropIds": [changed],
        "state": [{"id": i, "property": p, "value": v} for i, p, v in states],
    }
    response = client.post("/_dash-update-component", json=body)
    assert response.status_code == 200, response.data[:500]
    return json.loads(response.data)["response"]


def _objectives(path: Path) -> list[tuple[str, ...]]:
    with open(path, newline="") as fh:
        return [
            tuple(
                row[k]
                for k in (
                    "trail_in",
                    "diameter_in",
                    "groove_in",
                    "damping_N_m_per_rad",
                    "turning_effort_N",
                    "threshold_force_N",
                    "buildable",
                )  # fmt: skip
                if k in row
            )
            for row in csv.DictReader(fh)
        ]


def test_write_report_is_designer_pareto(tmp_path):
    """ "Write report" (the button's callback, over HTTP) writes <out>/<name>/ with the files of a report, and its
    front.csv is the one `designer pareto` writes for the same problem (the saved TOML): same rows, same numbers.
    A 5-point front keeps the two reports quick."""
    data, name = state.read_problem_data(PROBLEM)
    data = {**data, "pareto": {**data.get("pareto", {}), "points": POINTS}}
    problem, merged = state.build_problem(data, state.control_values(data))
    app = create_app(data, name, tmp_path / "studio")
    reply = _callback(
        app.server.test_client(),
        [("save-result", "children"), ("download", "data")],
        [("save", "n_clicks", 0), ("report", "n_clicks", 1)],
        "report.n_clicks",
        [("problem-data", "data", merged)],
    )
    written = tmp_path / "studio" / problem.name
    assert "report written" in json.dumps(reply["save-result"]) and (written / "index.html").is_file()
    toml = tmp_path / f"{problem.name}.toml"
    toml.write_text(state.to_toml(merged), encoding="utf-8")
    assert main(["pareto", str(toml), "--out", str(tmp_path / "cli")]) == 0
    studio_rows, cli_rows = _objectives(written / "front.csv"), _objectives(tmp_path / "cli" / "front.csv")
    assert len(studio_rows) >= POINTS and studio_rows == cli_rows


def test_fixes_panel_says_when_the_list_is_cut():
    """ "My caster" lists the whole ranking when it is short ("all N found"); a ranking cut at FIX_LIMIT says it
    is the top n of N and names the `designer fix` command that lists every fix."""
    problem = problem_from_dict(state.read_problem_data(PROBLEM)[0])
    numbers = {
        "critical_speed": 0.75,
        "confident_speed": 0.6,
        "shimmy_probability": 1.0,
        "turning_effort": 17.5,
        "threshold_force": 98.5,
    }
    rows = [{**numbers, "rank": i + 1, "description": f"fix {i + 1}", "shimmy_probability": 0.01} for i in range(3)]
    text = json.dumps(fixes_panel({"numbers": numbers, "fixes": rows, "found": 3}, problem), default=str)
    assert "all 3 found" in text and "designer fix" not in text
    command = 'designer fix out/p.toml --current "T=1in,d=8in,B=0in,c=1.3"'
    result = {"numbers": numbers, "fixes": rows, "found": 250, "command": command}
    text = json.dumps(fixes_panel(result, problem), default=str)
    assert "top 3 of 250" in text and "designer fix out/p.toml" in text


def test_my_caster_lists_the_full_ranking():
    """For the default problem and a 1 in trail, 8 in wheel, bare fork: every fix designer.fix finds is listed
    (the ranking is shorter than FIX_LIMIT), and my caster's numbers are fix's own record of it."""
    from designer import fix

    problem = problem_from_dict(state.read_problem_data(PROBLEM)[0])
    design = Design(0.0254, 0.2032, 0.0, 1.3)
    result = view.my_caster(problem, design)
    assert result["found"] <= view.FIX_LIMIT
    assert len(result["fixes"]) == result["found"] > 10
    current = fix(problem, design, limit=0, specs=0).current
    assert result["numbers"]["shimmy_probability"] == current.shimmy_probability > 0.99
    assert result["numbers"]["critical_speed"] == current.critical_speed


def _default_fronts():
    data, _ = state.read_problem_data(PROBLEM)
    problem, merged = state.build_problem(data, state.control_values(data))
    return problem, view.compute_fronts(problem, key=json.dumps(merged, sort_keys=True))


def test_card_shows_the_knock_safe_speeds():
    """A card's numbers carry the knock-safe speeds of the θ0 = 20° and 40° knocks [m/s] (simulated on the click),
    shown as a row beside V_c; the 40° knock's is lower."""
    problem, fronts = _default_fronts()
    n = view.card(problem, fronts.recommendation)["numbers"]
    assert 0 < n["knock_safe_speed_double"] < n["knock_safe_speed"]
    assert n["knock_safe_speed"] == pytest.approx(n["critical_speed"], rel=0.05)
    table = json.dumps(
        numbers_table(n, problem, "card").to_plotly_json(), default=lambda o: o.to_plotly_json(), ensure_ascii=False
    )
    assert "knock-safe speed, 20° / 40° knock" in table
    assert f"{display.number(n['knock_safe_speed'], 'critical_speed')} / " in table


def test_the_card_of_the_caster_to_build_is_the_recommendations_record():
    """Issue 41: the card of the recommended caster said P(shimmy) 0.26 % beside the panel's 2.98 % (it evaluated
    the caster again with its power-law I_w as a measured wheel).  Its numbers are now the recommendation's own
    record, the default problem's 2.98 %; the same for an alternative's card and a buildable point's."""
    problem, fronts = _default_fronts()
    rec = fronts.recommendation
    n = view.card(problem, view.card_record(fronts, "recommendation"), with_simulation=False)["numbers"]
    for key in ("shimmy_probability", "critical_speed", "confident_speed", "turning_effort", "threshold_force"):
        assert n[key] == getattr(rec, key), key
    assert display.shown(n["shimmy_probability"], "shimmy_probability") == "2.98 %"
    alt = view.card_record(fronts, "alternative", 0)
    assert alt is rec.alternatives[0]
    for i, point in enumerate(rec.buildable):  # a buildable point's card is the record of that caster
        record = view.card_record(fronts, "buildable", i)
        assert record in (rec, *rec.alternatives) and record.design == point.design


def test_a_front_points_card_is_the_points_record():
    """A point of the front within the risk: its card's forces and V_c are the point's record (FrontPoint), its
    risk numbers fix's diagnosis of the same caster (the recommendation's exact law): P(shimmy) at the target
    is about α for a point on the risk bound, and the speed reached w.p. 1 − α is V_req."""
    from designer import fix

    problem, fronts = _default_fronts()
    point = fronts.risk.points[len(fronts.risk.points) // 2]
    assert view.card_record(fronts, "risk", len(fronts.risk.points) // 2) is point
    n = view.card(problem, point, with_simulation=False)["numbers"]
    assert (n["turning_effort"], n["threshold_force"], n["critical_speed"]) == (
        point.turning_effort,
        point.threshold_force,
        point.critical_speed,
    )
    current = fix(problem, point.design, limit=0, specs=0).current
    assert n["shimmy_probability"] == current.shimmy_probability
    assert n["confident_speed"] == pytest.approx(problem.required_speed, rel=1e-6)


def test_the_diameter_sweep_follows_the_wheels_inertia():
    """Issue 41: the card's "V_c vs diameter" was a flat line (one wheel's I_w held at every diameter).  Each
    diameter now takes the problem's inertia model: V_c falls by more than half from the smallest wheel to the
    largest (I_w grows about as d^3.7, Table 1), and both sweeps pass through the caster's own V_c."""
    problem, fronts = _default_fronts()
    rec = fronts.recommendation
    sweeps = view.card(problem, rec, with_simulation=False)["sweeps"]
    vc = sweeps["diameter"]["critical_speed"]
    assert vc[0] > 2 * vc[-1] and np.all(np.diff(vc) < 0)
    for name in ("trail", "diameter"):
        s = sweeps[name]
        at = float(np.interp(s["value"], s["x"], s["critical_speed"]))
        assert at == pytest.approx(rec.critical_speed, rel=0.02), name


def test_recommendations_card_uses_its_wheels_inertia():
    """Catalogue problem: the recommendation's card shows the recommended wheel's own numbers (its measured
    I_w): V_c and P(shimmy) are the recommendation's, the knock-safe speed is within 5 % of V_c."""
    from designer import load_problem
    from designer.studies.recommend import recommend

    problem = load_problem(PROBLEM.parent / "catalog-retrofit.toml")
    rec = recommend(problem)
    n = view.card(problem, rec)["numbers"]
    assert n["critical_speed"] == rec.critical_speed and n["shimmy_probability"] == rec.shimmy_probability
    assert n["measured"] and n["inertia"] == rec.inertia
    assert n["knock_safe_speed"] == pytest.approx(rec.critical_speed, rel=0.05)


def test_recommendations_card_button_opens_its_card(tmp_path):
    """The card button of the caster to build (its callback, over HTTP) opens its card with the knock-safe speed
    row beside V_c and the recommendation's own P(shimmy), 2.98 %."""
    data, name = state.read_problem_data(PROBLEM)
    problem, merged = state.build_problem(data, state.control_values(data))
    app = create_app(data, name, tmp_path)
    reply = _callback(
        app.server.test_client(),
        [("card", "children")],
        [("front", "clickData", None), ("rec-card", "n_clicks", 1), []],
        "rec-card.n_clicks",
        [("problem-data", "data", merged), ("mine-store", "data", None)],
    )
    text = json.dumps(reply["card"]["children"], ensure_ascii=False)
    assert "Card: the caster to build" in text and "knock-safe speed, 20° / 40° knock" in text
    assert "card-knocksafe" in text
    (probability,) = _find(reply["card"]["children"], "id", "card-probability")
    assert json.dumps(probability, ensure_ascii=False).count("2.98 %") == 1


def test_catalogue_points_are_their_casters_records():
    """Catalogue problem: each buildable point of the chart opens the card of its own caster's record (the
    recommendation or an alternative, with its Table 1 wheel's measured I_w): the card's V_c is the point's."""
    from designer import load_problem
    from designer.studies.recommend import recommend

    problem = load_problem(PROBLEM.parent / "catalog-retrofit.toml")
    rec = recommend(problem)
    fronts = view.Fronts(problem=problem, continuous=None, buildable=rec.buildable, recommendation=rec)
    points = view.front_points(rec.buildable)
    assert points and all(p["label"] for p in points)
    for i, p in enumerate(points):
        record = view.card_record(fronts, "buildable", i)
        assert record.wheel == p["label"] and record.measured
        card = view.card(problem, record, with_simulation=False)
        assert card["numbers"]["critical_speed"] == p["critical_speed"]


def _find(component, key, value):
    """The components under ``component`` (Dash components or their JSON) whose ``key`` is ``value``."""
    if isinstance(component, dict):
        props = component.get("props", component)
        found = [component] if value in (component.get(key), props.get(key)) else []
        return found + _find(props.get("children"), key, value)
    if isinstance(component, (list, tuple)):
        return [c for child in component for c in _find(child, key, value)]
    if hasattr(component, "to_plotly_json"):
        return _find(component.to_plotly_json(), key, value)
    return []


def test_the_recommendation_card_shows_the_limits_of_the_chosen_caster(tmp_path):
    """The studio's recommendation card gives the chosen caster's joint acceptance box as the spec rounds it
    (trail, groove min, friction moment min, wheel inertia max; accept when every part is inside) under id rec-limits: the trade-off's
    callback sends the chart and the card with "computing…" there and the change's number in rec-pending; the
    limits callback, asked with that number once the browser has painted the chart (rec-go), answers the limits
    of recommend(problem) (the CLI's spec) for that change; going back to that state shows them at once."""
    from designer import load_problem
    from designer.studies.recommend import recommend
    from designer.studies.acceptance import box_short
    from designer.studio import panels
    from test_studio_updates import _post

    path = PROBLEM.parent / "catalog-retrofit.toml"
    rec = recommend(load_problem(path))
    record = view.recommendation_record(rec)
    assert record["limits"] == list(rec.spec.limits) and len(record["limits"]) >= 3
    fronts = view.Fronts(problem=rec.problem, recommendation=rec, continuous=None, risk=None, notes=[])
    shown = _find(panels.recommendation_panel(fronts), "id", "rec-limits")
    # the joint box (a caster whose parts are all inside passes), in the problem's units, not the one-at-a-time limits
    text = shown[0]["props"]["children"]
    assert len(shown) == 1 and text.startswith("acceptance limits: accept a caster when every part is inside: ")
    assert box_short(rec.spec.joint, rec.problem.units) in text and "one part at a time" not in text

    data, name = state.read_problem_data(path)
    client = create_app(data, name, tmp_path).server.test_client()
    keys = [c.key for c in state.all_controls()]
    values = state.control_values(data)
    first = _post(client, keys, values, "url.search", None)
    card = json.dumps(first["recommendation"]["children"], ensure_ascii=False)
    assert panels.LIMITS_PENDING in card and "rec-limits" in card
    n = first["rec-pending"]["data"]
    assert isinstance(n, int)
    answer = _callback(client, [("rec-answer", "data")], [("rec-go", "data", n)], "rec-go.data", [])
    answer = answer["rec-answer"]["data"]
    assert answer["n"] == n and answer["text"] == panels.limits_text(record, rec.problem.units) == text
    again = _post(client, keys, values, "url.search", first["front-shown"]["data"])
    card = json.dumps(again["recommendation"]["children"], ensure_ascii=False)
    assert answer["text"] in card and panels.LIMITS_PENDING not in card
    assert again["rec-pending"]["data"] is None  # an answer still on its way for the card before is not shown


def test_a_failed_limits_computation_does_not_leave_the_card_computing(tmp_path, monkeypatch, caplog):
    """When computing the limits fails for a reason the model does not give (an internal error, here a
    RuntimeError), the card's answer says they were not computed and where to find them, not "computing…" for
    ever, and the console gets one line naming the error (with its traceback only under --debug)."""
    from designer.studio import panels
    from test_studio_updates import _post

    data, name = state.read_problem_data(PROBLEM)
    client = create_app(data, name, tmp_path).server.test_client()
    keys = [c.key for c in state.all_controls()]
    first = _post(client, keys, state.control_values(data), "url.search", None)
    n = first["rec-pending"]["data"]

    def broken(*args, **kwargs):
        raise RuntimeError("quadrature did not converge\nsecond line")

    monkeypatch.setattr(view, "compute_spec", broken)
    answer = _callback(client, [("rec-answer", "data")], [("rec-go", "data", n)], "rec-go.data", [])
    assert answer["rec-answer"]["data"] == {"n": n, "text": panels.LIMITS_FAILED}
    assert panels.LIMITS_PENDING not in panels.LIMITS_FAILED
    assert _studio_lines(caplog) == ["acceptance limits: RuntimeError: quadrature did not converge"]
    assert [r.exc_info for r in caplog.records if r.name == "designer.studio"] == [None]  # no traceback ...
    caplog.clear()
    monkeypatch.undo()
    client = create_app(data, name, tmp_path, debug=True).server.test_client()
    n = _post(client, keys, state.control_values(data), "url.search", None)["rec-pending"]["data"]
    monkeypatch.setattr(view, "compute_spec", broken)
    _callback(client, [("rec-answer", "data")], [("rec-go", "data", n)], "rec-go.data", [])
    (record,) = [r for r in caplog.records if r.name == "designer.studio"]
    assert record.exc_info is not None and record.exc_info[0] is RuntimeError  # ... but with --debug


def _guarded_client(tmp_path, debug=False):
    """The app as `designer studio` serves it on 127.0.0.1:8050 (server.guard applied), as a test client."""
    from designer.studio.server import allowed_hosts, guard

    data, name = state.read_problem_data(PROBLEM)
    app = create_app(data, name, tmp_path)
    guard(app.server, allowed_hosts("127.0.0.1", 8050), debug=debug)
    return app.server.test_client()


def _studio_lines(caplog) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == "designer.studio"]


@pytest.mark.parametrize("host", ["attacker.example", "attacker.example:8050", "127.0.0.1:9999", "localhost.evil"])
def test_foreign_host_is_forbidden(tmp_path, caplog, host):
    """Issue 24.7: a request with `Host: attacker.example` was answered 200, so a DNS-rebinding page could
    drive the callbacks ("Write report" included). Only the loopback names and the --host given, with or
    without the studio's port, are answered; any other Host gets 403 (one log line), the page included."""
    client = _guarded_client(tmp_path)
    assert client.get("/", headers={"Host": host}).status_code == 403
    assert client.post("/_dash-update-component", json={}, headers={"Host": host}).status_code == 403
    for good in ("localhost", "127.0.0.1:8050", "[::1]:8050", "LOCALHOST:8050"):
        assert client.get("/", headers={"Host": good}).status_code == 200
    assert client.get("/", headers={"Origin": "http://attacker.example"}).status_code == 403
    lines = _studio_lines(caplog)
    assert len(lines) == 3 and all("403" in line for line in lines)


def test_oversized_body_is_one_line(tmp_path, caplog):
    """Issue 24.7: a 30 MB request body was printed twice on the console (60 MB of stderr). A body above
    MAX_REQUEST_BYTES is refused with 413 and one short log line that does not echo the body."""
    from designer.studio.server import MAX_REQUEST_BYTES

    client = _guarded_client(tmp_path)
    body = json.dumps({"output": "x" * (MAX_REQUEST_BYTES + 10)})
    response = client.post("/_dash-update-component", data=body, content_type="application/json")
    assert response.status_code == 413
    lines = _studio_lines(caplog)
    assert len(lines) == 1 and "413" in lines[0] and len(lines[0]) < 300 and "xxxx" not in lines[0]


WRONG_CALLBACK = json.dumps(
    {"output": "nope.children", "outputs": {"id": "nope", "property": "children"}, "inputs": [], "changedPropIds": []}
).encode()
"""A callback that does not exist."""

MISSING_INPUTS = json.dumps(
    {
        "output": "card.children",
        "outputs": {"id": "card", "property": "children"},
        "inputs": [{"id": "front", "property": "clickData", "value": None}],
        "changedPropIds": ["rec-card.n_clicks"],
        "state": [],
    }
).encode()
"""The card's callback with one of its three inputs."""


@pytest.mark.parametrize(
    "body",
    [b"[]", b"[1,2,3]", b"null", b'{"output": 1}', b'{"output": "x.y"}', b'{"output":"front.figure","inputs":5}']
    + [b"{", b"", WRONG_CALLBACK, MISSING_INPUTS],
)
def test_malformed_callback_is_a_4xx_in_one_line(tmp_path, caplog, body):
    """Issue 42: a POST of the wrong shape ([1,2,3], a callback that does not exist, too few inputs) was a 500
    whose console line named the exception.  Each is a 400 whose body is a fixed sentence (nothing of the
    exception), logged as exactly one line without a traceback; a failure inside the studio's own callback
    stays a 500 (the next test)."""
    client = _guarded_client(tmp_path)
    response = client.post("/_dash-update-component", data=body, content_type="application/json")
    assert response.status_code == 400
    assert response.data.decode() in ("a malformed callback request (not one this studio's page sends)", "") or (
        b"Bad Request" in response.data
    )
    assert not any(word in response.data for word in (b"Error", b"Traceback", b"nope", b"index"))
    records = [r for r in caplog.records if r.name == "designer.studio"]
    assert len(records) == 1 and "\n" not in records[0].getMessage() and records[0].exc_info is None
    assert not [r for r in caplog.records if r.exc_info and r.name != "designer.studio"]


@pytest.mark.parametrize("path", ["/_dash-component-suites/dash/nope.js", "/_dash-component-suites/nope/nope.js"])
def test_an_unknown_component_file_is_a_404(tmp_path, caplog, path):
    """Issue 42: a GET of a component file Dash does not have was a 500 naming Dash's DependencyException; it
    is a 404 saying "no such file", one line on the console."""
    response = _guarded_client(tmp_path).get(path)
    assert (response.status_code, response.data) == (404, b"no such file")
    assert len(_studio_lines(caplog)) == 1


def test_a_failure_in_the_studios_own_code_stays_an_internal_error(tmp_path, caplog, monkeypatch):
    """The 4xx rule is not a blanket: a callback that fails inside the studio's code (here the card, made to
    raise) is a 500 with one console line, and the traceback with `designer --debug studio`: a planted fault is
    not passed off as the user's malformed request."""

    def broken(*args, **kwargs):
        raise RuntimeError("planted")

    import designer.studio.app as app_module

    monkeypatch.setattr(app_module, "card_panel", broken)
    data, _ = state.read_problem_data(PROBLEM)
    _, merged = state.build_problem(data, state.control_values(data))
    body = {
        "output": "card.children",
        "outputs": {"id": "card", "property": "children"},
        "inputs": [
            {"id": "front", "property": "clickData", "value": None},
            {"id": "rec-card", "property": "n_clicks", "value": 1},
            [],
        ],
        "changedPropIds": ["rec-card.n_clicks"],
        "state": [
            {"id": "problem-data", "property": "data", "value": merged},
            {"id": "mine-store", "property": "data", "value": None},
        ],
    }
    for debug in (False, True):
        caplog.clear()
        response = _guarded_client(tmp_path, debug=debug).post("/_dash-update-component", json=body)
        assert response.status_code == 500 and b"planted" not in response.data
        (record,) = [r for r in caplog.records if r.name == "designer.studio"]
        assert "RuntimeError: planted" in record.getMessage() and (record.exc_info is not None) == debug


def test_every_answer_carries_the_security_headers(tmp_path):
    """Issue 42: no answer said nosniff or refused framing, so another site could frame the studio and steer a
    click on "Save problem".  Every answer, the page, its layout, a callback, a 403, a 404, a 400 and a 413,
    carries X-Content-Type-Options: nosniff, X-Frame-Options: DENY and a CSP with frame-ancestors 'none'."""
    from designer.studio.server import MAX_REQUEST_BYTES

    client = _guarded_client(tmp_path)
    answers = [
        client.get("/"),
        client.get("/_dash-layout"),
        client.get("/", headers={"Host": "attacker.example"}),
        client.get("/_dash-component-suites/dash/nope.js"),
        client.post("/_dash-update-component", data=b"[1,2,3]", content_type="application/json"),
        client.post(
            "/_dash-update-component",
            data=json.dumps({"x": "x" * MAX_REQUEST_BYTES}),
            content_type="application/json",
        ),
        client.post("/_dash-update-component", data=WRONG_CALLBACK, content_type="application/json"),
    ]
    assert [a.status_code for a in answers] == [200, 200, 403, 404, 400, 413, 400]
    for answer in answers:
        assert answer.headers["X-Content-Type-Options"] == "nosniff"
        assert answer.headers["X-Frame-Options"] == "DENY"
        assert "frame-ancestors 'none'" in answer.headers["Content-Security-Policy"]


def test_make_server_applies_the_guard(tmp_path, monkeypatch):
    """The served app (make_server on a free port) answers a foreign Host with 403 and its own address with 200."""
    import http.client
    import threading

    from designer.solvers.nlp import SHARED, CasterNLP
    from designer.studio.server import make_server

    monkeypatch.setattr(CasterNLP, "EXPAND", CasterNLP.EXPAND)  # make_server expands this process's batches
    server, url = make_server(PROBLEM, 0, "127.0.0.1", tmp_path)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        statuses = []
        for host in ("attacker.example", f"127.0.0.1:{server.server_port}"):
            connection = http.client.HTTPConnection("127.0.0.1", server.server_port, timeout=60)
            connection.request("GET", "/", headers={"Host": host})
            statuses.append(connection.getresponse().status)
            connection.close()
    finally:
        server.shutdown()
        server.server_close()
        SHARED.clear()  # its expanded solvers: the tests after it build their own
    assert statuses == [403, 200]


def test_front_convention_is_the_reports():
    """Issue 28.6: one front convention everywhere.  The studio's chart, the report's Figure 1 and
    ``Front.plot()`` all draw the threshold (sill) force P across and the turning effort F_turn up: every
    studio trace's x is its points' P and y their F_turn, and the axis titles say so."""
    import matplotlib

    matplotlib.use("Agg")
    from designer.plots.figures import figure_front
    from designer.plots.fronts import draw_fronts
    from designer.studio.figures import front_figure

    points = [
        {"design": Design("2 in", "7 in", 0, 1.3).to_dict(), "turning_effort": 9.0, "threshold_force": 107.0},
        {"design": Design("2.5 in", "5 in", 0, 1.3).to_dict(), "turning_effort": 7.0, "threshold_force": 133.5},
    ]
    rec = {**points[0], "critical_speed": 3.3}
    fig = front_figure(points, points, points, rec)
    labels = (display.axis("threshold_force"), display.axis("turning_effort"))  # the table's: one name per quantity
    assert (fig["layout"]["xaxis"]["title"]["text"], fig["layout"]["yaxis"]["title"]["text"]) == labels
    for trace in fig["data"]:
        assert trace["x"] == [p["threshold_force"] for p in (points if len(trace["x"]) == 2 else [rec])]
        assert trace["y"] == [p["turning_effort"] for p in (points if len(trace["y"]) == 2 else [rec])]
        assert "P %{x:.2f} N<br>F_turn %{y:.3f} N" in trace["hovertemplate"]
    from matplotlib.figure import Figure

    ax = draw_fronts(Figure().add_subplot(), [{"threshold_force": [107.0], "turning_effort": [9.0], "label": "x"}], [])
    assert (ax.get_xlabel(), ax.get_ylabel()) == labels
    report = figure_front(
        {"turning_effort": [9.0, 7.0], "threshold_force": [107.0, 133.5], "family": ["bare fork"] * 2}, "t"
    )
    (axes, *_) = report.axes
    assert (axes.xlabel, axes.ylabel) == labels
    assert min(axes.data_x) == 107.0 and max(axes.data_y) == 9.0


def _controls_in_page_order(component, where="open", out=None) -> list:
    """(control key, where it sits) of every control of the layout in page order: "first" in the top row,
    "folded" inside a closed <details>, else "open"."""
    from dash import html

    out = [] if out is None else out
    cid = getattr(component, "id", None)
    if cid == "first-controls":
        where = "first"
    elif isinstance(component, html.Details) and not component.open:
        where = "folded"
    if isinstance(cid, dict) and cid.get("type") == "ctl":
        out.append((cid["key"], where))
    children = getattr(component, "children", None)
    for child in children if isinstance(children, (list, tuple)) else [children]:
        if hasattr(child, "to_plotly_json"):  # a component, not text
            _controls_in_page_order(child, where, out)
    return out


def test_first_controls_on_top_the_rest_folded_in_callback_order():
    """Load, sill, surface, target speed and α sit in the top row; every other control is folded; the page
    order is the order the callbacks read the controls in (state.all_controls: a control out of place would
    receive another's value)."""
    from designer.studio.layout import FIRST, build_layout

    data, _ = state.read_problem_data(state.default_problem_path())
    placed = _controls_in_page_order(build_layout("t", state.control_values(data)))
    assert [k for k, _ in placed] == [c.key for c in state.all_controls()]
    assert [k for k, where in placed if where == "first"] == list(FIRST)
    assert {where for k, where in placed if k not in FIRST} == {"folded"}


def test_a_card_opened_again_is_not_computed_again(tmp_path, monkeypatch):
    """Opening the card of the caster to build twice computes it once (its sweeps, θ(t) and knock-safe speeds
    are kept by the problem and the record): the second answer is the first, and view.card ran once."""
    calls = []
    card = view.card

    def counted(*args, **kwargs):
        calls.append(args[1])
        return card(*args, **kwargs)

    monkeypatch.setattr(view, "card", counted)
    data, name = state.read_problem_data(PROBLEM)
    _, merged = state.build_problem(data, state.control_values(data))
    client = create_app(data, name, tmp_path).server.test_client()
    replies = [
        _callback(
            client,
            [("card", "children")],
            [("front", "clickData", None), ("rec-card", "n_clicks", n), []],
            "rec-card.n_clicks",
            [("problem-data", "data", merged), ("mine-store", "data", None)],
        )
        for n in (1, 2)
    ]
    assert len(calls) == 1 and replies[0] == replies[1]


def test_every_listed_quantity_of_the_table_is_on_the_card_and_in_the_report():
    """Issue 41: a quantity declared once in parameters.OUTPUT_TABLE (and computed by the evaluator) reaches the
    studio's card and the report's caster table with no other edit: the shimmy frequency in hertz of Eq. 15B,
    planted that way, is on the card of the caster to build with its label and its value at the table's precision,
    as are θ_a and ω; the report's numbers of that caster list the same quantities with the same text."""
    from designer.parameters import OUTPUT_TABLE
    from designer.report.context import caster_panel

    problem, fronts = _default_fronts()
    record = view.card_record(fronts, "recommendation")
    n = view.card(problem, record, with_simulation=False)["numbers"]
    listed = [p.name for p in OUTPUT_TABLE if p.listed and record.caster.get(p.name) is not None]
    assert {"shimmy_frequency_hz", "shimmy_amplitude", "shimmy_frequency"} <= set(listed)
    table = json.dumps(
        numbers_table(n, problem, "card").to_plotly_json(), default=lambda o: o.to_plotly_json(), ensure_ascii=False
    )
    report = caster_panel(record.caster, problem.units).table.rows
    for name in set(listed) - {"inertia", "critical_speed", "turning_effort", "threshold_force", "swept_radius"}:
        text = display.shown(record.caster[name], name, problem.units)
        assert f'"{display.label(name)}"' in table and f'"{text}"' in table, name
        assert [display.label(name), text] in report, name
    hz = record.caster["shimmy_frequency_hz"]
    assert hz == pytest.approx(record.caster["shimmy_frequency"] / (2 * np.pi), rel=1e-12) and 5 < hz < 50
