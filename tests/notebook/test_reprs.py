"""Notebook API (issue 17): short ``__repr__`` and ``_repr_html_`` of Problem, Design, Front, Solution,
Recommendation, ExploreResult and the simulation result; data out (Front, Solution and fleet to pandas, the
Front <-> pandas and front.csv round trips)."""

from __future__ import annotations

import dataclasses
import math
import re
from html.parser import HTMLParser

import numpy as np
import pytest

from designer.studies.front._front import MULTIPLIER_ZERO

from designer.studies.optimum import optimise
from designer.studies.front import Front, pareto_front
from designer.studies.recommend import recommend
from designer.data.paper import INCH
from designer.problem import load_problem

from conftest import ROOT

VOID = {"br", "hr", "img", "input", "meta", "link", "col", "area", "base", "embed", "source", "track", "wbr"}


class _Checker(HTMLParser):
    """Collects text and checks every opened tag is closed in order (SVG self-closing tags allowed)."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.text: list[str] = []
        self.errors: list[str] = []
        self.tags: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.tags.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes {self.stack[-1] if self.stack else 'nothing'}")
        else:
            self.stack.pop()

    def handle_data(self, data):
        self.text.append(data)


def parse(html: str) -> tuple[str, list[str]]:
    """(the text, the tags) of an HTML fragment; fails if a tag is left open or closed out of order."""
    checker = _Checker()
    checker.feed(html)
    checker.close()
    assert checker.errors == [], checker.errors
    assert checker.stack == [], f"unclosed tags {checker.stack}"
    return " ".join(checker.text), checker.tags


@pytest.fixture(scope="module")
def problem():
    return load_problem(ROOT / "problems" / "indoor-manual.toml")


@pytest.fixture(scope="module")
def front(problem):
    return pareto_front(problem, points=11)


@pytest.fixture(scope="module")
def solution(problem):
    return optimise(problem, cross_check=False)


@pytest.fixture(scope="module")
def rec(problem):
    return recommend(problem)


def _short(text: str) -> None:
    assert len(text) < 300, (len(text), text)
    assert 1 <= len(text.splitlines()) <= 3, text


def test_problem_repr_is_short_with_headline_numbers(problem):
    """Problem's repr is < 300 chars, 1-3 lines, and names the problem, target and required speed, load, sill."""
    text = repr(problem)
    _short(text)
    c = problem.conditions
    for part in (
        problem.name,
        f"{problem.target_speed:.3g} m/s",
        f"{problem.required_speed:.3g} m/s",
        f"{c.load:.4g} N",
        f"{c.threshold_height * 1000:.3g} mm",
    ):
        assert part in text, (part, text)


def test_problem_html_is_valid_with_units(problem):
    """Problem's HTML parses (tags balanced) and shows the target speed in m/s, the load in N, and the bounds in
    the problem's own unit system: inches for the inch problem, millimetres (and no inch) for the same problem in mm."""
    text, tags = parse(problem._repr_html_())
    assert "table" in tags
    assert f"{problem.target_speed:.4g}" in text and "m/s" in text
    assert f"{problem.conditions.load:.4g}" in text and " N " in f" {text} "
    b = problem.bounds["trail"]
    assert problem.units == "in"
    assert f"{b.low / INCH:.3f} – {b.high / INCH:.3f} in" in text
    metric, _ = parse(dataclasses.replace(problem, units="mm")._repr_html_())
    assert f"{b.low * 1000:.2f} – {b.high * 1000:.2f} mm" in metric
    assert not re.search(r"\d in\b", metric), metric


def test_front_repr_is_short_with_headline_numbers(front):
    """Front's repr (the issue measured 12,103 chars) is < 300 chars and gives the point count, objective ranges
    [N], the knee and the hypervolume."""
    text = repr(front)
    _short(text)
    (f0, p0), (f1, p1) = front.ideal_nadir()
    k = front.knee()
    for part in (
        f"{len(front)} points",
        f"F_turn {f0:.3g}–{f1:.3g} N",
        f"P {p0:.3g}–{p1:.3g} N",
        f"{k.turning_effort:.3g} N",
        f"{front.hypervolume():.3f}",
    ):
        assert part in text, (part, text)


