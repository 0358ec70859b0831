"""Hardening (issue 8): bad input ends as the tool's own one-line errors with the documented exit
codes, solver failures are retried and reported, reports are written safely, and the README's
error table matches :mod:`designer.errors`."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import designer.errors as errors_module
from designer import load_problem
from designer.cli import main
from designer.errors import DesignerError, InputError, OutputError, ProblemError, SolverError
from designer.output import TEMP_PREFIX
from designer.problem import problem_from_toml
from designer.solvers.nlp import CasterNLP
from designer.units import parse_quantity

ROOT = Path(__file__).resolve().parents[2]
INDOOR = ROOT / "problems" / "indoor-manual.toml"
INVACARE = ROOT / "problems" / "paper-invacare.toml"
BASE = 'name = "t"\n[shimmy]\ntarget_speed = "2.5 m/s"\n'


# --------------------------------------------------------------------------- 1. one error style


@pytest.mark.parametrize(
    "text, fragment",
    [
        (BASE + "[conditions]\nload = [1, 2]\n", "conditions.load = [1, 2]: expected a number"),
        (BASE + '[pareto]\npoints = "x"\n', "pareto.points = 'x': expected an integer"),
        (BASE + "[variables]\ntrail = {min = true, max = 2}\n", "variables.trail.min = True"),
        ("title = 5\n" + BASE, "title = 5: expected a string"),
        ('name = "t"\nshimmy = "fast"\n', "[shimmy] must be a table"),
        ('name = "t"\nconditions = "x"\n[shimmy]\ntarget_speed = 2.5\n', "[conditions] must be a table"),
        (BASE + '[variables]\ntrail = "1 m"\n', "outside the model's range"),  # fixed, out of range
        (BASE + '[variables]\ndiameter = "3 m"\n', "outside the model's range"),  # a 3 m wheel
        (BASE + "[objective]\nturning_effort = 0\nthreshold_force = 0\n", "not all zero"),
        (BASE + "[objective]\nturning_effort = -1\nthreshold_force = -2\n", "non-negative"),
        (BASE + "[objective]\nturning_effort = 1e308\nthreshold_force = 1e308\n", "weights are relative"),
        (BASE + "[objective]\nturning_effort = 1" + "0" * 400 + "\n", "too large"),
        (BASE + "[conditions]\nload = 1" + "0" * 5000 + "\n", "cannot read the file"),  # raw ValueError
        (BASE + '[inertia]\nmodel = "catalog"\nwheel = "Z"\n', "unknown Table 1 wheel"),
        (BASE + '[inertia]\nmodel = "catalog"\nwheels = []\n', "non-empty list"),
        (
            BASE
            + '[inertia]\nmodel = "catalog"\nwheels = ["C"]\n[variables]\ndiameter = {min = "2 in", max = "3 in"}\n',
            "no catalog wheel",
        ),  # empty range of wheels
        (BASE + "[choices]\nsurface = []\n", "non-empty list"),
        (BASE + '[variables]\ntrail = {min = "2 in", max = "1 in"}\n', "min is greater than max"),
        (BASE + '[conditions]\nload = "[1,2] N"\n', "unexpected character '['"),  # pint read this as 12 N
        (BASE + '[conditions]\nload = "N"\n', "a unit without a number"),  # pint read this as 1 N
        (BASE + '[conditions]\nload = "10**10**10 N"\n', "exponents must be small"),  # pint never returned
        (BASE + '[conditions]\nload = "2**9**9 N"\n', "exponents must be small"),  # raw OverflowError
        (BASE + '[conditions]\nload = "10**999 N"\n', "too large"),  # raw OverflowError
        (BASE + "[conditions]\nload = 1e300\n", "conditions.load = 1e+300 N: outside the model's range"),
        (BASE + "[conditions]\nthreshold_height = 1e-320\n", "conditions.threshold_height"),
        ('name = "t"\n[shimmy]\ntarget_speed = 1e-320\n', "shimmy.target_speed"),  # was a SolverError later
        (BASE + "slip_coefficient = 1e308\n", "shimmy.slip_coefficient"),
        (BASE + "[inertia]\ncoefficient = 1e308\n", "I_w = "),  # inertia overflow
        (BASE + '[inertia]\nmodel = "fixed"\ninertia = 1e-320\n', "I_w = "),  # V_c = inf
        (BASE + "[turning]\ngroove_coefficient = 1e308\n", "turning.groove_coefficient"),
        (BASE + "[robust]\nsamples = 1000000000000\n", "robust.samples"),  # memory blow-up
        (BASE + "[constraints]\nswept_radius_max = 1e308\n", "constraints.swept_radius_max"),
        (BASE + '[conditions]\n"lo\\nad" = 1\n', "unknown key conditions.'lo\\nad'"),  # a newline broke the line
        (BASE + "[turning]\nbare_fork_damping = 1e-320\n", "turning.bare_fork_damping"),
    ],
)
def test_bad_problem_files_are_one_line_problem_errors(text, fragment):
    """Wrong types, absurd sizes, empty ranges and unit tricks end as one-line ProblemErrors (exit 3)
    naming the key, quickly (the exponent tower used to hang pint)."""
    t0 = time.perf_counter()
    with pytest.raises(ProblemError) as info:
        problem_from_toml(text, source="bad.toml")
    message = str(info.value)
    assert fragment in message
    assert "\n" not in message and message.startswith("bad.toml: ")
    assert info.value.exit_code == 3
    assert time.perf_counter() - t0 < 5


def test_suggestion_for_misspelt_keys():
    """An unknown key names the nearest valid one (the existing suggestion style)."""
    with pytest.raises(ProblemError, match=r"unknown key variables.trial \(did you mean 'trail'\?\)"):
        problem_from_toml(BASE + "[variables]\ntrial = 1\n")


@pytest.mark.parametrize("value", ["9/16 in", "2in", "0.5 in", "5 %", "0.00127 kg*m**2", "1 kg*m^2", "7 1/m"])
def test_ordinary_quantities_still_parse(value):
    """The guard against pint's arithmetic keeps ordinary quantities working (fractions, m**2, percent)."""
    dimension = {"%": "dimensionless", "kg": "inertia", "1/m": "per_length"}
    dim = next((d for k, d in dimension.items() if k in value), "length")
    assert np.isfinite(parse_quantity(value, dim, "k"))


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["--diameter", "3m"], "--diameter = '3m': outside the model's range 0.01 to 0.6 m"),
        (["--trail", "1e300"], "--trail = 1e+300 m"),  # was OverflowError, exit 70
        (["--groove", "1e300"], "--groove = 1e+300 m"),  # was OverflowError, exit 70
        (["--inertia", "1e-320"], "--inertia 1e-320"),  # printed V_c = inf
        (["--threshold-height", "1e-320"], "--threshold-height"),  # printed P = nan
        (["--target-speed", "1e308"], "--target-speed"),  # was LinAlgError, exit 70
        (["--trail", "[1,2]in"], "unexpected character '['"),
    ],
)
def test_evaluate_absurd_values_exit_2(args, fragment, capsys):
    """``designer evaluate`` with absurd sizes: one line on stderr, exit 2, nothing printed with NaN or inf."""
    base = {"--trail": "2in", "--diameter": "8in", "--groove": "0", "--damping": "1.3"}
    for key, value in zip(args[::2], args[1::2]):
        base[key] = value
    argv = ["evaluate"] + [x for kv in base.items() for x in kv]
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2
    assert fragment in err and err.count("\n") == 1 and err.startswith("designer: error: ")
    assert not re.search(r"\bnan\b|\binf\b", out, re.I)


