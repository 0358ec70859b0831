"""Problem files: units at the edges, validation with one-line errors, shipped problems."""

from __future__ import annotations

import dataclasses
import math

import pytest

from designer.data.paper import INCH
from designer.errors import InputError, ProblemError
from designer.problem import load_problem, problem_from_dict, problem_from_toml
from designer.units import parse_quantity

from conftest import PROBLEMS


@pytest.mark.parametrize(
    "text, dimension, expected",
    [
        ("2 in", "length", 0.0508),
        ("50.8 mm", "length", 0.0508),
        ("20 deg", "angle", math.radians(20)),
        ("1.3 N*m/rad", "damping", 1.3),
        ("178 N", "force", 178.0),
        ("0.5625 in", "length", 0.0142875),
        ("40 lbf", "force", 177.929),
        ("2.5 m/s", "speed", 2.5),
        (0.05, "length", 0.05),
    ],
)
def test_parse_quantity(text, dimension, expected):
    """Numbers are SI; strings with units convert to SI."""
    assert parse_quantity(text, dimension, "k") == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize(
    "value, dimension, message",
    [
        ("2 kg", "length", "wrong dimension"),
        ("2 furlongz", "length", "unknown unit"),
        ("", "length", "empty"),
        (float("nan"), "length", "finite"),
        (float("inf"), "force", "finite"),
        (True, "length", "boolean"),
        ([1], "length", "expected a number"),
    ],
)
def test_parse_quantity_errors(value, dimension, message):
    """Bad quantities raise InputError naming the key and the reason."""
    with pytest.raises(InputError, match=message) as info:
        parse_quantity(value, dimension, "variables.trail.max")
    assert "variables.trail.max" in str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("path", PROBLEMS, ids=[p.stem for p in PROBLEMS])
def test_shipped_problems_load(path):
    """Every shipped problem loads, names itself after its file, has a positive target speed and a title,
    and opens with a comment of at least three lines saying whose chair it models (issue 3)."""
    problem = load_problem(path)
    assert problem.name == path.stem
    assert problem.required_speed > 0
    assert problem.title and problem.title != problem.name
    header = [line for line in path.read_text().splitlines()[:12] if line.startswith("#")]
    assert len(header) >= 3


def test_indoor_manual_values():
    """indoor-manual: inches converted to SI, 6 in swept radius, weights (1, 1)."""
    p = load_problem(PROBLEMS[[x.stem for x in PROBLEMS].index("indoor-manual")])
    assert p.bounds["trail"].high == pytest.approx(2.5 * INCH)
    assert p.bounds["diameter"].low == pytest.approx(3 * INCH)
    assert p.swept_radius_max == pytest.approx(6 * INCH)
    assert p.conditions.disturbance_angle == pytest.approx(math.radians(20))
    assert p.weights == (1.0, 1.0)


def _base(**sections):
    data = {"name": "t", "shimmy": {"target_speed": "2.5 m/s"}}
    for key, value in sections.items():
        data[key] = value
    return data


@pytest.mark.parametrize(
    "data, message",
    [
        (
            _base(variables={"trail": {"min": "-1 in", "max": "2 in"}}),
            "variables.trail.min = -0.0254: must be positive",
        ),
        (_base(variables={"trail": {"min": "3 in", "max": "2 in"}}), "min is greater than max"),
        (_base(variables={"diameter": {"min": "0.9 in", "max": "8 in"}}), "must exceed twice the threshold height"),
        (_base(variables={"diameter": {"min": "3 m", "max": "8 m"}}), "outside the model's range"),
        (_base(variables={"trail": {"min": "1 kg", "max": "2 in"}}), "wrong dimension"),
        (_base(variables={"trail": {"min": "1 in"}}), "variables.trail.max: missing"),
        (_base(variables={"damping": {"min": 1.0, "max": 3}}), "below the bare fork"),
        (_base(conditions={"surface": "grass"}), "conditions.surface = 'grass'"),
        (_base(conditions={"turning_mode": "spin"}), "conditions.turning_mode = 'spin'"),
        (_base(conditions={"lod": "178 N"}), "did you mean 'load'"),
        (_base(inertia={"model": "sphere"}), "inertia.model = 'sphere'"),
        (_base(inertia={"model": "catalog", "wheel": "Z"}), "unknown Table 1 wheel"),
        (_base(inertia={"model": "disc"}), "inertia.tyre_width: missing"),
        (_base(objective={"turning_effort": 0, "threshold_force": 0}), "not all zero"),
        (_base(objective={"turning_effort": -1}), "non-negative"),
        (_base(pareto={"points": 1}), "pareto.points"),
        (_base(constraints={"swept_radius_max": "1 in"}), "smaller than the smallest possible"),
        ({"name": "t"}, "shimmy.target_speed: missing"),
        ({"name": "../../x", "shimmy": {"target_speed": 2}}, "name = '../../x'"),
        (_base(shimmy={"target_speed": "nan m/s"}), "finite"),
        (_base(shimmy={"target_speed": -2}), "must be positive"),
        (_base(extra={"a": 1}), "unknown section or key 'extra'"),
    ],
)
def test_invalid_problems(data, message):
    """Each invalid problem is rejected before any solve with one line naming the key, value and reason."""
    with pytest.raises(ProblemError) as info:
        problem_from_dict(data)
    assert message in str(info.value)
    assert "\n" not in str(info.value)


