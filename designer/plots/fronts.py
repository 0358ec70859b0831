"""Fronts over fronts: arrays in, matplotlib Axes out.

:func:`draw_fronts` draws turning effort F_turn [N] against sill force P [N] for several fronts (the
continuous risk-bounded front under the buildable one, so the price of stock can be read off; or the
nominal front under the risk-bounded one, the price of safety) and marks single designs on them.
"""

from __future__ import annotations

import numpy as np
from designer.display import axis, header, quantity, rescale, unit
from designer.parameters import VARIABLES

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
MARK_WORDS = {
    "recommended": "the caster to build (gold star, 'build this')",
    "alternative": "the other casters from the same parts (white triangles)",
    "knee": "the knee of the continuous front (blue circle)",
    "weighted": "the weighted optimum, not the recommendation (grey cross)",
}
"""Each kind of marked design as a caption names its marker (:data:`MARK_STYLE`): the report's Figure 1 caption
is written from these, so caption and legend agree."""
FAMILY_STYLE = {
    "bare fork": ("#555555", "o"),
    "groove": ("#1f77b4", "o"),
    "damper": ("#d62728", "s"),
    "groove+damper": ("#9467bd", "D"),
}
"""Colour and marker per design family (the mechanism that stops shimmy)."""


def variable_axis(name: str, units: str = "mm") -> str:
    """A design variable's short axis label: its name, symbol and unit in ``units`` ("trail T [mm]", "damping
    c_f [N·m/rad]"; the table's descriptions are too long for a panel)."""
    return f"{name} {header(name, units)}"


COLOR_BY = {
    name: (variable_axis(name), k, unit(quantity(name).dimension, "mm").factor) for k, name in enumerate(VARIABLES)
}
"""``color_by`` choices of :func:`plot_front` besides "family", "critical_speed" and None: (label, design column,
scale to the plotted unit)."""
LEGEND = dict(fontsize=7.5, loc="upper right", framealpha=0.92)
"""The legend of a front's Axes."""


