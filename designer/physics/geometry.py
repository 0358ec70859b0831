"""Geometry of the swivelling caster."""
from __future__ import annotations


def swept_radius(trail, diameter):
    """Radius swept by the caster wheel about the spindle axis [m].

    R_s = T + d/2: the tyre's front edge reaches this far from the spindle when
    the caster swivels, so footrests and frame must clear it (docs/model.md#shimmy; the
    paper's Fig. 13 test fork shows the geometry).

    Parameters
    ----------
    trail : float | array | casadi
        Trail T [m].
    diameter : float | array | casadi
        Wheel diameter d [m].
    """
    return trail + diameter / 2
