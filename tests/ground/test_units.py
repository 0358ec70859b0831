"""Issue 12.3: units that pint converts but that mean another quantity, and range messages in the user's unit."""

from __future__ import annotations

import pytest

from designer.cli import main
from designer.errors import InputError, ProblemError
from designer.problem import problem_from_toml
from designer.units import COMMON_UNITS, DIMENSIONS, _registry, parse_quantity

EVAL = ["evaluate", "--trail", "2in", "--diameter", "8in", "--groove", "0", "--damping", "1.3"]


@pytest.mark.parametrize("text", ["1.3 N*m", "1.3 J", "1.3 N m", "1.3 lbf*ft"])
def test_moment_is_not_a_damping(text):
    """A moment (no angle in the denominator) is refused for a damping; pint alone reads N·m as N·m/rad."""
    with pytest.raises(InputError, match="a moment \\(or energy\\), not a damping; .* e.g. '1.3 N\\*m/rad'"):
        parse_quantity(text, "damping", "--damping")


@pytest.mark.parametrize("text, si", [("1.3 N*m/rad", 1.3), ("1.3 N*m/deg", 1.3 * 180 / 3.141592653589793), (1.3, 1.3)])
def test_damping_per_angle_accepted(text, si):
    """Per radian, per degree, or a plain number (SI, N·m/rad) are dampings."""
    assert parse_quantity(text, "damping", "--damping") == pytest.approx(si)


def test_cli_damping_moment_rejected(capsys):
    """`evaluate --damping "1.3 N*m"` is an input error naming the option and saying to use N*m/rad."""
    assert main(EVAL[:-1] + ["1.3 N*m"]) == 2
    assert "--damping = '1.3 N*m': a moment (or energy), not a damping" in capsys.readouterr().err


@pytest.mark.parametrize("text, hint", [("40 lb", "'40 lbf'"), ("40 lbs", "'40 lbf'"), ("18 kg", "kgf")])
def test_mass_for_force_hints_lbf(text, hint):
    """'40 lb' is a mass: the error says to write lbf (pound-force), not only 'wrong dimension'."""
    with pytest.raises(InputError) as info:
        parse_quantity(text, "force", "conditions.load")
    assert "wrong dimension" in str(info.value) and hint in str(info.value)


def test_groove_in_inches_out_of_range_said_in_inches(capsys):
    """--groove 5in is outside the model range, said in inches; no 'were inches written as metres?'."""
    assert main(EVAL[:5] + ["--groove", "5in", "--damping", "1.3"]) == 2
    err = capsys.readouterr().err
    assert "--groove = '5in' (0.127 m): outside the model's range 0 to 3.94 in" in err
    assert "were inches written as metres" not in err


def test_groove_plain_number_still_hints_inches(capsys):
    """A plain 0.5 (read as metres) for a groove keeps the hint: 0.5 in would be in range."""
    assert main(EVAL[:5] + ["--groove", "0.5", "--damping", "1.3"]) == 2
    assert "were inches written as metres?" in capsys.readouterr().err


def test_problem_file_bound_in_inches_said_in_inches():
    """In a problem file, groove max '5 in' gets the range in inches, not the metres hint."""
    text = 'name = "x"\n[shimmy]\ntarget_speed = "2 m/s"\n[variables]\ngroove = { min = "0 in", max = "5 in" }\n'
    with pytest.raises(ProblemError) as info:
        problem_from_toml(text)
    assert "variables.groove.max = '5 in' (0.127 m): outside the model's range 0 to 3.94 in" in str(info.value)
    assert "were inches" not in str(info.value)


@pytest.fixture(scope="module")
def ureg():
    """A pint UnitRegistry of its own (not the package's cached one), built once: building one takes seconds."""
    return pytest.importorskip("pint").UnitRegistry()


@pytest.mark.parametrize("unit", sorted(COMMON_UNITS))
def test_common_unit_factor_equals_pints(unit, ureg):
    """Each unit read without pint (COMMON_UNITS, the cold-start shortcut) converts exactly as pint does:
    2.5, 0.75, 178 and 1e-3 of it agree with pint's conversion to the SI unit to 2 ulp."""
    dimension, _ = COMMON_UNITS[unit]
    target = DIMENSIONS[dimension][0]
    for x in (2.5, 0.75, 178.0, 1e-3):
        expected = ureg.Quantity(x, unit).to(target).magnitude
        assert parse_quantity(f"{x!r} {unit}", dimension, "k") == pytest.approx(expected, rel=5e-16, abs=0)


