"""designer.display: the one formatter of every surface (label, unit and precision from the parameter table)."""

import math

import numpy as np
import pytest

import designer.display as display
from designer.units import INCH


def test_every_quantity_of_the_table_can_be_shown_in_every_unit_system():
    """A quantity whose dimension has no display entry would fail here (a new dimension needs one)."""
    display.check_units()


@pytest.mark.parametrize(
    ("units", "expected"),
    [("in", "2.500 in"), ("mm", "63.50 mm"), ("si", "0.0635 m")],
)
def test_a_length_is_shown_in_the_problems_unit_system(units, expected):
    """A 2.5 in trail reads in inches, millimetres or metres, never in another system than the one asked."""
    assert display.shown(2.5 * INCH, "trail", units) == expected


def test_precision_comes_from_the_tables_entry():
    """The load's entry asks 0.1 N, the turning effort's 1 mN; a speed without an entry of its own takes the
    dimension's 1 mm/s."""
    assert display.shown(178.04, "load") == "178.0 N"
    assert display.shown(8.31649, "turning_effort") == "8.316 N"
    assert display.shown(2.70512, "critical_speed", "mm") == "2.705 m/s"


def test_a_probability_is_a_percentage_to_three_significant_digits():
    """0.02977 -> "2.98 %"; 0.001 (the least risk bound) stays "0.1 %", not "0 %"."""
    assert display.shown(0.02977, "shimmy_probability") == "2.98 %"
    assert display.percent(0.001) == "0.1 %"


@pytest.mark.parametrize(
    "p, text", [(0.9974, "99.7 %"), (0.9999, "99.99 %"), (0.99996, "99.996 %"), (1.0, "100 %"), (0.99949, "99.9 %")]
)
def test_a_probability_below_one_never_reads_certain(p, text):
    """Three significant digits round 0.9999 to "100 %", which reads as certain shimmy: a probability below 1
    gets the decimals that tell it from 1 (the fix screen's "99.7 % -> 99.99 %"); exactly 1 is "100 %"."""
    assert display.percent(p) == text


def test_a_standard_error_has_two_significant_digits():
    """percent(..., digits=2) for a Monte Carlo standard error: 0.000751 -> "0.075 %"."""
    assert display.percent(0.000751, digits=2) == "0.075 %"


@pytest.mark.parametrize("value", [None, math.nan, math.inf, -math.inf, np.float64("nan")])
def test_a_missing_value_has_one_mark(value):
    """None, NaN and infinities print the one mark, never "nan" or "–"."""
    assert display.shown(value, "critical_speed") == display.MISSING == "n/a"


def test_headers_and_labels_come_from_the_table():
    """A column's heading is the symbol with the system's unit; a row's label is the description and symbol."""
    assert display.header("trail", "mm") == "T [mm]"
    assert display.header("turning_effort", "in") == "F_turn [N]"
    assert display.label("critical_speed") == "critical shimmy speed V_c"
    assert display.axis("threshold_force") == "sill force P [N]"


def test_an_unknown_quantity_or_unit_system_is_refused_with_its_name():
    """A typo in a quantity's name or a unit system is an error naming it, not a silent SI number."""
    with pytest.raises(KeyError, match="'trial'"):
        display.shown(0.05, "trial")
    with pytest.raises(ValueError, match="'cm'"):
        display.shown(0.05, "trail", "cm")
