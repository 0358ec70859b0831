"""Figures of shimmy beyond onset: arrays and plain records in, matplotlib Axes out.

matplotlib is imported inside each function (heavy; ``import designer`` stays light).
"""

from __future__ import annotations

import math

import numpy as np

from designer.display import axis, shown
from designer.plots.fronts import dress, new_axes


def plot_knock(
    t,
    theta,
    speed: float,
    grows: bool,
    critical_speed: float,
    predicted_amplitude: float,
    onset_speed: float | None = None,
    ax=None,
):
    """θ(t) after a knock: the caster angle [deg] against time [s]; returns the Axes.

    Dashed red lines: ± the Eq. 29B amplitude θ_i V/(ωT); the title gives the speed V [m/s], whether the
    shimmy grows, Eq. 7's V_c [m/s] and, when given, the simulated onset speed [m/s].  Used by
    :meth:`SimulationResult.plot <designer.studies.dynamics._simulate.SimulationResult.plot>` and
    ``designer simulate --plot``.

    Parameters
    ----------
    t : times [s]; theta : caster angle θ [rad]
    speed : V [m/s]; grows : the oscillation grows (shimmy)
    critical_speed : Eq. 7 V_c [m/s]; predicted_amplitude : Eq. 29B amplitude [rad]
    onset_speed : simulated onset speed [m/s] or None
    ax : matplotlib Axes, or None for a new figure
    """
    ax = new_axes(ax, (8, 3.5))
    ax.plot(t, np.degrees(theta), lw=1)
    amp = math.degrees(predicted_amplitude)
    ax.axhline(amp, color="tab:red", ls="--", lw=0.8, label=f"Eq. 29B amplitude ±{amp:.1f}°")
    ax.axhline(-amp, color="tab:red", ls="--", lw=0.8)
    ax.axhline(0, color="k", lw=0.5)
    title = f"V = {shown(speed, 'critical_speed')}: {'grows' if grows else 'decays'}; Eq. 7 V_c = "
    title += shown(critical_speed, "critical_speed")
    if onset_speed is not None:
        title += f", simulated onset {shown(onset_speed, 'critical_speed')}"
    dress(ax, "time [s]", "caster angle θ [deg]", title, dict(fontsize=8), grid=False)
    return ax


def bifurcation_axes(
    branches,
    eq7_speed: float,
    eq29b_slope: float,
    rolling_branches=(),
    fold_speed=None,
    measured=None,
    speed_range=None,
    title: str | None = None,
    ax=None,
):
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
    ax = new_axes(ax, (7, 4.5), None)
    _branches(ax, branches, rolling_branches)
    lo, hi = speed_range if speed_range is not None else ax.get_xlim()
    if fold_speed is not None and math.isfinite(fold_speed):
        label = f"hysteresis: rest and shimmy both stable (V > {shown(fold_speed, 'critical_speed')})"
        ax.axvspan(fold_speed, hi, color="tab:orange", alpha=0.08, label=label)
    v = np.linspace(lo, hi, 50)
    ax.plot(v, eq29b_slope * v, ":", color="k", lw=1.2, label="Eq. 29B/6C amplitude θ0 V/(ωT)")
    ax.axvline(eq7_speed, color="tab:green", lw=1.2, label=f"Eq. 7 V_c = {shown(eq7_speed, 'critical_speed')}")
    if measured is not None:
        label = f"measured (Fig. 1C): {math.degrees(measured[1]):.0f}° at {shown(measured[0], 'critical_speed')}"
        ax.plot(*measured, "k*", ms=13, label=label)
    ax.set_xlim(lo, hi)
    ax.set_yscale("log")
    ax.secondary_yaxis("right", functions=(np.degrees, np.radians)).set_ylabel("[deg]")
    legend = dict(fontsize=7.5, loc="lower left")
    dress(ax, "wheelchair speed V [m/s]", "shimmy amplitude θ_a [rad]", title or None, legend, grid=False)
    ax.grid(True, which="both", alpha=0.25)
    return ax


_BRANCH_STYLE = {
    True: dict(color="tab:red", ls="-", lw=2.2, marker="o"),
    False: dict(color="tab:blue", ls="--", lw=1.8, marker=None),
}
"""Line style of a stable (True) and an unstable periodic-orbit branch of the brush tyre."""


def _branches(ax, branches, rolling_branches) -> None:
    """The periodic-orbit branches of the bifurcation diagram: rolling tyre grey dashes, brush tyre stable red
    (sustained shimmy) and unstable blue dashes (knock threshold), each kind labelled once."""
    for k, b in enumerate(rolling_branches):
        label = "rolling tyre (paper's model): unstable" if k == 0 else None
        ax.plot(b["speed"], b["amplitude"], color="0.55", ls="--", lw=1.5, label=label)
    labels = {"stable": "brush tyre: stable (sustained shimmy)", "unstable": "brush tyre: unstable (knock threshold)"}
    for b in branches:
        style = _BRANCH_STYLE[b["kind"] == "stable"]
        ax.plot(b["speed"], b["amplitude"], ms=3, label=labels.pop(b["kind"], None), **style)


