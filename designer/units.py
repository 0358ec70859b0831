"""Quantities with units at the edges: parse user input into SI floats.

Problem files and command-line options accept either plain numbers, taken as
SI, or strings with units ("2 in", "50.8 mm", "20 deg", "1.3 N*m/rad").
Inside the package every quantity is a float in SI units; pint is used only
here, never in the model's hot paths.
"""

from __future__ import annotations

import math
import numbers
import re
from fractions import Fraction
from functools import lru_cache
from typing import Any

from designer.errors import InputError

INCH = 0.0254
"""One inch [m] (exact, by the international yard and pound agreement of 1959): the one definition of the
package; plots, reports and messages show lengths in inches with it."""


CSV_UNITS = {
    "force": ("N", 1.0),
    "speed": ("m_per_s", 1.0),
    "damping": ("N_m_per_rad", 1.0),
    "angle": ("rad", 1.0),
    "angular_speed": ("rad_per_s", 1.0),
    "time": ("s", 1.0),
    "inertia": ("kgm2", 1.0),
    "mass": ("kg", 1.0),
    "stiffness": ("N_per_m", 1.0),
    "per_length": ("per_m", 1.0),
    "moment": ("N_m", 1.0),
}
"""The unit a CSV column of each dimension but length is written in: (name suffix, factor from SI)."""

LENGTH_UNITS = {"in": ("in", 1 / INCH), "mm": ("mm", 1000.0), "m": ("m", 1.0)}
"""The unit a CSV column of a length is written in, by the problem's units: (name suffix, factor from SI)."""


def csv_column(name: str, dimension: str, units: str = "in") -> tuple[str, float]:
    """The one rule for the CSV files the tool writes: the name a spreadsheet sees for a quantity's column and
    the factor from SI to its values.  A length in the problem's units, ``("trail_in", 1 / INCH)`` or
    ``("trail_mm", 1000)``; a force ``("threshold_force_N", 1)``, a speed ``..._m_per_s``, a damping
    ``..._N_m_per_rad`` (:data:`CSV_UNITS`); anything else (flags, fractions, counts: ``dimension`` "" or
    "dimensionless") keeps its name, factor 1.  A name that already ends in its unit is not named twice."""
    if dimension == "length":
        suffix, factor = LENGTH_UNITS.get(units, LENGTH_UNITS["in"])
    else:
        suffix, factor = CSV_UNITS.get(dimension, ("", 1.0))
    if not suffix or name.endswith(f"_{suffix}"):
        return name, factor
    return f"{name}_{suffix}", factor


_SUFFIXES = sorted([*LENGTH_UNITS.values(), *CSV_UNITS.values()], key=lambda sf: -len(sf[0]))


def csv_quantity(column: str) -> tuple[str, float]:
    """The inverse of :func:`csv_column`: the quantity a column names and the factor from SI to its values
    (``"trail_in"`` -> ``("trail", 1 / INCH)``, ``"turning_effort_N"`` -> ``("turning_effort", 1)``); a name
    without a unit (``"status"``, or a column written before the columns named their units) is itself, 1."""
    for suffix, factor in _SUFFIXES:
        if column.endswith(f"_{suffix}") and len(column) > len(suffix) + 1:
            return column[: -len(suffix) - 1], factor
    return column, 1.0


def resolved(value: float, digits: int = 12) -> float:
    """``value`` at ``digits`` significant digits: the precision a number is resolved to, so that JSON and
    CSV show 0.1778 for 7 in and not 0.17779999999999999 (binary rounding of 7 times the inch)."""
    return float(f"{value:.{digits}g}") if math.isfinite(value) else value


MISSING = "n/a"
"""The one mark of a value that does not exist (None, NaN, an infinity): every surface prints this
(:data:`designer.display.MISSING`)."""


