"""Issue 33, class 1: a user's file is never overwritten or mixed (designer/output.py).

Each test is a table of inputs through one code path of :mod:`designer.output`:

- :func:`designer.output.write_file` / :func:`check_file` (every single file a command writes or writes into):
  a file the tool did not write is refused with one line and exit 7, left byte-identical; a new or empty file,
  or the tool's own file of the same kind, is written;
- :func:`designer.output.check_folder` (every output folder): the filesystem root, the home folder and a folder
  holding the user's files of the names a command writes are refused by every writing command;
- :func:`designer.output.output_folder`'s commit (a write-ahead record under the folder's lock): a kill -9 at
  each of its steps leaves, after the next run, the old report or the new one byte for byte and no leftovers;
  the ownership is checked under the lock of the commit; a dead run's temporary folder is removed by the next
  run and a live run's is not.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from designer import output
from designer.cli import main
from designer.errors import OutputError
from designer.output import TEMP_PREFIX

ROOT = Path(__file__).resolve().parents[2]
INDOOR = str(ROOT / "problems" / "indoor-manual.toml")
INVACARE = str(ROOT / "problems" / "paper-invacare.toml")
EXAMPLES = ROOT / "designer" / "data" / "examples"
PYTHON_ENV = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
PNG = b"\x89PNG\r\n\x1a\n" + b"\x00" * 40  # the user's own picture (no metadata of this tool)


def _tree(folder: Path) -> dict[str, str | None]:
    """Every entry under ``folder``: sha256 of a file's bytes, None for a folder."""
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None
        for p in sorted(folder.rglob("*"))
    }


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob(f"{TEMP_PREFIX}*"))


# --------------------------------------------------------------------------- one file: write_file's rule


def _sqlite_with_table(path: Path) -> None:
    with sqlite3.connect(path) as con:
        con.execute("create table accounts (name text, balance real)")
        con.execute("insert into accounts values ('me', 12.5)")
    con.close()


def _journal_of_optuna(path: Path) -> None:
    assert (
        main(
            [
                "explore",
                INVACARE,
                "--trials",
                "4",
                "--no-compare",
                "--storage",
                str(path),
                "--out",
                str(path.parent / "e0"),
            ]
        )
        == 0
    )


