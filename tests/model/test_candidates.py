"""The one evaluator (designer.model.evaluate, shimmy_probability): its numbers are model.performance's, its limits use one tolerance, the sill gives P = inf, the inputs are read by name, and
the batched Monte Carlo gives for every caster the number of that caster's own seeded stream."""

from __future__ import annotations

import math

import numpy as np
import pytest

from designer.data.paper import INCH
from designer.model import (
    FEASIBILITY_TOLERANCE,
    Conditions,
    Design,
    Caster,
    Casters,
    design_columns,
    evaluate,
    performance,
    scatter_of,
    shimmy_probability,
)
from designer.physics.geometry import effective_trail
from designer.physics.scatter import inertia_prediction
from designer.physics.uncertainty import MC_BLOCK, MC_MAX_SAMPLES, Uncertainty, law_draws
from designer.physics.shimmy import critical_shimmy_speed

RISK = Conditions(uncertainty=Uncertainty())


def evaluate_candidates(designs, conditions, probability_at=None, **options) -> Casters:
    """The evaluator on a batch (one Design as a batch of one), the Monte Carlo speed as ``risk``."""
    return evaluate(design_columns(designs), conditions, risk=probability_at, **options)


DESIGNS = [
    Design(2.5 * INCH, 7 * INCH, 0.5 * INCH, 1.3),
    Design(1.0 * INCH, 3 * INCH, 0.0, 1.3),
    Design(2.0 * INCH, 8 * INCH, 0.75 * INCH, 4.0),
    Design(1.5 * INCH, 5 * INCH, 0.25 * INCH, 2.0),
]