def test_common_units_skip_pint_and_others_use_it():
    """ "2.5 in" for a length is read by the shortcut (pint's registry is never built); "2.5 in" for a
    force, "1 ft + 2 in" and "N*m" for a damping go through pint, with its checks and messages."""
    _registry.cache_clear()
    assert parse_quantity("2.5 in", "length", "k") == pytest.approx(0.0635, rel=1e-15)
    assert parse_quantity("20 deg", "angle", "k") == pytest.approx(0.3490658503988659, rel=1e-15)
    assert _registry.cache_info().currsize == 0
    with pytest.raises(InputError, match="wrong dimension, expected force"):
        parse_quantity("2.5 in", "force", "k")
    assert _registry.cache_info().currsize == 1
    assert parse_quantity("1 ft + 2 in", "length", "k") == pytest.approx(14 * 0.0254, rel=1e-12)
    with pytest.raises(InputError, match="not a damping"):
        parse_quantity("1.3 N*m", "damping", "k")
    with pytest.raises(InputError, match="too long"):
        parse_quantity("1" * 120 + " in", "length", "k")


def test_the_inch_is_defined_once():
    """0.0254 is written once in the package, in designer/units.py, and the paper's INCH is that object."""
    from pathlib import Path

    import designer.data.paper as paper
    import designer.units as units

    package = Path(units.__file__).resolve().parent
    hits = [
        f"{path.relative_to(package)}:{n}"
        for path in sorted(package.rglob("*.py"))
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if "0.0254" in line
    ]
    assert len(hits) == 1 and hits[0].startswith("units.py:"), hits
    assert paper.INCH is units.INCH and units.INCH == 0.0254


@pytest.mark.parametrize(
    "text, inches",
    [("2 1/2 in", 2.5), ("1 1/4in", 1.25), ("7 3/4 in", 7.75), ("-1 1/2 in", -1.5), ("3/4 in", 0.75), ("2 in", 2.0)],
)
def test_mixed_numbers_read_as_the_tool_writes_them(text, inches):
    """A size as the tool prints it ("2 1/2 in": fleet part numbers, fix tables, the first screen) reads back as
    2.5 in; pint alone reads "2 1/2" as 2 × 1/2 = 1 in, and a copied size silently lost 1.5 in."""
    assert parse_quantity(text, "length", "trail") == pytest.approx(inches * 0.0254, rel=1e-12)


def test_a_copied_size_makes_the_same_design():
    """designer.Design("2 1/2 in", "7 in", "3/4 in", 1.3) is the recommendation's caster (T = 63.5 mm)."""
    from designer import Design

    assert Design("2 1/2 in", "7 in", "3/4 in", 1.3).trail == pytest.approx(0.0635, rel=1e-12)


def test_a_probability_is_shown_to_three_digits():
    """designer.units.percent shows α and 1 − α as the problem file allows them (0.001 to 0.5): 0.001 is 0.1%,
    not the 0% a whole-percent format printed; whole percentages read as before (5%, 95%)."""
    from designer.units import percent

    assert [percent(x) for x in (0.001, 0.025, 0.05, 1 - 0.05, 0.975, 0.5)] == [
        "0.1%",
        "2.5%",
        "5%",
        "95%",
        "97.5%",
        "50%",
    ]


def test_limit_shown_leads_with_the_problems_unit():
    """A length limit is shown in the problem's unit first and the other in brackets, each rounded toward the safe
    side: 2.5 in as a max is 2.500 in (63.50 mm) for an inch problem, 63.50 mm (2.500 in) for a mm problem."""
    from designer.units import INCH, limit_shown

    assert limit_shown(2.5 * INCH, "m", "max", "in") == "2.500 in (63.50 mm)"
    assert limit_shown(2.5 * INCH, "m", "max", "mm") == "63.50 mm (2.500 in)"
    assert limit_shown(0.0497, "m", "min", "in") == "1.957 in (49.70 mm)"
    assert limit_shown(0.45, "N·m", "min", "in") == "0.450 N·m"
