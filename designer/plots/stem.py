"""The tilted stem: side view of the caster geometry and V_c against stem angle (``docs/retrofit.md``).

Drawn from the physics functions (:func:`designer.physics.geometry.effective_trail`,
:func:`designer.physics.geometry.ground_trail`, Eq. 7); no formula is re-typed.
Regenerate the documentation figure with::

    python -m designer.plots.stem docs/retrofit-stem.png
"""

from __future__ import annotations

import math
import sys

import numpy as np

from designer.data.paper import INCH, SLIP_COEFFICIENT
from designer.model import critical_speed
from designer.physics.geometry import effective_trail, ground_trail

EQ8_CASTER = {
    "offset": 1.5 * INCH,
    "diameter": 7.75 * INCH,
    "groove": 0.5625 * INCH,
    "damping": 1.3,
    "inertia": 0.00127,
}
"""The Eq. 8 wheel (I_w = 0.00127 kg·m², 9/16 in groove, c_f 1.3) on a 1.5 in fork: the docs' example."""


def draw_stem_geometry(ax, offset: float, radius: float, angle: float):
    """Side view (x forward, z up) of a caster whose stem leans back by ``angle`` [rad].

    Marks the stem axis down to the floor, the fork offset e (perpendicular to
    the axis), the floor trail t_g and the effective trail T_eff = e + R sin φ
    (perpendicular from the contact to the axis).  Lengths in inches.  Returns ``ax``.
    """
    from matplotlib.patches import Circle  # heavy: matplotlib only when a figure is drawn

    u = np.array([-math.sin(angle), math.cos(angle)])
    n = np.array([-math.cos(angle), -math.sin(angle)])
    s = (radius + offset * math.sin(angle)) / math.cos(angle)
    axle = s * u + offset * n
    contact = axle - np.array([0.0, radius])
    scale = 1 / INCH
    top = (2 * radius + 1.0 * INCH) / math.cos(angle) * u  # the stem reaches above the wheel
    ax.axhline(0, color="0.3", lw=1)
    ax.add_patch(Circle(axle * scale, radius * scale, fill=False, lw=2, color="0.2"))
    ax.plot(*(np.array([[0, 0], top]).T * scale), "--", color="tab:blue", lw=1.2, label="stem axis")
    foot = s * u
    ax.plot(
        *(np.array([foot, axle]).T * scale), color="tab:orange", lw=3, label=f"fork offset e = {offset * scale:.2f} in"
    )
    ax.plot(*axle * scale, "o", color="0.2", ms=4)
    ax.plot(*contact * scale, "o", color="tab:red", ms=5)
    t_g = float(ground_trail(offset, radius, angle))
    t_eff = float(effective_trail(offset, radius, angle))
    ax.annotate(
        "", xy=(0, -0.35), xytext=(contact[0] * scale, -0.35), arrowprops={"arrowstyle": "<->", "color": "tab:green"}
    )
    ax.text(
        contact[0] * scale / 2,
        -0.75,
        f"floor trail t_g = {t_g * scale:.3f} in",
        ha="center",
        color="tab:green",
        fontsize=8,
    )
    proj = float(np.dot(contact, u)) * u  # foot of the perpendicular from the contact to the axis
    ax.plot(
        *(np.array([contact, proj]).T * scale),
        color="tab:purple",
        lw=2,
        label=f"effective trail T_eff = e + R sin φ = {t_eff * scale:.3f} in",
    )
    ax.text(
        top[0] * scale - 0.2,
        top[1] * scale + 0.1,
        f"φ = {math.degrees(angle):.0f}°",
        color="tab:blue",
        fontsize=9,
        ha="right",
    )
    ax.plot([0, 0], [0, top[1] * scale], ":", color="0.6", lw=1)
    ax.set_aspect("equal")
    ax.set_xlabel("x, forward [in]")
    ax.set_ylabel("z [in]")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_ylim(-1.2, top[1] * scale + 0.6)
    ax.set_xlim(axle[0] * scale - radius * scale - 0.3, 7.5)
    return ax


def draw_speed_against_angle(ax, angles, speeds, marks=()):
    """V_c (Eq. 7) against stem angle [deg]; ``marks``: (angle [deg], V_c, label) points to annotate."""
    ax.plot(angles, speeds, color="tab:blue", lw=2)
    for a, v, label in marks:
        ax.plot([a], [v], "o", color="tab:red")
        ax.annotate(label, (a, v), textcoords="offset points", xytext=(6, -12), fontsize=8)
    ax.set_xlabel("stem angle φ [deg] (positive: top leans back)")
    ax.set_ylabel("critical speed V_c, Eq. 7 [m/s]")
    ax.grid(alpha=0.3)
    return ax


def stem_angle_figure(path, caster: dict = EQ8_CASTER, tilt_degrees: float = 5.0, drawn_degrees: float = 15.0):
    """Write the docs figure (:func:`stem_figure`) to ``path`` (120 dpi); returns ``path``."""
    stem_figure(caster, tilt_degrees, drawn_degrees).savefig(path, dpi=120)
    return path


def stem_figure(caster: dict = EQ8_CASTER, tilt_degrees: float = 5.0, drawn_degrees: float = 15.0):
    """The docs figure (a matplotlib Figure): the geometry drawn at ``drawn_degrees`` [deg] (large enough to see
    the angles) and V_c [m/s] (Eq. 7 at the effective trail of Eq. 8) of ``caster`` against stem angle, with
    ±``tilt_degrees`` [deg] marked."""
    import matplotlib  # heavy: matplotlib only when a figure is drawn

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    c = caster
    radius = c["diameter"] / 2
    angles = np.linspace(-10, 10, 201)
    t_eff = effective_trail(c["offset"], radius, np.radians(angles))
    speeds = critical_speed(t_eff, c["inertia"], c["groove"], c["damping"], SLIP_COEFFICIENT)
    marks = []
    for a in (-tilt_degrees, 0.0, tilt_degrees):
        v = float(
            critical_speed(
                effective_trail(c["offset"], radius, math.radians(a)),
                c["inertia"],
                c["groove"],
                c["damping"],
                SLIP_COEFFICIENT,
            )
        )
        marks.append((a, v, f"{a:+.0f}°: {v:.3f} m/s"))
    fig = Figure(figsize=(11, 4.6))
    left, right = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.1, 1]})
    draw_stem_geometry(left, c["offset"], radius, math.radians(drawn_degrees))
    left.set_title(f"7.75 in wheel on a 1.5 in fork, stem drawn {drawn_degrees:.0f}° back", fontsize=10)
    draw_speed_against_angle(right, angles, speeds, marks)
    right.axhline(2.5, color="0.4", ls="--", lw=1)
    right.text(-9.8, 2.52, "V_target 2.5 m/s (indoor-manual)", fontsize=8, color="0.3")
    right.set_title("Eq. 8 wheel (I_w 0.00127 kg·m², B 9/16 in, c_f 1.3) on a 1.5 in fork", fontsize=10)
    fig.tight_layout()
    return fig


if __name__ == "__main__":  # pragma: no cover - regenerates the docs figure
    stem_angle_figure(sys.argv[1] if len(sys.argv) > 1 else "docs/retrofit-stem.png")
