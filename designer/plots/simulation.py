"""Figures of shimmy beyond onset (issue 16): arrays and plain records in, matplotlib Axes out.

matplotlib is imported inside each function (heavy; ``import designer`` stays light).
"""
from __future__ import annotations

import math

import numpy as np


def _axes(ax, figsize=(7, 4.5)):
    if ax is None:
        import matplotlib  # heavy, only for figures

        matplotlib.use("Agg")
        # late import: loads matplotlib only when this runs
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=figsize)
    return ax


def bifurcation_axes(branches, eq7_speed: float, eq29b_slope: float, rolling_branches=(), fold_speed=None,
                     measured=None, speed_range=None, title: str | None = None, ax=None):
    """Bifurcation diagram: shimmy amplitude θ_a [rad] against speed V [m/s].

    Parameters
    ----------
    branches : [{"kind": "stable" | "unstable", "speed": [m/s], "amplitude": [rad]}] (brush tyre)
    eq7_speed : Eq. 7's V_c [m/s] (vertical line)
    eq29b_slope : θ0/(ωT) [s/m]: Eq. 4/29B/6C amplitude θ_a = θ0 V/(ωT) (dotted line)
    rolling_branches : the same for the paper's rolling tyre (grey)
    fold_speed : lowest speed of a periodic orbit [m/s]: the hysteresis region lies above it
    measured : optional (V [m/s], θ_a [rad]) of the paper's measurement (Fig. 1C)
    speed_range : (low, high) x limits [m/s]
    """
    ax = _axes(ax)
    for b in rolling_branches:
        ax.plot(b["speed"], b["amplitude"], color="0.55", ls="--", lw=1.5,
                label="rolling tyre (paper's model): unstable" if b is rolling_branches[0] else None)
    seen = set()
    for b in branches:
        stable = b["kind"] == "stable"
        label = None if b["kind"] in seen else ("brush tyre: stable (sustained shimmy)" if stable
                                                else "brush tyre: unstable (knock threshold)")
        seen.add(b["kind"])
        ax.plot(b["speed"], b["amplitude"], color="tab:red" if stable else "tab:blue", ls="-" if stable else "--",
                lw=2.2 if stable else 1.8, marker="o" if stable else None, ms=3, label=label)
    lo, hi = speed_range if speed_range is not None else ax.get_xlim()
    if fold_speed is not None and math.isfinite(fold_speed):
        ax.axvspan(fold_speed, hi, color="tab:orange", alpha=0.08,
                   label=f"hysteresis: rest and shimmy both stable (V > {fold_speed:.2f} m/s)")
    v = np.linspace(lo, hi, 50)
    ax.plot(v, eq29b_slope * v, ":", color="k", lw=1.2, label="Eq. 29B/6C amplitude θ0 V/(ωT)")
    ax.axvline(eq7_speed, color="tab:green", lw=1.2, label=f"Eq. 7 V_c = {eq7_speed:.2f} m/s")
    if measured is not None:
        ax.plot(*measured, "k*", ms=13, label=f"measured (Fig. 1C): {math.degrees(measured[1]):.0f}° at "
                                               f"{measured[0]:.2f} m/s")
    ax.set_xlim(lo, hi)
    ax.set_yscale("log")
    ax.set_xlabel("wheelchair speed V [m/s]")
    ax.set_ylabel("shimmy amplitude θ_a [rad]")
    sec = ax.secondary_yaxis("right", functions=(np.degrees, np.radians))
    sec.set_ylabel("[deg]")
    if title:
        ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7.5, loc="lower left")
    ax.grid(True, which="both", alpha=0.25)
    return ax