SINGLE_FILES = {
    # row: (argv with F for the file, how the file is made before the run, expected exit code)
    "explore --storage: one line without newline": (
        ["explore", INVACARE, "--trials", "4", "--no-compare", "--storage", "F.log"],
        lambda p: p.write_bytes(b"my notes about the chair"),
        7,
    ),
    "explore --storage: one line with newline": (
        ["explore", INVACARE, "--trials", "4", "--no-compare", "--storage", "F.log"],
        lambda p: p.write_bytes(b"my notes about the chair\n"),
        7,
    ),
    "explore --storage: JSON lines of another tool": (
        ["explore", INVACARE, "--trials", "4", "--no-compare", "--storage", "F.log"],
        lambda p: p.write_bytes(b'{"event": "start"}\n{"event": "stop"}\n'),
        7,
    ),
    "explore --storage: a text file named .db": (
        ["explore", INVACARE, "--trials", "4", "--no-compare", "--storage", "F.db"],
        lambda p: p.write_bytes(b"not a database\n"),
        7,
    ),
    "explore --storage: the user's SQLite database": (
        ["explore", INVACARE, "--trials", "4", "--no-compare", "--storage", "F.db"],
        _sqlite_with_table,
        7,
    ),
    "explore --storage: an empty file": (
        ["explore", INVACARE, "--trials", "4", "--no-compare", "--storage", "F.log"],
        lambda p: p.write_bytes(b""),
        0,
    ),
    "explore --storage: optuna's journal (resumed)": (
        ["explore", INVACARE, "--trials", "6", "--no-compare", "--storage", "F.log", "--resume"],
        _journal_of_optuna,
        0,
    ),
    "calibrate --snippet: the user's problem file": (
        ["calibrate", "turning", str(EXAMPLES / "turning_tile.csv"), "--snippet", "F.toml"],
        lambda p: shutil.copy(INDOOR, p),
        7,
    ),
    "calibrate --snippet: a snippet of the tool the user edited": (
        ["calibrate", "turning", str(EXAMPLES / "turning_tile.csv"), "--snippet", "F.toml"],
        lambda p: (
            main(["calibrate", "turning", str(EXAMPLES / "turning_tile.csv"), "--snippet", str(p)]),
            p.write_text(p.read_text() + "carpet_factor = 1.4  # mine\n"),
        ),
        7,
    ),
    "calibrate --snippet: a snippet of the tool": (
        ["calibrate", "slip", str(EXAMPLES / "slip.csv"), "--snippet", "F.toml"],
        lambda p: main(["calibrate", "turning", str(EXAMPLES / "turning_tile.csv"), "--snippet", str(p)]),
        0,
    ),
    "calibrate --plot: the user's picture": (
        ["calibrate", "slip", str(EXAMPLES / "slip.csv"), "--plot", "F.png"],
        lambda p: p.write_bytes(PNG),
        7,
    ),
    "calibrate --plot: a figure of the tool": (
        ["calibrate", "slip", str(EXAMPLES / "slip.csv"), "--plot", "F.png"],
        lambda p: main(["calibrate", "slip", str(EXAMPLES / "slip.csv"), "--plot", str(p)]),
        0,
    ),
    "simulate --plot: the user's picture": (
        ["simulate", "--trail", "2in", "--speed", "1m/s", "--duration", "1", "--plot", "F.png"],
        lambda p: p.write_bytes(PNG),
        7,
    ),
    "simulate --plot: the user's SVG": (
        ["simulate", "--trail", "2in", "--speed", "1m/s", "--duration", "1", "--plot", "F.svg"],
        lambda p: p.write_text("<svg xmlns='http://www.w3.org/2000/svg'/>"),
        7,
    ),
    "fleet --example --out: the user's fleet": (
        ["fleet", "--example", "3", "--out", "F.csv"],
        lambda p: p.write_text("name,load_N\nmy chair,900\n"),
        7,
    ),
    "fleet --example --out: an example of the tool": (
        ["fleet", "--example", "4", "--out", "F.csv"],
        lambda p: main(["fleet", "--example", "3", "--out", str(p)]),
        0,
    ),
    "fleet --example --out: a new file": (
        ["fleet", "--example", "3", "--out", "F.csv"],
        lambda p: None,
        0,
    ),
}


@pytest.mark.parametrize("row", list(SINGLE_FILES))
def test_a_file_the_tool_did_not_write_is_never_written(row, tmp_path, capsys):
    """Every single-file option through write_file/check_file's rule: a file of the user's (text with and
    without a final newline, another tool's JSON lines, a database, a problem file, a picture, a fleet) is
    refused with exit 7 and one line naming the option and the file, and stays byte-identical; an empty or new
    file, or the tool's own file of the same kind (a journal of optuna, a snippet unchanged since the tool
    wrote it, a figure or an example it wrote), is written (exit 0: new bytes, or the file replaced by a
    rename, a new inode)."""
    argv, make, code = SINGLE_FILES[row]
    option = next(a for a in argv if a.startswith("--") and argv[argv.index(a) + 1].startswith("F."))
    name = argv[argv.index(option) + 1]
    path = tmp_path / f"mine{Path(name).suffix}"
    make(path)
    capsys.readouterr()
    before = path.read_bytes() if path.exists() else None
    inode = path.stat().st_ino if path.exists() else None
    argv = [str(path) if a == name else a for a in argv]
    if argv[0] == "explore":
        argv += ["--out", str(tmp_path / "explore-out")]
    assert main(argv) == code, capsys.readouterr().err
    err = capsys.readouterr().err
    if code == 7:
        edited = "edited" in row
        why = "is a file you edited since this tool wrote it" if edited else "is a file this tool did not write"
        assert err.count("\n") == 1 and f"{option} {path}: {why}" in err, err
        assert path.read_bytes() == before
    else:
        assert path.stat().st_size > 0 and (path.read_bytes() != before or path.stat().st_ino != inode)
    assert _leftovers(tmp_path) == []


