"""JSON-safe data: the one place that turns results into plain, finite JSON values."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np


SCHEMA_VERSION = 1
"""The version of the JSON files the tool writes and of its ``--json`` output; raised when a key changes meaning or
goes away (CHANGELOG.md says what changed), not when a key is added."""


RESOLVED_DIGITS = 12
"""Significant digits of every number in the JSON the tool writes: more than anything the tool resolves (the
solver's 9, designer.report.resolution), fewer than a float's 17, so 7 in is 0.1778, not 0.17779999999999999."""


def stamped(kind: str, data: dict[str, Any]) -> dict[str, Any]:
    """``data`` with its ``schema`` first: ``"caster-designer/<kind>/<SCHEMA_VERSION>"`` (``kind``: the file, e.g.
    ``"front.json"``, or the command of a ``--json`` output), as plain JSON data (:func:`finite`) with every number
    at the precision it is resolved to (:func:`resolved_numbers`): every JSON file and ``--json`` output is stamped
    here, so one rule writes their numbers."""
    return {"schema": f"caster-designer/{kind}/{SCHEMA_VERSION}", **finite(data, RESOLVED_DIGITS)}


def finite(value: Any, digits: int | None = None) -> Any:
    """JSON-safe copy: non-finite floats become None, NumPy scalars and arrays plain Python; with ``digits``,
    every float at that many significant digits (:func:`resolved_numbers`).

    Reports, ``--json`` output and exploration files all pass through this, so
    no NaN or infinity ever reaches a file or a terminal as a number.
    """
    kind = type(value)
    if kind is float:  # the common cases first, by exact type: a report holds some 10^5 values
        if not math.isfinite(value):
            return None
        return value if digits is None else float(f"{value:.{digits}g}")
    if kind is str or kind is int or kind is bool or value is None:
        return value
    if kind is dict:
        return {k if type(k) is str else str(k): finite(v, digits) for k, v in value.items()}
    if isinstance(value, Mapping):  # a record's read-only mapping (designer.reprs.FrozenMapping), other mappings
        return {str(k): finite(v, digits) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v, digits) for v in value]
    if isinstance(value, np.ndarray):
        return finite(value.tolist(), digits)
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        return finite(float(value), digits)
    return value


def resolved_numbers(value: Any, digits: int = RESOLVED_DIGITS) -> Any:
    """A copy of plain JSON data (:func:`finite`'s output) with every float at ``digits`` significant digits
    (:func:`designer.units.resolved`): 0.1778 for 7 in, not 0.17779999999999999."""
    return finite(value, digits)
