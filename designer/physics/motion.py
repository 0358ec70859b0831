"""The caster's equations of motion with Coulomb spindle friction (Appendix B), written once.

Two-degree-of-freedom model of Fig. 1B: lateral spindle displacement X [m] and caster angle θ [rad].
Eq. 3B and 4B with F_N eliminated (Eq. 5B) and the mass distribution of Eq. 9B–11B (wheel mass at the
contact point, fork mass at the spindle, so I_G − a b M_C = I_w and the wheel mass drops out) give

    T K X + T N X'' = I_w θ'' + M_f sgn(θ') + (K_s B²/(2V)) θ'

with N = M_F + M_1 (Eq. 14B), the spindle moment the Coulomb friction M_f sgn θ' instead of Eq. 4B's
C_D θ', and the treads' moment (K_s B²/2) θ'/V of Eq. 2B.  The tyre rolls without lateral slip, Eq. 6B:
X' = −T θ' − V θ, hence X'' = −T θ'' − V θ' (Eq. 7B).  The state y = (X, θ, θ') then obeys

    X'  = −T θ' − V θ
    θ'' = [ T K X − D θ' − M_f sgn θ' ] / J,      J = I_w + N T²,   D = N T V + K_s B²/(2V)

(J and D are a3 and a2 − C_D of Eq. 12B: differentiating the second line once gives Eq. 12B with C_D θ''
replaced by d/dt(M_f sgn θ')).  While θ' = 0 the spindle holds the moment T K X; the caster sticks while
|T K X| <= M_f, and then X' = −V θ with θ fixed.  A knock starts from θ = θ_i, θ' = θ'_i, θ'' = 0
(Eq. 24B), which fixes X(0).

With the brush tyre of :mod:`designer.physics.tyre` the contact may slip: X' is a state of its own, the
floor's lateral force F(σ) with σ = (X' + T θ' + V θ)/V replaces Eq. 6B, and the wheel mass M at the
contact point no longer drops out; the state is (X, X', θ, θ') (:func:`brush_field`).

Plain floats (and NumPy arrays where it makes sense); the studies integrate these equations
(:mod:`designer.studies.dynamics`: the event-driven stick–slip simulation, the knock-safe speeds and
the periodic orbits) and never write them again.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from designer.physics.tyre import TyreParameters, lateral_tyre_force
from designer.physics.types import Scalar

Field = Callable[[float, Sequence[float]], list[float]]
"""f(t, y) -> y' of the state y = (X, θ, θ')."""


def tread_coefficient(slip_coefficient: Scalar, groove: Scalar) -> Scalar:
    """K_s B²/2 [N·m²]: the two treads' moment about the spindle is this × θ'/V (Eq. 2B).

    Parameters
    ----------
    slip_coefficient : tyre slip coefficient K_s [N]
    groove : groove width B [m]
    """
    return slip_coefficient * groove**2 / 2


def rolling_coefficients(
    trail: float, inertia: float, lateral_mass: float, speed: float, tread: float
) -> tuple[float, float]:
    """(J, D) of the rolling caster: J = I_w + N T² [kg·m²] and D = N T V + K_s B²/(2V) [N·m·s/rad].

    a3 and a2 without the hydraulic damper of Eq. 12B.

    Parameters
    ----------
    trail : T [m]
    inertia : I_w [kg·m²]
    lateral_mass : N = M_F + M_1 [kg] (Eq. 14B)
    speed : V [m/s]
    tread : K_s B²/2 [N·m²] (:func:`tread_coefficient`)
    """
    return inertia + lateral_mass * trail**2, lateral_mass * trail * speed + tread / speed


def rolling_field(
    sign: float, trail: float, stiffness: float, speed: float, friction_moment: float, J: float, D: float
) -> Field:
    """The equations of motion of a rolling caster (module text, Eq. 3B, 4B, 6B) as f(t, y) for an ODE solver.

    Parameters
    ----------
    sign : sgn θ' of the phase: ±1 slip (the friction moment opposes the motion), 0 stick (θ' held at 0:
        X' = −V θ, θ and θ' constant)
    trail : T [m]
    stiffness : frame lateral stiffness K [N/m]
    speed : V [m/s]
    friction_moment : M_f = c_f θ0 [N·m]
    J, D : :func:`rolling_coefficients`
    """
    T, K, V, M_f = trail, stiffness, speed, friction_moment
    if sign == 0:
        return lambda _t, y: [-V * y[1], 0.0, 0.0]
    s = sign
    return lambda _t, y: [-T * y[2] - V * y[1], y[2], (T * K * y[0] - D * y[2] - s * M_f) / J]


def held_moment(lateral: Scalar, trail: float, stiffness: float) -> Scalar:
    """T K X [N·m]: the moment the spindle transmits while θ' = 0 (it sticks while |T K X| <= M_f)."""
    return trail * stiffness * lateral


