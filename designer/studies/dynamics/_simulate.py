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
* stick (θ' = 0, θ constant): X' = −V θ is integrated in closed form until
  |T K X| reaches M_f, then slip resumes in the direction of τ.

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

Layout: :func:`simulate` checks its arguments (:func:`_knock`), runs the stick–slip event loop
(:class:`_StickSlip`) and measures the amplitudes and the frequency; :func:`onset_speed` brackets and
bisects the onset.  The records :class:`SimulationResult` and :class:`OnsetResult` live in
:mod:`designer.studies.dynamics._result` (re-exported here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from designer.boundary import Count, Instance, Quantity, checked
from designer.errors import InputError, SolverError
from designer.model import Conditions, Design, critical_speed
from designer.units import real_number
from designer.physics.motion import (
    held_moment,
    knock_lateral,
    rolling_coefficients,
    rolling_field,
    stick_release,
    tread_coefficient,
)
from designer.physics.shimmy import shimmy_frequency, steady_shimmy_amplitude
from designer.studies.dynamics._result import OnsetResult, SimulationResult
from designer.studies.dynamics._work import SPEED_RANGE, bisect_speed, bounded, counted, spend


def _check(name: str, value: float, allow_zero: bool = False) -> None:
    value = real_number(value, name)  # the boundary's one rule (numpy scalars pass, booleans do not)
    if value < 0 or (value == 0 and not allow_zero):
        raise InputError(f"{name} = {value:g}: must be {'non-negative' if allow_zero else 'positive'}")


@dataclass(frozen=True)
class _Knock:
    """The constants of one integration (SI), from :func:`_knock`: trail T, spring K, speed V, friction moment
    M_f, the Eq. 12B coefficients J and visc = D of :func:`designer.physics.motion.rolling_coefficients`, the Eq. 15B period, the time
    span, the solver settings, the knock θ_i, I_w, the Eq. 15B ω, the aligning transient, B and K_s."""

    T: float
    K: float
    V: float
    M_f: float
    J: float
    visc: float
    period: float
    duration: float
    max_step: float
    angle_limit: float
    rtol: float
    theta_i: float
    inertia: float
    omega: float
    transient: float
    groove: float
    slip_coefficient: float

    def rhs(self, s):
        """The equations of motion (:func:`designer.physics.motion.rolling_field`) while slipping with sgn θ' = ``s``."""
        return rolling_field(s, self.T, self.K, self.V, self.M_f, self.J, self.visc)


class _StickSlip:
    """The event loop of :func:`simulate`: slip segments integrated by ``solve_ivp`` until θ' = 0, stick
    segments in closed form, until the end of the time span or |θ| reaches the angle limit.

    Collects the trace (``ts``, ``xs``, ``ths``), the zero crossings of θ, the reversals of the motion
    (``extrema``: (time, θ)), the number of stick/slip switches and whether |θ| reached the limit.
    """

    max_switches = 200_000

    def __init__(self, k: _Knock, w0: float):
        self.k = k
        theta_i = k.theta_i
        # Initial state, Eq. 24B: theta'' = 0 fixes X(0).
        s = float(np.sign(w0))
        x0 = knock_lateral(w0, k.M_f, k.T, k.K, k.visc)
        self.s = s
        self.y = np.array([x0, theta_i, w0])
        self.t = 0.0
        self.ts, self.xs, self.ths = [self.t], [x0], [theta_i]
        self.crossings: list[float] = []
        self.extrema: list[tuple[float, float]] = []  # (time, θ) where the motion reverses
        self.direction = s  # last direction of θ motion (0: none yet)
        self.switches = 0
        self.diverged = False
        self.graze = False  # last slip segment had zero length (θ' = 0 with |τ| ≈ M_f)
        angle_limit = k.angle_limit

        def limit_event(_t, y):
            return abs(y[1]) - angle_limit

        limit_event.terminal = True
        self.limit_event = limit_event

    def run(self) -> _StickSlip:
        """Integrate to the end (or the angle limit); returns self."""
        while self.t < self.k.duration and self.switches < self.max_switches:
            spend(10)  # a phase costs about ten evaluations more than its integration counts
            if self._stick() if self.s == 0.0 else self._slip():
                break
        return self

    def _stick(self) -> bool:
        """Stick: θ' = 0, θ constant, X' = −Vθ until |T K X| = M_f.  True when the run ends."""
        k, y, t = self.k, self.y, self.t
        T, K, V, M_f = k.T, k.K, k.V, k.M_f
        th = y[1]
        tau = held_moment(y[0], T, K)
        if abs(tau) > M_f and not self.graze:  # cannot stick: slip toward tau
            self.s = float(np.sign(tau))
        elif th == 0.0:
            t_end = k.duration  # aligned and held: rest for ever
            self.ts.append(t_end), self.xs.append(y[0]), self.ths.append(th)
            self.t = t_end
            return True
        else:
            x_exit = stick_release(th, M_f, T, K)
            dt = max((y[0] - x_exit) / (V * th), 0.0)
            t_end = min(t + dt, k.duration)
            for tt in np.linspace(t, t_end, max(2, int((t_end - t) / k.max_step) + 1))[1:]:
                self.ts.append(tt), self.xs.append(y[0] - V * th * (tt - t)), self.ths.append(th)
            self.y = np.array([y[0] - V * th * (t_end - t), th, 0.0])
            self.t = t_end
            if self.t >= k.duration:
                return True
            self.s = -math.copysign(1.0, th)
            self.switches += 1
        self.graze = False
        if self.s != self.direction and self.direction != 0.0:
            self.extrema.append((self.t, self.y[1]))
        self.direction = self.s
        return False

    def _slip(self) -> bool:
        """Slip with sgn θ' = s until θ' crosses zero (terminal event), then reverse or stick.  True when
        the run ends (end of the time span, or |θ| reached the angle limit)."""
        k, s, t = self.k, self.s, self.t

        def stop(_t, yy, s=s):
            return s * yy[2]

        stop.terminal = True
        stop.direction = -1

        def cross(_t, yy):
            return yy[1]

        from scipy.integrate import solve_ivp

        sol = solve_ivp(
            counted(k.rhs(s)),
            (t, k.duration),
            self.y,
            method="DOP853",
            rtol=k.rtol,
            atol=[1e-12, 1e-10, 1e-8],
            max_step=k.max_step,
            events=[stop, cross, self.limit_event],
        )
        if sol.status < 0:
            raise SolverError(f"shimmy simulation failed at t = {t:.4g} s: {sol.message}")
        self.ts.extend(sol.t[1:]), self.xs.extend(sol.y[0, 1:]), self.ths.extend(sol.y[1, 1:])
        self.crossings.extend(float(v) for v in sol.t_events[1])
        if sol.t_events[2].size:
            self.diverged = True
            self.t = float(sol.t_events[2][0])
            return True
        if sol.status == 0 or not sol.t_events[0].size:  # reached the end
            self.t = k.duration
            return True
        t_start = t
        t = self.t = float(sol.t_events[0][0])
        y = np.array(sol.y_events[0][0], dtype=float)
        y[2] = 0.0
        self.y = y
        self.switches += 1
        tau = held_moment(y[0], k.T, k.K)
        new = float(np.sign(tau)) if abs(tau) > k.M_f else 0.0
        if t - t_start <= 1e-9 * k.period:
            # Grazing: |τ| exceeds M_f by a rounding error and the slip ends at
            # once (its excursion is shorter than the first step).  The
            # physical motion is a stick; treat it so (error ~ rounding).
            new = 0.0
            self.graze = True
        if new == -s:
            self.extrema.append((t, y[1]))
            self.direction = new
        else:
            self.direction = s  # entering stick; extremum decided on exit
        self.s = new
        return False


@checked(
    design=Instance(
        (Design,), "a designer.Design, e.g. Design(trail='1.5 in', diameter='6 in', groove=0, damping=1.3)"
    ),
    conditions=Instance((Conditions,), "a designer.Conditions, e.g. Conditions(load=178)"),
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
def simulate(  # long: its docstring documents every argument; the body (30 lines) is _knock, _StickSlip, measure
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
        Maximum step as a fraction of the Eq. 15B period (trace resolution).

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
    k = _knock(
        design, conditions, speed, angle, angular_velocity, duration, cycles, angle_limit, rtol, samples_per_period
    )
    run = _StickSlip(k, float(angular_velocity)).run()
    ext = np.asarray(run.extrema, dtype=float).reshape(-1, 2)
    end = run.t if run.diverged else k.duration
    early, late = _amplitudes(ext, k.transient, k.period, end, run.diverged, angle_limit)
    growth = late / early if early > 0 else (math.inf if late > 0 else 0.0)
    c_eff = k.M_f / k.theta_i
    return SimulationResult(
        t=np.asarray(run.ts),
        theta=np.asarray(run.ths),
        lateral=np.asarray(run.xs),
        speed=k.V,
        angle=k.theta_i,
        angular_velocity=float(angular_velocity),
        friction_moment=k.M_f,
        inertia=k.inertia,
        early_amplitude=early,
        late_amplitude=late,
        amplitude_ratio=late / k.theta_i,
        growth_ratio=float(growth),
        grows=bool(run.diverged or growth > 1.0),
        diverged=run.diverged,
        frequency=_frequency(run.crossings, k.transient),
        predicted_frequency=k.omega,
        predicted_amplitude=float(steady_shimmy_amplitude(k.V, k.T, k.omega, k.theta_i)),
        critical_speed=float(critical_speed(k.T, k.inertia, k.groove, c_eff, k.slip_coefficient)),
        switches=run.switches,
        extrema=ext,
    )


def _knock(
    design: Design,
    conditions: Conditions,
    speed,
    angle,
    angular_velocity,
    duration,
    cycles,
    angle_limit,
    rtol,
    samples_per_period,
) -> _Knock:
    """The arguments of :func:`simulate` checked (InputError naming the value) and turned into the constants
    of the integration."""
    T, B, c_f = float(design.trail), float(design.groove), float(design.damping)
    _check("trail", T)
    _check("diameter", float(design.diameter))
    _check("groove", B, allow_zero=True)
    _check("damping", c_f, allow_zero=True)
    _check("speed", float(speed))
    theta_design = float(conditions.disturbance_angle)
    theta_i = theta_design if angle is None else float(angle)
    _check("angle", theta_i)
    if not math.isfinite(float(angular_velocity)):
        raise InputError(f"angular_velocity = {angular_velocity!r}: must be finite")
    _check("angle_limit", float(angle_limit))
    V = float(speed)
    inertia = float(conditions.inertia(design.diameter))
    _check("inertia", inertia)
    dyn = conditions.dynamics
    K, N = float(dyn.stiffness), float(dyn.lateral_mass)
    Ks = float(conditions.slip_coefficient)
    M_f = c_f * theta_design
    J, visc = rolling_coefficients(T, inertia, N, V, tread_coefficient(Ks, B))  # a3 and a2 − C_D of Eq. 12B
    omega = float(shimmy_frequency(T, inertia, dyn))
    period = 2 * math.pi / omega
    transient = max(3 * T / V, period)
    if duration is None:
        duration = transient + float(cycles) * period
    _check("duration", float(duration))
    duration = float(duration)
    max_step = period / max(int(samples_per_period), 4)
    return _Knock(
        T=T,
        K=K,
        V=V,
        M_f=M_f,
        J=J,
        visc=visc,
        period=period,
        duration=duration,
        max_step=max_step,
        angle_limit=angle_limit,
        rtol=rtol,
        theta_i=theta_i,
        inertia=inertia,
        omega=omega,
        transient=transient,
        groove=B,
        slip_coefficient=Ks,
    )


def _amplitudes(ext: np.ndarray, transient: float, period: float, end: float, diverged: bool, angle_limit):
    """(early, late) amplitude [rad]: the mean half peak-to-peak of the swings (between the reversals
    ``ext``) over two periods after the aligning transient and over the last two periods (``angle_limit``
    if |θ| reached it)."""
    half = np.abs(np.diff(ext[:, 1])) / 2 if ext.shape[0] >= 2 else np.empty(0)
    half_times = ext[1:, 0] if ext.shape[0] >= 2 else np.empty(0)

    def window_amplitude(lo, hi, first_after=False):
        """Mean half peak-to-peak of the swings ending in [lo, hi] [rad]."""
        mask = (half_times >= lo) & (half_times <= hi)
        if mask.any():
            return float(half[mask].mean())
        if first_after and (half_times >= lo).any():
            return float(half[np.argmax(half_times >= lo)])
        return 0.0

    early = window_amplitude(transient, transient + 2 * period, first_after=True)
    if diverged:
        late = float(angle_limit)
    else:
        late = window_amplitude(end - 2 * period, end)
    return early, late


def _frequency(crossings: list[float], transient: float) -> float:
    """Measured shimmy frequency [rad/s] from the zero crossings of θ after the transient (NaN if fewer
    than three)."""
    cr = np.asarray(crossings)
    cr = cr[cr >= transient]
    if cr.size >= 3:
        half_periods = np.diff(cr)
        return float(math.pi / np.median(half_periods[len(half_periods) // 2 :]))
    return math.nan


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
    evaluations = 0
    cache: dict[float, SimulationResult] = {}

    def run(v: float) -> SimulationResult:
        nonlocal evaluations
        if v not in cache:
            evaluations += 1
            cache[v] = simulate(design, conditions, v, angle=theta_i, angular_velocity=angular_velocity, cycles=cycles)
        return cache[v]

    inertia = float(conditions.inertia(design.diameter))
    c_eff = float(design.damping) * float(conditions.disturbance_angle) / theta_i  # M_f / θ_i
    v7 = float(critical_speed(design.trail, inertia, design.groove, c_eff, conditions.slip_coefficient))
    if bracket is None:
        low, high = 0.8 * v7, 1.25 * v7
    else:
        low, high = (float(b) for b in bracket)
        _check("bracket low", low)
        _check("bracket high", high)
    low, high = bisect_speed(lambda v: run(v).grows, *_bracket(run, low, high, max_expansions, v7), rtol)
    speed = math.sqrt(low * high)
    at = run(high)
    omega = at.predicted_frequency
    return OnsetResult(
        speed=speed,
        low=low,
        high=high,
        critical_speed=v7,
        relative_error=(speed - v7) / v7,
        angle=theta_i,
        evaluations=evaluations,
        amplitude_at_onset=at.early_amplitude,
        predicted_amplitude=float(steady_shimmy_amplitude(speed, design.trail, omega, theta_i)),
        frequency_at_onset=at.frequency,
        predicted_frequency=omega,
    )


def _bracket(run, low: float, high: float, max_expansions: int, v7: float) -> tuple[float, float]:
    """Widen (low, high) [m/s] ×2 outward, inside :data:`SPEED_RANGE`, until the knock decays at ``low`` and
    grows at ``high`` (``run(v)`` simulates at speed v); SolverError when that takes more than
    ``max_expansions`` doublings or would leave the model's speeds."""
    v_min, v_max = SPEED_RANGE
    low, high = min(max(low, v_min), v_max), min(max(high, v_min), v_max)
    for _ in range(max_expansions):
        if run(low).grows:
            if low <= v_min:
                raise SolverError(
                    f"shimmy onset below {v_min:g} m/s, the model's lowest speed: the knock grows there already "
                    f"(Eq. 7 gives {v7:.3g} m/s)"
                )
            high, low = low, max(low / 2, v_min)
            continue
        if not run(high).grows:
            if high >= v_max:
                raise SolverError(
                    f"no shimmy onset up to {v_max:g} m/s, the model's highest speed: the knock decays there "
                    f"(Eq. 7 gives {v7:.3g} m/s); the caster does not shimmy at any speed the model covers"
                )
            low, high = high, min(high * 2, v_max)
            continue
        break
    else:
        raise SolverError(
            f"shimmy onset not bracketed after {max_expansions} doublings (last bracket {low:.3g}–{high:.3g} m/s, "
            f"Eq. 7 gives {v7:.3g} m/s)"
        )
    if run(low).grows or not run(high).grows:
        raise SolverError(f"shimmy onset not bracketed in {low:.3g}–{high:.3g} m/s (Eq. 7 gives {v7:.3g} m/s)")
    return low, high
