"""Writing the tool's output safely: only the files a command owns, replaced atomically, one-line errors.

Every command that writes goes through this module (``pareto``, ``robust``, ``fleet``, ``simulate --report``,
``calibrate --report/--plot/--snippet/examples``, ``explore``, the studio's "Save problem" and "Write report"):

- :func:`check_folder` and :func:`check_file`, called before any computing: a regular file, a path under
  one, a link to nothing, a place where nothing can be created, or a folder holding files of the user's
  that the command would replace, is an :class:`~designer.errors.OutputError` (exit 7).
- :func:`output_folder`: the command writes its files into a temporary folder inside the target; once
  they are complete they are renamed into the target one by one (each rename atomic, SIGINT and SIGTERM
  held back, other writers of the same folder locked out), so a reader finds the previous set or the new
  one, never a mixture.  Nothing else in the folder is removed or moved; a link to a folder is followed;
  the folder itself (its mode, its other files) is left as it was.  An error or a signal removes the
  temporary folder (and a folder the command created for nothing).
- :func:`write_file`: one file replaced atomically (a temporary file beside it), its mode kept.
- :func:`write_error`: an OSError while writing as one line naming the path ("no space left on device").

Nothing here computes; the commands decide what to write.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import signal
import stat
import tempfile
import threading
import uuid
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path

from designer.errors import OutputError

TEMP_PREFIX = ".designer-tmp-"
"""Name prefix of the temporary folders and files (hidden; removed on any failure or signal)."""

_FULL = {errno.ENOSPC: "no space left on device", errno.EDQUOT: "no space left (disk quota exceeded)"}
_WRITE_ERRNOS = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS}
"""Errors that can only come from writing: an OSError with one of these is the output's, wherever it arose."""

Marker = str | Callable[[Path], bool] | None
"""What makes an existing folder the command's own: a file name it always writes, or a test of the folder."""


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
    if exc.errno in _WRITE_ERRNOS:
        return True
    for name in (exc.filename, exc.filename2):
        if isinstance(name, str | os.PathLike):
            full = os.path.abspath(name)
            if any(full == str(p) or full.startswith(str(p) + os.sep) for p in places):
                return True
    return False


# --------------------------------------------------------------------------- checks before computing


def _regular(path: Path) -> bool:
    return stat.S_ISREG(os.stat(path).st_mode)


def _nearest_existing(path: Path) -> Path:
    probe = path
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    return probe


def _probe(place: Path, path: Path, option: str, hint: str) -> None:
    """Make and remove a temporary folder in ``place`` (permission bits alone do not tell: root, read-only mounts)."""
    try:
        tempfile.TemporaryDirectory(prefix=TEMP_PREFIX, dir=place).cleanup()
    except OSError as exc:
        reason = os.strerror(exc.errno) if exc.errno else str(exc)
        raise OutputError(f"{option} {path}: cannot write in {place} ({reason}); {hint}") from None


def _refuse_files_on_the_way(path: Path, option: str, what: str) -> Path:
    """The nearest existing ancestor of ``path`` (``path`` itself if it exists); OutputError if it is not a folder."""
    if path.is_symlink() and not path.exists():
        raise OutputError(
            f"{option} {path}: is a link to {os.readlink(path)}, which does not exist; choose another {option}"
        )
    probe = _nearest_existing(path)
    if probe.exists() and not probe.is_dir():
        where = "is" if probe == path else f"lies under {probe}, which is"
        raise OutputError(f"{option} {path}: {where} a regular file, not a folder; choose another {option}{what}")
    return probe


def is_ours(folder: Path, marker: Marker) -> bool:
    """True if ``folder`` is one the command wrote before (its ``marker`` file exists, or ``marker(folder)``)."""
    if marker is None:
        return False
    if callable(marker):
        return bool(marker(folder))
    return (folder / marker).is_file()


def clashes(folder: Path, owned: Iterable[str]) -> list[str]:
    """The names of ``owned`` that exist in ``folder`` (files, folders or links)."""
    return sorted(n for n in set(owned) if (folder / n).exists() or (folder / n).is_symlink())


