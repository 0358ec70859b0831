"""One compiled NLP per problem structure (designer.solvers.nlp.shared_nlp): the front, the tighter front of
check 8c, the weighted optimum and check 8c's domination test share it, and every solve is the one of a
fresh build, to the bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from designer.studies import front as pareto
from designer.studies.optimum import optimise
from designer.problem import load_problem
from designer.solvers import nlp as N
from designer.solvers import nlp as S

INDOOR = Path(__file__).resolve().parents[2] / "problems" / "indoor-manual.toml"


@pytest.fixture()
def problem():
    S.SHARED.clear()
    yield load_problem(INDOOR)
    S.SHARED.clear()


def _same(a: N.NLPResult, b: N.NLPResult) -> None:
    np.testing.assert_array_equal(a.design.as_array(), b.design.as_array())
    np.testing.assert_array_equal(a.lam_g, b.lam_g)
    assert (a.success, a.status, a.iterations, a.objective) == (b.success, b.status, b.iterations, b.objective)


def test_views_share_the_build_and_solve_as_a_fresh_build(problem):
    """A faster target (check 8c) gets a view of the same compiled solver; its ε-constraint and weighted solves
    equal those of a fresh build of that problem bit for bit (design, multipliers, iterations)."""
    base = S.shared_nlp(problem)
    tighter = problem.replace(target_speed=problem.target_speed * 1.1)
    view = S.shared_nlp(tighter, same_scaling=True)
    assert view.solver is base.solver and view is not base
    assert view.problem is tighter and base.problem is problem  # the build is not changed
    fresh = N.CasterNLP(tighter)
    assert view.references() == (fresh.f_ref, fresh.p_ref)
    start = problem.upper()
    cap = float(view.objectives(problem.lower())[1]) * 3
    _same(view.solve(start, (1.0, 0.0), cap), fresh.solve(start, (1.0, 0.0), cap))
    _same(view.solve(start, (1.0, 1.0)), fresh.solve(start, (1.0, 1.0)))


def test_other_load_gets_its_own_scaling_when_asked(problem):
    """Another caster load shares the structure but not the objective's scale: ``same_scaling`` then builds
    anew (its solves are a fresh build's), while the front's default reuses the first build."""
    base = S.shared_nlp(problem)
    heavier = problem.replace(conditions=problem.conditions.replace(load=problem.conditions.load * 1.5))
    assert S.structure_key(heavier) == S.structure_key(problem)
    own = S.shared_nlp(heavier, same_scaling=True)
    assert own.solver is not base.solver
    assert own.f_ref != base.f_ref
    assert S.shared_nlp(heavier).solver is base.solver
    assert S.SHARED[S.structure_key(problem)] is base  # the kept build is still the first one


def test_optimum_with_the_fronts_build_equals_a_fresh_build(problem, monkeypatch):
    """The weighted optimum solved on the front's compiled NLP (after pareto_front) equals the one solved on
    a new CasterNLP, to the bit, and builds nothing more."""
    pareto.pareto_front(problem, points=5)
    built = []
    real = N.CasterNLP.__init__

    def counting(self, *args, **kwargs):
        built.append(1)
        real(self, *args, **kwargs)

    monkeypatch.setattr(N.CasterNLP, "__init__", counting)
    shared = optimise(problem, cross_check=False)
    assert built == []
    S.SHARED.clear()
    fresh = optimise(problem, cross_check=False)
    assert built == [1]
    np.testing.assert_array_equal(shared.design.as_array(), fresh.design.as_array())
    assert shared.objectives == fresh.objectives


def test_check_8c_batch_screen_agrees_with_single_solves(problem, monkeypatch):
    """Check 8c's warm batched screen (checks._front._dominated_in_batch) finds every point of the tighter front
    dominated, as the cold solves do; a point at half its F_turn (below the optimum) is not screened and is
    counted as not dominated by the cold solves."""
    import dataclasses
    from types import SimpleNamespace

    from designer.studies import checks
    from designer.studies.checks import _front as checks_front

    pareto.pareto_front(problem, points=9)
    tighter = pareto.pareto_front(problem.replace(target_speed=problem.target_speed * 1.1), points=7)
    points = list(tighter.points)
    assert len(points) == 7
    assert checks_front._dominated_in_batch(problem, points, 1e-7) == set(range(7))
    assert checks.dominated_by_problem(problem, tighter) == (0, 7)
    cheaper = dataclasses.replace(points[3], turning_effort=points[3].turning_effort * 0.5)
    mixed = SimpleNamespace(points=points[:3] + [cheaper])
    assert checks_front._dominated_in_batch(problem, mixed.points, 1e-7) == {0, 1, 2}
    assert checks.dominated_by_problem(problem, mixed) == (1, 4)
    batch = checks_front._dominated_in_batch
    cold = lambda *args, warm=True, skip=None: batch(*args, warm=False, skip=skip) if not warm else set()  # noqa: E731
    monkeypatch.setattr(checks_front, "_dominated_in_batch", cold)  # the cold solves alone
    assert checks.dominated_by_problem(problem, tighter) == (0, 7)
    assert checks.dominated_by_problem(problem, mixed) == (1, 4)


# ----------------------------------------------------------------------------------------------------
# CasterNLP.solve_many: the batch is an MX map of the one-block NLP; every block reaches its own NLP's optimum.
from pathlib import Path


from designer.solvers.nlp import CasterNLP

INDOOR = Path(__file__).resolve().parents[2] / "problems" / "indoor-manual.toml"


def test_batched_blocks_equal_single_solves():
    """Six ε-constraint NLPs solved in two 4-block chunks (4, then 2 padded with a copy) give, block by block, the
    optimum of the single solve from the same start: F_turn within 1e-9 relative, P within its cap and V_c >= V_req
    (the diameter is not compared: F_turn does not depend on it, the optimum is flat in d)."""
    problem = load_problem(INDOOR)
    nlp = CasterNLP(problem)
    p_lo = nlp.objectives(problem.upper())[1]
    p_hi = nlp.objectives(problem.lower())[1]
    caps = np.linspace(p_lo, p_hi, 8)[1:-1] if p_hi > p_lo else np.linspace(p_hi, p_lo, 8)[1:-1]
    start = problem.upper()
    batch = nlp.solve_many([start] * len(caps), (1.0, 0.0), caps)
    assert len(batch) == 6 and all(r.success for r in batch)
    for r, cap in zip(batch, caps):
        single = nlp.solve(start, (1.0, 0.0), cap)
        assert single.success
        f_batch, p_batch = nlp.objectives(r.design)[:2]
        f_single = nlp.objectives(single.design)[0]
        assert abs(f_batch - f_single) <= 1e-9 * f_single
        assert p_batch <= cap * (1 + 1e-7)
        assert nlp.objectives(r.design)[2] >= problem.required_speed * (1 - 1e-7)  # V_c (F_turn is flat in d)
    assert (4, False) in nlp._batch and (16, False) not in nlp._batch  # chunks of 4: 4 + 2 (padded)


def test_expanded_batches_give_the_same_front(monkeypatch):
    """CasterNLP.EXPAND (the studio's build): the batches are SX functions, not MX maps, and the risk-bounded
    front of the indoor problem is the map's to 1e-9 relative in F_turn, P and every design variable (1e-12 m
    absolute for a groove at its bound of 0): both reach the optimum to IPOPT's tolerance (1e-10)."""
    problem = load_problem(INDOOR)
    fronts, kinds = [], []
    for expand in (False, True):
        S.SHARED.clear()
        monkeypatch.setattr(CasterNLP, "EXPAND", expand)
        fronts.append(pareto.pareto_front(problem, knee=False))
        batches = S.shared_nlp(problem)._batch
        kinds.append({built[0].oracle().class_name() for key, built in batches.items() if isinstance(key[0], int)})
    S.SHARED.clear()
    assert kinds == [{"MXFunction"}, {"SXFunction"}]
    mapped, expanded = fronts
    assert len(mapped.points) == len(expanded.points) >= 10
    for a, b in zip(mapped.points, expanded.points):
        assert b.turning_effort == pytest.approx(a.turning_effort, rel=1e-9)
        assert b.threshold_force == pytest.approx(a.threshold_force, rel=1e-9)
        np.testing.assert_allclose(b.design.as_array(), a.design.as_array(), rtol=1e-9, atol=1e-12)


def test_solver_output_never_reaches_the_terminal(capfd):
    """Issue 24.4: a model that evaluates to NaN (a risk bound with α = 1e-300, which the loader now refuses,
    built here directly) made CasADi print 115 "NaN detected" lines on the terminal. Every IPOPT solver is
    built with the QUIET options: the vmax search and a weighted solve run, and nothing reaches file
    descriptors 1 or 2 (captured at the descriptor, where C++ writes)."""
    import dataclasses

    base = load_problem(Path(__file__).parents[2] / "problems" / "indoor-manual-robust.toml")
    nan_risk = dataclasses.replace(base.risk, probability=1e-300)
    problem = dataclasses.replace(base, conditions=base.conditions.replace(uncertainty=nan_risk))
    N.max_critical_speed(problem)
    nlp = N.CasterNLP(problem)
    nlp.solve(problem.lower().as_array(), (1.0, 1.0))
    out, err = capfd.readouterr()
    assert "NaN detected" not in out + err and "Ipopt" not in out + err
    assert out == "" and err == ""
