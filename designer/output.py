"""Writing the tool's output safely: only the files a command owns, committed whole, one-line errors.

Every command that writes goes through this module (``pareto``, ``robust``, ``fleet``, ``simulate --report``
and ``--plot``, ``calibrate --report/--plot/--snippet/examples``, ``explore --out`` and ``--storage``, the
studio's "Save problem" and "Write report", :meth:`Front.to_csv <designer.studies.front.Front.to_csv>`):

- Ownership is proved by content, in one place: every folder the tool writes files into gets a manifest
  (:data:`MANIFEST`, ``.designer-manifest.json``) holding each file's sha256 and the command that wrote it,
  updated in the same commit as the files.  A file (or a folder such as ``figures``) is the tool's to replace
  only while the manifest holds every file of it with the digest of its present bytes, written by the same
  command (:func:`is_owned`); a file the user edited, a file put into ``figures/``, another command's report,
  a file of a release before manifests are the user's (:func:`foreign`).  Files that prove themselves by their
  content are the tool's too: a snippet or a saved problem whose first line carries the digest of the rest
  (:func:`signed_kind`), optuna's journal or SQLite study (``FileKind.recognise``).
- :func:`check_folder` and :func:`check_file`, called before any computing: a regular file, a device or a
  pipe as a folder, a path under one, a link to nothing, a loop of links, a name too long, a place where
  nothing can be created, the filesystem root or the home folder as an output folder, a folder holding files
  of the user's that the command would replace, or an existing file not proved the tool's, is an
  :class:`~designer.errors.OutputError` (exit 7).
- :func:`output_folder`: the command writes its files into a temporary folder inside the target; once they
  are complete they are committed (below), with the folder's manifest.  Nothing else in the folder is removed
  or moved; a link to a folder is followed; the folder itself (its mode, its other files) is left as it was.
- :func:`write_file`: one file replaced atomically (a temporary file beside it, renamed over it), its mode
  kept, its digest recorded in its folder's manifest, and only if it is new, empty, or proved the tool's; a
  character device or a pipe (``/dev/stdout``) is written in place; ``FileKind.new_only`` (``init``) never
  writes over anything.
- :func:`write_error`: an OSError while writing as one line naming the path ("no space left on device").

How a report of several files is committed: a write-ahead record
------------------------------------------------------------------
Linux can exchange two folders atomically (``renameat2(RENAME_EXCHANGE)``), but a report folder is shared: it
holds the user's own files and other commands' files (``explore.csv`` beside a Pareto report), may be a link,
has its own mode; exchanging the whole folder would have to carry them over, which is not atomic either.  So
the commit is a write-ahead record in the folder, under an exclusive lock of the folder (``flock``):

1. the record ``.designer-tmp-commit-<id>.json`` (the names to install and remove, the hidden name each
   previous entry is kept under) is written, synced and renamed into place;
2. each previous entry is kept aside (a hard link for a file, a rename for a folder:
   ``.designer-tmp-old-<id>-<name>``) and the new one renamed over it; the owned names of an older run that
   this one does not write again are set aside too;
3. the commit point: the record is renamed to ``.designer-tmp-done-<id>.json`` (one atomic rename);
4. the entries kept aside, the temporary folder and the record are removed.

Every command that touches the folder (:func:`check_folder` before computing, the commit itself, a single
file written there) first takes the lock and *recovers* (:func:`recover`): a ``commit`` record left by a
process killed before the commit point is rolled back (each previous entry put back, each new one removed), a
``done`` record is rolled forward (the entries kept aside removed).  A record is acted on only when its
temporary folder is there and no live run holds it (a record copied with a report or planted in a shared
folder touches nothing), and an entry is removed or replaced only when it has the digest the record says it
installed.  A kill -9 at any instant therefore leaves,
after the next run, the whole previous report or the whole new one, byte for byte.  A reader that does not
take the lock (a browser) can meet the few milliseconds of step 2; every command of this tool cannot.

Leftovers of dead processes: the temporary folder of a run holds an exclusive ``flock`` of itself while the
run computes (the kernel releases it when the process dies, whatever kills it); a temporary entry that can be
locked, found under the folder's lock, belongs to no live run and is removed.  Only names with the prefix
:data:`TEMP_PREFIX` are ever removed; nothing of the user's.

Ownership is checked twice: before computing (a clear refusal before minutes of work) and again under the
lock of the commit, with the same rule (the manifest): another command that wrote the folder meanwhile is seen.

Nothing here computes; the commands decide what to write.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import re
import shutil
import signal
import stat
import tempfile
import threading
import uuid
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from os.path import lexists
from pathlib import Path

from designer.errors import OS_REASONS, WRITE_ERRNOS, OutputError
from designer.textfiles import not_a_file

TEMP_PREFIX = ".designer-tmp-"
"""Name prefix of every temporary entry (hidden; removed on any failure or signal, or by the next run)."""

OLD_PREFIX = TEMP_PREFIX + "old-"
"""Name prefix of a previous entry kept aside during a commit."""

COMMIT_PREFIX = TEMP_PREFIX + "commit-"
"""Name prefix of a commit's write-ahead record before its commit point (rolled back by :func:`recover`)."""

DONE_PREFIX = TEMP_PREFIX + "done-"
"""Name prefix of a commit's record after its commit point (rolled forward by :func:`recover`)."""

_FULL = {e: OS_REASONS[e] for e in (errno.ENOSPC, errno.EDQUOT)}

