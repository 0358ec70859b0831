"""Input and system errors are mapped once, at the edge (issue class 5): every operating-system error by its
errno (designer.errors.system_error, designer.errors.os_reason), a RecursionError while reading, the csv module's
limits, an output whose encoding cannot take a glyph; and the readers (TOML problem, CSV data of calibrate and
fleet, storage) share one set of rules (designer.textfiles).  Each row is one line on stderr with the true
reason and the tool's exit code, never an internal error (exit 70)."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path

import pytest

from designer.cli import main
from designer.errors import InputError, OutputError, system_error

ROOT = Path(__file__).resolve().parents[2]
FLEET_HEADER = "name,load_N,threshold_height_in,target_speed_m/s,swept_radius_max_in,surface,turning_mode\n"
FLEET_ROW = "A,178,0.5,2.5,5,tile,chair\n"


def _turning_rows(n: int = 8) -> str:
    return "".join(f"{100 + 10 * i},{0.5 + 0.05 * i}\n" for i in range(n))


# (errno, exit code, reason in the message)
ERRNOS = [
    (errno.ENOSPC, 7, "no space left on device"),
    (errno.EDQUOT, 7, "disk quota exceeded"),
    (errno.EROFS, 7, "read-only file system"),
    (errno.ENAMETOOLONG, 2, "a name longer than the file system allows"),
    (errno.EFBIG, 7, "file too large"),
    (errno.ELOOP, 2, "a symbolic link loop"),
    (errno.EISDIR, 2, "is a folder"),
    (errno.ENOTDIR, 2, "a part of the path is a file, not a folder"),
    (errno.EACCES, 2, "permission denied"),
    (errno.ENOENT, 2, "no such file or folder"),
    (errno.EIO, 2, "input/output error"),
    (errno.ENXIO, 2, "no such device"),
]


@pytest.mark.parametrize("code, exit_code, reason", ERRNOS, ids=[errno.errorcode[e] for e, _, _ in ERRNOS])
def test_every_os_error_is_one_line_with_its_true_reason(code, exit_code, reason):
    """system_error, the edge's one mapping: an OSError names its path and its errno's reason (ELOOP is a link
    loop, not "no such file"), exit 7 for what only an output can cause, else exit 2."""
    mapped = system_error(OSError(code, os.strerror(code), "/some/place"))
    assert mapped is not None and mapped.exit_code == exit_code
    assert str(mapped) == f"/some/place: {mapped.args[0].split(': ', 1)[1]}" and reason in str(mapped)
    assert isinstance(mapped, OutputError if exit_code == 7 else InputError)


def test_other_failures_at_the_edge():
    """A RecursionError is input nested too deeply (exit 2), a UnicodeEncodeError an output's encoding (exit 7);
    anything else stays a bug (None: exit 70 with --debug's hint)."""
    assert system_error(RecursionError()).exit_code == 2
    unicode = system_error(UnicodeEncodeError("ascii", "·", 0, 1, "ordinal not in range"))
    assert unicode is not None and unicode.exit_code == 7 and "'·'" in str(unicode)
    assert system_error(ZeroDivisionError()) is None


def _cases(tmp: Path) -> list[tuple[str, list[str], int, str]]:
    """(label, argv, exit code, text of the one stderr line) of the command-line rows; files made in ``tmp``."""
    (tmp / "loop.toml").symlink_to("loop.toml")
    os.mkfifo(tmp / "pipe.csv")
    (tmp / "file").write_text("x")
    (tmp / "deep.toml").write_text("x = " + "[" * 100_000 + "]" * 100_000 + "\n")
    (tmp / "wide.csv").write_text("load_N,moment_Nm\n" + _turning_rows(), encoding="utf-16")
    (tmp / "dup.csv").write_text("load_N,moment_Nm,load_N\n" + "".join(f"{r},1\n" for r in _turning_rows().split()))
    (tmp / "big.csv").write_text("load_N,moment_Nm\n" + "1" * 200_000 + ",0.5\n" + _turning_rows())
    (tmp / "bigname.csv").write_text(FLEET_HEADER + "A" * 200_000 + FLEET_ROW[1:])
    (tmp / "fleet.csv").write_text(FLEET_HEADER + FLEET_ROW)
    (tmp / "quote.csv").write_text('load_N,moment_Nm\n"100,0.5\n' + _turning_rows())
    long_name = str(tmp / ("a" * 300))
    return [
        ("symlink loop", ["run", str(tmp / "loop.toml")], 3, "loop.toml: a symbolic link loop"),
        ("character device", ["run", "/dev/zero"], 3, "/dev/zero: is a character device, expected a .toml"),
        ("FIFO nobody writes, as fleet", ["fleet", str(tmp / "pipe.csv")], 3, "pipe.csv: a pipe (FIFO) that nothing"),
        ("FIFO nobody writes, as data", ["calibrate", "turning", str(tmp / "pipe.csv")], 2, "that nothing writes to"),
        ("folder as problem", ["run", str(tmp)], 3, "is a folder, expected a .toml problem file"),
        ("path under a file", ["run", str(tmp / "file" / "p.toml")], 3, "a part of the path is a file"),
        ("100 000 levels of nesting", ["run", str(tmp / "deep.toml")], 3, "nested too deeply to read"),
        ("UTF-16 calibration data", ["calibrate", "turning", str(tmp / "wide.csv")], 2, "UTF-16 text"),
        (
            "duplicate calibration column",
            ["calibrate", "turning", str(tmp / "dup.csv")],
            2,
            "column 'load_N': load_N appears twice in the header",
        ),
        (
            "200 kB calibration cell",
            ["calibrate", "turning", str(tmp / "big.csv")],
            2,
            "big.csv: row 2, column 'load_N': a cell of 200,000 characters",
        ),
        (
            "200 kB fleet name",
            ["fleet", str(tmp / "bigname.csv")],
            3,
            "bigname.csv: row 2, column 'name': a cell of 200,000 characters",
        ),
        (
            "unclosed quote",
            ["calibrate", "turning", str(tmp / "quote.csv")],
            2,
            "quote.csv: line 10: not CSV (unexpected end of data)",
        ),
        (
            "scheduler without a port",
            ["fleet", str(tmp / "fleet.csv"), "--scheduler", "tcp://host"],
            2,
            "--scheduler 'tcp://host': expected an address",
        ),
        (
            "scheduler of a broken IPv6 host",
            ["fleet", str(tmp / "fleet.csv"), "--scheduler", "tcp://[::1"],
            2,
            "--scheduler 'tcp://[::1': not an address",
        ),
        (
            "scheduler port out of range",
            ["fleet", str(tmp / "fleet.csv"), "--scheduler", "tcp://h:99999"],
            2,
            "--scheduler 'tcp://h:99999': not an address",
        ),
        (
            "output name too long",
            ["pareto", "paper-invacare", "--out", long_name],
            7,
            "a name longer than the file system allows",
        ),
        (
            "in-memory SQLite",
            ["explore", "paper-invacare", "--storage", "sqlite:///"],
            6,
            "an in-memory SQLite database keeps nothing",
        ),
        (
            "in-memory SQLite by name",
            ["explore", "paper-invacare", "--storage", "sqlite:///:memory:"],
            6,
            "in-memory SQLite",
        ),
        (
            "journal on a device",
            ["explore", "paper-invacare", "--storage", "journal:///dev/null", "--trials", "4", "--out", str(tmp / "e")],
            6,
            "is a character device, expected a journal file",
        ),
    ]


def test_system_and_input_errors_through_the_command_line(tmp_path, capsys, monkeypatch):
    """Each row through ``designer``: its exit code and one stderr line with the true reason (the issue's cases:
    a symlink loop, a character device, 100 000 levels of nesting, a 200 kB cell, a duplicate calibration column,
    a malformed --scheduler, an output name too long, sqlite:///; and more: a FIFO, UTF-16 data, an unclosed
    quote, a journal on a device)."""
    import designer.textfiles

    monkeypatch.setattr(designer.textfiles, "PIPE_WAIT_SECONDS", 0.2)  # a FIFO nobody writes to: not 5 s each
    failures = []
    for label, argv, code, text in _cases(tmp_path):
        got = main(argv)
        out, err = capsys.readouterr()
        if got != code or text not in err or err.count("\n") != 1 or "internal error" in err:
            failures.append((label, got, err.strip()[:300]))
    assert failures == []


def test_a_terminal_that_cannot_print_the_glyphs_gets_ascii():
    """With an ASCII-only standard output (a C locale), `designer evaluate` prints its table with ASCII for the
    glyphs (N*m/rad for N·m/rad, kg*m^2 for kg·m²) and exits 0; it was a UnicodeEncodeError."""
    env = {**os.environ, "PYTHONIOENCODING": "ascii", "LC_ALL": "C", "LANG": "C", "COLUMNS": "120"}
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "designer",
            "evaluate",
            "--trail",
            "1.5in",
            "--diameter",
            "6in",
            "--groove",
            "0",
            "--damping",
            "1.3",
        ],
        capture_output=True,
        text=True,
        encoding="ascii",
        errors="strict",
        env=env,
        cwd=ROOT,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert "N*m/rad" in proc.stdout and "kg*m^2" in proc.stdout