def _stream(trail, inertia, groove, damping, slip, speed, u, samples, seed, target_se, diameter=None):
    """The reference: one caster's estimate from its own stream, written out as the risk law defines it:
    blocks of 10 000 draws (model t_5, inertia t_5, inertia, damping and slip normals, in that order) from
    default_rng(seed), at least ``samples`` (whole blocks), then more blocks (to the needed count plus 2 %,
    whole blocks) until the SE is at most ``target_se``, at most MC_MAX_SAMPLES in all; the wheel's I_w
    scattered by σ_I = 0.05 when measured (``diameter`` None), by Table 1's prediction at d otherwise."""
    rng = np.random.default_rng(seed)
    hits = drawn = 0
    block = MC_BLOCK
    want = -(-samples // block) * block
    scale = u.inertia if diameter is None else float(inertia_prediction().scale(diameter))
    while True:
        while drawn < want:
            f = law_draws(u, rng, 5)
            iota = scale * (f["inertia_z"] if diameter is None else f["inertia_t"])
            v = critical_shimmy_speed(
                trail,
                inertia * np.exp(iota),
                groove,
                damping * np.exp(u.damping * f["damping"]),
                slip * np.exp(u.slip_coefficient * f["slip"]),
            ) * np.exp(u.model_error * f["model"])
            hits += int(np.count_nonzero(v < speed))
            drawn += block
        p = hits / drawn
        if target_se is None or drawn >= MC_MAX_SAMPLES:
            break
        needed = math.ceil(max(p * (1 - p), 1.0 / drawn) / target_se**2)
        if needed <= drawn:
            break
        want = min(MC_MAX_SAMPLES, -(-(needed + needed // 50) // block) * block)
    return p, math.sqrt(max(p * (1 - p), 1.0 / drawn) / drawn)


def test_the_evaluator_gives_the_numbers_of_model_performance():
    """V_c, V_q, F_turn, P, I_w of a batch are model.performance's of each design alone, bit for bit, and the
    swept radius is T + d/2."""
    values = evaluate_candidates(DESIGNS, RISK)
    for k, d in enumerate(DESIGNS):
        one = performance(d.trail, d.diameter, d.groove, d.damping, RISK)
        assert values.critical_speed[k] == float(one["critical_speed"])
        assert values.confident_speed[k] == float(one["confident_speed"])
        assert values.turning_effort[k] == float(one["turning_effort"])
        assert values.threshold_force[k] == float(one["threshold_force"])
        assert values.inertia[k] == float(one["inertia"])
        assert values.swept_radius[k] == pytest.approx(d.trail + d.diameter / 2, rel=1e-15)
    assert values.confident_speed[0] < values.critical_speed[0]  # the bound lowers the speed (α = 5 %)


def test_designs_are_read_by_name_in_every_form():
    """A mapping, an (N, 4) array, a list of Designs and a record array with the table's names give the same
    numbers; a mapping in another key order too."""
    by_list = evaluate_candidates(DESIGNS, RISK).turning_effort
    array = np.array([d.as_array() for d in DESIGNS])
    mapping = {name: array[:, k] for k, name in enumerate(("trail", "diameter", "groove", "damping"))}
    shuffled = {name: mapping[name] for name in ("damping", "groove", "trail", "diameter")}
    records = np.rec.fromarrays([mapping[n] for n in mapping], names=list(mapping))
    for form in (array, mapping, shuffled, records):
        np.testing.assert_array_equal(evaluate_candidates(form, RISK).turning_effort, by_list)
    assert design_columns(DESIGNS[2])["damping"][0] == 4.0


def test_one_tolerance_for_both_limits():
    """A candidate FEASIBILITY_TOLERANCE/2 beyond a limit passes, one 2 × FEASIBILITY_TOLERANCE beyond fails,
    for the risk bound and for the swept radius alike."""
    d = DESIGNS[0]
    q = float(evaluate_candidates(d, RISK).confident_speed[0])
    r = d.trail + d.diameter / 2
    for factor, ok in ((1 + FEASIBILITY_TOLERANCE / 2, True), (1 + 2 * FEASIBILITY_TOLERANCE, False)):
        v = evaluate_candidates(d, RISK, required_speed=q * factor, swept_radius_max=r / factor)
        assert bool(v.risk_ok[0]) is ok and bool(v.radius_ok[0]) is ok and bool(v.feasible[0]) is ok


def test_a_wheel_that_cannot_climb_the_sill_is_infeasible_with_infinite_force():
    """d <= 2h: P = +inf and not feasible (Eq. 4A has no value there), while the other candidates keep their
    Eq. 4A force; the sill may differ per candidate (a fleet's chairs)."""
    v = evaluate_candidates(DESIGNS, RISK, threshold_height=np.array([[0.5 * INCH], [1.6 * INCH]]))
    assert v.threshold_force.shape == (2, 4)
    assert np.isinf(v.threshold_force[1, 1]) and not v.feasible[1, 1] and not v.sill_ok[1, 1]
    assert np.isinf(v.threshold_force[1, 0]) is np.False_  # 7 in > 3.2 in
    assert np.all(np.isfinite(v.threshold_force[0])) and v.feasible[0].all()


def test_stem_angle_and_calibration():
    """A tilted stem: V_c and F_turn on the effective trail e + (d/2) sin φ, the swept radius on the fork as
    built; a calibration factor k multiplies the bound's speed and divides the Monte Carlo's speed."""
    d = DESIGNS[3]
    phi = math.radians(4.0)
    tilted = evaluate_candidates(d, RISK, stem_angle=phi)
    t_eff = float(effective_trail(d.trail, d.diameter / 2, phi))
    upright = evaluate_candidates(Design(t_eff, d.diameter, d.groove, d.damping), RISK)
    assert tilted.critical_speed[0] == upright.critical_speed[0]
    assert tilted.turning_effort[0] == upright.turning_effort[0]
    assert tilted.swept_radius[0] == pytest.approx(d.trail + d.diameter / 2, rel=1e-15)
    k = 0.8
    cal = evaluate_candidates(d, RISK, calibration=k, probability_at=2.0, samples=20_000, target_se=None)
    plain = evaluate_candidates(d, RISK, probability_at=2.0 / k, samples=20_000, target_se=None)
    assert cal.confident_speed[0] == pytest.approx(k * plain.confident_speed[0], rel=1e-15)
    assert cal.shimmy_probability[0] == plain.shimmy_probability[0]


def test_scatter_of_is_the_bound_or_the_default():
    """The reported risk uses the problem's bound, or the default Uncertainty when the bound is off."""
    tight = Uncertainty(probability=0.01)
    assert scatter_of(Conditions(uncertainty=tight)) is tight
    assert scatter_of(Conditions()) == Uncertainty()


@pytest.mark.parametrize("samples,target_se", [(50_000, 1e-3), (5_000, 2e-3), (3_000, None)])
def test_batched_monte_carlo_equals_each_casters_own_stream(samples, target_se):
    """P(shimmy) and SE of many casters and speeds at once equal, exactly, the written-out stream of each caster
    alone; speeds are spread so that some estimates need the top-up from the same stream and some do not,
    two rows share a design at different speeds, and two wheels are known by their diameter only."""
    u = Uncertainty()
    designs = [DESIGNS[0], DESIGNS[0], DESIGNS[2], DESIGNS[3]]
    inertia = np.array([1.6e-3, 1.6e-3, 3.0e-3, 0.7e-3])
    speeds = np.array([2.2, 2.9, 2.6, 2.1])
    measured = np.array([True, True, False, False])
    cols = design_columns(designs)
    p, se = shimmy_probability(
        cols["trail"],
        inertia,
        cols["groove"],
        cols["damping"],
        1250.0,
        speeds,
        u,
        samples,
        4242,
        target_se,
        diameter=cols["diameter"],
        measured=measured,
    )
    for k in range(4):
        want = _stream(
            cols["trail"][k],
            inertia[k],
            cols["groove"][k],
            cols["damping"][k],
            1250.0,
            speeds[k],
            u,
            samples,
            4242,
            target_se,
            None if measured[k] else cols["diameter"][k],
        )
        assert (p[k], se[k]) == want, k
    assert p.min() < 0.05 < p.max()  # the top-up path is exercised where an SE target is set


def test_candidate_values_take_and_monte_carlo_on_request():
    """Without ``probability_at`` there is no Monte Carlo; ``take`` keeps the chosen candidates of every field, and
    a slice's columns cannot be written into."""
    v = evaluate_candidates(DESIGNS, RISK, required_speed=2.5)
    assert v.shimmy_probability is None and len(v) == 4
    sub = v.take(v.feasible)
    assert len(sub) == int(v.feasible.sum()) and np.all(sub.confident_speed >= 2.5 * (1 - FEASIBILITY_TOLERANCE))
    head = v.take(slice(0, 2))  # a slice's columns are views of the record's: read-only, as the record is
    assert len(head) == 2 and not head.threshold_force.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        head.threshold_force[0] = 0.0
    mc = evaluate_candidates(DESIGNS[:1], RISK, probability_at=2.5, samples=10_000, seed=1, target_se=None)
    assert 0 < mc.shimmy_probability[0] < 1 and mc.shimmy_probability_se[0] > 0


def test_one_design_is_a_caster_read_by_key():
    """evaluate() of one Design is a Caster whose fields are the batch's row 0, read by attribute and by key
    (designer.evaluate's dict answer: result["threshold_force"]); the J of given weights is w_F F + w_P P; g <= 0
    within the one tolerance is feasible; an 8 m wheel is refused."""
    from designer.errors import InputError

    one = evaluate(DESIGNS[0], RISK, weights=(1.0, 2.0), required_speed=2.0)
    row = evaluate(DESIGNS, RISK, weights=(1.0, 2.0), required_speed=2.0).row(0)
    assert isinstance(one, Caster) and one == row
    assert one["threshold_force"] == one.threshold_force and dict(one)["critical_speed"] == one.critical_speed
    assert one.weighted == pytest.approx(one.turning_effort + 2 * one.threshold_force, rel=1e-15)
    assert one.g_risk == pytest.approx(1 - one.confident_speed / 2.0, rel=1e-15) and one.feasible
    assert one.g_radius == -math.inf and "growth_rate" not in one
    with pytest.raises(InputError, match="diameter"):
        evaluate(Design(0.06, 8.0, 0.0, 1.3), RISK)


def test_one_design_with_risk_says_where_the_risk_comes_from():
    """evaluate() of one Design with ``risk`` gives the risk law's sources at the caster (law_sources on its
    trail, I_w, groove, damping and K_s, the wheel by its diameter unless measured) and the dominant one, which
    designer evaluate renders; not a column (not in keys()), None without risk and for a batch's row."""
    from designer.physics.uncertainty import dominant_sentence, law_sources
    from designer.reprs import deep_frozen

    for inertia in (None, 0.0012):
        one = evaluate(DESIGNS[0], Conditions(), risk=2.5, inertia=inertia)
        d = None if inertia else DESIGNS[0].diameter
        sources = law_sources(one.trail, one.inertia, one.groove, one.damping, 1250.0, Uncertainty(), d)
        assert one.risk_law == deep_frozen({"sources": sources, "dominant": dominant_sentence(sources)})
        assert "risk_law" not in one.keys() and "risk_law" not in dict(one) and "risk_law" not in one.to_dict()
    assert evaluate(DESIGNS[0], Conditions()).risk_law is None
    assert evaluate(DESIGNS, Conditions(), risk=2.5).row(0).risk_law is None


def test_feasibility_is_g_within_the_one_tolerance():
    """feasible <=> every g <= FEASIBILITY_TOLERANCE: a caster whose V_q is 2 tolerances short of V_req fails,
    one half a tolerance short passes, and violation() is the sum of the positive g."""
    q = float(evaluate_candidates(DESIGNS[0], RISK).confident_speed[0])
    short = evaluate_candidates(DESIGNS[0], RISK, required_speed=q / (1 - 2 * FEASIBILITY_TOLERANCE))
    near = evaluate_candidates(DESIGNS[0], RISK, required_speed=q / (1 - 0.5 * FEASIBILITY_TOLERANCE))
    assert not short.feasible[0] and near.feasible[0]
    assert short.violation()[0] == pytest.approx(2 * FEASIBILITY_TOLERANCE, rel=1e-6)


def test_exact_risk_matches_the_monte_carlo():
    """risk with exact=True is the quadrature of the exact law; the Monte Carlo of the same caster agrees with it
    within 3 of its standard errors."""
    exact = evaluate(DESIGNS[0], RISK, risk=2.5, exact=True)
    mc = evaluate(DESIGNS[0], RISK, risk=2.5)
    assert exact.shimmy_probability_se == 0
    assert abs(mc.shimmy_probability - exact.shimmy_probability) <= 3 * mc.shimmy_probability_se


def test_a_caster_without_numbers_has_no_risk():
    """A batch row with a NaN trail has V_c NaN and P(shimmy) NaN (by Monte Carlo and by the exact law), never
    P = 0, which would call it safe; the other row keeps its risk, the same as alone."""
    from designer.model import Conditions, Design, evaluate

    batch = {"trail": [0.05, np.nan], "diameter": [0.15, 0.15], "groove": [0.0, 0.0], "damping": [1.3, 1.3]}
    for exact in (False, True):
        out = evaluate(batch, Conditions(), risk=1.0, exact=exact)
        alone = evaluate(Design(0.05, 0.15, 0.0, 1.3), Conditions(), risk=1.0, exact=exact)
        assert np.isnan(out.critical_speed[1]) and np.isnan(out.shimmy_probability[1])
        assert out.shimmy_probability[0] == pytest.approx(alone.shimmy_probability, rel=1e-12)
        assert 0 < out.shimmy_probability[0] < 1


def test_rows_are_each_row_with_the_columns_read_once():
    """Casters.rows() (a front's points take their casters from it) is [row(0), row(1), ...]: the same Caster
    records, equal field by field and quantity by quantity, with and without the Monte Carlo columns, and one
    Caster for a batch of one."""
    for values in (
        evaluate(DESIGNS, RISK, weights=(1.0, 2.0), required_speed=2.0),
        evaluate(DESIGNS[:2], RISK, risk=2.5, samples=2_000, seed=3, target_se=None),
        evaluate(DESIGNS[:1], RISK, required_speed=2.0),
    ):
        rows = values.rows()
        assert len(rows) == len(values) and rows == [values.row(i) for i in range(len(values))]
        assert all(type(r.critical_speed) is float for r in rows)