def test_run_absurd_weights_is_input_error(capsys):
    """``--weights 1e308,1e308`` used to reach IPOPT and come back as a misleading SolverError; now exit 2."""
    code = main(["run", str(INDOOR), "--weights", "1e308,1e308", "--no-cross-check"])
    err = capsys.readouterr().err
    assert code == 2 and "weights are relative" in err and err.count("\n") == 1
    with pytest.raises(InputError, match="weights"):
        from designer.studies.optimum import optimise

        optimise(load_problem(INDOOR), weights=(0.0, 0.0), cross_check=False)


def test_problem_error_one_line_and_debug_traceback(tmp_path, capsys):
    """A bad problem file: one line and exit 3; with --debug the exception (and traceback) comes through."""
    bad = tmp_path / "bad.toml"
    bad.write_text(BASE + "[conditions]\nload = [1, 2]\n")
    assert main(["run", str(bad)]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "conditions.load" in err and "Traceback" not in err
    with pytest.raises(ProblemError, match="conditions.load"):
        main(["--debug", "run", str(bad)])
    proc = subprocess.run(
        [sys.executable, "-m", "designer.cli", "--debug", "run", str(bad)], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode != 0 and "Traceback (most recent call last)" in proc.stderr
    assert "designer.errors.ProblemError" in proc.stderr


def test_problem_names_cannot_escape_results(tmp_path, capsys):
    """A problem name like ../../x is rejected (it names the results folder), exit 3."""
    bad = tmp_path / "evil.toml"
    bad.write_text(INVACARE.read_text().replace('name = "paper-invacare"', 'name = "../../x"'))
    assert 'name = "../../x"' in bad.read_text()
    assert main(["pareto", str(bad), "--out", str(tmp_path / "r")]) == 3
    assert "name = '../../x'" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()


# --------------------------------------------------------------------------- 2. solver failures


def _failed(result, status="Restoration_Failed"):
    return dataclasses.replace(result, success=False, status=status)


def test_nlp_reports_max_iter_and_nan_as_failures():
    """IPOPT at its iteration limit, or with a NaN in a function evaluation, gives success=False and its status:
    the limit we set is IPOPT's documented Maximum_Iterations_Exceeded; for the NaN, whichever failure IPOPT (or
    CasADi before it) reports is passed on unchanged, never a success."""
    problem = load_problem(INDOOR)
    limited = CasterNLP(problem, ipopt_options={"ipopt.max_iter": 1})
    result = limited.solve(problem.lower())
    assert not result.success and result.status == "Maximum_Iterations_Exceeded"
    assert all(not r.success for r in limited.solve_many([problem.lower(), problem.upper()]))
    fresh = CasterNLP(problem)
    nan = fresh.solve(problem.lower(), overrides={"slip_coefficient": float("nan")})
    assert not nan.success and nan.status == fresh.solver.stats()["return_status"]
    assert nan.status not in ("Solve_Succeeded", "Solved_To_Acceptable_Level")


def test_optimise_retries_other_starts(monkeypatch):
    """When some starts fail (restoration failure), the optimum comes from the others and is the same."""
    from designer.studies.optimum import optimise

    problem = load_problem(INDOOR)
    reference = optimise(problem, cross_check=False)
    real = CasterNLP.solve
    calls = {"n": 0}

    def flaky(self, *args, **kwargs):
        calls["n"] += 1
        result = real(self, *args, **kwargs)
        return _failed(result) if calls["n"] % 2 else result

    monkeypatch.setattr(CasterNLP, "solve", flaky)
    solution = optimise(problem, cross_check=False)
    assert calls["n"] >= 4
    assert solution.objectives["weighted"] == pytest.approx(reference.objectives["weighted"], rel=1e-6)


def test_optimise_raises_solver_error_when_every_start_fails(monkeypatch, capsys):
    """IPOPT failing from every start on a feasible problem: SolverError, one line, exit 5 from the CLI where it
    shows the weighted optimum (--verbose; the one-screen answer does not solve it)."""
    from designer.studies.optimum import optimise

    real = CasterNLP.solve
    monkeypatch.setattr(CasterNLP, "solve", lambda self, *a, **k: _failed(real(self, *a, **k)))
    with pytest.raises(SolverError) as info:
        optimise(load_problem(INDOOR), cross_check=False)
    assert "from any start" in str(info.value) and "\n" not in str(info.value)
    capsys.readouterr()
    assert main(["run", str(INDOOR), "--no-cross-check", "--verbose"]) == 5
    errors = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("designer: warning")]
    assert len(errors) == 1 and errors[0].startswith("designer: error: IPOPT found no optimum")


def test_pareto_marks_failed_points(monkeypatch):
    """ε-points whose solves all fail (any start, any retry) are kept in front.failed with their status,
    never in front.points, the indicators or the CSV; the rest of the front is unaffected."""
    import designer.studies.front._pareto as pareto
    from designer.solvers.nlp import BIG, SHARED

    problem = load_problem(INDOOR)
    SHARED.clear()
    clean = pareto.pareto_front(problem, points=9)
    p = clean.objectives()[:, 1]
    band = (p.min() + 0.35 * np.ptp(p), p.min() + 0.65 * np.ptp(p))

    def in_band(cap):
        return band[0] <= cap <= band[1]

    real_solve, real_many = CasterNLP.solve, CasterNLP.solve_many

    def solve(self, start, weights=(1.0, 1.0), threshold_cap=BIG, *args, **kwargs):
        result = real_solve(self, start, weights, threshold_cap, *args, **kwargs)
        return _failed(result) if in_band(threshold_cap) else result

    def solve_many(self, starts, weights=(1.0, 1.0), threshold_caps=BIG, *args, **kwargs):
        results = real_many(self, starts, weights, threshold_caps, *args, **kwargs)
        caps = np.broadcast_to(np.asarray(threshold_caps, float), (len(results),))
        return [_failed(r) if in_band(c) else r for r, c in zip(results, caps)]

    monkeypatch.setattr(CasterNLP, "solve", solve)
    monkeypatch.setattr(CasterNLP, "solve_many", solve_many)
    SHARED.clear()
    try:
        front = pareto.pareto_front(problem, points=9)
    finally:
        SHARED.clear()
    assert front.failed, "points in the band must be reported as failed"
    assert all(not f.success and f.status == "Restoration_Failed" and in_band(f.epsilon) for f in front.failed)
    assert all(q.success and not in_band(q.epsilon) for q in front.points)
    assert front.meta["points_failed"] == len(front.failed)
    assert len(front.points) >= 3 and np.isfinite(front.hypervolume())
    data = front.to_dict()
    assert len(data["failed"]) == len(front.failed) and all(r["status"] == "Restoration_Failed" for r in data["failed"])
    from designer.jsonsafe import finite

    json.dumps(finite(data), allow_nan=False)  # failed points may hold NaN objectives; front.json is cleaned


def test_pareto_total_solver_failure_is_an_error(monkeypatch):
    """IPOPT failing everywhere on a feasible problem used to give a silent empty front; now a SolverError."""
    import designer.studies.front._pareto as pareto
    from designer.solvers.nlp import SHARED

    real = CasterNLP.__init__
    monkeypatch.setattr(
        CasterNLP, "__init__", lambda self, problem, ipopt_options=None: real(self, problem, {"ipopt.max_iter": 1})
    )
    SHARED.clear()
    try:
        with pytest.raises(SolverError) as info:
            pareto.pareto_front(load_problem(INDOOR), points=5)
    finally:
        monkeypatch.undo()
        SHARED.clear()  # the crippled NLPs must not serve later tests
    assert "Maximum_Iterations_Exceeded" in str(info.value) and "\n" not in str(info.value)
    # an unreachable target is still an empty front (the report explains it), not a solver error
    infeasible = pareto.pareto_front(load_problem(INDOOR).replace(target_speed=40.0), points=5)
    assert not infeasible.points and not infeasible.failed


# --------------------------------------------------------------------------- 3. safe writes


@pytest.fixture(scope="module")
def invacare_front():
    """The paper's Invacare problem (fixed diameter, a one-point front): fast to compute."""
    from designer.studies.front import pareto_front

    problem = load_problem(INVACARE)
    return problem, pareto_front(problem)


def test_interrupted_report_leaves_nothing(invacare_front, tmp_path, monkeypatch):
    """Ctrl-C while the report is written leaves no half folder, no temporary folder, and an old report intact."""
    from designer.report import writer

    from designer.pipeline import report_data

    problem, front = invacare_front
    data = report_data(problem, front=front, with_tighter=False)
    previous = writer.write_report(data, tmp_path / "r")
    before = (previous / "front.json").read_text()

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(writer, "_render", interrupted)
    with pytest.raises(KeyboardInterrupt):
        writer.write_report(data, tmp_path / "new")
    with pytest.raises(KeyboardInterrupt):
        writer.write_report(data, tmp_path / "r")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r"]
    assert (tmp_path / "r" / "front.json").read_text() == before
    assert not [p.name for p in (tmp_path / "r").iterdir() if p.name.startswith(TEMP_PREFIX)]


def test_out_refuses_the_users_report_names_unless_force(invacare_front, tmp_path, capsys):
    """--out pointing at a folder holding the user's own index.html (a name the report writes, not proved the
    tool's by a manifest) is refused (exit 7, the one code of this refusal, before any work and without touching
    it); --force writes the report into it, keeping its other files; a previous report is replaced without
    --force; a file as the folder is exit 7 too."""
    from designer.pipeline import report_data
    from designer.report import write_report

    problem, front = invacare_front
    data = report_data(problem, front=front, with_tighter=False)
    mine = tmp_path / "thesis"
    mine.mkdir()
    (mine / "chapter1.tex").write_text("precious")
    (mine / "index.html").write_text("<h1>my thesis</h1>")
    with pytest.raises(OutputError, match="holds index.html, which designer pareto would replace"):
        write_report(data, mine)
    assert main(["pareto", str(INVACARE), "--out", str(mine)]) == 7
    err = capsys.readouterr().err
    assert "index.html" in err and err.count("\n") == 1
    assert (mine / "chapter1.tex").read_text() == "precious"
    assert (mine / "index.html").read_text() == "<h1>my thesis</h1>"
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputError, match="is a regular file, not a folder"):  # the user's setup: exit 7
        write_report(data, tmp_path / "file")
    assert (tmp_path / "file").read_text() == "x"
    assert main(["pareto", str(INVACARE), "--out", str(mine), "--force"]) == 0
    # the report owns only its own files: the foreign one is kept (issue 12.4)
    assert (mine / "chapter1.tex").read_text() == "precious" and (mine / "index.html").is_file()
    assert main(["pareto", str(INVACARE), "--out", str(mine)]) == 0  # now a previous report
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "thesis"]