def check_folder(
    folder,
    option: str = "--out",
    owned: Iterable[str] = (),
    marker: Marker = None,
    force: bool = False,
    command: str = "the command",
) -> Path:
    """Raise OutputError (exit 7) unless ``command`` can write its ``owned`` files into ``folder``; no side effect.

    Called before any computing.  ``folder`` may be absent (it will be made), a folder, or a link to a folder
    (followed).  Refused: a regular file or a path under one, a link to nothing, a place where nothing can be
    created (read-only, no permission), and a folder that holds an ``owned`` name while it is not one the
    command wrote (``marker``) -- those are the user's files, unless ``force``.

    Returns
    -------
    Path
        The folder with links resolved (where the files will go).
    """
    path = Path(folder)
    probe = _refuse_files_on_the_way(path, option, "")
    _probe(probe, path, option, f"choose a writable {option} folder")
    real = Path(os.path.realpath(path))
    if real.is_dir() and not force:
        clash = clashes(real, owned)
        if clash and not is_ours(real, marker):
            raise OutputError(
                f"{option} {path}: holds {', '.join(clash)}, which {command} would replace, and is not a folder "
                f"{command} wrote; choose another {option} (your files are left as they are)"
            )
    return real


def check_file(path, option: str = "--out", example: str = "out.csv") -> Path:
    """Raise OutputError (exit 7) unless the file ``path`` can be written; no side effect; called before computing.

    Refused: a folder (the file needs a name), a path under a regular file, a link to nothing, a folder where
    nothing can be created.  A link to a file is followed (the file it names is replaced, the link kept).

    Returns
    -------
    Path
        The file with links resolved (where the bytes will go).
    """
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"{option} {path}: is a folder; give a file name, e.g. {path / example}")
    if path.exists() and not _regular(path):  # a device or a pipe (/dev/stdout): written in place
        return Path(os.path.realpath(path))
    if path.exists():  # a file (or a link to one): its folder must take a temporary file
        place = Path(os.path.realpath(path)).parent
    else:
        place = _refuse_files_on_the_way(path, option, "")
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


@contextlib.contextmanager
def _locked(folder: Path) -> Iterator[None]:
    """An exclusive lock on ``folder`` (flock of the folder itself: nothing is added to it) while committing."""
    try:
        import fcntl  # POSIX only; elsewhere concurrent writers are not serialised
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


# --------------------------------------------------------------------------- writing a folder


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(path)


def _same_file(new: Path, old: Path) -> bool:
    """True if ``new`` and ``old`` are regular files with the same bytes (replacing one by the other loses nothing)."""
    try:
        if not (new.is_file() and old.is_file() and not old.is_symlink()) or new.stat().st_size != old.stat().st_size:
            return False
        return new.read_bytes() == old.read_bytes()
    except OSError:
        return False


def _aside(dst: Path) -> Path | None:
    """Keep the previous ``dst`` under a hidden name until the commit is complete (None if there is none).

    A file or a link gets a second hard link, so ``dst`` itself stays in place until the rename replaces it; a
    folder is renamed aside (it cannot be replaced by a rename while it holds files)."""
    if not (dst.exists() or dst.is_symlink()):
        return None
    aside = dst.with_name(f"{TEMP_PREFIX}old-{uuid.uuid4().hex[:8]}-{dst.name}")
    if dst.is_dir() and not dst.is_symlink():
        os.rename(dst, aside)
        return aside
    try:
        os.link(dst, aside, follow_symlinks=False)
    except OSError:  # a file system without hard links
        os.rename(dst, aside)
    return aside


def _undo(done: list[tuple[Path, Path | None]]) -> None:
    """Put the previous entries back, newest change first: the folder is as it was before the commit."""
    for dst, aside in reversed(done):
        if aside is None or aside.is_dir() or dst.is_dir() and not dst.is_symlink():
            if dst.exists() or dst.is_symlink():
                _remove(dst)
        if aside is not None:
            with contextlib.suppress(OSError):
                if (dst.exists() or dst.is_symlink()) and os.path.samestat(os.lstat(aside), os.lstat(dst)):
                    os.unlink(aside)  # never replaced (a rename onto its own hard link would do nothing)
                else:
                    os.replace(aside, dst)


