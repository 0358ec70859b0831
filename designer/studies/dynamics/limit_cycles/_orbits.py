"""Periodic orbits: shooting on the section θ' = 0 at a maximum, Floquet multipliers, continuation.

The method is described in :mod:`designer.studies.dynamics.limit_cycles`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from typing import TypeAlias

import numpy as np

from designer.studies.dynamics.limit_cycles._system import CasterDynamics, _integrate
from designer.errors import SolverError
from designer.studies.dynamics.limit_cycles._results import Branch, PeriodicOrbit

Residual: TypeAlias = Callable[[np.ndarray], "np.ndarray | None"]
"""A shooting residual: the weighted return-map residual of the unknowns [rad], None where the map is undefined."""


def _weights(sys: CasterDynamics) -> np.ndarray:
    """Section coordinates → rad: X/T, X'/(ωT), θ."""
    T, w = sys.trail, sys.frequency
    return np.array([1 / T, 1 / (w * T), 1.0]) if sys.tyre is not None else np.array([1 / T, 1.0])


def _full_period(
    sys: CasterDynamics, z: np.ndarray, signs: tuple[float, ...] = (-1.0, 1.0)
) -> tuple[np.ndarray | None, float]:
    """Section state after one full period (no symmetry used) and the period [s]; ``signs`` (-1.0,): after half
    of it, at the next minimum of θ (None where the motion stops first)."""
    period = 2 * math.pi / sys.frequency
    state, time = np.append(z, 0.0), 0.0
    for sign in signs:  # to the next minimum, then back to a maximum
        run = _integrate(sys, state, 20 * period, stop_at_end_of=sign)
        if run.reason != "section":
            return None, math.nan
        state, time = run.state, time + run.time
    return np.asarray(state[:-1]), time


def _scales(sys: CasterDynamics, z: np.ndarray) -> np.ndarray:
    """Scales of the section state z (X, [X',] θ = A): T A, [V A,] A (difference steps)."""
    A = abs(z[-1])
    return np.concatenate([[sys.trail * A], [sys.speed * A] if sys.size == 4 else [], [A]])


def _half_map(sys: CasterDynamics, z: np.ndarray) -> tuple[np.ndarray | None, float]:
    """G(z) = −H(z): from a maximum of θ (θ' = 0, section state z) to minus the state at the next minimum."""
    end, time = _full_period(sys, z, signs=(-1.0,))
    return (None if end is None else -end), time


# long: Newton on the half-period map, its step control, Floquet multipliers and the closure check
def _damped_newton(
    residual: Residual,
    u: np.ndarray,
    scales: Callable[[np.ndarray], np.ndarray],
    tol: float,
    max_iter: int,
    what: str,
    flip_step: bool,
) -> tuple[np.ndarray, np.ndarray, int]:
    """Newton's method with a forward-difference Jacobian and step halving, for the shooting maps below.

    ``residual(u)`` is the weighted return-map residual [rad] or None where the map is undefined (the motion
    stops; at ``u`` too: SolverError); ``scales(u)`` gives the difference step of each unknown (times 1e-7).
    With ``flip_step`` an undefined forward difference is retried backwards.  Returns the unknowns with
    max |residual| <= ``tol``, that residual and the iteration count; raises SolverError naming ``what`` otherwise.
    """
    n = u.size
    iterations = 0
    r = residual(u)
    if r is None:
        raise SolverError(f"{what}: the motion stops from the guess")
    while np.max(np.abs(r)) > tol:
        if iterations >= max_iter:
            raise SolverError(
                f"{what}: Newton did not converge (residual {np.max(np.abs(r)):.2g} rad after {max_iter} iterations)"
            )
        iterations += 1
        steps = scales(u)
        J = np.empty((n, n))
        for j in range(n):
            h = 1e-7 * steps[j]
            up = u.copy()
            up[j] += h
            rp = residual(up)
            if rp is None and flip_step:
                up[j] -= 2 * h
                rp = residual(up)
                h = -h
            if rp is None:
                raise SolverError(f"{what}: map undefined near the guess")
            J[:, j] = (rp - r) / h
        try:
            step = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            raise SolverError(f"{what}: singular Jacobian") from None
        lam = 1.0
        for _ in range(12):
            trial = u + lam * step
            rt = residual(trial)
            if rt is not None and np.max(np.abs(rt)) < np.max(np.abs(r)):
                u, r = trial, rt
                break
            lam /= 2
        else:
            raise SolverError(f"{what}: no descent step (residual {np.max(np.abs(r)):.2g} rad)")
    return u, r, iterations


