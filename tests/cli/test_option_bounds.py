"""Issue 24.5-6: command-line values are bounded as problem files are (exit 2 naming the option), and each
error names its real cause in one line: an option that overrides a problem value is blamed, not the file; a
storage that cannot be shared is one line, not worker tracebacks."""

from __future__ import annotations

from pathlib import Path

import pytest

from designer.cli import main
from designer.errors import StorageError

ROOT = Path(__file__).resolve().parents[2]
INDOOR = str(ROOT / "problems" / "indoor-manual.toml")


def _one_line_error(capsys, argv: list[str]) -> tuple[int, str]:
    code = main(argv)
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("designer: error: "), err
    return code, err


@pytest.mark.parametrize(
    "argv, option",
    [
        (["run", INDOOR, "--target-speed", "-1"], "--target-speed"),
        (["run", INDOOR, "--target-speed", "1e9"], "--target-speed"),
        (["run", INDOOR, "--target-speed", "0 m/s"], "--target-speed"),
        (["run", INDOOR, "--target-speed", "5000 kph"], "--target-speed"),
        (["run", INDOOR, "--weights", "1e300,1"], "--weights"),
        (["explore", INDOOR, "--seed", "-1"], "--seed"),
        (["explore", INDOOR, "--population", "1000000000"], "--population"),
        (["calibrate", "examples", "--seed", "-1"], "--seed"),
        (["calibrate", "damping", "x.csv", "--slip-coefficient", "-1"], "--slip-coefficient"),
    ],
)
def test_an_option_out_of_range_is_named(capsys, argv, option):
    """`run --target-speed -1` was exit 3 blaming the problem file ("p.toml: shimmy.target_speed = -1 m/s"):
    a value given on the command line is checked as the problem file's key is (the parameter table's range,
    0.01 to 100 m/s for a speed) and the error is exit 2 naming the option, before any file is read."""
    code, err = _one_line_error(capsys, argv)
    assert code == 2 and option in err and "indoor-manual.toml" not in err


def test_in_memory_sqlite_cannot_serve_workers(capsys, tmp_path):
    """`explore --storage sqlite:///:memory: --workers 2` gave exit 6 after 54 lines of two workers'
    tracebacks (each worker opened a database of its own): one line naming --storage, exit 6, at once."""
    code, err = _one_line_error(
        capsys, ["explore", INDOOR, "--storage", "sqlite:///:memory:", "--workers", "2", "--out", str(tmp_path)]
    )
    assert code == StorageError.exit_code == 6 and "storage 'sqlite:///:memory:': an in-memory SQLite" in err


def test_a_failing_worker_says_one_line(monkeypatch, capsys):
    """A worker process whose study fails (any exception) prints one line naming the error and exits 1 for
    the parent's summary; no traceback."""
    from designer.studies.explore import _workers

    def broken(*args):
        raise KeyError("Record does not exist.")

    monkeypatch.setattr(_workers, "_run_worker", broken)
    with pytest.raises(SystemExit) as info:
        _workers._worker_entry(())
    err = capsys.readouterr().err
    assert info.value.code == 1 and err.count("\n") == 1 and "Record does not exist" in err
    assert "Traceback" not in err


SIMULATE = ["simulate", "--trail", "2in", "--speed", "2"]