def test_commits_to_one_folder_take_turns(tmp_path, monkeypatch):
    """Two writers committing into one folder at once take turns (a lock on the folder): while the first one's
    renames run (slowed down here), the second waits, so the folder ends as one complete set of files (the
    second writer's), never a mixture, with nothing temporary left behind."""
    import threading

    from designer.output import output_folder

    target = tmp_path / "r"
    names = [f"f{i:02d}.txt" for i in range(20)]
    real_replace = os.replace
    renaming = threading.Event()

    def slow_replace(src, dst, *a, **k):
        if threading.current_thread().name == "first":
            renaming.set()
            time.sleep(0.01)
        return real_replace(src, dst, *a, **k)

    monkeypatch.setattr(os, "replace", slow_replace)

    def writer(tag):
        with output_folder(target, names) as tmp:
            for n in names:
                (tmp / n).write_text(tag)

    first = threading.Thread(target=writer, args=("first",), name="first")
    first.start()
    assert renaming.wait(10)  # the first writer is half-way through its renames
    writer("second")
    first.join(10)
    contents = [(target / n).read_text() for n in names]
    assert contents == ["second"] * len(names)
    assert sorted(p.name for p in target.iterdir()) == sorted([*names, ".designer-manifest.json"])


def test_title_script_is_escaped_via_cli(tmp_path):
    """A <script> title in a problem file is escaped in index.html and report.md."""
    evil = tmp_path / "evil.toml"
    evil.write_text(INVACARE.read_text().replace('title = "', 'title = "<script>alert(1)</script> ', 1))
    assert "<script>" in evil.read_text()
    assert main(["pareto", str(evil), "--out", str(tmp_path / "r")]) == 0
    html = (tmp_path / "r" / "index.html").read_text()
    assert "<script>alert(1)</script>" not in html and "&lt;script&gt;alert(1)&lt;/script&gt;" in html
    assert "<script>alert(1)</script>" not in (tmp_path / "r" / "report.md").read_text()


