"""designer.physics._roots.brentq takes scipy.optimize.brentq's steps: the same roots to the bit."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from scipy.optimize import brentq as scipy_brentq

from designer.analysis.limit_cycles import dynamics, knock_safe_speed
from designer.model import Conditions, Design
from designer.physics import shimmy
from designer.physics._roots import EPS, brentq


def _same(x: float, y: float) -> bool:
    return x == y and math.copysign(1.0, x) == math.copysign(1.0, y)


def test_brentq_equals_scipy_to_the_bit_on_random_functions():
    """On 2,000 random bracketed functions and three tolerance settings the root is scipy's, bit for bit."""
    rng = random.Random(7)
    compared = 0
    for _ in range(2000):
        a0, a1, a2, a3 = (rng.uniform(-2, 2) for _ in range(4))
        k = rng.choice([1, 3, 5])

        def f(x, a0=a0, a1=a1, a2=a2, a3=a3, k=k):
            return a0 + a1 * x + a2 * math.sin(k * x) + a3 * x**3

        if f(-3.0) * f(3.0) >= 0:
            continue
        for xtol, rtol in ((1e-16, 4 * EPS), (2e-12, 1e-10), (1e-6, 1e-6)):
            ours = brentq(f, -3.0, 3.0, xtol=xtol, rtol=rtol, maxiter=200)
            theirs = scipy_brentq(f, -3.0, 3.0, xtol=xtol, rtol=rtol, maxiter=200)
            assert _same(ours, theirs), (a0, a1, a2, a3, k, xtol, rtol, ours, theirs)
            compared += 1
    assert compared > 1000


def test_brentq_given_end_values_and_errors():
    """fa/fb passed in give the same root; an exact zero at an end is returned; same-sign ends, NaN and too
    small tolerances raise as scipy does; no convergence raises RuntimeError."""

    def f(x):
        return x**3 - 2.0

    root = brentq(f, 0.0, 2.0, xtol=1e-16, rtol=4 * EPS)
    assert root == scipy_brentq(f, 0.0, 2.0, xtol=1e-16, rtol=4 * EPS)
    assert brentq(f, 0.0, 2.0, xtol=1e-16, rtol=4 * EPS, fa=f(0.0), fb=f(2.0)) == root
    assert abs(root - 2 ** (1 / 3)) < 1e-15
    assert brentq(lambda x: x - 1.0, 1.0, 3.0) == 1.0
    with pytest.raises(ValueError, match="different signs"):
        brentq(f, 2.0, 3.0)
    with pytest.raises(ValueError, match="NaN"):
        brentq(lambda x: math.nan if x > 0.5 else -1.0, 0.0, 1.0, fb=1.0)
    with pytest.raises(ValueError, match="rtol too small"):
        brentq(f, 0.0, 2.0, rtol=EPS)
    with pytest.raises(RuntimeError, match="converge"):
        brentq(f, 0.0, 2.0, xtol=1e-16, rtol=4 * EPS, maxiter=2)


def test_knock_event_roots_equal_scipy(monkeypatch):
    """Every Brent root of two knocks simulated at their onset (decaying, then sustained 1 % faster) equals scipy's root of the
    same event function (about 90 of them), so the knock verdicts and knock-safe speeds are unchanged."""
    pairs = []
    ours = dynamics.brentq

    def spy(f, a, b, **kw):
        x = ours(f, a, b, **kw)
        pairs.append((x, scipy_brentq(f, a, b, xtol=kw["xtol"], rtol=kw["rtol"], maxiter=kw["maxiter"])))
        return x

    design = Design(trail=0.04, diameter=0.125, groove=0.004, damping=0.5)
    onset = knock_safe_speed(design, Conditions(), angle=0.35)
    monkeypatch.setattr(dynamics, "brentq", spy)
    sys = dynamics.caster_dynamics(design, Conditions(), 1.0)
    verdicts = [dynamics.simulate_knock(sys.at(v), 0.35, exact=True).shimmy for v in (onset, onset * 1.01)]
    assert verdicts == [False, True]
    assert len(pairs) > 50
    assert all(_same(x, y) for x, y in pairs)


def test_routh_hurwitz_speed_equals_scipy_root():
    """Check 6's Routh–Hurwitz critical speed is the root scipy's brentq finds on the same margin function."""
    t, i, b, c = 0.05, 6e-4, 0.004, 0.5
    ours = shimmy.routh_hurwitz_critical_speed(t, i, b, c, "friction")

    def margin(speed):
        c_d = shimmy.friction_damping_at_speed(c, t, speed)
        return float(shimmy.routh_hurwitz_margin(shimmy.third_order_coefficients(t, i, b, c_d, speed)))

    assert ours == scipy_brentq(margin, 1e-3, 1e3, xtol=1e-12, rtol=1e-12, maxiter=500)
    assert np.isfinite(ours) and ours > 0


def test_report_data_of_the_default_problem_loads_no_scipy():
    """The main job's compute (front, tighter front, recommendation, knock-safe speeds, optimum, checks) runs
    without importing scipy: Brent's roots are designer.physics._roots and the default risk-bound fit is stored
    (scipy.optimize and scipy.special cost about 0.35 and 0.3 s of CPU to import)."""
    import subprocess
    import sys
    from pathlib import Path

    code = (
        "import sys, warnings; warnings.simplefilter('ignore')\n"
        "from designer.problem import load_problem\n"
        "from designer.pipeline import report_data\n"
        "data = report_data(load_problem('problems/indoor-manual.toml'))\n"
        "assert data.knock_safe and data.knock_safe[0]['knock_safe_speed'] > 0 and data.front.points\n"
        "print(sorted(m for m in sys.modules if m == 'scipy' or m.startswith('scipy.')))\n"
    )
    root = Path(__file__).resolve().parents[1]
    out = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "[]"
