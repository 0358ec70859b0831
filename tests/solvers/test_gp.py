"""Tests of the geometric-programming solver (designer.solvers.gp._solve, docs/model.md#solvers cvxpy paragraph)."""

from __future__ import annotations

import math
import warnings
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from designer.model import Design, performance
from designer.physics.threshold import threshold_force_ratio, threshold_series_remainder_bound
from designer.problem import Bound, load_problem
from designer.solvers import gp
from designer.solvers.gp import _terms as gp_terms_module
from designer.solvers.nlp import CasterNLP, best_starts, solve_best

PROBLEMS = sorted((Path(__file__).resolve().parents[2] / "problems").glob("*.toml"))
NAMES = [p.stem for p in PROBLEMS]


def _quiet_perf(design: Design, conditions) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return performance(design.trail, design.diameter, design.groove, design.damping, conditions)


@lru_cache(maxsize=None)
def _problem(name):
    """The shipped problem without its risk bound (the GP's exactness and duals are for Eq. 7 itself)."""
    return load_problem(next(p for p in PROBLEMS if p.stem == name)).nominal()


@lru_cache(maxsize=None)
def _gp(name):
    record = []
    result = gp.solve_gp(_problem(name), record=record)
    return result, tuple(record)


@lru_cache(maxsize=None)
def _nlp_best(name):
    """Best NLP optimum over the problem's variants: (J, variant, nlp, result)."""
    problem = _problem(name)
    w = problem.weights
    best = None
    for variant in problem.variants():
        nlp = CasterNLP(variant)
        result, _ = solve_best(nlp, best_starts(variant, w), w)
        if result is not None and (best is None or result.objective < best[0]):
            best = (result.objective, variant, nlp, result)
    return best


def _bare_fork_indoor():
    """indoor-manual with the groove fixed at 0 and the bare fork's damping: only the exact family."""
    p = _problem("indoor-manual")
    bounds = dict(p.bounds)
    bounds["groove"] = Bound(0.0, 0.0)
    bounds["damping"] = Bound(1.3, 1.3)
    return p.replace(name="indoor-bare-fork", bounds=bounds)


@pytest.mark.parametrize("name", NAMES)
def test_polished_gp_agrees_with_nlp(name):
    """For every shipped problem, the GP/SGP answer after exact-model polish has the NLP's J within 1e-4 relative;
    the GP answer itself (before polish) is within 1e-6, or 1 % for a robust problem (where the GP bounds the
    quantile of V_c conservatively)."""
    problem = _problem(name)
    result, _ = _gp(name)
    _, j_polished = gp.polish(problem, result)
    j_nlp = _nlp_best(name)[0]
    assert abs(j_polished - j_nlp) <= 1e-4 * j_nlp, (j_polished, j_nlp)
    robust = getattr(problem.conditions, "uncertainty", None) is not None
    assert abs(result.objective - j_nlp) <= (1e-2 if robust else 1e-6) * j_nlp, (result.objective, j_nlp)
    # the GP's own value is the truncated-series J: at most the exact J, and by less than the bound
    assert result.gp_objective <= result.objective * (1 + 1e-8)
    assert (
        result.objective - result.gp_objective <= result.truncation_error * result.objective + 1e-8 * result.objective
    )


@pytest.mark.parametrize("name", NAMES)
def test_every_gp_iterate_is_feasible_for_exact_model(name):
    """Every GP and SGP iterate of every family (and the answer) meets the exact shimmy constraint
    (V_c, or its robust quantile, >= V_req within 1e-9 relative), the box and the swept-radius limit."""
    problem = _problem(name)
    result, record = _gp(name)
    assert len(record) >= len(result.families) - sum(1 for f in result.families if f[3] == "infeasible")
    for variant, design in list(record) + [(result.problem, result.design)]:
        values = _quiet_perf(design, variant.conditions)
        speed = float(values.get("confident_speed", values["critical_speed"]))
        assert speed >= problem.required_speed * (1 - 1e-9), (design, speed)
        lo, hi = variant.lower().as_array(), variant.upper().as_array()
        x = design.as_array()
        assert np.all(x >= lo - 1e-12) and np.all(x <= hi * (1 + 1e-9) + 1e-12), design
        if problem.swept_radius_max is not None:
            assert float(values["swept_radius"]) <= problem.swept_radius_max * (1 + 1e-9)