_step_hook: Callable[[str], None] | None = None
"""Test hook: called with the name of each step of a commit (``staged``, ``record``, ``aside <name>``,
``install <name>``, ``remove <name>``, ``commit``, ``drop <name>``, ``done``); None in normal runs."""


def _step(name: str) -> None:
    if _step_hook is not None:
        _step_hook(name)


# --------------------------------------------------------------------------- kinds of single files


@dataclass(frozen=True)
class FileKind:
    """A kind of single file a command writes, and how to prove an existing one is the tool's.

    ``what``: how messages name it ("an example fleet written by designer fleet --example").  An existing file
    is the tool's when the manifest of its folder (:data:`MANIFEST`) holds its name with the sha256 of its
    bytes, or when ``recognise(path)`` proves it by its content alone (a file that carries its own digest,
    :func:`signed_kind`; optuna's journal or SQLite study, which optuna itself keeps writing).  ``new_only``:
    nothing that exists is ever written over, not even an empty file or a device (``designer init``).
    A new or empty regular file is otherwise always the tool's to write.
    """

    what: str
    recognise: Callable[[Path], bool] | None = None
    new_only: bool = False


_SIGNATURE = re.compile(r"^# written by (?P<writer>[^\n]*?) \(sha256 (?P<digest>[0-9a-f]{16})\)[^\n]*\n")


def _digest(body: str) -> str:
    return hashlib.sha256(body.encode("utf-8")).hexdigest()[:16]


def signed(body: str, writer: str) -> str:
    """``body`` (a TOML or CSV text whose format takes ``#`` comments) under a first line naming ``writer`` and
    the sha256 of ``body``: the tool replaces the file later only while that line is first and ``body``
    unchanged (:func:`signed_kind`); a file the user edited, or any other file, is left as it is."""
    return f"# written by {writer} (sha256 {_digest(body)}); replaced by its next run, so edit a copy\n{body}"


def signed_kind(writer: str, what: str) -> FileKind:
    """The :class:`FileKind` of the files :func:`signed` writes for ``writer``: the first line names ``writer``
    and the digest matches the rest (the user has not edited it) -- proved by the content, a manifest or not."""

    def recognise(path: Path) -> bool:
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            return False
        match = _SIGNATURE.match(text)
        return bool(match and match["writer"] == writer and match["digest"] == _digest(text[match.end() :]))

    return FileKind(what, recognise)


SOFTWARE = "caster-designer"
"""The name figures carry in their metadata (a PNG's Software text, an SVG's or PDF's Creator)."""

PLOT = FileKind(f"a figure written by {SOFTWARE}")
"""A figure of ``--plot``: replaced only while the manifest of its folder proves it the tool's, unedited."""


# --------------------------------------------------------------------------- ownership: the manifest

MANIFEST = ".designer-manifest.json"
"""The manifest the tool writes into every folder it writes files into: each file's name (``figures/fit.png``
for a file inside a folder the tool writes whole), the sha256 of its bytes and the command that wrote it.
It is the one proof of ownership: a file is the tool's only while the manifest holds its name with the digest
of its present bytes (a file edited since is the user's); a folder entry (``figures``) only while every file in
it is (a file of the user's put in it makes the folder the user's)."""

MANIFEST_SCHEMA = "caster-designer/manifest/1"
"""The ``schema`` of a manifest; a file of that name with anything else in it is not the tool's."""


