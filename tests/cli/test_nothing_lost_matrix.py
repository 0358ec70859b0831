"""Issue 42, class 1 and 2: every writer x every kind of path already there, one table of expected outcomes.

Every writing command (each ``--out``, ``--report``, ``--snippet``, ``--plot``, ``--storage``, ``--example``,
``calibrate examples DIR``, ``init``, :meth:`Front.to_csv`, the studio's "Save problem" and "Write report"
through the function their buttons call) is run, in-process and with its cheapest input, against each kind of
path (:data:`KINDS`).  :data:`EXPECTED` says the exit code of every cell: 0 written, 7 refused (the output's
setup), 6 refused (a storage's, docs/commands.md), n/a where the kind means nothing for the writer.  In every
cell nothing of the user's changes (each file the user made or edited: its bytes and its mtime), a refused cell
changes no file at all, a written one leaves its file, and no temporary entry is left.

The ownership rule under test (:mod:`designer.output`): a file or folder is the tool's only while the manifest
of its folder (``.designer-manifest.json``) holds each of its files with the sha256 of its present bytes, written
by the same command; recovery acts only on a commit record whose temporary folder is there.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import uuid
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from designer.cli import main
from designer.errors import DesignerError
from designer.output import MANIFEST, TEMP_PREFIX, entry_digest

ROOT = Path(__file__).resolve().parents[2]
INDOOR = str(ROOT / "problems" / "indoor-manual.toml")
INVACARE = str(ROOT / "problems" / "paper-invacare.toml")
SLIP = str(ROOT / "designer" / "data" / "examples" / "slip.csv")

KINDS = (
    "absent",
    "own",
    "own edited",
    "user's file",
    "user's folder",
    "planted record",
    "link to absent",
    "link to own",
    "link to own edited",
    "link to user's file",
    "link to user's folder",
    "loop of links",
    "FIFO",
    "character device",
    "read-only folder",
    "full filesystem",
)
"""The kinds of path a writer meets: the target absent; written by this writer before (own), and then edited by
the user; a file or a folder of the user's of that name; a commit record planted beside it (naming a file of the
user's, with the digest of that file, and no temporary folder); a link to each of those, and a link to
nothing; l1 -> l2 -> l1; a FIFO nothing reads; /dev/null; a place on a read-only file system; a full one (a
64 kB tmpfs, filled)."""


@dataclass(frozen=True)
class Writer:
    """One writer: its target's name (``t`` a folder, ``t.csv`` a file) and how it runs on a target."""

    target: str
    run: Callable[[Path], int]
    storage: bool = False  # a storage: its refusals are exit 6, its own file is proved by optuna's content
    new_only: bool = False  # init: never over anything


def _cli(*argv: str) -> Callable[[Path], int]:
    def run(target: Path) -> int:
        return main([str(target) if a == "T" else a for a in argv])

    return run


def _api(call: Callable[[Path], object]) -> Callable[[Path], int]:
    def run(target: Path) -> int:
        try:
            call(target)
        except DesignerError as exc:  # the line the studio shows on its page, the API's one-line error
            print(f"designer: error: {exc}", file=sys.stderr)
            return exc.exit_code
        return 0

    return run


def _storage() -> Callable[[Path], int]:
    def run(target: Path) -> int:
        out = Path(tempfile.mkdtemp(prefix="explore-out-"))  # explore.csv/json: not the cell's subject
        code = main(
            ["explore", INVACARE, "--trials", "2", "--no-compare", "--storage", str(target)]
            + ["--study", f"s{uuid.uuid4().hex[:8]}", "--out", str(out)]
        )
        shutil.rmtree(out, ignore_errors=True)
        return code

    return run


def _cheap_simulation(monkeypatch) -> None:
    """simulate --report's two studies replaced by stand-ins that write a file each (minutes of simulation
    otherwise); the report's folder handling, the subject here, is the command's own."""
    import designer.cli.simulate as cli_simulate
    import designer.report.limit_cycles as limit_cycles
    from designer.studies import dynamics

    class Result:
        summary = {"cases": 1, "all": {"min_error": 0.0, "max_error": 0.0}}

    def onset(folder, progress=None):
        (Path(folder) / "onset.csv").write_text("trail_in,inertia_kgm2\n1,2\n")
        return Result()

    def files(study, folder):
        (Path(folder) / "bifurcation.json").write_text("{}\n")
        return ["bifurcation.json"]

    monkeypatch.setattr(dynamics, "write_simulation_report", onset)
    monkeypatch.setattr(cli_simulate, "limit_cycle_study", lambda progress=None: None)
    monkeypatch.setattr(limit_cycles, "limit_cycle_files", files)


