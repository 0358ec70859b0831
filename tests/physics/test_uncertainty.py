"""The risk bound: Student-t model error, the exact t-plus-normal quantile, and the Monte Carlo of the same law."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtri, stdtrit

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
    p, se = U.shimmy_probability_mc(t, i, b, c, 1250.0, v_q, u, samples=200_000, seed=4242)
    assert se <= 0.001
    assert p <= u.probability + 2 * se
    assert U.shimmy_probability_first_order(t, i, b, c, 1250.0, v_q, u) == pytest.approx(0.05, abs=1e-5)


def test_reported_monte_carlo_reaches_its_standard_error():
    """samples is a minimum: a 50 % design gets more draws until SE <= 0.1 percentage point; same seed, same p."""
    u = U.Uncertainty(samples=1000)
    t, i, b, c = 0.0508, 2.0e-3, 0.0143, 1.3
    v = float(U.critical_shimmy_speed(t, i, b, c, 1250.0))
    p, se = U.shimmy_probability_mc(t, i, b, c, 1250.0, v, u)
    assert 0.4 < p < 0.6 and se <= 0.001
    assert U.shimmy_probability_mc(t, i, b, c, 1250.0, v, u) == (p, se)


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
    assert (0.05, 5, U._NODES, U._DEGREE) in U._STORED_FITS
    np.testing.assert_allclose(stored, computed, rtol=0, atol=1e-13)
    assert shift == pytest.approx(computed_shift, abs=1e-13)
    other, _ = U._fit(0.1, 5)
    assert abs(other[0] - stored[0]) > 0.1  # the 90 % quantile is lower than the 95 %
    np.testing.assert_array_equal(other, U._compute_fit(0.1, 5)[0])