def written_size(value: float | None, units: str = "in") -> str:
    """A length [m] as a user writes it: ``"7 in"``, ``"1/2 in"``, ``"2 1/2 in"`` (inches to the nearest 1/16, a
    fraction in lowest terms), or ``"13 mm"``, ``"177.8 mm"`` (millimetres to 0.1, no trailing zero).

    A length that is not within 1/128 in of a sixteenth (a continuous optimum's 2.139 in) is marked as rounded:
    ``"≈ 2 1/8 in"``.  NaN or None is :data:`MISSING`.  Display only (reports, ``designer fix``, the drawing).
    """
    if value is None or not math.isfinite(float(value)):
        return MISSING
    if units == "mm":
        text = f"{value * 1000:.1f}".rstrip("0").rstrip(".")
        return f"{'0' if text in ('-0', '') else text} mm"
    sixteenths = round(value / INCH * 16)
    approx = abs(value / INCH * 16 - sixteenths) > 1 / 8  # more than 1/128 in from a sixteenth
    whole, rest = divmod(abs(sixteenths), 16)
    frac = str(Fraction(rest, 16)) if rest else ""  # in lowest terms
    text = f"{whole} {frac}" if whole and rest else frac or str(whole)
    sign = "-" if sixteenths < 0 else ""
    return f"{'≈ ' if approx else ''}{sign}{text} in"


MAX_TEXT = 100
"""Longest quantity string accepted (characters)."""

_ALLOWED = re.compile(r"^[0-9A-Za-z_\s.+\-*/^()%°·µμ²³]*$")
"""Characters of a number with units; anything else (brackets, commas, quotes) is rejected before pint sees it."""

_EXPONENT = re.compile(r"(\*\*|\^)\s*([-+]?\s*)([0-9.]+(?:[eE][-+]?[0-9]+)?|\(|[A-Za-z_])")
"""An exponent operator and what follows it: a short number is fine, a bracket or a name is not."""

#: Dimension name -> (pint unit the value is converted to, SI unit shown to users).
DIMENSIONS: dict[str, tuple[str, str]] = {
    "length": ("m", "m"),
    "force": ("N", "N"),
    "speed": ("m/s", "m/s"),
    "angle": ("rad", "rad"),
    "damping": ("N*m/rad", "N·m/rad"),
    "inertia": ("kg*m**2", "kg·m²"),
    "mass": ("kg", "kg"),
    "density": ("kg/m**3", "kg/m³"),
    "stiffness": ("N/m", "N/m"),
    "per_length": ("1/m", "1/m"),
    "moment": ("N*m", "N·m"),
    "angular_speed": ("rad/s", "rad/s"),
    "rate": ("1/s", "1/s"),
    "frequency": ("Hz", "Hz"),
    "time": ("s", "s"),
    "dimensionless": ("", "-"),
    "probability": ("", "%"),
}


@lru_cache(maxsize=1)
def _registry():
    import pint

    return pint.UnitRegistry()


def parse_quantity(value, dimension: str, key: str = "value") -> float:
    """Convert ``value`` to a float in SI units of ``dimension``.

    Parameters
    ----------
    value : float | int | str
        A number (taken as SI: metres, newtons, radians, ...) or a string with
        units, e.g. ``"2 in"``, ``"20 deg"``, ``"1.3 N*m/rad"``.
    dimension : str
        One of :data:`DIMENSIONS` (``"length"``, ``"force"``, ...).
    key : str
        Name of the input, used in error messages.

    Returns
    -------
    float
        The value in SI units (angles in radians).

    Raises
    ------
    InputError
        One line naming ``key``, the value and the reason: not a number, NaN
        or infinite, unknown unit, or a unit of the wrong dimension.
    """
    target, shown = DIMENSIONS[dimension]
    if isinstance(value, str):
        number = _parse_string(value, target, shown, dimension, key)
        if not math.isfinite(number):
            raise InputError(f"{key} = {value!r}: must be a finite number")
        return number
    return real_number(value, key, f"a number (SI, {shown}) or a string with units such as {example(dimension)!r}")