def _front():
    from designer import load_problem, pareto_front

    return pareto_front(load_problem(INVACARE), points=3)


def _studio(trigger: str) -> Callable[[Path], object]:
    def call(target: Path):
        pytest.importorskip("dash")
        from designer.studio import state
        from designer.studio.app import _save_or_report

        data, _ = state.read_problem_data(state.default_problem_path())
        _, merged = state.build_problem(data, state.control_values(data))
        merged = {**merged, "name": Path(target).stem, "pareto": {**merged.get("pareto", {}), "points": 3}}
        return _save_or_report(trigger, merged, Path(target).parent)

    return call


FRONT: list = []

WRITERS = {
    "pareto --out": Writer("t", _cli("pareto", INVACARE, "--points", "3", "--out", "T")),
    "robust --out": Writer("t", _cli("robust", INVACARE, "--points", "3", "--out", "T")),
    "fleet --out": Writer("t", _cli("fleet")),  # its FLEET.csv made by a fixture (the test runs it)
    "simulate --report": Writer("t", _cli("simulate", "--report", "T")),
    "calibrate --report": Writer("t", _cli("calibrate", "slip", SLIP, "--report", "T")),
    "calibrate examples DIR": Writer("t", _cli("calibrate", "examples", "T")),
    "explore --out": Writer("t", _cli("explore", INVACARE, "--trials", "2", "--no-compare", "--out", "T")),
    "studio Write report": Writer("t", _api(_studio("report"))),
    "calibrate --plot": Writer("t.png", _cli("calibrate", "slip", SLIP, "--plot", "T")),
    "calibrate --snippet": Writer("t.toml", _cli("calibrate", "slip", SLIP, "--snippet", "T")),
    "simulate --plot": Writer("t.png", _cli("simulate", "--trail", "2in", "--speed", "1m/s", "--plot", "T")),
    "fleet --example --out": Writer("t.csv", _cli("fleet", "--example", "3", "--out", "T")),
    "spec --out": Writer("t.html", _cli("spec", INVACARE, "--out", "T")),
    "explore --storage FILE.log": Writer("t.log", _storage(), storage=True),
    "explore --storage FILE.db": Writer("t.db", _storage(), storage=True),
    "init PATH": Writer("t.toml", _cli("init", "T", "--defaults"), new_only=True),
    "Front.to_csv": Writer("t.csv", _api(lambda t: (FRONT or FRONT.append(_front()) or FRONT)[0].to_csv(t))),
    "studio Save problem": Writer("t.toml", _api(_studio("save"))),
}

_ROW = {k: 0 if k in ("absent", "own", "planted record", "link to own") else 7 for k in KINDS}
"""The rule every writer follows: written where the path is new, the tool's own and unedited (through a link
too), or beside a planted record (which is not acted on); refused everywhere else."""

EXPECTED: dict[str, dict[str, int | None]] = {}
for _name, _w in WRITERS.items():
    row = dict(_ROW)  # a folder writer: /dev/null and a FIFO are not folders (7)
    if _w.new_only:  # init: only a path where nothing is
        row = {k: 0 if k in ("absent", "planted record") else 7 for k in KINDS}
    elif _w.target.startswith("t."):
        row["character device"] = 0  # a single file written in place into /dev/null (as into /dev/stdout)
    if _name.endswith("--plot"):
        row["character device"] = 2  # a figure's name is checked first: /dev/null has no .png, .svg or .pdf
    if _w.storage:  # a storage: exit 6 for every refusal; optuna's file is proved by its content, not edited
        row = {k: 6 if v == 7 else v for k, v in row.items()}
        row["character device"] = 6  # /dev/null is no journal or database
        row["own edited"] = row["link to own edited"] = None
    EXPECTED[_name] = row


# --------------------------------------------------------------------------- making each kind of path


def _own(writer: Writer, template: Path, place: Path) -> None:
    """A copy of what ``writer`` wrote (the target and its folder's manifest) at ``place``."""
    place.parent.mkdir(parents=True, exist_ok=True)
    src = template / writer.target
    (shutil.copytree if src.is_dir() else shutil.copy2)(src, place)
    if (template / MANIFEST).exists() and not src.is_dir():
        shutil.copy2(template / MANIFEST, place.parent / MANIFEST)


