"""Issue 12.5, mutation testing, second round: the closed-form ε-optima (``designer/solvers/structured.py``)
where its guards and edges decide (benchmarks/mutation.md): when the closed form applies, what an ε out of
reach gives, the trail limit reached exactly, and a slip coefficient other than the paper's."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from designer.data.paper import INCH
from designer.model import performance
from designer.physics.inertia import Fixed, PowerLaw
from designer.physics.turning import TurningConstants
from designer.problem import load_problem
from designer.solvers import structured
from designer.solvers.nlp import evaluate_many

from conftest import ROOT


@pytest.fixture(scope="module")
def indoor():
    return load_problem(ROOT / "problems" / "indoor-manual.toml").nominal()


def _with_conditions(problem, validated=True, **changes):
    """The problem with some conditions changed; ``validated=False`` skips the loader's checks (to reach the
    closed form's own guards with values the loader would refuse)."""
    conditions = problem.conditions.replace(**changes)
    if validated:
        return problem.replace(conditions=conditions)
    raw = copy.copy(problem)
    object.__setattr__(raw, "conditions", conditions)
    return raw


@pytest.mark.parametrize(
    "changes, expected",
    [
        (dict(turning=TurningConstants(groove_coefficient=0.0)), True),  # a groove that costs nothing: still monotone
        (dict(turning=TurningConstants(groove_coefficient=0.5)), True),
        (dict(slip_coefficient=1.0), True),  # the smallest K_s the loader accepts
        (dict(inertia=Fixed(1.27e-3)), True),  # I_w constant in d: non-decreasing
        (dict(inertia=PowerLaw(1e-4, -1.0)), False),  # I_w falling with d: d_lo not optimal
    ],
)
def test_applicable_on_validated_problems(indoor, changes, expected):
    """The closed form needs F_turn non-increasing in T, cost non-decreasing in B and c_f, I_w non-decreasing
    in d: a zero or small groove coefficient, K_s = 1 N and a constant I_w keep it; a falling I_w breaks it."""
    assert structured.applicable(_with_conditions(indoor, **changes)) is expected


@pytest.mark.parametrize(
    "changes",
    [
        dict(turning=TurningConstants(groove_coefficient=-1.0)),
        dict(disturbance_angle=0.0),
        dict(slip_coefficient=0.0),
        dict(load=100.0, turning=TurningConstants(bare_fork_damping=3.0)),
    ],
)
def test_applicable_guards_without_the_loader(indoor, changes):
    """The guards hold on their own, for values the loader refuses: a groove that lowers the moment, no
    disturbance, no slip stiffness, or a negative turning moment at the corner B = B_min, c_f = c_f,min (L = 100 N,
    c_0 = 3 above c_f,min = 1.3: M = 0.5·0.005·100 + (1.3 − 3)·0.349 = −0.34 N·m < 0, although it is positive at
    the other corners) each make the closed form inapplicable."""
    raw = _with_conditions(indoor, validated=False, **changes)
    assert not structured.applicable(raw)
    if "load" in changes:
        lo, hi = raw.lower().as_array(), raw.upper().as_array()
        assert performance(hi[0], hi[1], lo[2], lo[3], raw.conditions)["turning_moment"] < 0
        assert performance(hi[0], hi[1], hi[2], hi[3], raw.conditions)["turning_moment"] > 0


def test_applicable_moment_exactly_zero_is_not_positive(indoor):
    """F = M/T falls with T only for M > 0: a moment of exactly zero at the corner (0.5 × 2⁻⁷ m × 64 N = 0.25 N·m
    of sliding, (1.5 − 2.5) × 0.25 rad = −0.25 N·m of damper, both exact in binary) is not applicable."""
    from designer.problem import Bound

    raw = _with_conditions(
        indoor,
        validated=False,
        load=64.0,
        disturbance_angle=0.25,
        turning=TurningConstants(tile_moment_per_load=0.0078125, groove_coefficient=0.0, bare_fork_damping=2.5),
    )
    bounds = dict(raw.bounds)
    bounds["damping"] = Bound(1.5, 6.0)
    object.__setattr__(raw, "bounds", bounds)
    lo, hi = raw.lower().as_array(), raw.upper().as_array()
    assert performance(hi[0], hi[1], lo[2], lo[3], raw.conditions)["turning_moment"] == 0.0
    assert not structured.applicable(raw)


