"""Issue 16: the brush tyre, its rolling limit, periodic orbits and their Floquet multipliers."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from designer.studies.dynamics.limit_cycles import (
    caster_dynamics,
    continue_orbits,
    knock_safe_speed,
    periodic_orbit,
    simulate_knock,
)
from designer.data.paper import APPENDIX_C_CASE, BARE_FORK_DAMPING
from designer.errors import InputError
from designer.model import Conditions, Design
from designer.physics.inertia import Fixed
from designer.physics.tyre import TyreParameters, lateral_tyre_force

I_C = 4 * BARE_FORK_DAMPING * APPENDIX_C_CASE.trail**2 / (math.pi * APPENDIX_C_CASE.critical_speed**2)
COND_C = Conditions(inertia=Fixed(I_C))
DESIGN_C = Design(trail=APPENDIX_C_CASE.trail, diameter=0.2, groove=0.0, damping=BARE_FORK_DAMPING)
TODAY_ONSET_C = (
    2.4412  # designer.studies.dynamics._simulate.onset_speed(DESIGN_C, COND_C, rtol=0.002): bracket 2.4391-2.4433 m/s
)


def test_brush_force_linear_then_saturates():
    """Brush tyre: F = −C σ for small slip (0.1 % at σ = σ_sl/1000), exactly −μL from σ_sl = 3μL/C on,
    continuous there, odd in σ, and linear for ever with saturation removed."""
    tyre = TyreParameters()
    s_sl = tyre.sliding_slip
    assert s_sl == pytest.approx(3 * 0.7 * 178 / 1250)
    small = 1e-3 * s_sl
    assert lateral_tyre_force(small, tyre) == pytest.approx(-1250 * small, rel=1e-3)
    assert lateral_tyre_force(s_sl, tyre) == pytest.approx(-0.7 * 178)
    assert lateral_tyre_force(5 * s_sl, tyre) == pytest.approx(-0.7 * 178)
    assert lateral_tyre_force(0.999999 * s_sl, tyre) == pytest.approx(-0.7 * 178, rel=1e-9)
    grid = np.linspace(-2 * s_sl, 2 * s_sl, 41)
    forces = lateral_tyre_force(grid, tyre)
    assert np.allclose(forces, -forces[::-1])
    assert np.all(np.diff(forces) <= 0)  # never pushes with the slip
    assert np.allclose(forces, [lateral_tyre_force(float(g), tyre) for g in grid])  # array = scalar path
    assert lateral_tyre_force(5 * s_sl, tyre.replace(saturation=False)) == pytest.approx(-1250 * 5 * s_sl)


def test_bad_tyre_parameter_is_input_error():
    """A non-positive friction coefficient is rejected with a message naming it."""
    with pytest.raises(InputError, match="friction_coefficient"):
        TyreParameters(friction_coefficient=0.0)


def test_tyre_model_reduces_to_todays_onset():
    """Saturation removed and C × 30: the 20° knock on the Appendix C caster decays at 0.995 × today's
    simulated onset (designer.studies.dynamics._simulate, 2.441 m/s) and grows at 1.005 ×: the onsets agree within
    0.5 %.  Decays: no shimmy, |θ| never at the limit, the last reversal within a tenth of the knock (whether the
    integrator then stops at rest or at the end of the time is its business); grows: |θ| reaches the 1 rad limit."""
    stiff = TyreParameters().rolling_limit(30.0)
    below = simulate_knock(caster_dynamics(DESIGN_C, COND_C, 0.995 * TODAY_ONSET_C, stiff), 0.349, cycles=24)
    above = simulate_knock(caster_dynamics(DESIGN_C, COND_C, 1.005 * TODAY_ONSET_C, stiff), 0.349, cycles=24)
    assert not below.shimmy and below.reason != "limit"
    assert abs(below.extrema[-1, 1]) < 0.1 * 0.349
    assert above.shimmy and above.reason == "limit"


def test_rolling_engine_matches_designer_simulate():
    """The new event-driven integrator, rolling tyre: the same 20° knock decays at 0.998 × and grows at
    1.002 × today's onset (same equations as designer.studies.dynamics._simulate, independent code)."""
    sys = caster_dynamics(DESIGN_C, COND_C, 1.0, None)
    assert not simulate_knock(sys.at(0.998 * TODAY_ONSET_C), 0.349).shimmy
    assert simulate_knock(sys.at(1.002 * TODAY_ONSET_C), 0.349).shimmy