def test_the_api_writers_follow_the_same_rule(tmp_path):
    """Front.to_csv (the public API) goes through the same rule: the user's CSV is refused (OutputError naming
    the file) and kept; a front CSV it wrote is replaced."""
    from designer import load_problem, pareto_front

    front = pareto_front(load_problem(INVACARE), points=3)
    mine = tmp_path / "mine.csv"
    mine.write_text("a,b\n1,2\n")
    with pytest.raises(OutputError, match="mine.csv: is a file this tool did not write"):
        front.to_csv(mine)
    assert mine.read_text() == "a,b\n1,2\n"
    ours = tmp_path / "front.csv"
    front.to_csv(ours)
    first = ours.read_text()
    front.to_csv(ours)
    assert ours.read_text() == first and first.startswith("trail_in,diameter_in,groove_in,damping_N_m_per_rad,")
    # the user edits the tool's front CSV: it is the user's now, refused and kept
    ours.write_text(first + "# my note\n")
    with pytest.raises(OutputError, match="front.csv: is a file you edited since this tool wrote it"):
        front.to_csv(ours)
    assert ours.read_text() == first + "# my note\n"


# --------------------------------------------------------------------------- folders: one rule for every command


def _fleet_csv(tmp: Path) -> str:
    path = tmp / "chairs" / "fleet.csv"
    path.parent.mkdir(exist_ok=True)
    if not path.exists():
        assert main(["fleet", "--example", "3", "--out", str(path)]) == 0
    return str(path)


FOLDER_COMMANDS = {
    # command: (argv with OUT, exit code for a foreign folder holding the names it writes)
    "pareto": (["pareto", INVACARE, "--points", "3", "--out", "OUT"], 7),
    "robust": (["robust", INVACARE, "--points", "3", "--out", "OUT"], 7),
    "fleet": (["fleet", "FLEET", "--problem", INDOOR, "--no-monte-carlo", "--out", "OUT"], 7),
    "simulate --report": (["simulate", "--report", "OUT"], 7),
    "calibrate --report": (["calibrate", "slip", str(EXAMPLES / "slip.csv"), "--report", "OUT"], 7),
    "calibrate examples": (["calibrate", "examples", "OUT"], 7),
    "explore --out": (["explore", INVACARE, "--trials", "4", "--no-compare", "--out", "OUT"], 7),
    "studio --out": (["studio", "--out", "OUT", "--no-browser", "--port", "0"], None),
}
FILE_COMMANDS = {
    # command: (argv with OUT for the file, exit code for a folder given as the file: 2 where the name is
    # checked first (a figure needs .png, .svg or .pdf), else 7)
    "calibrate --plot": (["calibrate", "slip", str(EXAMPLES / "slip.csv"), "--plot", "OUT"], 2),
    "calibrate --snippet": (["calibrate", "slip", str(EXAMPLES / "slip.csv"), "--snippet", "OUT"], 7),
    "simulate --plot": (["simulate", "--trail", "2in", "--speed", "1m/s", "--duration", "1", "--plot", "OUT"], 2),
    "fleet --example --out": (["fleet", "--example", "3", "--out", "OUT"], 7),
    "explore --storage": (["explore", INVACARE, "--trials", "4", "--no-compare", "--storage", "journal://OUT"], 7),
}
FOREIGN = {  # a user's folder holding names the command writes
    "pareto": ["index.html"],
    "robust": ["index.html", "robust.md"],
    "fleet": ["fleet.csv", "index.html"],
    "simulate --report": ["onset.csv", "report.md"],
    "calibrate --report": ["index.html", "report.md"],
    "calibrate examples": ["slip.csv"],
    "explore --out": ["explore.csv"],
}


@pytest.fixture
def home(tmp_path, monkeypatch):
    """A home folder of its own (HOME), holding the user's notes."""
    folder = tmp_path / "home"
    folder.mkdir()
    (folder / "notes.txt").write_text("mine")
    monkeypatch.setenv("HOME", str(folder))
    return folder