def _boolean(value: Any) -> bool:
    """A boolean: Python's ``True``/``False`` or NumPy's ``np.bool_`` (a 0-d boolean array too)."""
    return isinstance(value, bool) or type(value).__name__ in ("bool_", "bool") and type(value).__module__ == "numpy"


def _item(value: Any, key: str, expected: str, kind: type) -> Any:
    """``value`` (a NumPy 0-d array as its one value) when it is a ``kind`` (:class:`numbers.Real` or
    :class:`numbers.Integral`) and no boolean; else one InputError line saying ``expected``."""
    item = value  # a NumPy 0-d array read by its attributes: this module does not import NumPy
    if type(value).__module__ == "numpy" and getattr(value, "shape", None) == () and hasattr(value, "item"):
        item = value.item()
    if _boolean(value) or _boolean(item):
        raise InputError(f"{key} = {value!r}: expected {expected}, got a boolean")
    if not isinstance(item, kind):
        raise InputError(f"{key} = {value!r}: expected {expected}")
    return item


def real_number(value: Any, key: str, expected: str = "a number") -> float:
    """The one rule for a number at the package's boundary: ``value`` as a finite float, or one InputError line
    naming ``key``, the value and the reason.

    A number is a :class:`numbers.Real` (``int``, ``float``, ``fractions.Fraction``, NumPy's scalars such as
    ``np.float32(900)`` and ``np.int64(900)``) or a NumPy 0-d array of one; a boolean (``True``, ``np.bool_``)
    is never a number, however Python counts it; NaN and infinities are refused as such.  ``expected`` says
    what was wanted, in the message for a value that is not a number.  Strings with units are read by
    :func:`parse_quantity`, which calls this for everything else: the problem file, the command line and every
    public function and record of the API use these two.
    """
    item = _item(value, key, expected, numbers.Real)
    try:
        number = float(item)
    except OverflowError:
        raise InputError(
            f"{key}: an integer of about {int(getattr(item, 'bit_length', lambda: 0)() * 0.30103)} digits is too large"
        ) from None
    if not math.isfinite(number):
        raise InputError(f"{key} = {value!r}: must be a finite number")
    return number


def whole_number(
    value: Any, key: str, low: int | None = None, high: int | None = None, what: str = "", optional: bool = False
) -> int:
    """The one rule for a count or a seed at the boundary: ``value`` as an int within [``low``, ``high``] (either
    end None: open), or one InputError line naming ``key``, the value and the range.

    A count is a :class:`numbers.Integral` (``int``, ``np.int64``, ...) or a NumPy 0-d array of one; a
    boolean, a float (``1024.0``, ``2.5``) and a string are refused, as the command line refuses them.
    ``what`` names the thing counted in the message ("Monte Carlo draws"); ``optional``: the message says that
    None is also taken (the caller passes None on before).
    """
    span = ""
    if low is not None:
        span = f" from {low} to {high}" if high is not None else f", {low} or more"
    elif high is not None:
        span = f", {high} or less"
    expected = ("None or " if optional else "") + "a whole number" + (f" of {what}" if what else "") + span
    number = int(_item(value, key, expected, numbers.Integral))
    if (low is not None and number < low) or (high is not None and number > high):
        raise InputError(f"{key} = {number}: expected {expected}")
    return number


#: The units problem files use most, with their exact SI factors (inch and pound by the 1959 agreement, the
#: degree as pi/180): ``"2.5 in"`` is read without loading pint, which costs about 0.9 s of CPU on a cold
#: start (its import and registry).  Anything else, and every error, goes through pint; a test checks each
#: factor against pint's own conversion.
COMMON_UNITS: dict[str, tuple[str, float]] = {
    "m": ("length", 1.0),
    "cm": ("length", 0.01),
    "mm": ("length", 0.001),
    "in": ("length", INCH),
    "inch": ("length", INCH),
    "ft": ("length", 0.3048),
    "N": ("force", 1.0),
    "kN": ("force", 1000.0),
    "lbf": ("force", 4.4482216152605),
    "m/s": ("speed", 1.0),
    "km/h": ("speed", 1000.0 / 3600.0),
    "mph": ("speed", 0.44704),
    "rad": ("angle", 1.0),
    "deg": ("angle", math.pi / 180.0),
    "degree": ("angle", math.pi / 180.0),
    "N*m/rad": ("damping", 1.0),
    "N*m": ("moment", 1.0),
    "kg": ("mass", 1.0),
    "g": ("mass", 0.001),
    "lb": ("mass", 0.45359237),
    "kg*m**2": ("inertia", 1.0),
    "kg/m**3": ("density", 1.0),
    "N/m": ("stiffness", 1.0),
}