def test_rolling_orbit_is_the_describing_function_threshold():
    """Rolling tyre, A = 0.15 rad: the periodic orbit closes over one full period to 1e-6 rad, its speed is
    within 10 % of Eq. 6 + 20B (V = 4 M_f T/(π ω I_w A)), it is unstable (a Floquet multiplier > 1), and
    perturbed simulations leave it: 2 % larger grows past 0.3 rad, 2 % smaller comes to rest."""
    sys = caster_dynamics(DESIGN_C, COND_C, 2.0, None)
    orb = periodic_orbit(sys, 0.15)
    m_f = BARE_FORK_DAMPING * COND_C.disturbance_angle
    assert orb.speed == pytest.approx(4 * m_f * DESIGN_C.trail / (math.pi * 104.7 * I_C * 0.15), rel=0.10)
    assert orb.closure < 1e-6
    assert not orb.stable and np.max(np.abs(orb.multipliers)) > 1.05
    at = sys.at(orb.speed)
    from designer.studies.dynamics.limit_cycles._system import _integrate

    for factor, grows in ((1.02, True), (0.98, False)):
        run = _integrate(at, orb.state * factor, 40 * orb.period, angle_limit=0.3)
        assert (run.reason == "limit") is grows


def test_saturating_tyre_has_a_stable_large_cycle():
    """Brush tyre (C = 1250 N/rad, μ = 0.7, L = 178 N), Appendix C caster: following the orbits up in
    amplitude from 0.4 rad, the unstable branch folds back and a stable orbit appears by 0.8 rad
    (all Floquet multipliers inside the unit circle, closure < 1e-6 rad); a 5 % perturbed start returns
    to within 1 % of its amplitude."""
    sys = caster_dynamics(DESIGN_C, COND_C, 1.0, TyreParameters())
    branch = continue_orbits(sys, np.geomspace(0.4, 0.8, 5))
    assert not branch.orbits[0].stable
    top = branch.orbits[-1]
    assert top.amplitude == pytest.approx(0.8)
    assert top.stable and np.max(np.abs(top.multipliers)) < 0.95
    assert top.closure < 1e-6
    speeds = [o.speed for o in branch.orbits]
    assert min(speeds) < speeds[0] and min(speeds) < speeds[-1]  # the fold
    from designer.studies.dynamics.limit_cycles._system import _extrema, _integrate

    at = sys.at(top.speed)
    run = _integrate(at, top.state * 1.05, 30 * top.period)
    ext = _extrema(run.ends)
    assert np.abs(ext[-1, 1]) == pytest.approx(top.amplitude, rel=0.01)


def test_knock_safe_speed_is_todays_onset():
    """Knock-safe speed of the Appendix C caster for the 20° knock equals today's simulated onset
    (designer.studies.dynamics._simulate, 2.441 m/s) within its 0.5 % bracket, and lies below it (it is the decaying end)."""
    v1 = knock_safe_speed(DESIGN_C, COND_C)
    assert v1 == pytest.approx(TODAY_ONSET_C, rel=0.006)
    assert v1 < TODAY_ONSET_C * 1.001


