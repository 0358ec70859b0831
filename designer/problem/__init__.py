"""Problem files (TOML) -> validated, immutable :class:`Problem` objects.

Schema: docs/problem-file.md.  Every quantity is a number in SI units or a string with
units ("2 in", "20 deg"); a design variable given one value instead of
``{min, max}`` is fixed.  Everything is checked before any solve, and every
error is one line naming the key, the value and the reason.

Modules
-------
_core      the :class:`Problem` record (bounds, stock, risk, constraint margins), its validation, the ranges and
           :data:`SCHEMA` (the keys that are not quantities)
_loader    problem file / TOML text / dict -> :class:`Problem` (:func:`load_problem`, :func:`problem_from_dict`)
_stock     the ``[stock]`` section: parts that exist
_examples  the shipped example problems (package data): :func:`example_problem`, :func:`example_names`

The public names are in ``__all__``: import them from ``designer.problem``.
"""

from __future__ import annotations

from designer.problem._core import (
    DEFAULT_BOUNDS,
    DEFAULT_PART_COSTS,
    PART_KINDS,
    INERTIA_RANGE,
    MAX_SAMPLES,
    PHYSICAL_RANGE,
    POINTS_RANGE,
    PROBABILITY_RANGE,
    REPORT_UNITS,
    SCHEMA,
    Bound,
    Problem,
    Stock,
    Tolerances,
    check_range,
    check_weights,
    family_of,
)
from designer.problem._examples import example_names, example_problem, example_text
from designer.problem._loader import (
    load_problem,
    problem_argument,
    problem_files,
    problem_from_dict,
    problem_from_toml,
    problem_path,
    tolerances_option,
)

__all__ = [
    "tolerances_option",
    "DEFAULT_BOUNDS",
    "DEFAULT_PART_COSTS",
    "PART_KINDS",
    "INERTIA_RANGE",
    "MAX_SAMPLES",
    "PHYSICAL_RANGE",
    "POINTS_RANGE",
    "PROBABILITY_RANGE",
    "REPORT_UNITS",
    "SCHEMA",
    "Bound",
    "Problem",
    "Stock",
    "Tolerances",
    "check_range",
    "check_weights",
    "example_names",
    "example_problem",
    "example_text",
    "family_of",
    "load_problem",
    "problem_argument",
    "problem_files",
    "problem_path",
    "problem_from_dict",
    "problem_from_toml",
]