def _edit(path: Path) -> Path:
    """The user edits the tool's file (a folder: its first file): returns the edited file."""
    if path.is_dir():
        path = sorted(p for p in path.rglob("*") if p.is_file() and p.name != MANIFEST)[0]
    with open(path, "ab") as fh:
        fh.write(b"\n<!-- mine -->\n")
    return path


def _users_folder(path: Path, writer: Writer, template: Path) -> list[Path]:
    """A folder of the user's at ``path``: for a folder writer, files of the user's of every name it writes
    (a figures/ with the user's picture in it); for a file writer, a folder where the file would go."""
    path.mkdir(parents=True)
    made = []
    names = [p.name for p in (template / writer.target).iterdir()] if (template / writer.target).is_dir() else []
    for name in names or ["notes.txt"]:
        if name == MANIFEST:
            continue
        if (template / writer.target / name).is_dir():
            (path / name).mkdir()
            made.append(path / name / "bench.jpg")
        else:
            made.append(path / name)
        made[-1].write_bytes(b"the user's own " + name.encode())
    return made


def _plant(folder: Path) -> list[Path]:
    """A commit record of the tool's form in ``folder``, naming the user's notes.txt (with the digest of its
    bytes) as an entry it installed, without its temporary folder: the next run must leave notes.txt alone."""
    folder.mkdir(parents=True, exist_ok=True)
    notes = folder / "notes.txt"
    notes.write_text("the user's notes\n")
    record = {
        "stage": f"{TEMP_PREFIX}gone",
        "install": [["notes.txt", None]],
        "remove": [],
        "digests": {"notes.txt": entry_digest(notes)},
    }
    (folder / f"{TEMP_PREFIX}commit-0badc0de.json").write_text(json.dumps(record))
    return [notes]


@contextlib.contextmanager
def _tmpfs(where: Path, readonly: bool) -> Iterator[Path]:
    """A 64 kB tmpfs at ``where`` (read-only, or filled to the last byte); skips when it cannot be mounted."""
    where.mkdir(parents=True)
    made = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(where)], capture_output=True)
    if made.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({made.stderr.decode().strip() or 'not root'})")
    try:
        if readonly:
            subprocess.run(["mount", "-o", "remount,ro", str(where)], check=True)
        else:
            fd = os.open(where / "filler", os.O_WRONLY | os.O_CREAT)
            with contextlib.suppress(OSError):
                while os.write(fd, b"\0" * 4096):
                    pass
            os.close(fd)
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], check=False)


def _make(kind: str, writer: Writer, template: Path, work: Path, stack: contextlib.ExitStack):
    """(the target to give the writer, the files of the user's there) for ``kind``."""
    target = work / writer.target
    inner = work / "sub" / writer.target
    users: list[Path] = []
    if kind == "own":
        _own(writer, template, target)
    elif kind == "own edited":
        _own(writer, template, target)
        users.append(_edit(target))
    elif kind == "user's file":
        target.write_bytes(b"the user's own file\n")
        users.append(target)
    elif kind == "user's folder":
        users += _users_folder(target, writer, template)
    elif kind == "planted record":
        users += _plant(target if not writer.target.startswith("t.") else work)
    elif kind.startswith("link to"):
        (work / "sub").mkdir()
        if kind == "link to own":
            _own(writer, template, inner)
        elif kind == "link to own edited":
            _own(writer, template, inner)
            users.append(_edit(inner))
        elif kind == "link to user's file":
            inner.write_bytes(b"the user's own file\n")
            users.append(inner)
        elif kind == "link to user's folder":
            users += _users_folder(inner, writer, template)
        target.symlink_to(Path("sub") / writer.target)
    elif kind == "loop of links":
        target.symlink_to("l2")
        (work / "l2").symlink_to(writer.target)
    elif kind == "FIFO":
        os.mkfifo(target)
    elif kind == "character device":
        target = Path("/dev/null")
    elif kind in ("read-only folder", "full filesystem"):
        place = stack.enter_context(_tmpfs(work / "mnt", readonly=kind == "read-only folder"))
        target = place / writer.target
    return target, users


def _files(work: Path) -> dict[str, tuple[str, int]]:
    """Every file under ``work`` (not following links): its sha256 and mtime."""
    out = {}
    for root, _, names in os.walk(work):
        for name in names:
            p = Path(root) / name
            if p.is_file() and not p.is_symlink():
                out[str(p.relative_to(work))] = (hashlib.sha256(p.read_bytes()).hexdigest(), p.stat().st_mtime_ns)
    return out


