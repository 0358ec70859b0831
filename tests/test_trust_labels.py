"""Issue 12.2: no numerical noise from the package, and labels that say what was used (weights, units)."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from designer.cli import main

from conftest import ROOT

INDOOR = str(ROOT / "problems" / "indoor-manual.toml")


def test_structured_swept_radius_without_divide_by_zero():
    """The closed-form designs get T_max = R_max − d/2 from the geometry, not by evaluating the whole model
    at T = 0 (F_turn = M/T divided by zero on every pareto run); any warning here is an error."""
    from designer.problem import load_problem
    from designer.solvers import structured

    problem = load_problem(INDOOR)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        x, ok = structured.designs_at_diameter(problem, np.linspace(4, 8, 9) * 0.0254)
    # trail = min(2.5 in, 6 in − d/2): the swept-radius limit binds above d = 7 in
    assert x[:, 0] == pytest.approx(np.minimum(2.5, 6 - np.linspace(4, 8, 9) / 2) * 0.0254)
    assert ok.all()


def test_package_runtime_warnings_fail_the_suite():
    """pyproject's filterwarnings turns a RuntimeWarning raised from a designer module into an error,
    while the same warning from elsewhere stays a warning."""
    code = compile("import warnings\nwarnings.warn('divide by zero', RuntimeWarning)\n", "designer/fake.py", "exec")
    with pytest.raises(RuntimeWarning, match="divide by zero"):
        exec(code, {"__name__": "designer.fake"})
    with pytest.warns(RuntimeWarning):
        exec(code, {"__name__": "elsewhere"})


def test_extrapolation_warning_only_for_reported_diameters():
    """The inertia-extrapolation warning names reported designs outside 4–8 in, never the bounds alone."""
    from designer.problem import load_problem

    problem = load_problem(INDOOR)  # diameter bounds 3–8 in reach outside Table 1
    assert problem.model_warnings([8 * 0.0254, 6 * 0.0254]) == []
    (message,) = problem.model_warnings([3.5 * 0.0254, 6 * 0.0254])
    assert "a reported design uses d = 3.5 in, outside the Table 1 inertia fit (4–8 in)" in message


def test_optimise_inside_table1_does_not_warn():
    """indoor-manual's bounds reach 3 in, but its (risk-bounded) optimum lies inside Table 1's 4-8 in
    (d = 7.72 in): no extrapolation warning."""
    from designer.analysis.optimise import optimise
    from designer.problem import load_problem

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        solution = optimise(load_problem(INDOOR), cross_check=False)
    assert 4 * 0.0254 <= solution.design.diameter <= 8 * 0.0254 * (1 + 1e-9)
    assert not [w for w in caught if "extrapolated" in str(w.message)]


def test_run_weights_printed_and_recorded(capsys):
    """run --weights 10,1 prints the weights used (was the problem's '1, 1') and JSON records them."""
    assert main(["run", INDOOR, "--weights", "10,1", "--no-cross-check"]) == 0
    assert "(weights 10, 1)" in capsys.readouterr().out
    assert main(["run", INDOOR, "--weights", "10,1", "--no-cross-check", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["weights"] == [10.0, 1.0]


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--weights", "-1,1"], "--weights -1,1: w_turn = -1 must be a finite non-negative number"),
        (["--weights=-1,1"], "--weights -1,1: w_turn = -1 must be a finite non-negative number"),
        (["--weights", "1,-2"], "--weights 1,-2: w_threshold = -2 must be a finite non-negative number"),
    ],
)
def test_negative_weights_named(argv, fragment, capsys):
    """A negative weight is named with its value (argparse used to take '-1,1' for an option)."""
    assert main(["run", INDOOR] + argv) == 2
    assert fragment in capsys.readouterr().err


def test_explore_summary_shows_units(tmp_path, capsys):
    """The explore front table's headers keep their units (rich read '[in]' as a markup tag and dropped it)."""
    assert main(["explore", INDOOR, "--trials", "20", "--no-compare", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    for header in ("T [in]", "d [in]", "B [in]", "c_f [N·m/rad]", "V_c [m/s]"):
        assert header in out


def test_calibration_rms_residual_has_unit(capsys):
    """The calibration summary gives the rms residual with the unit of the fitted quantity."""
    data = ROOT / "designer" / "data" / "examples"
    assert main(["calibrate", "turning", str(data / "turning_tile.csv")]) == 0
    assert "rms residual" in (out := capsys.readouterr().out)
    assert " N·m;" in out.split("rms residual", 1)[1].split(")")[0] + ")"
    assert main(["calibrate", "slip", str(data / "slip.csv"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rms_residual_unit"] == "N"