def table1_axes(wheels, measured, predictions: dict, stable_up_to: float | None = None, ax=None):
    """Table 1: measured critical speed and the predictions, per wheel.

    Parameters
    ----------
    wheels : wheel letters (A–G)
    measured : measured V_c [m/s] per wheel (None/NaN where stable up to ``stable_up_to``)
    predictions : {label: [V [m/s] per wheel]}
    stable_up_to : treadmill limit [m/s] for wheels measured stable (drawn as an arrow from it)
    """
    ax = new_axes(ax, (8, 4.5), None)
    x = np.arange(len(wheels))
    width = 0.8 / (len(predictions) + 1)
    meas = np.array([np.nan if m is None else m for m in measured], float)
    left = x - 0.4 + width / 2  # the measured bars
    ax.bar(left, np.nan_to_num(meas), width, color="k", label="measured")
    if stable_up_to is not None:
        for xi in left[np.isnan(meas)]:
            ax.bar(xi, stable_up_to, width, color="none", edgecolor="k", hatch="//")
            ax.annotate("", (xi, stable_up_to + 0.5), (xi, stable_up_to), arrowprops={"arrowstyle": "->"})
        ax.axhline(stable_up_to, color="k", lw=0.6, ls=":")
        ax.bar([], [], color="none", edgecolor="k", hatch="//", label=f"stable up to {stable_up_to} m/s (A, B)")
    colours = ["tab:green", "tab:blue", "tab:red", "tab:purple"]
    for k, (label, values) in enumerate(predictions.items()):
        ax.bar(x - 0.4 + width * (k + 1.5), values, width, color=colours[k % 4], label=label)
    ax.set_xticks(x, wheels)
    xlabel = "Table 1 wheel (T = 2 in, bare fork c_f = 1.3 N·m/rad, B = 0)"
    dress(ax, xlabel, axis("critical_speed"), legend=dict(fontsize=7.5, loc="upper right"), grid=False)
    ax.grid(True, axis="y", alpha=0.3)
    return ax


def map_axes(
    k_factors,
    n_factors,
    values,
    title: str,
    unit: str,
    fmt: str = "{:.2f}",
    ax=None,
    cmap="viridis",
    center: float | None = None,
    marks=None,
):
    """A (K, N) map: ``values[i, j]`` at K factor ``k_factors[i]`` and N factor ``n_factors[j]``, annotated.

    Colour: log scale; with ``center`` the ratio value/center on a diverging scale clipped to [1/2, 2].
    NaN cells are drawn grey and marked "none"; cells where ``marks`` is True get a "*".
    """
    ax = new_axes(ax, (4.5, 4), None)
    vals = np.asarray(values, float)
    masked = np.ma.masked_invalid(vals)
    import matplotlib.pyplot as plt  # heavy, only for figures
    from matplotlib.colors import LogNorm

    cm = plt.get_cmap("RdBu_r" if center is not None else cmap).with_extremes(bad="0.85")
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
    dress(ax, "frame stiffness K / K0", "lateral mass N / N0", title, title_size=9, grid=False)
    ax.figure.colorbar(im, ax=ax, label=unit, shrink=0.8)
    return ax


def figure_onset_comparison(rows, traces, onset_c):
    """The simulated-onset study against Eq. 7 (results/simulation/onset.png); returns the Figure.

    (a) simulated onset vs Eq. 7 V_c [m/s]; (b) the onset error [%] against the error implied by Eq. 29B's
    amplitude; (c) simulated amplitude vs Eq. 4/29B [rad]; (d) θ(t) [deg] of the Appendix C caster below,
    at and above the onset.

    Parameters
    ----------
    rows : the study's rows (``eq7_critical_speed``, ``onset_speed`` [m/s], ``relative_error``,
        ``groove_in``, ``angle_deg``, ``amplitude_sim``, ``amplitude_eq29b`` [rad], ``amplitude_error``)
    traces : {speed factor (0.9, 1.0, 1.1): a simulation result with ``t`` [s], ``theta`` [rad], ``speed``,
        ``grows``}
    onset_c : the Appendix C onset (``speed``, ``critical_speed`` [m/s])
    """
    from matplotlib.figure import Figure

    v7 = np.array([r["eq7_critical_speed"] for r in rows])
    vs = np.array([r["onset_speed"] for r in rows])
    err = 100 * np.array([r["relative_error"] for r in rows])
    grooved = np.array([r["groove_in"] > 0 for r in rows])
    ang = np.array([r["angle_deg"] for r in rows])
    amp_s = np.array([r["amplitude_sim"] for r in rows])
    amp_p = np.array([r["amplitude_eq29b"] for r in rows])
    implied = 100 * ((1 + np.array([r["amplitude_error"] for r in rows])) ** -0.5 - 1)

    fig = Figure(figsize=(12, 9.5))
    axes = fig.subplots(2, 2)
    _onset_panel(axes[0, 0], v7, vs, grooved, ang)
    _error_panel(axes[0, 1], implied, err, grooved, ang)
    _amplitude_panel(axes[1, 0], amp_p, amp_s, grooved, ang)
    _trace_panel(axes[1, 1], traces, onset_c)
    fig.suptitle("Time-domain shimmy with Coulomb spindle friction vs the describing-function Eq. 7", fontsize=12)
    fig.tight_layout()
    return fig


