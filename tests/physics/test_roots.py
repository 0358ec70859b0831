"""The bracketed root finder (designer/physics/roots.py) against scipy's brentq, the field's reference."""

from __future__ import annotations

import math

import pytest

from designer.physics import bracketed_root
from designer.physics.roots import EPS

CASES = [
    (lambda x: x**3 - 2 * x - 5, 2.0, 3.0),  # Wallis's cubic
    (lambda x: math.cos(x) - x, 0.0, 1.0),
    (lambda x: math.exp(x) - 10.0, 0.0, 5.0),
    (lambda x: (x - 1.5) ** 5, 0.0, 3.0),  # a fifth-order root: flat, regula falsi's hard case
    (lambda x: math.tanh(50 * (x - 0.77)), 0.0, 1.0),  # a steep step
    (lambda x: 1e6 * math.atan(x - 0.3), 10.0, -10.0),  # ends in the other order, large values
    (lambda x: x - 1e-9, -1.0, 1.0),  # a root near zero: the absolute tolerance decides
]


@pytest.mark.parametrize("case", range(len(CASES)))
def test_same_root_as_brentq(case):
    """The root agrees with scipy.optimize.brentq's to the tolerance asked of both (xtol 1e-14, rtol 4 eps)."""
    from scipy.optimize import brentq  # the reference: loaded by this test only

    f, a, b = CASES[case]
    ours = bracketed_root(f, a, b, xtol=1e-14, rtol=4 * EPS)
    theirs = brentq(f, min(a, b), max(a, b), xtol=1e-14, rtol=4 * EPS)
    assert abs(ours - theirs) <= 2 * (1e-14 + 4 * EPS * abs(theirs))


def test_converges_in_few_steps():
    """Regula falsi with the Illinois rule is superlinear: the cubic's root in at most 15 evaluations."""
    calls = []

    def f(x):
        calls.append(x)
        return x**3 - 2 * x - 5

    assert bracketed_root(f, 2.0, 3.0) == pytest.approx(2.0945514815423265, abs=1e-12)
    assert len(calls) <= 15


def test_exact_zero_at_an_end_is_returned():
    """A bracket end where f is exactly zero is the root, without iterating."""
    assert bracketed_root(lambda x: x - 2.0, 2.0, 5.0) == 2.0
    assert bracketed_root(lambda x: x - 5.0, 2.0, 5.0) == 5.0


def test_no_sign_change_is_an_error():
    """Ends of the same sign: ValueError naming both values; a non-finite end too."""
    with pytest.raises(ValueError, match="sign change"):
        bracketed_root(lambda x: x * x + 1.0, -1.0, 1.0)
    with pytest.raises(ValueError, match="finite"):
        bracketed_root(lambda x: x, -math.inf, 1.0)


def test_too_few_steps_is_an_error():
    """A tolerance not reached within maxiter evaluations raises instead of returning a rough value."""
    with pytest.raises(RuntimeError, match="no root within tolerance after 3 steps"):
        bracketed_root(lambda x: math.cos(x) - x, 0.0, 1.0, xtol=0.0, rtol=4 * EPS, maxiter=3)


def test_bracketed_roots_take_the_scalar_steps():
    """The batched finder returns, row by row, the scalar finder's root on every case at once (each row its own
    Illinois steps: the same iterates, so the same end to rounding), and evaluates only the rows still searching."""
    import numpy as np

    from designer.physics.roots import bracketed_roots

    seen_rows = []

    def f(x, rows):
        seen_rows.append(len(rows))
        return np.array([CASES[r][0](float(v)) for v, r in zip(x, rows)])

    a = np.array([c[1] for c in CASES])
    b = np.array([c[2] for c in CASES])
    batched = bracketed_roots(f, a, b, xtol=1e-14, rtol=4 * EPS)
    for k, (g, lo, hi) in enumerate(CASES):
        assert batched[k] == pytest.approx(bracketed_root(g, lo, hi, xtol=1e-14, rtol=4 * EPS), abs=1e-15, rel=4 * EPS)
    assert seen_rows[0] == len(CASES) and min(seen_rows) < len(CASES)  # rows that converged stop being evaluated


def test_bracketed_roots_refuse_a_bracket_without_a_sign_change():
    """A row whose ends have the same sign is an error naming its ends, as for the scalar finder."""
    import numpy as np

    from designer.physics.roots import bracketed_roots

    with pytest.raises(ValueError, match="must hold a sign change"):
        bracketed_roots(lambda x, rows: x**2 - 4, np.array([0.0, 3.0]), np.array([3.0, 5.0]))
