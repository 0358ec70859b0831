"""The command line: evaluate, validate, run; one-line errors with the documented exit codes."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from designer.cli import main

from conftest import ROOT

EVAL = ["evaluate", "--trail", "2in", "--diameter", "7.75in", "--groove", "0.5625in", "--damping", "1.3"]


def test_evaluate_json_eq8(capsys):
    """evaluate --json at the Eq. 8 point with I_w = 0.00127 gives V_c = 2.91 m/s and every documented key
    (B = 9/16 in = 0.0142875 m here against the paper's rounded 0.0143 m: 2.9098 instead of 2.9113)."""
    assert main(EVAL + ["--inertia", "0.00127", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["critical_speed"] == pytest.approx(2.9098, abs=1e-4)
    for key in (
        "critical_speed",
        "inertia",
        "threshold_force_ratio",
        "threshold_force",
        "turning_moment",
        "turning_effort",
        "swept_radius",
        "shimmy_frequency",
    ):
        assert key in out
    assert out["turning_effort"] == pytest.approx(9.636, abs=1e-3)


def test_evaluate_table(capsys):
    """Without --json a readable table in SI and inches, with the stability verdict at a target speed."""
    assert main(EVAL + ["--target-speed", "3 m/s"]) == 0
    text = capsys.readouterr().out
    assert "critical shimmy speed" in text and "SHIMMIES" in text and "in)" in text


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["--trail", "=-2in"], "--trail -0.0508: must be positive"),
        (["--trail", "0"], "--trail 0: must be positive"),
        (["--diameter", "0.9in"], "--diameter 0.9in: must exceed twice the threshold height"),
        (["--surface", "grass"], "--surface 'grass': expected one of tile, carpet"),
        (["--trail", "2kg"], "--trail = '2 kg': wrong dimension"),
        (["--damping", "abc"], "--damping"),
        (["--turning-mode", "drift"], "--turning-mode 'drift'"),
    ],
)
def test_evaluate_bad_input(args, fragment, capsys):
    """Bad input exits 2 with one line naming the option, the value and the reason; no traceback."""
    argv = list(EVAL)
    for i in range(0, len(args), 2):
        if args[i + 1].startswith("="):  # a negative value must be attached: --trail=-2in
            j = argv.index(args[i])
            argv[j : j + 2] = [args[i] + args[i + 1]]
        elif args[i] in argv:
            argv[argv.index(args[i]) + 1] = args[i + 1]
        else:
            argv += args[i : i + 2]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert fragment in err
    assert len(err.splitlines()) == 1 and "Traceback" not in err


def test_validate_passes(capsys):
    """designer validate: all paper checks pass, exit 0, table lists every check."""
    assert main(["validate"]) == 0
    out = capsys.readouterr().out
    for name in ("1 Eq. 8", "2 Table 1", "7 P/L vs d", "9 Routh", "10 Quadra"):
        assert name in out
    assert "0 failed" in out


def test_validate_fails_loudly(monkeypatch, capsys):
    """A failing check makes validate exit 1 and print which check failed and by how much."""
    import designer.analysis.checks as checks

    bad = checks.Check("x broken", "claim", 1.0, 2.0, False, "")
    monkeypatch.setattr("designer.commands.validate.paper_checks", lambda: [bad])
    assert main(["validate"]) == 1
    assert "FAILED x broken: expected 1.0, got 2.0" in capsys.readouterr().out


def test_run_json_keys(capsys):
    """designer run --json gives design, objectives, critical_speed, constraints, sensitivities, cross_check, status."""
    path = str(ROOT / "problems" / "paper-invacare.toml")
    assert main(["run", path, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("design", "objectives", "critical_speed", "constraints", "sensitivities", "cross_check", "status"):
        assert key in out
    assert set(out["design"]) == {"trail", "diameter", "groove", "damping"}
    assert out["critical_speed"] >= 2.5 - 1e-8
    assert out["objectives"]["weighted"] == pytest.approx(out["cross_check"]["scipy-slsqp"], rel=1e-4)


def test_run_weights_option(capsys):
    """--weights 1,0 minimises turning effort alone (paper-invacare, risk-bounded by default: 2.5 in trail,
    0.491 in groove; the nominal Eq. 7 needs 0.222 in)."""
    path = str(ROOT / "problems" / "paper-invacare.toml")
    assert main(["run", path, "--weights", "1,0", "--json", "--no-cross-check"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["design"]["trail"] == pytest.approx(0.0635, rel=1e-6)
    assert out["design"]["groove"] / 0.0254 == pytest.approx(0.4915, abs=1e-3)


@pytest.mark.parametrize("weights", ["1", "a,b", "-1,1", "0,0"])
def test_run_bad_weights(weights, capsys):
    """Malformed --weights exit 2 with a one-line error."""
    path = str(ROOT / "problems" / "paper-invacare.toml")
    assert main(["run", path, f"--weights={weights}"]) == 2
    assert "--weights" in capsys.readouterr().err


def test_run_infeasible_exit_code(capsys):
    """A 40 m/s target: exit 4 with the highest reachable V_c in one line."""
    path = str(ROOT / "problems" / "indoor-manual.toml")
    assert main(["run", path, "--target-speed", "40 m/s"]) == 4
    lines = capsys.readouterr().err.strip().splitlines()
    errors = [line for line in lines if line.startswith("designer: error:")]
    assert len(errors) == 1 and "out of reach" in errors[0] and "highest critical speed" in errors[0]
    assert all(line.startswith("designer: warning:") for line in lines if line not in errors)


def test_run_missing_problem(capsys):
    """A missing problem file: exit 3, one line."""
    assert main(["run", "nope.toml"]) == 3
    assert "no such problem file" in capsys.readouterr().err


def test_console_script_runs():
    """The installed console script answers --help (the entry point is wired)."""
    result = subprocess.run([sys.executable, "-m", "designer.cli", "--help"], capture_output=True, text=True)
    assert result.returncode == 0 and "evaluate" in result.stdout
