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

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from designer.errors import InputError, SolverError
from designer.model import Conditions, Design
from designer.physics.shimmy import critical_shimmy_speed, shimmy_frequency, steady_shimmy_amplitude
from designer.plots.simulation import plot_knock
from designer.reprs import dataframe, html_table, svg_sparkline

__all__ = [
    "SimulationResult",
    "OnsetResult",
    "simulate",
    "onset_speed",
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

    def __repr__(self) -> str:
        """Two lines: speed, knock, verdict and amplitudes; frequency, Eq. 7 V_c and the trace length."""
        verdict = "GROWS (shimmy)" if self.grows else "decays"
        freq = f"{self.frequency:.4g}" if math.isfinite(self.frequency) else "n/a"
        return (
            f"SimulationResult(V {self.speed:.3g} m/s, knock {math.degrees(self.angle):.3g}°: {verdict}; "
            f"amplitude {self.early_amplitude:.3g} → {self.late_amplitude:.3g} rad, Eq. 29B "
            f"{self.predicted_amplitude:.3g} rad)\n  ω {freq} rad/s (Eq. 15B {self.predicted_frequency:.4g}), "
            f"Eq. 7 V_c {self.critical_speed:.4g} m/s, {len(self.t)} samples over {self._end():.3g} s"
        )

    def _end(self) -> float:
        return float(self.t[-1]) if len(self.t) else 0.0

    def _repr_html_(self) -> str:
        """A compact HTML table with units beside a small SVG of θ(t) [deg] (notebooks; no integration runs)."""
        deg = math.degrees
        rows = [
            ("speed V", f"{self.speed:.4g}", "m/s"),
            ("knock θ_i (θ'_i)", f"{deg(self.angle):.3g}° ({self.angular_velocity:.3g} rad/s)", ""),
            (
                "verdict",
                ("grows: shimmy" if self.grows else "decays") + (" (|θ| hit the limit)" if self.diverged else ""),
                "",
            ),
            ("amplitude after the transient", f"{self.early_amplitude:.4g} ({deg(self.early_amplitude):.3g}°)", "rad"),
            ("amplitude at the end", f"{self.late_amplitude:.4g} ({deg(self.late_amplitude):.3g}°)", "rad"),
            ("Eq. 4 / 29B amplitude θ_i V/(ωT)", f"{self.predicted_amplitude:.4g}", "rad"),
            (
                "frequency (Eq. 15B)",
                (f"{self.frequency:.4g}" if math.isfinite(self.frequency) else "n/a")
                + f" ({self.predicted_frequency:.4g})",
                "rad/s",
            ),
            ("Eq. 7 V_c (c_f,eff = M_f/θ_i)", f"{self.critical_speed:.4g}", "m/s"),
            ("friction moment M_f", f"{self.friction_moment:.4g}", "N·m"),
            ("wheel inertia I_w", f"{self.inertia:.4g}", "kg·m²"),
            ("trace", f"{len(self.t)} samples, {self._end():.3g}", "s"),
        ]
        svg = svg_sparkline(self.t, np.degrees(self.theta), "time t [s]", "θ [deg]", band=deg(self.predicted_amplitude))
        return html_table(
            "Shimmy after a knock (Coulomb friction, App. B)",
            rows,
            caption="θ(t); dashed: ± the Eq. 29B amplitude",
            extra=svg,
        )

    def to_pandas(self):
        """The trace as a pandas DataFrame (pandas: the ``notebook`` extra): columns ``t_s`` [s], ``theta_rad``
        [rad], ``theta_deg`` [deg] and ``lateral_m`` (spindle displacement X [m]); the scalars of
        :meth:`as_dict` in ``df.attrs``, units in ``df.attrs["units"]``."""
        records = [
            {"t_s": float(t), "theta_rad": float(th), "theta_deg": math.degrees(th), "lateral_m": float(x)}
            for t, th, x in zip(self.t, self.theta, self.lateral)
        ]
        return dataframe(
            "SimulationResult.to_pandas",
            records,
            ["t_s", "theta_rad", "theta_deg", "lateral_m"],
            {"t_s": "s", "theta_rad": "rad", "theta_deg": "deg", "lateral_m": "m"},
            **self.as_dict(),
        )

    def plot(self, ax=None, onset_speed: float | None = None):
        """θ(t) in degrees against time [s], with ± the Eq. 29B amplitude; returns the matplotlib Axes.

        ``ax``: your Axes or None for a new figure; ``onset_speed`` [m/s] (e.g. from :func:`onset_speed`) is
        added to the title.  Drawn by :func:`designer.plots.simulation.plot_knock` (as ``designer simulate
        --plot``).
        """
        return plot_knock(
            self.t,
            self.theta,
            self.speed,
            self.grows,
            self.critical_speed,
            self.predicted_amplitude,
            onset_speed=onset_speed,
            ax=ax,
        )

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
    J = inertia + N * T**2  # a3 of Eq. 12B
    visc = N * T * V + Ks * B**2 / (2 * V)  # a2 of Eq. 12B without C_D
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
    extrema: list[tuple[float, float]] = []  # (time, θ) where the motion reverses
    direction = s  # last direction of θ motion (0: none yet)
    switches = 0
    diverged = False
    max_switches = 200_000
    graze = False  # last slip segment had zero length (θ' = 0 with |τ| ≈ M_f)

    while t < duration and switches < max_switches:
        if s == 0.0:
            # Stick: θ' = 0, θ constant, X' = −Vθ until |T K X| = M_f.
            th = y[1]
            tau = T * K * y[0]
            if abs(tau) > M_f and not graze:  # cannot stick: slip toward tau
                s = float(np.sign(tau))
            elif th == 0.0:
                t_end = duration  # aligned and held: rest for ever
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

        sol = solve_ivp(
            rhs(s),
            (t, duration),
            y,
            method="DOP853",
            rtol=rtol,
            atol=[1e-12, 1e-10, 1e-8],
            max_step=max_step,
            events=[stop, cross, limit_event],
        )
        if sol.status < 0:
            raise SolverError(f"shimmy simulation failed at t = {t:.4g} s: {sol.message}")
        ts.extend(sol.t[1:]), xs.extend(sol.y[0, 1:]), ths.extend(sol.y[1, 1:])
        crossings.extend(float(v) for v in sol.t_events[1])
        if sol.t_events[2].size:
            diverged = True
            t = float(sol.t_events[2][0])
            break
        if sol.status == 0 or not sol.t_events[0].size:  # reached the end
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
            direction = s  # entering stick; extremum decided on exit
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
        frequency = float(math.pi / np.median(half_periods[len(half_periods) // 2 :]))
    else:
        frequency = math.nan

    c_eff = M_f / theta_i
    v7 = float(critical_shimmy_speed(T, inertia, B, c_eff, Ks))
    return SimulationResult(
        t=t_arr,
        theta=th_arr,
        lateral=x_arr,
        speed=V,
        angle=theta_i,
        angular_velocity=float(angular_velocity),
        friction_moment=M_f,
        inertia=inertia,
        early_amplitude=early,
        late_amplitude=late,
        amplitude_ratio=late / theta_i,
        growth_ratio=float(growth),
        grows=grows,
        diverged=diverged,
        frequency=frequency,
        predicted_frequency=omega,
        predicted_amplitude=float(steady_shimmy_amplitude(V, T, omega, theta_i)),
        critical_speed=v7,
        switches=switches,
        extrema=ext,
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
            cache[v] = simulate(design, conditions, v, angle=theta_i, angular_velocity=angular_velocity, cycles=cycles)
        return cache[v]

    inertia = float(conditions.inertia(design.diameter))
    c_eff = float(design.damping) * float(conditions.disturbance_angle) / theta_i  # M_f / θ_i
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