_COMMON = re.compile(r"^([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?) ?(\S+)$")
"""A number, at most one space and a unit of :data:`COMMON_UNITS` (e.g. ``"2.5 in"``, ``"1.3 N*m/rad"``)."""


def _common(text: str, dimension: str) -> float | None:
    """``text`` in SI when it is a number and a :data:`COMMON_UNITS` unit of ``dimension``; else None."""
    match = _COMMON.match(text) if len(text) <= MAX_TEXT else None
    if match is None or COMMON_UNITS.get(match.group(2), ("", 0.0))[0] != dimension:
        return None
    number = float(match.group(1))
    if not math.isfinite(number) or abs(number) > 1e300:
        return None  # let pint say what is wrong
    return number * COMMON_UNITS[match.group(2)][1]


_MIXED = re.compile(r"^\s*([+-]?)(\d+)\s+(\d+)\s*/\s*(\d+)(?=\s*[^\d\s./*]|\s*$)(.*)$", re.S)
"""A mixed number, "2 1/2 in" (whole, numerator, denominator, then the unit): the tool writes sizes so."""


def _parse_string(text: str, target: str, shown: str, dimension: str, key: str) -> float:
    m = _MIXED.match(text)
    if m and int(m[4]) != 0:  # as one decimal ("2.5 in"): pint alone reads "2 1/2" as 2 × 1/2 = 1
        text = f"{m[1]}{int(m[2]) + int(m[3]) / int(m[4])!r} {m[5].strip()}".strip()
    fast = _common(text.strip(), dimension)
    if fast is not None:
        return fast
    import pint

    ureg = _registry()
    stripped = text.strip()
    if not stripped:
        raise InputError(f"{key} = {text!r}: empty string; give a number or e.g. {example(dimension)!r}")
    _check_text(stripped, text, key, dimension)
    try:
        quantity = ureg.Quantity(stripped)
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError) as exc:
        raise InputError(f"{key} = {text!r}: unknown unit ({exc})") from None
    except OverflowError:
        raise InputError(f"{key} = {text!r}: the number is too large") from None
    except Exception as exc:  # tokenizer errors, bad syntax
        raise InputError(f"{key} = {text!r}: cannot read it as a quantity ({type(exc).__name__})") from None
    try:
        if not isinstance(quantity, ureg.Quantity):
            return float(quantity)
        magnitude = quantity.to(target or "dimensionless").magnitude
        _check_kind(quantity, text, dimension, key)
        return float(magnitude)
    except InputError:  # _check_kind's reason
        raise
    except pint.errors.DimensionalityError:
        if not dict(quantity.unit_items()):  # "3" for a speed: the true reason is the missing unit
            raise InputError(
                f"{key} = {text!r}: a number without its unit; give a number (SI, {shown}) or a string with "
                f"its unit such as {example(dimension)!r}"
            ) from None
        hint = _mass_for_force_hint(quantity, stripped, key) if dimension == "force" else ""
        raise InputError(
            f"{key} = {text!r}: wrong dimension, expected {dimension} ({shown}), e.g. {example(dimension)!r}{hint}"
        ) from None
    except OverflowError:
        raise InputError(f"{key} = {text!r}: the number is too large") from None
    except (TypeError, ValueError):
        raise InputError(f"{key} = {text!r}: not a single number") from None