def test_front_html_is_valid_with_units_and_curve(front):
    """Front's HTML parses, has the ranges and knee in N and an inline SVG polyline with one vertex per point."""
    html = front._repr_html_()
    text, tags = parse(html)
    (f0, p0), (f1, p1) = front.ideal_nadir()
    k = front.knee()
    assert f"{f0:.4g} – {f1:.4g}" in text and f"{p0:.4g} – {p1:.4g}" in text
    assert f"{k.turning_effort:.4g} / {k.threshold_force:.4g}" in text
    assert "N·m/rad" in text and "m/s" in text and "in" in text.split()
    assert "svg" in tags and "polyline" in tags
    vertices = html.split('<polyline points="')[1].split('"')[0].split()
    assert len(vertices) == len(front)


def test_solution_repr_is_short_with_headline_numbers(solution):
    """Solution's repr (the issue measured 3,773 chars) is < 300 chars, 1-3 lines, with the design in inches and
    F_turn, P, J [N], V_c [m/s]."""
    text = repr(solution)
    _short(text)
    d, o = solution.design, solution.objectives
    for part in (
        f"T = {d.trail / INCH:.3f} in",
        f"d = {d.diameter / INCH:.3f} in",
        f"F_turn {o['turning_effort']:.4g} N",
        f"P {o['threshold_force']:.4g} N",
        f"J {o['weighted']:.4g} N",
        f"V_c {solution.critical_speed:.4g} m/s",
    ):
        assert part in text, (part, text)


def test_solution_html_is_valid_with_units(solution):
    """Solution's HTML parses and shows the trail in inches and mm, the objectives in N and V_c in m/s."""
    text, _ = parse(solution._repr_html_())
    d, o = solution.design, solution.objectives
    assert f"{d.trail / INCH:.3f} ({d.trail * 1000:.2f} mm)" in text
    assert f"{o['turning_effort']:.4g}" in text and f"{o['threshold_force']:.4g}" in text
    assert f"{solution.critical_speed:.4g}" in text and "m/s" in text and "N·m/rad" in text


def test_recommendation_repr_is_short_with_headline_numbers(rec):
    """Recommendation's repr is < 300 chars, 1-3 lines, with the caster in inches, F_turn and P [N] and P(shimmy)."""
    text = repr(rec)
    _short(text)
    d = rec.design
    for part in (
        f"T {d.trail / INCH:.3f} in",
        f"d {d.diameter / INCH:.3f} in",
        f"F_turn {rec.turning_effort:.4g} N",
        f"P {rec.threshold_force:.4g} N",
        f"{rec.shimmy_probability:.2%}",
    ):
        assert part in text, (part, text)


def test_recommendation_html_has_table_and_drawing_without_solving(rec):
    """Recommendation's HTML parses, shows its numbers with units and the caster drawing (SVG), and does not
    compute the continuous front (no solver runs in a repr; recommend() was given none, so it stays None)."""
    assert rec.front is None
    html = rec._repr_html_()
    text, tags = parse(html)
    d = rec.design
    assert f"{d.trail / INCH:.3f} ({d.trail * 1000:.2f} mm)" in text
    assert f"{rec.turning_effort:.4g}" in text and f"{rec.threshold_force:.4g}" in text
    assert f"{rec.confident_speed:.4g}" in text and "m/s" in text and "mm" in text
    assert 'class="caster-drawing"' in html and "svg" in tags
    assert rec.front is None


def test_front_pandas_round_trip(front):
    """to_pandas has SI units in the column names and attrs; from_pandas gives back the same points to 1e-12."""
    pytest.importorskip("pandas")
    df = front.to_pandas()
    assert len(df) == len(front)
    for col in (
        "trail_m",
        "diameter_m",
        "groove_m",
        "damping_N_m_per_rad",
        "turning_effort_N",
        "threshold_force_N",
        "critical_speed_m_s",
    ):
        assert col in df.columns
    assert df.attrs["units"]["turning_effort_N"] == "N" and df.attrs["problem"] == front.problem.name
    # the variables' columns and units come from the parameter table (the damping's unit was once "rad")
    assert df.attrs["units"]["damping_N_m_per_rad"] == "N·m/rad" and df.attrs["units"]["trail_m"] == "m"
    np.testing.assert_allclose(df["turning_effort_N"].to_numpy(), front.objectives()[:, 0], rtol=0, atol=0)
    back = Front.from_pandas(df, front.problem)
    assert len(back) == len(front) and list(back.failed) == []
    np.testing.assert_allclose(back.objectives(), front.objectives(), rtol=1e-12, atol=0)
    np.testing.assert_allclose(back.designs(), front.designs(), rtol=1e-12, atol=0)
    for a, b in zip(front, back):
        assert (a.family, a.status, a.success, a.wheel) == (b.family, b.status, b.success, b.wheel)
        assert math.isclose(a.critical_speed, b.critical_speed, rel_tol=1e-12)
        assert math.isclose(a.epsilon, b.epsilon, rel_tol=1e-12, abs_tol=1e-300)
        assert a.margins.keys() == b.margins.keys() and a.multipliers.keys() == b.multipliers.keys()
        for name in a.margins:
            assert math.isclose(a.margins[name], b.margins[name], rel_tol=1e-12, abs_tol=1e-300)
        for name in a.multipliers:  # a multiplier within the solver's tolerance of 0 is written 0
            assert math.isclose(a.multipliers[name], b.multipliers[name], rel_tol=1e-12, abs_tol=MULTIPLIER_ZERO)
    lambdas = df[[c for c in df.columns if c.startswith("lambda_")]].to_numpy().ravel()
    assert not np.any((lambdas != 0) & (np.abs(lambdas) < MULTIPLIER_ZERO))  # no -9.96e-17: 0 at the tolerance
    assert math.isclose(back.hypervolume(), front.hypervolume(), rel_tol=1e-12)