@pytest.mark.parametrize(
    "extra, option",
    [
        (["--speed", "1e6"], "--speed"),
        (["--speed", "0.001"], "--speed"),
        (["--trail", "2 m"], "--trail"),
        (["--trail", "0"], "--trail"),
        (["--diameter", "1e3"], "--diameter"),
        (["--groove", "1 m"], "--groove"),
        (["--damping", "1e9"], "--damping"),
        (["--load", "1e9"], "--load"),
        (["--slip-coefficient", "1e12"], "--slip-coefficient"),
        (["--inertia", "1e-12"], "--inertia"),
        (["--angular-velocity", "1e300"], "--angular-velocity"),
        (["--angle", "95 deg"], "--angle"),
        (["--disturbance-angle", "-1 deg"], "--disturbance-angle"),
        (["--duration", "1e9"], "--duration"),
        (["--bifurcation", "--max-speed", "1e6"], "--max-speed"),
        (["--bifurcation", "--points", "100000"], "--points"),
        (["--knock-safe", "--tyre", "--friction-coefficient", "1e9"], "--friction-coefficient"),
        (["--knock-safe", "--tyre", "--cornering-stiffness", "1e300"], "--cornering-stiffness"),
        (["--knock-safe", "--tyre", "--wheel-mass", "1e9"], "--wheel-mass"),
    ],
)
def test_simulate_options_are_bounded_as_problem_files(capsys, extra, option):
    """Every numeric option of `designer simulate` is bounded: the design and the speeds by the parameter
    table's ranges (speed 0.01 to 100 m/s, as shimmy.target_speed), the brush tyre's by stated ranges; a value
    outside is exit 2 naming the option, before any simulation (a huge --speed ran for minutes)."""
    code, err = _one_line_error(capsys, SIMULATE + extra)
    assert code == 2 and option in err


@pytest.mark.parametrize(
    "argv, code, fragment",
    [
        (SIMULATE[:3] + ["--speed", "1e8"], 2, "--speed"),
        (["simulate", "--trail", "2in", "--bifurcation", "--max-speed", "1e8"], 2, "--max-speed"),
        (SIMULATE + ["--inertia", "1e-9", "--find-onset"], 5, "no shimmy onset up to 100 m/s"),
    ],
)
def test_battery_cases_end(tmp_path, argv, code, fragment):
    """The three cases that gave no answer within 60 s now end (a generous 600 s guard, no timing asserted)
    with one line and a non-zero exit: a huge --speed or --max-speed is refused, and the onset of a
    1e-9 kg·m² wheel is said to lie beyond the model's speeds."""
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, "-m", "designer", *argv], capture_output=True, text=True, timeout=600, cwd=tmp_path
    )
    assert done.returncode == code and fragment in done.stderr and done.stderr.count("\n") == 1, done.stderr


def test_command_studies_share_one_budget(monkeypatch, capsys):
    """`designer simulate` runs its studies (a simulation and an onset search, or knock-safe speeds and two
    bifurcation diagrams) under one work budget: with the budget made small, the command ends with exit 5
    and one line saying what stopped and after how many evaluations."""
    from designer.studies.dynamics import _work

    monkeypatch.setattr(_work, "MAX_EVALUATIONS", 20_000)
    code, err = _one_line_error(capsys, SIMULATE + ["--find-onset"])
    assert code == 5 and "designer simulate: stopped after 20,000 evaluations" in err


def test_fleet_beyond_its_documented_size_is_refused(tmp_path, capsys):
    """A fleet of 1 000 000 rows ran for minutes at 1.2 GB while docs/fleet.md promises 100 000 chairs: a
    file with more rows than MAX_CHAIRS is refused with one line and exit 3 before anything is parsed or
    computed, as is --example beyond it (exit 2)."""
    from designer.studies.fleet import MAX_CHAIRS

    row = "c{},200,0.5,2.5,7,tile,chair\n"
    path = tmp_path / "big.csv"
    with open(path, "w") as f:
        f.write("name,load_N,threshold_height_in,target_speed_m/s,swept_radius_max_in,surface,turning_mode\n")
        f.writelines(row.format(i) for i in range(MAX_CHAIRS + 1))
    code, err = _one_line_error(capsys, ["fleet", str(path), "--problem", INDOOR, "--out", str(tmp_path / "o")])
    assert code == 3 and f"{MAX_CHAIRS + 1:,} rows" in err and f"at most {MAX_CHAIRS:,} chairs" in err
    assert not (tmp_path / "o").exists()
    code, err = _one_line_error(capsys, ["fleet", "--example", str(MAX_CHAIRS + 1), "--out", str(tmp_path / "x.csv")])
    assert code == 2 and "--example" in err
