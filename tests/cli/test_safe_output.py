"""Issue 24, classes 1-3: nothing of the user's is lost, the user's setup is never an internal error, and
signals end a command cleanly.

1. Every command that writes, pointed at a folder of the user's (through a link to it, then at the folder
   itself), leaves every file of the user's byte-identical, the folder's mode unchanged, and writes only its
   own files; a regular file (or a path under one) is refused with exit 7 before any computing.
2. A full disk, a full or closed standard output, a read-only working folder, a folder where a file is
   expected, a negative seed and an endless problem file are one line with the documented exit code.
3. SIGINT during the imports, SIGTERM during a report's write, Ctrl-C in ``explore``: one line, exit 130/143,
   the previous report as it was, nothing temporary left.

The slow studies (``simulate --report`` takes minutes) are replaced by stand-ins that write the same file
names: what is tested is where and how the command writes, not the study.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from designer.cli import main
from designer.output import TEMP_PREFIX

ROOT = Path(__file__).resolve().parents[2]
INDOOR = str(ROOT / "problems" / "indoor-manual.toml")
INVACARE = str(ROOT / "problems" / "paper-invacare.toml")
SLIP = str(ROOT / "designer" / "data" / "examples" / "slip.csv")
USER_FILES = {"thesis.tex": b"\\documentclass{article}\n% my thesis\n", "src/data.txt": b"1 2 3\n"}
PYTHON_ENV = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")


# --------------------------------------------------------------------------- helpers


def _user_folder(path: Path) -> Path:
    path.mkdir(parents=True)
    for name, data in USER_FILES.items():
        (path / name).parent.mkdir(parents=True, exist_ok=True)
        (path / name).write_bytes(data)
    os.chmod(path, 0o750)
    return path


def _snapshot(folder: Path) -> dict:
    """Every entry under ``folder``: (sha256 of its bytes or None for a folder, its mode)."""
    out = {".": (None, stat.S_IMODE(folder.stat().st_mode))}
    for p in sorted(folder.rglob("*")):
        digest = hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None
        out[str(p.relative_to(folder))] = (digest, stat.S_IMODE(p.lstat().st_mode))
    return out


def _assert_user_files_kept(folder: Path, before: dict) -> None:
    after = _snapshot(folder)
    changed = {k: (before[k], after.get(k)) for k in before if k == "." or k in _user_names(before)}
    assert all(old == new for old, new in changed.values()), changed
    assert not [p.name for p in folder.rglob(f"{TEMP_PREFIX}*")]


def _user_names(snapshot: dict) -> set[str]:
    return {k for k in snapshot if k == "." or k.split("/")[0] in {n.split("/")[0] for n in USER_FILES}}


@pytest.fixture(scope="module")
def fleet_csv(tmp_path_factory) -> str:
    """A 3-chair fleet (``designer fleet --example 3``)."""
    path = tmp_path_factory.mktemp("fleet") / "fleet.csv"
    assert main(["fleet", "--example", "3", "--out", str(path)]) == 0
    return str(path)


@pytest.fixture
def fast_simulation_report(monkeypatch):
    """simulate --report's two studies (minutes of integration) replaced by stand-ins writing the same names."""
    import designer.cli.simulate as simulate
    import designer.report.limit_cycles as limit_cycles
    import designer.studies.dynamics as dynamics
    from designer.cli.simulate import ONSET_FILES
    from designer.studies.dynamics import OnsetStudy

    def onset_study(out_dir, progress=None, **kw):
        for name in ONSET_FILES:
            (Path(out_dir) / name).write_text(f"onset stand-in {name}\n")
        return OnsetStudy(rows=[], summary={"cases": 0, "all": {"min_error": 0.0, "max_error": 0.0}})

    def limit_cycle_files(study, folder):
        for name in limit_cycles.FILES:
            (Path(folder) / name).write_text(f"limit-cycle stand-in {name}\n")
        return list(limit_cycles.FILES)

    monkeypatch.setattr(dynamics, "write_simulation_report", onset_study)
    monkeypatch.setattr(simulate, "limit_cycle_study", lambda progress=None: {})
    monkeypatch.setattr(limit_cycles, "limit_cycle_files", limit_cycle_files)


