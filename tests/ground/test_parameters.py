"""The one parameter table (designer/parameters.py) and the places that read it."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from designer import parameters
from designer.model import MODEL_RANGE, VARIABLES, performance
from designer.physics.inertia import Catalog, Disc, Fixed, PowerLaw
from designer.problem import DEFAULT_BOUNDS, PHYSICAL_RANGE, SCHEMA, problem_from_dict

ROOT = Path(__file__).resolve().parents[2]
BASE = {"shimmy": {"target_speed": "2.5 m/s"}}


def test_docs_table_is_generated_from_the_table():
    """docs/parameters.md is exactly what ``python -m designer.parameters`` prints (regenerate it if this fails)."""
    text = (ROOT / "docs" / "parameters.md").read_text(encoding="utf-8")
    assert text == (
        parameters.DOC_HEADER
        + parameters.markdown_table()
        + parameters.OUTPUTS_HEADER
        + parameters.outputs_markdown_table()
    )


def test_every_entry_is_complete():
    """Each entry has a symbol, a description and a source; a range, where given, is ordered and holds the default."""
    for p in parameters.PARAMETERS.values():
        assert p.symbol and p.description and p.source, p.name
        if p.range is not None:
            assert p.range[0] < p.range[1], p.name
            if p.default is not None:
                assert p.range[0] <= p.default <= p.range[1], p.name


def test_loader_and_model_read_the_table():
    """Variable order, model ranges, default bounds, schema keys and checked ranges come from the table."""
    assert VARIABLES == ("trail", "diameter", "groove", "damping")
    assert MODEL_RANGE["diameter"] == parameters.PARAMETERS["diameter"].range == (0.01, 0.6)
    assert DEFAULT_BOUNDS["damping"] == (1.3, 6.0)
    for p in parameters.PARAMETERS.values():
        if p.key:
            section, key = p.key.split(".", 1)
            assert key in SCHEMA[section], p.key
    assert PHYSICAL_RANGE["shimmy.slip_coefficient"] == (1.0, 1e6, "N", "the paper's tyres have 1250 N")


@pytest.mark.parametrize(
    "key",
    sorted(p.key for p in parameters.CONSTANT_TABLE if p.key and p.default is not None and p.key != "inertia.inertia"),
)
def test_every_constant_key_loads_with_its_default(key):
    """Writing a constant's default value in a problem file (in its SI unit) gives a valid problem, equal to the
    problem that leaves the key out (so the table's default is the loader's default)."""
    p = next(q for q in parameters.CONSTANT_TABLE if q.key == key)
    section, name = key.split(".", 1)
    data = {"shimmy": {"target_speed": "2.5 m/s"}}
    data.setdefault(section, {})[name] = f"{p.default!r} {p.unit}" if p.unit else p.default
    if section == "inertia" and name in ("tyre_width", "density"):
        data["inertia"].update(model="disc", tyre_width=0.025, density=1200.0)
    without = {s: {k: v for k, v in table.items() if k != name or s != section} for s, table in data.items()}
    if section == "inertia" and name in ("tyre_width", "density"):
        without["inertia"].update({name: {"tyre_width": 0.025, "density": 1200.0}[name]})
    assert problem_from_dict(data) == problem_from_dict(without)


def test_solver_parameters_of_a_default_problem():
    """The NLP/GP parameter vector: names in table order, values from the problem; carpet only on carpet."""
    problem = problem_from_dict(BASE)
    values = parameters.solver_values(problem)
    assert list(values) == [
        "load",
        "threshold_height",
        "target_speed",
        "slip_coefficient",
        "disturbance_angle",
        "tile_moment_per_load",
        "groove_coefficient",
        "bare_fork_damping",
        "mode_factor",
        "inertia_coefficient",
        "inertia_exponent",
    ]
    assert values["target_speed"] == 2.5 and values["mode_factor"] == 0.5
    carpet = problem_from_dict(
        {**BASE, "conditions": {"surface": "carpet"}, "constraints": {"swept_radius_max": "3.5 in"}}
    )
    assert {"carpet_factor", "swept_radius_max"} <= set(parameters.solver_values(carpet))


@pytest.mark.parametrize("inertia", [PowerLaw(), Disc(), Catalog.from_key("C"), Fixed(0.00127)])
def test_putting_the_values_back_changes_nothing(inertia):
    """Conditions rebuilt from the solver values give the same performance (to round-off) as the originals."""
    problem = problem_from_dict(BASE)
    problem = dataclasses.replace(problem, conditions=problem.conditions.replace(inertia=inertia))
    rebuilt = parameters.with_solver_values(problem, parameters.solver_values(problem))
    x = (0.05, 0.17, 0.004, 2.0)
    a, b = performance(*x, problem.conditions), performance(*x, rebuilt)
    for key in a:
        assert math.isclose(a[key], b[key], rel_tol=1e-14), key


def test_a_changed_value_reaches_the_conditions():
    """A perturbed parameter (as the sensitivities use) lands where the physics reads it."""
    problem = problem_from_dict(BASE)
    values = parameters.solver_values(problem)
    changed = parameters.with_solver_values(problem, {**values, "mode_factor": 0.7, "slip_coefficient": 1500.0})
    assert changed.turning.mode_factors == {"chair": 0.7, "pivot": 1.0}
    assert changed.slip_coefficient == 1500.0
    assert problem.conditions.turning.mode_factors["chair"] == 0.5  # the original is not touched


NEW_CONSTANT = """    Parameter("floor_slope", "α", "rad", "floor cross-slope", 0.0, (0.0, 0.2), "an example entry",
              key="conditions.floor_slope", dimension="angle", hint="a cross-slope of 0 to 11 deg",
              path='conditions.constants["floor_slope"]'),