def file_sha256(path: Path) -> str | None:
    """The sha256 of the regular file at ``path`` (not following a link), None for anything else."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0))
    except OSError:
        return None
    with os.fdopen(fd, "rb") as fh:
        try:
            return hashlib.file_digest(fh, "sha256").hexdigest() if stat.S_ISREG(os.fstat(fd).st_mode) else None
        except OSError:
            return None


def tree_digests(path: Path, prefix: str = "") -> dict[str, str | None]:
    """Every file under ``path`` (itself if a file) by its name relative to ``path``'s folder, with its sha256;
    a link, a device or a FIFO with None (never the tool's: it writes none)."""
    name = prefix or path.name
    if path.is_symlink() or not path.is_dir():
        return {name: file_sha256(path)}
    out: dict[str, str | None] = {}
    try:
        entries = sorted(os.listdir(path))
    except OSError:
        return {name + "/": None}
    for entry in entries:
        out.update(tree_digests(path / entry, f"{name}/{entry}"))
    return out


RUN_MANIFEST = ".designer-manifest-run.json"
"""The second manifest, of the files that hold the run's own date and timings (:data:`VOLATILE`): their digests
change with every run, so they are kept apart and the first manifest stays byte-identical across reruns (a
committed report stays clean; the repository ignores run.json and this file)."""

VOLATILE = frozenset({"run.json", "spec.html"})
"""Names whose digests go to :data:`RUN_MANIFEST`: a Pareto report's run.json (the date, seconds, versions) and
the inspection sheet ``designer spec`` writes beside a report by default (the user's print-out, ignored by the
repository like run.json), so neither changes the committed manifest."""


def _read_one(path: Path) -> dict[str, dict] | None:
    """The entries of one manifest file: empty when there is none, None when a file of that name is not a
    manifest (not a regular file, a link, not JSON of :data:`MANIFEST_SCHEMA`): the user's, proving nothing."""
    if not lexists(path):
        return {}
    if path.is_symlink() or not path.is_file():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    if not isinstance(data, dict) or data.get("schema") != MANIFEST_SCHEMA or not isinstance(data.get("files"), dict):
        return None
    return {k: v for k, v in data["files"].items() if isinstance(v, dict) and isinstance(v.get("sha256"), str)}


def read_manifest(folder: Path) -> dict[str, dict]:
    """The entries of ``folder``'s manifests (:data:`MANIFEST` and :data:`RUN_MANIFEST`; name ->
    ``{"sha256": ..., "by": ...}``); empty without one.  A file of a manifest's name that is not one proves
    nothing."""
    return {**(_read_one(Path(folder) / MANIFEST) or {}), **(_read_one(Path(folder) / RUN_MANIFEST) or {})}


def _split(entries: dict[str, dict]) -> tuple[dict[str, dict], dict[str, dict]]:
    """``entries`` as (those of :data:`MANIFEST`, those of :data:`RUN_MANIFEST`)."""
    run = {k: v for k, v in entries.items() if k.split("/", 1)[0] in VOLATILE}
    return {k: v for k, v in entries.items() if k not in run}, run


def manifest_text(entries: dict[str, dict]) -> str:
    """A manifest's bytes: sorted, no time stamp (a rerun that writes the same files writes the same manifest)."""
    return json.dumps({"schema": MANIFEST_SCHEMA, "files": dict(sorted(entries.items()))}, indent=1) + "\n"


def is_owned(folder: Path, name: str, manifest: dict[str, dict] | None = None, by: str | None = None) -> bool:
    """True if the entry ``name`` of ``folder`` is the tool's, unedited: every file of it (itself, or each file
    in it for a folder) is in the manifest with the sha256 of its present bytes (and, with ``by``, written by
    that command: another command's report of the same names is not this one's to replace).  An absent name
    is not owned; a link, a device, a FIFO never are."""
    manifest = read_manifest(folder) if manifest is None else manifest
    path = Path(folder) / name
    if not lexists(path):
        return False
    digests = tree_digests(path, name)
    entries = [manifest.get(k, {}) for k in digests]
    return (
        bool(digests)
        and all(d is not None and e.get("sha256") == d for e, d in zip(entries, digests.values(), strict=True))
        and (by is None or all(e.get("by") == by for e in entries))
    )


def _updated(manifest: dict[str, dict], folder: Path, names: Iterable[str], gone: Iterable[str], by: str) -> dict:
    """``manifest`` with the entries of ``names`` (now in ``folder``) digested anew and those of ``gone`` dropped."""
    names = list(names)
    dropped = [*names, *gone]
    out = {k: v for k, v in manifest.items() if not any(k == n or k.startswith(n + "/") for n in dropped)}
    for name in names:
        digests = tree_digests(folder / name, name).items()
        out.update({key: {"sha256": digest, "by": by} for key, digest in digests if digest is not None})
    return out


# --------------------------------------------------------------------------- messages


def _reason(exc: OSError) -> str:
    if exc.errno in _FULL:
        return _FULL[exc.errno]
    text = os.strerror(exc.errno) if exc.errno else str(exc)
    return text[:1].lower() + text[1:]


def write_error(path, exc: OSError, option: str | None = None) -> OutputError:
    """``exc`` (raised while writing ``path``) as one OutputError line: the option, the path and the reason.

    A full disk says "no space left on device" and that nothing was written (the temporary files are gone).
    """
    what = f"{option} {path}" if option else str(path)
    culprit = exc.filename if isinstance(exc.filename, str) else None
    name = Path(culprit).name if culprit else ""
    inside = f" (writing {name})" if name and not name.startswith(TEMP_PREFIX) and name != Path(path).name else ""
    if exc.errno in _FULL:
        return OutputError(f"{what}: {_reason(exc)}{inside}; nothing was written; free some space and run it again")
    return OutputError(f"{what}: cannot write{inside} ({_reason(exc)}); choose another {option or 'place'}")


def _is_write_error(exc: OSError, *places: Path) -> bool:
    """True if ``exc`` came from writing: a writing-only errno, or an error on a path inside ``places``."""
    if exc.errno in WRITE_ERRNOS:  # errors that can only come from writing, wherever they arose
        return True
    names = [os.path.abspath(n) for n in (exc.filename, exc.filename2) if isinstance(n, str | os.PathLike)]
    return any(full == str(p) or full.startswith(str(p) + os.sep) for full in names for p in places)


# --------------------------------------------------------------------------- checks before computing


def _probe(place: Path, path: Path, option: str, hint: str) -> None:
    """Make and remove a temporary folder in ``place`` (permission bits alone do not tell: root, read-only mounts)."""
    try:
        made = tempfile.mkdtemp(prefix=f"{TEMP_PREFIX}probe-", dir=place)
    except OSError as exc:
        reason = os.strerror(exc.errno) if exc.errno else str(exc)
        raise OutputError(f"{option} {path}: cannot write in {place} ({reason}); {hint}") from None
    with contextlib.suppress(OSError):  # removed meanwhile by another run's clean-up: as good
        os.rmdir(made)


def link_chain(path: Path, limit: int = 8) -> str:
    """``l1 -> l2 -> l1``: the links ``path`` leads through, until one repeats (or ``limit`` of them)."""
    seen: list[str] = [str(path)]
    here = Path(path)
    for _ in range(limit):
        try:
            target = os.readlink(here)
        except OSError:
            break
        here = here.parent / target
        shown = os.path.normpath(str(here))
        seen.append(target)
        if shown in {os.path.normpath(str(x if Path(x).is_absolute() else Path(path).parent / x)) for x in seen[:-1]}:
            break
    return " -> ".join(seen)


def _path_problem(path: Path, option: str) -> None:
    """OutputError naming the true reason when ``path`` itself cannot be looked up: a loop of links
    (``l1 -> l2 -> l1``), a name longer than the file system allows; nothing otherwise."""
    try:
        os.stat(path)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise OutputError(
                f"{option} {path}: is a loop of symbolic links ({link_chain(path)}); choose another {option}"
            ) from None
        if exc.errno == errno.ENAMETOOLONG:
            longest = max(len(p.encode()) for p in path.parts)
            raise OutputError(
                f"{option} {path}: a name longer than the file system allows ({longest} bytes in one name, or "
                f"{len(str(path).encode())} in the path); choose a shorter {option}"
            ) from None


def _refuse_files_on_the_way(path: Path, option: str) -> Path:
    """The nearest existing ancestor of ``path`` (``path`` itself if it exists); OutputError if it is not a folder."""
    _path_problem(path, option)
    if path.is_symlink() and not path.exists():
        raise OutputError(
            f"{option} {path}: is a link to {os.readlink(path)}, which does not exist; choose another {option}"
        )
    probe = path
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        where = "is" if probe == path else f"lies under {probe}, which is"
        kind = _not_regular(probe) or "a regular file"
        raise OutputError(f"{option} {path}: {where} {kind}, not a folder; choose another {option}")
    return probe


def _not_regular(path: Path) -> str | None:
    """What ``path`` is when it is a device, a pipe or a socket ("a character device"), else None."""
    kind = not_a_file(path)
    return None if kind in ("a folder", "not a regular file") else kind


def foreign(folder: Path, names: Iterable[str], same_as: Path | None = None, by: str | None = None) -> list[str]:
    """The names of ``names`` in ``folder`` that are not the tool's (:func:`is_owned`, by the manifest), and the
    manifest itself when a file of that name is not one (the user's): what a command must not replace.  With
    ``same_as`` (a temporary folder), an entry whose bytes equal the new one's there is not counted (replacing it
    loses nothing).  ``by``: the command that would write them (:func:`is_owned`)."""
    folder = Path(folder)
    manifest = read_manifest(folder)
    out = [
        n
        for n in sorted(set(names))
        if lexists(folder / n)
        and not is_owned(folder, n, manifest, by)
        and not (same_as is not None and _same_file(same_as / n, folder / n))
    ]
    out += [m for m in (MANIFEST, RUN_MANIFEST) if _read_one(folder / m) is None]
    return out


def _refused_place(real: Path, path: Path, option: str) -> None:
    """OutputError if ``real`` is the filesystem root or the home folder: no command writes its files there."""
    try:
        home: Path | None = Path(os.path.realpath(Path.home()))
    except (RuntimeError, KeyError, OSError):  # no HOME and no password entry: no home folder to protect
        home = None
    if real == real.parent:
        where = "the filesystem root"
    elif home is not None and real == home and home != home.parent:
        where = "your home folder"
    else:
        return
    raise OutputError(
        f"{option} {path}: is {where}; a command writes its files into a folder of their own, "
        f"e.g. {option} {real / 'caster-report'}"
    )


def _refuse_clash(real: Path, clash: list[str], option: str, command: str) -> None:
    manifest = read_manifest(real)
    others = sorted(
        {e.get("by", "") for k, e in manifest.items() for n in clash if k == n or k.startswith(n + "/")} - {command}
    )
    why = f"another command's ({', '.join(others)})" if others else "your files, or files edited since"
    raise OutputError(
        f"{option} {real}: holds {', '.join(clash)}, which {command} would replace, and the folder's manifest "
        f"({MANIFEST}) does not prove them its own, unedited ({why}, or a report of a release before manifests); "
        f"they are left as they are: move them away or choose another {option}"
    )


def check_folder(
    folder,
    option: str = "--out",
    owned: Iterable[str] = (),
    force: bool = False,
    command: str = "the command",
) -> Path:
    """Raise OutputError (exit 7) unless ``command`` can write its ``owned`` files into ``folder``.

    Called before any computing.  ``folder`` may be absent (it will be made), a folder, or a link to a folder
    (followed).  Refused: a regular file, a device or a pipe, a path under one, a link to nothing, a loop of
    links, a name too long, a place where nothing can be created (read-only, no permission), the filesystem root
    and the home folder (even with ``force``), and a folder holding an ``owned`` name that its manifest does not
    prove the tool's, unedited (:func:`foreign`) -- those are the user's files, unless ``force``.  Its one side
    effect: an existing folder is recovered first (:func:`recover`: an interrupted commit rolled back or
    forward, leftovers of dead runs removed).

    Returns
    -------
    Path
        The folder with links resolved (where the files will go).
    """
    path = Path(folder)
    probe = _refuse_files_on_the_way(path, option)
    real = Path(os.path.realpath(path))
    _refused_place(real, path, option)
    _probe(probe, path, option, f"choose a writable {option} folder")
    if real.is_dir():
        recover(real)
        if not force:
            clash = foreign(real, owned, by=command)
            if clash:
                _refuse_clash(real, clash, option, command)
    return real


def _refuse_foreign(real: Path, path: Path, option: str, kind: FileKind) -> None:
    """OutputError unless the file at ``real`` is new, empty, a device or a pipe (written in place), or proved
    the tool's: by the manifest of its folder with the digest of its present bytes, or by its own content
    (``kind.recognise``)."""
    try:
        st = os.stat(real)
    except FileNotFoundError:
        return
    if kind.new_only:
        raise OutputError(
            f"{option} {path}: already exists; this command never writes over a file, a folder or a device; "
            f"choose another {option}"
        )
    if not stat.S_ISREG(st.st_mode) or st.st_size == 0:
        return
    if is_owned(real.parent, real.name, by=kind.what) or (kind.recognise is not None and kind.recognise(real)):
        return
    entry = read_manifest(real.parent).get(real.name)
    if entry is not None and entry.get("by") != kind.what:
        raise OutputError(
            f"{option} {path}: was written by {entry.get('by')}, not as {kind.what}; it is left as it is; "
            f"choose another {option}"
        )
    if entry is not None:
        raise OutputError(
            f"{option} {path}: is a file you edited since this tool wrote it (its sha256 differs from the one in "
            f"{MANIFEST}); it is left as it is; choose another {option}, or remove it to have it written anew"
        )
    raise OutputError(
        f"{option} {path}: is a file this tool did not write (nothing proves it {kind.what}: no entry in the "
        f"folder's {MANIFEST}); it is left as it is; choose another {option}, or remove it if it is an "
        f"earlier run's"
    )


def check_file(path, option: str = "--out", example: str = "out.csv", *, kind: FileKind) -> Path:
    """Raise OutputError (exit 7) unless the file ``path`` can be written; no side effect; called before computing.

    Refused: a folder (the file needs a name), a path under a regular file, a link to nothing, a loop of links,
    a name too long, a folder where nothing can be created, and an existing non-empty file that is not proved
    the tool's (:func:`_refuse_foreign`: the manifest of its folder, or its own content).  A link to a file is
    followed (the file it names is replaced, the link kept).  A character device or a pipe (``/dev/stdout``,
    ``>(cat)``) is written in place, unless ``kind.new_only``.

    Returns
    -------
    Path
        The file with links resolved (where the bytes will go).
    """
    path = Path(path)
    if kind.new_only and lexists(path):
        what = "a link" if path.is_symlink() else _not_regular(path) or ("a folder" if path.is_dir() else "a file")
        raise OutputError(
            f"{option} {path}: already exists ({what}); this command never writes over an existing path; "
            f"choose another {option}"
        )
    _path_problem(path, option)
    if path.is_dir():
        raise OutputError(f"{option} {path}: is a folder; give a file name, e.g. {path / example}")
    other = _not_regular(path) if path.exists() else None
    if other in ("a character device", "a pipe (FIFO)"):  # /dev/stdout, /dev/null, a pipe: written in place
        return path  # as given: /dev/stdout resolves to /proc/<pid>/fd/pipe:[...], a name that cannot be opened
    if other is not None:
        raise OutputError(f"{option} {path}: is {other}, not a file; choose another {option}")
    if path.exists():  # a file (or a link to one): its folder must take a temporary file
        place = Path(os.path.realpath(path)).parent
        _refuse_foreign(Path(os.path.realpath(path)), path, option, kind)
    else:
        place = _refuse_files_on_the_way(path, option)
    _probe(place, path, option, f"choose another {option}")
    return Path(os.path.realpath(path))


# --------------------------------------------------------------------------- signals and locks


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back meanwhile (main thread; elsewhere the main thread receives them anyway).

    A signal that arrives meanwhile is delivered when the block ends: a commit or a clean-up is never cut short.
    """
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _hold(path: Path, blocking: bool = True) -> int | None:
    """An open descriptor of ``path`` holding its exclusive flock (None: no lock to be had, or none without
    waiting when not ``blocking``).  Closing the descriptor, or the process's death, releases it."""
    try:
        import fcntl  # POSIX only; elsewhere concurrent writers are not serialised
    except ImportError:  # pragma: no cover - Windows
        return None
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) * (not path.is_dir()))
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | (0 if blocking else fcntl.LOCK_NB))
    except OSError:
        os.close(fd)
        return None
    return fd