def _commands(fleet: str) -> dict:
    """Every command that writes, as argv with OUT for the folder (or F for a file inside it)."""
    return {
        "pareto --force": ["pareto", INVACARE, "--points", "3", "--out", "OUT", "--force"],
        "robust": ["robust", INVACARE, "--points", "3", "--out", "OUT"],
        "fleet": ["fleet", fleet, "--problem", INDOOR, "--no-monte-carlo", "--out", "OUT"],
        "fleet --example": ["fleet", "--example", "3", "--out", "OUT/chairs.csv"],
        "simulate --report": ["simulate", "--report", "OUT"],
        "simulate --plot": ["simulate", "--trail", "2in", "--speed", "1m/s", "--duration", "2", "--plot", "OUT/t.png"],
        "calibrate --report/--plot/--snippet": [
            "calibrate",
            "slip",
            SLIP,
            "--report",
            "OUT",
            "--plot",
            "OUT/fit.png",
            "--snippet",
            "OUT/slip.toml",
        ],
        "calibrate examples": ["calibrate", "examples", "OUT"],
        "explore": ["explore", INVACARE, "--trials", "12", "--no-compare", "--out", "OUT"],
    }


def _argv(argv: list[str], out: Path) -> list[str]:
    return [a.replace("OUT", str(out)) for a in argv]


# --------------------------------------------------------------------------- 1. the user's folder


@pytest.mark.parametrize(
    "name",
    [
        "pareto --force",
        "robust",
        "fleet",
        "fleet --example",
        "simulate --report",
        "simulate --plot",
        "calibrate --report/--plot/--snippet",
        "calibrate examples",
        "explore",
    ],
)
def test_every_writing_command_keeps_the_users_folder(name, tmp_path, fleet_csv, fast_simulation_report, capsys):
    """A folder with the user's thesis.tex and src/data.txt (mode 750), written into by a command twice: through
    a link to it (the link is followed and stays a link), then at the folder itself (the previous output is
    replaced). Every file of the user's is byte-identical, nothing is missing, the folder's mode is still 750,
    the command's own files are there, and nothing temporary is left. (``designer fix`` writes nothing.)"""
    folder = _user_folder(tmp_path / "mine")
    link = tmp_path / "link"
    link.symlink_to(folder)
    before = _snapshot(folder)
    argv = _commands(fleet_csv)[name]
    assert main(_argv(argv, link)) == 0, capsys.readouterr().err
    assert link.is_symlink() and link.resolve() == folder.resolve()
    first = _snapshot(folder)
    written = set(first) - set(before)
    assert written, "the command wrote nothing"
    assert main(_argv(argv, folder)) == 0, capsys.readouterr().err
    _assert_user_files_kept(folder, before)
    assert set(_snapshot(folder)) - set(before) == written  # the same own files, replaced; nothing else
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "mine"]


def test_pareto_refuses_the_users_files_of_its_names_without_force(tmp_path, capsys):
    """``designer pareto --out`` a folder holding the user's own index.html (a name a report writes, that no
    manifest proves the tool's): refused before any work with exit 7, as every command refuses it; the folder is
    untouched.  With --force the report's files are written and the user's other files are left as they are."""
    folder = _user_folder(tmp_path / "mine")
    (folder / "index.html").write_text("<h1>my page</h1>")
    before = _snapshot(folder)
    assert main(["pareto", INVACARE, "--points", "3", "--out", str(folder)]) == 7
    err = capsys.readouterr().err
    assert "index.html" in err and "would replace" in err and err.count("\n") == 1, err
    assert _snapshot(folder) == before
    assert main(["pareto", INVACARE, "--points", "3", "--out", str(folder), "--force"]) == 0
    after = _snapshot(folder)
    assert all(after[k] == v for k, v in before.items() if k not in (".", "index.html"))