def test_robust_problem_is_not_closed_form(indoor):
    """A risk bound whose quantile factor G varies fast with the friction share (σ of log c_f and log K_s of 2)
    has no closed form (the default scatter has one: tests/test_structured.py), and asking for the ε-optima or
    the ends says why."""
    from designer.physics.uncertainty import Uncertainty

    assert structured.applicable(_with_conditions(indoor, uncertainty=Uncertainty()))
    robust = _with_conditions(indoor, uncertainty=Uncertainty(damping=2.0, slip_coefficient=2.0))
    assert not structured.applicable(robust)
    why = (
        r" need a continuous problem with a positive moment \(and a risk bound whose quantile factor varies "
        r"slowly with the friction share\)$"
    )
    with pytest.raises(ValueError, match="^the closed-form ε-optima" + why):
        structured.structured_front_designs(robust, [100.0])
    with pytest.raises(ValueError, match="^the closed-form ends" + why):
        structured.structured_ends(robust)


def test_front_designs_at_the_ends_of_the_diameter_range(indoor):
    """ε above P(d_lo) gives d = d_lo (the bound, not below it); ε = P(d_hi) exactly is reachable at d = d_hi;
    ε below P(d_hi) (here P at 1.5 d_hi) is out of reach: flagged infeasible, its design evaluated at d_hi."""
    lo, hi = indoor.lower(), indoor.upper()
    p = lambda d: float(performance(0.05, d, 0.0, 1.3, indoor.conditions)["threshold_force"])  # noqa: E731
    eps = [p(lo.diameter) * 1.2, p(hi.diameter), p(1.5 * hi.diameter)]
    x, ok = structured.structured_front_designs(indoor, eps)
    assert x[:, 1] == pytest.approx([lo.diameter, hi.diameter, hi.diameter], rel=1e-12)
    assert ok.tolist() == [True, True, False]


def test_trail_limit_reached_exactly_is_feasible(indoor):
    """R_max = T_min + d/2 leaves exactly the shortest trail (up to rounding): feasible, T = T_min."""
    d = np.array([6 * INCH])
    limited = indoor.replace(swept_radius_max=indoor.lower().trail + 3 * INCH)
    x, ok = structured.designs_at_diameter(limited, d)
    assert ok.tolist() == [True] and x[0, 0] == pytest.approx(indoor.lower().trail, rel=1e-12)


def test_designs_use_the_problems_slip_coefficient(indoor):
    """With K_s = 2500 N (twice the paper's) the closed-form designs still sit on V_c = V_req exactly when the
    shimmy constraint binds (Eq. 7 with the problem's K_s), and are feasible."""
    stiff = _with_conditions(indoor, slip_coefficient=2500.0)
    d = np.linspace(4, 8, 5) * INCH
    x, ok = structured.designs_at_diameter(stiff, d)
    assert ok.all()
    values = evaluate_many(stiff, x)
    v = values["critical_speed"]
    bare = (x[:, 2] <= 1e-12) & (x[:, 3] <= stiff.lower().damping * (1 + 1e-12))
    assert np.all(v >= stiff.required_speed * (1 - 1e-9))
    assert v[~bare] == pytest.approx(stiff.required_speed, rel=1e-9) and (~bare).any()


class _Hump(Fixed):
    """I_w = 1e-3 exp(−(d − 0.25 m)²/0.01): rising up to d = 0.25 m, falling beyond (outside the box)."""

    def __call__(self, diameter):
        return 1e-3 * np.exp(-((np.asarray(diameter, float) - 0.25) ** 2) / 0.01)


def test_applicable_checks_inertia_only_inside_the_diameter_box(indoor):
    """The closed form needs I_w non-decreasing over the box's diameters (3–8 in), not beyond: an inertia that
    rises up to 0.25 m and falls after it is fine for a box ending at 8 in = 0.2032 m."""
    problem = _with_conditions(indoor, validated=False, inertia=_Hump())
    assert indoor.upper().diameter < 0.25
    assert structured.applicable(problem)
