"""Joint acceptance limits (issue 43): a box of part limits inside which every caster meets P(shimmy) <= α, checked
at all 2^k corners by the exact law (32-node quadrature, not the box's own 16-node array law)."""

from __future__ import annotations

import itertools
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from designer.physics.uncertainty import shimmy_probability_exact
from designer.problem import load_problem
from designer.physics.acceptance import measured_probabilities

ROOT = Path(__file__).resolve().parents[2]


def _recommended(name: str):
    from designer.studies.recommend import recommend

    problem = load_problem(ROOT / "problems" / f"{name}.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return problem, recommend(problem)


@pytest.fixture(scope="module", params=["indoor-manual", "indoor-manual-tolerances"])
def recommended(request):
    """The default problem and the shipped tolerances example, each with its recommendation and spec."""
    return _recommended(request.param)


def _law(problem):
    return problem.risk


def _corner_p(problem, trail, groove, moment, inertia) -> float:
    """P(V_c,true < V_req) of a caster with a measured wheel by the exact law (32 Gauss–Hermite nodes a side)."""
    theta0 = float(problem.conditions.disturbance_angle)
    return float(
        shimmy_probability_exact(
            trail,
            inertia,
            groove,
            moment / theta0,
            float(problem.conditions.slip_coefficient),
            problem.required_speed,
            _law(problem),
            None,
            None,
            32,
        )
    )


def _corners(problem, joint) -> list[float]:
    """P at every corner of the box: each risk part at its limit or its mirror about nominal (a half-open side ends
    there), the trail between its risk minimum and its footrest maximum."""
    nom = joint.nominal
    axes = [
        (joint.trail_min, joint.trail_max),
        (joint.groove_min, 2 * nom["groove"] - joint.groove_min),
        (joint.friction_moment_min, 2 * nom["friction_moment"] - joint.friction_moment_min),
        (joint.wheel_inertia_max, 2 * nom["wheel_inertia"] - joint.wheel_inertia_max),
    ]
    return [_corner_p(problem, *corner) for corner in itertools.product(*axes)]


def test_every_corner_of_the_joint_box_meets_the_bound_and_one_is_at_it(recommended):
    """All 2^4 = 16 corners of the recommendation's joint box give P <= α by the 32-node exact law, the worst within
    1 % of α (the box is not needlessly small; the root is to 1e-9); the worst is the corner of every risk limit
    (P monotone in each part), and the box's own record agrees."""
    problem, rec = recommended
    joint = rec.spec.joint
    alpha = float(problem.risk.probability)
    p = _corners(problem, joint)
    assert len(p) == 16 == joint.corners
    assert max(p) <= alpha * (1 + 1e-9)
    assert max(p) >= 0.99 * alpha
    assert p[0] == max(p)  # trail_min, groove_min, friction_moment_min, wheel_inertia_max
    assert joint.monotone and joint.probability == pytest.approx(p[0], rel=1e-8)  # 16 against 32 nodes


def test_one_at_a_time_limits_together_break_the_bound(recommended):
    """The check catches a box that is too large: the one-at-a-time limits (each at α with the others at nominal)
    taken together as a box give P well above α at their worst corner with a measured wheel (the issue's finding),
    while the joint box's worst corner is at α."""
    problem, rec = recommended
    spec, joint = rec.spec, rec.spec.joint
    one = {lim.key: lim.value for lim in spec.limits}
    p = _corner_p(problem, one["trail_min"], one["groove_min"], one["friction_moment_min"], one["wheel_inertia_max"])
    assert p > 2 * float(problem.risk.probability)
    assert joint.probability == pytest.approx(float(problem.risk.probability), rel=1e-8)


def test_box_shape_follows_the_stated_tolerances():
    """indoor-manual-tolerances: the box is in proportion to [tolerances] (trail ±1.5 mm of 63.5 mm, groove ±0.4 mm
    of 14.29 mm, friction ±30 %), the windows stand in those ratios, the stated tolerances fit inside (scale >= 1),
    and the trail maximum is the footrest's R_max − (d + 1 mm)/2 = 75.70 mm (the issue's number)."""
    problem, rec = _recommended("indoor-manual-tolerances")
    joint = rec.spec.joint
    assert joint.shape == "tolerances"
    assert joint.weights["trail"] == pytest.approx(1.5e-3 / rec.design.trail, rel=1e-12)
    assert joint.weights["friction_moment"] == pytest.approx(0.3, rel=1e-12)
    assert joint.window("trail") / joint.window("friction_moment") == pytest.approx(1.5e-3 / rec.design.trail / 0.3)
    assert joint.scale >= 1
    assert joint.trail_max == pytest.approx(6 * 0.0254 - (rec.design.diameter + 1e-3) / 2, abs=1e-12)
    assert joint.trail_max * 1000 == pytest.approx(75.70, abs=0.005)
    assert joint.protects["trail_max"] == "footrest" and joint.protects["trail_min"] == "risk"
    assert joint.diameter_max == pytest.approx(rec.design.diameter + 1e-3)


def test_default_box_is_equal_relative_and_says_the_footrest_leaves_no_trail_window():
    """indoor-manual (no [tolerances]): the largest equal relative window (every risk part's window the same
    fraction of nominal); the trail maximum equals the nominal 63.50 mm (T + d/2 = R_max), marked footrest, with
    a note that names the fix."""
    problem, rec = _recommended("indoor-manual")
    joint = rec.spec.joint
    assert joint.shape == "equal relative"
    nom = joint.nominal
    windows = [
        1 - joint.trail_min / nom["trail"],
        1 - joint.groove_min / nom["groove"],
        1 - joint.friction_moment_min / nom["friction_moment"],
        joint.wheel_inertia_max / nom["wheel_inertia"] - 1,
    ]
    assert np.allclose(windows, joint.scale, rtol=1e-12)
    assert joint.trail_max == pytest.approx(nom["trail"], abs=1e-12)
    assert "no window" in joint.notes["trail_max"] and "shorter trail" in joint.notes["trail_max"]


def test_array_law_matches_the_exact_law_caster_by_caster():
    """measured_probabilities (one array call for many casters) equals shimmy_probability_exact with the same 16
    nodes caster by caster to 1e-12, grooved and plain, and gives 1 where Eq. 7's V_c is zero."""
    problem = load_problem(ROOT / "problems" / "indoor-manual.toml")
    law, ks = problem.risk, float(problem.conditions.slip_coefficient)
    t = np.array([0.03, 0.05, 0.0635, 0.07, 0.0])
    i = np.array([1.2e-3, 0.6e-3, 1.0e-3, 2.0e-3, 1e-3])
    b = np.array([0.0, 0.01, 0.019, 0.005, 0.01])
    c = np.array([1.3, 2.0, 1.3, 3.0, 1.3])
    got = measured_probabilities(t, i, b, c, ks, 2.5, law)
    for k in range(4):
        ref = float(shimmy_probability_exact(t[k], i[k], b[k], c[k], ks, 2.5, law, None, None, 16))
        assert math.isclose(got[k], ref, rel_tol=1e-12, abs_tol=2e-12)  # the inversion is exact to 7e-13
    assert got[4] == 1.0


def test_default_sheet_marks_the_trail_maximum_as_the_footrest_limit_with_no_window():
    """indoor-manual's sheet (an inch problem: inches first): the trail row's maximum 2.500 in is tagged [footrest] (not [risk]) in both the joint box
    and the one-at-a-time column, the minimum [risk]; a sentence says the maximum leaves no window and names the fix;
    the old claim "a part beyond its limit fails the risk bound" (read as: inside passes) is gone."""
    from designer.report.sheet import sheet_html

    problem, rec = _recommended("indoor-manual")
    html = sheet_html(rec)
    row = html[html.index('<td class="part" data-label="part">trail T</td>') :].split("</tr>")[0]
    assert row.count("max 2.500 in (63.50 mm) [footrest") == 2 and row.count("[risk]") == 2
    assert "no window above the nominal trail: fix: a shorter trail step or a smaller wheel" in html
    assert "A part beyond its limit fails the risk bound" not in html
    assert "joint box: accept when every part is inside" in html


def test_one_at_a_time_trail_maximum_applies_the_diameters_tolerance():
    """indoor-manual-tolerances (6 in wheel, d ± 1 mm, R_max 6 in): the one-at-a-time trail maximum is
    R_max − (d + 1 mm)/2 = 75.70 mm, not R_max − d/2 = 76.20 mm, and is labelled footrest."""
    problem, rec = _recommended("indoor-manual-tolerances")
    lim = rec.spec.limit("trail", "max")
    assert lim.value * 1000 == pytest.approx(75.70, abs=1e-9) and lim.protects == "footrest"
    assert rec.spec.limit("trail", "min").protects == "risk"


def test_speed_reached_with_probability_one_minus_alpha_is_the_exact_quantile(tmp_path, capsys):
    """designer run indoor-manual --json: the printed V_q satisfies P(V_c,true < V_q) = α within 1e-4 relative by the
    exact law's quadrature (48 nodes a side, the wheel known by its diameter as the recommendation's is); the
    solvers' conservative V_q bound of the same caster gives P below α by more than 1e-4 (the test would catch a
    bound printed as the quantile)."""
    import json

    from designer.cli import main
    from designer.physics.uncertainty import shimmy_speed_quantile
    from designer.model import evaluate

    problem = load_problem(ROOT / "problems" / "indoor-manual.toml")
    assert main(["run", str(ROOT / "problems" / "indoor-manual.toml"), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)["recommendation"]
    d = rec["design"]
    caster = evaluate(_design(d), problem.conditions)
    law, alpha = problem.risk, float(problem.risk.probability)

    def p_at(speed: float) -> float:
        return float(
            shimmy_probability_exact(
                d["trail"],
                float(caster.inertia),
                d["groove"],
                d["damping"],
                float(problem.conditions.slip_coefficient),
                speed,
                law,
                d["diameter"],
                None,
                48,
            )
        )

    assert p_at(rec["confident_speed"]) == pytest.approx(alpha, rel=1e-4)
    bound = float(caster.confident_speed)
    assert shimmy_speed_quantile is not None and bound < rec["confident_speed"]
    assert p_at(bound) < alpha * (1 - 1e-4)


def _design(d: dict):
    from designer.model import Design

    return Design(trail=d["trail"], diameter=d["diameter"], groove=d["groove"], damping=d["damping"])


def test_theta_a_is_eq3s_full_amplitude_on_the_default_caster():
    """indoor-manual's caster (T 2.5 in, d 7 in, B 3/4 in, c_f 1.3): ω T/V_c = 1.54, so θ_a = θ0/√(1 + 1.54²) =
    0.190 rad (the issue's number), not Eq. 4's θ0 V_c/(ω T) = 0.227 rad."""
    from designer.model import Design, evaluate

    problem = load_problem(ROOT / "problems" / "indoor-manual.toml")
    caster = evaluate(Design(trail=0.0635, diameter=0.1778, groove=0.01905, damping=1.3), problem.conditions)
    ratio = float(caster.shimmy_frequency * caster.trail / caster.critical_speed)
    assert ratio == pytest.approx(1.54, abs=0.005)
    assert float(caster.shimmy_amplitude) == pytest.approx(0.190, abs=0.0005)
    assert float(problem.conditions.disturbance_angle) / ratio == pytest.approx(0.227, abs=0.0005)


@pytest.mark.parametrize("dof", [1, 3, 5, 7, 4, 0])
def test_measured_linear_cdf_is_the_inversions_distribution(dof):
    """The closed-form route (odd ν: Gauss–Hermite over the normal part, the Student-t CDF in closed form) gives the
    characteristic-function inversion's CDF to 2e-12 over ±2 (ν = 1, 3, 5, 7); an even ν and the normal model
    error (ν = 0) take the inversion itself."""
    from designer.physics.uncertainty import _linear_part, data_law
    from designer.physics.acceptance import measured_linear_cdf

    law = data_law(model_error_dof=dof)
    x = np.linspace(-2, 2, 4001)
    ref = _linear_part(1.0, 1.0, 0.0, 1.0, 1250.0, law, None, None).cdf(x.reshape(1, -1))[0]
    assert np.max(np.abs(measured_linear_cdf(x, 1250.0, law) - ref)) < 2e-12


def test_joint_boxes_searched_together_equal_each_searched_alone():
    """joint_limits_many (one root search and one corner call for all casters) gives each of 40 random casters of
    two problems (the default, V_req 2.5 m/s, and the tolerances example at V_target 2.8 m/s, its box in proportion to
    its tolerances) the box it
    gets alone, to the scale's root tolerance (SCALE_RTOL), with the same corner count and the same notes; and
    measured_probabilities with one speed per caster equals a call per speed."""
    from designer.model import Design
    from designer.studies.acceptance import SCALE_RTOL, joint_limits_many

    problems = [load_problem(ROOT / "problems" / f"{n}.toml") for n in ("indoor-manual", "indoor-manual-tolerances")]
    problems[1] = problems[1].replace(target_speed=2.8)
    rng = np.random.default_rng(44)
    each, designs, inertia = [], [], []
    for k in range(40):
        each.append(problems[k % 2])
        designs.append(
            Design(
                trail=rng.uniform(0.03, 0.07),
                diameter=rng.uniform(0.1, 0.2),
                groove=rng.choice([0.0, rng.uniform(0.005, 0.02)]),
                damping=rng.uniform(0.5, 3.0),
            )
        )
        inertia.append(rng.uniform(0.4e-3, 2.0e-3))
    measured = [False] * 40
    together = joint_limits_many(each, designs, inertia, measured, problems[0].risk)
    assert len({j.required_speed for j in together}) == 2
    for p, d, i, box in zip(each, designs, inertia, together):
        (alone,) = joint_limits_many([p], [d], [i], [False], problems[0].risk)
        assert box.corners == alone.corners and box.notes == alone.notes and box.shape == alone.shape
        assert box.scale == pytest.approx(alone.scale, rel=4 * SCALE_RTOL, abs=1e-12)
        if box.scale > 0:  # the worst corner at α, from inside
            assert box.alpha * (1 - 1e-5) <= box.probability <= box.alpha
        else:  # no window: even the nominal caster with a measured wheel is above α
            assert box.probability > box.alpha and "box" in box.notes
    assert any(j.scale == 0.0 for j in together) and any(j.scale > 0 for j in together)  # both branches
    law, ks = problems[0].risk, float(problems[0].conditions.slip_coefficient)
    speeds = np.array([2.2, 2.5, 2.9])
    got = measured_probabilities(0.05, 1e-3, 0.01, 1.3, ks, speeds, law)
    assert np.array_equal(got, [measured_probabilities(0.05, 1e-3, 0.01, 1.3, ks, v, law) for v in speeds])


def test_speed_quantiles_found_together_equal_each_found_alone():
    """exact_speed_quantiles (one bracketed search for many casters) gives each of 12 casters (wheels known by their
    diameter and measured ones, with and without the solvers' V_q as a start, one without trail) the quantile it gets
    alone, to the search's 1e-10 in log V, and P(V_c,true < V_q) = α there by the 32-node quadrature to 1e-4."""
    from designer.physics.acceptance import LawCaster, exact_speed_quantile, exact_speed_quantiles

    problem = load_problem(ROOT / "problems" / "indoor-manual.toml")
    law, ks = problem.risk, float(problem.conditions.slip_coefficient)
    rng = np.random.default_rng(43)
    casters = [
        LawCaster(
            trail=0.0 if k == 5 else rng.uniform(0.03, 0.07),
            inertia=rng.uniform(0.4e-3, 2e-3),
            groove=rng.uniform(0.0, 0.02),
            damping=rng.uniform(0.5, 3.0),
            slip_coefficient=ks,
            diameter=None if k % 3 == 0 else rng.uniform(0.1, 0.2),
        )
        for k in range(12)
    ]
    guesses = [None if k % 2 else 2.0 for k in range(12)]
    together = exact_speed_quantiles(casters, law, guesses=guesses)
    assert together[5] == 0.0
    for c, g, q in zip(casters, guesses, together):
        assert q == pytest.approx(exact_speed_quantile(c, law, guess=g), rel=3e-10, abs=0.0)
        if q > 0:
            p = shimmy_probability_exact(c.trail, c.inertia, c.groove, c.damping, ks, q, law, c.diameter, None, 32)
            assert float(p) == pytest.approx(law.probability, rel=1e-4)


def test_the_measured_law_works_in_blocks_whatever_the_batch():
    """measured_linear_cdf keeps its temporaries to a block for every law: with a normal model error (ν = 0, the
    law a calibrated retrofit uses, which takes the characteristic-function inversion over 512 nodes) 50,000 points
    peak below 50 MB (one (points × nodes) array was 205 MB, and a retrofit's 329 boxes reached 16.9 GB); the
    blocks give the same CDF as one call; x = ±∞ gives 0 and 1 for the closed-form laws (ν = 5, 1), not NaN."""
    import tracemalloc

    from designer.physics.acceptance import measured_linear_cdf
    from designer.physics.uncertainty import data_law

    law = data_law(model_error_dof=0)
    x = np.linspace(-0.3, 0.3, 50_000)
    tracemalloc.start()
    try:
        got = measured_linear_cdf(x, 1250.0, law)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6
    assert np.array_equal(got[:500], measured_linear_cdf(x[:500], 1250.0, law))
    assert np.all(np.diff(got) >= -1e-12) and 0.001 < got[0] < 0.01 and 0.99 < got[-1] < 0.999  # the inversion's 7e-13
    for dof in (5, 1):
        ends = measured_linear_cdf(np.array([-np.inf, np.inf]), 1250.0, data_law(model_error_dof=dof))
        assert ends.tolist() == [0.0, 1.0]


def test_a_joint_batch_that_mixes_slip_coefficients_is_refused():
    """joint_limits_many evaluates the law with one K_s: a batch that mixes two is refused with a ValueError naming
    K_s (caster_specs groups by it), not answered with the first caster's K_s."""
    import dataclasses

    from designer.model import Design
    from designer.studies.acceptance import joint_limits_many

    p = load_problem(ROOT / "problems" / "indoor-manual.toml")
    q = dataclasses.replace(p, conditions=p.conditions.replace(slip_coefficient=2000.0))
    d = Design(trail=0.0635, diameter=0.1778, groove=0.019, damping=1.3)
    with pytest.raises(ValueError, match="one slip coefficient K_s"):
        joint_limits_many([p, q], [d, d], [1e-3, 1e-3], [False, False], p.risk)