# --------------------------------------------------------------------------- 5. concurrency


def test_two_pareto_runs_on_one_out_folder(tmp_path):
    """Two ``designer pareto`` processes writing the same --out at once: both succeed and the folder is one
    complete report (its front.json, CSV and HTML from the same run), with no temporary folder left."""
    out = tmp_path / "r"
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    procs = [
        subprocess.Popen(
            [
                sys.executable,
                "-m",
                "designer.cli",
                "pareto",
                str(INVACARE),
                "--points",
                str(n),
                "--out",
                str(out),
                "--json",
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )
        for n in (5, 7)
    ]
    results = [p.communicate(timeout=300) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], [r[1][-500:] for r in results]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r"]
    data = json.loads((out / "front.json").read_text())
    assert data["run"]["points_option"] in (5, 7)
    for name in ("index.html", "report.md", "front.csv", "checks.json"):
        assert (out / name).is_file()
    assert len(list((out / "figures").glob("*.svg"))) >= 6
    html = (out / "index.html").read_text()
    assert data["problem_digest"] in html


def test_explore_workers_share_one_storage_exists():
    """Two explore workers on one journal storage losing no trials is covered in tests/studies/explore/test_explore.py."""
    text = (ROOT / "tests" / "studies" / "explore" / "test_explore.py").read_text()
    assert re.search(r"def test_\w*two_workers\w*|def test_\w*workers\w*", text)


# --------------------------------------------------------------------------- README error table


def _readme_table() -> dict[int, str]:
    """The exit-code table of docs/commands.md (moved there from the README)."""
    text = (ROOT / "docs" / "commands.md").read_text(encoding="utf-8")
    section = text.split("## Errors and exit codes", 1)[1].split("\n## ", 1)[0]
    rows = {}
    for line in section.splitlines():
        match = re.match(r"^\|\s*(\d+)\s*\|\s*([^|]*)\|", line)
        if match:
            rows[int(match.group(1))] = match.group(2).strip()
    return rows


def test_readme_exit_codes_match_errors_module():
    """Every exit code in README's table matches designer/errors.py and every error kind is documented."""
    rows = _readme_table()
    assert rows, "the README has no exit-code table"
    kinds = {
        cls.__name__: cls.exit_code
        for cls in vars(errors_module).values()
        if isinstance(cls, type) and issubclass(cls, DesignerError) and cls is not DesignerError
    }
    documented = {}
    for code, kind in rows.items():
        for name in re.findall(r"`(\w+Error)`", kind):
            documented[name] = code
    assert documented == kinds
    assert rows[1].startswith("a check failed") and DesignerError.exit_code == 1
    assert 0 in rows and 70 in rows and 130 in rows and 141 in rows and 143 in rows


def test_internal_error_and_interrupt_codes_match_readme(monkeypatch, capsys):
    """A bug gives exit 70 with one line (traceback under --debug); Ctrl-C gives 130, SIGTERM 143 and a closed
    standard output 141, as the README says."""
    import designer.cli.evaluate as evaluate

    rows = _readme_table()
    argv = ["evaluate", "--trail", "2in", "--diameter", "8in", "--groove", "0", "--damping", "1.3"]

    def bug(args):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr(evaluate, "analyse", bug)
    assert main(argv) == 70 and "internal" in rows[70]
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "ZeroDivisionError" in err and "--debug" in err
    with pytest.raises(ZeroDivisionError):
        main(["--debug"] + argv)

    def interrupt(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(evaluate, "analyse", interrupt)
    assert main(argv) == 130 and "interrupted" in rows[130]

    def terminate(args):
        from designer.errors import Terminated

        raise Terminated

    monkeypatch.setattr(evaluate, "analyse", terminate)
    assert main(argv) == 143 and "terminated" in rows[143]
    assert capsys.readouterr().err.strip().splitlines()[-1] == "designer: terminated (SIGTERM)"

    def closed(args):
        raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(evaluate, "analyse", closed)
    assert main(argv) == 141 and "closed" in rows[141]
    assert capsys.readouterr().err == ""


def test_pareto_front_points_must_be_whole_number():
    """pareto_front(points="x") from Python raises the tool's InputError naming the value, not a raw ValueError."""
    import designer
    from designer.errors import InputError

    problem = designer.load_problem(Path(__file__).resolve().parents[2] / "problems" / "paper-invacare.toml")
    with pytest.raises(InputError, match="points = 'x'"):
        designer.pareto_front(problem, points="x")
