"""The limit-cycle report's three figures: bifurcation diagram, Table 1 comparison, (K, N) map.

Each function picks its arguments out of the study record (``LimitCycleStudy`` and its parts, read by attribute) and calls the drawing function of
:mod:`designer.plots.simulation`; it returns the matplotlib figure (the caller saves it).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from designer.plots.simulation import bifurcation_axes, map_axes, table1_axes
from designer.display import shown
from designer.report.limit_cycles.text import PREDICTIONS, _pct


def _figure(nrows=1, ncols=1, figsize=(8, 5)):
    import matplotlib  # heavy, only for figures

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots(nrows, ncols, figsize=figsize, squeeze=False)


def _map_grid(rows, caster, key, factors):
    grid = np.full((len(factors), len(factors)), np.nan)
    for r in rows:
        if r.caster == caster:
            grid[factors.index(r.stiffness_factor), factors.index(r.mass_factor)] = getattr(r, key)
    return grid


def bifurcation_figure(study: Any):
    """Periodic orbits against speed, brush and rolling tyre, with Eq. 7, Eq. 29B and the measured point."""
    bif, roll = study.bifurcation, study.rolling
    slope = bif.disturbance_angle / (bif.frequency * bif.design.trail)
    fig, axes = _figure(1, 1, (9, 5.5))
    bifurcation_axes(
        bif.branches,
        bif.eq7_critical_speed,
        slope,
        rolling_branches=roll.branches,
        fold_speed=bif.fold_speed,
        measured=(study.measured_speed, study.measured_amplitude),
        speed_range=(0.3, 4.0),
        ax=axes[0, 0],
        title="Appendix C caster (T = 2.5 in, bare fork, θ0 = 20°): periodic orbits, brush tyre "
        f"(C = {bif.tyre.cornering_stiffness:.0f} N/rad, μ = "
        f"{bif.tyre.friction_coefficient}, L = {shown(bif.tyre.load, 'load')})",
    )
    fig.tight_layout()
    return fig


def table1_figure(table: Any):
    """Measured critical speed of each Table 1 wheel against Eq. 7 and the two simulations."""
    fig, axes = _figure(1, 1, (9, 5))
    st = table.stats
    table1_axes(
        [r.wheel for r in table.rows],
        [r.measured for r in table.rows],
        {
            f"{label} (RMS {100 * st[key].rms:.1f} %, bias {_pct(st[key].bias)})": [
                r.prediction(key) for r in table.rows
            ]
            for key, label in PREDICTIONS.items()
        },
        stable_up_to=table.stable_up_to,
        ax=axes[0, 0],
    )
    axes[0, 0].set_title(
        "Table 1: measured critical speed against Eq. 7 and the two simulations (20° knock; RMS/bias over C–G)",
        fontsize=10,
    )
    fig.tight_layout()
    return fig


def map_figure(kn: Any):
    """Onsets (both tyres) and the stable amplitude over the (K, N) grid, one row of panels per caster."""
    factors = list(kn.factors)
    casters = kn.casters()
    fig, axes = _figure(len(casters), 3, (15, 4.2 * len(casters)))
    for i, (name, _, base) in enumerate(casters):
        measured = shown(base.measured, dimension="speed")
        islands = _map_grid(kn.rows, name, "tyre_onset_monotone", factors) == 0
        for j, (key, label, unit, fmt) in enumerate(
            (
                ("rolling_onset", "onset, rolling tyre", "m/s", "{:.2f}"),
                ("tyre_onset", "onset, brush tyre (* islands in speed)", "m/s", "{:.2f}"),
                ("stable_amplitude", f"stable amplitude at {measured}, brush tyre", "rad", "{:.2f}"),
            )
        ):
            map_axes(
                factors,
                factors,
                _map_grid(kn.rows, name, key, factors),
                f"{name} (measured {measured}): {label}",
                unit,
                fmt,
                ax=axes[i, j],
                cmap="magma",
                center=getattr(base, key) if key != "stable_amplitude" else None,
                marks=islands if key == "tyre_onset" else None,
            )
    fig.suptitle(
        f"Unknowns mapped: K0 = {shown(kn.stiffness, 'frame_stiffness')}, N0 = {shown(kn.lateral_mass, dimension='mass')} "
        "(20° knock)",
        fontsize=11,
    )
    fig.tight_layout()
    return fig
