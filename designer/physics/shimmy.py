"""Caster shimmy: critical speed and the third-order model of Appendix B.

Notation (paper, Appendix D): trail T [m], wheel inertia about a diameter
I_w [kg·m²], groove width / tread separation B [m], slip coefficient K_s [N],
spindle friction damping c_f = M_f/θ0 [N·m/rad], hydraulic damping C_D
[N·m·s/rad], frame lateral stiffness K [N/m], N = fork mass + bearing-block
mass [kg], speed V [m/s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

from designer.data.paper import APPENDIX_C_CASE, BARE_FORK_DAMPING, SLIP_COEFFICIENT
from designer.parameters import default  # the defaults: one table (designer/parameters.py)
from designer.physics.roots import bracketed_root
from designer.physics.types import Array, Scalar

Coefficients: TypeAlias = tuple[Scalar, Scalar, Scalar, Scalar]
"""(a3, a2, a1, a0) of the caster equation, Eq. 12B."""


def critical_shimmy_speed(
    trail: Scalar, inertia: Scalar, groove: Scalar, damping: Scalar, slip_coefficient: Scalar = SLIP_COEFFICIENT
) -> Scalar:
    """Critical shimmy speed of a friction-damped caster, Eq. 7 (= Eq. 10C) [m/s].

    V_c = sqrt( 4 c_f T² / (π I_w) + K_s B² T / (2 I_w) )

    Parameters
    ----------
    trail : trail T [m]
    inertia : wheel moment of inertia about a diameter I_w [kg·m²]
    groove : groove width (tread separation) B [m]; 0 for a single tread
    damping : spindle friction damping c_f = M_f/θ0 [N·m/rad] (bare fork 1.3, Eq. 11C)
    slip_coefficient : tyre slip coefficient K_s [N] (1250, Appendix C)

    Works on floats, NumPy arrays and CasADi symbols.  Check: Eq. 8 (T = 2 in,
    B = 0.0143 m, I_w = 0.00127, c_f = 1.3) gives 2.91 m/s.
    """
    friction, groove_term = critical_speed_terms(trail, inertia, groove, damping, slip_coefficient)
    return np.sqrt(friction + groove_term)


def critical_speed_terms(
    trail: Scalar, inertia: Scalar, groove: Scalar, damping: Scalar, slip_coefficient: Scalar = SLIP_COEFFICIENT
) -> tuple[Scalar, Scalar]:
    """The two terms of V_c² in Eq. 7 [m²/s²]: (friction damping, co-rotating groove).

    4 c_f T² / (π I_w) and K_s B² T / (2 I_w); their shares tell how the
    caster is stabilised and give the sensitivities of V_c.
    """
    return 4 * damping * trail**2 / (np.pi * inertia), slip_coefficient * groove**2 * trail / (2 * inertia)


def critical_speed_log_sensitivities(
    trail: Scalar, inertia: Scalar, groove: Scalar, damping: Scalar, slip_coefficient: Scalar = SLIP_COEFFICIENT
) -> dict[str, Scalar]:
    """Elasticities d log V_c / d log p of Eq. 7 for the uncertain constants [-].

    With a = 4 c_f T²/(π I_w) and b = K_s B² T/(2 I_w), V_c² = a + b, so
    d log V_c/d log c_f = a / (2(a+b)), d log V_c/d log K_s = b / (2(a+b)),
    d log V_c/d log I_w = −1/2.  Works on floats, arrays and CasADi symbols.
    """
    a, b = critical_speed_terms(trail, inertia, groove, damping, slip_coefficient)
    return {"damping": a / (2 * (a + b)), "slip_coefficient": b / (2 * (a + b)), "inertia": -0.5 + 0 * a}


def critical_speed_hydraulic(
    trail: Scalar,
    inertia: Scalar,
    groove: Scalar,
    hydraulic_damping: Scalar,
    slip_coefficient: Scalar = SLIP_COEFFICIENT,
) -> Scalar:
    """Critical shimmy speed with a hydraulic spindle damper, Eq. 5, positive root [m/s].

    V_c² − (C_D T / I_w) V_c − K_s B² T / (2 I_w) = 0, so
    V_c = ( C_D T/I_w + sqrt((C_D T/I_w)² + 2 K_s B² T / I_w) ) / 2.

    Parameters
    ----------
    hydraulic_damping : torsional viscous damping C_D [N·m·s/rad]
    (others as :func:`critical_shimmy_speed`)
    """
    a = hydraulic_damping * trail / inertia
    return (a + np.sqrt(a**2 + 2 * slip_coefficient * groove**2 * trail / inertia)) / 2


def equivalent_hydraulic_damping(friction_moment: Scalar, amplitude: Scalar, frequency: Scalar) -> Scalar:
    """Hydraulic damping equivalent to a Coulomb friction moment, Eq. 6 = Eq. 3C [N·m·s/rad].

    C_D = 4 M_f / (π θ_a ω): equal work per cycle of sinusoidal motion.

    Parameters
    ----------
    friction_moment : constant friction moment M_f [N·m]
    amplitude : shimmy amplitude θ_a [rad]
    frequency : shimmy frequency ω [rad/s]
    """
    return 4 * friction_moment / (np.pi * amplitude * frequency)


def steady_shimmy_amplitude(speed: Scalar, trail: Scalar, frequency: Scalar, disturbance_angle: Scalar) -> Scalar:
    """Steady amplitude of shimmy at the threshold, Eq. 4 / Eq. 29B [rad].

    θ_a = θ0 V / (ω T): the amplitude left after the transient of Eq. 3 decays.
    """
    return disturbance_angle * speed / (frequency * trail)


def full_shimmy_amplitude(speed: Scalar, trail: Scalar, frequency: Scalar, disturbance_angle: Scalar) -> Scalar:
    """Steady amplitude of the oscillating term of Eq. 3 [rad]: θ_a = θ0 / √(1 + (ω T/V)²).

    Eq. 3's second term, θ0 cos(ωt − φ)/√(1 + ω²T²/V²), without Eq. 4's simplification; Eq. 4's θ0 V/(ω T)
    (:func:`steady_shimmy_amplitude`) is its limit for ω T/V ≫ 1 and overstates it by √(1 + (V/(ω T))²) − 1:
    19 % at ω T/V = 1.54 (indoor-manual's caster at V_c), 1 % only when ω T/V >= 7.  Works on floats, arrays
    and CasADi symbols.
    """
    return disturbance_angle * speed / (speed**2 + (frequency * trail) ** 2) ** 0.5  # = θ0/√(1 + (ωT/V)²), 0 at V = 0


def friction_damping_at_speed(damping: Scalar, trail: Scalar, speed: Scalar) -> Scalar:
    """Equivalent hydraulic damping of spindle friction at speed V [N·m·s/rad].

    Eq. 6 with the amplitude of Eq. 4 (θ_a = θ0 V/(ω T)) and c_f = M_f/θ0:
    C_D = 4 M_f/(π θ_a ω) = 4 c_f T / (π V).  Substituting this into Eq. 20B
    gives Eq. 7 (the paper's own derivation, Appendix C, Eq. 9C).
    """
    return 4 * damping * trail / (np.pi * speed)


@dataclass(frozen=True)
class DynamicsParameters:
    """Frame and fork parameters of the third-order model, Eq. 12B–15B.

    Attributes
    ----------
    frame_stiffness : lateral stiffness K of frame at the bearing block [N/m]
    fork_mass : fork mass M_f (paper's M_F) [kg]
    bearing_block_mass : apparent bearing-block mass M_1 [kg]

    Defaults: the paper does not give K, M_F or M_1.  We take M_F = 0.3 kg and
    M_1 = 0.2 kg (N = 0.5 kg, typical of a steel fork and housing) and choose K
    so that ω = 104.7 rad/s at T = 2.5 in (Appendix C, Eq. 7C) for the wheel of
    that test, whose I_w follows from its measured V_c = 2.53 m/s through Eq. 7
    with B = 0 and c_f = 1.3: I_w = 4 c_f T²/(π V_c²) = 1.043e-3 kg·m².  Then
    K = ω² (I_w + N T²) / T² (Eq. 15B) ≈ 8.3e3 N/m.
    """

    frame_stiffness: float | None = default("frame_stiffness")
    fork_mass: float = default("fork_mass")
    bearing_block_mass: float = default("bearing_block_mass")

    @property
    def lateral_mass(self) -> float:
        """N = M_F + M_1 [kg], Eq. 14B."""
        return self.fork_mass + self.bearing_block_mass

    @property
    def stiffness(self) -> float:
        """K [N/m]: given, or calibrated to Appendix C's ω = 104.7 rad/s at 2.5 in."""
        if self.frame_stiffness is not None:
            return self.frame_stiffness
        case = APPENDIX_C_CASE
        inertia = 4 * BARE_FORK_DAMPING * case.trail**2 / (math.pi * case.critical_speed**2)
        return case.frequency**2 * (inertia + self.lateral_mass * case.trail**2) / case.trail**2


def shimmy_frequency(trail: Scalar, inertia: Scalar, dynamics: DynamicsParameters = DynamicsParameters()) -> Scalar:
    """Natural (shimmy) frequency of the third-order model, Eq. 15B [rad/s].

    ω² = K T² / (I_w + N T²).
    """
    k = dynamics.stiffness
    return np.sqrt(k * trail**2 / (inertia + dynamics.lateral_mass * trail**2))


def third_order_coefficients(
    trail: Scalar,
    inertia: Scalar,
    groove: Scalar,
    hydraulic_damping: Scalar,
    speed: Scalar,
    slip_coefficient: Scalar = SLIP_COEFFICIENT,
    dynamics: DynamicsParameters = DynamicsParameters(),
) -> Coefficients:
    """Coefficients (a3, a2, a1, a0) of the caster equation, Eq. 12B.

    a3 θ''' + a2 θ'' + a1 θ' + a0 θ = 0 with
    a3 = I_w + N T², a2 = C_D + N T V + K_s B²/(2V), a1 = K T², a0 = K T V.

    For friction damping pass ``hydraulic_damping = friction_damping_at_speed(c_f, T, V)``.
    """
    n = dynamics.lateral_mass
    k = dynamics.stiffness
    a3 = inertia + n * trail**2
    a2 = hydraulic_damping + n * trail * speed + slip_coefficient * groove**2 / (2 * speed)
    a1 = k * trail**2
    a0 = k * trail * speed
    return a3, a2, a1, a0


def routh_hurwitz_margin(coefficients: Coefficients) -> Scalar:
    """Routh–Hurwitz stability margin of a cubic, a2 a1 − a3 a0 (Eq. 19B, AB = C).

    With all coefficients positive the caster is stable (no shimmy) when the
    margin is positive and shimmies when it is negative.
    """
    a3, a2, a1, a0 = coefficients
    return a2 * a1 - a3 * a0


def characteristic_roots(coefficients: Coefficients) -> npt.NDArray[np.complex128]:
    """Roots of a3 s³ + a2 s² + a1 s + a0 (Eq. 2 / Eq. 16B exponents λ, μ ± iω) [1/s].

    Numeric only (floats or 1-D arrays of coefficients); returns an array of
    shape (..., 3) of complex roots.
    """
    stacked = np.stack(np.broadcast_arrays(*(np.asarray(c, dtype=float) for c in coefficients)), axis=-1)
    roots = np.array([np.roots(row) for row in stacked.reshape(-1, 4)])
    return roots.reshape(stacked.shape[:-1] + (3,))


def growth_rate(coefficients: Coefficients) -> Array | float:
    """Growth rate μ of the oscillatory mode (real part of μ ± iω), Eq. 16B [1/s].

    Positive: shimmy grows; negative: it decays; zero at the critical speed.
    """
    roots = characteristic_roots(coefficients)
    oscillatory = np.where(np.abs(roots.imag) > 1e-9 * (1 + np.abs(roots.real)), roots.real, -np.inf)
    mu = oscillatory.max(axis=-1)
    return float(mu) if mu.ndim == 0 else mu


def routh_hurwitz_critical_speed(
    trail: float,
    inertia: float,
    groove: float,
    damping: float,
    damping_kind: str = "friction",
    slip_coefficient: float = SLIP_COEFFICIENT,
    dynamics: DynamicsParameters = DynamicsParameters(),
    speed_range: tuple[float, float] = (1e-3, 1e3),
) -> float:
    """Critical speed where the Routh–Hurwitz margin of Eq. 12B crosses zero [m/s].

    Solved numerically (:func:`designer.physics.roots.bracketed_root`, regula falsi) from the full third-order
    coefficients, independently of Eq. 5/7: must equal Eq. 20B, i.e. Eq. 5 for
    ``damping_kind="hydraulic"`` (damping = C_D) and Eq. 7 for ``"friction"``
    (damping = c_f, converted with :func:`friction_damping_at_speed`).
    """

    def margin(speed: float) -> float:
        if damping_kind == "friction":
            c_d = friction_damping_at_speed(damping, trail, speed)
        elif damping_kind == "hydraulic":
            c_d = damping
        else:
            raise ValueError(f"damping_kind = {damping_kind!r}: expected 'friction' or 'hydraulic'")
        coeffs = third_order_coefficients(trail, inertia, groove, c_d, speed, slip_coefficient, dynamics)
        return float(routh_hurwitz_margin(coeffs))

    return bracketed_root(margin, *speed_range, xtol=1e-12, rtol=1e-12, maxiter=500)
