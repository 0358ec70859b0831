"""Notebook plot methods (issue 17, part 3): front.plot, front.plot_variables, recommendation.draw and
simulation.plot return matplotlib Axes that show the object's own numbers, and the report draws with the
same functions."""

from __future__ import annotations

import numpy as np
import pytest

from designer.studies.front import Front
from designer.studies.front import pareto_front
from designer.studies.recommend import recommend
from designer.studies.dynamics import simulate
from designer.data.paper import INCH
from designer import display
from designer.problem import load_problem

from conftest import ROOT

plt = pytest.importorskip("matplotlib.pyplot")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def problem():
    return load_problem(ROOT / "problems" / "indoor-manual.toml")


@pytest.fixture(scope="module")
def front(problem):
    return pareto_front(problem, points=9)


@pytest.fixture(scope="module")
def rec(problem):
    return recommend(problem)


def test_front_plot_line_is_the_front(front):
    """front.plot() returns Axes whose line runs through (P, F_turn) of every point in order, with one
    marker per point over the family scatters, and the knee circled; a buildable front says so in its legend."""
    from matplotlib.axes import Axes

    ax = front.plot()
    assert isinstance(ax, Axes)
    f = front.objectives()
    line = ax.lines[0]
    np.testing.assert_array_equal(line.get_xdata(), f[:, 1])
    np.testing.assert_array_equal(line.get_ydata(), f[:, 0])
    families = [c for c in ax.collections if c.get_label().startswith("continuous front: ")]
    assert sum(len(c.get_offsets()) for c in families) == len(front)
    assert {c.get_label().split(": ")[1] for c in families} == {p.family for p in front}
    knee = [c for c in ax.collections if c.get_label().startswith("knee")]
    k = front.knee()
    assert len(knee) == 1 and tuple(knee[0].get_offsets()[0]) == (k.threshold_force, k.turning_effort)
    assert ax.get_xlabel() == display.axis("threshold_force") == "sill force P [N]" and "[N]" in ax.get_ylabel()
    buildable = Front(front.problem, front.points, meta={"buildable": True})  # as Recommendation.buildable
    stock = [c.get_label() for c in buildable.plot().collections]
    assert all(label.startswith(("buildable front: ", "knee")) for label in stock), stock


def test_front_plot_color_by_a_variable(front):
    """color_by="trail" colours the points by the trail in mm (colour bar); an unknown name is a ValueError."""
    ax = front.plot(color_by="trail")
    points = [c for c in ax.collections if c.get_array() is not None and len(c.get_offsets()) == len(front)]
    np.testing.assert_allclose(points[0].get_array(), front.designs()[:, 0] * 1000)
    assert len(ax.figure.axes) == 2  # the colour bar
    _, given = plt.subplots()
    assert front.plot(ax=given, color_by=None) is given
    with pytest.raises(ValueError, match="color_by = 'colour'"):
        front.plot(color_by="colour")


def test_front_plot_variables_panels(front):
    """plot_variables() gives a 2 × 2 array of Axes: T, d, B in mm and c_f, each line the front's values
    against P."""
    axes = front.plot_variables()
    assert axes.shape == (2, 2)
    p = [q.threshold_force for q in front]
    for ax, k, scale in zip(axes.ravel(), range(4), (1000, 1000, 1000, 1)):
        np.testing.assert_array_equal(ax.lines[0].get_xdata(), p)
        np.testing.assert_allclose(ax.lines[0].get_ydata(), front.designs()[:, k] * scale)
    assert [ax.get_ylabel() for ax in axes.ravel()] == [
        "trail T [mm]",
        "diameter d [mm]",
        "groove B [mm]",
        "damping c_f [N·m/rad]",
    ]


def test_recommendation_draw_to_scale(rec):
    """recommendation.draw() returns (side, top) Axes: the wheel circle has radius d/2 and the swept circle
    radius T + d/2, in inches."""
    from matplotlib.patches import Circle

    side, top = rec.draw()
    d = rec.design
    radii = [c.get_radius() for c in side.patches if isinstance(c, Circle)]
    assert any(abs(r - d.diameter / 2 / INCH) < 1e-12 for r in radii)
    swept = [c.get_radius() for c in top.patches if isinstance(c, Circle)]
    assert abs(swept[0] - (d.trail + d.diameter / 2) / INCH) < 1e-12
    only_side, none = rec.draw(ax=plt.subplots()[1])
    assert none is None and only_side.patches


