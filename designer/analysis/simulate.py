"""Time-domain shimmy simulation with true Coulomb spindle friction (Appendix B, issue 7).

Eq. 7 is a *describing-function* result: the paper replaces the spindle's
constant friction moment M_f by the hydraulic damper that dissipates the same
work per cycle (Eq. 6 = 3C, C_D = 4 M_f/(π θ_a ω)), takes the shimmy
amplitude from the linear transient at the threshold (Eq. 4 / 29B,
θ_a = θ0 V/(ω T)) and applies Routh–Hurwitz to the linear third-order model
(Eq. 12B, 20B).  This module integrates the nonlinear model instead, so the
approximation can be checked.

Equations integrated
--------------------
Two-degree-of-freedom model of Fig. 1B (lateral spindle displacement X [m],
caster angle θ [rad]).  Eq. 3B and 4B, with F_N eliminated (Eq. 5B) and the
mass distribution of Eq. 9B–11B (wheel mass at the contact point, fork mass at
the spindle, so I_G − a b M_C = I_w and the wheel mass drops out), give

    T K X + T N X'' = I_w θ'' + M_f sgn(θ') + (K_s B²/(2V)) θ'          (5B')

with N = M_F + M_1 (Eq. 14B) and, unlike Eq. 4B, the spindle moment is the
Coulomb friction M_f sgn(θ') instead of C_D θ'.  The tyre rolls without
lateral slip, Eq. 6B:  X' = −T θ' − V θ, hence X'' = −T θ'' − V θ' (Eq. 7B).
Substituting, the state (X, θ, θ') obeys the first-order system

    X'  = −T θ' − V θ
    θ'' = [ T K X − (N T V + K_s B²/(2V)) θ' − M_f sgn(θ') ] / (I_w + N T²)

Differentiating the second line once and using the first gives Eq. 12B with
C_D θ'' replaced by d/dt(M_f sgn θ'): the paper's third-order equation is the
same model.  (The constraint Eq. 6B makes X' a function of θ and θ', so the
"two degrees of freedom" have three states, not four.)

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
"""
from __future__ import annotations

import csv
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from designer.data.paper import INCH
from designer.errors import InputError, SolverError
from designer.model import Conditions, Design
from designer.physics.inertia import Fixed
from designer.physics.shimmy import critical_shimmy_speed, shimmy_frequency, steady_shimmy_amplitude

__all__ = [
    "SimulationResult",
    "OnsetResult",
    "simulate",
    "onset_speed",
    "simulation_report_cases",
    "write_simulation_report",
]


@dataclass
class SimulationResult:
    """Outcome of one shimmy simulation (all SI).

    Attributes
    ----------
    t, theta, lateral : arrays
        Time [s], caster angle θ(t) [rad] and spindle displacement X(t) [m].
    speed : wheelchair speed V [m/s]
    angle, angular_velocity : initial θ_i [rad] and θ'_i [rad/s] (Eq. 24B)
    friction_moment : M_f = c_f θ0_design [N·m]
    inertia : I_w [kg·m²]
    early_amplitude : mean half peak-to-peak of θ over two periods just after
        the aligning transient (t ≳ 3T/V) [rad]
    late_amplitude : the same over the last two periods [rad]
    amplitude_ratio : late_amplitude / θ_i [-] (Eq. 29B predicts V/(ωT) at
        the threshold)
    growth_ratio : late_amplitude / early_amplitude [-]; > 1 is shimmy
    grows : True if the oscillation grows (growth_ratio > 1 or |θ| reached
        ``angle_limit``)
    diverged : True if |θ| reached ``angle_limit`` (simulation stopped)
    frequency : measured shimmy frequency [rad/s] from zero crossings of θ
    predicted_frequency : ω of Eq. 15B [rad/s]
    predicted_amplitude : θ_i V/(ω T) of Eq. 4 / 29B [rad] (Eq. 15B ω)
    critical_speed : Eq. 7 with c_f,eff = M_f/θ_i [m/s]
    switches : number of stick/slip transitions handled
    """

    t: np.ndarray
    theta: np.ndarray
    lateral: np.ndarray
    speed: float
    angle: float
    angular_velocity: float
    friction_moment: float
    inertia: float
    early_amplitude: float
    late_amplitude: float
    amplitude_ratio: float
    growth_ratio: float
    grows: bool
    diverged: bool
    frequency: float
    predicted_frequency: float
    predicted_amplitude: float
    critical_speed: float
    switches: int
    extrema: np.ndarray = field(repr=False, default_factory=lambda: np.empty((0, 2)))

    def as_dict(self, with_trace: bool = False) -> dict:
        """Scalars (and optionally the trace) as plain Python types."""
        out = {
            "speed": self.speed,
            "angle": self.angle,
            "angular_velocity": self.angular_velocity,
            "friction_moment": self.friction_moment,
            "inertia": self.inertia,
            "amplitude_ratio": self.amplitude_ratio,
            "growth_ratio": self.growth_ratio,
            "early_amplitude": self.early_amplitude,
            "late_amplitude": self.late_amplitude,
            "grows": bool(self.grows),
            "diverged": bool(self.diverged),
            "frequency": self.frequency,
            "predicted_frequency": self.predicted_frequency,
            "predicted_amplitude": self.predicted_amplitude,
            "critical_speed": self.critical_speed,
            "switches": self.switches,
        }
        if with_trace:
            out["t"] = self.t.tolist()
            out["theta"] = self.theta.tolist()
        return out


