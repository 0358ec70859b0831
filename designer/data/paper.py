"""Table 1 and the constants of the reference paper, with their sources.

Units are SI.  Table 1's column "Moment of Inertia kg-m²" is printed in units
of 1e-3 kg·m² (docs/model.md#wheel-inertia): Eq. 8 uses I_w = 0.00127 kg·m² for a 7¾ in wheel,
and a thin disc, m r²/4, reproduces wheels A and B only with that factor.
The values below are therefore the printed numbers times 1e-3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from designer.units import INCH as INCH  # the one definition of the inch; the paper's lengths are in inches

SLIP_COEFFICIENT = 1250.0
"""Tyre slip coefficient K_s [N]; Appendix C, Eq. 12C and Fig. 3C
(polyurethane tyre, 178 N load, treadmill at 2 km/h)."""

BARE_FORK_DAMPING = 1.3
"""Lumped spindle friction damping M_f/θ0 of the bare ball-bearing test fork
[N·m/rad]; Appendix C, Eq. 11C (fit to Bruning's data, Fig. 2C)."""

DISTURBANCE_ANGLE = math.radians(20.0)
"""Design disturbance angle θ0 [rad]; Appendix C: the initial displacement
seen when the caster is struck with a rubber hammer, "on the order of
θ0 = 20 degrees = 0.35 radians"."""

WALKING_SPEED = 1.0
"""Moderate walking speed [m/s]; text beside Table 1 ("about one meter per
second (2.24 mph)")."""

TABLE1_STABLE_UP_TO = 3.8
"""Maximum treadmill speed [m/s] at which wheels A and B were still stable;
Table 1 footnote ("up to 3.8 m/s (13.7 km/hr)")."""


@dataclass(frozen=True)
class Wheel:
    """One caster wheel of Table 1.

    Attributes
    ----------
    key : str
        Table 1 letter (A–G).
    name : str
        Maker and model as printed.
    diameter : float
        Wheel diameter d [m].
    mass : float
        Wheel mass M_w [kg].
    inertia : float
        Moment of inertia about a diameter I_w [kg·m²] (printed value × 1e-3).
    critical_speed : float | None
        Measured critical shimmy speed at 2 in trail [m/s]; None where the
        wheel was stable up to the treadmill's 3.8 m/s.
    """

    key: str
    name: str
    diameter: float
    mass: float
    inertia: float
    critical_speed: float | None


TABLE1: tuple[Wheel, ...] = (
    Wheel("A", "Quadra", 0.1016, 0.280, 0.18e-3, None),
    Wheel("B", "Kryptonics (Mod.)", 0.1270, 0.338, 0.33e-3, None),
    Wheel("C", "E & J (Mod.)", 0.1778, 0.444, 1.07e-3, 2.39),
    Wheel("D", "PRC Pneumatic", 0.2032, 0.562, 1.25e-3, 1.77),
    Wheel("E", "Stainless", 0.2032, 0.815, 1.60e-3, 1.46),
    Wheel("F", "E & J 8 x 7/8", 0.2032, 0.699, 2.00e-3, 1.58),
    Wheel("G", "E & J 8 x 1 1/4", 0.2032, 1.380, 3.42e-3, 1.20),
)
"""Table 1, "Caster wheel parameters" (test fork, 2 in trail, 160 N load)."""

TABLE1_TRAIL = 2.0 * INCH
"""Trail at which Table 1's critical speeds were measured [m]."""

TABLE1_SOURCE = (
    'Table 1, "Caster wheel parameters": seven commercial wheels (A-G) with their diameter, mass and '
    "measured moment of inertia; wheels C-G with their critical speed measured on the test fork at 2 in "
    "trail, 160 N load, bare ball-bearing spindle (B = 0); A and B stable up to 3.8 m/s"
)
"""Provenance of the scales derived from Table 1 (the risk law's model error and inertia prediction)."""

DAMPING_SOURCE = (
    'Appendix C, Eq. 11C: "several caster shimmy tests reported by Bruning (7) were plotted and an overall '
    'M_f/θ_0 calculated ... Fitting a curve to the data gives M_f/θ_0 = 1.3" (Fig. 2C); the paper gives '
    "no scatter for it"
)
"""Provenance of c_f = M_f/θ0 = 1.3 N·m/rad (:data:`BARE_FORK_DAMPING`); its scatter is an assumption."""

SLIP_COEFFICIENT_SOURCE = (
    'Appendix C, Eq. 12C and Fig. 3C: "it was found that K_s = 1250 newtons. Results for other speeds, '
    'tire materials, and loads did not change K_s significantly" (one polyurethane tyre, 178 N); the '
    "paper gives no scatter for it"
)
"""Provenance of K_s = 1250 N (:data:`SLIP_COEFFICIENT`); its scatter is an assumption."""


def table1_wheel(key: str) -> Wheel:
    """Return the Table 1 wheel with letter ``key`` (case-insensitive).

    Raises
    ------
    KeyError
        With a message listing the valid letters.
    """
    for wheel in TABLE1:
        if wheel.key == key.strip().upper():
            return wheel
    valid = ", ".join(w.key for w in TABLE1)
    raise KeyError(f"unknown Table 1 wheel {key!r}: valid wheels are {valid}")


@dataclass(frozen=True)
class _Eq8Case:
    """The sample calculation of Eq. 8 (Fig. 4, Invacare 7¾ in wheel)."""

    trail: float = 0.0508
    groove: float = 0.0143
    inertia: float = 0.00127
    damping: float = BARE_FORK_DAMPING
    slip_coefficient: float = SLIP_COEFFICIENT
    critical_speed: float = 2.91


EQ8_CASE = _Eq8Case()
"""Eq. 8: B = 9/16 in (0.0143 m), T = 2 in, I_w = 0.00127 kg·m², gives 2.91 m/s."""


@dataclass(frozen=True)
class _AppendixCCase:
    """Appendix C, Eqs. 6C–8C: the measured shimmy trace of Fig. 1C."""

    critical_speed: float = 2.53
    frequency: float = 104.7
    trail: float = 0.0635
    steady_amplitude: float = 0.14
    initial_angle: float = 0.35


APPENDIX_C_CASE = _AppendixCCase()
"""Appendix C: V_c = 2.53 m/s, ω = 104.7 rad/s, T = 2.5 in, θ_a = 0.14 rad, θ0 = 0.35 rad."""
