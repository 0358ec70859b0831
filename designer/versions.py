"""The installed versions a report or a result file records (read from the installed distributions' metadata,
so nothing heavy is imported to learn them)."""

from __future__ import annotations

import contextlib
import platform
from importlib.metadata import PackageNotFoundError, version

PACKAGES = ("caster-designer", "numpy", "scipy", "casadi", "cvxpy", "optuna", "matplotlib", "jinja2")
"""Distributions whose versions go into every report and result file."""


def versions() -> dict[str, str | None]:
    """Installed versions of :data:`PACKAGES` (None for one not installed) and of Python."""
    out: dict[str, str | None] = dict.fromkeys(PACKAGES)
    for name in PACKAGES:
        with contextlib.suppress(PackageNotFoundError):
            out[name] = version(name)
    return out | {"python": platform.python_version()}