def knock_lateral(angular_velocity: float, friction_moment: float, trail: float, stiffness: float, D: float) -> float:
    """X(0) [m] after a knock with θ' = θ'_i and θ'' = 0 (Eq. 24B): (D θ'_i + M_f sgn θ'_i) / (T K)."""
    w0 = float(angular_velocity)
    return (D * w0 + math.copysign(friction_moment, w0) * (w0 != 0)) / (trail * stiffness)


def stick_release(angle: float, level: float, trail: float, stiffness: float) -> float:
    """X [m] at which a stuck caster (θ' = 0, θ ≠ 0, X' = −V θ) starts to slip: T K X = −sgn θ · level.

    ``level`` is the friction moment M_f [N·m] (or the held moment a grazing contact must exceed).
    """
    return -math.copysign(level, angle) / (trail * stiffness)


def slip_equilibrium(sign: float, friction_moment: float, trail: float, stiffness: float) -> float:
    """X [m] of the equilibrium y_p = (X, 0, 0) of a slip of sign s: T K X = s M_f."""
    return sign * (friction_moment / (trail * stiffness))


def slip_matrix(trail: float, stiffness: float, speed: float, J: float, D: float) -> np.ndarray:
    """A of the linear flow y' = A (y − y_p) during a slip [SI], y_p = (s M_f/(T K), 0, 0) its equilibrium.

    A = [[0, −V, −T], [0, 0, 1], [T K/J, 0, −D/J]] (module text).
    """
    T, K, V = trail, stiffness, speed
    return np.array([[0.0, -V, -T], [0.0, 0.0, 1.0], [T * K / J, 0.0, -D / J]])


# --------------------------------------------------------------------------- the brush tyre


def brush_field(
    sign: float,
    trail: float,
    inertia: float,
    lateral_mass: float,
    stiffness: float,
    speed: float,
    friction_moment: float,
    tread: float,
    tyre: TyreParameters,
) -> Field:
    """The equations of motion with the brush tyre (module text) as f(t, y), y = (X, X', θ, θ').

    Mass matrix [[N + M, M T], [M T, I_w + M T²]] (M the wheel mass at the contact point) on (X'', θ''), forces
    (F − K X, T F − M_f sgn θ' − (K_s B²/2) θ'/V); in a stick (``sign`` 0) θ' = 0 is held and only X moves.

    Parameters
    ----------
    sign : sgn θ' of the phase (±1 slip, 0 stick)
    trail, inertia, lateral_mass, stiffness, speed, friction_moment : T [m], I_w [kg·m²], N [kg], K [N/m],
        V [m/s], M_f [N·m]
    tread : K_s B²/2 [N·m²] (:func:`tread_coefficient`)
    tyre : the brush tyre (cornering stiffness, friction, wheel mass; ``saturation`` False: F = −C σ)
    """
    T, K, N, I, V = trail, stiffness, lateral_mass, inertia, speed
    M_f, G, M = friction_moment, tread / speed, tyre.wheel_mass
    m11, m12, m22 = N + M, M * T, I + M * T**2
    det = m11 * m22 - m12**2
    i11, i12, i22 = m22 / det, -m12 / det, m11 / det
    if not tyre.saturation:
        C = tyre.cornering_stiffness

        def force(v: float) -> Any:
            return -C * v / V
    else:

        def force(v: float) -> Any:
            return lateral_tyre_force(v / V, tyre)

    if sign == 0:

        def stick(_t: float, y: Sequence[float]) -> list[float]:
            F = force(y[1] + V * y[2])
            return [y[1], (F - K * y[0]) / m11, 0.0, 0.0]

        return stick
    s = sign

    def slip(_t: float, y: Sequence[float]) -> list[float]:
        F = force(y[1] + T * y[3] + V * y[2])
        q1 = F - K * y[0]
        q2 = T * F - s * M_f - G * y[3]
        return [y[1], i11 * q1 + i12 * q2, y[3], i12 * q1 + i22 * q2]

    return slip


def brush_held_moment(
    y: Sequence[float], trail: float, lateral_mass: float, stiffness: float, speed: float, tyre: TyreParameters
) -> float:
    """The moment [N·m] the spindle transmits to hold θ' = 0 at the brush-tyre state y = (X, X', θ, θ'):
    T (N F + M K X)/(N + M), F the tyre's lateral force (it sticks while this is at most M_f)."""
    N, M = lateral_mass, tyre.wheel_mass
    F = float(lateral_tyre_force((y[1] + speed * y[2]) / speed, tyre))
    return trail * (N * F + M * stiffness * y[0]) / (N + M)
