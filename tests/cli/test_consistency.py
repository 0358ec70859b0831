"""Issue 28.4: the commands agree with each other (version, PROBLEM by name, --target-speed, the words of the help
texts, the inertia unit, the default point counts, what evaluate used)."""

from __future__ import annotations

import argparse
import json

import pytest

import designer
from designer.cli import build_parser, main
from designer.problem import example_problem, load_problem


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def test_version(capsys):
    """``designer --version`` prints the package's version on one line and exits 0."""
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"designer {designer.__version__} (Python 3.") and out.count("\n") == 1


def test_shipped_problem_by_name_from_any_folder(tmp_path, monkeypatch, capsys):
    """From a folder without problems/, ``designer run indoor-manual`` reads the shipped problem: the same
    recommendation as the repository's file; a file of that name in the folder wins, and an unknown name lists
    the shipped ones (exit 3)."""
    from designer.studies.recommend import recommend

    from conftest import ROOT

    expected = recommend(load_problem(ROOT / "problems" / "indoor-manual.toml")).design.to_dict()
    monkeypatch.chdir(tmp_path)
    assert load_problem("indoor-manual").to_dict() == example_problem("indoor-manual").to_dict()
    assert load_problem("indoor-manual.toml").name == "indoor-manual"
    assert main(["run", "indoor-manual", "--no-cross-check", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["recommendation"]["design"] == pytest.approx(expected, rel=1e-12)
    (tmp_path / "indoor-manual").write_text('name = "mine"\n[shimmy]\ntarget_speed = "2 m/s"\n')
    assert load_problem("indoor-manual").name == "mine"
    assert main(["run", "no-such-problem"]) == 3
    err = capsys.readouterr().err
    assert "no-such-problem: no such problem file, nor a shipped problem of that name (" in err
    assert "indoor-manual" in err and err.count("\n") == 1


def test_every_problem_argument_takes_a_shipped_name():
    """Every verb with a PROBLEM argument says it takes a shipped problem's name too."""
    verbs = {}
    for name, sub in _subparsers().items():
        for action in sub._actions:
            if action.dest == "problem" and not action.option_strings:
                verbs[name] = action.help
    assert set(verbs) >= {"run", "pareto", "explore", "robust", "fix", "studio"}
    assert all("the name of a shipped problem" in text for text in verbs.values()), verbs


@pytest.mark.parametrize("verb", ["run", "pareto", "fix"])
def test_target_speed_on_run_pareto_and_fix(verb, capsys):
    """``--target-speed`` is an option of run, pareto and fix alike, checked against the parameter table's range
    before the problem file is read (exit 2 naming the option, not the missing file)."""
    extra = ["--current", "T=2in,d=7in,B=0,c=1.3"] if verb == "fix" else []
    assert main([verb, "no-such-file.toml", "--target-speed", "500 m/s", *extra]) == 2
    err = capsys.readouterr().err
    assert err.startswith("designer: error: --target-speed = '500 m/s': outside") and "no-such-file" not in err


def test_target_speed_moves_the_fix(capsys):
    """``fix --target-speed`` replaces the problem's V_target: the diagnosis is at the speed given."""
    args = ["fix", "indoor-manual", "--current", "T=2.5in,d=7in,B=0.5in,c=1.3", "--top", "1", "--json"]
    assert main(args + ["--target-speed", "1.5 m/s"]) == 0
    assert json.loads(capsys.readouterr().out)["target_speed"] == pytest.approx(1.5)


def test_help_says_risk_bounded_where_the_result_is():
    """pareto and explore solve under the problem's risk bound: their help says so and no longer says
    "V_c >= V_req (Eq. 7)" alone."""
    subs = _subparsers()
    for verb in ("pareto", "explore"):
        text = subs[verb].format_help()
        assert "risk-bounded" in text and "V_req" not in text, verb


def test_inertia_unit_written_one_way():
    """Every help text writes the inertia unit kg·m² (none kg*m**2)."""
    for name, sub in _subparsers().items():
        text = sub.format_help()
        assert "kg*m**2" not in text, name
    for verb in ("evaluate", "fix", "simulate"):
        assert "[kg·m²]" in _subparsers()[verb].format_help().replace("\n", " ").replace("  ", " "), verb


def test_point_counts_state_why_robust_differs():
    """pareto's default is the problem's [pareto] points (41); robust's 21 comes with its reason in the help."""
    from designer.studies.robust import ROBUST_POINTS

    assert example_problem("indoor-manual").pareto_points == 41 and ROBUST_POINTS == 21
    text = " ".join(_subparsers()["robust"].format_help().split())
    assert "default 21, not pareto's 41: it solves two fronts and runs two Monte Carlo checks per point" in text


def test_evaluate_shows_the_load_and_sill_it_used(capsys, monkeypatch):
    """evaluate's table starts with the load and the sill, saying whether they were given or the defaults; its
    JSON has both [SI] (at 200 columns: no cell folded)."""
    monkeypatch.setenv("COLUMNS", "200")
    base = ["evaluate", "--trail", "2in", "--diameter", "7in", "--groove", "0", "--damping", "1.3"]
    assert main(base + ["--threshold-height", "13 mm"]) == 0
    text = capsys.readouterr().out
    assert "178.0 N  default" in text
    assert "0.512 in  --threshold-height" in text
    assert main(base + ["--threshold-height", "13 mm", "--verbose"]) == 0
    assert "default: the paper's test load" in capsys.readouterr().out
    assert main(base + ["--load", "215.7 N", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["load"] == 215.7 and data["threshold_height"] == pytest.approx(0.0127)


def test_run_says_the_load_it_used_from_a_mass(tmp_path, capsys):
    """A problem file with mass = "110 kg" and front_fraction = 0.4: `designer run` names the load it computed
    for (L = m g f / 2 = 215.7463 N per front caster, by hand), the sill, floor and turning mode on its first
    line, and --json has them under "conditions"."""
    from conftest import ROOT

    text = (ROOT / "problems" / "indoor-manual.toml").read_text()
    lines = [ln for ln in text.splitlines() if not ln.startswith("load =")]
    at = lines.index("[conditions]") + 1
    path = tmp_path / "mass.toml"
    path.write_text("\n".join(lines[:at] + ['mass = "110 kg"', "front_fraction = 0.4"] + lines[at:]) + "\n")
    assert main(["run", str(path), "--no-cross-check"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "For 215.7 N per front caster, a 1/2 in sill, tile floor, chair turning:"
    assert main(["run", str(path), "--no-cross-check", "--json"]) == 0
    conditions = json.loads(capsys.readouterr().out)["conditions"]
    assert conditions["load_N"] == pytest.approx(110 * 9.80665 * 0.4 / 2, rel=1e-12)
    assert conditions["threshold_height_m"] == pytest.approx(0.0127)


def test_run_fits_the_terminal(monkeypatch, capsys):
    """`designer run` wraps its prose to the terminal's width (COLUMNS=80: no line wider than 80 characters,
    the risk's source and the measured wheel's sentence included), its answer in one screen; --verbose keeps the
    aligned rows of the caster in full whole."""
    monkeypatch.setenv("COLUMNS", "80")
    assert main(["run", "indoor-manual", "--no-cross-check"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert max(len(ln) for ln in lines) <= 80 and len(lines) <= 24
    assert "  T 2.500 in, d 7.000 in, B 0.750 in, c_f 1.30 N·m/rad" in lines
    text = " ".join(" ".join(lines).split())
    assert "Most of the risk (69.6 %) comes from the wheel's inertia" in text
    assert main(["run", "indoor-manual", "--no-cross-check", "--verbose"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert max(len(ln) for ln in lines) <= 80
    assert any(ln.startswith("  trail T ") and ln.rstrip().endswith("mm") for ln in lines)
    assert any("dominates the risk" in ln for ln in lines)
