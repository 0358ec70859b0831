"""Issue 12.5: the closed-form candidate "damping at its maximum, groove from Eq. 7" is needed on a
constructed problem, and the NLP agrees with it there."""

from __future__ import annotations

import numpy as np
import pytest

from designer.problem import problem_from_toml
from designer.solvers import structured
from designer.solvers.nlp import CasterNLP, evaluate_many

HEAVY = """name = "heavy-carpet-pivot"
title = "Heavy load on carpet, pivot turning, small damper"
[conditions]
load = "700 N"
threshold_height = "0.5 in"
surface = "carpet"
turning_mode = "pivot"
[shimmy]
target_speed = "3.5 m/s"
[variables]
trail = { min = "1 in", max = "2.5 in" }
diameter = { min = "3 in", max = "8 in" }
groove = { min = "0 in", max = "0.75 in" }
damping = { min = "1.3 N*m/rad", max = "1.5 N*m/rad" }
[robust]
enabled = false
"""
"""Nominal Eq. 7 constraint (the closed form is for it). A heavy caster (700 N) turned on carpet in pivot mode: the groove costs much turning moment, the damper
is capped at 1.5 N·m/rad.  Between the bare-fork and the full-groove designs the cheapest way to reach
V_c = 3.5 m/s is the whole damper plus just the groove Eq. 7 still needs."""
LAST = structured.CANDIDATES.index("groove from Eq. 7 at the most damping")


@pytest.fixture(scope="module")
def heavy():
    problem = problem_from_toml(HEAVY)
    d = np.linspace(problem.lower().diameter, problem.upper().diameter, 400)
    x, ok = structured.designs_at_diameter(problem, d)
    others = tuple(i for i in range(len(structured.CANDIDATES)) if i != LAST)
    x3, ok3 = structured.designs_at_diameter(problem, d, candidates=others)
    f = evaluate_many(problem, x)["turning_effort"]
    f3 = np.where(ok3, evaluate_many(problem, x3)["turning_effort"], np.inf)
    return problem, d, x, ok, f, f3


def test_damping_at_max_groove_from_eq7_is_chosen(heavy):
    """At 43 of 400 diameters the optimum is c_f = 1.5 (its maximum) with 0 < B < 0.75 in on the shimmy
    constraint (V_c = V_req): the fourth closed-form candidate, and only it."""
    problem, d, x, ok, f, f3 = heavy
    chosen = ok & (f3 > f * (1 + 1e-9))
    assert chosen.sum() >= 30  # 43 today; ≥ 30 keeps the test about the candidate, not the grid
    xc = x[chosen]
    assert np.all(xc[:, 3] == pytest.approx(1.5))
    assert np.all((xc[:, 2] > 1e-4) & (xc[:, 2] < 0.75 * 0.0254 - 1e-4))
    v = evaluate_many(problem, xc)["critical_speed"]
    assert v == pytest.approx(problem.required_speed, rel=1e-9)


def test_removing_the_candidate_costs_up_to_2_percent(heavy):
    """Without the candidate the closed form is up to 2.15 % worse in F_turn (> 1.5 % asserted: the cost
    the audit measured, 2.15 %, minus margin for the 400-point grid)."""
    problem, d, x, ok, f, f3 = heavy
    cost = np.max(np.where(ok, f3 / f - 1, 0.0))
    assert 0.015 < cost < 0.03


def test_nlp_confirms_the_candidate(heavy):
    """IPOPT from the closed-form design at the diameter of largest cost stays there (it is the optimum of
    min F_turn at that d, not only the best of the four candidates)."""
    problem, d, x, ok, f, f3 = heavy
    k = int(np.argmax(np.where(ok, f3 / f, 0.0)))
    from designer.problem import Bound

    fixed = problem.replace(bounds={**problem.bounds, "diameter": Bound(d[k], d[k])})
    nlp = CasterNLP(fixed)
    r = nlp.solve(x[k], (1.0, 0.0))
    assert r.success
    assert nlp.objectives(r.design)[0] == pytest.approx(f[k], rel=1e-6)
    assert r.design.damping == pytest.approx(1.5, rel=1e-6)
