"""Regenerate the committed reports of every shipped problem: ``python -m designer.cli.regenerate``.

Runs ``designer pareto`` on each ``problems/*.toml`` and writes
``results/<problem>/``.  Equivalent to ``designer pareto --all``.  The exit
code is 1 if a check of any front fails (the reports are written anyway).

Usage::

    python -m designer.cli.regenerate [PROBLEMS_DIR_OR_FILES ...] [--out results] [--points N]
"""

from __future__ import annotations

import sys

from designer.cli import main as cli_main
from designer.problem import problem_files
import argparse

__all__ = ["main", "problem_files"]


def main(argv: list[str] | None = None) -> int:
    """Entry point: ``designer pareto --all`` on each folder (or file) given, default ``problems``."""

    parser = argparse.ArgumentParser(
        prog="python -m designer.cli.regenerate",
        description="Regenerate results/<problem>/ for every shipped problem.",
    )
    parser.add_argument("where", nargs="*", default=["problems"], help="problem folders or files (default problems)")
    parser.add_argument("--out", default="results", help="parent folder of the reports (default results)")
    parser.add_argument("--points", default=None, help="front points (default: each problem's)")
    args = parser.parse_args(argv)
    # --force: the committed reports are the repository's own, and those written before manifests
    # (.designer-manifest.json, designer.output) prove nothing by themselves; the rerun writes their manifests
    extra = ["--out", args.out, "--force"] + (["--points", args.points] if args.points else [])
    code = 0
    for where in args.where:
        code = max(code, cli_main(["pareto", "--all", where, *extra]))
    return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
