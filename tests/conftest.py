"""Shared fixtures: the shipped problems and a quiet warning filter."""

from __future__ import annotations

import fcntl
import os
import warnings
from pathlib import Path

import pytest

from designer.errors import InertiaExtrapolationWarning

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


def first_order_probability(trail, inertia, groove, damping, slip_coefficient, speed, law, diameter=None):
    """P(log V_c + X < log speed), X the first-order law of log V_c,true − log V_c (the model error; the inertia, a
    Student-t for a wheel known by its ``diameter``, else normal; c_f and K_s through Eq. 7's elasticities): the
    probability the deterministic bound controls, α at V_q (the reference of the quantile fit's tests)."""
    import math

    from designer.physics import uncertainty as U
    from designer.physics._sums import SumDistribution
    from designer.physics.scatter import inertia_prediction

    x = (trail, inertia, groove, damping, slip_coefficient)
    terms = [(law.model_error, law.model_error_dof)]
    if diameter is not None:
        terms.append((U.inertia_log_scale(*x, diameter), inertia_prediction().dof))
    rest = U.rest_log_std(*x, law, measured=diameter is None)
    gap = math.log(speed) - math.log(float(U.critical_shimmy_speed(*x)))
    return float(SumDistribution(terms, rest).cdf(gap))


@pytest.fixture(autouse=True)
def _quiet_extrapolation():
    """The Table 1 power-law extrapolation warning is tested on its own; silence it elsewhere."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaExtrapolationWarning)
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


SLOWEST_FIRST = (
    "studies/explore/test_postgres.py",  # `alone`: the other workers wait while it runs, so it runs first
    "cli/test_safe_output.py",
    "test_benchmarks.py",
    "studies/explore/test_explore.py",
    "test_quality.py",
    "studies/fleet/test_fleet.py",
    "studio/test_studio_browser.py",
    "cli/test_cli.py",
    "cli/test_hardening.py",
    "notebook/test_notebook.py",
    "docs/test_docs_build.py",
)
"""The modules that take longest (``pytest --durations``; benchmarks/results.md), slowest first.  Under
pytest-xdist they are handed out first, so the run does not end with one worker finishing a long module while
the others wait; a module missing here only runs in its usual place."""


def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist (a worker's collection), the modules of :data:`SLOWEST_FIRST` first, in that order; the
    rest as collected.  Every worker sorts alike, as xdist requires; a plain run keeps the usual order."""
    if "PYTEST_XDIST_WORKER" not in os.environ:
        return
    tests = Path(__file__).resolve().parent

    def rank(item) -> int:
        try:
            module = item.path.resolve().relative_to(tests).as_posix()
        except ValueError:
            return len(SLOWEST_FIRST)
        return SLOWEST_FIRST.index(module) if module in SLOWEST_FIRST else len(SLOWEST_FIRST)

    items.sort(key=rank)


@pytest.fixture
def browser():
    """A function ``width -> Selenium driver`` of Debian's headless Chromium with a viewport ``width`` CSS px
    wide (narrower than Chromium's smallest window: its device emulation, as its phone preview); every driver
    opened is closed after the test.  Skipped without Selenium, chromium or chromedriver."""
    import shutil

    webdriver = pytest.importorskip("selenium.webdriver")
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    driver_path = shutil.which("chromedriver")
    if not (chromium and driver_path):
        pytest.skip("needs Debian's chromium and chromium-driver")
    opened = []

    def open_at(width: int, height: int = 900):
        options = webdriver.ChromeOptions()
        options.binary_location = chromium
        for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu"):
            options.add_argument(arg)
        options.add_argument(f"--window-size={max(width, 500)},{height}")
        driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(driver_path))
        opened.append(driver)
        driver.execute_cdp_cmd(
            "Emulation.setDeviceMetricsOverride",
            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": width < 500},
        )
        return driver

    yield open_at
    for driver in opened:
        driver.quit()