def test_simulation_plot_is_theta_in_degrees(rec, problem):
    """simulation.plot() draws θ(t) in degrees against t [s], with ± the Eq. 29B amplitude."""
    result = simulate(rec.design, problem.conditions, speed=problem.target_speed, cycles=4)
    ax = result.plot()
    line = ax.lines[0]
    np.testing.assert_array_equal(line.get_xdata(), result.t)
    np.testing.assert_allclose(line.get_ydata(), np.degrees(result.theta))
    amp = np.degrees(result.predicted_amplitude)
    assert [tuple(h.get_ydata()) for h in ax.lines[1:3]] == [(amp, amp), (-amp, -amp)]
    assert ax.get_ylabel() == "caster angle θ [deg]" and ax.get_xlabel() == "time [s]"


def test_report_figures_draw_with_the_same_functions(front, monkeypatch):
    """The report's front and variables figures call plot_front and plot_variables, the functions behind
    Front.plot and Front.plot_variables (one drawing code)."""
    from designer.plots import figures, fronts

    called = []
    for name in ("plot_front", "plot_variables"):
        real = getattr(fronts, name)

        def spy(*args, _real=real, _name=name, **kwargs):
            called.append(_name)
            return _real(*args, **kwargs)

        monkeypatch.setattr(figures, name, spy)
        monkeypatch.setattr(fronts, name, spy)
    f = front.objectives()
    figures.figure_front(
        {"turning_effort": f[:, 0], "threshold_force": f[:, 1], "family": [p.family for p in front]}, "title"
    )
    figures.figure_variables(
        [p.threshold_force for p in front],
        front.designs(),
        [p.family for p in front],
        [front.problem.bounds[v] for v in ("trail", "diameter", "groove", "damping")],
    )
    front.plot()
    front.plot_variables()
    assert called == ["plot_front", "plot_variables", "plot_front", "plot_variables"]


def test_simulation_model_draws_nothing():
    """analysis/simulate.py (the time-domain model) imports no matplotlib, not even late: its drawing lives in
    plots/simulation.py and the validation study in analysis/simulation_study.py."""
    import ast

    from designer.studies.dynamics import _simulate as module
    from designer.studies.dynamics import write_simulation_report
    from designer.plots.simulation import figure_onset_comparison

    tree = ast.parse(open(module.__file__, encoding="utf-8").read())
    names = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    names += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    assert not [n for n in names if n.startswith("matplotlib")], names
    assert callable(write_simulation_report) and callable(figure_onset_comparison)


def test_readme_says_what_each_plot_method_returns(front, rec, problem):
    """Issue 28.6: the README said "four plot methods return matplotlib Axes" while plot_variables() returns a
    2 × 2 array and draw() a pair; the notebook guide (docs/examples/index.md, where the README's notebook
    section moved) says what each returns, and each returns that."""
    from matplotlib.axes import Axes

    text = " ".join((ROOT / "docs" / "examples" / "index.md").read_text(encoding="utf-8").split())
    assert "`front.plot_variables()` (T, d, B, c_f along the front) returns the 2 × 2 NumPy array of Axes" in text
    assert "`recommendation.draw()` (side and top views to scale) returns the pair `(ax_side, ax_top)`" in text
    assert "Four plot methods return matplotlib Axes" not in text
    assert isinstance(front.plot(), Axes)
    axes = front.plot_variables()
    assert isinstance(axes, np.ndarray) and axes.shape == (2, 2) and all(isinstance(a, Axes) for a in axes.flat)
    side, top = rec.draw()
    assert isinstance(side, Axes) and isinstance(top, Axes)
    assert isinstance(simulate(rec.design, problem.conditions, speed=2.0, cycles=2).plot(), Axes)
