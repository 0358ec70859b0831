"""Closed-form ε-optima (designer.solvers.structured) against the NLP front and the NLP itself."""
import dataclasses
import warnings

import numpy as np
import pytest

from designer.analysis import pareto
from designer.model import VARIABLES, Design
from designer.problem import load_problem
from designer.solvers import structured
from designer.solvers.nlp import CasterNLP, best_starts, evaluate_many

warnings.filterwarnings("ignore", message="inertia power law used at")
NAMES = ["indoor-manual", "sports-court", "powered-chair"]


def _problem(name):
    """The shipped problem without its risk bound: the closed form is for the nominal Eq. 7 constraint."""
    return load_problem(f"problems/{name}.toml").nominal()


@pytest.fixture(scope="module")
def fronts():
    out = {}
    for name in NAMES:
        p = _problem(name)
        slow = pareto.pareto_front(p, 101, strategy="nlp")
        fast = pareto.pareto_front(p, 101)
        out[name] = (p, slow, fast)
    return out


def _f(problem, x):
    return evaluate_many(problem, np.asarray(x, float).reshape(-1, 4))["turning_effort"]


@pytest.mark.parametrize("name", NAMES)
def test_closed_form_matches_nlp_front(fronts, name):
    """At every ε of the NLP-only front the closed form is never worse, and equal to 1e-8 except where the
    NLP front missed the damper (a short segment next to the bare-fork end, where the NLP stays on the
    groove local optimum): there the closed form is strictly better."""
    problem, slow, _ = fronts[name]
    eps = np.array([p.epsilon for p in slow.points])
    x, ok = structured.structured_front_designs(problem, np.minimum(eps, 1e8))
    assert ok.all()
    f_slow = slow.objectives()[:, 0]
    f_cf = _f(problem, x)
    rel = (f_cf - f_slow) / f_slow
    assert np.all(rel <= 1e-8)
    worse = np.flatnonzero(rel < -1e-8)
    assert len(worse) <= 2
    for i in worse:
        assert pareto.family_of(problem, slow.points[i].design) in ("groove", "groove+damper")
        assert pareto.family_of(problem, Design.from_array(x[i])) == "damper"
    # same threshold force: the diameter is the smallest one meeting the cap
    p_cf = evaluate_many(problem, x)["threshold_force"]
    assert np.allclose(p_cf, slow.objectives()[:, 1], rtol=1e-7)


@pytest.mark.parametrize("name", NAMES)
def test_fast_front_is_the_closed_form(fronts, name):
    """The fast path's points (NLP-confirmed) equal the closed form at their ε, and the front is at least as
    good as the NLP-only front (hypervolume on common normalisation), with the same fields."""
    problem, slow, fast = fronts[name]
    assert len(fast) == len(slow) and not fast.failed
    eps = np.array([p.epsilon for p in fast.points])
    x, ok = structured.structured_front_designs(problem, np.minimum(eps, 1e8))
    assert ok.all()
    assert np.allclose(fast.objectives()[:, 0], _f(problem, x), rtol=1e-8, atol=0)
    ideal, nadir = slow.ideal_nadir()
    assert fast.hypervolume(ideal=ideal, nadir=nadir) >= slow.hypervolume(ideal=ideal, nadir=nadir) * (1 - 1e-9)
    assert fast.points[0].multipliers.keys() == slow.points[0].multipliers.keys()
    assert fast.meta.keys() == slow.meta.keys()


def test_both_families_covered(fronts):
    """powered-chair: bare fork → damper → groove → groove+damper, in that order, on the fast front."""
    _, _, fast = fronts["powered-chair"]
    seq = [p.family for p in fast.points]
    order = [f for i, f in enumerate(seq) if i == 0 or f != seq[i - 1]]
    assert order == ["bare fork", "damper", "groove", "groove+damper"]
    assert [i for i, _ in fast.gaps() if True]  # switches reported


def _nlp_best(problem, eps, x_cf):
    """Best NLP optimum at ε from the closed form and from sample / family starts."""
    nlp = CasterNLP(problem)
    starts = [x_cf] + best_starts(problem, (1.0, 0.0), k=6, threshold_cap=eps)
    res = [r for r in (nlp.solve(s, (1.0, 0.0), eps) for s in starts) if r.success]
    return min(float(_f(problem, r.design.as_array())[0]) for r in res) if res else np.inf


@pytest.mark.parametrize("fixed", ["groove", "damping", "trail", "diameter"])
def test_fixed_variables(fixed):
    base = _problem("powered-chair")
    b = base.bounds[fixed]
    value = {"groove": b.low, "damping": b.high, "trail": 0.5 * (b.low + b.high), "diameter": 0.2}[fixed]
    problem = base.replace(bounds={**base.bounds, fixed: dataclasses.replace(b, low=value, high=value)})
    assert structured.applicable(problem)
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    p_hi = evaluate_many(problem, np.array([[lo[0], lo[1], lo[2], lo[3]], [lo[0], hi[1], lo[2], lo[3]]]))[
        "threshold_force"]
    eps = np.linspace(p_hi[1], p_hi[0], 5)
    x, ok = structured.structured_front_designs(problem, eps)
    i = list(VARIABLES).index(fixed)
    assert np.all(x[:, i] == value)
    for e, xi, oki in zip(eps, x, ok):
        ref = _nlp_best(problem, float(e), xi)
        if not oki:
            assert ref == np.inf
            continue
        assert float(_f(problem, xi)[0]) <= ref * (1 + 1e-8)
        assert float(_f(problem, xi)[0]) == pytest.approx(ref, rel=1e-6)


def test_infeasible_epsilon_and_target():
    problem = _problem("indoor-manual")
    hi = problem.upper().as_array()
    p_min = evaluate_many(problem, hi[None, :])["threshold_force"][0]
    _, ok = structured.structured_front_designs(problem, [p_min * 0.99, p_min * 1.01, 0.0, -1.0])
    assert ok.tolist() == [False, True, False, False]
    unreachable = problem.replace(target_speed=100.0)
    _, ok = structured.structured_front_designs(unreachable, np.linspace(p_min, 10 * p_min, 7))
    assert not ok.any()
    assert structured.structured_ends(unreachable) is None


def test_not_applicable():
    assert not structured.applicable(load_problem("problems/indoor-manual-robust.toml"))
    assert not structured.applicable(load_problem("problems/indoor-manual.toml"))  # risk-bounded by default
    assert not structured.applicable(_problem("catalog-retrofit"))
    with pytest.raises(ValueError):
        structured.structured_front_designs(load_problem("problems/indoor-manual-robust.toml"), [100.0])


@pytest.mark.parametrize("name", NAMES)
def test_ends(fronts, name):
    """Closed-form ends equal the NLP-only front's ends (F and P to 1e-8)."""
    problem, slow, _ = fronts[name]
    a, b = structured.structured_ends(problem)
    v = evaluate_many(problem, np.array([a, b]))
    f = slow.objectives()
    assert np.allclose([v["turning_effort"][0], v["threshold_force"][1]], [f[0, 0], f[-1, 1]], rtol=1e-8)
    assert np.allclose([v["threshold_force"][0], v["turning_effort"][1]], [f[0, 1], f[-1, 0]], rtol=1e-7)
