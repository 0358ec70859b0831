"""Problem files (TOML) -> validated, immutable :class:`Problem` objects.

Schema: docs/problem-file.md.  Every quantity is a number in SI units or a string with
units ("2 in", "20 deg"); a design variable given one value instead of
``{min, max}`` is fixed.  Everything is checked before any solve, and every
error is one line naming the key, the value and the reason.

Modules
-------
core    the :class:`Problem` record (bounds, stock, risk, constraint margins), its validation, the ranges and
        :data:`SCHEMA` (the keys that are not quantities)
loader  problem file / TOML text / dict -> :class:`Problem` (:func:`load_problem`, :func:`problem_from_dict`)

Every name is importable from ``designer.problem`` itself.
"""

from __future__ import annotations

from designer.model import MODEL_RANGE
from designer.problem.core import (
    DEFAULT_BOUNDS,
    INERTIA_MODELS,
    INERTIA_RANGE,
    MAX_SAMPLES,
    NAME_PATTERN,
    PHYSICAL_RANGE,
    POINTS_RANGE,
    SCHEMA,
    VARIABLE_DIMENSIONS,
    WEIGHT_RANGE,
    Bound,
    Problem,
    Stock,
    StockWheel,
    check_range,
    check_weights,
)
from designer.problem.loader import load_problem, problem_files, problem_from_dict, problem_from_toml

__all__ = [
    "DEFAULT_BOUNDS",
    "INERTIA_MODELS",
    "INERTIA_RANGE",
    "MAX_SAMPLES",
    "MODEL_RANGE",
    "NAME_PATTERN",
    "PHYSICAL_RANGE",
    "POINTS_RANGE",
    "SCHEMA",
    "VARIABLE_DIMENSIONS",
    "WEIGHT_RANGE",
    "Bound",
    "Problem",
    "Stock",
    "StockWheel",
    "check_range",
    "check_weights",
    "load_problem",
    "problem_files",
    "problem_from_dict",
    "problem_from_toml",
]
