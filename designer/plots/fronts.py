"""Fronts over fronts: arrays in, matplotlib Axes out.

:func:`draw_fronts` draws turning effort F_turn [N] against sill force P [N] for several fronts (the
continuous risk-bounded front under the buildable one, so the price of stock can be read off; or the
nominal front under the risk-bounded one, the price of safety) and marks single designs on them.
"""
from __future__ import annotations

import numpy as np

CURVE_STYLE = {
    "continuous": dict(color="#1f77b4", lw=1.6, ls="-", marker=None, ms=0, zorder=2),
    "nominal": dict(color="#7f7f7f", lw=1.4, ls="--", marker="o", ms=3, zorder=2),
    "risk-bounded": dict(color="#1f77b4", lw=1.6, ls="-", marker="s", ms=3, zorder=3),
    "buildable": dict(color="black", lw=0.8, ls=":", marker="s", ms=6, zorder=4, drawstyle="steps-post"),
    "reference": dict(color="0.65", lw=1.3, ls="--", marker=".", ms=4, zorder=1),
}
"""Line style per kind of front."""
MARK_STYLE = {
    "recommended": dict(marker="*", s=360, facecolor="gold", edgecolor="black", lw=1.2, zorder=7),
    "alternative": dict(marker="^", s=110, facecolor="white", edgecolor="black", lw=1.4, zorder=6),
    "weighted": dict(marker="X", s=70, facecolor="0.6", edgecolor="0.2", lw=0.8, zorder=5),
    "knee": dict(marker="o", s=170, facecolor="none", edgecolor="#1f77b4", lw=1.8, zorder=5),
}
"""Marker style per kind of marked design."""


def draw_fronts(ax, curves, marks=(), legend: bool = True):
    """Draw fronts and marked designs on ``ax``; returns ``ax``.

    Parameters
    ----------
    ax : matplotlib Axes
    curves : iterable of dicts ``{"threshold_force": array [N], "turning_effort": array [N], "label": str,
        "kind": one of CURVE_STYLE}``; points are drawn in order of P
    marks : iterable of dicts ``{"threshold_force": float [N], "turning_effort": float [N], "label": str,
        "kind": one of MARK_STYLE}``
    legend : draw the legend
    """
    for c in curves:
        p = np.asarray(c["threshold_force"], float)
        f = np.asarray(c["turning_effort"], float)
        order = np.argsort(p)
        style = dict(CURVE_STYLE[c.get("kind", "continuous")])
        marker, ms = style.pop("marker"), style.pop("ms")
        ax.plot(p[order], f[order], marker=marker or "", ms=ms, label=c["label"], **style)
    for m in marks:
        ax.scatter([m["threshold_force"]], [m["turning_effort"]], label=m["label"],
                   **MARK_STYLE[m.get("kind", "alternative")])
    ax.set_xlabel("threshold (door-sill) force P [N]")
    ax.set_ylabel("turning effort F_turn [N]")
    ax.grid(True, alpha=0.3)
    if legend:
        ax.legend(fontsize=7.5, loc="upper right", framealpha=0.92)
    return ax


__all__ = ["CURVE_STYLE", "MARK_STYLE", "draw_fronts"]
