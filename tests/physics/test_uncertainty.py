"""The risk bound: Student-t model error, the exact t-plus-normal quantile, and the Monte Carlo of the same law."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtri, stdtrit

from conftest import first_order_probability
from designer.physics import uncertainty as U


def test_quantile_fit_never_below_exact_and_within_2e5():
    """On 401 shares s ∈ [0, 1] the fitted Q/√(σ_m²+σ_r²) is >= the quadrature quantile and within 2e-5 of it;
    the ends are the t_5 and the normal quantiles."""
    u = U.Uncertainty()
    s = np.linspace(0, 0.999, 401)
    exact = U.exact_sum_quantile(s, 0.05, 5)
    fitted = np.array([float(U.log_speed_quantile(np.sqrt(1 - x), np.sqrt(x), u)) for x in s])
    assert np.all(fitted >= exact - 1e-12)
    assert np.max(fitted - exact) < 2e-5
    assert exact[0] == pytest.approx(stdtrit(5, 0.95), rel=1e-9)
    assert float(U.log_speed_quantile(0.0, 1.0, u)) == pytest.approx(ndtri(0.95), rel=1e-12)


def test_exact_quantile_matches_sampling():
    """The quadrature quantile of √(1−s) t_5 + √s Z equals the empirical 95 % quantile of 2e6 draws (±0.01)."""
    rng = np.random.default_rng(7)
    t, z = rng.standard_t(5, 2_000_000), rng.normal(size=2_000_000)
    for s in (0.2, 0.5, 0.8):
        empirical = np.quantile(np.sqrt(1 - s) * t + np.sqrt(s) * z, 0.95)
        assert U.exact_sum_quantile([s], 0.05, 5)[0] == pytest.approx(empirical, abs=0.01)


def test_root_sum_square_is_not_conservative():
    """Why the exact quantile: the root-sum-square of the t and normal quantiles is below it at s = 0.7."""
    rss = np.sqrt(0.3 * stdtrit(5, 0.95) ** 2 + 0.7 * ndtri(0.95) ** 2)
    assert rss < U.exact_sum_quantile([0.7], 0.05, 5)[0] * (1 - 0.005)


@pytest.mark.parametrize("design", [(0.0508, 2.0e-3, 0.0143, 1.3), (0.0635, 0.4e-3, 0.0, 3.0), (0.04, 1e-3, 0.01, 2.0)])
def test_monte_carlo_at_the_bound_is_at_most_alpha(design):
    """At V_req = V_q(x) (the bound just active) the Monte Carlo of the same law (t_5 model error, lognormal
    constants) gives P(shimmy) <= α + 2 SE: the first-order bound is conservative; with its own seed."""
    t, i, b, c = design
    u = U.Uncertainty()
    v_q = float(U.shimmy_speed_quantile(t, i, b, c, 1250.0, u))
    p, se = _mc(t, i, b, c, 1250.0, v_q, u, samples=200_000, seed=4242)
    assert se <= 0.001
    assert p <= u.probability + 2 * se
    assert first_order_probability(t, i, b, c, 1250.0, v_q, u) == pytest.approx(0.05, abs=1e-5)


def test_reported_monte_carlo_reaches_its_standard_error():
    """samples is a minimum: a 50 % design gets more draws until SE <= 0.1 percentage point; same seed, same p."""
    u = U.Uncertainty(samples=1000)
    t, i, b, c = 0.0508, 2.0e-3, 0.0143, 1.3
    v = float(U.critical_shimmy_speed(t, i, b, c, 1250.0))
    p, se = _mc(t, i, b, c, 1250.0, v, u)
    assert 0.4 < p < 0.6 and se <= 0.001
    assert _mc(t, i, b, c, 1250.0, v, u) == (p, se)


def test_casadi_bound_equals_numeric():
    """V_q written once: a CasADi evaluation equals the NumPy one."""
    import casadi as ca

    x = ca.SX.sym("x", 4)
    u = U.Uncertainty()
    f = ca.Function("q", [x], [U.shimmy_speed_quantile(x[0], x[1], x[2], x[3], 1250.0, u)])
    args = (0.05, 1.5e-3, 0.01, 2.0)
    assert float(f(args)) == pytest.approx(float(U.shimmy_speed_quantile(*args, 1250.0, u)), rel=1e-12)


def test_stored_fit_is_the_computed_fit():
    """The stored Chebyshev fit of the default α = 0.05, ν = 5 is what the quadrature computes (coefficients and
    shift within 1e-13; bit for bit on the reference machine), so reading it changes no number; other α or ν
    are computed (and differ from it)."""
    stored, shift = U._fit(0.05, 5)
    computed, computed_shift = U._compute_fit(0.05, 5)
    assert (0.05, 5, U._NODES, U._DEGREE) in U.STORED_SUM_FITS
    np.testing.assert_allclose(stored, computed, rtol=0, atol=1e-13)
    assert shift == pytest.approx(computed_shift, abs=1e-13)
    other, _ = U._fit(0.1, 5)
    assert abs(other[0] - stored[0]) > 0.1  # the 90 % quantile is lower than the 95 %
    np.testing.assert_array_equal(other, U._compute_fit(0.1, 5)[0])


# --------------------------------------------------------------------------- the data law (issue 26)

INCH = 0.0254


def _default_recommendation():
    """The issue's default recommendation: 7 in wheel, 1/2 in groove, 2.5 in trail, bare fork, K_s 1250 N."""
    from designer.physics.inertia import power_law_inertia

    d = 7 * INCH
    return 2.5 * INCH, float(power_law_inertia(d)), 0.5 * INCH, 1.3, 1250.0, d


