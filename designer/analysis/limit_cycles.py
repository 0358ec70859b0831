"""Shimmy beyond onset: knocks, periodic orbits, Floquet multipliers, knock-safe speed (issue 16).

Two caster models, both with exact Coulomb spindle friction M_f sgn θ'
(stick–slip handled by events, as ``designer.analysis.simulate``):

``rolling`` (``tyre=None``): the paper's Appendix B model, the tyre rolls
without lateral slip (Eq. 6B).  State (X, θ, θ'):

    X'  = −T θ' − V θ
    θ'' = [T K X − (N T V + K_s B²/(2V)) θ' − M_f sgn θ'] / (I_w + N T²)

``tyre`` (a :class:`~designer.physics.tyre.TyreParameters`): the contact may
slip; the floor force F(σ) is the brush model of ``designer.physics.tyre``
(saturating at μ L).  Wheel mass M_W at the contact point, fork + bearing
block N at the spindle (Eq. 9B–11B, 14B).  State (X, X', θ, θ'):

    (N + M_W) X'' + M_W T θ''          = F − K X
    M_W T X'' + (I_w + M_W T²) θ''     = T F − M_f sgn θ' − K_s B² θ'/(2V)
    F = F_brush(σ),  σ = (X' + T θ' + V θ)/V

Eliminating F between the two lines gives I_w θ'' = T K X + N T X'' − M_f sgn θ'
− K_s B² θ'/(2V), and with Eq. 7B (X'' = −T θ'' − V θ') this is the rolling model:
with the saturation removed and C → ∞ the tyre model reduces to the paper's.

Stick (θ' = 0): the moment the spindle must hold is T K X (rolling) or
T (N F + M_W K X)/(N + M_W) (tyre); the caster sticks while it is at most M_f.

Docs: docs/limit-cycles.md.  Periodic orbits are found by shooting on the Poincaré section θ' = 0 at a
maximum of θ (end of a positive slip).  Both models are odd-symmetric
(y → −y), so a symmetric orbit is a fixed point of the half-period map
G = −H (H: from a maximum to the next minimum); the amplitude A = θ_max is the
continuation parameter and the speed V an unknown, which follows the branch
round its fold.  Floquet multipliers (full period) are the squared eigenvalues
of DG (finite differences); the orbit is confirmed by integrating one full
period from it (closure) and by perturbed simulations.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from designer.errors import InputError, SolverError
from designer.model import Conditions, Design
from designer.physics.shimmy import critical_shimmy_speed
from designer.physics.tyre import TyreParameters, lateral_tyre_force
from designer.data.paper import TABLE1, TABLE1_STABLE_UP_TO, TABLE1_TRAIL
from designer.physics.inertia import Fixed
from designer.physics.shimmy import DynamicsParameters
from designer.data.paper import APPENDIX_C_CASE, BARE_FORK_DAMPING, table1_wheel
import time

__all__ = [
    "CasterDynamics",
    "KnockResult",
    "PeriodicOrbit",
    "Branch",
    "caster_dynamics",
    "simulate_knock",
    "knock_onset_speed",
    "periodic_orbit",
    "continue_orbits",
    "bifurcation_diagram",
    "knock_safe_speed",
]

_RTOL = 1e-10


@dataclass(frozen=True)
class CasterDynamics:
    """One caster at one speed, all in SI (module docstring for the equations).

    Attributes
    ----------
    trail : T [m]
    inertia : I_w [kg·m²]
    lateral_mass : N = M_F + M_1 [kg] (Eq. 14B)
    stiffness : frame lateral stiffness K [N/m]
    friction_moment : M_f = c_f θ0 [N·m]
    groove_coefficient : K_s B²/2 [N·m²]; the tread moment is this × θ'/V (Eq. 2B)
    speed : V [m/s]
    tyre : None (rolling without slip, Eq. 6B) or the brush tyre
    """

    trail: float
    inertia: float
    lateral_mass: float
    stiffness: float
    friction_moment: float
    groove_coefficient: float
    speed: float
    tyre: TyreParameters | None = None

    def at(self, speed: float) -> "CasterDynamics":
        """The same caster at another speed V [m/s]."""
        return CasterDynamics(self.trail, self.inertia, self.lateral_mass, self.stiffness, self.friction_moment,
                              self.groove_coefficient, float(speed), self.tyre)

    @property
    def frequency(self) -> float:
        """ω of Eq. 15B [rad/s] (rolling model)."""
        T = self.trail
        return math.sqrt(self.stiffness * T**2 / (self.inertia + self.lateral_mass * T**2))

    @property
    def size(self) -> int:
        """Number of states: 3 (X, θ, θ') rolling, 4 (X, X', θ, θ') tyre."""
        return 3 if self.tyre is None else 4

    # -- equations --------------------------------------------------------------------------------------
    def rhs(self, s: float):
        """f(t, y) of the slip phase with sgn θ' = s (s = 0: stick, θ' held at 0)."""
        T, K, N, I, V = self.trail, self.stiffness, self.lateral_mass, self.inertia, self.speed
        M_f, G = self.friction_moment, self.groove_coefficient / self.speed
        if self.tyre is None:
            J = I + N * T**2
            visc = N * T * V + G
            if s == 0:
                return lambda _t, y: [-V * y[1], 0.0, 0.0]
            return lambda _t, y: [-T * y[2] - V * y[1], y[2], (T * K * y[0] - visc * y[2] - s * M_f) / J]
        tyre, M = self.tyre, self.tyre.wheel_mass
        m11, m12, m22 = N + M, M * T, I + M * T**2
        det = m11 * m22 - m12**2
        i11, i12, i22 = m22 / det, -m12 / det, m11 / det
        if not tyre.saturation:
            C = tyre.cornering_stiffness

            def force(v):
                return -C * v / V
        else:
            def force(v):
                return lateral_tyre_force(v / V, tyre)
        if s == 0:
            def stick(_t, y):
                F = force(y[1] + V * y[2])
                return [y[1], (F - K * y[0]) / m11, 0.0, 0.0]
            return stick

        def slip(_t, y):
            F = force(y[1] + T * y[3] + V * y[2])
            q1 = F - K * y[0]
            q2 = T * F - s * M_f - G * y[3]
            return [y[1], i11 * q1 + i12 * q2, y[3], i12 * q1 + i22 * q2]
        return slip

    def hold_moment(self, y) -> float:
        """Moment the spindle must transmit to keep θ' = 0 at state y [N·m] (sticks while |·| ≤ M_f)."""
        T, K = self.trail, self.stiffness
        if self.tyre is None:
            return T * K * y[0]
        N, M = self.lateral_mass, self.tyre.wheel_mass
        F = float(lateral_tyre_force((y[1] + self.speed * y[2]) / self.speed, self.tyre))
        return T * (N * F + M * K * y[0]) / (N + M)

    def knock_state(self, angle: float, angular_velocity: float = 0.0) -> np.ndarray:
        """Initial state after a knock, Eq. 24B: θ = θ_i, θ' = θ'_i, θ'' = 0, no tyre slip."""
        T, K, N, V = self.trail, self.stiffness, self.lateral_mass, self.speed
        w0 = float(angular_velocity)
        visc = N * T * V + self.groove_coefficient / V
        x0 = (visc * w0 + math.copysign(self.friction_moment, w0) * (w0 != 0)) / (T * K)
        if self.tyre is None:
            return np.array([x0, angle, w0])
        return np.array([x0, -T * w0 - V * angle, angle, w0])


def caster_dynamics(design: Design, conditions: Conditions = Conditions(), speed: float = 2.5,
                    tyre: TyreParameters | None = None) -> CasterDynamics:
    """Build :class:`CasterDynamics` from a design and conditions.

    Parameters
    ----------
    design : T [m], d [m] (I_w from ``conditions.inertia``), B [m], c_f [N·m/rad]
    conditions : K_s [N], θ0 [rad] (M_f = c_f θ0), dynamics (K [N/m], N [kg])
    speed : V [m/s]
    tyre : None for the paper's rolling tyre (Eq. 6B), else the brush tyre
    """
    for name, value in (("speed", speed), ("trail", design.trail)):
        if not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
            raise InputError(f"{name} = {value!r}: must be a positive finite number")
    inertia = float(conditions.inertia(design.diameter))
    dyn = conditions.dynamics
    return CasterDynamics(
        trail=float(design.trail), inertia=inertia, lateral_mass=float(dyn.lateral_mass),
        stiffness=float(dyn.stiffness), friction_moment=float(design.damping) * float(conditions.disturbance_angle),
        groove_coefficient=float(conditions.slip_coefficient) * float(design.groove) ** 2 / 2,
        speed=float(speed), tyre=tyre)


# ---------------------------------------------------------------------------------------------------------
# Event-driven integration with exact stick-slip

@dataclass
class _Run:
    t: list
    y: list
    ends: list            # (t, θ, s, state) at the end of each slip phase
    state: np.ndarray
    time: float
    reason: str           # "end", "limit", "section", "rest"
    switches: int


def _integrate(sys: CasterDynamics, y0, t_end: float, stop_at_end_of: float | None = None,  # noqa: C901 - event-driven stick-slip integration: one branch per event
               angle_limit: float = math.inf, record: bool = False, max_step: float = math.inf,
               rtol: float = _RTOL, max_switches: int = 20_000) -> _Run:
    """Integrate from y0 until t_end, |θ| = angle_limit, or the end of a slip of sign ``stop_at_end_of``."""
    from scipy.integrate import solve_ivp  # heavy import, only for time integration

    n = sys.size
    ith, iw = n - 2, n - 1
    M_f = sys.friction_moment
    scale = max(abs(float(y0[ith])), 1e-6)
    if n == 4:
        atol = [1e-12 * scale * sys.trail, 1e-12 * scale * sys.speed, 1e-12 * scale, 1e-10 * scale]
    else:
        atol = [1e-12 * scale * sys.trail, 1e-12 * scale, 1e-10 * scale]
    y = np.array(y0, dtype=float)
    t = 0.0
    ts, ys, ends = ([t], [y.copy()], []) if record else ([], [], [])
    switches = 0

    def decide(state) -> float:
        h = sys.hold_moment(state)
        return float(np.sign(h)) if abs(h) > M_f else 0.0

    s = float(np.sign(y[iw])) if y[iw] != 0 else decide(y)
    graze_level = None
    tiny = 1e-13 * max(scale, 1e-3) * sys.frequency

    def limit(_t, yy):
        return abs(yy[ith]) - angle_limit
    limit.terminal = True

    while t < t_end and switches < max_switches:
        if s == 0.0:
            level = M_f if graze_level is None else graze_level

            def unstick(_t, yy, level=level):
                return abs(sys.hold_moment(yy)) - level
            unstick.terminal = True
            unstick.direction = 1
            sol = solve_ivp(sys.rhs(0.0), (t, t_end), y, method="DOP853", rtol=rtol, atol=atol,
                            max_step=max_step, events=[unstick])
            graze_level = None
            if sol.status < 0:
                raise SolverError(f"shimmy integration failed in stick at t = {t:.4g} s: {sol.message}")
            if record:
                ts.extend(sol.t[1:]), ys.extend(sol.y[:, 1:].T)
            if not sol.t_events[0].size:
                return _Run(ts, ys, ends, sol.y[:, -1], t_end, "rest", switches)
            t = float(sol.t_events[0][0])
            y = np.array(sol.y_events[0][0], dtype=float)
            y[iw] = 0.0
            s = float(np.sign(sys.hold_moment(y)))
            switches += 1
            continue

        y[iw] = y[iw] if y[iw] * s > 0 else s * tiny     # start the slip just off θ' = 0

        def stop(_t, yy, s=s):
            return s * yy[iw]
        stop.terminal = True
        stop.direction = -1
        sol = solve_ivp(sys.rhs(s), (t, t_end), y, method="DOP853", rtol=rtol, atol=atol, max_step=max_step,
                        events=[stop, limit])
        if sol.status < 0:
            raise SolverError(f"shimmy integration failed at t = {t:.4g} s: {sol.message}")
        if record:
            ts.extend(sol.t[1:]), ys.extend(sol.y[:, 1:].T)
        if sol.t_events[1].size:
            return _Run(ts, ys, ends, np.array(sol.y_events[1][0]), float(sol.t_events[1][0]), "limit", switches)
        if not sol.t_events[0].size:
            return _Run(ts, ys, ends, sol.y[:, -1], t_end, "end", switches)
        t_start, t = t, float(sol.t_events[0][0])
        y = np.array(sol.y_events[0][0], dtype=float)
        y[iw] = 0.0
        switches += 1
        ends.append((t, float(y[ith]), s, y.copy()))
        if stop_at_end_of is not None and s == stop_at_end_of:
            return _Run(ts, ys, ends, y, t, "section", switches)
        new = decide(y)
        if new == s and t - t_start < 1e-9 / sys.frequency:
            # grazing: the slip ended at once although |hold| > M_f by a rounding error; stick until the
            # held moment grows past its present value
            new = 0.0
            graze_level = abs(sys.hold_moment(y)) * (1 + 1e-9)
        s = new
    if switches >= max_switches:
        raise SolverError(f"shimmy integration: more than {max_switches} stick/slip switches before t = {t_end:g} s")
    return _Run(ts, ys, ends, y, t, "end", switches)


def _extrema(ends) -> np.ndarray:
    """(t, θ) where θ reverses: the end of a slip phase followed by a slip of the other sign."""
    out = []
    for k, (t, th, s, _y) in enumerate(ends):
        if k + 1 == len(ends) or ends[k + 1][2] != s:
            out.append((t, th))
    return np.asarray(out, dtype=float).reshape(-1, 2)


@dataclass
class KnockResult:
    """What a knock does: the trace, the amplitudes and the verdict.

    Attributes
    ----------
    t, theta : time [s] and caster angle θ [rad] (empty unless ``record``)
    extrema : (t [s], θ [rad]) at the reversals
    early_amplitude : mean half peak-to-peak over two periods after the aligning transient [rad]
    late_amplitude : the same over the last two periods (0 if the motion stopped) [rad]
    shimmy : True if the knock ends in sustained shimmy: |θ| reached the limit, or the caster still
        reverses at least 3 times in the last two periods with late ≥ 0.5 early (a decaying
        Coulomb-damped motion stops in finite time; a slow creep of a sliding tyre is not shimmy)
    reason : "end", "limit" (|θ| reached ``angle_limit``) or "rest" (the caster stopped)
    """

    t: np.ndarray
    theta: np.ndarray
    extrema: np.ndarray
    early_amplitude: float
    late_amplitude: float
    shimmy: bool
    reason: str
    speed: float = 0.0
    angle: float = 0.0


def simulate_knock(sys: CasterDynamics, angle: float, angular_velocity: float = 0.0, cycles: float = 30.0,
                   angle_limit: float = 1.0, record: bool = False) -> KnockResult:
    """Simulate the caster after a knock θ_i (Eq. 24B) and say whether shimmy is sustained.

    Parameters
    ----------
    sys : the caster at its speed (:func:`caster_dynamics`)
    angle : knock θ_i [rad]
    angular_velocity : θ'_i [rad/s]
    cycles : periods of Eq. 15B simulated after the aligning transient 3T/V
    angle_limit : stop when |θ| reaches it [rad] (shimmy has grown out of the small-angle model)
    record : keep the trace
    """
    if not (isinstance(angle, (int, float)) and math.isfinite(angle) and angle > 0):
        raise InputError(f"angle = {angle!r}: must be a positive finite number [rad]")
    period = 2 * math.pi / sys.frequency
    transient = max(3 * sys.trail / sys.speed, period)
    duration = transient + cycles * period
    run = _integrate(sys, sys.knock_state(angle, angular_velocity), duration, angle_limit=angle_limit,
                     record=record, max_step=period / 40 if record else math.inf)
    ext = _extrema(run.ends)
    half = np.abs(np.diff(ext[:, 1])) / 2 if len(ext) > 1 else np.empty(0)
    times = ext[1:, 0] if len(ext) > 1 else np.empty(0)
    early_sel = (times >= transient) & (times < transient + 2 * period)
    early = float(half[early_sel].mean()) if early_sel.any() else (float(half[0]) if half.size else 0.0)
    end = run.time
    late_sel = times >= end - 2 * period
    late = float(half[late_sel].mean()) if (late_sel.any() and run.reason != "rest") else 0.0
    # sustained = still oscillating at the end (>= 3 reversals in the last two periods: a slow creep of a
    # sliding tyre at a crawl is not shimmy) with an amplitude at least half the early one
    shimmy = run.reason == "limit" or (early > 0 and late >= 0.5 * early and int(late_sel.sum()) >= 3)
    theta = np.array([v[sys.size - 2] for v in run.y]) if record else np.empty(0)
    return KnockResult(np.asarray(run.t), theta, ext, early, late, bool(shimmy), run.reason, sys.speed, angle)


@dataclass
class OnsetBracket:
    """Knock onset by bisection: the knock decays at ``low`` and is sustained at ``high`` [m/s]."""

    low: float
    high: float
    evaluations: int

    @property
    def speed(self) -> float:
        """Geometric mean of the bracket [m/s]."""
        return math.sqrt(self.low * self.high)


def knock_onset_speed(sys: CasterDynamics, angle: float, angular_velocity: float = 0.0, rtol: float = 0.005,
                      cycles: float = 30.0, guess: float | None = None) -> OnsetBracket:
    """Lowest speed at which a knock θ_i is sustained (bisection in log V) [m/s].

    The bracket starts at ``guess`` (default Eq. 7's V_c with c_f,eff = M_f/θ_i) × [0.8, 1.25], widened × 1.5
    until it holds a decaying and a sustained speed; bisection stops when high/low − 1 < ``rtol``.
    """
    if guess is None:   # Eq. 7 with c_f,eff = M_f/θ_i
        c_eff = sys.friction_moment / angle
        guess = math.sqrt(4 * c_eff * sys.trail**2 / (math.pi * sys.inertia)
                          + sys.groove_coefficient * sys.trail / sys.inertia)
    n = 0
    cache = {}

    def sustained(v):
        nonlocal n
        if v not in cache:
            n += 1
            cache[v] = simulate_knock(sys.at(v), angle, angular_velocity, cycles).shimmy
        return cache[v]

    low, high = 0.8 * guess, 1.25 * guess
    for _ in range(12):
        if sustained(low):
            high, low = low, low / 1.5
        elif not sustained(high):
            low, high = high, high * 1.5
        else:
            break
    else:
        raise SolverError(f"knock onset not bracketed between {low:.3g} and {high:.3g} m/s")
    while high / low - 1 > rtol:
        mid = math.sqrt(low * high)
        if sustained(mid):
            high = mid
        else:
            low = mid
    return OnsetBracket(low, high, n)


# ---------------------------------------------------------------------------------------------------------
# Periodic orbits: shooting on the section θ' = 0 at a maximum, amplitude as the continuation parameter

@dataclass
class PeriodicOrbit:
    """A symmetric periodic orbit (shimmy at constant amplitude) and its stability.

    Attributes
    ----------
    amplitude : θ_max = A [rad]
    speed : V [m/s]
    state : state at the maximum of θ (θ' = 0) [SI]
    period : full period [s]
    multipliers : nontrivial Floquet multipliers of the full period (complex) [-]
    stable : all |multiplier| < 1
    closure : largest change of the section state over one full period, in rad
        (X/T, X'/(ωT), θ) [rad]
    residual : half-period fixed-point residual at convergence [rad]
    iterations : Newton iterations
    """

    amplitude: float
    speed: float
    state: np.ndarray
    period: float
    multipliers: np.ndarray
    stable: bool
    closure: float
    residual: float
    iterations: int

    @property
    def frequency(self) -> float:
        """2π / period [rad/s]."""
        return 2 * math.pi / self.period

    def as_dict(self) -> dict:
        """Plain floats (multipliers as [re, im] pairs)."""
        return {"amplitude": self.amplitude, "speed": self.speed, "period": self.period,
                "frequency": self.frequency, "stable": bool(self.stable), "closure": self.closure,
                "residual": self.residual, "iterations": self.iterations,
                "multipliers": [[float(m.real), float(m.imag)] for m in self.multipliers],
                "max_abs_multiplier": float(np.max(np.abs(self.multipliers)))}


def _weights(sys: CasterDynamics) -> np.ndarray:
    """Section coordinates → rad: X/T, X'/(ωT), θ."""
    T, w = sys.trail, sys.frequency
    return np.array([1 / T, 1 / (w * T), 1.0]) if sys.tyre is not None else np.array([1 / T, 1.0])


def _half_map(sys: CasterDynamics, z: np.ndarray):
    """G(z) = −H(z): from a maximum of θ (θ' = 0, section state z) to minus the state at the next minimum."""
    period = 2 * math.pi / sys.frequency
    run = _integrate(sys, np.append(z, 0.0), 20 * period, stop_at_end_of=-1.0)
    if run.reason != "section":
        return None, math.nan
    return -np.asarray(run.state[:-1]), run.time


def _full_period(sys: CasterDynamics, z: np.ndarray):
    """Section state after one full period (no symmetry used) and the period [s]."""
    period = 2 * math.pi / sys.frequency
    first = _integrate(sys, np.append(z, 0.0), 20 * period, stop_at_end_of=-1.0)
    if first.reason != "section":
        return None, math.nan
    second = _integrate(sys, first.state, 20 * period, stop_at_end_of=1.0)
    if second.reason != "section":
        return None, math.nan
    return np.asarray(second.state[:-1]), first.time + second.time


def _describing_function_speed(sys: CasterDynamics, amplitude: float) -> float:
    """Speed of the unstable cycle of amplitude A by Eq. 6 + Eq. 20B (C_D = 4 M_f/(π ω A)) [m/s]."""
    c_d = 4 * sys.friction_moment / (math.pi * sys.frequency * amplitude)
    a = sys.inertia / sys.trail
    return (c_d + math.sqrt(c_d**2 + 4 * a * sys.groove_coefficient)) / (2 * a)


# long: Newton on the half-period map, its step control, Floquet multipliers and the closure check
def periodic_orbit(sys: CasterDynamics, amplitude: float, guess: np.ndarray | None = None, tol: float = 1e-9,
                   max_iter: int = 25) -> PeriodicOrbit:
    """Symmetric periodic orbit of amplitude A: solve G(z) = z for the other section states and V.

    Newton's method with a finite-difference Jacobian on the half-period map G (module docstring); the
    unknowns are (X, [X',] V) with θ = A fixed.  Floquet multipliers are the squares of the eigenvalues of
    DG at fixed V (central differences); ``closure`` integrates one full period without the symmetry.

    Parameters
    ----------
    sys : the caster (its speed is the starting guess unless ``guess`` is given)
    amplitude : A = θ_max [rad]
    guess : optional starting unknowns (X [m], [X' [m/s],] V [m/s])
    tol : convergence of the weighted residual [rad]

    Raises
    ------
    SolverError
        If Newton's method does not converge (no orbit of that amplitude nearby).
    """
    A = float(amplitude)
    w = _weights(sys)
    n = sys.size - 1                     # section dimension
    if guess is None:
        V = _describing_function_speed(sys, A)
        guess = np.array([-sys.trail * A, V]) if n == 2 else np.array([-sys.trail * A, -V * A, V])
    u = np.array(guess, dtype=float)

    def section(u):
        return np.concatenate([u[:-1], [A]])

    def residual(u):
        if not (u[-1] > 0 and math.isfinite(u[-1])):
            return None
        g, _ = _half_map(sys.at(u[-1]), section(u))
        return None if g is None else (g - section(u)) * w

    scales = np.concatenate([[sys.trail * A], [u[-1] * A] if n == 3 else [], [1.0]])
    r = residual(u)
    if r is None:
        raise SolverError(f"periodic orbit of amplitude {A:.4g} rad: the motion stops from the first guess")
    iterations = 0
    while np.max(np.abs(r)) > tol:
        if iterations >= max_iter:
            raise SolverError(f"periodic orbit of amplitude {A:.4g} rad: Newton did not converge "
                              f"(residual {np.max(np.abs(r)):.2g} rad after {max_iter} iterations)")
        iterations += 1
        J = np.empty((n, n))
        for j in range(n):
            h = 1e-7 * scales[j]
            up = u.copy()
            up[j] += h
            rp = residual(up)
            if rp is None:
                up[j] -= 2 * h
                rp = residual(up)
                if rp is None:
                    raise SolverError(f"periodic orbit of amplitude {A:.4g} rad: map undefined near the guess")
                h = -h
            J[:, j] = (rp - r) / h
        try:
            step = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            raise SolverError(f"periodic orbit of amplitude {A:.4g} rad: singular Jacobian") from None
        lam = 1.0
        for _ in range(12):
            trial = u + lam * step
            rt = residual(trial)
            if rt is not None and np.max(np.abs(rt)) < np.max(np.abs(r)):
                u, r = trial, rt
                break
            lam /= 2
        else:
            raise SolverError(f"periodic orbit of amplitude {A:.4g} rad: no descent step "
                              f"(residual {np.max(np.abs(r)):.2g} rad)")
    V = float(u[-1])
    at = sys.at(V)
    z = section(u)
    multipliers, closure, period = _floquet_and_closure(at, z)
    return PeriodicOrbit(amplitude=A, speed=V, state=np.append(z, 0.0), period=period, multipliers=multipliers,
                         stable=bool(np.all(np.abs(multipliers) < 1)), closure=closure,
                         residual=float(np.max(np.abs(r))), iterations=iterations)


@dataclass
class Branch:
    """Periodic orbits along amplitude, split into stable and unstable pieces for the diagram."""

    orbits: list = field(default_factory=list)
    failed: list = field(default_factory=list)        # amplitudes where no orbit was found [rad]

    def pieces(self) -> list[dict]:
        """Consecutive runs of equal stability: [{"kind", "speed", "amplitude"}] (SI, rad)."""
        out: list[dict] = []
        for orb in self.orbits:
            kind = "stable" if orb.stable else "unstable"
            if not out or out[-1]["kind"] != kind:
                out.append({"kind": kind, "speed": [], "amplitude": []})
            out[-1]["speed"].append(float(orb.speed))
            out[-1]["amplitude"].append(float(orb.amplitude))
        return out


def continue_orbits(sys: CasterDynamics, amplitudes, progress=None) -> Branch:
    """Follow the branch of symmetric periodic orbits over ``amplitudes`` [rad] (increasing or decreasing).

    Each orbit starts from the previous one (secant prediction of the unknowns scaled by A); a point where
    Newton fails is recorded in ``Branch.failed`` and the next point restarts from the last good orbit.
    """
    branch = Branch()
    prev: list[tuple[float, np.ndarray]] = []
    amplitudes = [float(a) for a in amplitudes]
    for i, A in enumerate(amplitudes):
        guess = None
        if len(prev) >= 2:
            (a1, u1), (a2, u2) = prev[-2], prev[-1]
            # unknowns scale roughly with A (X, X') or 1/A (V): extrapolate in log A
            k = math.log(A / a2) / math.log(a2 / a1)
            guess = u2 * (u2 / u1) ** k if np.all(u1 * u2 > 0) else u2 + (u2 - u1) * k
        elif prev:
            a2, u2 = prev[-1]
            guess = u2 * np.concatenate([np.full(len(u2) - 1, A / a2), [1.0]])
        try:
            orb = periodic_orbit(sys if guess is None else sys.at(guess[-1]), A, guess)
        except SolverError:
            if guess is not None and len(prev) >= 1:
                try:
                    a2, u2 = prev[-1]
                    g2 = u2 * np.concatenate([np.full(len(u2) - 1, A / a2), [1.0]])
                    orb = periodic_orbit(sys.at(g2[-1]), A, g2)
                except SolverError:
                    branch.failed.append(A)
                    continue
            else:
                branch.failed.append(A)
                continue
        branch.orbits.append(orb)
        prev.append((A, np.concatenate([orb.state[:-2], [orb.speed]])))
        if progress is not None:
            progress(i + 1, len(amplitudes))
    return branch


# ---------------------------------------------------------------------------------------------------------
# Knock-safe speed

def knock_safe_speed(design: Design, conditions: Conditions = Conditions(), angle: float | None = None,
                     tyre: TyreParameters | None = None, rtol: float = 0.005) -> float:
    """Highest speed at which a knock of θ_i decays instead of growing into shimmy [m/s].

    The low end of the knock-onset bracket (:func:`knock_onset_speed`, relative width ``rtol``): the knock
    was simulated and seen to decay there.  Cost: about 8–10 time simulations (≈ 0.5–1 s of CPU with the
    rolling tyre, a few seconds with the brush tyre), so reports compute it for a few designs only.

    Parameters
    ----------
    design : T [m], d [m], B [m], c_f [N·m/rad]
    conditions : K_s, θ0 (M_f = c_f θ0), inertia model, dynamics (K, N)
    angle : knock θ_i [rad]; default the design θ0 of the conditions (20°); the report also gives 2 θ0
    tyre : None for the paper's rolling tyre (Eq. 6B; the default, as for Eq. 7), else the brush tyre
    rtol : relative width of the bracket [-]

    Returns 0.0 when the knock is sustained at every speed down to 1 % of Eq. 7's V_c (no safe speed).
    """
    theta = float(conditions.disturbance_angle if angle is None else angle)
    if not math.isfinite(theta) or not 0 < theta < math.pi / 2:
        raise InputError(f"angle = {angle!r}: knock angle must be between 0 and 90 deg (in rad)")
    sys = caster_dynamics(design, conditions, 1.0, tyre)
    try:
        return float(knock_onset_speed(sys, theta, rtol=rtol).low)
    except SolverError:
        # not bracketed: a knock that is sustained even at a crawl has no safe speed
        crawl = 0.01 * math.sqrt(4 * sys.friction_moment / theta * sys.trail**2 / (math.pi * sys.inertia)
                                 + sys.groove_coefficient * sys.trail / sys.inertia)
        if simulate_knock(sys.at(crawl), theta).shimmy:
            return 0.0
        raise


def _floquet_and_closure(at: CasterDynamics, z: np.ndarray):
    """Floquet multipliers (squared eigenvalues of DG), full-period closure [rad] and period [s] at z."""
    n = at.size - 1
    w = _weights(at)
    A = abs(z[-1])
    zs = np.concatenate([[at.trail * A], [at.speed * A] if n == 3 else [], [A]])
    DG = np.empty((n, n))
    for j in range(n):
        h = 1e-6 * zs[j]
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        gp, _ = _half_map(at, zp)
        gm, _ = _half_map(at, zm)
        if gp is None or gm is None:
            DG[:, j] = np.nan
        else:
            DG[:, j] = (gp - gm) / (2 * h)
    mu = np.linalg.eigvals(DG) if np.all(np.isfinite(DG)) else np.full(n, np.nan + 0j)
    full, period = _full_period(at, z)
    closure = float(np.max(np.abs((full - z) * w))) if full is not None else math.nan
    return mu**2, closure, period


def periodic_orbit_at_speed(sys: CasterDynamics, guess: np.ndarray, tol: float = 1e-9,
                            max_iter: int = 25) -> PeriodicOrbit:
    """Symmetric periodic orbit at the fixed speed of ``sys``: Newton on G(z) = z over the whole section state.

    ``guess`` is a state at a maximum of θ (θ' = 0; its last entry is ignored), e.g. from a long simulation.
    Used for the stable branch, swept in speed.  Raises SolverError when Newton fails (past a fold).
    """
    w = _weights(sys)
    n = sys.size - 1
    z = np.array(guess, dtype=float)[:n]

    def residual(z):
        g, _ = _half_map(sys, z)
        return None if g is None else (g - z) * w

    r = residual(z)
    if r is None:
        raise SolverError(f"periodic orbit at {sys.speed:.4g} m/s: the motion stops from the guess")
    iterations = 0
    while np.max(np.abs(r)) > tol:
        if iterations >= max_iter:
            raise SolverError(f"periodic orbit at {sys.speed:.4g} m/s: Newton did not converge "
                              f"(residual {np.max(np.abs(r)):.2g} rad)")
        iterations += 1
        A = abs(z[-1])
        zs = np.concatenate([[sys.trail * A], [sys.speed * A] if n == 3 else [], [A]])
        J = np.empty((n, n))
        for j in range(n):
            h = 1e-7 * zs[j]
            zp = z.copy()
            zp[j] += h
            rp = residual(zp)
            if rp is None:
                raise SolverError(f"periodic orbit at {sys.speed:.4g} m/s: map undefined near the guess")
            J[:, j] = (rp - r) / h
        try:
            step = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            raise SolverError(f"periodic orbit at {sys.speed:.4g} m/s: singular Jacobian") from None
        lam = 1.0
        for _ in range(12):
            trial = z + lam * step
            rt = residual(trial)
            if rt is not None and np.max(np.abs(rt)) < np.max(np.abs(r)):
                z, r = trial, rt
                break
            lam /= 2
        else:
            raise SolverError(f"periodic orbit at {sys.speed:.4g} m/s: no descent step")
    if z[-1] < 0:
        z = -z
    multipliers, closure, period = _floquet_and_closure(sys, z)
    return PeriodicOrbit(amplitude=float(z[-1]), speed=sys.speed, state=np.append(z, 0.0), period=period,
                         multipliers=multipliers, stable=bool(np.all(np.abs(multipliers) < 1)), closure=closure,
                         residual=float(np.max(np.abs(r))), iterations=iterations)


def stable_orbit(sys: CasterDynamics, angle: float = 0.6, cycles: float = 80.0,
                 angle_limit: float = 6.0) -> PeriodicOrbit | None:
    """Sustained shimmy at the speed of ``sys``: simulate a knock θ_i = ``angle`` [rad] for ``cycles`` periods,
    then polish the last maximum into a periodic orbit (:func:`periodic_orbit_at_speed`).

    Returns None if the knock decays (no stable cycle reached from it) or |θ| passes ``angle_limit``.
    """
    period = 2 * math.pi / sys.frequency
    run = _integrate(sys, sys.knock_state(angle), cycles * period, angle_limit=angle_limit)
    if run.reason != "end":
        return None
    maxima = [e for e in run.ends if e[2] > 0]
    if not maxima:
        return None
    orb = periodic_orbit_at_speed(sys, maxima[-1][3])
    return orb if orb.stable else None


def speed_sweep(sys: CasterDynamics, speeds, start: PeriodicOrbit) -> Branch:
    """Follow an orbit in speed (each Newton solve starts from the last orbit); stops at the first failure."""
    branch = Branch()
    z = start.state
    for v in speeds:
        try:
            orb = periodic_orbit_at_speed(sys.at(v), z)
        except SolverError:
            branch.failed.append(float(v))
            break
        branch.orbits.append(orb)
        z = orb.state
    return branch


# ---------------------------------------------------------------------------------------------------------
# Studies: bifurcation diagram, Table 1, the (K, N) map

def _branch_dicts(orbits) -> list[dict]:
    return Branch(orbits=list(orbits)).pieces()


def _find_stable(sys: CasterDynamics, angles=(0.6, 1.2, 0.3, 2.4)) -> PeriodicOrbit | None:
    for a in angles:
        try:
            orb = stable_orbit(sys, angle=a, cycles=40.0)
        except SolverError:
            orb = None
        if orb is not None:
            return orb
    return None


def bifurcation_diagram(design: Design, conditions: Conditions = Conditions(),
                        tyre: TyreParameters | None = TyreParameters(), speed_range: tuple[float, float] = (0.3, 4.0),
                        reference_speed: float | None = None, points: int = 24, max_amplitude: float = 3.0,
                        progress=None) -> dict:
    """Periodic orbits against speed: amplitude of the unstable (knock threshold) and stable (sustained
    shimmy) branches, with their Floquet multipliers.

    The unstable branch is followed in amplitude (:func:`continue_orbits`) from the amplitude whose
    describing-function speed is ``speed_range[1]`` up to ``max_amplitude`` or the first failures (round the
    fold it turns stable); the stable branch is found by simulating large knocks at ``reference_speed``
    (default Eq. 7's V_c) and followed in speed down to its fold and up to ``speed_range[1]``.

    Parameters
    ----------
    design, conditions : the caster (M_f = c_f θ0)
    tyre : the brush tyre (None: the paper's rolling tyre, which has no stable branch)
    speed_range : (low, high) speeds of the diagram [m/s]
    reference_speed : where the stable branch is first looked for [m/s]
    points : amplitudes on the unstable branch
    max_amplitude : largest amplitude followed [rad] (the small-angle model is not valid up there)

    Returns
    -------
    dict
        ``branches`` [{"kind": "stable" | "unstable", "speed": [m/s], "amplitude": [rad]}],
        ``orbits`` (each orbit's speed, amplitude, period, multipliers, closure), ``fold_speed`` [m/s]
        (lowest speed of a periodic orbit: below it every knock decays), ``eq7_critical_speed`` [m/s],
        ``frequency`` (Eq. 15B) [rad/s], ``stable_at_reference`` (orbit dict or None), ``max_closure`` [rad].
    """
    lo, hi = (float(v) for v in speed_range)
    if not 0 < lo < hi:
        raise InputError(f"speed_range = {speed_range!r}: expected 0 < low < high [m/s]")
    sys = caster_dynamics(design, conditions, hi, tyre)
    inertia = sys.inertia
    v7 = float(critical_shimmy_speed(design.trail, inertia, design.groove, design.damping,
                                     conditions.slip_coefficient))
    ref = v7 if reference_speed is None else float(reference_speed)
    c_d_hi = inertia * hi / sys.trail - sys.groove_coefficient / hi
    a_lo = 4 * sys.friction_moment / (math.pi * sys.frequency * c_d_hi) if c_d_hi > 0 else 0.01
    amplitudes = np.geomspace(a_lo, max_amplitude, int(points))
    unstable = continue_orbits(sys, amplitudes, progress=progress)
    orbits = [o for o in unstable.orbits if lo * 0.5 <= o.speed <= hi * 1.5]
    stable_ref = None
    stable_orbits: list[PeriodicOrbit] = []
    if tyre is not None:
        stable_ref = _find_stable(sys.at(ref))
        if stable_ref is not None:
            down = speed_sweep(sys, np.geomspace(ref, lo, max(5, 2 * points // 3))[1:], stable_ref)
            up = speed_sweep(sys, np.geomspace(ref, hi, max(4, points // 3))[1:], stable_ref)
            stable_orbits = down.orbits[::-1] + [stable_ref] + up.orbits
    # merge: amplitude branch (unstable part and the stable part near the fold) + the speed sweep
    unstable_part = [o for o in orbits if not o.stable]
    fold_part = [o for o in orbits if o.stable and (not stable_orbits or o.amplitude < stable_orbits[0].amplitude)]
    stable_all = sorted(fold_part + stable_orbits, key=lambda o: o.amplitude)
    branches = _branch_dicts(unstable_part) + _branch_dicts(stable_all)
    every = unstable_part + stable_all
    fold = min((o.speed for o in every), default=math.nan) if stable_orbits or fold_part else math.nan
    return {
        "design": design.as_dict(),
        "model": "rolling" if tyre is None else "brush tyre",
        "tyre": None if tyre is None else {"cornering_stiffness": tyre.cornering_stiffness,
                                           "friction_coefficient": tyre.friction_coefficient, "load": tyre.load,
                                           "wheel_mass": tyre.wheel_mass, "saturation": tyre.saturation},
        "inertia": inertia,
        "friction_moment": sys.friction_moment,
        "frequency": sys.frequency,
        "eq7_critical_speed": v7,
        "disturbance_angle": float(conditions.disturbance_angle),
        "branches": branches,
        "orbits": [o.as_dict() for o in every],
        "fold_speed": fold,
        "reference_speed": ref,
        "stable_at_reference": None if stable_ref is None else stable_ref.as_dict(),
        "max_closure": max((o.closure for o in every), default=math.nan),
        "failed_amplitudes": unstable.failed,
    }


def _stats(pred, meas) -> dict:
    e = np.asarray(pred, float) / np.asarray(meas, float) - 1
    return {"rms": float(np.sqrt(np.mean(e**2))), "bias": float(np.mean(e)), "max_abs": float(np.max(np.abs(e))),
            "n": int(e.size)}


def table1_comparison(conditions: Conditions = Conditions(), tyre: TyreParameters = TyreParameters(load=160.0),
                      angle: float | None = None, rtol: float = 0.005, progress=None) -> dict:
    """Table 1 (test fork, T = 2 in, bare fork c_f = 1.3, B = 0): measured onset, Eq. 7, the rolling
    simulation (the paper's model, Coulomb friction) and the brush-tyre simulation, from the same knock.

    Each wheel uses its own I_w and mass M_W (tyre model); the load is Table 1's 160 N.  Errors are
    prediction/measured − 1 over wheels C–G; wheels A and B were stable up to 3.8 m/s, and a prediction
    below that is flagged.

    Returns
    -------
    dict
        ``rows`` (per wheel: key, inertia, mass, measured, eq7, rolling_sim, tyre_sim (+ brackets),
        flagged) and ``stats`` {eq7, rolling_sim, tyre_sim: {rms, bias, max_abs, n}}.
    """

    theta = float(conditions.disturbance_angle if angle is None else angle)
    rows = []
    for i, wheel in enumerate(TABLE1):
        cond = conditions.replace(inertia=Fixed(wheel.inertia))
        design = Design(trail=TABLE1_TRAIL, diameter=wheel.diameter, groove=0.0, damping=1.3)
        v7 = float(critical_shimmy_speed(TABLE1_TRAIL, wheel.inertia, 0.0, 1.3 * conditions.disturbance_angle
                                         / theta, conditions.slip_coefficient))
        rolling = knock_onset_speed(caster_dynamics(design, cond, 1.0, None), theta, rtol=rtol)
        wheel_tyre = tyre.replace(wheel_mass=wheel.mass)
        slipping = knock_onset_speed(caster_dynamics(design, cond, 1.0, wheel_tyre), theta, rtol=rtol,
                                     guess=rolling.speed)
        predicted = {"eq7": v7, "rolling_sim": rolling.speed, "tyre_sim": slipping.speed}
        flagged = [k for k, v in predicted.items() if wheel.critical_speed is None and v < TABLE1_STABLE_UP_TO]
        rows.append({"wheel": wheel.key, "name": wheel.name, "inertia": wheel.inertia, "mass": wheel.mass,
                     "measured": wheel.critical_speed, **predicted,
                     "rolling_sim_bracket": [rolling.low, rolling.high],
                     "tyre_sim_bracket": [slipping.low, slipping.high],
                     "flagged_below_3.8": flagged})
        if progress is not None:
            progress(i + 1, len(TABLE1))
    measured = [r for r in rows if r["measured"] is not None]
    stats = {k: _stats([r[k] for r in measured], [r["measured"] for r in measured])
             for k in ("eq7", "rolling_sim", "tyre_sim")}
    return {"rows": rows, "stats": stats, "angle": theta, "trail": TABLE1_TRAIL, "load": tyre.load,
            "tyre": {"cornering_stiffness": tyre.cornering_stiffness,
                     "friction_coefficient": tyre.friction_coefficient}, "stable_up_to": TABLE1_STABLE_UP_TO}


def scanned_onset_speed(sys: CasterDynamics, angle: float, speeds, rtol: float = 0.01) -> dict:
    """Lowest speed at which a knock θ_i [rad] is sustained, from a scan over ``speeds`` [m/s] then bisection.

    Unlike :func:`knock_onset_speed` it does not assume one transition: the brush tyre on a stiff frame has
    islands of shimmy in speed.  Islands narrower than the scan spacing can be missed.

    Returns {"speed" [m/s] (NaN if sustained nowhere in the scan), "monotone" (sustained at every scanned
    speed above the first), "below_scan" (sustained already at the lowest scanned speed), "evaluations"}.
    """
    speeds = [float(v) for v in speeds]
    outcomes = [simulate_knock(sys.at(v), angle).shimmy for v in speeds]
    n = len(speeds)
    if not any(outcomes):
        return {"speed": math.nan, "monotone": True, "below_scan": False, "evaluations": n}
    k = outcomes.index(True)
    monotone = all(outcomes[k:])
    if k == 0:
        return {"speed": speeds[0], "monotone": monotone, "below_scan": True, "evaluations": n}
    low, high = speeds[k - 1], speeds[k]
    while high / low - 1 > rtol:
        mid = math.sqrt(low * high)
        n += 1
        if simulate_knock(sys.at(mid), angle).shimmy:
            high = mid
        else:
            low = mid
    return {"speed": math.sqrt(low * high), "monotone": monotone, "below_scan": False, "evaluations": n}


MAP_FACTORS = (0.25, 1.0, 4.0)
"""Factors on the default frame stiffness K and lateral mass N of the (K, N) map [-]."""


def stiffness_mass_map(casters: dict, conditions: Conditions = Conditions(), tyre: TyreParameters = TyreParameters(),
                       factors=MAP_FACTORS, angle: float | None = None, rtol: float = 0.01, progress=None) -> dict:
    """Onset and sustained amplitude over a grid of frame stiffness K and lateral mass N (issue 16).

    For each caster and each (K, N) = (f_K K0, f_N N0): the knock onset with the rolling tyre (bisection from
    Eq. 7) and with the brush tyre (lowest sustained speed of a 13-speed scan over 0.2-4 × the measured V_c,
    refined by bisection, :func:`scanned_onset_speed`), and the stable shimmy amplitude (brush tyre) at the
    caster's measured critical speed.

    Parameters
    ----------
    casters : {name: (design, inertia [kg·m²], wheel mass [kg], measured V_c [m/s])}
    conditions : base conditions; K0, N0 from ``conditions.dynamics`` (N split 60/40 fork/bearing block)
    factors : the grid factors for K and N
    angle : knock θ_i [rad] (default θ0)

    Returns
    -------
    dict
        ``rows`` (caster, K, N, f_K, f_N, ω, rolling_onset, tyre_onset, stable_amplitude, eq7) and the
        defaults ``K0``, ``N0``.
    """

    K0, N0 = float(conditions.dynamics.stiffness), float(conditions.dynamics.lateral_mass)
    theta = float(conditions.disturbance_angle if angle is None else angle)
    rows = []
    total = len(casters) * len(factors) ** 2
    done = 0
    for name, (design, inertia, mass, measured) in casters.items():
        v7 = float(critical_shimmy_speed(design.trail, inertia, design.groove, design.damping,
                                         conditions.slip_coefficient))
        for fk in factors:
            for fn in factors:
                dyn = DynamicsParameters(frame_stiffness=K0 * fk, fork_mass=0.6 * N0 * fn,
                                         bearing_block_mass=0.4 * N0 * fn)
                cond = conditions.replace(inertia=Fixed(inertia), dynamics=dyn)
                try:
                    rolling = knock_onset_speed(caster_dynamics(design, cond, 1.0, None), theta, rtol=rtol).speed
                except SolverError:
                    rolling = math.nan
                t = tyre.replace(wheel_mass=mass)
                sys_t = caster_dynamics(design, cond, 1.0, t)
                scan = scanned_onset_speed(sys_t, theta, np.geomspace(0.2, 4.0, 13) * measured, rtol=rtol)
                onset_t = scan["speed"]
                orb = _find_stable(sys_t.at(measured))
                rows.append({"caster": name, "K": K0 * fk, "N": N0 * fn, "K_factor": fk, "N_factor": fn,
                             "frequency": sys_t.frequency, "eq7": v7, "measured": measured,
                             "rolling_onset": rolling, "tyre_onset": onset_t, "tyre_onset_monotone": scan["monotone"],
                             "tyre_onset_below_scan": scan["below_scan"],
                             "stable_amplitude": math.nan if orb is None else orb.amplitude,
                             "stable_max_multiplier": math.nan if orb is None
                             else float(np.max(np.abs(orb.multipliers)))})
                done += 1
                if progress is not None:
                    progress(done, total)
    return {"rows": rows, "K0": K0, "N0": N0, "factors": list(factors), "angle": theta}


def map_casters() -> dict:
    """The three casters of the (K, N) map: Appendix C (T = 2.5 in) and Table 1 wheels C and G (T = 2 in)."""

    case = APPENDIX_C_CASE
    i_c = 4 * BARE_FORK_DAMPING * case.trail**2 / (math.pi * case.critical_speed**2)
    out = {"Appendix C": (Design(case.trail, 0.2, 0.0, BARE_FORK_DAMPING), i_c, 0.444, case.critical_speed)}
    for key in ("C", "G"):
        w = table1_wheel(key)
        out[f"Table 1 {key}"] = (Design(TABLE1_TRAIL, w.diameter, 0.0, BARE_FORK_DAMPING), w.inertia, w.mass,
                                 w.critical_speed)
    return out


def friction_sensitivity(design: Design, conditions: Conditions, speed: float,
                         coefficients=(0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0),
                         tyre: TyreParameters = TyreParameters()) -> list[dict]:
    """Fold and stable shimmy amplitude for several tyre friction coefficients μ [-].

    For each μ: the orbit branch followed in amplitude (0.03–3 rad); the fold (lowest speed of any orbit
    [m/s] and its amplitude [rad], the smallest sustained shimmy) and the stable amplitude at ``speed``.
    """
    rows = []
    for mu in coefficients:
        sys = caster_dynamics(design, conditions, speed, tyre.replace(friction_coefficient=float(mu)))
        branch = continue_orbits(sys, np.geomspace(0.03, 3.0, 26))
        stable = [o for o in branch.orbits if o.stable]
        fold = min(branch.orbits, key=lambda o: o.speed) if stable else None
        orb = _find_stable(sys, angles=(0.6, 1.2, 0.3, 2.4, 0.15))
        rows.append({"friction_coefficient": float(mu),
                     "fold_speed": math.nan if fold is None else fold.speed,
                     "fold_amplitude": math.nan if fold is None else fold.amplitude,
                     "stable_amplitude": math.nan if orb is None else orb.amplitude,
                     "max_abs_multiplier": math.nan if orb is None else float(np.max(np.abs(orb.multipliers))),
                     "closure": math.nan if orb is None else orb.closure})
    return rows


def appendix_c_caster() -> tuple[Design, Conditions]:
    """The caster of Appendix C / Fig. 1C: T = 2.5 in, bare fork, I_w from V_c = 2.53 m/s by Eq. 7 (B = 0)."""

    case = APPENDIX_C_CASE
    i_c = 4 * BARE_FORK_DAMPING * case.trail**2 / (math.pi * case.critical_speed**2)
    return Design(case.trail, 0.2, 0.0, BARE_FORK_DAMPING), Conditions(inertia=Fixed(i_c))


def limit_cycle_study(progress=None, quick: bool = False) -> dict:
    """Everything the results/simulation limit-cycle report shows (issue 16); minutes of CPU.

    Appendix C caster: bifurcation diagrams (brush tyre and rolling tyre), stable amplitude against the
    measured 8° and its dependence on μ, knock-safe speeds (θ0, 2θ0); Table 1 comparison; (K, N) map.
    ``quick`` uses a 3 × 3 map and fewer orbits (for checking the pipeline, not for results).
    """


    def say(text):
        if progress is not None:
            progress(text)

    t0 = time.perf_counter()
    design, cond = appendix_c_caster()
    say("bifurcation diagram (brush tyre)")
    bif = bifurcation_diagram(design, cond, TyreParameters(), speed_range=(0.3, 4.0),
                              reference_speed=APPENDIX_C_CASE.critical_speed, points=12 if quick else 28)
    say("bifurcation diagram (rolling tyre)")
    roll = bifurcation_diagram(design, cond, None, speed_range=(0.3, 4.0), points=8 if quick else 16,
                               max_amplitude=1.5)
    say("stable amplitude against μ")
    fric = friction_sensitivity(design, cond, APPENDIX_C_CASE.critical_speed,
                                (0.15, 0.7) if quick else (0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0))
    say("knock-safe speeds")
    theta0 = float(cond.disturbance_angle)
    knock = {}
    for label, tyre in (("rolling", None), ("brush", TyreParameters())):
        for k in (1, 2):
            knock[f"{label}_{k}theta0"] = knock_safe_speed(design, cond, angle=k * theta0, tyre=tyre)
    say("rolling limit of the brush tyre")
    factor = 30.0
    from designer.analysis.simulate import onset_speed as _today_onset  # today's model, for the reduction check

    today = _today_onset(design, cond, rtol=0.002)
    limit = knock_onset_speed(caster_dynamics(design, cond, 1.0, TyreParameters().rolling_limit(factor)), theta0,
                              rtol=0.002, guess=today.speed)
    rolling_limit = {"factor": factor, "today": today.speed, "tyre_limit": limit.speed,
                     "today_bracket": [today.low, today.high], "tyre_limit_bracket": [limit.low, limit.high]}
    say("Table 1")
    table = table1_comparison(rtol=0.01 if quick else 0.005)
    say("(K, N) map")
    kn = stiffness_mass_map(map_casters(), factors=(0.25, 4.0) if quick else MAP_FACTORS,
                            progress=None if progress is None else (lambda i, n: progress(f"map {i}/{n}")))
    return {"bifurcation": bif, "rolling": roll, "friction": fric, "knock_safe": knock, "table1": table,
            "rolling_limit": rolling_limit,
            "map": kn, "measured": {"speed": APPENDIX_C_CASE.critical_speed,
                                    "amplitude": APPENDIX_C_CASE.steady_amplitude},
            "seconds": time.perf_counter() - t0, "quick": quick}
