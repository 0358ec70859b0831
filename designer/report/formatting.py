"""Display strings of numbers, shared by every report kind: table cells in a format spec, through
:mod:`designer.display` (its one missing-value mark, its lengths in each unit system).
"""

from __future__ import annotations

import numpy as np

from designer.display import MISSING, number, shown
from designer.units import written_size


def fmt(value, spec: str = ".4g", unit: str = "") -> str:
    """Format a number for a table in the format ``spec`` with ``unit`` after it; None, NaN and infinities are
    :data:`designer.display.MISSING` (never "nan"), a flag "yes" or "no", text itself."""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if not isinstance(value, (int, float, np.floating, np.integer)) and value is not None:
        return str(value)
    if number(value) == MISSING:
        return MISSING
    return f"{format(float(value), spec)} {unit}".rstrip()


def length(value: float, digits: int = 2) -> tuple[str, str]:
    """(millimetres, inches) strings of a length in metres (:func:`designer.display.shown`)."""
    return shown(value, dimension="length", units="mm", digits=digits), shown(value, dimension="length", units="in")


size = written_size
"""A length [m] as the user writes it (:func:`designer.units.written_size`): "7 in", "1/2 in", "13 mm"."""
