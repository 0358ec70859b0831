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
    """A variable fixed by equal bounds keeps the closed form applicable and stays at its value on every front
    design."""
    base = _problem("powered-chair")
    b = base.bounds[fixed]
    value = {"groove": b.low, "damping": b.high, "trail": 0.5 * (b.low + b.high), "diameter": 0.2}[fixed]
    problem = base.replace(bounds={**base.bounds, fixed: dataclasses.replace(b, low=value, high=value)})
    assert structured.applicable(problem)
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    p_hi = evaluate_many(problem, np.array([[lo[0], lo[1], lo[2], lo[3]], [lo[0], hi[1], lo[2], lo[3]]]))[
        "threshold_force"
    ]
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
    """An ε below the least sill force, ε <= 0 and an unreachable target speed give infeasible points (and no
    front ends), not designs."""
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
    """Catalog problems and a risk bound whose quantile factor G varies fast with the friction share (the
    fixed points of the curve's box edges would not contract) have no closed form: the NLP sweep runs."""
    assert structured.applicable(load_problem("problems/indoor-manual-robust.toml"))
    assert structured.applicable(load_problem("problems/indoor-manual.toml"))  # risk-bounded by default
    assert not structured.applicable(_problem("catalog-retrofit"))
    wild = _with_scatter(load_problem("problems/indoor-manual.toml"), damping=2.0, slip_coefficient=2.0)
    assert not structured.applicable(wild)
    with pytest.raises(ValueError):
        structured.structured_front_designs(wild, [100.0])
    assert pareto.pareto_front(wild, 5).meta["strategy"] == "nlp"


@pytest.mark.parametrize("name", NAMES)
def test_ends(fronts, name):
    """Closed-form ends equal the NLP-only front's ends (F and P to 1e-8)."""
    problem, slow, _ = fronts[name]
    a, b = structured.structured_ends(problem)
    v = evaluate_many(problem, np.array([a, b]))
    f = slow.objectives()
    assert np.allclose([v["turning_effort"][0], v["threshold_force"][1]], [f[0, 0], f[-1, 1]], rtol=1e-8)
    assert np.allclose([v["threshold_force"][0], v["turning_effort"][1]], [f[0, 1], f[-1, 0]], rtol=1e-7)


# --------------------------------------------------------------------------- the risk-bounded closed form


def _with_scatter(problem, **scatter):
    """``problem`` with its risk bound's scatter changed (:class:`~designer.physics.uncertainty.Uncertainty`)."""
    u = dataclasses.replace(problem.risk, **scatter)
    return problem.replace(conditions=problem.conditions.replace(uncertainty=u))


@pytest.fixture(scope="module")
def risk_fronts():
    out = {}
    for name in NAMES:
        p = load_problem(f"problems/{name}.toml")  # risk-bounded by default (α = 5 %, Student-t ν = 5)
        out[name] = (p, pareto.pareto_front(p, strategy="nlp"), pareto.pareto_front(p))
    return out


@pytest.mark.parametrize("name", NAMES)
def test_risk_closed_form_matches_nlp_front(risk_fronts, name):
    """At every ε of the NLP-only risk-bounded front the closed form is feasible (V_q = V_req to 1e-12 or
    above, P <= ε), never worse than the NLP by more than its tolerance (1e-9) and equal to it to 1e-6."""
    problem, slow, _ = risk_fronts[name]
    assert problem.risk is not None and structured.applicable(problem)
    eps = np.array([p.epsilon for p in slow.points])
    x, ok = structured.structured_front_designs(problem, np.minimum(eps, 1e8))
    assert ok.all()
    values = evaluate_many(problem, x)
    assert np.all(values["design_speed"] >= problem.required_speed * (1 - 1e-12))
    assert np.all(values["threshold_force"] <= np.minimum(eps, 1e8) * (1 + 1e-12))
    assert np.all(problem.lower().as_array() <= x) and np.all(x <= problem.upper().as_array())
    f_slow = slow.objectives()[:, 0]
    rel = (values["turning_effort"] - f_slow) / f_slow
    assert np.all(rel <= 1e-9)
    assert np.all(rel >= -1e-6)