def _commit(stage: Path, real: Path, owned: set[str], marker: Marker, force: bool, option: str, command: str) -> None:
    """Rename every entry of ``stage`` into ``real`` (the marker last) and remove the owned names of an older run
    that this one did not write again; all or nothing: on any failure the previous entries are put back.
    Under the folder's lock, with signals held back."""
    names = sorted(os.listdir(stage), key=lambda n: (isinstance(marker, str) and n == marker, n))
    with _locked(real), signals_held():
        ours = is_ours(real, marker)
        clash = [n for n in clashes(real, set(names) | owned) if not _same_file(stage / n, real / n)]
        if clash and not (ours or force):  # something of the user's appeared meanwhile (or an undeclared name)
            raise OutputError(
                f"{option} {real}: holds {', '.join(clash)}, which {command} would replace, and is not a folder "
                f"{command} wrote; choose another {option} (your files are left as they are)"
            )
        stale = sorted(owned - set(names)) if ours else []  # written by an older run, not by this one
        done: list[tuple[Path, Path | None]] = []
        try:
            for name in names:
                src, dst = stage / name, real / name
                done.append((dst, _aside(dst)))
                if src.is_dir() and (dst.exists() or dst.is_symlink()):
                    os.unlink(dst)  # a file or a link where the new folder goes (kept aside)
                os.replace(src, dst)
            for name in stale:
                if (real / name).exists() or (real / name).is_symlink():
                    done.append((real / name, _aside(real / name)))
                    _remove(real / name)
        except BaseException:
            _undo(done)
            raise
        for _, aside in done:
            if aside is not None:
                _remove(aside)


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
    marker: Marker = None,
    force: bool = False,
    command: str = "the command",
) -> Iterator[Path]:
    """Context manager: yield an empty temporary folder; when the block ends normally, its entries replace
    those of ``folder``.

    ``owned``: the names the command writes in ``folder`` (files, or folders such as ``figures`` that are
    replaced whole); nothing else there is touched.  ``marker``: a file name (or test) that makes an existing
    folder one the command wrote before; in any other folder an owned name is the user's, and the command is
    refused (OutputError, exit 7) unless ``force``, or unless the file there has the very bytes about to be
    written (checked again when committing, for every name written).  The checks of :func:`check_folder`
    run first.

    An exception or a signal in the block, or an OSError while committing, removes the temporary folder
    (and ``folder`` if it was made for this run and holds nothing else); an OSError from writing becomes an
    OutputError line naming the path (:func:`write_error`).
    """
    owned = set(owned)
    real = check_folder(folder, option, owned, marker, force, command)
    made: list[Path] = []
    stage: Path | None = None
    done = False
    try:
        try:
            made = _make_folders(real)
            stage = Path(tempfile.mkdtemp(prefix=TEMP_PREFIX, dir=real))
        except OSError as exc:
            raise write_error(folder, exc, option) from None
        try:
            yield stage
            _commit(stage, real, owned, marker, force, option, command)
        except OSError as exc:
            if _is_write_error(exc, real, stage):
                raise write_error(folder, exc, option) from None
            raise
        done = True
    finally:
        with signals_held():  # the clean-up itself is not cut short by a second Ctrl-C
            if stage is not None:
                shutil.rmtree(stage, ignore_errors=True)
            if not done:
                for made_folder in reversed(made):
                    with contextlib.suppress(OSError):
                        made_folder.rmdir()  # only if empty: a folder made for this run and nothing else


# --------------------------------------------------------------------------- writing one file


def write_file(path, content: str | bytes, option: str = "--out", example: str = "out.csv") -> Path:
    """Replace the file ``path`` with ``content`` atomically (a temporary file beside it, renamed over it).

    A link to a file is followed (the file is replaced, the link kept); an existing file keeps its mode, a new
    one gets the usual mode (0666 less the umask); missing parent folders are made.  Refusals and write
    failures are OutputError lines (exit 7); the temporary file is removed on any failure or signal.

    Returns
    -------
    Path
        ``path`` as given.
    """
    path = Path(path)
    real = check_file(path, option, example)
    data = content.encode("utf-8") if isinstance(content, str) else bytes(content)
    if real.exists() and not _regular(real):  # a device or a pipe: nothing to replace, nothing to leave behind
        try:
            with open(real, "wb") as fh:
                fh.write(data)
        except OSError as exc:
            raise write_error(path, exc, option) from None
        return path
    tmp = real.with_name(f"{TEMP_PREFIX}{real.name}-{uuid.uuid4().hex[:8]}")
    try:
        _make_folders(real.parent)
        mode = stat.S_IMODE(real.stat().st_mode) if real.exists() else None
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the umask applies
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        if mode is not None:
            os.chmod(tmp, mode)
        with signals_held():
            os.replace(tmp, real)
    except OSError as exc:
        raise write_error(path, exc, option) from None
    finally:
        with signals_held(), contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
    return path


__all__ = [
    "TEMP_PREFIX",
    "check_file",
    "check_folder",
    "clashes",
    "is_ours",
    "output_folder",
    "signals_held",
    "write_error",
    "write_file",
]
