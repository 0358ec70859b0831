"""Issue 12.5, mutation testing, third round: the risk-bounded closed form of ``designer/solvers/structured.py``
(``log_gain``, ``_edge_shares``, ``_on_curve``, ``_risk_designs``) against independent calculations from
:mod:`designer.physics` alone: the V_c quantile ratio of real designs, the box edges of the constraint curve by
root finding, and the least F_turn at (T, d) by a brute-force search over the groove B (c_f from the risk bound
by bisection).  Fast (no IPOPT), so in the mutmut test selection (benchmarks/mutation.md)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from designer.physics.turning import TurningConstants
from designer.physics.shimmy import critical_shimmy_speed, critical_speed_terms
from designer.physics.uncertainty import shimmy_speed_quantile
from designer.problem import load_problem
from designer.solvers import structured
from designer.solvers.nlp import evaluate_many

from conftest import ROOT


def _problem(name="indoor-manual", speed=None, groove_cost=1.0, **scatter):
    """A shipped (risk-bounded) problem, its target speed, the groove's turning-moment coefficient (× groove_cost)
    and its risk bound's scatter optionally changed."""
    p = load_problem(ROOT / "problems" / f"{name}.toml")
    if groove_cost != 1.0:
        kappa = p.conditions.turning.groove_coefficient * groove_cost
        p = p.replace(conditions=p.conditions.replace(turning=TurningConstants(groove_coefficient=kappa)))
    if scatter:
        u = dataclasses.replace(p.risk, **scatter)
        p = p.replace(conditions=p.conditions.replace(uncertainty=u))
    if speed is not None:
        p = p.replace(target_speed=speed)
    return p


def _quantile(p, t, inertia, b, c):
    """V_q of designs from the physics layer directly [m/s]."""
    return shimmy_speed_quantile(t, inertia, b, c, p.conditions.slip_coefficient, p.conditions.uncertainty)


def _least_c(p, t, inertia, b):
    """The least c_f in [c_lo, c_hi] with V_q >= V_req at groove b (bisection), or inf when c_hi is not enough."""
    lo, hi = p.lower().as_array()[3], p.upper().as_array()[3]
    need = p.required_speed
    if _quantile(p, t, inertia, b, lo) >= need:
        return lo
    if _quantile(p, t, inertia, b, hi) < need:
        return np.inf
    return brentq(lambda c: _quantile(p, t, inertia, b, c) - need, lo, hi, xtol=1e-14, rtol=1e-15)


def _brute_best(p, t, d):
    """Least F_turn at (T, d) over the box in (B, c_f) under the risk bound: a 401-point grid in B, then a bounded
    scalar minimisation around the best cell (c_f the least feasible at each B).  inf when nothing is feasible."""
    lo, hi = p.lower().as_array(), p.upper().as_array()
    inertia = float(evaluate_many(p, np.array([[t, d, lo[2], lo[3]]]))["inertia"][0])

    def f(b):
        c = _least_c(p, t, inertia, b)
        if not np.isfinite(c):
            return np.inf
        return float(evaluate_many(p, np.array([[t, d, b, c]]))["turning_effort"][0])

    grid = np.linspace(lo[2], hi[2], 401)
    vals = np.array([f(b) for b in grid])
    if not np.isfinite(vals).any():
        return np.inf
    k = int(np.argmin(vals))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    res = minimize_scalar(f, bounds=(a, b), method="bounded", options=dict(xatol=1e-13))
    return min(vals[k], float(res.fun), f(lo[2]), f(hi[2]))


CASES = [  # (problem, target speed, scatter): corner, curve ends on each edge, a curve missing the box
    ("indoor-manual", 6.0, dict(groove_cost=50.0)),  # a costly groove: the far end of the curve (B_lo, c_f > c_lo) wins
    ("indoor-manual", None, {}),
    ("indoor-manual", 4.0, {}),
    ("indoor-manual", 6.0, {}),
    ("indoor-manual", 9.0, {}),
    ("indoor-manual", 6.0, dict(damping=0.3, slip_coefficient=0.05, probability=0.01, model_error_dof=0)),
    ("indoor-manual", 6.0, dict(damping=0.05, slip_coefficient=0.4, inertia=0.2, probability=0.2)),
    ("sports-court", None, {}),
    ("sports-court", None, dict(damping=0.05, slip_coefficient=0.4, inertia=0.2, probability=0.2)),
]