def test_sum_distribution_ends_and_sampling():
    """The characteristic-function inversion gives the t_5, t_4 and normal CDFs and quantiles to 1e-11, is
    unchanged (1e-11) with twice the nodes, and its 95 % quantile of 0.6 t_5 + 0.6 t_5 + 0.52 Z matches the
    empirical quantile of 2e6 draws (±0.01)."""
    from scipy.special import ndtr, stdtr

    from designer.physics._sums import SumDistribution

    for dof in (4, 5):
        d = SumDistribution([(1.0, dof)])
        x = np.linspace(-6, 6, 13)
        np.testing.assert_allclose(d.cdf(x), stdtr(dof, x), atol=1e-11)
        assert float(d.quantile(0.95)) == pytest.approx(stdtrit(dof, 0.95), abs=1e-11)
    np.testing.assert_allclose(
        SumDistribution([], 1.0).cdf(np.array([-2.0, 0.3, 1.7])), ndtr([-2.0, 0.3, 1.7]), atol=1e-11
    )
    a, b, c = np.array([0.6, 0.1]), np.array([0.6, 0.9]), np.array([0.52, 0.02])
    fine = SumDistribution([(a, 5), (b, 5)], c, nodes=1024)
    np.testing.assert_allclose(SumDistribution([(a, 5), (b, 5)], c).quantile(0.95), fine.quantile(0.95), atol=1e-11)
    rng = np.random.default_rng(5)
    t1, t2, z = rng.standard_t(5, 2_000_000), rng.standard_t(5, 2_000_000), rng.normal(size=2_000_000)
    assert float(fine.quantile(0.95)[0]) == pytest.approx(np.quantile(0.6 * t1 + 0.6 * t2 + 0.52 * z, 0.95), abs=0.01)


def test_two_t_quantile_is_above_the_single_t_of_the_same_scale():
    """Why a 2-D fit: the 95 % quantile of (t_5 + t_5)/√2 is 2.057, 2.1 % above t_5's 2.015, so folding the
    inertia's t into the model error's (one t of scale √(σ_m² + σ_I²)) would not be conservative."""
    q = float(U.exact_pair_quantile(0.5, 0.0, 0.05, 5, 5))
    assert q == pytest.approx(2.0575, abs=1e-3)
    assert q > stdtrit(5, 0.95) * 1.02


