"""A calibration fit: the data and the fitted curve above, the residuals below (arrays in, Axes out)."""

from __future__ import annotations

import numpy as np

from designer.plots.fronts import dress


def draw_fit(ax, ax_residuals, x, y, fitted, x_label: str, y_label: str, title: str | None = None):
    """Draw measured ``y`` and ``fitted`` against ``x`` on ``ax`` and ``y − fitted`` on ``ax_residuals``.

    Parameters
    ----------
    ax, ax_residuals : matplotlib Axes (``ax_residuals`` may be None)
    x, y, fitted : arrays of the abscissa, measured and fitted ordinate (units in the labels)
    x_label, y_label : axis labels with units, e.g. ``"load L [N]"``
    title : optional title of ``ax``

    Returns
    -------
    (ax, ax_residuals)
    """
    x, y, fitted = (np.asarray(v, float) for v in (x, y, fitted))
    order = np.argsort(x)
    ax.plot(x, y, "o", label="data")
    ax.plot(x[order], fitted[order], "-", label="fit")
    dress(ax, x_label if ax_residuals is None else "", y_label, title or None, {}, 9)
    if ax_residuals is not None:
        ax_residuals.axhline(0, color="k", lw=0.8)
        ax_residuals.plot(x, y - fitted, "o")
        unit = y_label[y_label.rfind("[") :] if "[" in y_label else ""
        dress(ax_residuals, x_label, f"residual {unit}".strip())
    return ax, ax_residuals


def fit_figure(result):
    """A Figure of a :class:`designer.studies.calibrate.CalibrationResult` (data, fit, residuals)."""
    from matplotlib.figure import Figure  # matplotlib: heavy, loaded only when drawing

    fig = Figure(figsize=(7, 6), layout="constrained")
    ax, ax2 = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    lo, hi = result.interval
    title = f"{result.kind}: {result.name} = {result.value:.4g} {result.unit} "
    title += f"(95 % CI {lo:.4g}–{hi:.4g}), {result.equation}"
    draw_fit(ax, ax2, result.x, result.y, result.fitted, result.x_label, result.y_label, title=title)
    return fig


__all__ = ["draw_fit", "fit_figure"]