def test_the_users_files_of_the_same_name_are_never_replaced(tmp_path, fleet_csv, capsys):
    """A folder holding the user's own index.html and figures/ (names a report owns), that no command of this
    tool wrote: robust, fleet and calibrate refuse it with exit 7, naming the files, before computing; explore
    writes its two files beside them. Every file of the user's stays byte-identical."""
    folder = _user_folder(tmp_path / "mine")
    (folder / "index.html").write_text("<h1>my page</h1>")
    (folder / "figures").mkdir()
    (folder / "figures" / "plot.png").write_bytes(b"my figure")
    before = _snapshot(folder)
    for name in ("robust", "fleet", "calibrate --report/--plot/--snippet"):
        assert main(_argv(_commands(fleet_csv)[name], folder)) == 7, name
        err = capsys.readouterr().err
        assert "figures, index.html" in err and "would replace" in err and err.count("\n") == 1, err
        assert _snapshot(folder) == before, name
    assert main(_argv(_commands(fleet_csv)["explore"], folder)) == 0
    _assert_user_files_kept(folder, before)
    assert (folder / "index.html").read_text() == "<h1>my page</h1>" and (folder / "explore.json").is_file()


@pytest.mark.parametrize("under", [False, True])
def test_a_regular_file_is_refused_before_computing(under, tmp_path, fleet_csv, monkeypatch, capsys):
    """``--out`` (``--report``, ``--plot``, ``examples DIR``) naming a regular file, or a path under one: exit 7
    with one line naming the path, the file untouched, and the study never started (its function would fail)."""
    import designer.cli.fleet as fleet_cli
    import designer.cli.robust as robust_cli
    import designer.jobs as build
    import designer.studies.calibrate as calibrate
    import designer.studies.dynamics as dynamics
    import designer.studies.explore as explore

    def computed(*a, **k):
        raise AssertionError("computed before checking the output place")

    for module, attr in (
        (build, "compute_and_write"),
        (robust_cli, "robust_data"),
        (fleet_cli, "fleet_recommendations"),
        (fleet_cli, "example_fleet"),
        (calibrate, "calibrate_file"),
        (calibrate, "write_examples"),
        (dynamics, "write_simulation_report"),
        (explore, "explore"),
    ):
        monkeypatch.setattr(module, attr, computed)
    mine = tmp_path / "notes.txt"
    mine.write_text("precious")
    target = mine / "sub" if under else mine
    commands = _commands(fleet_csv)
    commands["pareto"] = ["pareto", INVACARE, "--out", "OUT"]
    for name, argv in commands.items():  # (--plot, --snippet and fleet --example name files under OUT)
        code = main(_argv(argv, target))
        err = capsys.readouterr().err
        assert code == 7, (name, err)
        assert err.count("\n") == 1 and "regular file" in err and str(mine) in err, (name, err)
        assert mine.read_text() == "precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_a_file_option_naming_a_folder_is_refused(tmp_path, capsys):
    """``fleet --example 5 --out DIR`` with DIR a folder: exit 7, one line saying to give a file name."""
    assert main(["fleet", "--example", "5", "--out", str(tmp_path)]) == 7
    err = capsys.readouterr().err
    assert "is a folder; give a file name" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- 2. the user's setup


