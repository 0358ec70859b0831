"""Figures of a fleet report, drawn on the SVG canvas of :mod:`designer.plots.svg` (as the Pareto report's).

Arrays in, :class:`designer.plots.svg.Figure` out (``to_svg()`` gives the SVG text); no solver, no fleet
object, no matplotlib.  A point's numbers show on hover (SVG ``<title>``).

regret         the regret curve: the least mean regret per unit sold [N] for K = 1 … K_max part numbers,
               with the --max-regret threshold and the suggested and the asked K marked
distributions  what the chairs get: bar charts of the recommended trail, diameter, groove, damping and
               histograms of turning effort, sill force and P(shimmy)
"""

from __future__ import annotations

import numpy as np

from designer.display import axis, percent, quantity, unit
from designer.parameters import VARIABLES
from designer.plots.figures import _new
from designer.plots.fronts import dress, variable_axis
from designer.plots.svg import Figure

BLUE, RED, GREEN, GREY = "#1f77b4", "#d62728", "#2e7d32", "#7f7f7f"


def figure_regret(
    k,
    regret,
    asked: int | None = None,
    suggested: int | None = None,
    max_regret: float | None = None,
    hover=None,
    unit: str = "N",
) -> Figure:
    """Regret curve: the least mean regret per unit sold against the number of part numbers K.

    Parameters
    ----------
    k : K values
    regret : least count-weighted mean regret for each K [unit] (NaN where no K casters serve every chair)
    asked : the K whose part numbers the report lists (marked)
    suggested : the suggested count (marked, when it differs from ``asked``)
    max_regret : the threshold of the suggestion [unit] (a dashed line)
    hover : per K, the text its point shows on hover
    """
    fig = _new(4.6, 3.6, left=0.6, right=0.12, bottom=0.5, top=0.35)
    ax = fig.add_subplot()
    k = np.asarray(k, float)
    regret = np.asarray(regret, float)
    ok = np.isfinite(regret)
    ax.plot(k[ok], regret[ok], "-", color=BLUE, marker="o", label="least mean regret (each proved)")
    for kk in k[~ok]:
        ax.axvline(kk, color=GREY, ls=":", lw=1)
    if max_regret is not None:
        ax.axhline(max_regret, color=GREEN, ls="--", lw=1.2, label=f"--max-regret {max_regret:g} {unit}")
    for word, kk, fmt, colour, ms in (("suggested", suggested, "D", GREEN, 10), ("asked", asked, "s", RED, 9)):
        if kk is not None and (word == "suggested" or kk != suggested) and kk in set(k[ok].tolist()):
            i = int(np.flatnonzero(k == kk)[0])
            ax.plot([kk], [regret[i]], fmt, color=colour, ms=ms, label=f"{word}: K = {kk}")
    if hover is not None:
        ax.hover(k[ok], regret[ok], [t for t, good in zip(hover, ok) if good])
    ax.set_xticks(k.tolist())
    ax.set_ylim(0, None)
    legend = dict(loc="upper right", fontsize=8.5)
    dress(ax, "part numbers K", f"mean regret per unit sold [{unit}]", "What each added part number buys", legend, 10.5)
    return fig


def figure_distributions(values: dict, alpha: float | None = None) -> Figure:
    """Bar charts and histograms of each chair's own recommendation.

    Parameters
    ----------
    values : {"trail" [m], "diameter" [m], "groove" [m], "damping" [N·m/rad], "turning_effort" [N],
        "threshold_force" [N], "shimmy_probability" [-]}: arrays over the feasible chairs (NaN ignored)
    alpha : the risk bound's α, drawn on the P(shimmy) panel
    """
    keys = (*VARIABLES, "turning_effort", "threshold_force", "shimmy_probability")
    panels = [key for key in keys if key in values and np.isfinite(np.asarray(values[key], float)).any()]
    cols = 4
    rows = max(1, (len(panels) + cols - 1) // cols)
    fig = _new(11.0, 2.9 * rows + 0.3, left=0.6, right=0.15, bottom=0.75, top=0.55, wspace=0.45, hspace=0.75)
    grid = fig.subplots(rows, cols)
    axes = list(np.ravel(grid))
    for ax, key in zip(axes, panels):
        discrete = key in VARIABLES  # the design variables: bars of their values (lengths in inches); then histograms
        label = variable_axis(key, "in") if discrete else axis(key)
        v = np.asarray(values[key], float)
        v = v[np.isfinite(v)] * unit(quantity(key).dimension, "in").factor
        if discrete:
            levels, counts = np.unique(np.round(v, 6), return_counts=True)
            pos = np.arange(len(levels), dtype=float)
            ax.bar(pos, counts, color=BLUE)
            ax.set_xticks(pos.tolist(), [f"{x:.4g}" for x in levels], fontsize=8)
            ax.hover(pos, counts, [f"{label.split(' [')[0]} {x:.4g}: {c} chairs" for x, c in zip(levels, counts)])
        else:
            counts, edges = np.histogram(v, bins=24)
            mid = (edges[:-1] + edges[1:]) / 2
            ax.bar(mid, counts, width=float(edges[1] - edges[0]) * 0.95, color=BLUE)
            ax.hover(mid, counts, [f"{a:.3g}–{b:.3g}: {c} chairs" for a, b, c in zip(edges, edges[1:], counts)])
        legend = None
        if key == "shimmy_probability" and alpha is not None:
            ax.axvline(alpha * 100, color=RED, ls="--", label=f"α = {percent(alpha)}")
            legend = dict(loc="upper right", fontsize=8)
        dress(ax, label, "chairs", legend=legend)
    for ax in axes[len(panels) :]:  # the grid's empty cells are not drawn
        fig.axes.remove(ax)
    fig.suptitle("What each chair's own recommendation is (chairs with a caster)", fontsize=11)
    return fig
