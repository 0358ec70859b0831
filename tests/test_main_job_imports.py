"""The main job's compute loads none of the heavy libraries issue 13 names (cvxpy, scipy.stats, optuna)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HEAVY = ("cvxpy", "scipy.stats", "optuna", "pint", "matplotlib")


def test_report_data_of_the_default_problem_loads_no_heavy_library():
    """``report_data`` of the default problem (front, tighter front, recommendation, knock-safe speeds, optimum,
    checks) runs without importing cvxpy, scipy.stats, optuna, pint or matplotlib: the GP cross-check is
    opt-in, normal quantiles come from scipy.special, the default risk-bound fit and Sobol sample are stored,
    "2.5 in" is read without pint, and matplotlib waits for the figures.  (scipy.optimize does load: the
    knock-safe speeds find their event times with its brentq.)"""
    code = (
        "import sys, warnings; warnings.simplefilter('ignore')\n"
        "from designer.problem import load_problem\n"
        "from designer.pipeline import report_data\n"
        "data = report_data(load_problem('problems/indoor-manual.toml'))\n"
        "assert data.knock_safe and data.knock_safe[0]['knock_safe_speed'] > 0 and data.front.points\n"
        f"print(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY!r} or m in {HEAVY!r}))\n"
        "print(sorted(m for m in sys.modules if m.startswith('scipy.stats')))\n"
    )
    root = Path(__file__).resolve().parents[1]
    out = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True, check=True)
    heavy, stats = out.stdout.strip().splitlines()[-2:]
    assert heavy == "[]"
    assert stats == "[]"
