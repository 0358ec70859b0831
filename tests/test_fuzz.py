"""Property-based fuzzing (hypothesis) of the physics and of problem files.

The default budget keeps the whole file well under 30 s; set ``FUZZ_EXAMPLES=5000`` for a long run.
Physics: no NaN/inf for valid inputs, the monotonicity claims of docs/checks.md#6-monotonicity everywhere in range,
CasADi and NumPy agreeing.  Problem files: random valid files load and either solve or raise a
:class:`~designer.errors.DesignerError`; random invalid files never raise anything else.
"""

from __future__ import annotations

import math
import os
import warnings

import casadi as ca

from designer.physics import enable_casadi

enable_casadi()  # NumPy mode: the physics functions build CasADi expressions here, without the solvers
import numpy as np
import pytest
import tomllib
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from designer.data.paper import INCH
from designer.errors import DesignerError, InfeasibleError
from designer.model import Conditions, performance
from designer.physics.inertia import PowerLaw
from designer.physics.shimmy import critical_shimmy_speed, critical_speed_terms
from designer.physics.threshold import threshold_force_ratio
from designer.physics.turning import turning_effort
from designer.parameters import MODEL_RANGE
from designer.problem import SCHEMA, problem_from_dict, problem_from_toml

EXAMPLES = int(os.environ.get("FUZZ_EXAMPLES", "60"))
"""Examples per property (default small; FUZZ_EXAMPLES=5000 for the long run)."""
SOLVE_EXAMPLES = max(3, EXAMPLES // 20)
"""Problem files actually solved (each solve takes ~0.1–1 s)."""

FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=os.environ.get("FUZZ_EXAMPLES") is None,
)


def real(low, high):
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


# valid ranges of the design variables and fixed parameters (SI)
trail = real(1e-3, MODEL_RANGE["trail"][1])
diameter = real(0.02, MODEL_RANGE["diameter"][1])
groove = st.one_of(st.just(0.0), real(1e-6, MODEL_RANGE["groove"][1]))  # below a micron is a plain tread
damping = st.one_of(st.just(0.0), real(1e-3, MODEL_RANGE["damping"][1]))  # problems require >= 1e-3 (bare fork)
inertia = real(1e-6, 1.0)
slip = real(10.0, 1e5)
load = real(1.0, 1e4)
height = real(1e-3, 0.05)
REL = 1 + 1e-3  # a step that is surely larger than rounding


@FUZZ
@given(trail, inertia, groove, damping, slip)
def test_critical_speed_finite_and_monotone(t, i_w, b, c_f, k_s):
    """Eq. 7: V_c finite and positive; it rises with T, c_f and B and falls with I_w (docs/checks.md#6-monotonicity)."""
    v = critical_shimmy_speed(t, i_w, b, c_f, k_s)
    assert math.isfinite(v) and v >= 0
    assume(v > 0)
    friction, grooved = critical_speed_terms(t, i_w, b, c_f, k_s)
    assert critical_shimmy_speed(t * REL, i_w, b, c_f, k_s) > v
    assert critical_shimmy_speed(t, i_w * REL, b, c_f, k_s) < v
    # weakly everywhere; strictly where the term is not lost in rounding (> 1e-9 of V_c²)
    for bigger, share in (
        (critical_shimmy_speed(t, i_w, b, c_f * REL, k_s), friction),
        (critical_shimmy_speed(t, i_w, b * REL, c_f, k_s), grooved),
    ):
        assert bigger >= v
        if share > 1e-9 * (friction + grooved):
            assert bigger > v


@FUZZ
@given(trail, diameter, groove, damping)
def test_critical_speed_falls_with_diameter(t, d, b, c_f):
    """With I_w(d) from the Table 1 power law, V_c falls as the wheel grows (docs/checks.md#6-monotonicity)."""
    assume(b > 0 or c_f > 0)
    model = PowerLaw()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        v1 = critical_shimmy_speed(t, model(d), b, c_f)
        v2 = critical_shimmy_speed(t, model(d * REL), b, c_f)
    assert math.isfinite(v1) and math.isfinite(v2) and v2 < v1


@FUZZ
@given(height, real(2.0 + 1e-6, 1e3))
def test_threshold_ratio_finite_and_falls_with_diameter(h, ratio):
    """Eq. 4A: P/L finite and positive for d/h > 2, and falling with d."""
    d = h * ratio
    p = threshold_force_ratio(d, h)
    assert math.isfinite(p) and p > 0
    assert threshold_force_ratio(d * REL, h) < p


