"""Safe report folders: refuse a foreign folder, replace a report atomically, keep files it does not own."""

from __future__ import annotations

import errno
import json
import os
import shutil
import uuid
from pathlib import Path

from designer.errors import DesignerError, InputError

REPORT_MARKERS = ("index.html", "front.json")
"""Files that make a folder a report of this tool (every report has them)."""


def is_report(folder: Path) -> bool:
    """True if ``folder`` is empty or a report written by this tool (index.html and a front.json of a front)."""
    folder = Path(folder)
    if not folder.is_dir():
        return False
    if not any(folder.iterdir()):
        return True
    if not all((folder / name).is_file() for name in REPORT_MARKERS):
        return False
    try:
        data = json.loads((folder / "front.json").read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return False
    return isinstance(data, dict) and "problem" in data and "points" in data


def check_target(target: Path, force: bool = False) -> None:
    """Refuse (InputError, exit 2) to replace ``target`` unless it is absent, a previous report, or ``force``."""
    target = Path(target)
    if target.is_symlink() or (target.exists() and not target.is_dir()):
        raise InputError(f"report folder {target}: exists and is not a folder")
    if target.exists() and not force and not is_report(target):
        raise InputError(
            f"report folder {target}: exists and is not a report of this tool (no index.html and "
            f"front.json); choose another --out or pass --force to write the report into it"
        )


REPORT_OWNED = frozenset({"index.html", "report.md", "front.csv", "front.json", "checks.json", "figures"})
"""Names a report replace owns besides those it writes: anything else in the folder (``designer explore``'s
explore.csv and explore.json, the user's notes) is carried over into the new report folder."""


def _link_or_copy(src, dst) -> None:
    try:
        os.link(src, dst)
    except OSError:  # another file system, or one without hard links
        shutil.copy2(src, dst)


def _carry_over(old: Path, new: Path, owned=REPORT_OWNED) -> None:
    """Put into ``new`` what ``old`` holds and a report does not own, as hard links (else copies).

    Links, not moves: if the replace fails afterwards, ``new`` is deleted and ``old`` still has everything.
    """
    for entry in old.iterdir():
        if entry.name in owned or entry.name.startswith(".") and ".tmp-" in entry.name:
            continue
        dest = new / entry.name
        if dest.exists() or dest.is_symlink():  # the new report wrote it: it owns it
            continue
        if entry.is_symlink():
            os.symlink(os.readlink(entry), dest)
        elif entry.is_dir():
            shutil.copytree(entry, dest, symlinks=True, copy_function=_link_or_copy)
        else:
            _link_or_copy(entry, dest)


def _replace(tmp: Path, target: Path, owned=REPORT_OWNED) -> None:
    """Move the finished ``tmp`` folder to ``target`` by renames; an old ``target`` is removed only afterwards.

    Files of the old ``target`` that the report does not own (:data:`REPORT_OWNED`, e.g. explore.csv
    and explore.json) are linked into ``tmp`` first, so the new folder has them from its first moment.
    Another process writing the same report at once may rename its own folder into place between
    our renames; then ours is retried, so the target ends as one complete report (the last one in),
    never a mixture, and no moved-aside folder is left behind.
    """
    olds = []
    try:
        for _ in range(50):
            if target.is_symlink() or (target.exists() and not target.is_dir()):
                raise InputError(f"report folder {target}: exists and is not a folder")
            if target.exists():
                try:
                    _carry_over(target, tmp, owned)
                except FileNotFoundError:  # another writer moved it aside meanwhile: retry
                    continue
                old = target.with_name(f".{target.name}.old-{uuid.uuid4().hex[:8]}")
                try:
                    target.rename(old)
                except FileNotFoundError:  # another writer moved it aside first
                    continue
                olds.append(old)
            try:
                tmp.rename(target)
                return
            except OSError as exc:
                if exc.errno not in (errno.ENOTEMPTY, errno.EEXIST):
                    raise
                # another writer's report landed in between: move it aside and retry
        raise DesignerError(f"report folder {target}: other processes keep replacing it; try again")
    except BaseException:
        if olds and not target.exists():
            try:
                olds.pop().rename(target)
            except OSError:
                pass
        raise
    finally:
        for old in olds:
            shutil.rmtree(old, ignore_errors=True)