def dress(ax, xlabel: str, ylabel: str, title: str | None = None, legend=None, title_size: float = 10, grid=True):
    """Finish ``ax`` (matplotlib's or the SVG canvas's): its axis labels, the light grid (``grid``), the legend
    when ``legend`` gives its options (call it after the labelled artists) and the ``title`` (``title_size`` [pt])."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if grid:
        ax.grid(True, alpha=0.3)
    if legend is not None:
        ax.legend(**legend)
    if title is not None:
        ax.set_title(title, fontsize=title_size)
    return ax


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
        ax.scatter(
            [m["threshold_force"]], [m["turning_effort"]], label=m["label"], **MARK_STYLE[m.get("kind", "alternative")]
        )
    return dress(ax, axis("threshold_force"), axis("turning_effort"), legend=LEGEND if legend else None)


def new_axes(ax=None, figsize=(7.5, 5.0), layout: str | None = "constrained"):
    """``ax``, or the Axes of a new figure of ``figsize`` [in] with matplotlib's ``layout`` (pyplot, so a notebook
    shows it; no backend is forced: matplotlib picks Agg without a display)."""
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    _, ax = plt.subplots(figsize=figsize, layout=layout)
    return ax


def plot_front(
    turning_effort,
    threshold_force,
    families=None,
    ax=None,
    color_by="family",
    designs=None,
    critical_speed=None,
    label: str = "continuous front",
    legend: bool = True,
):
    """Draw one Pareto front: turning effort F_turn [N] against threshold force P [N]; returns the Axes.

    The points are joined in order by a thin grey line (x = P, y = F_turn) and drawn as markers coloured by
    ``color_by``: ``"family"`` (:data:`FAMILY_STYLE`, one legend entry per family), a design variable
    (``"trail"``, ``"diameter"``, ``"groove"`` [mm] or ``"damping"`` [N·m/rad], with a colour bar),
    ``"critical_speed"`` V_c [m/s], or None (one colour).  Used by :meth:`Front.plot` and by the report's
    front figure (:func:`designer.plots.figures.figure_front`).

    Parameters
    ----------
    turning_effort, threshold_force : arrays [N], one entry per point, in front order
    families : design family per point (needed for ``color_by="family"``)
    ax : matplotlib Axes, or None for a new figure
    color_by : "family" | "trail" | "diameter" | "groove" | "damping" | "critical_speed" | None
    designs : (n, 4) array of (T [m], d [m], B [m], c_f [N·m/rad]) (for a design variable ``color_by``)
    critical_speed : array [m/s] (for ``color_by="critical_speed"``)
    label : legend text before the family name
    legend : draw the legend
    """
    ax = new_axes(ax)
    f = np.asarray(turning_effort, float).reshape(-1)
    p = np.asarray(threshold_force, float).reshape(-1)
    if len(f) != len(p):
        raise ValueError(f"turning_effort has {len(f)} points, threshold_force {len(p)}: must be equal")
    dress(ax, axis("threshold_force"), axis("turning_effort"))
    if not len(f):
        ax.text(0.5, 0.5, "no valid point on the front", transform=ax.transAxes, ha="center")
        return ax
    ax.plot(p, f, color="0.3", lw=1, zorder=1)
    if color_by == "family":
        fam = list(families) if families is not None else ["front"] * len(f)
        for family in list(FAMILY_STYLE) + [x for x in dict.fromkeys(fam) if x not in FAMILY_STYLE]:
            colour, marker = FAMILY_STYLE.get(family, ("#1f77b4", "o"))
            sel = [i for i, x in enumerate(fam) if x == family]
            if sel:
                ax.scatter(p[sel], f[sel], color=colour, marker=marker, s=28, zorder=3, label=f"{label}: {family}")
    elif color_by is None:
        ax.scatter(p, f, color="#1f77b4", s=28, zorder=3, label=label)
    else:
        values, what = _colour_values(color_by, designs, critical_speed, len(f))
        points = ax.scatter(p, f, c=values, cmap="viridis", s=28, zorder=3, label=label)
        ax.figure.colorbar(points, ax=ax, label=what)
    if legend:
        ax.legend(**LEGEND)
    return ax


def _colour_values(color_by, designs, critical_speed, n):
    """(values, colour-bar label) of a numeric ``color_by``."""
    if color_by == "critical_speed":
        if critical_speed is None:
            raise ValueError("color_by='critical_speed' needs critical_speed")
        return np.asarray(critical_speed, float).reshape(n), axis("critical_speed")
    if color_by not in COLOR_BY:
        raise ValueError(
            f"color_by = {color_by!r}: expected 'family', None, 'critical_speed' or one of "
            f"{', '.join(repr(k) for k in COLOR_BY)}"
        )
    if designs is None:
        raise ValueError(f"color_by={color_by!r} needs designs")
    what, column, scale = COLOR_BY[color_by]
    return np.asarray(designs, float).reshape(n, 4)[:, column] * scale, what


# long: four panels, their bounds, family switches and the shared legend in one figure
def plot_variables(threshold_force, designs, families, bounds, gaps=(), axes=None):
    """The design variables along a front against its threshold force P [N]; returns the 2 × 2 array of Axes.

    Panels: trail T, diameter d, groove B [mm, inches on the right] and spindle damping c_f [N·m/rad]; the
    points are coloured by family (:data:`FAMILY_STYLE`), dotted lines are the bounds, dashed vertical lines
    the family switches (``gaps``); the shared x axis runs with P increasing to the right, as in
    :func:`plot_front`, the report's front figure and the studio's chart (one direction per axis).  Used by
    :meth:`Front.plot_variables` and the report's variables figure.

    Parameters
    ----------
    threshold_force : array [N], one entry per point
    designs : (n, 4) array of (T [m], d [m], B [m], c_f [N·m/rad])
    families : design family per point
    bounds : four (low, high) pairs or objects with ``low``/``high`` [SI], in the order T, d, B, c_f
    gaps : (index of the point after the gap, description) pairs (:meth:`Front.gaps`)
    axes : a 2 × 2 array of Axes sharing x, or None for a new figure
    """
    if axes is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(8.5, 6.2))  # fixed margins: constrained layout misplaces the secondary axes
        fig.subplots_adjust(left=0.09, right=0.91, bottom=0.15, top=0.93, wspace=0.45, hspace=0.1)
        axes = fig.subplots(2, 2, sharex=True)
    axes = np.asarray(axes)
    fig = axes.flat[0].figure
    x = np.asarray(threshold_force, float).reshape(-1)
    designs = np.asarray(designs, float).reshape(-1, 4)
    families = list(families)
    for ax, (name, (label, k, scale)) in zip(axes.ravel(), COLOR_BY.items()):
        if len(x):
            colours = [FAMILY_STYLE.get(f, ("k", "o"))[0] for f in families]
            ax.plot(x, designs[:, k] * scale, color="0.35", lw=1)
            ax.scatter(x, designs[:, k] * scale, c=colours, s=16, zorder=3)
            for i, _ in gaps:
                ax.axvline(0.5 * (x[i - 1] + x[i]), color="0.5", ls="--", lw=0.8)
        low, high = (bounds[k].low, bounds[k].high) if hasattr(bounds[k], "low") else bounds[k]
        for v in [low] if low == high else [low, high]:
            ax.axhline(v * scale, color="#bb5500", lw=0.8, ls=":")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        span = (high - low) * scale
        pad = 0.08 * (span if span > 0 else max(abs(low * scale), 1e-3))
        ax.set_ylim(low * scale - pad, high * scale + pad)
        if scale != 1.0:  # a length: millimetres, inches on the right
            inches = ax.secondary_yaxis("right", functions=(rescale("mm", "in"), rescale("in", "mm")))
            inches.set_ylabel(header(name, "in"))
    for ax in axes[-1]:
        ax.set_xlabel(axis("threshold_force"))
    handles = [
        axes.flat[0].scatter([], [], color=c, marker="o", s=16, label=f)
        for f, (c, _) in FAMILY_STYLE.items()
        if f in families
    ]
    handles.append(axes.flat[0].axhline(np.nan, color="#bb5500", lw=0.8, ls=":", label="bounds"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8)
    note = " (single point)" if len(x) == 1 else "; dashed: family switch"
    fig.suptitle(f"Design variables along the front{note}", fontsize=10)
    return axes


__all__ = [
    "COLOR_BY",
    "CURVE_STYLE",
    "FAMILY_STYLE",
    "MARK_STYLE",
    "MARK_WORDS",
    "draw_fronts",
    "new_axes",
    "plot_front",
    "plot_variables",
    "variable_axis",
]
