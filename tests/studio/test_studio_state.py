"""The studio's state without a browser: controls -> problem loader, URL, TOML round trip, port in use."""

from __future__ import annotations

import json
import socket
import tomllib

import pytest

from designer.cli import main
from designer.problem import load_problem, problem_from_dict
from designer.physics.uncertainty import Uncertainty
from designer.studio import state

PROBLEM = state.default_problem_path()


@pytest.fixture(scope="module")
def base():
    data, name = state.read_problem_data(PROBLEM)
    return data, state.control_values(data)


def test_controls_show_the_problem_file(base):
    """Every control starts at the problem file's value: 178 N, 0.5 in, 2.5 m/s, the bounds as written."""
    _, values = base
    assert values["load"] == "178 N" and values["sill"] == "0.5 in"
    assert values["target"] == pytest.approx(2.5)
    assert values["trail_min"] == "1 in" and values["trail_max"] == "2.5 in"
    assert values["swept"] == "6 in"
    assert values["alpha"] == pytest.approx(0.05)


def test_unchanged_controls_give_the_files_problem(base):
    """Controls at their defaults give the problem `designer run` reads from the file, its risk law included
    (σ of the model error shown as 0.1075 stays 0.10751150496617…: a box left as shown writes nothing)."""
    data, values = base
    problem, merged = state.build_problem(data, values)
    direct = load_problem(PROBLEM)
    assert problem.to_dict() == direct.to_dict()
    assert merged == data


def test_numbers_shown_at_four_significant_digits(base):
    """The σ boxes show four significant digits (the model error's σ, 0.10751150496617…, as 0.1075); a number
    typed in is taken as typed."""
    data, values = base
    exact = Uncertainty().model_error
    assert values["s_model"] == 0.1075 != exact
    assert all(len(f"{values[k]:g}".lstrip("0.").replace(".", "")) <= 4 for k in ("alpha", "s_model", "s_damping"))
    problem, _ = state.build_problem(data, {**values, "s_model": 0.1})
    assert problem.conditions.uncertainty.model_error == 0.1


def test_min_above_max_names_the_control_with_the_loaders_message(base):
    """trail min 3 in > max 2.5 in: the loader's one line, blamed on the trail-min control."""
    data, values = base
    with pytest.raises(state.ControlError) as info:
        state.build_problem(data, {**values, "trail_min": "3 in"})
    assert info.value.key == "trail_min"
    assert "min is greater than max" in str(info.value) and "\n" not in str(info.value)


def test_unparsable_unit_names_the_control(base):
    """A load of '178 parsecs' is the units parser's message (as the CLI prints it), beside the load box."""
    data, values = base
    with pytest.raises(state.ControlError) as info:
        state.build_problem(data, {**values, "load": "178 parsecs"})
    assert info.value.key == "load"
    assert "conditions.load" in str(info.value)


def test_url_round_trip(base):
    """The URL holds only the changed controls, and reading it back gives the same controls."""
    _, values = base
    changed = {**values, "target": 3.1, "trail_max": "2.25 in", "surface": "carpet"}
    query = state.to_query(changed, values)
    assert query.startswith("?") and "target=3.1" in query and "load" not in query
    assert state.from_query(query, values) == changed
    assert state.to_query(values, values) == ""


def test_saved_toml_runs_to_the_same_results(base, tmp_path, capsys):
    """'Save problem' TOML: `designer run` reads it to the same problem and the same optimum as the studio's."""
    from designer.studies.optimum import optimise

    data, values = base
    changed = {**values, "target": 2.8, "trail_max": "2.25 in", "alpha": 0.1, "s_slip": 0.25, "swept": "5.5 in"}
    problem, merged = state.build_problem(data, changed)
    text = state.to_toml(merged)
    assert tomllib.loads(text) == merged
    path = tmp_path / "saved.toml"
    path.write_text(text, encoding="utf-8")
    loaded = load_problem(path)
    a, b = loaded.to_dict(), problem.to_dict()
    assert a == b
    assert main(["run", str(path), "--json", "--no-cross-check"]) == 0
    ran = json.loads(capsys.readouterr().out)
    direct = optimise(problem_from_dict(merged), cross_check=False).to_dict()
    for key in ("trail", "diameter", "groove", "damping"):
        assert ran["design"][key] == pytest.approx(direct["design"][key], rel=1e-9)


def test_port_in_use_is_one_line_and_exit_8(capsys):
    """A taken port: one line on stderr naming --port, exit code 8 (README table), no traceback."""
    pytest.importorskip("dash")
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        code = main(["studio", str(PROBLEM), "--port", str(port), "--no-browser"])
    err = capsys.readouterr().err.strip()
    assert code == 8
    assert err.count("\n") == 0 and f"--port {port}" in err and "in use" in err


def test_two_bad_boxes_each_keep_their_message(base):
    """min > max on trail and a load in parsecs: each control gets its own line (the loader stops at one)."""
    data, values = base
    errors = state.control_errors(data, {**values, "trail_min": "3 in", "load": "178 parsecs"}, values)
    assert set(errors) == {"trail_min", "load"}
    assert "min is greater than max" in errors["trail_min"] and "conditions.load" in errors["load"]
