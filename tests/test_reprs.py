"""Notebook API (issue 17): short ``__repr__`` and ``_repr_html_`` of Problem, Front, Solution and Recommendation,
and the Front <-> pandas round trip."""
from __future__ import annotations

import math
from html.parser import HTMLParser

import numpy as np
import pytest

from designer.analysis.optimise import optimise
from designer.analysis.pareto import Front, pareto_front
from designer.analysis.recommend import recommend
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
    for part in (problem.name, f"{problem.target_speed:.3g} m/s", f"{problem.required_speed:.3g} m/s",
                 f"{c.load:.4g} N", f"{c.threshold_height * 1000:.3g} mm"):
        assert part in text, (part, text)


def test_problem_html_is_valid_with_units(problem):
    """Problem's HTML parses (tags balanced) and shows the target speed in m/s, the load in N, bounds in mm."""
    text, tags = parse(problem._repr_html_())
    assert "table" in tags
    assert f"{problem.target_speed:.4g}" in text and "m/s" in text
    assert f"{problem.conditions.load:.4g}" in text and " N " in f" {text} "
    b = problem.bounds["trail"]
    assert f"{b.low * 1000:.4g} – {b.high * 1000:.4g}" in text and "mm" in text


def test_front_repr_is_short_with_headline_numbers(front):
    """Front's repr (the issue measured 12,103 chars) is < 300 chars and gives the point count, objective ranges
    [N], the knee and the hypervolume."""
    text = repr(front)
    _short(text)
    (f0, p0), (f1, p1) = front.ideal_nadir()
    k = front.knee()
    for part in (f"{len(front)} points", f"F_turn {f0:.3g}–{f1:.3g} N", f"P {p0:.3g}–{p1:.3g} N",
                 f"{k.turning_effort:.3g} N", f"{front.hypervolume():.3f}"):
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
    for part in (f"T {d.trail / INCH:.3f} in", f"d {d.diameter / INCH:.3f} in", f"F_turn {o['turning_effort']:.4g} N",
                 f"P {o['threshold_force']:.4g} N", f"J {o['weighted']:.4g} N", f"V_c {solution.critical_speed:.4g} m/s"):
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
    for part in (f"T {d.trail / INCH:.3f} in", f"d {d.diameter / INCH:.3f} in", f"F_turn {rec.turning_effort:.4g} N",
                 f"P {rec.threshold_force:.4g} N", f"{rec.shimmy_probability:.2%}"):
        assert part in text, (part, text)


def test_recommendation_html_has_table_and_drawing_without_solving(rec):
    """Recommendation's HTML parses, shows its numbers with units and the caster drawing (SVG), and does not
    compute the continuous front (no solver runs in a repr)."""
    assert rec._front is None
    html = rec._repr_html_()
    text, tags = parse(html)
    d = rec.design
    assert f"{d.trail / INCH:.3f} ({d.trail * 1000:.2f} mm)" in text
    assert f"{rec.turning_effort:.4g}" in text and f"{rec.threshold_force:.4g}" in text
    assert f"{rec.confident_speed:.4g}" in text and "m/s" in text and "mm" in text
    assert 'class="caster-drawing"' in html and "svg" in tags
    assert rec._front is None


def test_front_pandas_round_trip(front):
    """to_pandas has SI units in the column names and attrs; from_pandas gives back the same points to 1e-12."""
    pytest.importorskip("pandas")
    df = front.to_pandas()
    assert len(df) == len(front)
    for col in ("trail_m", "diameter_m", "groove_m", "damping_N_m_per_rad", "turning_effort_N", "threshold_force_N",
                "critical_speed_m_s"):
        assert col in df.columns
    assert df.attrs["units"]["turning_effort_N"] == "N" and df.attrs["problem"] == front.problem.name
    np.testing.assert_allclose(df["turning_effort_N"].to_numpy(), front.objectives()[:, 0], rtol=0, atol=0)
    back = Front.from_pandas(df, front.problem)
    assert len(back) == len(front) and back.failed == []
    np.testing.assert_allclose(back.objectives(), front.objectives(), rtol=1e-12, atol=0)
    np.testing.assert_allclose(back.designs(), front.designs(), rtol=1e-12, atol=0)
    for a, b in zip(front, back):
        assert (a.family, a.status, a.success, a.wheel) == (b.family, b.status, b.success, b.wheel)
        assert math.isclose(a.critical_speed, b.critical_speed, rel_tol=1e-12)
        assert math.isclose(a.epsilon, b.epsilon, rel_tol=1e-12, abs_tol=1e-300)
        assert a.margins.keys() == b.margins.keys() and a.multipliers.keys() == b.multipliers.keys()
        for name in a.margins:
            assert math.isclose(a.margins[name], b.margins[name], rel_tol=1e-12, abs_tol=1e-300)
        for name in a.multipliers:
            assert math.isclose(a.multipliers[name], b.multipliers[name], rel_tol=1e-12, abs_tol=1e-300)
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
