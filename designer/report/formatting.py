"""Display strings of numbers, shared by every report kind: table cells in SI and inches, "n/a" for no value.

Display only: the units here (lbf, mph) never enter a computation.
"""

from __future__ import annotations

import math

import numpy as np

from designer.data.paper import INCH
from designer.units import written_size

LBF = 4.4482216152605
"""One pound-force [N] (display only)."""
MPH = 0.44704
"""One mile per hour [m/s] (display only)."""


def fmt(value, spec: str = ".4g", unit: str = "") -> str:
    """Format a number for a table; None, NaN and infinities become "n/a" (never "nan")."""
    if value is None:
        return "n/a"
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (int, float, np.floating, np.integer)):
        if not math.isfinite(float(value)):
            return "n/a"
        text = format(float(value), spec)
        return f"{text} {unit}".rstrip()
    return str(value)


def length(value: float, digits: int = 2) -> tuple[str, str]:
    """(millimetres, inches) strings of a length in metres."""
    return fmt(value * 1000, f".{digits}f", "mm"), fmt(value / INCH, ".3f", "in")


size = written_size
"""A length [m] as the user writes it (:func:`designer.units.written_size`): "7 in", "1/2 in", "13 mm"."""