@pytest.mark.parametrize("name, speed, scatter", CASES)
def test_risk_designs_equal_a_brute_force_search(name, speed, scatter):
    """At five ε across the box the risk-bounded closed form is feasible exactly when a brute-force search in
    (B, c_f) at its (T, d) finds a design meeting V_q >= V_req (physics layer, bisection in c_f), its design meets
    the bound (to 1e-12) and the box, P <= ε, and its F_turn equals the search's least F_turn to 1e-8."""
    p = _problem(name, speed, **scatter)
    assert p.risk is not None and structured.applicable(p)
    lo, hi = p.lower().as_array(), p.upper().as_array()
    p_range = evaluate_many(p, np.array([lo, hi]))["threshold_force"]
    eps = np.linspace(p_range[1], p_range[0], 6)[:-1]
    x, ok = structured.structured_front_designs(p, eps)
    for e, xi, oki in zip(eps, x, ok):
        ref = _brute_best(p, xi[0], xi[1])
        assert oki == np.isfinite(ref)
        if not oki:
            continue
        v = evaluate_many(p, xi[None])
        inertia = float(v["inertia"][0])
        assert _quantile(p, xi[0], inertia, xi[2], xi[3]) >= p.required_speed * (1 - 1e-12)
        assert np.all(lo <= xi) and np.all(xi <= hi) and v["threshold_force"][0] <= e * (1 + 1e-12)
        assert float(v["turning_effort"][0]) == pytest.approx(ref, rel=1e-8)


def test_risk_design_on_the_bound_unless_at_the_corner():
    """Where the corner (B_lo, c_lo) misses the risk bound, the closed form's design lies on it: V_q = V_req to
    1e-9 (not above, which a cheaper design could exploit); where the corner meets it, the design is the corner."""
    p = _problem("indoor-manual", 6.0)
    lo, hi = p.lower().as_array(), p.upper().as_array()
    d = np.linspace(lo[1], hi[1], 9)
    x, ok = structured.designs_at_diameter(p, d)
    assert ok[:6].all()  # the larger diameters miss the bound (I_w too large): the box cannot meet it
    x, d = x[ok], d[ok]
    v = evaluate_many(p, x)
    corner = np.column_stack([x[:, 0], d, np.full(len(d), lo[2]), np.full(len(d), lo[3])])
    corner_ok = evaluate_many(p, corner)["design_speed"] >= p.required_speed
    assert corner_ok.any() and not corner_ok.all()
    assert np.array_equal(x[corner_ok], corner[corner_ok])
    assert np.allclose(v["design_speed"][~corner_ok], p.required_speed, rtol=1e-9, atol=0)


@pytest.mark.parametrize(
    "scatter",
    [
        {},
        dict(damping=0.3, slip_coefficient=0.05, probability=0.01, model_error_dof=0),
        dict(damping=0.05, slip_coefficient=0.4, inertia=0.2, probability=0.2),
    ],
)
def test_log_gain_is_the_quantile_ratio_of_real_designs(scatter):
    """log G(s) = 2 log(V_c/V_q) for real designs (T, I_w, B, c_f, K_s from the shipped problem's box) at their
    friction share s = a/(a + b) (Eq. 7 terms): computed from physics.shimmy and physics.uncertainty, to 1e-12."""
    p = _problem(**scatter)
    u, ks = p.risk, p.conditions.slip_coefficient
    rng = np.random.default_rng(3)
    t, inertia = rng.uniform(0.03, 0.07, 12), rng.uniform(5e-4, 3e-3, 12)
    b, c = rng.uniform(0.0, 0.02, 12), rng.uniform(1.3, 6.0, 12)
    b[0], c[1] = 0.0, 0.0  # the ends s = 1 and s = 0
    a_term, b_term = critical_speed_terms(t, inertia, b, c, ks)
    share = a_term / (a_term + b_term)
    direct = 2 * np.log(critical_shimmy_speed(t, inertia, b, c, ks) / shimmy_speed_quantile(t, inertia, b, c, ks, u))
    assert np.allclose(structured.log_gain(u, share), direct, rtol=1e-12, atol=1e-14)
    assert share[0] == 1.0 and share[1] == 0.0


