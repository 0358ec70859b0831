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
    assert code == StorageError.exit_code == 6 and "--storage sqlite:///:memory:" in err


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