@pytest.mark.parametrize("name", ["indoor-manual", "sports-court", "powered-chair", "catalog-retrofit"])
def test_gp_terms_reproduce_model(name):
    """The GP's posynomial terms, evaluated at the GP solution, reproduce designer.model._caster.performance:
    F_turn, I_w, T + d/2 to 1e-12; Σ shimmy terms / I_w = V_c² (Eq. 7) to 1e-12; the P series below the
    exact Eq. 4A by at most the stated truncation bound (< 1e-8 relative)."""
    result, _ = _gp(name)
    variant = result.problem
    order = result.order
    s_max = max(v.conditions.threshold_height / v.bounds["diameter"].low for v in _problem(name).variants())
    consts = gp_terms_module._constants(variant, gp_terms_module._parameters(variant))
    d = result.design
    terms = gp_terms_module.gp_terms(
        d.trail, d.diameter, d.groove, d.damping - variant.conditions.turning.bare_fork_damping, consts, order, s_max
    )
    exact = _quiet_perf(d, variant.conditions)
    assert terms["turning_effort"] == pytest.approx(float(exact["turning_effort"]), rel=1e-12)
    assert terms["inertia"] == pytest.approx(float(exact["inertia"]), rel=1e-12)
    assert terms["swept_radius"] == pytest.approx(float(exact["swept_radius"]), rel=1e-12)
    v2 = sum(terms["shimmy_rhs"]) / terms["inertia"]
    assert v2 == pytest.approx(float(exact["critical_speed"]) ** 2, rel=1e-12)
    p_exact = float(exact["threshold_force"])
    assert terms["threshold_force"] <= p_exact
    assert (p_exact - terms["threshold_force"]) / p_exact <= result.truncation_error + 1e-15
    assert result.truncation_error < 1e-8
    assert terms["threshold_force"] + terms["threshold_remainder"] >= p_exact * (1 - 1e-15)  # conservative cap form
    # and the GP's optimal value is its objective built from these terms
    w = _problem(name).weights
    assert result.gp_objective == pytest.approx(
        w[0] * terms["turning_effort"] + w[1] * terms["threshold_force"], rel=1e-7
    )


def test_series_truncation_bound_holds_against_exact_eq_4a():
    """For s = h/d from 0.01 to 0.45 and orders 0–40, the truncated series is below the exact Eq. 4A and
    the gap is within threshold_series_remainder_bound; series_order meets its 1e-9 target on every problem."""
    from designer.physics.threshold import threshold_series_coefficients

    s = np.linspace(0.01, 0.45, 89)
    exact = threshold_force_ratio(1.0, s)  # d = 1 m, h = s
    for order in (0, 1, 2, 5, 10, 20, 40):
        c = threshold_series_coefficients(order)
        series = 2 * np.sqrt(s) * sum(ck * s**k for k, ck in enumerate(c))
        gap = exact - series
        assert np.all(gap >= -1e-15)
        assert np.all(gap <= threshold_series_remainder_bound(s, order) * (1 + 1e-12) + 1e-15)
    for name in NAMES:
        order, bound = gp_terms_module.series_order(_problem(name))
        assert bound < gp_terms_module.SERIES_TOLERANCE and order <= 40, (name, order, bound)


def test_bare_fork_family_is_exact_and_global():
    """The bare-fork family (B = 0, c_f = c_0) is flagged exact, the SGP families are not, and its GP optimum is
    the global one: no feasible point of a 400×400 (T, d) grid has a lower exact J."""
    result, _ = _gp("indoor-manual")
    flags = {f[0]: f[2] for f in result.families}
    assert flags == {"bare fork": True, "groove": False, "damper": False, "groove+damper": False}
    problem = _bare_fork_indoor()
    r = gp.solve_gp(problem)
    assert r.family == "bare fork" and r.exact and r.iterations == 1
    t = np.linspace(problem.bounds["trail"].low, problem.bounds["trail"].high, 400)
    d = np.linspace(problem.bounds["diameter"].low, problem.bounds["diameter"].high, 400)
    tt, dd = np.meshgrid(t, d)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        v = performance(tt, dd, 0.0, 1.3, problem.conditions)
    j = v["turning_effort"] + v["threshold_force"]
    feasible = (v["critical_speed"] >= problem.required_speed) & (v["swept_radius"] <= problem.swept_radius_max)
    assert feasible.any()
    assert r.objective <= j[feasible].min() * (1 + 1e-9)
    assert r.objective >= j[feasible].min() * (1 - 2e-3)  # and the grid comes close to it