@pytest.mark.parametrize("place", ["/", "~"])
@pytest.mark.parametrize("command", [*FOLDER_COMMANDS, *FILE_COMMANDS])
def test_root_and_home_are_refused_by_every_command(command, place, tmp_path, home, capsys):
    """Every writing command (output folders and output files) pointed at the filesystem root or the home folder
    (as root too, where both are writable): refused with one line naming the place (exit 7: "is the filesystem
    root", "is your home folder", "is a folder" for a file option; exit 2 where a figure's name is checked
    first), nothing written there (the root's and the home folder's listings unchanged)."""
    argv, code = FOLDER_COMMANDS[command] if command in FOLDER_COMMANDS else FILE_COMMANDS[command]
    code = 7 if command in FOLDER_COMMANDS else code
    target = "/" if place == "/" else str(home)
    argv = [_fleet_csv(tmp_path) if a == "FLEET" else a.replace("OUT", target) for a in argv]
    root_before, home_before = sorted(os.listdir("/")), _tree(home)
    assert main(argv) == code, capsys.readouterr().err
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and target in err, err
    reason = "the filesystem root" if place == "/" else "your home folder"
    assert reason in err if command in FOLDER_COMMANDS else ("is a folder" in err or "expected a .png" in err), err
    assert sorted(os.listdir("/")) == root_before and _tree(home) == home_before


@pytest.mark.parametrize("command", list(FOREIGN))
def test_a_folder_with_the_users_files_is_refused_by_every_command(command, tmp_path, capsys):
    """A folder of the user's holding files of the names the command writes: refused before computing (exit 7,
    pareto too), every file byte-identical, nothing temporary left."""
    folder = tmp_path / "mine"
    folder.mkdir()
    for name in FOREIGN[command]:
        (folder / name).write_text(f"the user's {name}\n")
    before = _tree(folder)
    argv, code = FOLDER_COMMANDS[command]
    argv = [_fleet_csv(tmp_path) if a == "FLEET" else str(folder) if a == "OUT" else a for a in argv]
    assert main(argv) == code, capsys.readouterr().err
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(folder) in err
    assert _tree(folder) == before


# --------------------------------------------------------------------------- the commit of a report


_HOOKED = """
import os, signal, sys, time
from pathlib import Path
import designer.output as output
target, step = sys.argv[1], sys.argv[2]
def hook(name):
    if name == step:
        if os.environ.get("PAUSE"):
            Path(os.environ["PAUSE"]).write_text(str(os.getpid()))
            while not Path(os.environ["PAUSE"] + ".go").exists():
                time.sleep(0.05)
        else:
            os.kill(os.getpid(), signal.SIGKILL)
    with open(os.environ["STEPS"], "a") as fh:
        fh.write(name + "\\n")
output._step_hook = hook
if sys.argv[3] == "copy":  # the new report's files, committed as designer pareto commits them
    from designer.report.files import REPORT_OWNED
    import shutil
    with output.output_folder(target, REPORT_OWNED, command="designer pareto") as stage:
        for p in Path(sys.argv[4]).iterdir():
            (shutil.copytree if p.is_dir() else shutil.copy2)(p, stage / p.name)
    sys.exit(0)
from designer.cli import main
sys.exit(main(sys.argv[3:]))
"""


def _finish(proc: subprocess.Popen, timeout: float = 120) -> tuple[int, str]:
    """(exit code, stderr) of a process started by :func:`_hooked` (negative: killed by that signal)."""
    err = proc.communicate(timeout=timeout)[1]
    return proc.returncode, err


def _hooked(target: Path, step: str, argv: list[str], steps: Path, **env) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-c", _HOOKED, str(target), step, *argv],
        env={**PYTHON_ENV, "STEPS": str(steps), **env},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )


@pytest.fixture(scope="module")
def two_reports(tmp_path_factory) -> tuple[Path, Path]:
    """Two Pareto reports of indoor-manual (3 and 4 points): every file differs between them; the new one
    lacks run.json (an owned name the commit must remove), the old one has a folder of the user's."""
    base = tmp_path_factory.mktemp("reports")
    for name, points in (("old", "3"), ("new", "4")):
        assert main(["pareto", INDOOR, "--points", points, "--out", str(base / name)]) == 0
    (base / "old" / "stale-figure-dir").mkdir()  # not a name a report owns: must survive as it is
    (base / "new" / "run.json").unlink()  # an owned name the new run does not write: the old one is removed
    return base / "old", base / "new"