@contextlib.contextmanager
def _locked(folder: Path) -> Iterator[bool]:
    """An exclusive lock on ``folder`` (flock of the folder itself: nothing is added to it) meanwhile; yields
    whether it is held.  A temporary folder of this tool is private to its run: not locked."""
    if folder.name.startswith(TEMP_PREFIX):
        yield False
        return
    fd = _hold(folder)
    try:
        yield fd is not None
    finally:
        if fd is not None:
            os.close(fd)  # releases the lock


# --------------------------------------------------------------------------- recovery


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(path)


def _sync(path: Path) -> None:
    """fsync ``path`` (a file or a folder) where the system allows it."""
    with contextlib.suppress(OSError):
        fd = os.open(path, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _real_dir(path: Path) -> bool:
    return path.is_dir() and not path.is_symlink()


def entry_digest(path: Path) -> str | None:
    """One sha256 of the entry at ``path``: a file's bytes, or every file of a folder by its relative name; None
    for an absent entry or one holding a link, a device or a pipe (the tool installs none)."""
    if not lexists(path):
        return None
    digests = tree_digests(path, ".")
    if any(d is None for d in digests.values()):
        return None
    return hashlib.sha256(json.dumps(sorted(digests.items())).encode("utf-8")).hexdigest()


def _put_back(folder: Path, name: str, aside: str | None, installed: bool, digest: str | None) -> None:
    """Undo one entry of a commit: the previous ``name`` (kept as ``aside``, None if there was none) back in
    place; the new one removed if it was ``installed`` (renamed out of the temporary folder) and it is still the
    entry the record installed (its ``digest``): an entry of anyone else's is never removed or replaced."""
    dst = folder / name
    ours = installed and digest is not None and entry_digest(dst) == digest
    if aside is None:
        if ours:
            _remove(dst)
        return
    old = folder / aside
    if not lexists(old):
        return  # not set aside yet, or put back already
    if lexists(dst):
        if os.path.samestat(os.lstat(old), os.lstat(dst)):
            os.unlink(old)  # a hard link of a file that was never replaced
            return
        if not ours:
            return  # not this commit's entry: left as it is (the aside goes with the leftovers)
        if _real_dir(dst) or _real_dir(old):
            _remove(dst)  # the new folder (a rename cannot replace a folder by a file or a full folder)
    os.replace(old, dst)


def _roll_back(folder: Path, record: dict) -> None:
    """Undo an interrupted commit described by ``record``: the folder as it was before it."""
    stage = folder / record["stage"]
    digests = record["digests"]
    for name, aside in reversed(record["remove"]):
        _put_back(folder, name, aside, installed=False, digest=None)
    for name, aside in reversed(record["install"]):
        _put_back(folder, name, aside, installed=not lexists(stage / name), digest=digests.get(name))


def _read_record(path: Path) -> dict | None:
    """A commit record, or None when it is not one this release writes (every entry ``[name, aside or None]``, plain
    names of this folder with no separator and no '..', the temporary folder a name of the tool's, the digest of
    every entry it installs)."""
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
        entries = record["install"] + record["remove"]  # two lists (or a TypeError)
        valid = isinstance(record["install"], list) and _plain(record["stage"])
        valid = valid and record["stage"].startswith(TEMP_PREFIX)
        valid = valid and all(isinstance(v, str) for v in record["digests"].values())
        for e in entries:
            valid = valid and isinstance(e, list) and len(e) == 2 and _plain(e[0])
            valid = valid and (e[1] is None or _plain(e[1]) and e[1].startswith(OLD_PREFIX))
    except (OSError, UnicodeDecodeError, ValueError, TypeError, KeyError, AttributeError):
        return None
    return record if valid else None


def _plain(name: object) -> bool:
    """A plain name of this folder: a non-empty string without a separator, not '.' or '..'."""
    return isinstance(name, str) and bool(name) and "/" not in name and os.sep not in name and name not in (".", "..")


def _abandoned(stage: Path) -> bool:
    """True if ``stage`` is a temporary folder (a folder, not a link) that no live run holds: its flock can be
    taken now (a live run's, or one this process cannot open, is not)."""
    fd = _hold(stage, blocking=False) if _real_dir(stage) else None
    if fd is not None:
        os.close(fd)
    return fd is not None


def _stage_of(folder: Path, record: dict) -> Path | None:
    """The temporary folder ``record`` names, if it exists (a folder, not a link) and no live run holds it;
    a record without it (copied with a report, planted in a shared folder) is acted on in no way."""
    stage = folder / record["stage"]
    return stage if _abandoned(stage) else None


def _recover_records(folder: Path) -> None:
    """Roll back (``commit-``) or forward (``done-``) each record whose temporary folder is there, then drop the
    record, then the temporary folder; a record that is not one of this release's, or without its temporary
    folder, touches nothing (it is removed with the leftovers)."""
    for entry in sorted(os.listdir(folder)):
        if not entry.startswith((COMMIT_PREFIX, DONE_PREFIX)) or not entry.endswith(".json"):
            continue
        record = _read_record(folder / entry)
        stage = _stage_of(folder, record) if record is not None else None
        if record is not None and stage is not None:
            if entry.startswith(DONE_PREFIX):  # past the commit point: the previous entries kept aside removed
                for _, aside in record["install"] + record["remove"]:
                    if aside is not None:
                        _remove(folder / aside)
            else:
                _roll_back(folder, record)
            _sync(folder)
        os.unlink(folder / entry)
        _sync(folder)
        if stage is not None:
            _remove(stage)


def _remove_dead_leftovers(folder: Path) -> None:
    """Remove the temporary entries of runs that are gone: those no live process holds the flock of."""
    for entry in sorted(os.listdir(folder)):
        if not entry.startswith(TEMP_PREFIX):
            continue
        path = folder / entry
        if _real_dir(path) and not _abandoned(path):
            continue  # a live run's temporary folder (or one this process cannot open: left alone)
        with contextlib.suppress(OSError):  # another user's leftover: left for a run that may remove it
            _remove(path)


def recover(folder) -> None:
    """Bring ``folder`` back to a whole state before anything else touches it, under its lock: a commit
    interrupted before its commit point is rolled back, one interrupted after it is finished, and the
    temporary entries of runs that are no longer alive are removed.  Nothing if the folder cannot be locked;
    an OSError while putting entries back is an OutputError naming the folder (:func:`write_error`)."""
    folder = Path(folder)
    with _locked(folder) as held:
        if held:
            with signals_held():
                try:
                    _tidy(folder)
                except OSError as exc:  # e.g. no permission to put an entry back: the user's setup, one line
                    raise write_error(folder, exc) from None


def _tidy(folder: Path) -> None:
    """:func:`recover`'s work, the folder's lock held."""
    with contextlib.suppress(FileNotFoundError):
        _recover_records(folder)
        _remove_dead_leftovers(folder)


# --------------------------------------------------------------------------- committing a folder


def _same_file(new: Path, old: Path) -> bool:
    """True if ``new`` and ``old`` are regular files with the same bytes (replacing one by the other loses nothing)."""
    try:
        same = new.is_file() and old.is_file() and not old.is_symlink() and new.stat().st_size == old.stat().st_size
        return same and new.read_bytes() == old.read_bytes()
    except OSError:
        return False


def _aside(dst: Path, aside: Path) -> None:
    """Keep the previous ``dst`` as ``aside`` until the commit is complete.  A file or a link gets a second
    hard link, so ``dst`` itself stays in place until the rename replaces it; a folder is renamed aside (it
    cannot be replaced by a rename while it holds files)."""
    if _real_dir(dst):
        os.rename(dst, aside)
        return
    try:
        os.link(dst, aside, follow_symlinks=False)
    except OSError:  # a file system without hard links
        os.rename(dst, aside)


def _write_whole(path: Path, text: str) -> None:
    """Write ``text`` as ``path`` whole: a temporary file beside it, synced, renamed over it (removed on failure)."""
    tmp = path.parent / f"{TEMP_PREFIX}write-{uuid.uuid4().hex[:8]}"
    try:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def _apply(real: Path, stage: Path, record: dict) -> None:
    """Steps 2 of the commit: every previous entry aside, every new one in place, the stale ones aside."""
    for name, aside in record["install"]:
        src, dst = stage / name, real / name
        if aside is not None:
            _aside(dst, real / aside)
            _step(f"aside {name}")
            if src.is_dir() and lexists(dst):
                os.unlink(dst)  # a file or a link where the new folder goes (kept aside)
        os.replace(src, dst)
        _step(f"install {name}")
    for name, aside in record["remove"]:
        _aside(real / name, real / aside)
        _remove(real / name)
        _step(f"remove {name}")


def _commit(stage: Path, real: Path, owned: set[str], force: bool, option: str, command: str) -> None:
    """Commit the entries of ``stage`` into ``real`` (the module's write-ahead record), with the folder's manifest
    updated in the same commit, removing the owned names of an older run that this one did not write again
    (only those the manifest proves the tool's); all or nothing.  Under the folder's lock, with signals held
    back; ownership is checked again under that lock."""
    names = sorted(n for n in os.listdir(stage) if n not in (MANIFEST, RUN_MANIFEST))
    with _locked(real) as held, signals_held():
        if held:
            _tidy(real)
        manifest = read_manifest(real)
        clash = foreign(real, set(names) | owned, same_as=stage, by=command)
        if clash and not force:  # something of the user's, or edited, or another command's report meanwhile
            _refuse_clash(real, clash, option, command)
        stale = [n for n in sorted(owned - set(names)) if lexists(real / n) and is_owned(real, n, manifest, command)]
        stable, run = _split(_updated(manifest, stage, names, stale, command))
        (stage / MANIFEST).write_text(manifest_text(stable), "utf-8")
        names.append(MANIFEST)  # installed last: the files and their proof change together
        if run or lexists(real / RUN_MANIFEST):
            (stage / RUN_MANIFEST).write_text(manifest_text(run), "utf-8")
            names.append(RUN_MANIFEST)
        for root, _, files in os.walk(stage):  # every file synced: a crash of the machine after the commit keeps them
            for name in [*files, "."]:
                _sync(Path(root) / name)
        tag = uuid.uuid4().hex[:8]
        record = {
            "stage": stage.name,
            "install": [[n, f"{OLD_PREFIX}{tag}-{n}" if lexists(real / n) else None] for n in names],
            "remove": [[n, f"{OLD_PREFIX}{tag}-{n}"] for n in stale],
            "digests": {n: d for n in names if (d := entry_digest(stage / n)) is not None},
        }
        journal = real / f"{COMMIT_PREFIX}{tag}.json"
        _write_whole(journal, json.dumps(record))
        _sync(real)
        _step("record")
        try:
            _apply(real, stage, record)
        except BaseException:
            _roll_back(real, record)
            os.unlink(journal)
            raise
        _sync(real)
        done = real / f"{DONE_PREFIX}{tag}.json"
        os.replace(journal, done)  # the commit point
        _sync(real)
        _step("commit")
        for name, aside in record["install"] + record["remove"]:
            if aside is not None:
                with contextlib.suppress(OSError):  # left for the next run's recovery
                    _remove(real / aside)
                _step(f"drop {name}")
        os.unlink(done)
        _step("done")


def _make_folders(path: Path) -> list[Path]:
    """Make ``path`` and its missing parents; returns those made, deepest last."""
    made = []
    for folder in reversed([path, *path.parents]):
        if not folder.exists():
            folder.mkdir()
            made.append(folder)
    return made


@contextlib.contextmanager
def output_folder(
    folder,
    owned: Iterable[str],
    *,
    option: str = "--out",
    force: bool = False,
    command: str = "the command",
) -> Iterator[Path]:
    """Context manager: yield an empty temporary folder; when the block ends normally, its entries replace
    those of ``folder`` (committed whole: see the module's docstring).

    ``owned``: the names the command writes in ``folder`` (files, or folders such as ``figures`` that are
    replaced whole); nothing else there is touched.  An owned name already in ``folder`` is replaced only while
    the folder's manifest (:data:`MANIFEST`) proves it the tool's, unedited, or it has the very bytes about to be
    written; anything else there is the user's, and the command is refused (OutputError, exit 7) unless
    ``force`` (checked again under the lock of the commit, for every name written).  The manifest is updated
    in the same commit.  The checks of :func:`check_folder` run first.

    An exception or a signal in the block, or an OSError while committing, removes the temporary folder
    (and ``folder`` if it was made for this run and holds nothing else); an OSError from writing becomes an
    OutputError line naming the path (:func:`write_error`).
    """
    owned = set(owned)
    real = check_folder(folder, option, owned, force, command)
    made: list[Path] = []
    stage: Path | None = None
    held: int | None = None
    done = False
    try:
        try:
            made = _make_folders(real)
            # the temporary folder holds its own flock while this run lives, made under the folder's lock (so
            # another run's clean-up never sees it unlocked)
            with _locked(real):
                stage = Path(tempfile.mkdtemp(prefix=TEMP_PREFIX, dir=real))
                held = _hold(stage)
        except OSError as exc:
            raise write_error(folder, exc, option) from None
        _step("staged")
        try:
            yield stage
            _commit(stage, real, owned, force, option, command)
        except OSError as exc:
            if _is_write_error(exc, real, stage):
                raise write_error(folder, exc, option) from None
            raise
        done = True
    finally:
        with signals_held():  # the clean-up itself is not cut short by a second Ctrl-C
            if stage is not None:
                shutil.rmtree(stage, ignore_errors=True)
            if held is not None:
                os.close(held)
            if not done:
                for made_folder in reversed(made):
                    with contextlib.suppress(OSError):
                        made_folder.rmdir()  # only if empty: a folder made for this run and nothing else


# --------------------------------------------------------------------------- writing one file


def write_file(path, content: str | bytes, option: str = "--out", example: str = "out.csv", *, kind: FileKind) -> Path:
    """Replace the file ``path`` with ``content`` atomically (a temporary file beside it, renamed over it), and
    record its sha256 in the manifest of its folder (:data:`MANIFEST`), the proof that the next run may replace it.

    Only a new or empty file, or one the tool wrote and nobody edited since, is replaced (:func:`check_file`;
    checked again under the lock of the folder, just before the rename): anything else is an OutputError naming
    ``option``.  A link to a file is followed (the file is replaced, the link kept); a character device or a pipe
    (``/dev/stdout``) is written in place; an existing file keeps its mode, a new one gets the usual mode (0666
    less the umask); missing parent folders are made.  Refusals and write failures are OutputError lines (exit
    7); the temporary file is removed on any failure or signal (and by the next run after a kill).

    Returns
    -------
    Path
        ``path`` as given.
    """
    path = Path(path)
    real = check_file(path, option, example, kind=kind)
    data = content.encode("utf-8") if isinstance(content, str) else bytes(content)
    if real.exists() and not real.is_file():  # a device or a pipe: nothing to replace, nothing to leave behind
        _write_in_place(real, path, data, option)
        return path
    tmp = real.with_name(f"{TEMP_PREFIX}{real.name[:100]}-{uuid.uuid4().hex[:8]}")
    try:
        _make_folders(real.parent)
        with _locked(real.parent) as held, signals_held():
            if held:
                _tidy(real.parent)
            _refuse_foreign(real, path, option, kind)  # again, under the lock
            mode = stat.S_IMODE(real.stat().st_mode) if real.exists() else None
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the umask applies
            with os.fdopen(fd, "wb") as fh:
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            if mode is not None:
                os.chmod(tmp, mode)
            if kind.new_only:
                os.link(tmp, real)  # never over anything that appeared meanwhile (EEXIST)
            else:
                os.replace(tmp, real)
            _record(real.parent, real.name, kind.what)
    except OSError as exc:
        if kind.new_only and exc.errno == errno.EEXIST:
            raise OutputError(f"{option} {path}: already exists; choose another {option}") from None
        raise write_error(path, exc, option) from None
    finally:
        with signals_held(), contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
    return path


def _write_in_place(real: Path, path: Path, data: bytes, option: str) -> None:
    """Write ``data`` into a character device or a pipe (``/dev/stdout``, ``>(cat)``, a FIFO).  A FIFO that
    nothing reads is refused at once (its open would wait for a reader for ever)."""
    try:
        fd = os.open(real, os.O_WRONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        if exc.errno == errno.ENXIO:
            raise OutputError(
                f"{option} {path}: is a pipe (FIFO) that nothing reads; start its reader first, or choose "
                f"another {option}"
            ) from None
        raise write_error(path, exc, option) from None
    try:
        os.set_blocking(fd, True)
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
    except BrokenPipeError:
        raise OutputError(f"{option} {path}: the pipe's reader went away; the output is incomplete") from None
    except OSError as exc:
        raise write_error(path, exc, option) from None


def _record(folder: Path, name: str, by: str) -> None:
    """Record ``folder/name``'s digest in the folder's manifest (written whole: a temporary file renamed over
    it), the folder's lock held.  A file of that name that is not a manifest (the user's) is left as it is: the
    file is then simply not proved the tool's next time."""
    path = folder / (RUN_MANIFEST if name in VOLATILE else MANIFEST)
    entries = _read_one(path)
    if entries is None:
        return
    stable, run = _split(_updated(entries, folder, [name], [], by))
    _write_whole(path, manifest_text(run if name in VOLATILE else stable))


__all__ = [
    "MANIFEST",
    "PLOT",
    "RUN_MANIFEST",
    "SOFTWARE",
    "TEMP_PREFIX",
    "FileKind",
    "check_file",
    "check_folder",
    "entry_digest",
    "file_sha256",
    "foreign",
    "is_owned",
    "link_chain",
    "output_folder",
    "read_manifest",
    "recover",
    "signed",
    "signed_kind",
    "signals_held",
    "write_error",
    "write_file",
]