def test_negative_seed_names_the_option(tmp_path, fleet_csv, capsys):
    """``--seed -1`` (numpy refuses it with a ValueError, which was exit 70) is exit 2 naming --seed."""
    for argv in (
        ["fleet", "--example", "5", "--seed", "-1", "--out", str(tmp_path / "f.csv")],
        ["fleet", fleet_csv, "--problem", INDOOR, "--seed", "-1", "--out", str(tmp_path / "r")],
        ["explore", INVACARE, "--seed", "-1", "--out", str(tmp_path / "e")],
    ):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.startswith("designer: error: --seed -1:") and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_endless_or_huge_problem_file_is_exit_3(tmp_path, capsys):
    """A problem file that is /dev/zero (which used to fill the memory) or 2 MB of text: exit 3 within a second;
    the device is refused unread as what it is (not a regular file), the large file names the 1 MB limit and its
    size (only the first 1 MB + 1 byte is read)."""
    big = tmp_path / "big.toml"
    big.write_text('name = "x"\n' + "# padding\n" * 200_000)
    for path, fragment in (
        ("/dev/zero", "/dev/zero: is a character device, expected a .toml problem file"),
        (str(big), f"larger than the 1 MB a problem file may have ({big.stat().st_size:,} bytes)"),
    ):
        t0 = time.perf_counter()
        assert main(["run", path]) == 3
        err = capsys.readouterr().err
        assert time.perf_counter() - t0 < 5
        assert fragment in err and err.count("\n") == 1


def _mount(*args) -> None:
    """Mount (root only); skip the test with the reason when this machine does not allow it."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("needs root and mount(8) to make a small or read-only file system (CI runs as root)")
    proc = subprocess.run(["mount", *args], capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"mount is not permitted here: {proc.stderr.strip()}")


@pytest.fixture
def tiny_disk(tmp_path):
    """A 64 kB tmpfs (a full disk within a few writes)."""
    disk = tmp_path / "disk"
    disk.mkdir()
    _mount("-t", "tmpfs", "-o", "size=64k", "tmpfs", str(disk))
    yield disk
    _umount(disk)


def _umount(path: Path) -> None:
    """Unmount ``path``; lazily if something still holds it, so no mount outlives the test."""
    if subprocess.run(["umount", str(path)], capture_output=True).returncode != 0:
        subprocess.run(["umount", "-l", str(path)], capture_output=True)


def _fill(disk: Path, leave: int) -> None:
    """Fill ``disk`` up, then free ``leave`` bytes (whole 4 kB pages on tmpfs)."""
    fd = os.open(disk / "filler", os.O_WRONLY | os.O_CREAT | os.O_APPEND)
    try:
        while os.write(fd, b"x" * 4096):
            pass
    except OSError:
        pass
    finally:
        os.close(fd)
    size = (disk / "filler").stat().st_size
    os.truncate(disk / "filler", max(0, size - leave))


def test_full_disk_is_exit_7_with_nothing_left(tiny_disk, capsys):
    """On a full file system (ENOSPC): ``pareto`` (figures larger than the disk) and ``explore`` (room for one
    of its two files) end with exit 7 and one line naming the path and "no space left"; no report folder, no
    half-written or temporary file remains (explore used to leave .explore.csv.XXXX and exit 70)."""
    _fill(tiny_disk, 4096 * 4)
    assert main(["pareto", INVACARE, "--points", "3", "--out", str(tiny_disk / "r")]) == 7
    err = capsys.readouterr().err
    assert f"--out {tiny_disk / 'r'}: no space left on device" in err and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in tiny_disk.iterdir()) == ["filler"]
    _fill(tiny_disk, 4096)
    assert main(["explore", INVACARE, "--trials", "12", "--no-compare", "--out", str(tiny_disk)]) == 7
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(f"designer: error: --out {tiny_disk}: no space left on device"), err
    assert sorted(p.name for p in tiny_disk.iterdir()) == ["filler"]


def test_full_standard_output_is_exit_7(tiny_disk):
    """``designer validate --json > FILE`` on a full disk, and ``> /dev/full``: exit 7 (was 70) with one line
    naming standard output and "no space left"; no traceback, no "Exception ignored" at exit."""
    _fill(tiny_disk, 0)
    targets = [tiny_disk / "checks.json"] + ([Path("/dev/full")] if Path("/dev/full").exists() else [])
    for target in targets:
        with open(target, "w") as out:
            proc = subprocess.run(
                [sys.executable, "-m", "designer", "validate", "--json"],
                stdout=out,
                stderr=subprocess.PIPE,
                text=True,
                env=PYTHON_ENV,
                timeout=300,
            )
        assert proc.returncode == 7, proc.stderr
        errors = [line for line in proc.stderr.splitlines() if not line.startswith("designer: warning: ")]
        assert len(errors) == 1 and errors[0].startswith("designer: error: standard output"), proc.stderr
        assert f"({target})" in errors[0] and "no space left" in errors[0]


@pytest.mark.parametrize(
    "argv",
    [
        ["validate", "--json"],
        ["run", INVACARE, "--json", "--no-cross-check"],
    ],
)
def test_closed_standard_output_ends_quietly(argv):
    """``designer validate --json | head -c5`` (BrokenPipeError, exit 70): the reader is gone before the output
    is written; the command ends quietly with exit 141 (128 + SIGPIPE, what a shell reports for a Unix tool
    that SIGPIPE ended), nothing on stderr (besides the command's own warnings)."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "designer", *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=PYTHON_ENV,
    )
    proc.stdout.close()  # the reader went away
    err = proc.stderr.read()
    proc.wait(timeout=300)
    assert proc.returncode == 141
    assert [line for line in err.splitlines() if not line.startswith("designer: warning: ")] == []


