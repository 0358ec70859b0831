"""Guards on numeric inputs that pass CasADi symbols through untouched."""

from __future__ import annotations

import numpy as np

from designer.errors import InputError
from designer.physics.types import Scalar


def enable_casadi() -> None:
    """Import CasADi and switch on its NumPy mode (``np.sqrt`` of a symbol is a CasADi expression).

    Called by the solvers before they build symbols; CasADi is imported here, late, because
    ``import designer`` must not pay for it.
    """
    import casadi  # heavy: loaded only when symbols are built

    try:  # type-preserving NumPy functions on CasADi values (casadi >= 3.7.2)
        casadi.GlobalOptions.setNumpyMode(1)
    except AttributeError:  # pragma: no cover - older casadi: legacy behaviour
        pass


def is_symbolic(*values: object) -> bool:
    """True if any value is a CasADi SX or MX expression (not checkable numerically)."""
    symbolic = any(type(v).__module__.startswith("casadi") and type(v).__name__ in ("SX", "MX") for v in values)
    if symbolic:
        enable_casadi()
    return symbolic


def require_positive(name: str, value: Scalar, allow_zero: bool = False) -> None:
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


def _show(value: Scalar) -> str:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return f"{float(arr):g}"
    return f"array with min {np.nanmin(arr):g}"
