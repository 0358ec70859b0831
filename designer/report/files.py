"""Report folders: which folder is a report of this tool, and the owned names of each report kind.

The writing itself (temporary folder inside the target, renames of the owned names only, one-line errors,
exit 7 for the user's setup) is :mod:`designer.output`, shared by every command that writes.
"""

from __future__ import annotations

import json
from pathlib import Path

from designer.errors import InputError
from designer.output import TEMP_PREFIX, check_folder

REPORT_MARKERS = ("index.html", "front.json")
"""Files that make a folder a report of this tool (every report has them)."""

REPORT_OWNED = frozenset({"index.html", "report.md", "front.csv", "front.json", "checks.json", "figures", "run.json"})
"""Names a Pareto report owns in its folder: anything else there (``designer explore``'s explore.csv and
explore.json, the user's notes) is left as it is."""

NEIGHBOURS = frozenset({"explore.csv", "explore.json"})
"""Files another command of this tool writes into a report folder (``designer explore``)."""


def is_report(folder: Path) -> bool:
    """True if ``folder`` is empty, holds only files of this tool's other commands (explore.csv/json), or is
    a report written by this tool (index.html and a front.json of a front)."""
    folder = Path(folder)
    if not folder.is_dir():
        return False
    names = {e.name for e in folder.iterdir() if not e.name.startswith(TEMP_PREFIX)}
    if names <= NEIGHBOURS:
        return True
    if not all((folder / name).is_file() for name in REPORT_MARKERS):
        return False
    try:
        data = json.loads((folder / "front.json").read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return False
    return isinstance(data, dict) and "problem" in data and "points" in data


def check_target(target: Path, force: bool = False, option: str = "--out") -> Path:
    """Check a Pareto report's folder before computing; returns it with links resolved.

    A regular file, a path under one, or an unwritable place is an OutputError (exit 7,
    :func:`designer.output.check_folder`); a folder that is not a report of this tool is refused with
    InputError (exit 2, the user may have mistyped) unless ``force``, which writes the report's own files
    into it and leaves every other file there as it is.
    """
    real = check_folder(target, option)
    if real.exists() and not force and not is_report(real):
        raise InputError(
            f"report folder {target}: exists and is not a report of this tool (no index.html and "
            f"front.json); choose another {option} or pass --force to write the report into it"
        )
    return real


__all__ = ["NEIGHBOURS", "REPORT_MARKERS", "REPORT_OWNED", "check_target", "is_report"]