ANGLE_UNITS = frozenset(
    {"radian", "degree", "turn", "revolution", "arcminute", "arcsecond", "gradian", "milliradian", "microradian"}
)
"""pint unit names of angles: pint treats the radian as dimensionless, so "N*m" converts to "N*m/rad"
silently; a damping must name the angle it is per."""


def _check_kind(quantity, text: str, dimension: str, key: str) -> None:
    """Reject what pint would convert although it is another quantity: a moment given for a damping
    (N·m, no angle in the denominator), a mass given for a force (lb, kg)."""
    units = dict(quantity.unit_items())
    per_angle = any(name in ANGLE_UNITS and power < 0 for name, power in units.items())
    if dimension == "damping" and not per_angle:
        raise InputError(
            f"{key} = {text!r}: a moment (or energy), not a damping; a damping is a moment per "
            f"angle: write it per radian, e.g. {example('damping')!r}"
        )
    if dimension == "moment" and per_angle:
        raise InputError(f"{key} = {text!r}: a damping (moment per angle), not a moment; e.g. {example('moment')!r}")


def _mass_for_force_hint(quantity, text: str, key: str) -> str:
    """A hint for a mass written where a force is expected ("40 lb" -> "40 lbf")."""
    if quantity.dimensionality != _registry().kilogram.dimensionality:
        return ""
    units = dict(quantity.unit_items())
    if any(name in ("pound", "avoirdupois_pound") for name in units):
        suggestion = re.sub(r"\b(lbs|lb|pounds?)\b", "lbf", text)
        return f"; lb is a mass (pound): for a force write {suggestion.strip()!r} (pound-force)"
    return "; that is a mass: write a force, e.g. '40 lbf', '18 kgf' or '178 N'"


_GLUED = re.compile(r"^((?>[-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?))\s*([A-Za-z].*)$")
"""A number glued to its unit, e.g. ``2in``: a space is put between the two before pint sees it.  The number
is an atomic group: an exponent it has read (``2e0``) is never given back as a unit named ``e0``."""


def parse_quantity_text(value: str | None, dimension: str, key: str, default: float | None = None) -> float | None:
    """Parse a typed quantity ("2in", "2 in", "50.8 mm", a plain SI number) into an SI float.

    The command-line options and the studio's text boxes read quantities with this; ``default`` is
    returned for ``None`` (an option not given).  Errors as :func:`parse_quantity`, naming ``key``.
    """
    if value is None:
        return default
    text = value.strip()
    try:
        number = float(text)
    except ValueError:
        number = None
    if number is not None:
        return parse_quantity(number, dimension, key)
    match = _GLUED.match(text)  # allow "2in" without a space
    if match:
        text = f"{match.group(1)} {match.group(2)}"
    return parse_quantity(text, dimension, key)


def given_unit(value) -> str | None:
    """The unit written in ``value`` ("5in" -> "in", "50.8 mm" -> "mm"); None for a plain number (SI)."""
    if not isinstance(value, str):
        return None
    match = re.match(r"^\s*[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?\s*(.*?)\s*$", value)
    unit = match.group(1) if match else ""
    return unit or None


def outside_range(key: str, given, value: float, low: float, high: float, dimension: str) -> str:
    """One line: ``value`` [SI] is outside the model range [low, high] [SI], said in the user's unit.

    A value written with a unit ("5in") gets the range in that unit; a plain number (read as SI)
    gets the hint "were inches written as metres?" only for a length that would be in range in inches.
    """
    target, shown = DIMENSIONS[dimension]
    unit = given_unit(given)
    if unit is not None:
        try:
            factor = float(_registry().Quantity(1, unit).to(target or "dimensionless").magnitude)
        except Exception:  # a unit pint read as part of an expression: fall back to SI
            factor = 0.0
        if factor > 0:
            si = "" if abs(factor - 1) < 1e-12 else f" ({value:g} {shown})"
            return (
                f"{key} = {given!r}{si}: outside the model's range {low / factor:.3g} to "
                f"{high / factor:.3g} {unit}" + ("" if not si else f" ({low:g} to {high:g} {shown})")
            )
    text = f"{key} = {value:g} {shown}: outside the model's range {low:g} to {high:g} {shown}"
    if dimension == "length" and low <= value * INCH <= high:
        text += "; were inches written as metres? write e.g. '2 in'"
    return text