def test_buildable_front_with_failed_round_trips(rec):
    """The buildable (stock) front round-trips too, with failed=True keeping the failed rows apart."""
    pytest.importorskip("pandas")
    front = rec.buildable
    df = front.to_pandas(failed=True)
    assert len(df) == len(front) + len(front.failed) and "failed" in df.columns
    back = Front.from_pandas(df, front.problem)
    assert len(back) == len(front) and len(back.failed) == len(front.failed)
    np.testing.assert_allclose(back.objectives(), front.objectives(), rtol=1e-12, atol=0)
    assert [p.wheel for p in back] == [p.wheel for p in front]


def test_to_pandas_without_pandas_says_how_to_install(front, monkeypatch):
    """Without pandas, to_pandas raises ImportError with the pip command of the notebook extra."""
    import builtins

    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas" or name.startswith("pandas."):
            raise ImportError("No module named 'pandas'")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with pytest.raises(ImportError, match=r"caster-designer\[notebook\]"):
        front.to_pandas()


# --------------------------------------------------------------------------- Design, simulation, exploration


def test_design_repr_and_html(rec):
    """Design's repr is two lines < 300 chars (the SI constructor call, then inches); its HTML table parses and
    gives T, d, B in inches and mm, c_f in N·m/rad and the swept radius."""
    d = rec.design
    text = repr(d)
    _short(text)
    assert text.startswith(f"Design(trail={d.trail:.6g}, diameter={d.diameter:.6g}")
    assert f"T {d.trail / INCH:.3f} in" in text and f"c_f {d.damping:.4g} N·m/rad" in text
    body, tags = parse(d._repr_html_())
    assert f"{d.diameter / INCH:.3f} ({d.diameter * 1000:.2f} mm)" in body and "N·m/rad" in body
    assert f"{(d.trail + d.diameter / 2) / INCH:.3f}" in body and "table" in tags


@pytest.fixture(scope="module")
def simulation(problem, rec):
    from designer.studies.dynamics import simulate

    return simulate(rec.design, problem.conditions, speed=problem.target_speed, cycles=6)


def test_simulation_repr_is_short_with_headline_numbers(simulation):
    """The simulation result's repr (the dataclass default printed every array) is < 300 chars, 1-3 lines, with
    the speed [m/s], knock [°], verdict, amplitudes [rad] and Eq. 7 V_c [m/s]."""
    text = repr(simulation)
    _short(text)
    for part in (
        f"V {simulation.speed:.3g} m/s",
        f"knock {math.degrees(simulation.angle):.3g}°",
        "decays" if not simulation.grows else "GROWS",
        f"Eq. 29B {simulation.predicted_amplitude:.3g} rad",
        f"Eq. 7 V_c {simulation.critical_speed:.4g} m/s",
        f"{len(simulation.t)} samples",
    ):
        assert part in text, (part, text)


def test_simulation_html_has_table_and_theta_sparkline(simulation):
    """The simulation's HTML parses, shows speed [m/s], amplitudes [rad] and V_c, and an SVG polyline of θ(t)
    whose vertices span the trace (thinned to at most ~400)."""
    html = simulation._repr_html_()
    text, tags = parse(html)
    assert f"{simulation.speed:.4g}" in text and "m/s" in text and "rad" in text
    assert f"{simulation.critical_speed:.4g}" in text and f"{simulation.predicted_amplitude:.4g}" in text
    assert "svg" in tags and "polyline" in tags
    vertices = html.split('<polyline points="')[1].split('"')[0].split()
    assert 10 < len(vertices) <= 402 and len(vertices) <= len(simulation.t)
    assert len(html) < 20_000