def _edge_root(u, need, kind, k):
    """The share s where the risk-bounded curve meets one box edge, by brentq on the edge equation [-]:
    c_f edge s − k/G(s) = 0, B edge s − 1 + k/G(s) = 0 (k = a c or b B² over V_req²); clipped to [0, 1]."""
    g = lambda s: np.exp(float(structured.log_gain(u, s)))  # noqa: E731
    h = (lambda s: s - k / g(s)) if kind == "c" else (lambda s: s - 1 + k / g(s))
    if h(0.0) >= 0:
        return 0.0
    if h(1.0) <= 0:
        return 1.0
    return brentq(h, 0.0, 1.0, xtol=1e-15, rtol=1e-15)


@pytest.mark.parametrize("scatter", [{}, dict(damping=0.3, slip_coefficient=0.05, probability=0.01, model_error_dof=0)])
def test_edge_shares_are_the_roots_of_the_edge_equations(scatter):
    """The shares [s1, s2] where the risk-bounded curve enters and leaves the box equal the roots of the four edge
    equations found by brentq (s1 = max(s at c_lo, s at B_hi), s2 = min(s at c_hi, s at B_lo)) to 1e-12, for
    curves crossing the box, ending on an edge, and missing it (s1 > s2)."""
    p = _problem(**scatter)
    u = p.risk
    box = ((0.002, 1.3), (0.019, 6.0))
    a = np.array([0.5, 1.0, 2.0, 4.0, 0.05, 30.0])
    b = np.array([2e4, 1e4, 5e4, 1e5, 1e3, 1e6])
    need = 9.0
    s1, s2 = structured._edge_shares(u, need, a, b, box)
    for i in range(len(a)):
        roots = [
            _edge_root(u, need, "c", a[i] * box[0][1] / need),
            _edge_root(u, need, "c", a[i] * box[1][1] / need),
            _edge_root(u, need, "b", b[i] * box[1][0] ** 2 / need),
            _edge_root(u, need, "b", b[i] * box[0][0] ** 2 / need),
        ]
        assert s1[i] == pytest.approx(max(roots[0], roots[2]), abs=1e-12)
        assert s2[i] == pytest.approx(min(roots[1], roots[3]), abs=1e-12)
    assert np.any(s1 > s2) and np.any(s1 < s2)


@pytest.mark.parametrize("speed", [None, 6.0, 9.0])
def test_zero_design_scatter_is_the_nominal_closed_form_at_a_raised_target(speed):
    """With σ_c = σ_K = 0 the quantile factor G is constant, so the risk-bounded optima equal the nominal closed
    form at V_target·√G (the documented special case): same feasibility and designs to 1e-9 at seven ε."""
    flat = _problem("indoor-manual", speed, damping=0.0, slip_coefficient=0.0)
    g = structured.log_gain(flat.risk, np.linspace(0.0, 1.0, 5))
    assert np.ptp(g) < 1e-12 and g[0] > 0.01
    nominal = flat.nominal().replace(target_speed=flat.target_speed * float(np.exp(g[0] / 2)))
    lo, hi = flat.lower().as_array(), flat.upper().as_array()
    p_range = evaluate_many(flat, np.array([lo, hi]))["threshold_force"]
    eps = np.linspace(p_range[1], p_range[0], 9)[1:-1]
    x_risk, ok_risk = structured.structured_front_designs(flat, eps)
    x_nom, ok_nom = structured.structured_front_designs(nominal, eps)
    assert ok_risk.any() and np.array_equal(ok_risk, ok_nom)
    assert np.allclose(x_risk[ok_risk], x_nom[ok_nom], rtol=1e-9, atol=1e-12)
