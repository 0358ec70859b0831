"""Time-domain shimmy simulation with true Coulomb spindle friction (Appendix B).

Eq. 7 is a *describing-function* result: the paper replaces the spindle's
constant friction moment M_f by the hydraulic damper that dissipates the same
work per cycle (Eq. 6 = 3C, C_D = 4 M_f/(π θ_a ω)), takes the shimmy
amplitude from the linear transient at the threshold (Eq. 4 / 29B,
θ_a = θ0 V/(ω T)) and applies Routh–Hurwitz to the linear third-order model
(Eq. 12B, 20B).  This module integrates the nonlinear model instead, so the
approximation can be checked.

Equations integrated
--------------------
The two-degree-of-freedom rolling caster of Fig. 1B with the Coulomb spindle moment M_f sgn(θ') in place of
Eq. 4B's C_D θ': :mod:`designer.physics.motion` (Eq. 3B, 4B, 6B; the state (X, θ, θ') and its first-order
system, whose derivative is Eq. 12B with C_D θ'' replaced by d/dt(M_f sgn θ')).

Coulomb friction is handled exactly, by events (stick–slip), not smoothed:

* slip (θ' ≠ 0): integrate with sgn θ' = s fixed (scipy ``solve_ivp``,
  DOP853) until θ' crosses zero (terminal event);
* at θ' = 0 the moment the spring transmits is τ = T K X; if |τ| > M_f the
  caster reverses and slips with s = sgn τ, otherwise it sticks;
* stick (θ' = 0, θ constant): X' = −V θ is integrated until |T K X|
  reaches M_f, then slip resumes in the direction of τ.

Friction moment and initial conditions
--------------------------------------
The design variable c_f = M_f/θ0 (Eq. 7, 11C) is defined with the design
disturbance angle θ0 of the conditions (20°), so the fork's friction moment is
M_f = c_f · θ0_design.  A simulation may start from any angle θ_i (knock
size); Eq. 7 then predicts V_c with c_f,eff = M_f/θ_i, which is what the
comparisons below use.  Initial conditions are those of Eq. 24B:
θ = θ_i, θ' = θ'_i, θ'' = 0 (which fixes X(0)).

Paper numbers: K, N from :class:`designer.physics.shimmy.DynamicsParameters`
(N = 0.5 kg, K chosen so that ω = 104.7 rad/s at T = 2.5 in, App. C); K_s =
1250 N; θ0 = 20° = 0.349 rad.

Layout: :func:`simulate` checks its arguments (:func:`_knock`), runs the room's one stick–slip event loop
(:func:`designer.studies.dynamics.limit_cycles._system._integrate`) and measures the amplitudes and the frequency; :func:`onset_speed` brackets and
bisects the onset.  The records :class:`SimulationResult` and :class:`OnsetResult` live in
:mod:`designer.studies.dynamics._result` (re-exported here).
"""

from __future__ import annotations

import math

import numpy as np

from designer.boundary import Count, Quantity, checked
from designer.errors import InputError
from designer.model import Conditions, Design
from designer.units import real_number
from designer.physics.shimmy import steady_shimmy_amplitude
from designer.studies.dynamics._result import OnsetResult, SimulationResult
from designer.studies.dynamics._work import ARGUMENTS, bisect_speed, bounded, bracket_speed
from designer.studies.dynamics.limit_cycles._system import _integrate, caster_dynamics


def _check(name: str, value: float, allow_zero: bool = False) -> None:
    value = real_number(value, name)  # the boundary's one rule (numpy scalars pass, booleans do not)
    if value < 0 or (value == 0 and not allow_zero):
        raise InputError(f"{name} = {value:g}: must be {'non-negative' if allow_zero else 'positive'}")