_MARKERS = {10.0: "v", 20.0: "o", 40.0: "^"}
"""Marker of each knock angle θ_i [deg] in the onset study's scatter panels."""


def _scatter_cases(ax, x, y, grooved, ang, labelled: bool = False) -> None:
    """The onset study's cases: blue B = 0, orange grooved, one marker per knock angle (:data:`_MARKERS`);
    ``labelled``: each group named in the legend."""
    for g, colour, label in ((False, "tab:blue", "B = 0"), (True, "tab:orange", "B = 9/16 in")):
        for a, m in _MARKERS.items():
            sel = (grooved == g) & np.isclose(ang, a)
            extra = {"label": f"{label}, θ_i = {a:.0f}°"} if labelled else {}
            ax.scatter(x[sel], y[sel], marker=m, color=colour, s=36, edgecolor="k", lw=0.4, **extra)


def _onset_panel(ax, v7, vs, grooved, ang) -> None:
    """(a) simulated onset against Eq. 7's V_c [m/s], log-log, with the ±10 % band."""
    lim = (0.8 * min(v7.min(), vs.min()), 1.2 * max(v7.max(), vs.max()))
    xx = np.geomspace(*lim, 50)
    ax.fill_between(xx, 0.9 * xx, 1.1 * xx, color="0.9", label="±10 %")
    ax.plot(xx, xx, "k-", lw=1, label="simulated = Eq. 7")
    _scatter_cases(ax, v7, vs, grooved, ang, labelled=True)
    ax.set_xscale("log"), ax.set_yscale("log")
    ax.set_xlim(lim), ax.set_ylim(lim)
    ax.set_xlabel("Eq. 7 critical speed V_c [m/s] (c_f,eff = M_f/θ_i)")
    ax.set_ylabel("simulated onset speed [m/s]")
    ax.set_title("(a) Coulomb-friction simulation vs Eq. 7")
    ax.legend(fontsize=7, ncol=2, loc="upper left")


def _error_panel(ax, implied, err, grooved, ang) -> None:
    """(b) the onset error [%] against the error implied by Eq. 29B's amplitude [%]."""
    lo, hi = min(implied.min(), err.min()) - 2, max(implied.max(), err.max()) + 2
    ax.axhspan(-10, 10, color="0.9")
    ax.plot([lo, hi], [lo, hi], "k-", lw=1, label="error = (θ_a,29B / θ_a,sim)^½ − 1")
    _scatter_cases(ax, implied, err, grooved, ang)
    ax.set_xlim(lo, hi), ax.set_ylim(lo, hi)
    ax.set_xlabel("error implied by the amplitude of Eq. 29B: (θ_a,29B/θ_a,sim)^½ − 1 [%]")
    ax.set_ylabel("onset error (simulated − Eq. 7)/Eq. 7 [%]")
    ax.set_title("(b) Eq. 7's error comes from Eq. 29B's amplitude")
    ax.legend(fontsize=8, loc="upper left")


def _amplitude_panel(ax, amp_p, amp_s, grooved, ang) -> None:
    """(c) simulated amplitude after the transient against Eq. 4/29B's [rad]."""
    top = 1.1 * max(amp_s.max(), amp_p.max())
    ax.plot([0, top], [0, top], "k-", lw=1)
    _scatter_cases(ax, amp_p, amp_s, grooved, ang)
    ax.set_xlim(0, top), ax.set_ylim(0, top)
    ax.set_xlabel("Eq. 4 / 29B amplitude θ_i V/(ωT) at onset [rad]")
    ax.set_ylabel("simulated amplitude after the transient [rad]")
    ax.set_title("(c) shimmy amplitude at onset (blue B = 0, orange grooved)")


def _trace_panel(ax, traces, onset_c) -> None:
    """(d) θ(t) [deg] of the Appendix C caster at 0.9, 1.0 and 1.1 × its onset speed."""
    for f, colour in ((0.9, "tab:green"), (1.0, "tab:gray"), (1.1, "tab:red")):
        r = traces[f]
        label = f"V = {shown(r.speed, 'critical_speed')} ({f:.1f} × onset): {'grows' if r.grows else 'decays'}"
        ax.plot(r.t, np.degrees(r.theta), color=colour, lw=1, label=label)
    ax.axhline(0, color="k", lw=0.5)
    title = f"(d) Appendix C caster (T = 2.5 in, θ_i = 20°): onset {shown(onset_c.speed, 'critical_speed')}, "
    title += f"Eq. 7 {shown(onset_c.critical_speed, 'critical_speed')}"
    dress(ax, "time [s]", "caster angle θ [deg]", title, dict(fontsize=8, loc="lower right"), 9, grid=False)