def test_pair_quantile_fit_never_below_exact():
    """On 2000 random shares (u, r) and the corners, the 2-D fit of law_quantile is >= the inversion quantile
    and within 3e-5 of it (relative to √(σ_m² + σ_I² + σ_r²))."""
    u = U.data_law()
    rng = np.random.default_rng(3)
    uu = np.concatenate([rng.random(2000) * 0.999, [0.0, 0.0, 0.5, 0.999]])
    rr = np.concatenate([rng.random(2000) * 0.9999, [0.0, 0.9999, 0.0, 0.0]])
    sm = 0.3
    pair = sm**2 / (1 - uu)
    total = pair / (1 - rr)
    q = U.law_quantile(sm, np.sqrt(pair * uu), np.sqrt(total * rr), u)
    excess = (q - U.exact_pair_quantile(uu, rr, 0.05, 5, 5) * np.sqrt(total)) / np.sqrt(total)
    assert excess.min() >= 0 and excess.max() < 3e-5


def test_stored_pair_fit_is_the_computed_fit():
    """The stored 2-D fit of α = 0.05, ν = (5, 5) is what _compute_fit computes (1e-12), so reading it changes no
    number; its shift (the largest fit error) is below 3e-5."""
    stored, shift = U._fit(0.05, 5, 5)
    computed, computed_shift = U._compute_fit(0.05, 5, 5)
    np.testing.assert_allclose(stored, computed, rtol=0, atol=1e-12)
    assert shift == pytest.approx(computed_shift, abs=1e-12) and 0 < shift < 3e-5


def test_default_recommendation_risk_under_the_data_law():
    """Issue 26's numbers, by quadrature of the exact law: the default recommendation (7 in, 1/2 in groove,
    2.5 in trail, bare fork) has 12.7 % risk at 2.5 m/s for any 7 in wheel, 2.7 % for a wheel measured at the
    power law's value (σ 0.05); the data law's Monte Carlo agrees within 3 SE."""
    t, i, b, c, k, d = _default_recommendation()
    law = U.data_law()
    p_any = U.shimmy_probability_exact(t, i, b, c, k, 2.5, law, diameter=d)
    p_measured = U.shimmy_probability_exact(t, i, b, c, k, 2.5, law)
    assert p_any == pytest.approx(0.127, abs=5e-4)
    assert p_measured == pytest.approx(0.027, abs=5e-4)
    p, se = U.shimmy_probability_mc_many(t, i, b, c, k, 2.5, law, diameter=d, samples=400_000, seed=99)
    assert abs(float(p) - p_any) < 3 * float(se)
    p, se = U.shimmy_probability_mc_many(t, i, b, c, k, 2.5, law, samples=400_000, seed=99)
    assert abs(float(p) - p_measured) < 3 * float(se)


