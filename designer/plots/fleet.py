"""Figures of a fleet report: arrays in, matplotlib Figures out (no solver, no fleet object).

distributions  what the chairs get: histograms of the recommended trail, diameter, groove, damping,
               turning effort, sill force and P(shimmy)
regret         the regret curve: least count-weighted regret for K = 1 … K_max part numbers
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

INCH = 0.0254


def figure_distributions(values: dict, alpha: float | None = None) -> Figure:
    """Histograms of the per-chair recommendation.

    Parameters
    ----------
    values : {"trail" [m], "diameter" [m], "groove" [m], "damping" [N·m/rad], "turning_effort" [N],
        "threshold_force" [N], "shimmy_probability" [-]}: arrays over the feasible chairs (NaN ignored)
    alpha : the risk bound's α, drawn on the P(shimmy) panel
    """
    panels = [
        ("trail", "trail T [in]", 1 / INCH, True),
        ("diameter", "wheel diameter d [in]", 1 / INCH, True),
        ("groove", "groove B [in]", 1 / INCH, True),
        ("damping", "damping c_f [N·m/rad]", 1.0, True),
        ("turning_effort", "turning effort F_turn [N]", 1.0, False),
        ("threshold_force", "sill force P [N]", 1.0, False),
        ("shimmy_probability", "P(shimmy at V_target) [%]", 100.0, False),
    ]
    panels = [p for p in panels if p[0] in values and np.isfinite(np.asarray(values[p[0]], float)).any()]
    cols = 4
    rows = (len(panels) + cols - 1) // cols
    fig = Figure(figsize=(12, 3.0 * rows))
    for k, (key, label, scale, discrete) in enumerate(panels):
        ax = fig.add_subplot(rows, cols, k + 1)
        v = np.asarray(values[key], float)
        v = v[np.isfinite(v)] * scale
        if discrete:
            levels, counts = np.unique(np.round(v, 6), return_counts=True)
            ax.bar([f"{x:.3g}" for x in levels], counts, color="#1f77b4")
            ax.tick_params(axis="x", labelrotation=45, labelsize=7)
        else:
            ax.hist(v, bins=30, color="#1f77b4")
        if key == "shimmy_probability" and alpha is not None:
            ax.axvline(alpha * 100, color="#d62728", ls="--", label=f"α = {alpha:.0%}")
            ax.legend(fontsize=7)
        ax.set_xlabel(label, fontsize=8)
        ax.set_ylabel("chairs", fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle("What each chair's own recommendation is (feasible chairs)", fontsize=10)
    fig.tight_layout()
    return fig


def figure_regret(k: np.ndarray, regret: np.ndarray, chosen_k: int | None = None, unit: str = "N") -> Figure:
    """Regret curve: the least mean regret per unit sold against the number of part numbers K.

    Parameters
    ----------
    k : K values
    regret : least count-weighted mean regret for each K (NaN where no K casters serve every chair) [unit]
    chosen_k : the K asked for (marked)
    """
    fig = Figure(figsize=(6.5, 4.0))
    ax = fig.add_subplot(1, 1, 1)
    k = np.asarray(k)
    regret = np.asarray(regret, float)
    ok = np.isfinite(regret)
    ax.plot(k[ok], regret[ok], "o-", color="#1f77b4")
    for kk in k[~ok]:
        ax.axvline(kk, color="#999999", ls=":", lw=1)
    if chosen_k is not None and chosen_k in set(k[ok].tolist()):
        i = int(np.flatnonzero(k == chosen_k)[0])
        ax.plot([chosen_k], [regret[i]], "s", color="#d62728", ms=9, label=f"K = {chosen_k} (asked for)")
        ax.legend(fontsize=8)
    ax.set_xlabel("part numbers K")
    ax.set_ylabel(f"mean regret per unit sold, J − J_own best [{unit}]")
    ax.set_title("What each added part number buys (exact K-median)", fontsize=10)
    ax.set_xticks(k)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
