"""The installed versions a report or a result file records (read from the installed distributions' metadata,
so nothing heavy is imported to learn them)."""

from __future__ import annotations

import platform
from importlib.metadata import PackageNotFoundError, version

PACKAGES = ("caster-designer", "numpy", "scipy", "casadi", "cvxpy", "optuna", "matplotlib", "jinja2")
"""Distributions whose versions go into every report and result file."""


def versions() -> dict[str, str | None]:
    """Installed versions of :data:`PACKAGES` (None for one not installed) and of Python."""
    out: dict[str, str | None] = {}
    for name in PACKAGES:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = None
    out["python"] = platform.python_version()
    return out
