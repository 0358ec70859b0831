"""The one way a number reaches a person: its label, symbol, unit and precision from the parameter table, in the
problem's unit system.

Every surface (the CLI's tables and sentences, the report, the inspection sheet, the studio, the notebook reprs)
formats a quantity through :func:`shown` (value and unit), :func:`number` (the value alone), :func:`header`
(a column's "T [mm]") and :func:`label` (a row's "turning effort F_turn"); it never types a label, a unit or a
precision of its own.  The quantity is named by the table (:data:`designer.parameters.PARAMETERS`,
:data:`designer.parameters.OUTPUTS`); a name outside the table can still be shown by its ``dimension``.

Unit systems (a problem's ``units``): ``"in"`` (lengths in inches, the paper's), ``"mm"`` (lengths in
millimetres) and ``"si"`` (metres).  Every other dimension is shown in its SI unit in every system (forces in N,
speeds in m/s): the paper's and the clinic's; angles alone in degrees, the unit a fork's tilt, a disturbance and
a shimmy amplitude are measured in.  Display only: nothing here enters a computation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from designer.parameters import OUTPUTS, PARAMETERS, Parameter
from designer.units import DIMENSIONS, INCH, MISSING  # MISSING: the one mark of a value that does not exist

SYSTEMS = ("in", "mm", "si")
"""The unit systems a problem can be shown in (``Problem.units``; ``"si"`` for the library's own records)."""


@dataclass(frozen=True)
class Unit:
    """How one dimension is shown in one unit system: the unit's text, the factor from SI, and the decimals
    (``digits`` > 0 fixed decimals; ``significant`` True: that many significant digits instead)."""

    text: str
    factor: float
    digits: int
    significant: bool = False


_SI = {
    "length": Unit("m", 1.0, 4, significant=True),
    "force": Unit("N", 1.0, 2),
    "speed": Unit("m/s", 1.0, 3),
    "angle": Unit("deg", 180.0 / math.pi, 2),
    "damping": Unit("N·m/rad", 1.0, 2),
    "inertia": Unit("kg·m²", 1.0, 3, significant=True),
    "mass": Unit("kg", 1.0, 3, significant=True),
    "density": Unit("kg/m³", 1.0, 4, significant=True),
    "stiffness": Unit("N/m", 1.0, 4, significant=True),
    "per_length": Unit("1/m", 1.0, 3, significant=True),
    "moment": Unit("N·m", 1.0, 3),
    "angular_speed": Unit("rad/s", 1.0, 1),
    "rate": Unit("1/s", 1.0, 3, significant=True),
    "frequency": Unit("Hz", 1.0, 2),
    "time": Unit("s", 1.0, 3, significant=True),
    "probability": Unit("%", 100.0, 3, significant=True),
    "dimensionless": Unit("", 1.0, 4, significant=True),
}
"""Each dimension in SI, with its display precision (the default of a quantity whose entry sets none)."""

_LENGTHS = {"in": Unit("in", 1 / INCH, 3), "mm": Unit("mm", 1000.0, 2), "si": _SI["length"]}
"""A length in each system: inches to 0.001 in, millimetres to 0.01 mm (a fork hole's and a groove's scale)."""


def system_of(units: str | None) -> str:
    """The unit system of a problem's ``units`` ("in", "mm"; None or "si": SI), refusing anything else."""
    if units is None:
        return "si"
    if units not in SYSTEMS:
        raise ValueError(f"units = {units!r}: expected one of {', '.join(repr(s) for s in SYSTEMS)}")
    return units


def quantity(name: str) -> Parameter:
    """The parameter table's entry of ``name`` (a design variable, a constant, or an output of an evaluated
    caster); KeyError naming it when the table has none."""
    entry = PARAMETERS.get(name) or OUTPUTS.get(name)
    if entry is None:
        raise KeyError(f"{name!r} is not a quantity of designer.parameters (PARAMETERS or OUTPUTS)")
    return entry


def unit(dimension: str, units: str | None = "si") -> Unit:
    """How ``dimension`` is shown in the unit system ``units`` (see :data:`SYSTEMS`)."""
    system = system_of(units)
    if dimension == "length":
        return _LENGTHS[system]
    if dimension not in _SI:
        raise KeyError(f"dimension {dimension!r}: expected one of {', '.join(sorted(_SI))}")
    return _SI[dimension]


def _unit_of(name: str | None, dimension: str | None, units: str | None) -> Unit:
    entry = quantity(name) if name is not None else None
    dim = dimension or (entry.dimension if entry is not None else "dimensionless")
    shown_unit = unit(dim, units)
    if entry is not None and entry.digits is not None and dim != "length":
        shown_unit = Unit(shown_unit.text, shown_unit.factor, entry.digits, shown_unit.significant)
    return shown_unit


def _missing(value) -> bool:
    if value is None:
        return True
    try:
        return not math.isfinite(float(value))
    except (TypeError, ValueError):
        return True


def number(
    value, name: str | None = None, units: str | None = "si", *, dimension: str | None = None, digits=None
) -> str:
    """``value`` [SI] as a number in the unit system ``units``, without its unit ("63.50" for a 2.5 in trail in
    mm); :data:`MISSING` for None, NaN or an infinity.  Precision from the table's entry of ``name`` (or the
    dimension's default); ``digits`` overrides it where a surface needs a coarser number (a chart's tick)."""
    if _missing(value):
        return MISSING
    shown_unit = _unit_of(name, dimension, units)
    places = shown_unit.digits if digits is None else digits
    x = float(value) * shown_unit.factor
    if shown_unit.significant:
        return f"{x:.{places}g}"
    return f"{x:.{places}f}"


def shown(
    value, name: str | None = None, units: str | None = "si", *, dimension: str | None = None, digits=None
) -> str:
    """``value`` [SI] with its unit in the unit system ``units``: "63.50 mm", "2.500 in", "2.705 m/s", "2.98 %"
    (a number and its unit joined by one space, a percentage too); :data:`MISSING` alone for no value."""
    text = number(value, name, units, dimension=dimension, digits=digits)
    suffix = unit_text(name, units, dimension=dimension)
    return f"{text} {suffix}" if suffix and text != MISSING else text


def unit_text(name: str | None = None, units: str | None = "si", *, dimension: str | None = None) -> str:
    """The unit ``name`` is shown in, in the unit system ``units`` ("mm", "in", "N", "%"; "" for a plain
    number)."""
    return _unit_of(name, dimension, units).text


def label(name: str) -> str:
    """A quantity's name for a person, with its symbol: "turning effort F_turn", "trail T" (the table's
    description and symbol; the one name of each quantity on every surface)."""
    return quantity(name).label


def header(name: str, units: str | None = "si") -> str:
    """A column's heading: the symbol with the unit of the system in brackets ("T [mm]", "F_turn [N]"; the
    symbol alone for a plain number, the description for a quantity with no symbol)."""
    entry = quantity(name)
    text = unit_text(name, units)
    head = entry.symbol or entry.description
    return f"{head} [{text}]" if text else head


def axis(name: str, units: str | None = "si") -> str:
    """A chart axis: the label with the unit in brackets ("turning effort F_turn [N]")."""
    text = unit_text(name, units)
    return f"{label(name)} [{text}]" if text else label(name)


def percent(probability, digits: int | None = None) -> str:
    """A probability [-] as a percentage to 3 significant digits ("2.98 %", "0.1 %", "97.5 %"; ``digits``
    significant digits instead: 2 for a standard error, "0.075 %"); the risk bound α ranges from 0.001 to 0.5, so
    a whole-percent format would print 0.1 % as 0 %.  A probability below 1 never reads "100 %": it gets the
    decimals that tell it from certainty ("99.99 %")."""
    text = shown(probability, dimension="probability", digits=digits)
    places = 0
    while text.startswith("100") and not _missing(probability) and float(probability) < 1 and places < 12:
        places += 1
        text = f"{100 * float(probability):.{places}f} %"
    return text


def rescale(from_units: str, to_units: str, dimension: str = "length"):
    """The function taking numbers shown in ``from_units`` to ``to_units`` (arrays too): a chart's second axis
    (millimetres on the axis, inches on its twin: ``rescale("mm", "in")`` and back ``rescale("in", "mm")``)."""
    k = unit(dimension, to_units).factor / unit(dimension, from_units).factor

    def convert(values):
        return np.asarray(values, float) * k

    return convert


def check_units() -> None:
    """Every quantity of the table with a unit can be shown in every system (a new dimension without a display
    entry fails here, and ``tests/test_display.py`` calls this)."""
    for entry in (*PARAMETERS.values(), *OUTPUTS.values()):
        if entry.unit:
            for system in SYSTEMS:
                unit(entry.dimension, system)
    assert set(DIMENSIONS) <= set(_SI), sorted(set(DIMENSIONS) - set(_SI))
