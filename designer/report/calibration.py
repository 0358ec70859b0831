"""Render a calibration: ``--plot FILE`` (the figure alone) and ``--report DIR`` (index.html + report.md + figure).

Render only: takes the :class:`designer.studies.calibrate.CalibrationResult` that the fit computed and writes
it with the Pareto report's look (shared stylesheet); the figure is :func:`designer.plots.calibration.fit_figure`.
"""

from __future__ import annotations

import base64
from pathlib import Path

from designer.errors import InputError
from designer.output import output_folder
from designer.report.formatting import fmt
from designer.report.writer import _render, _write_json
from designer.plots.figures import png_bytes, save_figure
from designer.plots.calibration import fit_figure
from designer.jsonsafe import finite, stamped
from designer.versions import versions

OWNED = frozenset({"index.html", "report.md", "calibration.json", "figures"})
"""What a calibration report owns in its folder (anything else there is kept on replace)."""
FIGURE = "figures/fit.png"


def plot_fit(result, path) -> None:
    """Write the data, the fit and its residuals to an image file (PNG/SVG/PDF); a bad name is an InputError,
    a place that cannot be written an OutputError."""

    check_plot_name(path)

    save_figure(fit_figure(result), path, dpi=100)


def check_plot_name(path, option: str = "--plot") -> None:
    """InputError unless ``path`` ends .png, .svg or .pdf (checked before the fit)."""
    if not str(path).lower().endswith((".png", ".svg", ".pdf")):
        raise InputError(f"{option} {path}: expected a .png, .svg or .pdf file name")


def title(result) -> str:
    """The page title (also the figure's subject): what was fitted."""
    return f"Calibration of {result.name} ({result.kind}, {result.equation})"


def sentences(result, data_file: str) -> list[str]:
    """The summary, generated from the fit."""
    lo, hi = result.interval
    out = [
        f"{result.name} = {result.value:.5g} {result.unit}, 95 % confidence interval {lo:.5g} to {hi:.5g} "
        f"(standard error {result.stderr:.3g}) from n = {result.n} rows of {data_file}.",
        f"RMS residual {result.rms:.3g} {result.y_unit}; the residual panel should show no trend.",
    ]
    for key, value in result.notes.items():
        out.append(f"Held fixed: {key} = {value}.")
    return out


def write_calibration_report(result, out_dir, data_file: str = "", option: str = "--report") -> Path:
    """Write ``out_dir``/index.html (self-contained), report.md, calibration.json and figures/fit.png.

    Safely (:func:`designer.output.output_folder`): only these names are replaced, atomically; anything else
    in the folder is never touched.
    """

    with output_folder(out_dir, OWNED, option=option, command="designer calibrate") as tmp:
        (tmp / "figures").mkdir()
        png = png_bytes(fit_figure(result))
        (tmp / FIGURE).write_bytes(png)
        rows = [
            {"x": fmt(x, ".5g"), "y": fmt(y, ".5g"), "fitted": fmt(f, ".5g"), "residual": fmt(y - f, "+.3g")}
            for x, y, f in zip(result.x, result.y, result.fitted)
        ]
        context = {
            "title": title(result),
            "sentences": sentences(result, data_file or "the data"),
            "rows": rows,
            "result": result,
            "figure": FIGURE,
            "snippet": result.snippet(),
            "figure_uri": "data:image/png;base64," + base64.b64encode(png).decode("ascii"),
            "versions": ", ".join(f"{k} {v}" for k, v in versions().items() if v),
        }
        out = {**result.to_dict(), "data": data_file}
        _write_json(tmp / "calibration.json", stamped("calibration.json", finite(out)))
        (tmp / "index.html").write_text(_render("calibration.html.j2", context, autoescape=True), encoding="utf-8")
        (tmp / "report.md").write_text(_render("calibration.md.j2", context, autoescape=False), encoding="utf-8")
    return Path(out_dir)


__all__ = ["OWNED", "check_plot_name", "plot_fit", "sentences", "title", "write_calibration_report"]