@pytest.mark.parametrize("case", ["indoor-manual", "sports-court", "powered-chair", "bare-fork"])
def test_gp_duals_match_nlp_sensitivities(case):
    """GP dual sensitivities d log J / d log p equal CasterNLP.sensitivities on the same keys within 1e-6
    absolute: an exact family (bare fork) and converged SGPs (groove; groove+damper)."""
    if case == "bare-fork":
        problem = _bare_fork_indoor()
        result = gp.solve_gp(problem)
        nlp = CasterNLP(problem)
        best, _ = solve_best(nlp, best_starts(problem, problem.weights), problem.weights)
    else:
        problem = _problem(case)
        result, _ = _gp(case)
        _, _, nlp, best = _nlp_best(case)
    sens = nlp.sensitivities(best, problem.weights)
    gp_sens = result.duals
    significant = {k for k, v in sens.items() if abs(v) > 1e-6}
    assert significant <= set(gp_sens), significant - set(gp_sens)
    assert {"target_speed", "load", "threshold_height"} <= set(gp_sens)
    for key in set(sens) & set(gp_sens):
        assert gp_sens[key] == pytest.approx(sens[key], abs=1e-6), key
    for key in set(gp_sens) - set(sens):
        assert abs(gp_sens[key]) <= 1e-6, key
    if case in ("indoor-manual", "bare-fork"):
        assert gp_sens["target_speed"] > 0.01  # the shimmy constraint is active: 2 × its dual


def test_target_speed_dual_matches_resolve():
    """2 × the shimmy dual (the target-speed sensitivity) matches re-solving the GP at V_target ± 0.1 %."""
    problem = _problem("sports-court")
    result, _ = _gp("sports-court")
    js = [gp.solve_gp(problem.replace(target_speed=problem.target_speed * f)).gp_objective for f in (1.001, 1 / 1.001)]
    fd = (math.log(js[0]) - math.log(js[1])) / (2 * math.log(1.001))
    assert result.duals["target_speed"] == pytest.approx(fd, abs=2e-5)


def test_threshold_cap_is_conservative_and_active():
    """An ε-cap P <= ε (a Pareto point) holds for the exact Eq. 4A at the GP answer, is active (P within 1e-6
    of ε), gives a positive threshold_cap price, and raises the turning effort over the uncapped optimum."""
    problem = _problem("powered-chair")  # its optimum has d < d_max, so P can still fall
    free, _ = _gp("powered-chair")
    p_free = float(_quiet_perf(free.design, problem.conditions)["threshold_force"])
    cap = 0.995 * p_free
    r = gp.solve_gp(problem, threshold_cap=cap)
    values = _quiet_perf(r.design, problem.conditions)
    assert float(values["threshold_force"]) <= cap
    assert float(values["threshold_force"]) >= cap * (1 - 1e-6)
    assert -r.duals["threshold_cap"] > 0
    assert float(values["turning_effort"]) > float(_quiet_perf(free.design, problem.conditions)["turning_effort"])


def test_infeasible_target_raises_and_starts_are_cheap():
    """An unreachable target speed raises InfeasibleError (one line naming the speed) and the GP solver's optimum
    is a failure with no design (no NLP starts); solve_gp(max_iterations=1) gives one feasible design per family
    of a reachable problem (the NLP starts ``optimise`` takes from ``result.designs``)."""
    from designer.errors import InfeasibleError

    problem = _problem("sports-court")
    with pytest.raises(InfeasibleError, match="target speed"):
        gp.solve_gp(problem.replace(target_speed=40.0))
    assert gp.GP.optimum(problem.replace(target_speed=40.0)).design is None
    starts = [d.as_array() for d in gp.solve_gp(problem, max_iterations=1).designs.values()]
    assert len(starts) == 4
    for x in starts:
        v = _quiet_perf(Design.from_array(x), problem.conditions)
        assert float(v["critical_speed"]) >= problem.required_speed * (1 - 1e-9)


def test_a_cap_the_gp_cannot_meet_is_infeasible_not_a_crash():
    """The GP's ε-front down to a cap below its conservative P (indoor-manual, ε = 128, 120, 110, 100 N: the
    series' margin leaves no GP design under 100 N) gives three optima that meet their caps and one infeasible
    point.  It raised TypeError: a failed solve leaves the cvxpy variables empty, and the check that the duals
    belong to the kept solution read them as floats."""
    problem = load_problem(PROBLEMS[NAMES.index("indoor-manual")])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        found = gp.GP.front_designs(problem, [128.0, 120.0, 110.0, 100.0])
    assert list(found.success) == [True, True, True, False]
    assert list(found.status) == ["converged", "converged", "converged", "infeasible"]
    assert np.all(found.objectives[:3, 1] <= np.array([128.0, 120.0, 110.0]) * (1 + 1e-9))