@pytest.mark.parametrize("name", NAMES)
def test_risk_fast_front_is_the_closed_form(risk_fronts, name):
    """The risk-bounded front of ``pareto_front`` (structured strategy) is made of NLP optima equal to the
    closed form at their ε (1e-8); no point of the NLP-only front dominates one of its points (beyond 1e-9),
    and the two hypervolumes agree to 1e-5 (the re-spaced ε differ where the NLP sweep missed an optimum)."""
    problem, slow, fast = risk_fronts[name]
    assert fast.meta["strategy"] == "structured" and slow.meta["strategy"] == "nlp"
    assert len(fast) == len(slow) and not fast.failed
    eps = np.array([p.epsilon for p in fast.points])
    x, ok = structured.structured_front_designs(problem, np.minimum(eps, 1e8))
    assert ok.all()
    assert np.allclose(fast.objectives()[:, 0], _f(problem, x), rtol=1e-8, atol=0)
    f_fast, f_slow = fast.objectives(), slow.objectives()
    for q in f_fast:
        assert not np.any((f_slow[:, 0] < q[0] * (1 - 1e-9)) & (f_slow[:, 1] <= q[1] * (1 + 1e-12)))
    ideal, nadir = slow.ideal_nadir()
    assert fast.hypervolume(ideal=ideal, nadir=nadir) == pytest.approx(
        slow.hypervolume(ideal=ideal, nadir=nadir), rel=1e-5
    )
    assert fast.meta["nlp_solves"] < slow.meta["nlp_solves"]


def test_risk_bound_is_a_share_dependent_target():
    """The risk bound is V_c² >= V_req² G(s), G depending on the friction share s of V_c² (so not one tightened
    target) unless σ_c = σ_K = 0: then G is constant and the risk-bounded optima are the nominal closed form
    at V_target × √G, to 1e-12."""
    base = load_problem("problems/indoor-manual.toml")
    share = np.linspace(0, 1, 5)
    g = structured.log_gain(base.risk, share)
    assert np.ptp(g) > 1e-3
    flat = _with_scatter(base, damping=0.0, slip_coefficient=0.0)
    g_flat = structured.log_gain(flat.risk, share)
    assert np.ptp(g_flat) < 1e-12
    tightened = base.nominal().replace(target_speed=base.target_speed * float(np.exp(g_flat[0] / 2)))
    lo, hi = base.lower().as_array(), base.upper().as_array()
    p_range = evaluate_many(base, np.array([lo, hi]))["threshold_force"]
    eps = np.linspace(p_range[1], p_range[0], 8)[1:-1]
    x_risk, ok_risk = structured.structured_front_designs(flat, eps)
    x_nom, ok_nom = structured.structured_front_designs(tightened, eps)
    assert ok_risk.any() and np.array_equal(ok_risk, ok_nom)
    assert np.allclose(_f(flat, x_risk[ok_risk]), _f(tightened, x_nom[ok_nom]), rtol=1e-12, atol=0)


@pytest.mark.parametrize(
    "scatter",
    [
        dict(damping=0.3, slip_coefficient=0.05, probability=0.01, model_error_dof=0),
        dict(damping=0.05, slip_coefficient=0.4, inertia=0.2, probability=0.2),
    ],
)
def test_risk_closed_form_other_scatter(scatter):
    """Other scatters (damper-heavy, groove-heavy uncertainty; normal model error; α 1 % and 20 %): the closed
    form equals the best of several direct NLP solves at five ε (1e-6), never worse by more than 1e-9."""
    problem = _with_scatter(load_problem("problems/sports-court.toml"), **scatter)
    assert structured.applicable(problem)
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    p_range = evaluate_many(problem, np.array([lo, hi]))["threshold_force"]
    eps = np.linspace(p_range[1], p_range[0], 7)[1:-1]
    x, ok = structured.structured_front_designs(problem, eps)
    for e, xi, oki in zip(eps, x, ok):
        ref = _nlp_best(problem, float(e), xi)
        if not oki:
            assert ref == np.inf
            continue
        f = float(_f(problem, xi)[0])
        assert f <= ref * (1 + 1e-9) and f == pytest.approx(ref, rel=1e-6)


def test_stored_sobol_sample_is_scipys():
    """The default design sample read from designer/data (no scipy.stats import) is scipy's scrambled Sobol
    sample, seed 0, bit for bit; other sizes and seeds come from scipy itself."""
    from scipy.stats import qmc

    from designer.solvers.nlp import sample_designs

    problem = _problem("indoor-manual")
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    assert np.array_equal(sample_designs(problem), lo + qmc.Sobol(d=4, scramble=True, seed=0).random(1024) * (hi - lo))
    assert np.array_equal(
        sample_designs(problem, 16, seed=1), lo + qmc.Sobol(d=4, scramble=True, seed=1).random(16) * (hi - lo)
    )