def test_cli_knock_safe_json(capsys):
    """`designer simulate --knock-safe --angle 30deg --json`: knock_safe_speed in m/s; a 30° knock is safe only
    to 72-90 % of the 20° knock's speed (a fixed M_f resists a bigger knock less; Eq. 7 scales as
    1/sqrt(θ_i): 82 %), and the 60° knock to less again."""
    from designer.cli import main

    assert (
        main(["simulate", "--trail", "2.5in", "--inertia", f"{I_C}", "--knock-safe", "--angle", "30deg", "--json"]) == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert 0.72 * TODAY_ONSET_C < out["knock_safe_speed"] < 0.90 * TODAY_ONSET_C
    assert 0 <= out["knock_safe_speed_double"] < 0.8 * out["knock_safe_speed"]


def test_cli_bifurcation_json(capsys):
    """`designer simulate --bifurcation --json` gives branches of kind stable/unstable with speeds in m/s and
    amplitudes in rad: the unstable (threshold) branch falls with speed and crosses Eq. 29B's 0.13-0.17 rad
    near V_c, the stable branch lies above it (sustained shimmy larger than the threshold), and every orbit
    closes to 1e-6 rad."""
    from designer.cli import main

    assert (
        main(
            [
                "simulate",
                "--trail",
                "2.5in",
                "--inertia",
                f"{I_C}",
                "--bifurcation",
                "--points",
                "6",
                "--max-speed",
                "3.5",
                "--json",
            ]
        )
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    kinds = {b["kind"] for b in out["branches"]}
    assert kinds == {"stable", "unstable"}
    unstable = next(b for b in out["branches"] if b["kind"] == "unstable")
    stable = [a for b in out["branches"] if b["kind"] == "stable" for a in b["amplitude"]]
    v, a = np.array(unstable["speed"]), np.array(unstable["amplitude"])
    assert np.all(np.diff(v[np.argsort(a)]) < 0)
    assert 0.13 < np.interp(2.53, v[::-1] if v[0] > v[-1] else v, a[::-1] if v[0] > v[-1] else a) < 0.20
    assert min(stable) > max(a[v > 1.0])
    assert out["max_closure"] < 1e-6
    assert out["rolling_branches"] and all(b["kind"] == "unstable" for b in out["rolling_branches"])


def test_evaluate_knock_safe(capsys):
    """`designer evaluate --knock-safe --json` reports the knock-safe speed beside V_c: for T = 2 in, d = 8 in,
    bare fork it is within 15 % of Eq. 7 (the simulated onset's spread against Eq. 7 in results/simulation)
    and the 40° knock's is lower."""
    from designer.cli import main

    assert (
        main(
            [
                "evaluate",
                "--trail",
                "2in",
                "--diameter",
                "8in",
                "--groove",
                "0",
                "--damping",
                "1.3",
                "--knock-safe",
                "--json",
            ]
        )
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert out["knock_safe_speed"] == pytest.approx(out["critical_speed"], rel=0.15)
    assert out["knock_safe_speed_double"] < 0.8 * out["knock_safe_speed"]


def test_slow_creep_of_a_sliding_tyre_is_not_shimmy():
    """Brush tyre at 0.8 m/s (below the 0.65-0.7 m/s fold's stable branch reach for a 20° knock): the knocked
    tyre slides and the caster creeps back over many periods without oscillating; that is not sustained
    shimmy (fewer than 3 reversals at the end), while at 2.7 m/s the same knock locks onto the stable cycle."""
    sys = caster_dynamics(DESIGN_C, COND_C, 0.8, TyreParameters())
    creep = simulate_knock(sys, 0.349)
    # the physics, not the integrator's stop reason: a creep that ends at rest ("rest") or is still creeping when
    # the simulated time ends ("end") is not shimmy; only |θ| reaching the limit ("limit") would be
    assert not creep.shimmy and creep.reason != "limit"
    # few reversals: a sustained oscillation at ω = 104.7 rad/s would reverse about 60 times in 30 periods
    assert len(creep.extrema) <= 5
    # a decaying amplitude: the last reversal is within a tenth of the 20° knock
    assert abs(creep.extrema[-1, 1]) < 0.1 * 0.349
    locked = simulate_knock(sys.at(2.7), 0.349)
    assert locked.shimmy and locked.late_amplitude == pytest.approx(0.915, rel=0.02)


def test_closed_form_integration_matches_dop853():
    """Rolling model: the closed-form stick/slip integration (exact=True) gives the same knock as DOP853 at
    rtol 1e-10: same verdict, |θ| at the limit in both or in neither, the same reversals (time, θ) to 1e-6 where
    |θ| > 1e-6 θ_i, early and late amplitudes to 1e-6 (absolutely to 1e-6 θ_i), at speeds below, just around and
    above the onset, for the 20° and the 40° knock.  The last creep to rest (|θ| <= 1e-6 θ_i) is ill-conditioned
    in time: how many tiny reversals it makes and whether the integrator stops at "rest" or "end" are not compared."""
    sys = caster_dynamics(DESIGN_C, COND_C, 1.0, None)
    for angle in (0.349, 0.698):
        for factor in (0.6, 0.9, 0.99, 1.01, 1.2, 2.0):
            v = factor * TODAY_ONSET_C / (1.0 if angle < 0.5 else 1.35)
            a = simulate_knock(sys.at(v), angle)
            b = simulate_knock(sys.at(v), angle, exact=True)
            assert (a.shimmy, a.reason == "limit") == (b.shimmy, b.reason == "limit"), (angle, factor)
            assert b.early_amplitude == pytest.approx(a.early_amplitude, rel=1e-6, abs=1e-6 * angle)
            assert b.late_amplitude == pytest.approx(a.late_amplitude, rel=1e-6, abs=1e-6 * angle)
            big_a = a.extrema[np.abs(a.extrema[:, 1]) > 1e-6 * angle]
            big_b = b.extrema[np.abs(b.extrema[:, 1]) > 1e-6 * angle]
            assert len(big_a) == len(big_b), (angle, factor)
            np.testing.assert_allclose(big_b, big_a, rtol=1e-6, atol=1e-9)


def test_fast_knock_safe_speed_matches_the_dop853_bisection():
    """knock_safe_speed's fast path (closed-form knocks, bisection started at Eq. 7 × [0.96, 1.04]) agrees with
    the DOP853 bisection from Eq. 7 × [0.8, 1.25] within the bisection's 0.5 % tolerance, for the Appendix C
    caster and a grooved design of the default problem's front, knocks of θ0 and 2 θ0."""
    grooved = Design(trail=0.0635, diameter=0.1778, groove=0.0127, damping=1.3)
    for design, cond in ((DESIGN_C, COND_C), (grooved, Conditions())):
        for angle in (0.349, 0.698):
            slow = knock_safe_speed(design, cond, angle=angle, exact=False)
            fast = knock_safe_speed(design, cond, angle=angle)
            assert fast == pytest.approx(slow, rel=0.005)


def test_knock_safe_speeds_for_the_card():
    """knock_safe_speeds gives, per design, a KnockSafe record: the θ0 and 2 θ0 knock-safe speeds [m/s] (the 2 θ0
    one lower) and the knock angle, for the card of the report and the studio (which read its to_dict())."""
    from designer.studies.dynamics.limit_cycles import KnockSafe, knock_safe_speeds

    rows = knock_safe_speeds([DESIGN_C], COND_C)
    assert len(rows) == 1
    row = rows[0]
    assert isinstance(row, KnockSafe)
    assert row.knock_angle == pytest.approx(COND_C.disturbance_angle)
    assert row.knock_safe_speed == pytest.approx(TODAY_ONSET_C, rel=0.006)
    assert 0 < row.knock_safe_speed_double < 0.9 * row.knock_safe_speed
    assert row.to_dict() == {
        "knock_angle": row.knock_angle,
        "knock_safe_rtol": 0.005,
        "knock_safe_speed": row.knock_safe_speed,
        "knock_safe_speed_double": row.knock_safe_speed_double,
    }