def test_a_kill_at_each_step_of_the_commit_leaves_the_old_or_the_new_report(two_reports, tmp_path):
    """A report folder (the old report beside the user's notes.txt and explore.csv) receives the new report; the
    committing process is killed with SIGKILL at each step of the commit in turn (every one of them:
    the temporary folder made, the record written, each previous entry set aside, each new one renamed in,
    the old run.json removed, the commit point, each previous entry dropped, the end).  After the next run touches the folder (check_folder, as every command does first)
    the folder holds the old report or the new one, byte-identical, the user's files unchanged, and no
    temporary entry; before the commit point it is the old one, after it the new one."""
    old, new = two_reports
    steps_file = tmp_path / "steps"
    folder = tmp_path / "rep"
    shutil.copytree(old, folder)
    proc = _hooked(folder, "none", ["copy", str(new)], steps_file)  # a full commit: the list of the steps
    assert _finish(proc) == (0, "")
    steps = steps_file.read_text().splitlines()
    assert steps[:2] == ["staged", "record"] and steps[-1] == "done" and "commit" in steps, steps
    assert {"aside figures", "install index.html", "remove run.json", "drop front.json"} <= set(steps), steps
    mine = {"notes.txt": "my notes\n", "explore.csv": "trial,J\n"}
    expected = {"old": None, "new": None}
    for k, step in enumerate(steps):
        shutil.rmtree(folder)
        shutil.copytree(old, folder)
        for name, text in mine.items():
            (folder / name).write_text(text)
        if expected["old"] is None:
            expected["old"] = _tree(folder)
        steps_file.unlink(missing_ok=True)
        proc = _hooked(folder, step, ["copy", str(new)], steps_file)
        assert _finish(proc)[0] == -signal.SIGKILL, step
        output.check_folder(folder)  # the next run
        after = _tree(folder)
        which = "new" if k >= steps.index("commit") else "old"
        if which == "new" and expected["new"] is None:
            expected["new"] = after
        assert after == expected[which], (k, step)
        assert _leftovers(folder) == [], (k, step)
    assert expected["old"] != expected["new"]
    for name in new.iterdir():  # the new report is the new one, byte for byte (the manifest: the folder's own)
        assert name.name == output.MANIFEST or expected["new"][name.name] == _tree(new)[name.name]
    assert "run.json" in expected["old"] and "run.json" not in expected["new"] and "stale-figure-dir" in expected["new"]
    assert expected["new"]["notes.txt"] == expected["old"]["notes.txt"]


def test_ownership_is_checked_under_the_lock_of_the_commit(tmp_path):
    """pareto --out cc paused after it made its temporary folder; robust --out cc runs to its end; pareto
    resumes: it refuses (exit 7, naming the files robust wrote) and cc holds robust's whole report, nothing of
    pareto's, and no temporary entry."""
    cc = tmp_path / "cc"
    pause = tmp_path / "paused"
    proc = _hooked(
        cc, "staged", ["pareto", INVACARE, "--points", "3", "--out", str(cc)], tmp_path / "s", PAUSE=str(pause)
    )
    deadline = time.monotonic() + 300
    while not pause.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)
    assert pause.exists(), _finish(proc)
    assert main(["robust", INVACARE, "--points", "3", "--out", str(cc)]) == 0
    robust = {k: v for k, v in _tree(cc).items() if not k.startswith(TEMP_PREFIX)}  # pareto's folder aside
    assert len(robust) < len(_tree(cc))
    Path(str(pause) + ".go").write_text("")
    code, err = _finish(proc)
    assert code == 7, err
    assert "index.html" in err and "would replace" in err and len(err.strip().splitlines()) == 1, err
    assert _tree(cc) == robust and not (cc / "front.json").exists() and _leftovers(cc) == []


def test_leftovers_of_dead_runs_are_removed_and_a_live_runs_are_kept(tmp_path, capsys):
    """A run killed (SIGKILL) while computing leaves its temporary folder; the next run in that folder removes it.
    A run that is alive (paused after making its temporary folder) keeps its folder while another run
    recovers the same place, and then commits its report."""
    out = tmp_path / "rep"
    proc = _hooked(out, "staged", ["robust", INVACARE, "--points", "3", "--out", str(out)], tmp_path / "s")
    assert _finish(proc, 300)[0] == -signal.SIGKILL
    assert len(_leftovers(out)) == 1  # the dead run's temporary folder
    pause = tmp_path / "paused"
    live = _hooked(
        out, "staged", ["robust", INVACARE, "--points", "3", "--out", str(out)], tmp_path / "s", PAUSE=str(pause)
    )
    deadline = time.monotonic() + 300
    while not pause.exists() and live.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)
    assert pause.exists(), _finish(live)
    assert len(_leftovers(out)) == 1  # the live run's (the dead run's removed by the live run's own start)
    output.recover(out)  # another run touches the folder meanwhile
    assert len(_leftovers(out)) == 1
    Path(str(pause) + ".go").write_text("")
    assert _finish(live)[0] == 0
    assert _leftovers(out) == [] and (out / "robust.json").is_file()
    json.loads((out / "robust.json").read_text())