def test_simulation_to_pandas_is_the_trace(simulation):
    """The simulation's to_pandas has the trace with units in the names (t_s, theta_rad, theta_deg, lateral_m),
    equal to the arrays, and the scalars (speed, verdict) in attrs."""
    pytest.importorskip("pandas")
    df = simulation.to_pandas()
    np.testing.assert_array_equal(df["t_s"].to_numpy(), simulation.t)
    np.testing.assert_array_equal(df["theta_rad"].to_numpy(), simulation.theta)
    np.testing.assert_allclose(df["theta_deg"].to_numpy(), np.degrees(simulation.theta), rtol=1e-12)
    np.testing.assert_array_equal(df["lateral_m"].to_numpy(), simulation.lateral)
    assert df.attrs["speed"] == simulation.speed and df.attrs["grows"] == simulation.grows
    assert df.attrs["units"]["theta_deg"] == "deg"


@pytest.fixture(scope="module")
def explored(problem):
    pytest.importorskip("optuna")
    from designer.studies.explore import explore

    return explore(problem, trials=24, seed=0, compare=False)


def test_explore_result_repr_and_html(explored):
    """ExploreResult's repr is < 300 chars with trials, front size, F_turn and P ranges [N] and the hypervolume
    [N²]; its HTML parses, has the same numbers with units and the explored front as an SVG curve."""
    text = repr(explored)
    _short(text)
    f = explored.objectives()
    for part in (
        f"{explored.trials} trials",
        f"front of {len(explored.front)} points",
        f"F_turn {f[:, 0].min():.4g} – {f[:, 0].max():.4g} N",
        f"{explored.hypervolume:.4g} N²",
    ):
        assert part in text, (part, text)
    html = explored._repr_html_()
    body, tags = parse(html)
    assert f"{f[:, 1].min():.4g} – {f[:, 1].max():.4g}" in body and "N²" in body
    assert "polyline" in tags
    assert len(html.split('<polyline points="')[1].split('"')[0].split()) == len(explored.front)


# --------------------------------------------------------------------------- data out


def test_solution_to_pandas_long_and_wide(solution):
    """Solution.to_pandas(): one row per quantity with its unit (design in m, objectives in N, margins, active
    flags); wide=True: one row whose columns match Front.to_pandas's, values equal to the solution's."""
    pytest.importorskip("pandas")
    df = solution.to_pandas()
    row = df.set_index(["kind", "name"])
    assert row.loc[("design", "trail"), "value"] == solution.design.trail
    assert row.loc[("design", "trail"), "unit"] == "m" and row.loc[("objective", "weighted"), "unit"] == "N"
    assert row.loc[("margin", "shimmy"), "unit"] == "m/s"
    assert set(df[df.active]["name"]) == set(solution.active)
    assert len(df[df.kind == "sensitivity"]) == len(solution.sensitivities)
    wide = solution.to_pandas(wide=True)
    assert len(wide) == 1 and wide.attrs["units"]["turning_effort_N"] == "N"
    assert wide["threshold_force_N"][0] == solution.objectives["threshold_force"]
    assert wide["critical_speed_m_s"][0] == solution.critical_speed


def test_fleet_to_pandas_units_in_names(problem):
    """The fleet result's to_pandas has one row per chair, SI units in the column names and attrs, and the
    numbers of FleetResult.rows(); its repr is short with the headline numbers and its HTML parses."""
    pytest.importorskip("pandas")
    from designer.studies.fleet import example_fleet, fleet

    result = fleet(example_fleet(12), problem, skus=2, monte_carlo=False)
    df = result.to_pandas()
    rows = result.rows()
    assert len(df) == len(rows) == 12
    for col in (
        "trail_m",
        "diameter_m",
        "groove_m",
        "damping_N_m_per_rad",
        "turning_effort_N",
        "threshold_force_N",
        "sku",
        "status",
    ):
        assert col in df.columns, col
    assert df.attrs["units"]["damping_N_m_per_rad"] == "N·m/rad" and df.attrs["skus"] == 2
    ok = [i for i, r in enumerate(rows) if r["status"] == "ok"]
    assert ok and all(df["turning_effort_N"][i] == rows[i]["turning_effort"] for i in ok)
    # its repr: short, with the chair count, the part numbers and the F_turn range in N; the HTML parses
    text = repr(result)
    _short(text)
    f = df["turning_effort_N"].dropna()
    assert "chairs (with a caster) 12" in text and "part numbers (SKUs) 2" in text
    assert f"F_turn {f.min():.4g} – {f.max():.4g} N" in text
    body, _ = parse(result._repr_html_())
    assert f"{f.min():.4g} – {f.max():.4g}" in body and " N " in f" {body} "