def _box(n, seed):
    """n designs in the box T 1–3 in, d 3–8 in, B 0–0.75 in (a fifth at B = 0), c_f 1.3–6 N·m/rad."""
    from designer.physics.inertia import power_law_inertia

    rng = np.random.default_rng(seed)
    t, d = rng.uniform(1, 3, n) * INCH, rng.uniform(3, 8, n) * INCH
    b, c = rng.uniform(0, 0.75, n) * INCH, rng.uniform(1.3, 6, n)
    b[: n // 5] = 0.0
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return t, d, b, c, np.asarray(power_law_inertia(d))


@pytest.mark.parametrize("measured", [False, True])
def test_bound_is_conservative_by_quadrature_over_the_design_box(measured):
    """At V_req = V_q(x) (the bound just active) the exact law's P(shimmy) by quadrature is <= α on 60 designs of
    the box, for a wheel known by its diameter (two Student-t terms) and a measured one; it is at least
    α − 0.005 (the bound is not loose: the first-order law is exact for the model error and I_w)."""
    law = U.data_law()
    t, d, b, c, i = _box(60, 17)
    worst, least = 0.0, 1.0
    for k in range(60):
        kw = {} if measured else {"diameter": d[k]}
        v_q = float(U.shimmy_speed_quantile(t[k], i[k], b[k], c[k], 1250.0, law, **kw))
        p = U.shimmy_probability_exact(t[k], i[k], b[k], c[k], 1250.0, v_q, law, **kw)
        worst, least = max(worst, p), min(least, p)
    assert worst <= law.probability
    assert least >= law.probability - 0.005


@pytest.mark.parametrize("k", [0, 1, 2])
def test_bound_is_conservative_by_monte_carlo(k):
    """At V_req = V_q(x) for a wheel known by its diameter, the data law's Monte Carlo (400 000 draws, its own
    seed) gives P <= α + 2 SE, and agrees with the quadrature within 3 SE."""
    law = U.data_law()
    t, d, b, c, i = _box(40, 23)
    j = [25, 31, 37][k]  # three grooved designs
    v_q = float(U.shimmy_speed_quantile(t[j], i[j], b[j], c[j], 1250.0, law, diameter=d[j]))
    p, se = U.shimmy_probability_mc_many(
        t[j], i[j], b[j], c[j], 1250.0, v_q, law, diameter=d[j], samples=400_000, seed=7
    )
    assert float(p) <= law.probability + 2 * float(se)
    exact = U.shimmy_probability_exact(t[j], i[j], b[j], c[j], 1250.0, v_q, law, diameter=d[j])
    assert abs(float(p) - exact) < 3 * float(se)


def test_first_order_probability_controls_the_bound():
    """With a wheel known by its diameter the first-order law gives exactly α (1e-5, the fit's shift) at V_q, and
    it is above the exact law (conservative in c_f, K_s by convexity)."""
    t, i, b, c, k, d = _default_recommendation()
    law = U.data_law()
    v_q = float(U.shimmy_speed_quantile(t, i, b, c, k, law, diameter=d))
    assert first_order_probability(t, i, b, c, k, v_q, law, diameter=d) == pytest.approx(0.05, abs=1e-5)
    assert U.shimmy_probability_exact(t, i, b, c, k, v_q, law, diameter=d) < 0.05


def test_casadi_bound_with_a_symbolic_diameter_equals_numeric():
    """V_q of a wheel known by its diameter, written once: CasADi (d symbolic in I_w = C dⁿ and in the
    prediction scale) equals NumPy to 1e-12."""
    import casadi as ca

    from designer.physics import enable_casadi
    from designer.physics.inertia import power_law_inertia

    enable_casadi()
    x = ca.SX.sym("x", 4)
    law = U.data_law()
    expr = U.shimmy_speed_quantile(x[0], power_law_inertia(x[1]), x[2], x[3], 1250.0, law, diameter=x[1])
    f = ca.Function("q", [x], [expr])
    t, d, b, c = 0.05, 0.16, 0.01, 2.0
    numeric = float(U.shimmy_speed_quantile(t, float(power_law_inertia(d)), b, c, 1250.0, law, diameter=d))
    assert float(f([t, d, b, c])) == pytest.approx(numeric, rel=1e-12)


def test_monte_carlo_many_equals_each_caster_alone():
    """The batched sampler gives each caster the estimate it gets alone (same seed, same blocks), whatever else is
    evaluated beside it, with several speeds per caster and a mix of measured and predicted wheels; samples
    are whole blocks of 10 000; a high-risk caster is topped up until SE <= 0.1 pp."""
    law = U.data_law(samples=20_000)
    t, d, b, c, i = _box(6, 29)
    measured = np.array([True, False, True, False, False, True])
    speeds = np.stack([np.full(6, 1.0), np.full(6, 2.0)], axis=-1)
    p, se = U.shimmy_probability_mc_many(t, i, b, c, 1250.0, speeds, law, diameter=d, measured=measured, seed=3)
    assert p.shape == (6, 2)
    for j in range(6):
        kw = {} if measured[j] else {"diameter": d[j]}
        for s in range(2):
            alone = U.shimmy_probability_mc_many(t[j], i[j], b[j], c[j], 1250.0, speeds[j, s], law, seed=3, **kw)
            assert (float(alone[0]), float(alone[1])) == (p[j, s], se[j, s])
    assert np.all(se <= 0.001)
    p1, _ = U.shimmy_probability_mc_many(
        t[0], i[0], b[0], c[0], 1250.0, 1.0, law, samples=15_000, seed=3, target_se=None
    )
    p2, _ = U.shimmy_probability_mc_many(
        t[0], i[0], b[0], c[0], 1250.0, 1.0, law, samples=20_000, seed=3, target_se=None
    )
    assert float(p1) == float(p2)


def test_risk_record_shares_by_hand():
    """The risk record of the default recommendation: P ± SE by the data law's Monte Carlo (SE <= 0.1 pp, within
    3 SE of the quadrature's 12.7 %); sources in order model error, wheel inertia (diameter only), M_f/θ0,
    K_s with their kinds; shares by hand: variances 0.10751² × 5/3, (½ × 0.3647)² × 5/3, (e_c 0.10)²,
    (e_K 0.20)² with e_c + e_K = ½ the elasticities of Eq. 7; they add up to 1 and the inertia dominates."""
    from designer.physics.shimmy import critical_speed_log_sensitivities

    t, i, b, c, k, d = _default_recommendation()
    law = U.data_law()
    r = U.risk_record(t, i, b, c, k, 2.5, law, diameter=d)
    assert set(r) == {"probability", "se", "sources", "dominant"}
    assert r["se"] <= 0.001 and abs(r["probability"] - 0.1267) < 3 * r["se"]
    names = [s["name"] for s in r["sources"]]
    assert names == ["model error", "wheel inertia (diameter only)", "M_f/θ0", "K_s"]
    assert [s["kind"] for s in r["sources"]] == ["data", "data", "assumed", "assumed"]
    e = critical_speed_log_sensitivities(t, i, b, c, k)
    parts = [
        0.10751150**2 * 5 / 3,
        (0.5 * 0.36469278) ** 2 * 5 / 3,
        (float(e["damping"]) * 0.10) ** 2,
        (float(e["slip_coefficient"]) * 0.20) ** 2,
    ]
    shares = [x / sum(parts) for x in parts]
    assert [s["share"] for s in r["sources"]] == pytest.approx(shares, rel=1e-6)
    assert sum(s["share"] for s in r["sources"]) == pytest.approx(1.0, abs=1e-12)
    assert r["sources"][1]["scale"] == pytest.approx(0.3647, abs=5e-5) and r["sources"][1]["dof"] == 5
    assert r["dominant"].startswith("The inertia of a wheel known by its diameter only")
    assert f"{100 * shares[1]:.0f} % of the variance of log V_c" in r["dominant"]


def test_risk_record_of_a_measured_wheel_without_groove():
    """A measured wheel at B = 0: its inertia source is 'measured' (normal, σ 0.05) and K_s has no share (its
    elasticity is zero); the model error dominates."""
    law = U.data_law()
    r = U.risk_record(0.0508, 1.25e-3, 0.0, 1.3, 1250.0, 1.5, law)
    by = {s["name"]: s for s in r["sources"]}
    assert by["wheel inertia (measured)"]["kind"] == "measured" and by["wheel inertia (measured)"]["scale"] == 0.05
    assert by["K_s"]["share"] == 0.0
    assert r["dominant"].startswith("Eq. 7's own error against Table 1 dominates the risk")


def test_data_law_is_the_default():
    """data_law() is the default Uncertainty: model error 0.10751 on 5 dof (Table 1), measured inertia 0.05,
    M_f/θ0 0.10, K_s 0.20; changes replace fields."""
    law = U.data_law(probability=0.1)
    assert (law.model_error, law.model_error_dof) == (pytest.approx(0.10751, abs=5e-6), 5)
    assert (law.inertia, law.damping, law.slip_coefficient, law.probability) == (0.05, 0.10, 0.20, 0.1)
    assert U.data_law() == U.Uncertainty()


def _mc(*args, **kwargs) -> tuple[float, float]:
    """The model's Monte Carlo P(shimmy) and SE of one caster, as floats."""
    from designer.model import shimmy_probability

    p, se = shimmy_probability(*args, **kwargs)
    return float(p), float(se)


def test_quantile_fit_evaluation_is_the_same_for_floats_arrays_and_casadi():
    """The 2-D fit of the risk bound's quantile is one polynomial, evaluated three ways: plain-Python Clenshaw
    for two floats, the Chebyshev terms summed in C for arrays, the symbolic columns and recurrence for CasADi; all
    agree with NumPy's chebval2d to rounding (1e-14) at 200 random points of [-1, 1]²."""
    import casadi as ca
    from numpy.polynomial import chebyshev as cheb

    from designer.physics import uncertainty as U

    coef, _ = U._fit(0.05, 5, 5)
    rng = np.random.default_rng(7)
    x, y = rng.uniform(-1, 1, (2, 200))
    reference = cheb.chebval2d(x, y, coef)
    floats = np.array([U._clenshaw(coef, float(a), float(b)) for a, b in zip(x, y)])
    arrays = U._clenshaw(coef, x, y)
    sx, sy = ca.SX.sym("x"), ca.SX.sym("y")
    symbolic = ca.Function("q", [sx, sy], [U._clenshaw(coef, sx, sy)])
    casadi = np.array([float(symbolic(a, b)) for a, b in zip(x, y)])
    for got in (floats, arrays, casadi):
        assert np.max(np.abs(got - reference)) <= 1e-14 * np.max(np.abs(reference))


def test_quantile_fit_arrays_as_accurate_as_chebval2d_and_symbols_cheap_to_differentiate():
    """The arrays' evaluation of the 2-D quantile fit errs by at most 3e-16 relative (an 80-bit reference at 20000
    points, ends included; NumPy's chebval2d: 2.6e-16), whatever the array's shape; the symbolic one's Hessian in
    (x, y) takes under 2000 CasADi operations (nested Clenshaw recurrences took 3710): the risk NLP's cost."""
    import casadi as ca
    from numpy.polynomial import chebyshev as cheb

    from designer.physics import uncertainty as U

    coef, _ = U._fit(0.05, 5, 5)
    x, y = np.random.default_rng(3).uniform(-1, 1, (2, 20000))
    x[:100], y[100:200] = 1.0, -1.0
    exact = cheb.chebval2d(x.astype(np.longdouble), y.astype(np.longdouble), np.asarray(coef, np.longdouble))
    got = U._clenshaw(coef, x, y)
    assert np.max(np.abs(got - exact) / np.abs(exact)) <= 3e-16
    assert np.array_equal(U._clenshaw(coef, x[:60].reshape(3, 4, 5), y[:60].reshape(3, 4, 5)).ravel(), got[:60])
    sx, sy = ca.SX.sym("x"), ca.SX.sym("y")
    hessian = ca.hessian(U._clenshaw(coef, sx, sy), ca.vertcat(sx, sy))[0]
    assert ca.Function("h", [sx, sy], [hessian]).n_instructions() < 2000


def _blocks(seed, dof, n):
    """n blocks of draws as the Monte Carlo defined them before the stream was kept: default_rng(seed), one block
    after another."""
    rng = np.random.default_rng(seed)
    return [U.law_draws(U.Uncertainty(model_error_dof=dof), rng, 5) for _ in range(n)]


def test_the_kept_draw_stream_is_the_seeded_stream():
    """The Monte Carlo's kept stream gives, block for block, the draws of default_rng(seed) drawn one block after
    another: the kept blocks and those after them, on a first and a second reading, from four threads reading at
    once, and after a reading interrupted half-way through a block (Ctrl-C in a notebook) left the stream where it
    was.  Each reader gets its own dict of read-only arrays."""
    import itertools
    import threading

    seed, dof, n = 987_654, 5, U._KEPT_BLOCKS + 4
    want = _blocks(seed, dof, n)

    def same(got):
        return all(np.array_equal(a[key], b[key]) for a, b in zip(want, got, strict=True) for key in a)

    U._draw_stream.cache_clear()
    stream = U._draw_stream(seed, dof, 5)
    calls = {"n": 0}
    original = U.law_draws

    def interrupted(u, rng, inertia_dof):
        calls["n"] += 1
        if calls["n"] == 3:  # the third block: one variate drawn, then Ctrl-C
            rng.standard_normal(10)
            raise KeyboardInterrupt
        return original(u, rng, inertia_dof)

    U.law_draws = interrupted
    try:
        with pytest.raises(KeyboardInterrupt):
            list(itertools.islice(stream, n))
    finally:
        U.law_draws = original
    assert same(list(itertools.islice(stream, n)))
    assert same(list(itertools.islice(stream, n)))
    U._draw_stream.cache_clear()
    stream = U._draw_stream(seed, dof, 5)
    results = [None] * 4
    barrier = threading.Barrier(4)

    def read(i):
        barrier.wait()
        results[i] = list(itertools.islice(stream, n))

    threads = [threading.Thread(target=read, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(same(r) for r in results)
    first = next(iter(stream))
    first["model"] = None
    with pytest.raises(ValueError):
        next(iter(stream))["slip"][0] = 1.0
    assert next(iter(stream))["model"] is not None
