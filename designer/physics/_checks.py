"""Guards on numeric inputs that pass CasADi symbols through untouched."""
from __future__ import annotations

import numpy as np

from designer.errors import InputError


def is_symbolic(*values) -> bool:
    """True if any value is a CasADi SX or MX expression (not checkable numerically)."""
    import casadi

    return any(isinstance(v, (casadi.SX, casadi.MX)) for v in values)


def require_positive(name: str, value, allow_zero: bool = False) -> None:
    """Raise InputError if a numeric ``value`` is not > 0 (or >= 0) and finite."""
    if is_symbolic(value):
        return
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} = {_show(value)}: must be finite")
    bad = arr < 0 if allow_zero else arr <= 0
    if np.any(bad):
        sign = "non-negative" if allow_zero else "positive"
        raise InputError(f"{name} = {_show(value)}: must be {sign}")


def _show(value) -> str:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return f"{float(arr):g}"
    return f"array with min {np.nanmin(arr):g}"
