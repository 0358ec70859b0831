"""The tilted stem: side view of the caster geometry and V_c against stem angle (``docs/retrofit.md``).

Draws the arrays of :func:`designer.studies.curves.stem_curves` (the physics' effective and ground trail,
Eq. 7 by the model); computes nothing.  Regenerate the documentation figure with::

    python docs/img/render.py retrofit-stem
"""

from __future__ import annotations

import math

import numpy as np

from designer.display import axis, shown, unit
from designer.plots.fronts import dress


def draw_stem_geometry(ax, geometry: dict):
    """Side view (x forward, z up) of a caster whose stem leans back (``geometry`` of
    :func:`designer.studies.curves.stem_curves`).

    Marks the stem axis down to the floor, the fork offset e (perpendicular to
    the axis), the floor trail t_g and the effective trail T_eff = e + R sin φ
    (perpendicular from the contact to the axis).  Lengths in inches.  Returns ``ax``.
    """
    from matplotlib.patches import Circle  # heavy: matplotlib only when a figure is drawn

    g = geometry
    offset, radius, angle = g["offset"], g["radius"], g["angle"]
    axle, contact, foot, top = g["axle"], g["contact"], g["foot"], g["top"]
    scale = unit("length", "in").factor  # drawn in inches
    ax.axhline(0, color="0.3", lw=1)
    ax.add_patch(Circle(axle * scale, radius * scale, fill=False, lw=2, color="0.2"))
    ax.plot(*(np.array([[0, 0], top]).T * scale), "--", color="tab:blue", lw=1.2, label="stem axis")
    label = f"fork offset e = {shown(offset, dimension='length', units='in')}"
    ax.plot(*(np.array([foot, axle]).T * scale), color="tab:orange", lw=3, label=label)
    ax.plot(*axle * scale, "o", color="0.2", ms=4)
    ax.plot(*contact * scale, "o", color="tab:red", ms=5)
    t_g, t_eff = g["ground_trail"], g["effective_trail"]
    arrow = {"arrowstyle": "<->", "color": "tab:green"}
    ax.annotate("", xy=(0, -0.35), xytext=(contact[0] * scale, -0.35), arrowprops=arrow)
    text = f"floor trail t_g = {shown(t_g, dimension='length', units='in')}"
    ax.text(contact[0] * scale / 2, -0.75, text, ha="center", color="tab:green", fontsize=8)
    proj = g["projection"]  # foot of the perpendicular from the contact to the axis
    label = f"effective trail T_eff = e + R sin φ = {shown(t_eff, 'effective_trail', 'in')}"
    ax.plot(*(np.array([contact, proj]).T * scale), color="tab:purple", lw=2, label=label)
    text = f"φ = {math.degrees(angle):.0f}°"
    ax.text(top[0] * scale - 0.2, top[1] * scale + 0.1, text, color="tab:blue", fontsize=9, ha="right")
    ax.plot([0, 0], [0, top[1] * scale], ":", color="0.6", lw=1)
    ax.set_aspect("equal")
    dress(ax, "x, forward [in]", "z [in]", legend=dict(fontsize=7, loc="upper right"), grid=False)
    ax.set_ylim(-1.2, top[1] * scale + 0.6)
    ax.set_xlim(axle[0] * scale - radius * scale - 0.3, 7.5)
    return ax


def draw_speed_against_angle(ax, angles, speeds, marks=()):
    """V_c (Eq. 7) against stem angle [deg]; ``marks``: (angle [deg], V_c, label) points to annotate."""
    ax.plot(angles, speeds, color="tab:blue", lw=2)
    for a, v, label in marks:
        ax.plot([a], [v], "o", color="tab:red")
        ax.annotate(label, (a, v), textcoords="offset points", xytext=(6, -12), fontsize=8)
    return dress(ax, "stem angle φ [deg] (positive: top leans back)", f"{axis('critical_speed')}, Eq. 7")


def stem_figure(curves: dict):
    """The docs figure (a matplotlib Figure) of :func:`designer.studies.curves.stem_curves`: the geometry drawn at
    its angle (large enough to see the angles) and V_c [m/s] (Eq. 7 at the effective trail of Eq. 8) against
    stem angle, with the curves' marked angles."""
    import matplotlib  # heavy: matplotlib only when a figure is drawn

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    g = curves["geometry"]
    marks = [(a, v, f"{a:+.0f}°: {shown(v, 'critical_speed')}") for a, v in curves["marks"]]
    fig = Figure(figsize=(11, 4.6))
    left, right = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.1, 1]})
    draw_stem_geometry(left, g)
    left.set_title(f"7.75 in wheel on a 1.5 in fork, stem drawn {math.degrees(g['angle']):.0f}° back", fontsize=10)
    draw_speed_against_angle(right, curves["angles"], curves["speeds"], marks)
    right.axhline(2.5, color="0.4", ls="--", lw=1)
    right.text(-9.8, 2.52, "V_target 2.5 m/s (indoor-manual)", fontsize=8, color="0.3")
    right.set_title("Eq. 8 wheel (I_w 0.00127 kg·m², B 9/16 in, c_f 1.3) on a 1.5 in fork", fontsize=10)
    fig.tight_layout()
    return fig