def periodic_orbit(
    sys: CasterDynamics, amplitude: float, guess: np.ndarray | None = None, tol: float = 1e-9, max_iter: int = 25
) -> PeriodicOrbit:
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
    n = sys.size - 1  # section dimension
    if guess is None:
        # the unstable cycle's speed by Eq. 6 + Eq. 20B (C_D = 4 M_f/(π ω A)) [m/s]
        c_d = 4 * sys.friction_moment / (math.pi * sys.frequency * A)
        a = sys.inertia / sys.trail
        V = (c_d + math.sqrt(c_d**2 + 4 * a * sys.groove_coefficient)) / (2 * a)
        guess = np.array([-sys.trail * A, V]) if n == 2 else np.array([-sys.trail * A, -V * A, V])
    u = np.array(guess, dtype=float)

    def section(u: np.ndarray) -> np.ndarray:
        return np.concatenate([u[:-1], [A]])

    def residual(u: np.ndarray) -> np.ndarray | None:
        if not (u[-1] > 0 and math.isfinite(u[-1])):
            return None
        g, _ = _half_map(sys.at(u[-1]), section(u))
        return None if g is None else (g - section(u)) * w

    scales = np.concatenate([[sys.trail * A], [u[-1] * A] if n == 3 else [], [1.0]])
    what = f"periodic orbit of amplitude {A:.4g} rad"
    u, r, iterations = _damped_newton(residual, u, lambda u: scales, tol, max_iter, what, flip_step=True)
    return _orbit(sys.at(float(u[-1])), section(u), r, iterations)


def continue_orbits(
    sys: CasterDynamics, amplitudes: Iterable[float], progress: Callable[[int, int], object] | None = None
) -> Branch:
    """Follow the branch of symmetric periodic orbits over ``amplitudes`` [rad] (increasing or decreasing).

    Each orbit starts from the previous one (secant prediction of the unknowns scaled by A); a point where
    Newton fails is recorded in ``Branch.failed`` and the next point restarts from the last good orbit.
    """
    orbits: list[PeriodicOrbit] = []
    failed: list[float] = []  # the Branch is built once, at the end (records do not change)
    prev: list[tuple[float, np.ndarray]] = []
    amplitudes = [float(a) for a in amplitudes]
    for i, A in enumerate(amplitudes):
        guesses: list[np.ndarray | None] = [None]
        if prev:  # the last orbit's unknowns scaled by A (V kept); after two, first a secant step
            a2, u2 = prev[-1]
            guesses = [u2 * np.concatenate([np.full(len(u2) - 1, A / a2), [1.0]])]
        if len(prev) >= 2:
            a1, u1 = prev[-2]
            # unknowns scale roughly with A (X, X') or 1/A (V): extrapolate in log A
            k = math.log(A / a2) / math.log(a2 / a1)
            guesses.insert(0, u2 * (u2 / u1) ** k if np.all(u1 * u2 > 0) else u2 + (u2 - u1) * k)
        orb = None
        for guess in guesses:
            try:
                orb = periodic_orbit(sys if guess is None else sys.at(guess[-1]), A, guess)
                break
            except SolverError:
                pass
        if orb is None:
            failed.append(A)
            continue
        orbits.append(orb)
        prev.append((A, np.concatenate([orb.state[:-2], [orb.speed]])))
        if progress is not None:
            progress(i + 1, len(amplitudes))
    return Branch(orbits=orbits, failed=failed)