def test_fleet_in_a_read_only_folder_is_exit_7_before_computing(tmp_path, fleet_csv, monkeypatch, capsys):
    """``designer fleet FLEET.csv`` in a read-only working folder (default --out results/fleet/...): exit 7
    naming the folder and "Read-only file system", before the fleet is computed (it was exit 70, after)."""
    ro = tmp_path / "ro"
    ro.mkdir()
    shutil.copy(fleet_csv, ro / "fleet.csv")
    _mount("-o", "bind,ro", str(ro), str(ro))
    try:
        import designer.cli.fleet as fleet_cli

        monkeypatch.setattr(fleet_cli, "fleet_recommendations", lambda *a, **k: pytest.fail("computed first"))
        monkeypatch.chdir(ro)
        assert main(["fleet", "fleet.csv", "--problem", INDOOR, "--no-monte-carlo"]) == 7
        err = capsys.readouterr().err
        assert "--out results/fleet/fleet" in err and "Read-only file system" in err and err.count("\n") == 1
    finally:
        monkeypatch.chdir(tmp_path)
        _umount(ro)


# --------------------------------------------------------------------------- 3. signals


def _start(argv: list[str], **kw) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-X", "importtime", "-m", "designer", *argv],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env=PYTHON_ENV,
        **kw,
    )


@pytest.mark.parametrize(
    "module, signum, code",
    [
        ("designer.cli", signal.SIGINT, 130),  # imported by designer.entry under its start-up handler
        ("numpy._core", signal.SIGINT, 130),  # in the middle of NumPy's C extensions
        ("designer.studies.checks", signal.SIGTERM, 143),  # imported by the sub-command validate
    ],
)
def test_signal_during_the_imports_is_one_line(module, signum, code):
    """Ctrl-C (or SIGTERM) while the command's modules are imported (a 23-line traceback before): the import
    log (-X importtime) says when ``module`` is loaded, the signal is sent then; stderr has one line besides the
    import log, "designer: interrupted" (or "terminated"), and the exit code is 130 (143)."""
    proc = _start(["validate"])
    lines = []
    for line in proc.stderr:
        lines.append(line)
        if line.rstrip().endswith(f"| {module}") or line.rstrip().endswith(f"|   {module}"):
            break
        if module in line.split("|")[-1]:
            break
    proc.send_signal(signum)
    rest = proc.stderr.read()
    proc.wait(timeout=120)
    messages = [ln for ln in (lines + rest.splitlines(keepends=True)) if not ln.startswith("import time:")]
    assert proc.returncode == code, messages
    assert [m.strip() for m in messages] == [
        "designer: interrupted" if signum == signal.SIGINT else "designer: terminated (SIGTERM)"
    ]