"""

NEW_CONSTANT_RUN = r"""
import json, sys
from designer import parameters
from designer.errors import ProblemError
from designer.problem import problem_from_toml
from designer.studies.optimum._optimise import optimise
base = open(sys.argv[1]).read()
out = {}
problem = problem_from_toml(base.replace("[conditions]", '[conditions]\nfloor_slope = "2 deg"'))
out["value"] = problem.conditions.constant("floor_slope")
out["default"] = problem_from_toml(base).conditions.constant("floor_slope")
out["solver"] = parameters.solver_values(problem).get("floor_slope")
out["docs"] = [line for line in parameters.markdown_table().splitlines() if "floor_slope" in line]
out["sensitivity"] = optimise(problem.nominal(), cross_check=False).sensitivities.get("floor_slope")
try:
    problem_from_toml(base.replace("[conditions]", '[conditions]\nfloor_slope = "20 deg"'))
except ProblemError as exc:
    out["error"] = str(exc)
try:
    problem_from_toml(base.replace("[conditions]", '[conditions]\nfloor_slope = "2 N"'))
except Exception as exc:
    out["unit_error"] = str(exc)
print(json.dumps(out))
"""


def test_a_new_constant_is_one_table_entry(tmp_path):
    """Adding a model constant touches one place (issue 13): in a copy of the package whose only change is one
    Parameter line in CONSTANT_TABLE, a problem file's key is read with its units ("2 deg" -> 0.0349 rad) or
    takes its default, is range-checked with the entry's hint, is kept on the conditions
    (``conditions.constant``), has a docs-table row, and becomes a solver parameter with a sensitivity (0 here:
    no equation reads it yet; using it in an equation is the other half of adding a constant)."""
    import json
    import shutil
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[2]
    shutil.copytree(root / "designer", tmp_path / "designer", ignore=shutil.ignore_patterns("__pycache__"))
    source = tmp_path / "designer" / "parameters.py"
    text = source.read_text(encoding="utf-8")
    anchor = ')\n# fmt: on\n"""The model constants'
    assert text.count(anchor) == 1
    source.write_text(text.replace(anchor, NEW_CONSTANT + anchor), encoding="utf-8")
    run = subprocess.run(
        [sys.executable, "-c", NEW_CONSTANT_RUN, str(root / "problems" / "indoor-manual.toml")],
        cwd=tmp_path,
        env={**__import__("os").environ, "PYTHONPATH": str(tmp_path)},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["value"] == pytest.approx(math.radians(2), rel=1e-15)
    assert out["default"] == 0.0
    assert out["solver"] == pytest.approx(math.radians(2), rel=1e-15)
    assert len(out["docs"]) == 1 and "`conditions.floor_slope`" in out["docs"][0] and "| rad |" in out["docs"][0]
    assert out["sensitivity"] is not None and abs(out["sensitivity"]) < 1e-9
    assert "conditions.floor_slope = 0.349066 rad: outside the model's range 0 to 0.2 rad" in out["error"]
    assert "(a cross-slope of 0 to 11 deg)" in out["error"]
    assert "conditions.floor_slope = '2 N': wrong dimension, expected angle" in out["unit_error"]


def test_the_table_names_units_columns_and_scales_of_the_variables():
    """Each design variable's DataFrame column, JSON unit, index and NLP scale come from its table entry, and
    ``named`` reads a design vector (or an array of designs) by those names."""
    import numpy as np

    p = parameters
    assert [e.column for e in p.VARIABLE_TABLE] == ["trail_m", "diameter_m", "groove_m", "damping_N_m_per_rad"]
    assert [e.ascii_unit for e in p.VARIABLE_TABLE] == ["m", "m", "m", "N*m/rad"]
    assert p.PARAMETERS["wheel_inertia"].ascii_unit == "kg*m**2"
    assert p.SCALES == tuple(e.scale for e in p.VARIABLE_TABLE) and all(s > 0 for s in p.SCALES)
    assert [p.VARIABLE_INDEX[name] for name in p.VARIABLES] == [0, 1, 2, 3]
    x = np.array([0.05, 0.2, 0.01, 1.3])
    assert p.named(x)["groove"] == 0.01
    np.testing.assert_array_equal(p.named(np.vstack([x, 2 * x]))["damping"], [1.3, 2.6])


def _unit_mismatches(table) -> list[tuple[str, str, str]]:
    from designer.units import DIMENSIONS

    return [(p.name, p.unit, p.dimension) for p in table if p.unit and DIMENSIONS[p.dimension][1] != p.unit]


def test_every_quantity_prints_the_unit_of_its_dimension():
    """Each entry of the parameter tables (inputs and the quantities of an evaluated caster) prints the unit of
    its declared dimension, so its JSON unit (ascii_unit) and its CSV column name agree with what it shows; a
    quantity in rad/s declared dimensionless (as ω was) is caught."""
    from designer.parameters import OUTPUT_TABLE, PARAMETERS, Parameter

    assert _unit_mismatches(list(PARAMETERS.values()) + list(OUTPUT_TABLE)) == []
    planted = Parameter("omega", "ω", "rad/s", "shimmy frequency", None, None, "Eq. 15B")
    assert _unit_mismatches([planted]) == [("omega", "rad/s", "dimensionless")]


def test_csv_columns_take_their_dimensions_from_the_table():
    """parameters.dimensions gives the table's dimension of each quantity with a unit (a variable, a constant, an
    output, a part number's sku_ value as its quantity) and leaves out flags, fractions and names it does not
    know, so a CSV column names its unit from the one table; units_of gives the SI units the same way."""
    names = ["trail", "damping", "load", "critical_speed", "sku_turning_effort", "shimmy_probability", "status"]
    assert parameters.dimensions(names) == {
        "trail": "length",
        "damping": "damping",
        "load": "force",
        "critical_speed": "speed",
        "sku_turning_effort": "force",
    }
    assert parameters.units_of(names) == {
        "trail": "m",
        "damping": "N·m/rad",
        "load": "N",
        "critical_speed": "m/s",
        "sku_turning_effort": "N",
    }
    # a prefix names another caster's value, not a new word: "skull" is not sku_ + "ll"
    assert parameters.dimensions(["skull", "sku_status"]) == {}
