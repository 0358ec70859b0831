"""Lateral tyre force of the caster wheel: a brush model that slips and saturates.

The paper's shimmy model (Appendix B) lets the tyre roll without lateral
slip (Eq. 6B): the contact point moves only along the wheel plane, and the
floor supplies whatever lateral force F_N that takes.  Here the contact may
slip.  The lateral slip (tangent of the slip angle) is

    σ = v_c / V,    v_c = X' + T θ' + V θ                       (Eq. 6B residual)

(v_c [m/s] is the lateral velocity of the contact point; Eq. 6B is v_c = 0)
and the floor pushes back with the steady-state brush ("Fiala") force of a
parabolic contact pressure [Pacejka, *Tyre and Vehicle Dynamics*, 2nd ed.,
§3.2.2]:

    F = −C σ + C² σ|σ| / (3 μ L) − C³ σ³ / (27 μ² L²)   for |σ| < σ_sl = 3 μ L / C
    F = −μ L sgn σ                                        beyond (full sliding)

Small slip gives F = −C σ (cornering stiffness C [N/rad]); large slip gives the
friction limit μ L, so the caster load L enters the shimmy model.  With the
saturation removed (``saturation=False``: F = −C σ) and C → ∞ the slip is
forced to zero and the model is the paper's Eq. 6B (checked in the tests:
the onset from the same knock agrees to 0.5 %).

Parameters and their sources
----------------------------
C = 1250 N/rad: the paper's slip coefficient K_s (Appendix C, Eq. 12C, Fig. 3C)
was measured by holding a polyurethane caster (178 N) *at fixed angles to the
treadmill belt* and recording the force against ΔV/V, i.e. lateral force per
unit lateral slip: a cornering stiffness.  Its ratio C/L = 7 /rad is in the
range of hard solid tyres.

μ = 0.7: the paper's sliding turning moment on vinyl tile, Fig. 7A, is about
0.005 m per newton of caster load (``TurningConstants.tile_moment_per_load``);
a contact patch about 20 × 24 mm sliding in rotation gives that moment with a
friction coefficient of about 0.7.  It is an estimate from the paper's turning
data, not a direct measurement; the report maps its effect.

L = 178 N: the Fig. 3C test load (Table 1's critical speeds were measured at
160 N).

No relaxation length: the force follows the slip at once.  A caster tyre's
relaxation length (about half the contact length, ~1 cm) is short against
the ~0.6 m the chair travels in one shimmy period at 1.5-2.5 m/s.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from designer.data.paper import SLIP_COEFFICIENT
from designer.errors import InputError
from designer.physics.types import Array, Numeric
from designer.units import parse_quantity

TYRE_FRICTION_COEFFICIENT = 0.7
"""Tyre-floor friction coefficient μ [-] (vinyl tile); estimated from the paper's sliding turning moment,
Fig. 7A (0.005 m per newton of load over a ~20 × 24 mm patch; ``TurningConstants``)."""

TYRE_TEST_LOAD = 178.0
"""Caster load L [N] of the paper's slip-coefficient test (Appendix C, Fig. 3C)."""


TYRE_DIMENSIONS = {
    "cornering_stiffness": "force",
    "friction_coefficient": "dimensionless",
    "load": "force",
    "wheel_mass": "mass",
}
"""The dimension of each number of :class:`TyreParameters` (read by :func:`designer.units.parse_quantity`)."""


@dataclass(frozen=True)
class TyreParameters:
    """Lateral tyre model of the caster wheel (brush model, module docstring).

    Attributes
    ----------
    cornering_stiffness : C [N/rad] (default K_s = 1250 N, Fig. 3C)
    friction_coefficient : μ [-] (default 0.7, from the turning data of Fig. 7A)
    load : caster load L [N] (default 178 N, Fig. 3C)
    wheel_mass : M_W [kg], lumped at the wheel (Eq. 9B); with the no-slip
        constraint it drops out, with a slipping tyre it does not.  Default
        0.444 kg: Table 1 wheel C, whose I_w (1.07e-3 kg·m²) is nearest the
        Appendix C wheel's 1.04e-3.
    saturation : False gives the linear tyre F = −C σ (no friction limit)
    """

    cornering_stiffness: float = SLIP_COEFFICIENT
    friction_coefficient: float = TYRE_FRICTION_COEFFICIENT
    load: float = TYRE_TEST_LOAD
    wheel_mass: float = 0.444
    saturation: bool = True

    def __post_init__(self) -> None:

        for name in ("cornering_stiffness", "friction_coefficient", "load", "wheel_mass"):
            value = parse_quantity(getattr(self, name), TYRE_DIMENSIONS[name], f"tyre {name}")  # the one rule
            if value <= 0:
                raise InputError(f"tyre {name} = {value!r}: must be a positive finite number")
            object.__setattr__(self, name, value)

    @property
    def friction_limit(self) -> float:
        """μ L [N]: the largest lateral force the floor can give."""
        return self.friction_coefficient * self.load

    @property
    def sliding_slip(self) -> float:
        """σ_sl = 3 μ L / C [-]: slip at which the whole contact slides (brush model)."""
        return 3 * self.friction_limit / self.cornering_stiffness

    def replace(self, **changes: Any) -> "TyreParameters":
        """A copy with some fields changed."""
        return replace(self, **changes)

    def rolling_limit(self, stiffness_factor: float = 1e3) -> "TyreParameters":
        """The limit in which the model is the paper's Eq. 6B: no saturation, C × ``stiffness_factor``."""
        return replace(self, saturation=False, cornering_stiffness=self.cornering_stiffness * stiffness_factor)


def lateral_tyre_force(slip: Numeric, tyre: TyreParameters = TyreParameters()) -> Numeric:
    """Lateral floor force on the tyre, brush model [N] (module docstring; Pacejka §3.2.2).

    F = −C σ + C² σ|σ|/(3 μ L) − C³ σ³/(27 μ² L²) for |σ| < 3 μ L / C, −μ L sgn σ beyond;
    F = −C σ when ``tyre.saturation`` is False.

    Parameters
    ----------
    slip : lateral slip σ = v_c / V [-] (tangent of the slip angle); float or ndarray
    tyre : the tyre's C [N/rad], μ [-], L [N]

    Returns the force in the direction of +X (opposing the slip) [N].
    """
    C = tyre.cornering_stiffness
    if not tyre.saturation:
        return -C * slip
    F_max = tyre.friction_limit
    s_sl = 3 * F_max / C
    if np.ndim(slip) == 0:
        sigma = float(slip)  # a float, a NumPy scalar or a 0-d array
        a = abs(sigma)
        if a >= s_sl:
            return -F_max if sigma > 0 else F_max
        r = a / s_sl
        magnitude = F_max * (1 - (1 - r) ** 3)
        return -magnitude if sigma > 0 else magnitude
    slips = np.asarray(slip, dtype=float)
    ratio = np.minimum(np.abs(slips) / s_sl, 1.0)
    force: Array = -np.sign(slips) * F_max * (1 - (1 - ratio) ** 3)
    return force