def _orbit(at: CasterDynamics, z: np.ndarray, r: np.ndarray, iterations: int) -> PeriodicOrbit:
    """The orbit through section point z (θ = A = z[-1]) at ``at``'s speed, found by Newton with final residual
    r: its Floquet multipliers (squared eigenvalues of DG), full-period closure [rad] and period [s]."""
    n = at.size - 1
    w = _weights(at)
    zs = _scales(at, z)
    DG = np.empty((n, n))
    for j in range(n):
        h = 1e-6 * zs[j]
        step = np.where(np.arange(n) == j, h, 0.0)
        (gp, _), (gm, _) = _half_map(at, z + step), _half_map(at, z - step)
        DG[:, j] = np.nan if gp is None or gm is None else (gp - gm) / (2 * h)
    mu = np.linalg.eigvals(DG) if np.all(np.isfinite(DG)) else np.full(n, np.nan + 0j)
    full, period = _full_period(at, z)
    closure = float(np.max(np.abs((full - z) * w))) if full is not None else math.nan
    multipliers = mu**2
    return PeriodicOrbit(
        amplitude=float(z[-1]),
        speed=at.speed,
        state=np.append(z, 0.0),
        period=period,
        multipliers=multipliers,
        stable=bool(np.all(np.abs(multipliers) < 1)),
        closure=closure,
        residual=float(np.max(np.abs(r))),
        iterations=iterations,
    )


def periodic_orbit_at_speed(
    sys: CasterDynamics, guess: np.ndarray, tol: float = 1e-9, max_iter: int = 25
) -> PeriodicOrbit:
    """Symmetric periodic orbit at the fixed speed of ``sys``: Newton on G(z) = z over the whole section state.

    ``guess`` is a state at a maximum of θ (θ' = 0; its last entry is ignored), e.g. from a long simulation.
    Used for the stable branch, swept in speed.  Raises SolverError when Newton fails (past a fold).
    """
    w = _weights(sys)
    n = sys.size - 1
    z = np.array(guess, dtype=float)[:n]

    def residual(z: np.ndarray) -> np.ndarray | None:
        g, _ = _half_map(sys, z)
        return None if g is None else (g - z) * w

    what = f"periodic orbit at {sys.speed:.4g} m/s"
    z, r, iterations = _damped_newton(residual, z, lambda z: _scales(sys, z), tol, max_iter, what, flip_step=False)
    if z[-1] < 0:
        z = -z
    return _orbit(sys, z, r, iterations)


def stable_orbit(
    sys: CasterDynamics, angles: Iterable[float] = (0.6, 1.2, 0.3, 2.4), cycles: float = 40.0, angle_limit: float = 6.0
) -> PeriodicOrbit | None:
    """Sustained shimmy at the speed of ``sys``: simulate a knock θ_i [rad] of each of ``angles`` in turn for
    ``cycles`` periods, then polish the last maximum into a periodic orbit (:func:`periodic_orbit_at_speed`);
    the first stable orbit so found.

    Returns None if every knock decays (no stable cycle reached from it), |θ| passes ``angle_limit`` or the
    integration or the polish fails.
    """
    period = 2 * math.pi / sys.frequency
    for angle in angles:
        try:
            run = _integrate(sys, sys.knock_state(angle), cycles * period, angle_limit=angle_limit)
            maxima = [e for e in run.ends if e[2] > 0] if run.reason == "end" else []
            orb = periodic_orbit_at_speed(sys, maxima[-1][3]) if maxima else None
        except SolverError:
            orb = None
        if orb is not None and orb.stable:
            return orb
    return None


def speed_sweep(sys: CasterDynamics, speeds: Iterable[float], start: PeriodicOrbit) -> Branch:
    """Follow an orbit in speed (each Newton solve starts from the last orbit); stops at the first failure."""
    orbits: list[PeriodicOrbit] = []
    failed: list[float] = []
    z = start.state
    for v in speeds:
        try:
            orb = periodic_orbit_at_speed(sys.at(v), z)
        except SolverError:
            failed.append(float(v))
            break
        orbits.append(orb)
        z = orb.state
    return Branch(orbits=orbits, failed=failed)