_SIGTERM_IN_WRITE = """
import os, signal, sys
import designer.report.writer as writer
real = writer._render
def render(*args, **kwargs):
    os.kill(os.getpid(), signal.SIGTERM)  # a service manager stops the command while the report is written
    return real(*args, **kwargs)
writer._render = render
from designer.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_sigterm_during_the_report_write_keeps_the_previous_report(tmp_path):
    """SIGTERM while ``pareto`` renders its report (into its temporary folder): exit 143 with one line, the
    previous report byte-identical, no temporary folder left (it used to leave .rep.tmp-XXXX)."""
    out = tmp_path / "rep"
    assert main(["pareto", INVACARE, "--points", "3", "--out", str(out)]) == 0
    before = _snapshot(out)
    proc = subprocess.run(
        [sys.executable, "-c", _SIGTERM_IN_WRITE, "pareto", INVACARE, "--points", "4", "--out", str(out)],
        capture_output=True,
        text=True,
        env=PYTHON_ENV,
        timeout=300,
    )
    assert proc.returncode == 143, proc.stderr
    assert proc.stderr.strip().splitlines()[-1] == "designer: terminated (SIGTERM)"
    assert _snapshot(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


def test_interrupted_simulation_report_is_not_half_new(tmp_path, fast_simulation_report, monkeypatch, capsys):
    """``simulate --report DIR`` interrupted when the onset files are written and the limit-cycle study runs
    (it left a mix of new and previous files): DIR holds the previous files only, exit 143 for SIGTERM."""
    import designer.cli.simulate as simulate

    out = tmp_path / "sim"
    assert main(["simulate", "--report", str(out)]) == 0
    before = _snapshot(out)

    def study(progress=None):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(1)  # the handler raises here
        return {}

    monkeypatch.setattr(simulate, "limit_cycle_study", study)
    assert main(["simulate", "--report", str(out)]) == 143
    assert capsys.readouterr().err.strip().splitlines()[-1] == "designer: terminated (SIGTERM)"
    assert _snapshot(out) == before


def test_ctrl_c_in_explore_is_one_line(tmp_path, monkeypatch, capsys):
    """Ctrl-C during an explore trial: exit 130 and one line (how to resume), none of optuna's "Trial N failed
    ... KeyboardInterrupt" tracebacks (51 lines before); nothing written."""
    import designer.studies.explore._workers as workers

    real = workers._Evaluator.__call__
    calls = {"n": 0}

    def call(self, trial):
        calls["n"] += 1
        if calls["n"] == 8:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(1)  # the handler raises here, inside the trial
        return real(self, trial)

    monkeypatch.setattr(workers._Evaluator, "__call__", call)
    code = main(["explore", INVACARE, "--trials", "50", "--no-compare", "--json", "--out", str(tmp_path / "e")])
    err = capsys.readouterr().err
    assert code == 130
    assert err.strip().splitlines() == [err.strip().splitlines()[0]] and err.startswith("designer: interrupted")
    assert "Trial" not in err and "Traceback" not in err
    assert not (tmp_path / "e").exists()


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split(") ")[1][0] != "Z"  # a zombie has ended
    except (FileNotFoundError, IndexError):
        return False


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="reads the worker processes from /proc (Linux)")
def test_sigterm_stops_explore_workers_too(tmp_path):
    """``kill PID`` (SIGTERM to the parent only) of ``explore --workers 2``: the workers are stopped as well and the
    command ends within a minute with exit 143 and one line (the interpreter used to wait for the workers to finish
    the whole study)."""
    import sqlite3

    db = tmp_path / "study.db"
    proc = subprocess.Popen(
        [sys.executable, "-m", "designer", "explore", INVACARE, "--trials", "100000", "--no-compare", "--json"]
        + ["--workers", "2", "--storage", str(db), "--out", str(tmp_path / "out")],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env=PYTHON_ENV,
    )
    deadline = time.monotonic() + 240
    complete = 0
    while complete < 4 and time.monotonic() < deadline and proc.poll() is None:  # the workers are at work
        time.sleep(0.5)
        try:
            with sqlite3.connect(db) as con:
                complete = con.execute("select count(*) from trials where state = 'COMPLETE'").fetchone()[0]
        except sqlite3.Error:
            pass
    assert complete >= 4, "the workers did not start"
    children = Path(f"/proc/{proc.pid}/task/{proc.pid}/children").read_text().split()
    workers = [int(pid) for pid in children if "spawn_main" in Path(f"/proc/{pid}/cmdline").read_text()]
    assert len(workers) == 2
    proc.send_signal(signal.SIGTERM)
    err = proc.communicate(timeout=60)[1]
    assert proc.returncode == 143
    assert err.strip().splitlines()[-1].startswith("designer: interrupted; continue with --resume")
    time.sleep(1)
    assert not [pid for pid in workers if _alive(pid)]