def test_the_kill_test_catches_a_commit_without_recovery(two_reports, tmp_path, monkeypatch):
    """Planted fault: the same kill -9 between two renames of the commit, with the recovery switched off
    (no roll-back of the record): the folder is a mixture, the new front.csv beside the old front.json --
    the check of the test above fails on it."""
    old, new = two_reports
    folder = tmp_path / "rep"
    shutil.copytree(old, folder)
    proc = _hooked(folder, "install front.csv", ["copy", str(new)], tmp_path / "steps")
    assert _finish(proc)[0] == -signal.SIGKILL
    monkeypatch.setattr(output, "_recover_records", lambda folder: None)
    output.check_folder(folder)
    after = _tree(folder)
    assert after["front.csv"] == _tree(new)["front.csv"] and after["front.json"] == _tree(old)["front.json"]


def test_the_studios_save_follows_the_same_rule(tmp_path):
    """The studio's "Save problem" (write_file's rule, the studio's row of the table): over the user's own
    problem file of that name it answers the one-line refusal on the page and leaves the file byte-identical;
    into an empty folder it saves, and saving again replaces its own file (its first line names the studio)."""
    pytest.importorskip("dash")
    from designer.studio import state
    from designer.studio.app import create_app

    data, name = state.read_problem_data(state.default_problem_path())
    _, merged = state.build_problem(data, state.control_values(data))

    def save(folder: Path) -> str:
        body = {
            "output": "..save-result.children...download.data..",
            "outputs": [{"id": "save-result", "property": "children"}, {"id": "download", "property": "data"}],
            "inputs": [
                {"id": "save", "property": "n_clicks", "value": 1},
                {"id": "report", "property": "n_clicks", "value": 0},
            ],
            "changedPropIds": ["save.n_clicks"],
            "state": [{"id": "problem-data", "property": "data", "value": merged}],
        }
        response = create_app(data, name, folder).server.test_client().post("/_dash-update-component", json=body)
        assert response.status_code == 200
        return json.dumps(json.loads(response.data)["response"]["save-result"])

    mine = tmp_path / "mine"
    mine.mkdir()
    user_file = mine / f"{merged['name']}.toml"
    shutil.copy(INDOOR, user_file)
    before = user_file.read_bytes()
    assert "is a file this tool did not write" in save(mine)
    assert user_file.read_bytes() == before
    ours = tmp_path / "ours"
    assert "saved" in save(ours) and "saved" in save(ours)
    saved = ours / f"{merged['name']}.toml"
    assert saved.read_text().startswith("# written by designer studio (sha256 ")


def test_a_file_of_an_earlier_release_without_a_manifest_is_refused_with_the_way_on(tmp_path):
    """A result file of the tool's own from before manifests (release 3's onset.json) proves nothing: it is
    refused like a file of the user's (OutputError naming it and saying how to proceed) and kept byte-identical;
    once removed the file is written, with its manifest entry, and the next run replaces it."""
    from designer.studies.dynamics._onset_study import ONSET_KINDS

    kind = ONSET_KINDS["onset.json"]
    old = tmp_path / "onset.json"
    old.write_text('{\n  "summary": {\n    "single_tread_by_trail_inertia": {}\n  }\n}\n', encoding="utf-8")
    before = old.read_bytes()
    with pytest.raises(OutputError, match="onset.json: is a file this tool did not write.*remove it"):
        output.write_file(old, "{}\n", "--report", "onset.json", kind=kind)
    assert old.read_bytes() == before
    old.unlink()
    output.write_file(old, "{}\n", "--report", "onset.json", kind=kind)
    output.write_file(old, "{ }\n", "--report", "onset.json", kind=kind)
    assert old.read_text(encoding="utf-8") == "{ }\n"
    assert output.read_manifest(tmp_path)["onset.json"]["sha256"] == hashlib.sha256(b"{ }\n").hexdigest()