def _check(name: str, value: float, allow_zero: bool = False) -> None:
    if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
        raise InputError(f"{name} = {value!r}: must be a finite number")
    if value < 0 or (value == 0 and not allow_zero):
        raise InputError(f"{name} = {value:g}: must be {'non-negative' if allow_zero else 'positive'}")


def simulate(  # noqa: C901 - input checks and the stick/slip event loop of one integration
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
    """
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
    J = inertia + N * T**2                       # a3 of Eq. 12B
    visc = N * T * V + Ks * B**2 / (2 * V)       # a2 of Eq. 12B without C_D
    omega = float(shimmy_frequency(T, inertia, dyn))
    period = 2 * math.pi / omega
    transient = max(3 * T / V, period)
    if duration is None:
        duration = transient + float(cycles) * period
    _check("duration", float(duration))
    duration = float(duration)
    max_step = period / max(int(samples_per_period), 4)

    def rhs(s):
        def f(_t, y):
            x, th, w = y
            return [-T * w - V * th, w, (T * K * x - visc * w - s * M_f) / J]
        return f

    def limit_event(_t, y):
        return abs(y[1]) - angle_limit
    limit_event.terminal = True

    # Initial state, Eq. 24B: theta'' = 0 fixes X(0).
    w0 = float(angular_velocity)
    s = float(np.sign(w0))
    x0 = (visc * w0 + s * M_f) / (T * K)
    y = np.array([x0, theta_i, w0])
    t = 0.0
    ts, xs, ths = [t], [x0], [theta_i]
    crossings: list[float] = []
    extrema: list[tuple[float, float]] = []   # (time, θ) where the motion reverses
    direction = s                              # last direction of θ motion (0: none yet)
    switches = 0
    diverged = False
    max_switches = 200_000
    graze = False        # last slip segment had zero length (θ' = 0 with |τ| ≈ M_f)

    while t < duration and switches < max_switches:
        if s == 0.0:
            # Stick: θ' = 0, θ constant, X' = −Vθ until |T K X| = M_f.
            th = y[1]
            tau = T * K * y[0]
            if abs(tau) > M_f and not graze:   # cannot stick: slip toward tau
                s = float(np.sign(tau))
            elif th == 0.0:
                t_end = duration        # aligned and held: rest for ever
                ts.append(t_end), xs.append(y[0]), ths.append(th)
                t = t_end
                break
            else:
                x_exit = -math.copysign(M_f, th) / (T * K)
                dt = max((y[0] - x_exit) / (V * th), 0.0)
                t_end = min(t + dt, duration)
                for tt in np.linspace(t, t_end, max(2, int((t_end - t) / max_step) + 1))[1:]:
                    ts.append(tt), xs.append(y[0] - V * th * (tt - t)), ths.append(th)
                y = np.array([y[0] - V * th * (t_end - t), th, 0.0])
                t = t_end
                if t >= duration:
                    break
                s = -math.copysign(1.0, th)
                switches += 1
            graze = False
            if s != direction and direction != 0.0:
                extrema.append((t, y[1]))
            direction = s
            continue

        def stop(_t, yy, s=s):
            return s * yy[2]
        stop.terminal = True
        stop.direction = -1

        def cross(_t, yy):
            return yy[1]

        sol = solve_ivp(rhs(s), (t, duration), y, method="DOP853", rtol=rtol, atol=[1e-12, 1e-10, 1e-8],
                        max_step=max_step, events=[stop, cross, limit_event])
        if sol.status < 0:
            raise SolverError(f"shimmy simulation failed at t = {t:.4g} s: {sol.message}")
        ts.extend(sol.t[1:]), xs.extend(sol.y[0, 1:]), ths.extend(sol.y[1, 1:])
        crossings.extend(float(v) for v in sol.t_events[1])
        if sol.t_events[2].size:
            diverged = True
            t = float(sol.t_events[2][0])
            break
        if sol.status == 0 or not sol.t_events[0].size:   # reached the end
            t = duration
            break
        t_start = t
        t = float(sol.t_events[0][0])
        y = np.array(sol.y_events[0][0], dtype=float)
        y[2] = 0.0
        switches += 1
        tau = T * K * y[0]
        new = float(np.sign(tau)) if abs(tau) > M_f else 0.0
        if t - t_start <= 1e-9 * period:
            # Grazing: |τ| exceeds M_f by a rounding error and the slip ends at
            # once (its excursion is shorter than the first step).  The
            # physical motion is a stick; treat it so (error ~ rounding).
            new = 0.0
            graze = True
        if new == -s:
            extrema.append((t, y[1]))
            direction = new
        else:
            direction = s          # entering stick; extremum decided on exit
        s = new

    t_arr, th_arr, x_arr = np.asarray(ts), np.asarray(ths), np.asarray(xs)
    ext = np.asarray(extrema, dtype=float).reshape(-1, 2)
    end = t if diverged else duration

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
    growth = late / early if early > 0 else (math.inf if late > 0 else 0.0)
    grows = bool(diverged or growth > 1.0)

    cr = np.asarray(crossings)
    cr = cr[cr >= transient]
    if cr.size >= 3:
        half_periods = np.diff(cr)
        frequency = float(math.pi / np.median(half_periods[len(half_periods) // 2:]))
    else:
        frequency = math.nan

    c_eff = M_f / theta_i
    v7 = float(critical_shimmy_speed(T, inertia, B, c_eff, Ks))
    return SimulationResult(
        t=t_arr, theta=th_arr, lateral=x_arr, speed=V, angle=theta_i, angular_velocity=float(angular_velocity),
        friction_moment=M_f, inertia=inertia, early_amplitude=early, late_amplitude=late,
        amplitude_ratio=late / theta_i, growth_ratio=float(growth), grows=grows, diverged=diverged,
        frequency=frequency, predicted_frequency=omega,
        predicted_amplitude=float(steady_shimmy_amplitude(V, T, omega, theta_i)),
        critical_speed=v7, switches=switches, extrema=ext,
    )


@dataclass
class OnsetResult:
    """Simulated shimmy onset speed beside Eq. 7.

    Attributes
    ----------
    speed : simulated onset speed [m/s] (geometric mean of the final bracket)
    low, high : final bracket [m/s]: the knock decays at ``low``, grows at ``high``
    critical_speed : Eq. 7 with c_f,eff = M_f/θ_i [m/s]
    relative_error : (speed − critical_speed)/critical_speed [-]
    angle : initial angle θ_i [rad]
    evaluations : number of simulations run
    amplitude_at_onset : early shimmy amplitude simulated at ``high`` [rad]
    predicted_amplitude : Eq. 4 / 29B amplitude θ_i V/(ω T) at ``speed`` [rad]
    frequency_at_onset : measured ω at ``high`` [rad/s]
    predicted_frequency : Eq. 15B ω [rad/s]
    """

    speed: float
    low: float
    high: float
    critical_speed: float
    relative_error: float
    angle: float
    evaluations: int
    amplitude_at_onset: float
    predicted_amplitude: float
    frequency_at_onset: float
    predicted_frequency: float

    def __float__(self) -> float:
        return float(self.speed)

    def as_dict(self) -> dict:
        """All fields as plain floats."""
        return {k: (float(v) if not isinstance(v, int) else v) for k, v in self.__dict__.items()}


# long: input checks, bracketing and bisection of the shimmy onset in one search
def onset_speed(
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
    is widened ×2 until it holds a decaying and a growing speed; bisection in
    log V then stops when high/low − 1 < ``rtol``.

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
        If no bracket with decay below and growth above is found.
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
            cache[v] = simulate(design, conditions, v, angle=theta_i, angular_velocity=angular_velocity,
                                cycles=cycles)
        return cache[v]

    inertia = float(conditions.inertia(design.diameter))
    c_eff = float(design.damping) * float(conditions.disturbance_angle) / theta_i     # M_f / θ_i
    v7 = float(critical_shimmy_speed(design.trail, inertia, design.groove, c_eff, conditions.slip_coefficient))
    if bracket is None:
        low, high = 0.8 * v7, 1.25 * v7
    else:
        low, high = (float(b) for b in bracket)
        _check("bracket low", low)
        _check("bracket high", high)
    for _ in range(max_expansions):
        if run(low).grows:
            high, low = low, low / 2
            continue
        if not run(high).grows:
            low, high = high, high * 2
            continue
        break
    else:
        raise SolverError(
            f"shimmy onset not bracketed after {max_expansions} doublings (last bracket {low:.3g}–{high:.3g} m/s, "
            f"Eq. 7 gives {v7:.3g} m/s)"
        )
    if run(low).grows or not run(high).grows:
        raise SolverError(f"shimmy onset not bracketed in {low:.3g}–{high:.3g} m/s (Eq. 7 gives {v7:.3g} m/s)")
    while high / low - 1 > rtol:
        mid = math.sqrt(low * high)
        if run(mid).grows:
            high = mid
        else:
            low = mid
    speed = math.sqrt(low * high)
    at = run(high)
    omega = at.predicted_frequency
    return OnsetResult(
        speed=speed, low=low, high=high, critical_speed=v7, relative_error=(speed - v7) / v7, angle=theta_i,
        evaluations=evaluations, amplitude_at_onset=at.early_amplitude,
        predicted_amplitude=float(steady_shimmy_amplitude(speed, design.trail, omega, theta_i)),
        frequency_at_onset=at.frequency, predicted_frequency=omega,
    )


# ---------------------------------------------------------------------------
# Comparison report: simulated onset vs Eq. 7 over a grid (results/simulation)

REPORT_TRAILS = (1.0 * INCH, 2.0 * INCH, 3.0 * INCH)
"""Trails of the report grid [m] (1, 2, 3 in)."""
REPORT_INERTIAS = (0.33e-3, 1.27e-3, 3.42e-3)
"""Wheel inertias of the report grid [kg·m²]: Table 1 wheel B, the Eq. 8 wheel, Table 1 wheel G."""
REPORT_GROOVES = (0.0, 9 / 16 * INCH)
"""Groove widths of the report grid [m]: single tread and Eq. 8's 9/16 in."""
REPORT_ANGLES = (math.radians(10.0), math.radians(20.0), math.radians(40.0))
"""Initial (knock) angles θ_i of the report grid [rad]."""


def simulation_report_cases():
    """The grid of the comparison report: (T [m], I_w [kg·m²], B [m], θ_i [rad]) tuples.

    3 trails × 3 inertias × 2 grooves × 3 angles = 54 cases, bare fork
    c_f = 1.3 N·m/rad (Eq. 11C) defined at θ0 = 20°, K_s = 1250 N.
    """
    return [(T, I, B, a) for T in REPORT_TRAILS for I in REPORT_INERTIAS for B in REPORT_GROOVES
            for a in REPORT_ANGLES]


def _report_row(trail, inertia, groove, angle, conditions, damping, rtol):
    from designer.data.paper import BARE_FORK_DAMPING  # noqa: F401  (documented default)

    cond = conditions.replace(inertia=Fixed(inertia))
    design = Design(trail=trail, diameter=0.2, groove=groove, damping=damping)
    onset = onset_speed(design, cond, angle=angle, rtol=rtol)
    omega = onset.predicted_frequency
    groove_share = float(critical_shimmy_speed(trail, inertia, groove, 0.0, cond.slip_coefficient) ** 2
                         / onset.critical_speed**2)
    return {
        "trail_in": trail / INCH,
        "inertia_kgm2": inertia,
        "groove_in": groove / INCH,
        "angle_deg": math.degrees(angle),
        "eq7_critical_speed": onset.critical_speed,
        "onset_speed": onset.speed,
        "onset_low": onset.low,
        "onset_high": onset.high,
        "relative_error": onset.relative_error,
        "omega_eq15b": omega,
        "omega_T_over_V": omega * trail / onset.critical_speed,
        "groove_share": groove_share,
        "amplitude_sim": onset.amplitude_at_onset,
        "amplitude_eq29b": onset.predicted_amplitude,
        "amplitude_error": onset.amplitude_at_onset / onset.predicted_amplitude - 1,
        "frequency_sim": onset.frequency_at_onset,
        "frequency_error": onset.frequency_at_onset / omega - 1,
        "simulations": onset.evaluations,
    }


def write_simulation_report(out_dir="results/simulation", conditions: Conditions = Conditions(),
                            damping: float = 1.3, rtol: float = 0.005, progress=None) -> dict:
    """Write the simulated-onset vs Eq. 7 comparison to ``out_dir``.

    Files: ``onset.csv`` and ``onset.json`` (one row per case of
    :func:`simulation_report_cases`), ``report.md`` (table, where the
    describing-function approximation holds and where it breaks, Eq. 4/29B
    amplitude and Eq. 15B frequency checks) and ``onset.png`` (simulated vs
    Eq. 7 onset; error against ωT/V_c; amplitude vs Eq. 29B; θ(t) traces of
    the Appendix C case below, near and above onset, as Fig. 1C).

    Parameters
    ----------
    out_dir : directory to (re)write [created if missing]
    conditions : K_s [N], θ0 [rad], dynamics (K, N); inertia is set per case
    damping : c_f = M_f/θ0 [N·m/rad] of every case (bare fork 1.3, Eq. 11C)
    rtol : relative width of each onset bracket
    progress : optional callable(i, n) for progress display

    Returns
    -------
    dict
        ``rows`` (list of dicts) and ``summary`` (error statistics).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cases = simulation_report_cases()
    rows = []
    start = time.perf_counter()
    for i, (T, I, B, a) in enumerate(cases):
        rows.append(_report_row(T, I, B, a, conditions, damping, rtol))
        if progress is not None:
            progress(i + 1, len(cases))
    elapsed = time.perf_counter() - start

    # Appendix C reference case (Fig. 1C): T = 2.5 in, I_w from V_c = 2.53 m/s via Eq. 7, θ0 = 20°.
    from designer.data.paper import APPENDIX_C_CASE, BARE_FORK_DAMPING

    case = APPENDIX_C_CASE
    i_c = 4 * BARE_FORK_DAMPING * case.trail**2 / (math.pi * case.critical_speed**2)
    cond_c = conditions.replace(inertia=Fixed(i_c))
    design_c = Design(trail=case.trail, diameter=0.2, groove=0.0, damping=BARE_FORK_DAMPING)
    onset_c = onset_speed(design_c, cond_c, angle=case.initial_angle, rtol=rtol / 5)
    onset_c_kick = onset_speed(design_c, cond_c, angle=case.initial_angle, angular_velocity=0.7, rtol=rtol / 5)
    traces = {f: simulate(design_c, cond_c, f * onset_c.speed, angle=case.initial_angle, cycles=20, angle_limit=0.6)
              for f in (0.9, 1.0, 1.1)}

    summary = _summarise(rows)
    summary.update({
        "cases": len(rows),
        "seconds": elapsed,
        "appendix_c": {
            "inertia": i_c, "eq7_critical_speed": onset_c.critical_speed, "onset_speed": onset_c.speed,
            "relative_error": onset_c.relative_error,
            "onset_speed_with_0.7_rad_per_s": onset_c_kick.speed,
            "amplitude_sim": onset_c.amplitude_at_onset, "amplitude_eq29b": onset_c.predicted_amplitude,
            "paper_amplitude": case.steady_amplitude,
            "frequency_sim": onset_c.frequency_at_onset, "frequency_eq15b": onset_c.predicted_frequency,
        },
        "conditions": {"damping": damping, "design_angle": conditions.disturbance_angle,
                       "slip_coefficient": conditions.slip_coefficient,
                       "frame_stiffness": conditions.dynamics.stiffness,
                       "lateral_mass": conditions.dynamics.lateral_mass, "bracket_rtol": rtol},
    })
    fields = list(rows[0])
    with open(out / "onset.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
    (out / "onset.json").write_text(json.dumps({"summary": summary, "rows": rows}, indent=2))
    _plot_report(rows, traces, onset_c, out / "onset.png")
    (out / "report.md").write_text(_report_markdown(rows, summary))
    return {"rows": rows, "summary": summary}


def _summarise(rows) -> dict:
    err = np.array([r["relative_error"] for r in rows])
    wtv = np.array([r["omega_T_over_V"] for r in rows])
    share = np.array([r["groove_share"] for r in rows])
    amp = np.array([r["amplitude_error"] for r in rows])
    freq = np.array([r["frequency_error"] for r in rows])
    grooved = share > 0

    def stats(mask):
        if not mask.any():
            return None
        e = err[mask]
        return {"n": int(mask.sum()), "max_abs_error": float(np.abs(e).max()), "mean_error": float(e.mean()),
                "min_error": float(e.min()), "max_error": float(e.max())}

    trail = np.array([r["trail_in"] for r in rows])
    inertia = np.array([r["inertia_kgm2"] for r in rows])
    implied = (1 + amp) ** -0.5 - 1
    single = {f"T={t:.0f}in,I_w={i:.3g}": stats(~grooved & np.isclose(trail, t) & np.isclose(inertia, i))
              for t in sorted(set(np.round(trail, 6))) for i in sorted(set(inertia))}
    return {
        "single_tread_by_trail_inertia": single,
        "error_minus_amplitude_implied": {"max_abs_single_tread": float(np.abs(err - implied)[~grooved].max()),
                                          "median_abs_single_tread": float(np.median(np.abs(err - implied)[~grooved])),
                                          "max_abs_all": float(np.abs(err - implied).max())},
        "all": stats(np.ones_like(err, bool)),
        "omega_T_over_V_ge_2": stats(wtv >= 2),
        "omega_T_over_V_lt_2": stats(wtv < 2),
        "groove_share_ge_0.5": stats(share >= 0.5),
        "single_tread": stats(~grooved),
        "single_tread_omega_T_over_V_ge_2": stats(~grooved & (wtv >= 2)),
        "amplitude_error_single_tread": {"min": float(amp[~grooved].min()), "max": float(amp[~grooved].max())},
        "amplitude_error_grooved": {"min": float(amp[grooved].min()), "max": float(amp[grooved].max())},
        "frequency_error": {"min": float(np.nanmin(freq)), "max": float(np.nanmax(freq))},
    }


def _plot_report(rows, traces, onset_c, path: Path) -> None:
    # late import: loads matplotlib only when this runs
    import matplotlib

    matplotlib.use("Agg")
    # late import: loads matplotlib only when this runs
    import matplotlib.pyplot as plt

    v7 = np.array([r["eq7_critical_speed"] for r in rows])
    vs = np.array([r["onset_speed"] for r in rows])
    err = 100 * np.array([r["relative_error"] for r in rows])
    grooved = np.array([r["groove_in"] > 0 for r in rows])
    ang = np.array([r["angle_deg"] for r in rows])
    amp_s = np.array([r["amplitude_sim"] for r in rows])
    amp_p = np.array([r["amplitude_eq29b"] for r in rows])
    markers = {10.0: "v", 20.0: "o", 40.0: "^"}

    fig, axes = plt.subplots(2, 2, figsize=(12, 9.5))
    ax = axes[0, 0]
    lim = (0.8 * min(v7.min(), vs.min()), 1.2 * max(v7.max(), vs.max()))
    xx = np.geomspace(*lim, 50)
    ax.fill_between(xx, 0.9 * xx, 1.1 * xx, color="0.9", label="±10 %")
    ax.plot(xx, xx, "k-", lw=1, label="simulated = Eq. 7")
    for g, colour, label in ((False, "tab:blue", "B = 0"), (True, "tab:orange", "B = 9/16 in")):
        for a, m in markers.items():
            sel = (grooved == g) & np.isclose(ang, a)
            ax.scatter(v7[sel], vs[sel], marker=m, color=colour, s=36, edgecolor="k", lw=0.4,
                       label=f"{label}, θ_i = {a:.0f}°")
    ax.set_xscale("log"), ax.set_yscale("log")
    ax.set_xlim(lim), ax.set_ylim(lim)
    ax.set_xlabel("Eq. 7 critical speed V_c [m/s] (c_f,eff = M_f/θ_i)")
    ax.set_ylabel("simulated onset speed [m/s]")
    ax.set_title("(a) Coulomb-friction simulation vs Eq. 7")
    ax.legend(fontsize=7, ncol=2, loc="upper left")

    ax = axes[0, 1]
    implied = 100 * ((1 + np.array([r["amplitude_error"] for r in rows])) ** -0.5 - 1)
    lo, hi = min(implied.min(), err.min()) - 2, max(implied.max(), err.max()) + 2
    ax.axhspan(-10, 10, color="0.9")
    ax.plot([lo, hi], [lo, hi], "k-", lw=1, label="error = (θ_a,29B / θ_a,sim)^½ − 1")
    for g, colour, _label in ((False, "tab:blue", "B = 0"), (True, "tab:orange", "B = 9/16 in")):
        for a, m in markers.items():
            sel = (grooved == g) & np.isclose(ang, a)
            ax.scatter(implied[sel], err[sel], marker=m, color=colour, s=36, edgecolor="k", lw=0.4)
    ax.set_xlim(lo, hi), ax.set_ylim(lo, hi)
    ax.set_xlabel("error implied by the amplitude of Eq. 29B: (θ_a,29B/θ_a,sim)^½ − 1 [%]")
    ax.set_ylabel("onset error (simulated − Eq. 7)/Eq. 7 [%]")
    ax.set_title("(b) Eq. 7's error comes from Eq. 29B's amplitude")
    ax.legend(fontsize=8, loc="upper left")

    ax = axes[1, 0]
    top = 1.1 * max(amp_s.max(), amp_p.max())
    ax.plot([0, top], [0, top], "k-", lw=1)
    for g, colour in ((False, "tab:blue"), (True, "tab:orange")):
        for a, m in markers.items():
            sel = (grooved == g) & np.isclose(ang, a)
            ax.scatter(amp_p[sel], amp_s[sel], marker=m, color=colour, s=36, edgecolor="k", lw=0.4)
    ax.set_xlim(0, top), ax.set_ylim(0, top)
    ax.set_xlabel("Eq. 4 / 29B amplitude θ_i V/(ωT) at onset [rad]")
    ax.set_ylabel("simulated amplitude after the transient [rad]")
    ax.set_title("(c) shimmy amplitude at onset (blue B = 0, orange grooved)")

    ax = axes[1, 1]
    for f, colour in ((0.9, "tab:green"), (1.0, "tab:gray"), (1.1, "tab:red")):
        r = traces[f]
        ax.plot(r.t, np.degrees(r.theta), color=colour, lw=1,
                label=f"V = {r.speed:.2f} m/s ({f:.1f} × onset): {'grows' if r.grows else 'decays'}")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("caster angle θ [deg]")
    ax.set_title(f"(d) Appendix C caster (T = 2.5 in, θ_i = 20°): onset {onset_c.speed:.2f} m/s, "
                 f"Eq. 7 {onset_c.critical_speed:.2f} m/s", fontsize=9)
    ax.legend(fontsize=8, loc="lower right")
    fig.suptitle("Time-domain shimmy with Coulomb spindle friction vs the describing-function Eq. 7", fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _pct(x) -> str:
    return f"{100 * x:+.1f} %"


# long: the report's text, one line per statement
def _report_markdown(rows, summary) -> str:
    s = summary
    ac = s["appendix_c"]
    c = s["conditions"]

    def line(key, text):
        st = s.get(key)
        if not st:
            return f"- {text}: no cases\n"
        return (f"- {text} ({st['n']} cases): error {_pct(st['min_error'])} to {_pct(st['max_error'])}, "
                f"max |error| {100 * st['max_abs_error']:.1f} %\n")

    md = ["# Simulated shimmy onset vs Eq. 7\n\n",
          "Generated by `designer simulate --report results/simulation` "
          "(`designer.analysis.simulate.write_simulation_report`).\n\n",
          "## Model\n\n",
          "Two-degree-of-freedom caster of Appendix B (Eq. 3B, 4B, 6B, masses of Eq. 9B–11B), state "
          "(X, θ, θ'), with the spindle moment a true Coulomb friction M_f sgn(θ') integrated with exact "
          "stick–slip events (scipy `solve_ivp`, DOP853, rtol 1e-8):\n\n",
          "    X'  = −T θ' − V θ\n",
          "    θ'' = [T K X − (N T V + K_s B²/(2V)) θ' − M_f sgn θ'] / (I_w + N T²)\n\n",
          f"K = {c['frame_stiffness']:.0f} N/m, N = {c['lateral_mass']:.2f} kg (DynamicsParameters: ω = 104.7 rad/s "
          f"at T = 2.5 in), K_s = {c['slip_coefficient']:.0f} N, M_f = c_f θ0 with c_f = {c['damping']} N·m/rad "
          f"and θ0 = {math.degrees(c['design_angle']):.0f}°. Each case starts from θ = θ_i, θ' = 0, θ'' = 0 "
          "(Eq. 24B); Eq. 7 is evaluated with c_f,eff = M_f/θ_i. The onset is found by bisection on whether the "
          "oscillation over the last two periods is larger than just after the aligning transient "
          f"(bracket width {100 * c['bracket_rtol']:.1f} %).\n\n",
          f"{s['cases']} cases (trail 1, 2, 3 in × I_w 0.33e-3, 1.27e-3, 3.42e-3 kg·m² × B = 0, 9/16 in × "
          f"θ_i = 10°, 20°, 40°) in {s['seconds']:.0f} s.\n\n",
          "![onset comparison](onset.png)\n\n",
          "## Where the describing-function approximation (Eq. 6 + Eq. 29B → Eq. 7) holds and where it breaks\n\n",
          line("all", "All cases"),
          line("omega_T_over_V_ge_2", "ωT/V_c ≥ 2 (Eq. 26B's assumption ωT/V ≫ 1 roughly met)"),
          line("omega_T_over_V_lt_2", "ωT/V_c < 2"),
          line("single_tread", "Single tread, B = 0 (onset set by friction alone)"),
          line("single_tread_omega_T_over_V_ge_2", "Single tread with ωT/V_c ≥ 2"),
          line("groove_share_ge_0.5", "Groove term ≥ 50 % of V_c² (viscous tread damping dominates)"),
          "\n",
          "Reading the figure: (1) with a groove the tread moment K_s B² θ'/(2V) is a true viscous damper, "
          "so the groove part of Eq. 7 is exact (Routh–Hurwitz of Eq. 12B) and only the friction share is "
          "approximate: the more the groove term dominates V_c², the better Eq. 7 agrees. "
          "(2) For a single tread the onset rests entirely on the friction equivalence Eq. 6 evaluated at the "
          "amplitude of Eq. 4/29B, θ_a = θ_i V/(ωT). The describing function itself (Eq. 6) is accurate: the "
          "onset error is almost exactly the error of that amplitude, (θ_a,29B/θ_a,sim)^½ − 1 (panel b; "
          f"for B = 0 the two differ by {100 * s['error_minus_amplitude_implied']['median_abs_single_tread']:.1f} "
          f"points (median), {100 * s['error_minus_amplitude_implied']['max_abs_single_tread']:.1f} at worst). (3) The amplitude is where Eq. 29B breaks: for a heavy wheel on a short trail the friction-"
          "dominated transient leaves a larger oscillation than θ_i V/(ωT) and Eq. 7 is optimistic (the "
          "simulated onset is lower); for a light wheel with a small knock ωT/V_c approaches 1, where Eq. 29B "
          "(which needs ωT/V ≫ 1; the exact Eq. 3 amplitude is θ_i/√(1+ω²T²/V²)) overestimates the amplitude "
          "and Eq. 7 is conservative. Single-tread errors by trail and wheel (over θ_i = 10°, 20°, 40°):\n\n",
          "".join(f"  - {k}: {_pct(v['min_error'])} to {_pct(v['max_error'])}\n"
                  for k, v in s["single_tread_by_trail_inertia"].items() if v),
          "\n",
          "## Amplitude (Eq. 4 / 29B) and frequency (Eq. 15B)\n\n",
          f"- Amplitude just after the transient, simulated at the onset vs θ_i V/(ωT): single tread "
          f"{_pct(s['amplitude_error_single_tread']['min'])} to {_pct(s['amplitude_error_single_tread']['max'])}; "
          f"grooved {_pct(s['amplitude_error_grooved']['min'])} to {_pct(s['amplitude_error_grooved']['max'])} "
          "(the tread damping shrinks the oscillation that the knock excites, which Eq. 29B ignores).\n",
          f"- Shimmy frequency (zero crossings after the transient) vs Eq. 15B: "
          f"{_pct(s['frequency_error']['min'])} to {_pct(s['frequency_error']['max'])}.\n\n",
          "## Appendix C case (Fig. 1C)\n\n",
          f"T = 2.5 in, I_w = {ac['inertia']:.4g} kg·m² (from V_c = 2.53 m/s via Eq. 7), θ_i = 20°, B = 0: "
          f"simulated onset {ac['onset_speed']:.3f} m/s vs Eq. 7 {ac['eq7_critical_speed']:.3f} m/s "
          f"({_pct(ac['relative_error'])}); with the paper's θ'_0 = 0.7 rad/s (Eq. 7C) "
          f"{ac['onset_speed_with_0.7_rad_per_s']:.3f} m/s. Amplitude after the transient at onset "
          f"{ac['amplitude_sim']:.3f} rad vs Eq. 29B {ac['amplitude_eq29b']:.3f} rad (paper's measured "
          f"steady amplitude {ac['paper_amplitude']:.2f} rad); frequency {ac['frequency_sim']:.1f} rad/s vs "
          f"Eq. 15B {ac['frequency_eq15b']:.1f} rad/s. Above the onset the model (linear apart from friction, "
          "small angles) grows without bound; the paper's sustained 8° shimmy is limited by effects it does "
          "not contain (tyre saturation, large angles).\n\n",
          "## Table\n\n",
          "| T [in] | I_w [kg·m²] | B [in] | θ_i [deg] | ωT/V_c | V_c Eq. 7 [m/s] | onset sim [m/s] | error | "
          "amp sim [rad] | amp Eq. 29B [rad] | ω sim [rad/s] | ω Eq. 15B [rad/s] |\n",
          "|---|---|---|---|---|---|---|---|---|---|---|---|\n"]
    for r in rows:
        md.append(
            f"| {r['trail_in']:.0f} | {r['inertia_kgm2']:.3g} | {r['groove_in']:.4g} | {r['angle_deg']:.0f} | "
            f"{r['omega_T_over_V']:.2f} | {r['eq7_critical_speed']:.3f} | {r['onset_speed']:.3f} | "
            f"{_pct(r['relative_error'])} | {r['amplitude_sim']:.3f} | {r['amplitude_eq29b']:.3f} | "
            f"{r['frequency_sim']:.1f} | {r['omega_eq15b']:.1f} |\n")
    return "".join(md)