def test_toml_syntax_error_has_line():
    """A TOML syntax error reports its line number."""
    with pytest.raises(ProblemError, match="line 2"):
        problem_from_toml('name = "x"\n[shimmy\n', source="bad.toml")


def test_fixed_variable_and_catalog_variants():
    """A single value fixes a variable; a catalog problem has one variant per wheel with d fixed."""
    p = problem_from_dict(_base(variables={"trail": "2 in"}, inertia={"model": "catalog", "wheels": ["A", "D"]}))
    assert p.bounds["trail"].fixed and p.bounds["trail"].low == pytest.approx(0.0508)
    variants = p.variants()
    assert [v.conditions.inertia.wheel.key for v in variants] == ["A", "D"]
    assert variants[1].bounds["diameter"].low == variants[1].bounds["diameter"].high == pytest.approx(0.2032)


def test_problem_is_immutable_and_replace_validates():
    """Problems are frozen; replace() re-validates (a negative target speed is rejected)."""
    p = problem_from_dict(_base())
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.target_speed = 3.0
    with pytest.raises(ProblemError, match="target_speed"):
        p.replace(target_speed=-1.0)


def test_utf8_byte_order_mark_is_accepted(tmp_path):
    """Issue 24.6: a problem file saved with a UTF-8 byte-order mark (as Windows editors do) gave "TOML syntax
    error: Invalid statement (at line 1, column 1)"; it loads as the same file without the mark."""
    source = next(p for p in PROBLEMS if p.name == "indoor-manual.toml")
    marked = tmp_path / "indoor-manual.toml"
    marked.write_bytes(b"\xef\xbb\xbf" + source.read_bytes())
    assert load_problem(marked).to_dict() == load_problem(source).to_dict()


@pytest.mark.parametrize("encoding, name", [("utf-16", "UTF-16"), ("utf-32", "UTF-32")])
def test_wide_unicode_file_is_named(tmp_path, encoding, name):
    """Issue 24.6: a problem file saved as UTF-16 or UTF-32 ("Unicode" in Windows editors) starts with that
    encoding's byte-order mark; the error names the encoding and says to save it as UTF-8 (it was a
    UnicodeDecodeError about byte 0xff)."""
    from designer.errors import ProblemError

    source = next(p for p in PROBLEMS if p.name == "indoor-manual.toml")
    wide = tmp_path / "wide.toml"
    wide.write_text(source.read_text(encoding="utf-8"), encoding=encoding)
    with pytest.raises(ProblemError, match=f"{name} text .* save the problem file as UTF-8"):
        load_problem(wide)


def test_mass_and_front_fraction_give_the_load_per_caster(tmp_path):
    """Issue 28.3: ``[conditions] mass = "110 kg"`` and ``front_fraction = 0.4`` give L = m g f / 2 =
    110 × 9.80665 × 0.4 / 2 = 215.7463 N per front caster (hand calculation), the same value the fleet table
    gives for the same mass and fraction (one conversion, designer.model.caster_load); a percentage is read
    as a fraction."""
    from designer.studies.fleet import read_fleet

    problem = problem_from_toml(
        '[conditions]\nmass = "110 kg"\nfront_fraction = 0.4\n[shimmy]\ntarget_speed = "2.5 m/s"\n'
    )
    assert problem.conditions.load == pytest.approx(215.7463, abs=1e-9)
    percent = problem_from_toml('[conditions]\nmass = 110\nfront_fraction = "40 %"\n[shimmy]\ntarget_speed = 2.5\n')
    assert percent.conditions.load == pytest.approx(215.7463, abs=1e-9)
    csv = tmp_path / "fleet.csv"
    csv.write_text(
        "name,mass_kg,front_fraction,threshold_height_in,target_speed,swept_radius_max_in,surface,turning_mode\n"
        "a,110,0.4,0.5,2.5,6,tile,chair\n"
    )
    fleet = read_fleet(csv)
    assert fleet.load[0] == problem.conditions.load


@pytest.mark.parametrize(
    "conditions, message",
    [
        ('load = "200 N"\nmass = "110 kg"\nfront_fraction = 0.4', "conditions.load and conditions.mass: give load, or"),
        ('mass = "110 kg"', "conditions.front_fraction: missing; conditions.mass needs it"),
        ("front_fraction = 0.4", "conditions.mass: missing; conditions.front_fraction needs it"),
        ('mass = "110 lbf"\nfront_fraction = 0.4', "conditions.mass = '110 lbf': wrong dimension"),
        ('mass = "3 t"\nfront_fraction = 0.4', "conditions.mass = '3 t': must be 1 to 2000 kg"),
        ('mass = "110 kg"\nfront_fraction = 0', "conditions.front_fraction = 0: must be above 0 and at most 1"),
    ],
)
def test_mass_and_load_are_alternatives(conditions, message):
    """Issue 28.3: load, or mass with front_fraction: giving both, or one of the pair, or a value out of range, is
    one line naming the keys."""
    with pytest.raises(ProblemError) as info:
        problem_from_toml(f"[conditions]\n{conditions}\n[shimmy]\ntarget_speed = 2.5\n", source="p.toml")
    text = str(info.value)
    assert "\n" not in text and text.startswith("p.toml: ") and message in text
