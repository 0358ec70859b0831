"""JSON-safe data: the one place that turns results into plain, finite JSON values."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np


SCHEMA_VERSION = 1
"""The version of the JSON files the tool writes and of its ``--json`` output; raised when a key changes meaning or
goes away (CHANGELOG.md says what changed), not when a key is added."""


def stamped(kind: str, data: dict[str, Any]) -> dict[str, Any]:
    """``data`` with its ``schema`` first: ``"caster-designer/<kind>/<SCHEMA_VERSION>"`` (``kind``: the file, e.g.
    ``"front.json"``, or the command of a ``--json`` output)."""
    return {"schema": f"caster-designer/{kind}/{SCHEMA_VERSION}", **data}


def finite(value: Any) -> Any:
    """JSON-safe copy: non-finite floats become None, NumPy scalars and arrays plain Python.

    Reports, ``--json`` output and exploration files all pass through this, so
    no NaN or infinity ever reaches a file or a terminal as a number.
    """
    if isinstance(value, Mapping):  # a dict, or a record's read-only mapping (designer.reprs.FrozenMapping)
        return {str(k): finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    if isinstance(value, np.ndarray):
        return finite(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(float(value)) else None
    return value