def _leftovers(work: Path) -> list[str]:
    return sorted(str(p.relative_to(work)) for p in work.rglob(f"{TEMP_PREFIX}*") if "commit-0badc0de" not in p.name)


@pytest.fixture
def fleet_csv(tmp_path_factory) -> str:
    folder = tmp_path_factory.mktemp("fleet")
    assert main(["fleet", "--example", "2", "--out", str(folder / "fleet.csv")]) == 0
    return str(folder / "fleet.csv")


def _cell(go: Callable[[Path], int], writer: Writer, template: Path, kind: str, work: Path, expected: int, capsys):
    """What is wrong with one cell (empty: nothing): the writer ``go`` run on the path of ``kind`` made in
    ``work``."""
    work.mkdir()
    with contextlib.ExitStack() as stack:
        target, users = _make(kind, writer, template, work, stack)
        before_all = _files(work)
        before_users = {str(p): (p.read_bytes(), p.stat().st_mtime_ns) for p in users}
        capsys.readouterr()
        code = go(target)
        err = capsys.readouterr().err
        problems = []
        if code != expected:
            problems.append(f"exit {code}, expected {expected}: {err.strip()[:200]}")
        if code != 0 and (err.count("\n") != 1 or "internal error" in err):
            problems.append(f"not one line: {err!r}")
        if code != 0 and _files(work) != before_all:
            problems.append("a refusal changed a file")
        if {str(p): (p.read_bytes(), p.stat().st_mtime_ns) for p in users if p.exists()} != before_users:
            problems.append("a file of the user's changed or went")
        if code == 0 and target != Path("/dev/null") and not os.path.exists(target):
            problems.append("nothing written")
        if _leftovers(work):
            problems.append(f"leftovers {_leftovers(work)}")
    return problems


def _runner(name: str, fleet_csv: str, monkeypatch) -> Callable[[Path], int]:
    writer = WRITERS[name]
    if name == "simulate --report":
        _cheap_simulation(monkeypatch)

    def go(target: Path) -> int:
        if name == "fleet --out":
            return main(["fleet", fleet_csv, "--problem", INVACARE, "--no-monte-carlo", "--out", str(target)])
        return writer.run(target)

    return go


@pytest.mark.parametrize("name", list(WRITERS))
def test_every_writer_against_every_kind_of_path(name, tmp_path, capsys, monkeypatch, fleet_csv):
    """One writer through every kind of path (:data:`KINDS`): its exit code is :data:`EXPECTED`'s, a refusal is
    one line on stderr and changes no file, a success writes the target, nothing of the user's changes in any
    cell (bytes and mtimes), and no temporary entry is left."""
    writer = WRITERS[name]
    go = _runner(name, fleet_csv, monkeypatch)
    template = tmp_path / "template"
    template.mkdir()
    assert go(template / writer.target) == 0, capsys.readouterr().err
    failures = []
    for kind in KINDS:
        expected = EXPECTED[name][kind]
        if expected is not None:
            work = tmp_path / kind.replace(" ", "-").replace("'", "")
            problems = _cell(go, writer, template, kind, work, expected, capsys)
            if problems:
                failures.append((kind, problems))
    assert failures == []


def test_the_matrix_catches_ownership_by_name_and_a_trusted_record(tmp_path, capsys, monkeypatch, fleet_csv):
    """Planted faults, the rules of the last release: a folder counted as the tool's by the names in it, and a
    commit record acted on without its temporary folder.  The matrix's cells catch both: calibrate --report
    into the user's folder writes over calibration.json and figures/ (exit 0, the user's files changed), and
    a planted record beside fleet --example --out deletes the user's notes.txt."""
    from designer import output

    monkeypatch.setattr(output, "is_owned", lambda folder, name, manifest=None, by=None: True)
    monkeypatch.setattr(output, "_stage_of", lambda folder, record: folder / record["stage"])
    caught = {}
    for name, kind in (("calibrate --report", "user's folder"), ("fleet --example --out", "planted record")):
        writer = WRITERS[name]
        go = _runner(name, fleet_csv, monkeypatch)
        template = tmp_path / f"template-{writer.target}"
        template.mkdir()
        assert go(template / writer.target) == 0
        work = tmp_path / name.replace(" ", "-")
        caught[name] = _cell(go, writer, template, kind, work, EXPECTED[name][kind], capsys)
    assert any("user's changed" in p for p in caught["calibrate --report"]), caught
    assert any("user's changed or went" in p for p in caught["fleet --example --out"]), caught
