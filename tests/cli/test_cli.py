"""The command line: evaluate, validate, run; one-line errors with the documented exit codes."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys

import pytest

from designer.cli import main
from designer.output import MANIFEST, manifest_text

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
    """Without --json a readable table in SI and inches, with the stability verdict at a target speed (one
    screen), and the same in full with each quantity's source under --verbose."""
    assert main(EVAL + ["--target-speed", "3 m/s"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "critical shimmy speed V_c" in text and "At 3.000 m/s: Eq. 7 alone says it shimmies" in text
    assert "door-sill height h 0.500 in" in text
    assert main(EVAL + ["--target-speed", "3 m/s", "--verbose"]) == 0
    text = capsys.readouterr().out
    assert "critical shimmy" in text and "SHIMMIES" in text and "docs/model.md#turning-effort," in text


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["--trail", "=-2in"], "--trail = '-2in' (-0.0508 m): outside the model's range"),
        (["--trail", "0"], "--trail = 0 m: outside the model's range 0.001 to 0.25 m"),
        (["--diameter", "0.9in"], "--diameter 0.9in: must exceed twice the threshold height"),
        (["--surface", "grass"], "--surface = 'grass': expected one of tile, carpet"),
        (["--trail", "2kg"], "--trail = '2 kg': wrong dimension"),
        (["--damping", "abc"], "--damping"),
        (["--turning-mode", "drift"], "--turning-mode = 'drift'"),
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
    """designer validate: all paper checks pass, exit 0; the list numbers every check 1..n with its result in
    words, counted as pareto counts ("checks n/n pass"); --verbose: the tables with the checks' own names."""
    from designer.studies.checks import law_checks, paper_checks

    assert main(["validate"]) == 0
    lines = capsys.readouterr().out.splitlines()
    n = len(paper_checks()) + len(law_checks())
    assert lines[0] == f"The paper's checks (docs/checks.md): checks {n}/{n} pass."
    numbered = [ln for ln in lines if ln[:2].strip().isdigit() and ln[2:4] == ". "]
    assert [int(ln[:2]) for ln in numbered] == list(range(1, n + 1))
    assert " 1. Eq. 8: agrees" in lines and " 2. Table 1: agrees within the paper's scatter" in lines
    assert not any("disagree" in ln.lower() for ln in lines)
    assert main(["validate", "--verbose"]) == 0
    out = capsys.readouterr().out
    for name in ("1 Eq. 8", "2 Table 1", "7 P/L vs d", "9 Routh", "10 Quadra"):
        assert name in out
    assert f"checks {n}/{n} pass" in out


def test_validate_fails_loudly(monkeypatch, capsys):
    """A failing check makes validate exit 1 and print which check failed and by how much."""
    import designer.studies.checks as checks

    bad = checks.Check(name="x broken", claim="claim", expected=1.0, got=2.0, passed=False, detail="")
    monkeypatch.setattr("designer.cli.validate.paper_checks", lambda: [bad])
    assert main(["validate"]) == 1
    out = capsys.readouterr().out
    assert "checks 1/2 pass; disagreeing: x broken" in out  # the law check still runs
    assert " 1. x broken: DISAGREES\n    expected 1.0; ours 2.0" in out
    assert main(["validate", "--verbose"]) == 1
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
    """--weights 1,0 minimises turning effort alone (paper-invacare, risk-bounded by default: 2.5 in trail, and the
    least groove whose speed reached with probability 95 % is 2.5 m/s, found here by bisection on the physics
    layer's bound for the measured 0.00127 kg·m² wheel at c_f = 1.3: 0.488 in; the nominal Eq. 7 needs 0.222 in)."""
    from scipy.optimize import brentq

    from designer.physics.uncertainty import Uncertainty, shimmy_speed_quantile

    path = str(ROOT / "problems" / "paper-invacare.toml")
    assert main(["run", path, "--weights", "1,0", "--json", "--no-cross-check"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["design"]["trail"] == pytest.approx(0.0635, rel=1e-6)
    groove = brentq(
        lambda b: float(shimmy_speed_quantile(0.0635, 0.00127, b, 1.3, 1250.0, Uncertainty())) - 2.5, 0.0, 0.02
    )
    assert groove / 0.0254 == pytest.approx(0.488, abs=1e-3)
    assert out["design"]["groove"] == pytest.approx(groove, rel=1e-6)


@pytest.mark.parametrize("weights", ["1", "a,b", "-1,1", "0,0"])
def test_run_bad_weights(weights, capsys):
    """Malformed --weights exit 2 with a one-line error."""
    path = str(ROOT / "problems" / "paper-invacare.toml")
    assert main(["run", path, f"--weights={weights}"]) == 2
    assert "--weights" in capsys.readouterr().err


def test_run_infeasible_exit_code(capsys):
    """A 40 m/s target: exit 4 with the highest reachable speed in one line, named for what it is: under the
    risk bound V_q, the speed held with probability 95 % (not Eq. 7's critical speed)."""
    path = str(ROOT / "problems" / "indoor-manual.toml")
    assert main(["run", path, "--target-speed", "40 m/s"]) == 4
    lines = capsys.readouterr().err.strip().splitlines()
    errors = [line for line in lines if line.startswith("designer: error:")]
    assert len(errors) == 1 and "out of reach" in errors[0]
    assert "the highest speed held with probability 95% (V_q of the risk bound) inside the bounds is" in errors[0]
    assert all(line.startswith("designer: warning:") for line in lines if line not in errors)


def test_run_missing_problem(capsys):
    """A missing problem file: exit 3, one line."""
    assert main(["run", "nope.toml"]) == 3
    assert "no such problem file" in capsys.readouterr().err


def test_console_script_runs():
    """The installed console script answers --help (the entry point is wired)."""
    result = subprocess.run([sys.executable, "-m", "designer.cli", "--help"], capture_output=True, text=True)
    assert result.returncode == 0 and "evaluate" in result.stdout


# ----------------------------------------------------------------------------------------------------
# Issue 12.1: crashes and exits a user could reach (check 8c out of reach, infeasible problem, Ctrl-C,
# unwritable output folder, unbounded --points).
import os
import shutil
import signal
import time
from pathlib import Path

import pytest


TIGHT = """name = "tight"
[conditions]
load = "178 N"
threshold_height = "0.5 in"
surface = "tile"
turning_mode = "chair"
[shimmy]
target_speed = "{speed}"
[variables]
trail = {{ min = "1 in", max = "2.5 in" }}
diameter = {{ min = "7 in", max = "8 in" }}
groove = "0 in"
damping = "1.3 N*m/rad"
[robust]
enabled = false
[pareto]
points = 5
"""
"""Nominal Eq. 7 constraint (no risk bound): d 7–8 in, no groove, no damper, trail <= 2.5 in: V_c reaches at most 2.384 m/s (T = 2.5 in, d = 7 in)."""


def _problem(tmp_path: Path, speed: str) -> Path:
    path = tmp_path / "tight.toml"
    path.write_text(TIGHT.format(speed=speed))
    return path


def test_front_checks_8c_not_applicable_when_tighter_front_empty(tmp_path):
    """An empty tighter front (V_target × 1.1 out of reach) gives check 8c 'not applicable' with the highest
    reachable V_c (2.384 m/s, Eq. 7 at T = 2.5 in, d = 7 in, B = 0, c_f = 1.3), not a reduction of an empty
    array (the old ValueError, exit 70)."""
    from designer.studies.checks import NOT_APPLICABLE, front_checks
    from designer.studies.front import pareto_front
    from designer.problem import load_problem

    problem = load_problem(_problem(tmp_path, "2.3 m/s"))
    front = pareto_front(problem, 5)
    tighter = pareto_front(problem.replace(target_speed=2.3 * 1.1), 5)
    assert front.points and not tighter.points
    c8c = next(c for c in front_checks(front, tighter) if c.name.startswith("8c"))
    assert c8c.outcome == NOT_APPLICABLE and c8c.passed
    assert c8c.got.startswith("not applicable: the tighter target is out of reach (highest V_c 2.38")


def test_pareto_cli_writes_report_when_tighter_target_out_of_reach(tmp_path, capsys):
    """`designer pareto` on the issue's problem (target 2.3 m/s, reachable; 2.53 m/s is not) exits 0 and
    writes the report with check 8c not applicable in checks.json and report.md."""
    out = tmp_path / "report"
    assert main(["pareto", str(_problem(tmp_path, "2.3 m/s")), "--out", str(out), "--points", "5"]) == 0
    checks = {c["name"]: c for c in json.loads((out / "checks.json").read_text())}
    assert checks["8c tighter target"]["outcome"] == "not applicable"
    assert "the tighter target is out of reach (highest V_c" in (out / "report.md").read_text()


def test_pareto_cli_infeasible_problem_exit_4(tmp_path, capsys):
    """A problem whose own target (3.5 m/s) is out of reach gives `designer run`'s exit 4 message, no report."""
    out = tmp_path / "report"
    assert main(["pareto", str(_problem(tmp_path, "3.5 m/s")), "--out", str(out)]) == 4
    err = capsys.readouterr().err
    assert "out of reach: the highest critical speed (Eq. 7) inside the bounds is 2.384 m/s" in err  # nominal
    assert not out.exists()


@pytest.mark.parametrize("points", ["2", "100000", "-3"])
def test_pareto_points_bounded_like_problem_file(points, tmp_path, capsys):
    """--points takes the problem file's range 3..2001 (100000 used to run 4 min and die of MemoryError)."""
    assert (
        main(
            ["pareto", str(ROOT / "problems" / "indoor-manual.toml"), "--out", str(tmp_path / "r"), "--points", points]
        )
        == 2
    )
    assert f"--points {points}: expected a whole number from 3 to 2001" in capsys.readouterr().err


def test_pareto_front_api_rejects_huge_point_count():
    """pareto_front(points=100000) is refused with InputError before any memory is allocated."""
    from designer.errors import InputError
    from designer.studies.front import pareto_front
    from designer.problem import load_problem

    with pytest.raises(InputError, match="front points from 2 to 2001"):
        pareto_front(load_problem(ROOT / "problems" / "indoor-manual.toml"), 100000)


def test_explore_trials_bounded(tmp_path, capsys):
    """explore --trials beyond 1 000 000 is an input error (exit 2), not an ever-growing in-memory study."""
    assert (
        main(["explore", str(ROOT / "problems" / "indoor-manual.toml"), "--trials", "10000000", "--out", str(tmp_path)])
        == 2
    )
    assert "--trials 10000000: expected a whole number from 1 to 1000000" in capsys.readouterr().err


def test_out_under_regular_file_exit_7(tmp_path, capsys):
    """--out under a regular file: one line, exit 7 (OutputError), before any computing."""
    (tmp_path / "afile").write_text("x")
    assert main(["pareto", str(ROOT / "problems" / "indoor-manual.toml"), "--out", str(tmp_path / "afile" / "r")]) == 7
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "lies under" in err and "a regular file, not a folder" in err


def _drop_root_write_override() -> list[str]:
    """Command prefix under which a 0o555 folder is read-only even for root (CAP_DAC_OVERRIDE dropped)."""
    if os.geteuid() != 0:
        return []
    if shutil.which("setpriv") is None:
        pytest.skip("running as root without setpriv: a read-only folder cannot be made")
    return ["setpriv", "--bounding-set=-dac_override,-dac_read_search"]


@pytest.mark.parametrize("command", ["pareto", "explore"])
def test_read_only_out_folder_exit_7(command, tmp_path):
    """A read-only --out folder: one-line error with exit 7 before the work, not exit 70 after it."""
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        cmd = _drop_root_write_override() + [
            sys.executable,
            "-m",
            "designer.cli",
            command,
            str(ROOT / "problems" / "indoor-manual.toml"),
            "--out",
            str(ro),
        ]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    finally:
        ro.chmod(0o755)
    assert proc.returncode == 7, proc.stderr
    assert (
        proc.stderr.strip() == f"designer: error: --out {ro}: cannot write in {ro} (Permission denied); "
        f"choose a writable --out folder"
    )


def test_solver_call_raises_after_sigint_flag():
    """A SIGINT received while IPOPT runs is swallowed by CasADi; the flag set by the handler makes the
    next return from a solver raise KeyboardInterrupt (here the flag is set by a real SIGINT to ourselves)."""
    from designer.errors import sigint_handler
    from designer.problem import load_problem
    from designer.solvers.nlp import CasterNLP

    nlp = CasterNLP(load_problem(ROOT / "problems" / "indoor-manual.toml"))
    start = nlp.problem.lower()
    with sigint_handler():
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
        with pytest.raises(KeyboardInterrupt):  # the flag outlives the swallowed exception
            nlp.solve(start)
    nlp.solve(start)  # handler removed: the flag is cleared


SCRIPT = """
import sys, time
import designer.cli.pareto, designer.studies.front._pareto, designer.solvers, designer.report.writer  # noqa: F401
from designer.studies.front import _pareto
from designer.cli import main

respace = _pareto._respace_objectives


def marked(*args, **kwargs):  # pass 1 of the front is solved: pass 2's NLP solves follow
    print("pass 2", flush=True)
    return respace(*args, **kwargs)


_pareto._respace_objectives = marked
print("ready", flush=True)
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.parametrize("when", ["0.3 s after start", "at pass 2"])
def test_sigint_exits_130_within_a_second_report_intact(when, tmp_path):
    """SIGINT while the front is being solved (IPOPT inside CasADi), early in the solve or at the start of its
    second pass (a marker the script prints, so the signal never lands after a fast machine has finished): exit
    130 within ~1 s, the previous report byte-for-byte intact and no temporary folder left (it finished the
    whole report before).  400 points keep the solve running well past either moment."""
    out = tmp_path / "report"
    out.mkdir()
    (out / "index.html").write_text("<p>previous</p>")
    (out / "front.json").write_text(json.dumps({"problem": "indoor-manual", "points": []}))
    # the previous report is the tool's: its manifest holds each file's digest (designer.output)
    digests = {
        p.name: {"sha256": hashlib.sha256(p.read_bytes()).hexdigest(), "by": "designer pareto"} for p in out.iterdir()
    }
    (out / MANIFEST).write_text(manifest_text(digests))
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    proc = subprocess.Popen(
        [sys.executable, "-c", SCRIPT, "pareto", str(ROOT / "problems" / "indoor-manual.toml"), "--points", "400"]
        + ["--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=tmp_path,
    )
    assert proc.stdout.readline().strip() == "ready"
    if when == "at pass 2":
        assert proc.stdout.readline().strip() == "pass 2"
    else:
        time.sleep(0.3)
    assert proc.poll() is None
    proc.send_signal(signal.SIGINT)
    t0 = time.perf_counter()
    try:
        proc.wait(timeout=10)
    finally:
        proc.kill()
    waited = time.perf_counter() - t0
    err = proc.stderr.read()
    assert proc.returncode == 130, err
    assert err.strip().endswith("designer: interrupted")
    # ~1 s goal; 3 s leaves room for a machine shared by several test runs
    assert waited < 3.0, waited
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]


@pytest.mark.parametrize(
    "args, code, key",
    [
        (["evaluate", "--trail", "0.5mm", "--diameter", "8in", "--groove", "0", "--damping", "1.3"], 2, "--trail"),
        (["evaluate", "--trail", "2in", "--diameter", "5mm", "--groove", "0", "--damping", "1.3"], 2, "--diameter"),
        (["fix", "problems/indoor-manual.toml", "--current", "T=1e-300,d=8in,B=0,c=1.3"], 2, "trail = 1e-300 m"),
    ],
)
def test_a_caster_below_the_physical_floor_is_refused(args, code, key):
    """A trail under 1 mm or a wheel under 10 mm (the model range's physical floors, designer/parameters.py) is a
    one-line error naming the value, never a result with overflowing turning efforts (T = 1e-300 gave M/T ~ 1e300
    and exit 0 before)."""
    result = subprocess.run([sys.executable, "-m", "designer", *args], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == code, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0] and "outside the model's range" in lines[0]
    assert result.stdout == ""


def test_problem_bounds_below_the_physical_floor_are_refused(tmp_path):
    """A problem file whose trail bound lies under the 1 mm floor fails to load with the key and the floor."""
    from designer.errors import ProblemError
    from designer.problem import problem_from_toml

    text = (ROOT / "problems" / "indoor-manual.toml").read_text()
    text = text.replace('trail = { min = "1 in"', 'trail = { min = "0.2 mm"')
    assert '"0.2 mm"' in text
    with pytest.raises(ProblemError, match=r"variables\.trail\.min = '0\.2 mm'.*outside the model's range"):
        problem_from_toml(text)


def test_evaluate_target_speed_prints_the_risk_and_its_sources(capsys):
    """designer evaluate --target-speed gives P(shimmy) ± SE under the risk law and its sources (shares adding up to
    1, the inertia of a 7 in wheel known by its diameter the largest), the same as the physics layer's record; with
    --inertia the wheel is measured (σ 0.05); a 3 in wheel is flagged as outside Table 1."""
    from designer.physics.inertia import power_law_inertia
    from designer.physics.uncertainty import Uncertainty, risk_record
    from designer.units import resolved

    args = ["evaluate", "--trail", "2.5in", "--diameter", "7in", "--groove", "0.5in", "--damping", "1.3"]
    assert main(args + ["--target-speed", "2.5m/s", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    inertia = float(power_law_inertia(7 * 0.0254))
    want = risk_record(2.5 * 0.0254, inertia, 0.5 * 0.0254, 1.3, 1250.0, 2.5, Uncertainty(), diameter=7 * 0.0254)
    # --json gives numbers at the precision they are resolved to, 12 significant digits (designer.units.resolved)
    assert out["risk"]["probability"] == resolved(want["probability"]) and out["risk"]["se"] == resolved(want["se"])
    assert out["extrapolated"] is False
    shares = {s["name"]: s["share"] for s in out["risk"]["sources"]}
    assert sum(shares.values()) == pytest.approx(1.0, abs=1e-12) and max(shares, key=shares.get).startswith("wheel")
    assert main(args + ["--target-speed", "2.5m/s", "--inertia", "0.00117", "--json"]) == 0
    measured = json.loads(capsys.readouterr().out)["risk"]["sources"]
    assert measured[1]["name"] == "wheel inertia (measured)" and measured[1]["scale"] == 0.05
    assert main(args + ["--target-speed", "2.5m/s"]) == 0
    text = " ".join(capsys.readouterr().out.split())  # the console wraps lines
    assert f"it shimmies with probability {100 * want['probability']:.3g} %" in text
    assert main(args + ["--target-speed", "2.5m/s", "--verbose"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "P(shimmy at 2.50" in text and "Where the risk comes from" in text and "dominates the risk" in text
    small = ["evaluate", "--trail", "2.5in", "--diameter", "3in", "--groove", "0in", "--damping", "1.3"]
    assert main(small + ["--inertia", "0.0002", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["extrapolated"] is True
    assert main(small + ["--inertia", "0.0002"]) == 0
    assert "outside Table 1's 4–8 in" in " ".join(capsys.readouterr().out.split())


def test_run_json_has_risk_spec_if_measured_and_extrapolated(capsys):
    """designer run --json: the recommendation has risk (exact P, its Monte Carlo and SE), spec and if_measured,
    every design record its extrapolated flag beside its design (recommendation, alternatives, the weighted
    optimum); the spec's limits are SI numbers keyed by part and side, each with its unit under ``units``."""
    assert main(["run", str(ROOT / "problems" / "indoor-manual.toml"), "--json", "--no-cross-check"]) == 0
    out = json.loads(capsys.readouterr().out)
    rec = out["recommendation"]
    assert {"risk", "spec", "if_measured", "extrapolated", "design"} <= set(rec)
    assert {"probability", "monte_carlo", "se", "sources", "dominant"} == set(rec["risk"])
    assert {"trail", "diameter", "groove", "friction_moment", "wheel_inertia"} == set(rec["spec"]["nominal"])
    limits, units = rec["spec"]["limits"], rec["spec"]["units"]
    assert set(limits) == {"trail_min", "trail_max", "groove_min", "friction_moment_min", "wheel_inertia_max"}
    assert {k: units[k] for k in limits} == {
        "trail_min": "m",
        "trail_max": "m",
        "groove_min": "m",
        "friction_moment_min": "N·m",
        "wheel_inertia_max": "kg·m²",
    }
    assert 0.0254 < limits["trail_min"] < rec["design"]["trail"] <= limits["trail_max"] + 1e-12
    assert {"design", "turning_effort", "threshold_force", "shimmy_probability", "shimmy_probability_se"} <= set(
        rec["if_measured"]
    )
    assert all("extrapolated" in a for a in out["alternatives"]) and out["extrapolated"] is False
    # every other caster of the buildable front (results/indoor-manual/front.csv: 5, 6 and 7 in), the 6 in one
    # between the ends
    wheels = {round(a["design"]["diameter"] / 0.0254, 6): a["role"] for a in out["alternatives"]}
    assert round(rec["design"]["diameter"] / 0.0254, 6) == 7
    assert wheels == {5: "easiest to turn", 6: "between the ends"}


@pytest.mark.parametrize("user, expected", [(None, "1"), ("3", "3")])
def test_the_command_runs_one_blas_thread_unless_the_user_says_otherwise(user, expected):
    """The command's process sets OPENBLAS_NUM_THREADS=1 before NumPy loads (its matrices are small: more threads
    only spin, 0.2 s of CPU on the main job), and a value the user set stands."""
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if user is not None:
        env["OPENBLAS_NUM_THREADS"] = user
    code = "import os, designer.entry as e; e.single_thread_blas(); print(os.environ['OPENBLAS_NUM_THREADS'])"
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert done.stdout.strip() == expected