@FUZZ
@given(trail, groove, damping, load, st.sampled_from(["tile", "carpet"]), st.sampled_from(["chair", "pivot"]))
def test_turning_effort_monotone(t, b, c_f, l, surface, mode):
    """F_turn finite and positive; falls with T, rises with B and with added damping c_f > c_0 (docs/model.md#turning-effort)."""
    c_f = max(c_f, 1.3)
    f = turning_effort(t, b, c_f, l, surface, mode)
    assert math.isfinite(f) and f > 0
    assert turning_effort(t * REL, b, c_f, l, surface, mode) < f
    assert turning_effort(t, b + 1e-4, c_f, l, surface, mode) > f
    assert turning_effort(t, b, c_f * REL, l, surface, mode) > f


_SYM = ca.SX.sym("x", 4)
_CONDITIONS = Conditions()
_PERF = performance(_SYM[0], _SYM[1], _SYM[2], _SYM[3], _CONDITIONS)
_CASADI = ca.Function("perf", [_SYM], [ca.vertcat(*_PERF.values())])


@FUZZ
@given(trail, real(0.03, 0.6), groove, real(1.3, 100.0))
def test_casadi_and_numpy_agree(t, d, b, c_f):
    """The one set of formulas gives the same numbers on floats, NumPy arrays and CasADi symbols."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        floats = performance(t, d, b, c_f, _CONDITIONS)
        arrays = performance(np.array([t, t]), np.array([d, d]), np.array([b, b]), np.array([c_f, c_f]), _CONDITIONS)
    symbolic = np.asarray(_CASADI([t, d, b, c_f])).ravel()
    for k, (key, value) in enumerate(floats.items()):
        assert math.isfinite(float(value)), key
        assert float(symbolic[k]) == pytest.approx(float(value), rel=1e-12, abs=1e-300), key
        assert np.allclose(np.asarray(arrays[key]), float(value), rtol=1e-12, atol=0), key


# --------------------------------------------------------------------------- problem files


def length_text(metres):
    """A length as SI number, inches or millimetres string."""
    return st.sampled_from([metres, f"{metres / INCH:.6g} in", f"{metres * 1000:.6g} mm"])


@st.composite
def valid_problem(draw):
    """A random problem inside the documented ranges (it may be infeasible)."""
    h = draw(real(0.005, 0.02))
    d_lo = draw(real(2.2 * h, 0.25))
    d_hi = draw(real(d_lo, 0.3))
    t_lo = draw(real(0.01, 0.05))
    t_hi = draw(st.one_of(st.just(t_lo), real(t_lo * 1.01, 0.1)))  # fixed, or a range wider than rounding
    b_hi = draw(real(0.0, 0.03))
    c_hi = draw(real(1.3, 10.0))
    data = {
        "name": draw(st.from_regex(r"\A[a-z0-9][a-z0-9_.-]{0,20}\Z")),
        "title": draw(st.text(max_size=40)),
        "conditions": {
            "load": draw(st.sampled_from([draw(real(50, 1500)), "178 N", "40 lbf"])),
            "threshold_height": draw(length_text(h)),
            "surface": draw(st.sampled_from(["tile", "carpet"])),
            "turning_mode": draw(st.sampled_from(["chair", "pivot"])),
        },
        "shimmy": {
            "target_speed": draw(st.sampled_from([draw(real(0.5, 6.0)), "2.5 m/s", "5 mph"])),
            "margin": draw(real(0.0, 0.5)),
        },
        "variables": {
            "trail": draw(length_text(t_lo))
            if t_hi == t_lo
            else {"min": draw(length_text(t_lo)), "max": draw(length_text(t_hi))},
            "diameter": {"min": d_lo, "max": d_hi},
            "groove": draw(st.sampled_from([{"min": 0.0, "max": b_hi}, b_hi])),
            "damping": {"min": 1.3, "max": c_hi},
        },
        "objective": {"turning_effort": draw(real(0.0, 10.0)), "threshold_force": draw(real(0.1, 10.0))},
    }
    if draw(st.booleans()):
        data["constraints"] = {"swept_radius_max": t_hi + d_hi / 2 + draw(real(0.0, 0.05))}
    return data


def _within(values, low, high):
    return all(low <= v <= high for v in values)


@settings(
    max_examples=SOLVE_EXAMPLES,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=os.environ.get("FUZZ_EXAMPLES") is None,
)
@given(valid_problem())
def test_valid_problems_solve_or_raise_designer_error(data):
    """A random valid problem loads and its optimum is feasible and finite, or a DesignerError says why."""
    from designer.studies.optimum import optimise

    problem = problem_from_dict(data)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            solution = optimise(problem, cross_check=False, samples=128)
    except InfeasibleError as exc:
        assert "\n" not in str(exc) and exc.best["critical_speed"] < problem.required_speed
        return
    except DesignerError as exc:
        assert "\n" not in str(exc)
        return
    assert all(math.isfinite(v) for v in solution.objectives.values())
    assert solution.critical_speed >= problem.required_speed * (1 - 1e-6)
    x = solution.design
    for var in ("trail", "diameter", "groove", "damping"):
        b = problem.bounds[var]
        assert b.low - 1e-9 <= getattr(x, var) <= b.high + 1e-9


@FUZZ
@given(valid_problem())
def test_valid_problems_load(data):
    """Every random valid problem loads (the ranges of the generator are inside the documented ones)."""
    problem = problem_from_dict(data)
    assert problem.bounds["diameter"].low > 2 * problem.conditions.threshold_height


SECTIONS = [s for s in SCHEMA if s]
KEYS = sorted({k for s in SCHEMA.values() for k in s})
UNITS = [
    "in",
    "mm",
    "m",
    "N",
    "lbf",
    "kg",
    "deg",
    "rad",
    "m/s",
    "mph",
    "N*m/rad",
    "kg*m**2",
    "%",
    "furlong",
    "s",
    "J",
    "1/m",
    "kg/m**3",
    "",
    "**",
    "^2",
    "(",
    ")",
    "[1,2]",
    "e999",
    "**9**9",
    "/0",
]


def weird_number():
    return st.one_of(st.floats(), st.integers(-(10**30), 10**30), st.integers(-10, 10).map(lambda e: 10.0 ** (30 * e)))


def weird_value():
    scalar = st.one_of(
        weird_number(),
        st.booleans(),
        st.text(max_size=12),
        st.builds(lambda n, u: f"{n} {u}", weird_number(), st.sampled_from(UNITS)),
        st.builds(lambda n, u: f"{n}{u}", st.integers(-5, 500), st.sampled_from(UNITS)),
    )
    return st.recursive(
        scalar,
        lambda inner: st.one_of(
            st.lists(inner, max_size=3), st.dictionaries(st.sampled_from(["min", "max", "x"]), inner, max_size=3)
        ),
        max_leaves=6,
    )


@st.composite
def invalid_problem(draw):
    """A valid problem with random keys, types and unit strings planted in it."""
    data = draw(valid_problem())
    for _ in range(draw(st.integers(1, 4))):
        where = draw(st.sampled_from(["top", "section", "new"]))
        key = draw(st.one_of(st.sampled_from(KEYS), st.text(min_size=1, max_size=8)))
        value = draw(weird_value())
        if where == "top":
            data[draw(st.sampled_from(["name", "title", "description"] + SECTIONS + [key]))] = value
        elif where == "section":
            section = draw(st.sampled_from(SECTIONS))
            table = data.get(section)
            if not isinstance(table, dict):
                table = data[section] = {}
            table[draw(st.one_of(st.sampled_from(sorted(SCHEMA[section])), st.just(key)))] = value
        else:
            data[draw(st.sampled_from(SECTIONS))] = {key: value}
    return data


@FUZZ
@given(invalid_problem())
def test_invalid_problems_raise_only_designer_errors(data):
    """Random keys, types and unit strings never raise anything but the tool's own one-line errors,
    and whatever loads has finite values inside the model's ranges."""
    try:
        problem = problem_from_dict(data)
    except DesignerError as exc:
        assert "\n" not in str(exc)
        return
    values = [
        problem.target_speed,
        problem.conditions.load,
        problem.conditions.threshold_height,
        *problem.weights,
        *(x for b in problem.bounds.values() for x in (b.low, b.high)),
    ]
    assert all(math.isfinite(v) for v in values)
    for var, b in problem.bounds.items():
        assert _within((b.low, b.high), MODEL_RANGE[var][0], MODEL_RANGE[var][1])