def table1_axes(wheels, measured, predictions: dict, stable_up_to: float | None = None, ax=None):
    """Table 1: measured critical speed and the predictions, per wheel.

    Parameters
    ----------
    wheels : wheel letters (A–G)
    measured : measured V_c [m/s] per wheel (None/NaN where stable up to ``stable_up_to``)
    predictions : {label: [V [m/s] per wheel]}
    stable_up_to : treadmill limit [m/s] for wheels measured stable (drawn as an arrow from it)
    """
    ax = _axes(ax, (8, 4.5))
    x = np.arange(len(wheels))
    width = 0.8 / (len(predictions) + 1)
    meas = np.array([np.nan if m is None else m for m in measured], float)
    ax.bar(x - 0.4 + width / 2, np.nan_to_num(meas), width, color="k", label="measured")
    if stable_up_to is not None:
        for xi in x[np.isnan(meas)]:
            ax.bar(xi - 0.4 + width / 2, stable_up_to, width, color="none", edgecolor="k", hatch="//")
            ax.annotate("", (xi - 0.4 + width / 2, stable_up_to + 0.5), (xi - 0.4 + width / 2, stable_up_to),
                        arrowprops={"arrowstyle": "->"})
        ax.axhline(stable_up_to, color="k", lw=0.6, ls=":")
        ax.bar([], [], color="none", edgecolor="k", hatch="//", label=f"stable up to {stable_up_to} m/s (A, B)")
    colours = ["tab:green", "tab:blue", "tab:red", "tab:purple"]
    for k, (label, values) in enumerate(predictions.items()):
        ax.bar(x - 0.4 + width * (k + 1.5), values, width, color=colours[k % 4], label=label)
    ax.set_xticks(x, wheels)
    ax.set_xlabel("Table 1 wheel (T = 2 in, bare fork c_f = 1.3 N·m/rad, B = 0)")
    ax.set_ylabel("critical shimmy speed [m/s]")
    ax.legend(fontsize=7.5, loc="upper right")
    ax.grid(True, axis="y", alpha=0.3)
    return ax


def map_axes(k_factors, n_factors, values, title: str, unit: str, fmt: str = "{:.2f}", ax=None, cmap="viridis",
             center: float | None = None, marks=None):
    """A (K, N) map: ``values[i, j]`` at K factor ``k_factors[i]`` and N factor ``n_factors[j]``, annotated.

    Colour: log scale; with ``center`` the ratio value/center on a diverging scale clipped to [1/2, 2].
    NaN cells are drawn grey and marked "none"; cells where ``marks`` is True get a "*".
    """
    ax = _axes(ax, (4.5, 4))
    vals = np.asarray(values, float)
    masked = np.ma.masked_invalid(vals)
    import matplotlib.pyplot as plt  # heavy, only for figures
    from matplotlib.colors import LogNorm

    cm = plt.get_cmap("RdBu_r" if center is not None else cmap).copy()
    cm.set_bad("0.85")
    if center is not None:
        im = ax.imshow(masked.T / center, origin="lower", cmap=cm, aspect="auto", norm=LogNorm(0.5, 2.0))
        unit = f"{unit} / default cell ({fmt.format(center)})"
    else:
        finite = vals[np.isfinite(vals)]
        norm = LogNorm(finite.min(), finite.max()) if finite.size and finite.min() > 0 else None
        im = ax.imshow(masked.T, origin="lower", cmap=cm, aspect="auto", norm=norm)
    for i in range(vals.shape[0]):
        for j in range(vals.shape[1]):
            text = "none" if not np.isfinite(vals[i, j]) else fmt.format(vals[i, j])
            if marks is not None and marks[i][j]:
                text += "*"
            if center is not None:
                dark = np.isfinite(vals[i, j]) and abs(np.log2(vals[i, j] / center)) > 0.6
            else:
                dark = np.isfinite(vals[i, j]) and vals[i, j] < np.exp(np.nanmean(np.log(vals)))
            ax.text(i, j, text, ha="center", va="center", fontsize=7, color="w" if dark else "k")
    ax.set_xticks(range(len(k_factors)), [f"{f:g}" for f in k_factors])
    ax.set_yticks(range(len(n_factors)), [f"{f:g}" for f in n_factors])
    ax.set_xlabel("frame stiffness K / K0")
    ax.set_ylabel("lateral mass N / N0")
    ax.set_title(title, fontsize=9)
    ax.figure.colorbar(im, ax=ax, label=unit, shrink=0.8)
    return ax