@checked(
    **{k: ARGUMENTS[k] for k in ("design", "conditions")},
    speed=Quantity("speed"),
    angle=Quantity("angle", optional=True),
    angular_velocity=Quantity("angular_speed"),
    duration=Quantity("time", optional=True),
    cycles=Quantity("dimensionless"),
    angle_limit=Quantity("angle"),
    rtol=Quantity("dimensionless"),
    samples_per_period=Count(1, 100_000, what="steps a period"),
)
@bounded("shimmy simulation")
def simulate(  # long: its docstring documents every argument; the body (45 lines) is _knock, _integrate, measure
    design: Design,
    conditions: Conditions = Conditions(),
    speed: float = 2.5,
    angle: float | None = None,
    angular_velocity: float = 0.0,
    duration: float | None = None,
    cycles: float = 24.0,
    angle_limit: float = 1.0,
    rtol: float = 1e-8,
    samples_per_period: int = 40,
) -> SimulationResult:
    """Simulate caster shimmy after a knock, with Coulomb spindle friction (Appendix B).

    Integrates Eq. 3B/4B/6B with the spindle moment M_f sgn(θ') (module
    docstring) from θ = ``angle``, θ' = ``angular_velocity``, θ'' = 0
    (Eq. 24B), using scipy ``solve_ivp`` with exact stick–slip events.

    Parameters
    ----------
    design : Design
        T [m], d [m] (for I_w(d) of ``conditions.inertia``), B [m], c_f [N·m/rad].
    conditions : Conditions
        K_s [N], design θ0 [rad] (defines M_f = c_f θ0), inertia model, and
        ``dynamics`` (K [N/m], N [kg], Eq. 14B–15B).
    speed : float
        Wheelchair speed V [m/s].
    angle : float, optional
        Initial caster angle θ_i [rad]; default the design θ0 (20°).
    angular_velocity : float
        Initial θ'_i [rad/s] (Eq. 24B; App. C estimates 0.7 rad/s for Fig. 1C).
    duration : float, optional
        Simulated time [s]; default: the aligning transient (3T/V, at least
        one period) plus ``cycles`` periods of Eq. 15B.
    cycles : float
        Periods simulated after the transient when ``duration`` is None.
    angle_limit : float
        Stop when |θ| exceeds this [rad] (shimmy has grown; the small-angle
        model no longer applies).
    rtol : float
        Relative tolerance of ``solve_ivp``.
    samples_per_period : int
        Maximum step as a fraction of the Eq. 15B period (trace resolution; a stick, θ held, is kept at its ends).

    Returns
    -------
    SimulationResult
        Trace, amplitudes (late/θ_i and late/early), measured frequency, and
        the paper's predictions (Eq. 4/29B amplitude, Eq. 15B ω, Eq. 7 V_c).

    Raises
    ------
    InputError
        Non-positive trail, speed, diameter or inertia, negative groove or
        damping, non-finite values.
    WorkLimitError
        (exit 5) More than ``_work.MAX_EVALUATIONS`` evaluations of the equations of motion (a stiff
        case); a study that calls it shares its budget.
    """
    sys, theta_i, period, transient, duration = _knock(
        design, conditions, speed, angle, angular_velocity, duration, cycles, angle_limit
    )
    w0 = float(angular_velocity)
    run = _integrate(
        sys,
        sys.knock_state(theta_i, w0),
        duration,
        angle_limit=angle_limit,
        record=True,
        max_step=period / max(int(samples_per_period), 4),
        rtol=rtol,
        max_switches=200_000,
    )
    # the motion reverses where a slip starts in the other direction than the slip before (after a stick: on exit)
    ext = [(t, th) for (t, s, th), (_, before, _) in zip(run.slips[1:], run.slips) if s != before]
    ext = np.asarray(ext, dtype=float).reshape(-1, 2)
    diverged = run.reason == "limit"
    # the mean half peak-to-peak of the swings (between the reversals ``ext``) over two periods after the aligning
    # transient (early) and over the last two periods (late; ``angle_limit`` if |θ| reached it) [rad]
    half, half_times = np.abs(np.diff(ext[:, 1])) / 2, ext[1:, 0]  # the swings and when they end (none: empty)

    def window_amplitude(lo, hi, first_after=False):
        """Mean half peak-to-peak of the swings ending in [lo, hi] [rad]."""
        mask = (half_times >= lo) & (half_times <= hi)
        if mask.any():
            return float(half[mask].mean())
        if first_after and (half_times >= lo).any():
            return float(half[np.argmax(half_times >= lo)])
        return 0.0

    early = window_amplitude(transient, transient + 2 * period, first_after=True)
    late = float(angle_limit) if diverged else window_amplitude(run.time - 2 * period, run.time)
    # the shimmy frequency [rad/s] from the zero crossings of θ after the transient (NaN if fewer than three)
    cr = np.asarray(run.crossings)
    cr = cr[cr >= transient]
    frequency = float(math.pi / np.median(np.diff(cr)[(cr.size - 1) // 2 :])) if cr.size >= 3 else math.nan
    growth = late / early if early > 0 else (math.inf if late > 0 else 0.0)
    y = np.asarray(run.y, dtype=float).reshape(-1, 3)
    return SimulationResult(
        t=np.asarray(run.t),
        theta=y[:, 1],
        lateral=y[:, 0],
        speed=sys.speed,
        angle=theta_i,
        angular_velocity=w0,
        friction_moment=sys.friction_moment,
        inertia=sys.inertia,
        early_amplitude=early,
        late_amplitude=late,
        amplitude_ratio=late / theta_i,
        growth_ratio=float(growth),
        grows=bool(diverged or growth > 1.0),
        diverged=diverged,
        frequency=frequency,
        predicted_frequency=sys.frequency,
        predicted_amplitude=float(steady_shimmy_amplitude(sys.speed, sys.trail, sys.frequency, theta_i)),
        critical_speed=sys.eq7_speed(theta_i),  # c_f,eff = M_f/θ_i
        switches=run.switches,
        extrema=ext,
    )


def _knock(design: Design, conditions: Conditions, speed, angle, angular_velocity, duration, cycles, angle_limit):
    """The arguments of :func:`simulate` checked (InputError naming the value) and turned into the caster at its
    speed (:class:`~designer.studies.dynamics.limit_cycles._system.CasterDynamics`, M_f = c_f θ0_design), the
    knock θ_i [rad], the Eq. 15B period [s], the aligning transient (3T/V, at least a period) [s] and the time
    span [s]."""
    _check("speed", float(speed))
    theta_i = float(conditions.disturbance_angle) if angle is None else float(angle)
    _check("angle", theta_i)
    _check("angle_limit", float(angle_limit))
    _check("inertia", float(conditions.inertia(design.diameter)))
    sys = caster_dynamics(design, conditions, float(speed))
    period = 2 * math.pi / sys.frequency
    transient = max(3 * sys.trail / sys.speed, period)
    if duration is None:
        duration = transient + float(cycles) * period
    _check("duration", float(duration))
    return sys, theta_i, period, transient, float(duration)


@bounded("onset search")
def onset_speed(  # long: its docstring documents every argument and error; the body is bracket then bisect
    design: Design,
    conditions: Conditions = Conditions(),
    angle: float | None = None,
    angular_velocity: float = 0.0,
    rtol: float = 0.005,
    cycles: float = 16.0,
    bracket: tuple[float, float] | None = None,
    max_expansions: int = 8,
) -> OnsetResult:
    """Lowest speed at which a knock of θ_i grows into shimmy, by bisection [m/s].

    Each trial speed is classified by :func:`simulate` (``grows``: the
    oscillation amplitude over the last two periods exceeds the amplitude just
    after the aligning transient, or |θ| reached the angle limit).  The
    bracket starts at Eq. 7's V_c (with c_f,eff = M_f/θ_i) × [0.8, 1.25] and
    is widened ×2 within the model's speeds (0.01-100 m/s) until it holds a decaying and a growing
    speed; bisection in log V then stops when high/low − 1 < ``rtol``.  One work budget for all.

    Parameters
    ----------
    design, conditions : as :func:`simulate`
    angle : initial angle θ_i [rad] (default the design θ0 of the conditions)
    angular_velocity : initial θ'_i [rad/s]
    rtol : relative width of the final bracket [-]
    cycles : periods simulated after the transient at each trial speed
    bracket : optional starting (low, high) [m/s]
    max_expansions : how many times the bracket may be doubled outward

    Returns
    -------
    OnsetResult
        Onset speed and bracket beside Eq. 7 (and Eq. 4/29B amplitude, Eq.
        15B frequency at the onset).

    Raises
    ------
    SolverError
        No bracket (decay below, growth above) in the model's speeds and ``max_expansions`` doublings.
    """
    theta_i = float(conditions.disturbance_angle if angle is None else angle)
    _check("angle", theta_i)
    _check("rtol", float(rtol))
    cache: dict[float, SimulationResult] = {}  # one simulation a speed: len(cache) counts them

    def grows(v: float) -> bool:
        if v not in cache:
            cache[v] = simulate(design, conditions, v, angle=theta_i, angular_velocity=angular_velocity, cycles=cycles)
        return cache[v].grows

    v7 = caster_dynamics(design, conditions, 1.0).eq7_speed(theta_i)  # Eq. 7 with c_f,eff = M_f/θ_i
    if bracket is None:
        low, high = 0.8 * v7, 1.25 * v7
    else:
        low, high = (float(b) for b in bracket)
        _check("bracket low", low)
        _check("bracket high", high)
    low, high = bisect_speed(grows, *bracket_speed(grows, low, high, 2.0, max_expansions, v7, "shimmy onset"), rtol)
    speed = math.sqrt(low * high)
    at = cache[high]  # simulated: every bracket end was
    omega = at.predicted_frequency
    return OnsetResult(
        speed=speed,
        low=low,
        high=high,
        critical_speed=v7,
        relative_error=(speed - v7) / v7,
        angle=theta_i,
        evaluations=len(cache),
        amplitude_at_onset=at.early_amplitude,
        predicted_amplitude=float(steady_shimmy_amplitude(speed, design.trail, omega, theta_i)),
        frequency_at_onset=at.frequency,
        predicted_frequency=omega,
    )