def test_debug_still_shows_the_traceback(tmp_path):
    """``designer --debug`` shows the traceback of the user's-setup errors too (here exit 7 for a regular file)."""
    mine = tmp_path / "file"
    mine.write_text("x")
    proc = subprocess.run(
        [sys.executable, "-m", "designer", "--debug", "robust", INVACARE, "--out", str(mine)],
        capture_output=True,
        text=True,
        env=PYTHON_ENV,
        timeout=300,
    )
    assert proc.returncode != 0 and "Traceback (most recent call last)" in proc.stderr
    assert "designer.errors.OutputError" in proc.stderr and mine.read_text() == "x"


# --------------------------------------------------------------------------- the studio


def test_studio_writes_only_its_files_and_shows_failures_on_the_page(tmp_path, capsys):
    """The studio's "Save problem" and "Write report" into the user's folder keep every file of the user's;
    with --out under a regular file, ``designer studio`` stops at start with exit 7, and a callback whose
    write fails answers 200 with the one-line reason on the page (it was HTTP 500 and a console traceback)."""
    pytest.importorskip("dash")
    from designer.studio import state
    from designer.studio.app import create_app

    mine = tmp_path / "notes.txt"
    mine.write_text("precious")
    assert main(["studio", "--out", str(mine / "out"), "--no-browser", "--port", "0"]) == 7
    assert "lies under" in capsys.readouterr().err
    data, name = state.read_problem_data(state.default_problem_path())
    data = {**data, "pareto": {**data.get("pareto", {}), "points": 3}}
    _, merged = state.build_problem(data, state.control_values(data))

    def click(app, button):
        body = {
            "output": "..save-result.children...download.data..",
            "outputs": [{"id": "save-result", "property": "children"}, {"id": "download", "property": "data"}],
            "inputs": [
                {"id": "save", "property": "n_clicks", "value": int(button == "save")},
                {"id": "report", "property": "n_clicks", "value": int(button == "report")},
            ],
            "changedPropIds": [f"{button}.n_clicks"],
            "state": [{"id": "problem-data", "property": "data", "value": merged}],
        }
        response = app.server.test_client().post("/_dash-update-component", json=body)
        assert response.status_code == 200, response.data[:300]
        return json.dumps(json.loads(response.data)["response"]["save-result"])

    broken = create_app(data, name, mine / "out")
    for button in ("save", "report"):
        text = click(broken, button)
        assert "regular file" in text and str(mine) in text
    folder = _user_folder(tmp_path / "mine")
    before = _snapshot(folder)
    app = create_app(data, name, folder)
    assert "saved" in click(app, "save") and "report written" in click(app, "report")
    _assert_user_files_kept(folder, before)
    assert mine.read_text() == "precious"
