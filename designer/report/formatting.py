"""Display strings of numbers, shared by every report kind: table cells in SI and inches, "n/a" for no value.

Display only: the units here (lbf, mph) never enter a computation.
"""

from __future__ import annotations

import math

import numpy as np

from designer.data.paper import INCH

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


UNITS = ("in", "mm")
"""How the first screen writes sizes (``[report] units``): inches to 1/16, or millimetres to 0.1."""


def size(value: float, units: str = "in") -> str:
    """A length [m] as a user writes it: ``"7 in"``, ``"1/2 in"``, ``"2 1/2 in"`` (inches to the nearest 1/16,
    a fraction in lowest terms), or ``"13 mm"``, ``"177.8 mm"`` (millimetres to 0.1, no trailing zero).

    A length that is not within 1/128 in of a sixteenth (a continuous optimum's 2.139 in) is marked as rounded:
    ``"≈ 2 1/8 in"``.  NaN or None is ``"n/a"``.  Display only.
    """
    if value is None or not math.isfinite(float(value)):
        return "n/a"
    if units == "mm":
        text = f"{value * 1000:.1f}".rstrip("0").rstrip(".")
        return f"{'0' if text in ('-0', '') else text} mm"
    sixteenths = round(value / INCH * 16)
    approx = abs(value / INCH * 16 - sixteenths) > 1 / 8  # more than 1/128 in from a sixteenth
    whole, rest = divmod(abs(sixteenths), 16)
    if rest:
        g = math.gcd(rest, 16)
        frac = f"{rest // g}/{16 // g}"
        text = f"{whole} {frac}" if whole else frac
    else:
        text = str(whole)
    sign = "-" if sixteenths < 0 else ""
    return f"{'≈ ' if approx else ''}{sign}{text} in"
