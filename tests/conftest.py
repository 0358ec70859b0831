"""Shared fixtures: the shipped problems and a quiet warning filter."""

from __future__ import annotations

import fcntl
import os
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PROBLEMS = sorted((ROOT / "problems").glob("*.toml"))

HEAVY = """name = "heavy-carpet-pivot"
title = "Heavy load on carpet, pivot turning, small damper"
[conditions]
load = "700 N"
threshold_height = "0.5 in"
surface = "carpet"
turning_mode = "pivot"
[shimmy]
target_speed = "3.5 m/s"
[variables]
trail = { min = "1 in", max = "2.5 in" }
diameter = { min = "3 in", max = "8 in" }
groove = { min = "0 in", max = "0.75 in" }
damping = { min = "1.3 N*m/rad", max = "1.5 N*m/rad" }
[robust]
enabled = false
"""
"""A heavy caster on carpet in pivot mode with a small damper: the closed form's "damping at its maximum, groove
from Eq. 7" candidate is needed here (tests/solvers/test_closed_form.py, tests/studies/test_checks.py)."""


@pytest.fixture(autouse=True)
def _quiet_extrapolation():
    """The Table 1 power-law extrapolation warning is tested on its own; silence it elsewhere."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="inertia power law used at")
        yield


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "alone: loads the whole machine; under pytest-xdist no other test runs meanwhile"
    )


@pytest.fixture(autouse=True)
def _alone_under_xdist(request, tmp_path_factory):
    """Under pytest-xdist a test marked ``alone`` runs while no other test does (a readers-writer lock in the
    run's shared temporary folder: every test holds it shared, an ``alone`` test exclusive; a gate stops new
    tests from starting while an ``alone`` test waits).  Plain pytest runs one test at a time: no lock."""
    if "PYTEST_XDIST_WORKER" not in os.environ:
        yield
        return
    folder = tmp_path_factory.getbasetemp().parent  # pytest-N, shared by the run's workers (popen-gw0, ...)
    alone = request.node.get_closest_marker("alone") is not None
    with open(folder / "alone.gate", "a") as gate, open(folder / "alone.lock", "a") as lock:
        fcntl.flock(gate, fcntl.LOCK_EX)
        fcntl.flock(lock, fcntl.LOCK_EX if alone else fcntl.LOCK_SH)
        if not alone:
            fcntl.flock(gate, fcntl.LOCK_UN)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
            if alone:
                fcntl.flock(gate, fcntl.LOCK_UN)