def _check_text(stripped: str, text: str, key: str, dimension: str) -> None:
    """Reject strings that are not "a number and a unit" before pint evaluates them.

    pint evaluates arithmetic, so ``"10**10**10 N"`` would compute a
    ten-billion-digit integer (it never returns) and ``"[1,2] N"`` reads as
    12 N; both are user mistakes, not quantities.
    """
    hint = f"give a number and a unit, e.g. {example(dimension)!r}"
    if len(stripped) > MAX_TEXT:
        raise InputError(f"{key} = {text[:20]!r}...: too long ({len(stripped)} characters); {hint}")
    if not _ALLOWED.match(stripped):
        bad = next(ch for ch in stripped if not _ALLOWED.match(ch))
        raise InputError(f"{key} = {text!r}: unexpected character {bad!r}; {hint}")
    if not any(ch.isdigit() for ch in stripped) and not stripped.lower().lstrip("+-").startswith(("nan", "inf")):
        raise InputError(f"{key} = {text!r}: a unit without a number; {hint}")
    for match in _EXPONENT.finditer(stripped):
        operand = match.group(3)
        rest = stripped[match.end() :].lstrip()
        if operand[0] in "(_" or operand[0].isalpha() or len(operand) > 3 or rest.startswith(("**", "^")):
            raise InputError(f"{key} = {text!r}: exponents must be small plain numbers such as m**2; {hint}")


def example(dimension: str) -> str:
    """A quantity of ``dimension`` as a user writes it (``"2 in"``, ``"178 N"``): the example of every message."""
    return {
        "length": "2 in",
        "force": "178 N",
        "speed": "2.5 m/s",
        "angle": "20 deg",
        "damping": "1.3 N*m/rad",
        "inertia": "0.00127 kg*m**2",
        "mass": "0.5 kg",
        "density": "1200 kg/m**3",
        "stiffness": "10000 N/m",
        "per_length": "7 1/m",
        "moment": "0.45 N*m",
        "time": "2 s",
        "angular_speed": "0.5 rad/s",
        "rate": "10 1/s",
        "dimensionless": "0.1",
    }[dimension]


def percent(probability: float) -> str:
    """A probability [-] as a percentage to 3 significant digits: ``5%``, ``2.5%``, ``97.5%``, ``0.1%`` (the risk
    bound α ranges from 0.001 to 0.5, so a whole-percent format would print α = 0.001 as "0%")."""
    return f"{100 * float(probability):.3g}%"


def limit_shown(value: float | None, unit: str, side: str, units: str = "mm") -> str:
    """A limit for an inspector: lengths in mm to 0.01 and in to 0.001 (the problem's ``units`` first, the other
    in brackets), N·m to 0.001, kg·m² to 3 significant digits, each rounded toward the safe side (a min up, a max
    down) so the printed limit is never outside the computed one; "none" when there is no limit."""
    if value is None:
        return "none"

    def step(x: float) -> int:  # rounding noise (63.499999 mm for 2.5 in) is not a step
        return (math.ceil if side == "min" else math.floor)(round(x, 6))

    if unit == "m":
        mm, inches = f"{step(value * 1e5) / 100:.2f} mm", f"{step(value / INCH * 1000) / 1000:.3f} in"
        return f"{inches} ({mm})" if units == "in" else f"{mm} ({inches})"
    if unit == "N·m":
        return f"{step(value * 1000) / 1000:.3f} N·m"
    digits = 2 - math.floor(math.log10(abs(value)))
    return f"{step(value * 10**digits) / 10**digits:.{max(digits, 0)}f} {unit}"