@FUZZ
@given(st.text(max_size=300))
def test_random_toml_text(text):
    """Any text as a problem file: a Problem or a ProblemError, never another exception."""
    try:
        problem_from_toml(text)
    except DesignerError as exc:
        assert "\n" not in str(exc)


@FUZZ
@given(
    st.lists(
        st.sampled_from(
            [
                'name = "t"',
                "[shimmy]",
                "target_speed = 2.5",
                "[variables]",
                "[conditions]",
                "trail = ",
                "load = ",
                '"2 in"',
                "1e400",
                "[1, 2]",
                "{min = 1, max = 2}",
                "true",
                '"10**10**10 N"',
                "[objective]",
                "turning_effort = 0",
                "[pareto]",
                "points = ",
                "nan",
                "inf",
                "-1",
                '"x"',
                "\n",
                "=",
                "[inertia]",
                'model = "catalog"',
                'wheels = ["Z"]',
                "[robust]",
                "samples = ",
            ]
        ),
        max_size=25,
    )
)
def test_random_toml_fragments(parts):
    """Problem files glued from plausible fragments load or fail with a ProblemError only."""
    text = "\n".join(parts)
    try:
        tomllib.loads(text)
    except Exception:
        pass
    try:
        problem_from_toml(text)
    except DesignerError as exc:
        assert "\n" not in str(exc)
