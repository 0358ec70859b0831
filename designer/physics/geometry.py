"""Geometry of the swivelling caster: swept radius and the trail of a tilted stem.

Notation: fork offset e [m] (perpendicular distance from the stem axis to the
wheel axle; with the stem vertical it is the trail T of the paper), wheel
radius R = d/2 [m], stem angle φ [rad] (tilt of the stem axis from vertical,
positive when its top leans back, towards the rear wheels).  The derivation
and the figure are in ``docs/retrofit.md``.
"""

from __future__ import annotations

import numpy as np

from designer.physics._checks import is_symbolic
from designer.physics.types import Scalar


def swept_radius(trail: Scalar, diameter: Scalar) -> Scalar:
    """Radius swept by the caster wheel about the spindle axis [m].

    R_s = T + d/2: the tyre's front edge reaches this far from the spindle when
    the caster swivels, so footrests and frame must clear it (docs/model.md#shimmy;
    the paper's Fig. 13 test fork shows the geometry).  With a tilted stem, T is
    the fork offset e: the wheel is a disc in a plane that contains the stem
    axis, so its farthest point from the axis is e + R whatever the tilt
    (docs/retrofit.md).

    Parameters
    ----------
    trail : float | array | casadi
        Trail T (fork offset e) [m].
    diameter : float | array | casadi
        Wheel diameter d [m].
    """
    return trail + diameter / 2


def ground_trail(offset: Scalar, radius: Scalar, stem_angle: Scalar) -> Scalar:
    """Trail along the floor of a caster whose stem is tilted by φ from vertical [m].

    t_g = (e + R sin φ) / cos φ

    The distance on the floor from the point where the stem axis meets it to
    the tyre contact (directly below the axle).  It is the bicycle trail
    t = (R cos θ_h − o)/sin θ_h of the same geometry with the fork turned
    round: head angle θ_h = 90° − φ, fork rake o = −e (a bicycle's fork
    offset leads the steering axis, a caster's trails it); ``docs/retrofit.md``.

    Parameters
    ----------
    offset : fork offset e [m] (the trail T with the stem vertical)
    radius : wheel radius R = d/2 [m]
    stem_angle : φ [rad], positive when the stem's top leans back

    Works on floats, NumPy arrays and CasADi symbols.
    """
    return effective_trail(offset, radius, stem_angle) / np.cos(stem_angle)  # t_g = T_eff / cos φ


def effective_trail(offset: Scalar, radius: Scalar, stem_angle: Scalar) -> Scalar:
    """Effective trail of a tilted stem: the trail that enters Eq. 7 and the turning effort [m].

    T_eff = e + R sin φ  (= t_g cos φ, the bicycle's "normal" or mechanical trail)

    It is the perpendicular distance from the tyre contact to the stem axis:
    the lever arm of the lateral tyre force about the stem (Eq. 4B, Eq. 9)
    and, per unit swivel rate, the lateral speed of the contact (Eq. 6B).
    The paper's planar model (Appendix B) then holds with T = T_eff; what it
    leaves out is second order in φ (the wheel's heading turns by θ cos φ,
    1 − cos 5° = 0.4 %) or not in the model at all (the load's self-centring
    moment of a tilted axis).  φ = 0 gives T_eff = e.

    Parameters
    ----------
    offset : fork offset e [m] (the trail T with the stem vertical)
    radius : wheel radius R = d/2 [m]
    stem_angle : φ [rad], positive when the stem's top leans back (more trail)

    Works on floats, NumPy arrays and CasADi symbols.
    """
    is_symbolic(offset, radius, stem_angle)  # switches CasADi's NumPy mode on for a symbol (np.sin of it)
    return offset + radius * np.sin(stem_angle)
