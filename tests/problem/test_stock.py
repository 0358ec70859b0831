"""[stock] and [robust] parsing: parts that exist, the default risk bound, and every bad input as one line, exit 3."""

from __future__ import annotations

import numpy as np
import pytest

from designer.cli import main
from designer.data.paper import INCH
from designer.physics.uncertainty import Uncertainty
from designer.problem import problem_from_dict, problem_from_toml

BASE = """
name = "s"
[shimmy]
target_speed = "2.5 m/s"
[variables]
trail = { min = "1 in", max = "2.5 in" }
diameter = { min = "3 in", max = "8 in" }
groove = { min = "0 in", max = "0.75 in" }
damping = { min = "1.3 N*m/rad", max = "6 N*m/rad" }
"""


def test_default_risk_bound_and_enabled_false():
    """No [robust]: α = 0.05 with the data law (Table 1's log RMS 0.10751 as a t_5 model error, a measured wheel's
    σ 0.05, the assumed 0.10 and 0.20 for M_f/θ0 and K_s); enabled = false: none."""
    p = problem_from_toml(BASE)
    assert p.risk.model_error == pytest.approx(0.10751, abs=5e-6)  # Uncertainty reads numbers only (its boundary)
    assert p.risk == Uncertainty(
        probability=0.05,
        model_error=p.risk.model_error,
        damping=0.10,
        slip_coefficient=0.20,
        inertia=0.05,
        model_error_dof=5,
    )
    assert problem_from_toml(BASE + "[robust]\nenabled = false\n").risk is None
    assert problem_from_toml(BASE + "[robust]\nprobability = 0.01\n").risk.probability == 0.01


def test_stock_parsed_in_si_and_trails_from_step():
    """Diameters, grooves, dampings in SI (sorted, deduplicated); trail holes from min every step up to max."""
    p = problem_from_toml(
        BASE
        + """[stock]
diameters = ["5 in", "4 in", "5 in"]
grooves = ["0 in", "0.5625 in"]
trail_step = "0.25 in"
dampings = ["1.3 N*m/rad", 2]
"""
    )
    s = p.stock
    np.testing.assert_allclose(s.diameters, [4 * INCH, 5 * INCH])
    np.testing.assert_allclose(s.grooves, [0.0, 0.5625 * INCH])
    np.testing.assert_allclose(s.trails, (1 + 0.25 * np.arange(7)) * INCH)
    assert s.dampings == (1.3, 2.0)


def test_wheel_catalogue_and_key_left_out_is_continuous():
    """wheels = [{name, diameter, groove, inertia?}]: inertia where given, else from the model; no trail_step."""
    from designer.studies.recommend import stock_candidates

    p = problem_from_toml(
        BASE
        + """[stock]
wheels = [{ name = "Frog 5", diameter = "5 in", groove = "0.25 in", inertia = "0.35e-3 kg*m**2" },
          { name = "Plain 6", diameter = "6 in", groove = "0 in" }]
dampings = ["1.3 N*m/rad"]
"""
    )
    cand = stock_candidates(p)
    assert cand.trail is None and not cand.discrete  # trail left continuous
    assert list(cand.wheel) == ["Frog 5", "Plain 6"]
    assert cand.inertia[0] == pytest.approx(0.35e-3)
    assert cand.inertia[1] == pytest.approx(float(p.conditions.inertia(6 * INCH)))


BAD = [
    ("[stock]\ndiameters = []\n", "stock.diameters = []: empty"),
    ('[stock]\ngrooves = ["1 in"]\n', "stock.grooves[0] = '1 in': 1.000 in outside variables.groove"),
    ('[stock]\ndiameters = ["9 in"]\n', "outside variables.diameter"),
    ('[stock]\ntrail_step = "2 in"\n', "stock.trail_step = 2.000 in: larger than the trail range"),
    ('[stock]\ndiameters = ["5 kg"]\n', "stock.diameters[0]"),
    ('[stock]\ndampings = ["2 in"]\n', "stock.dampings[0]"),
    ('[stock]\ntrail_step = "0 in"\n', "stock.trail_step"),
    ('[stock]\ndiameters = "5 in"\n', "expected a list"),
    ('[stock]\nwheels = [{ name = "x" }]\n', "stock.wheels[0].diameter: missing"),
    ('[stock]\ncolours = ["red"]\n', "unknown key stock.colours"),
    ('[robust]\nenabled = "no"\n', "robust.enabled"),
    ('[objective]\nmax_threshold_force = "110 N"\nmax_turning_effort = "9 N"\n', "not both"),
    ('[objective]\nmax_threshold_force = "110 in"\n', "objective.max_threshold_force"),
]


@pytest.mark.parametrize("extra, message", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_stock_is_one_line_exit_3(tmp_path, capsys, extra, message):
    """Each bad [stock]/[robust]/[objective] entry: exit 3 and one line naming the key and the reason."""
    path = tmp_path / "p.toml"
    path.write_text(BASE + extra)
    assert main(["run", str(path), "--no-cross-check"]) == 3
    errors = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("designer: error")]
    assert len(errors) == 1 and message in errors[0], errors


@pytest.mark.parametrize(
    "inertia, why",
    [
        ('model = "catalog"\nwheels = ["C", "D"]', "the wheel stock is [inertia].wheels"),
        ('model = "fixed"\ninertia = "0.00127 kg*m**2"', "the diameter is fixed"),
    ],
)
def test_stock_diameters_with_catalog_or_fixed_inertia(inertia, why):
    """[stock].diameters with a catalogue or a fixed inertia is a problem-file error that says why."""
    from designer.errors import ProblemError

    text = (
        BASE.replace('diameter = { min = "3 in", max = "8 in" }\n', "")
        + f"[inertia]\n{inertia}\n"
        + '[stock]\ndiameters = ["5 in"]\n'
    )
    with pytest.raises(ProblemError, match="stock.diameters") as info:
        problem_from_toml(text)
    assert why in str(info.value)


def test_problem_dict_stock_keeps_variable_bounds():
    """A fixed variable is one part even without a stock key (paper-invacare's wheel)."""
    from designer.studies.recommend import stock_candidates

    p = problem_from_dict(
        {
            "name": "f",
            "shimmy": {"target_speed": 2.5},
            "variables": {"diameter": "7.75 in", "damping": 1.3},
            "stock": {"grooves": ["0 in", "0.5625 in"], "trail_step": "0.5 in"},
        }
    )
    cand = stock_candidates(p)
    assert cand.discrete and len(cand) == 4 * 2
    assert set(np.round(cand.diameter / INCH, 6)) == {7.75}