def test_a_full_disk_under_a_storage_is_the_storage_error():
    """A full disk while trials are stored (measured: an SQLite file on a 400 kB tmpfs filled after 412 trials and
    ended in optuna's StorageInternalError, exit 70) is the storage's one line, exit 6, "no space left on device";
    a journal's OSError likewise by its errno; an unrelated error stays what it is (a bug)."""
    import sqlalchemy.exc
    from optuna.exceptions import StorageInternalError

    from designer.studies.explore._runner import _storage_failure
    from designer.studies.explore._storage import parse_storage

    sqlite = parse_storage("sqlite:///study.db")
    try:
        try:
            raise sqlalchemy.exc.OperationalError("INSERT", {}, Exception("database or disk is full"))
        except sqlalchemy.exc.OperationalError as inner:
            raise StorageInternalError("An exception is raised during the commit.") from inner
    except StorageInternalError as outer:
        mapped = _storage_failure(outer, sqlite)
    assert mapped.exit_code == 6 and "storage sqlite:///study.db: OperationalError: no space left on device" in str(
        mapped
    )
    journal = _storage_failure(OSError(errno.ENOSPC, "No space left on device"), parse_storage("study.log"))
    assert journal.exit_code == 6 and "cannot write the journal (no space left on device)" in str(journal)
    bug = ZeroDivisionError()
    assert _storage_failure(bug, sqlite) is bug
