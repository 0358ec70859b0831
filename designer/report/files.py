"""Report folders: the owned names of a Pareto report, and the check of its folder before computing.

The writing itself (temporary folder inside the target, renames of the owned names only, one-line errors,
exit 7 for the user's setup) is :mod:`designer.output`, shared by every command that writes.
"""

from __future__ import annotations

from pathlib import Path

from designer.output import check_folder

REPORT_OWNED = frozenset({"index.html", "report.md", "front.csv", "front.json", "checks.json", "figures", "run.json"})
"""Names a Pareto report owns in its folder: anything else there (``designer explore``'s explore.csv and
explore.json, the user's notes) is left as it is."""


def check_target(target: Path, force: bool = False, option: str = "--out") -> Path:
    """Check a Pareto report's folder before computing; returns it with links resolved.

    :func:`designer.output.check_folder`, the rule of every command (exit 7): a regular file, a path under one,
    an unwritable place, or a folder holding a report's names that its manifest does not prove the tool's
    (the user's files, a report edited since) is refused, unless ``force``, which writes the report's own
    files into it and leaves every other file there as it is.
    """
    return check_folder(target, option, owned=REPORT_OWNED, force=force, command="designer pareto")


__all__ = ["REPORT_OWNED", "check_target"]