def test_front_csv_round_trip(front, tmp_path):
    """Front.to_csv -> Front.from_csv gives the same points (10 significant digits in the file) and, through
    to_pandas, the same frame as the original front's (numbers to 1e-9)."""
    pytest.importorskip("pandas")
    path = tmp_path / "front.csv"
    front.to_csv(path)
    back = Front.from_csv(path, front.problem)
    assert len(back) == len(front) and [p.family for p in back] == [p.family for p in front]
    np.testing.assert_allclose(back.objectives(), front.objectives(), rtol=1e-9)
    np.testing.assert_allclose(back.designs(), front.designs(), rtol=1e-9, atol=1e-15)
    a, b = front.to_pandas(), back.to_pandas()
    numeric = [
        "trail_m",
        "diameter_m",
        "groove_m",
        "damping_N_m_per_rad",
        "turning_effort_N",
        "threshold_force_N",
        "critical_speed_m_s",
        "epsilon_N",
    ]
    np.testing.assert_allclose(b[numeric].to_numpy(), a[numeric].to_numpy(), rtol=1e-9, atol=1e-15)
    again = Front.from_pandas(b, front.problem)
    np.testing.assert_array_equal(again.objectives(), back.objectives())


def test_front_from_report_csv_finds_its_problem():
    """Front.from_csv on a report's front.csv finds the problem from the front.json beside it (a shipped
    example, same digest) and gives the report's hypervolume to the precision of the file's 9 significant
    digits; buildable=True reads the stock front's rows.

    The bound: each objective is within ε = 5e-9 of its value; normalised by the front's ideal and nadir (read
    rounded too) a coordinate moves by at most 4 ε max|f| / span, and the area under a staircase inside the
    1.1 × 1.1 reference box (its length at most 2.2) by at most 2.2 times that; plus the saved value's rounding."""
    import json

    folder = ROOT / "results" / "catalog-retrofit"
    saved = json.loads((folder / "front.json").read_text())
    front = Front.from_csv(folder / "front.csv")
    assert front.problem.name == "catalog-retrofit" and len(front) == len(saved["points"])
    f = front.objectives()
    bound = 2.2 * 4 * 5e-9 * float(np.max(np.abs(f).max(axis=0) / np.ptp(f, axis=0))) + 5e-9 * saved["hypervolume"]
    assert abs(front.hypervolume() - saved["hypervolume"]) <= bound
    rows = (folder / "front.csv").read_text().splitlines()[1:]
    buildable = Front.from_csv(folder / "front.csv", buildable=True)
    assert len(buildable) == sum(",true," in r for r in rows) and len(buildable) > 0


def test_front_from_csv_without_a_problem_says_what_to_pass(front, tmp_path):
    """A front.csv with no front.json beside it and no problem= is an InputError telling what to pass."""
    from designer.errors import InputError

    path = tmp_path / "front.csv"
    front.to_csv(path)
    with pytest.raises(InputError, match=r"problem = None: no front.json beside .* pass problem="):
        Front.from_csv(path)
    assert len(Front.from_csv(path, "indoor-manual")) == len(front)


@pytest.mark.parametrize("method", ["solution", "fleet"])
def test_data_out_without_pandas_says_how_to_install(method, solution, monkeypatch):
    """Without pandas, Solution.to_pandas and FleetResult.to_pandas raise ImportError naming the method and the
    pip command of the notebook extra."""
    import builtins

    from designer.studies.fleet import FleetResult

    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas" or name.startswith("pandas."):
            raise ImportError("No module named 'pandas'")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    if method == "solution":
        call, name = solution.to_pandas, "Solution.to_pandas"
    else:
        result = FleetResult.__new__(FleetResult)
        monkeypatch.setattr(FleetResult, "rows", lambda self: [])
        monkeypatch.setattr(FleetResult, "sku_records", lambda self: [])
        object.__setattr__(result, "problem", solution.problem)  # a bare frozen record, for this test only
        call, name = result.to_pandas, "FleetResult.to_pandas"
    with pytest.raises(ImportError, match=rf"{name} needs pandas: pip install 'caster-designer\[notebook\]'"):
        call()
