"""Render the shimmy-beyond-onset study into results/simulation: CSV, JSON, PNG, Markdown, HTML.

Takes the record of :func:`designer.studies.dynamics.limit_cycles.limit_cycle_study` (a ``LimitCycleStudy``,
read by its attributes: this room imports no study); computes nothing but summaries of it (ratios, minima and
maxima for the text).

Modules
-------
(this one)  limit_cycle_files: the data files (CSV, JSON), then the figures, then the text (``designer simulate
            --report`` writes them safely, :mod:`designer.output`)
figures     the three figures (bifurcation diagram, Table 1, (K, N) map), drawn by :mod:`designer.plots.simulation`
text        the report's sections as blocks (headings, paragraphs, lists, tables), every sentence from the study
blocks      the blocks as Markdown (limit_cycles.md) and as HTML (limit_cycles.html)
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from designer.textfiles import csv_text, dict_rows
from designer.jsonsafe import finite, stamped
from designer.plots.figures import png_bytes
from designer.report.limit_cycles import blocks as _blocks
from designer.report.limit_cycles import figures as _figures
from designer.report.limit_cycles.text import blocks as _text

FILES = (
    "bifurcation.csv",
    "bifurcation.json",
    "bifurcation.png",
    "table1.csv",
    "table1.png",
    "stiffness_mass_map.csv",
    "stiffness_mass_map.png",
    "limit_cycles.md",
    "limit_cycles.html",
)


CSV_QUANTITIES = {
    **dict.fromkeys(("speed", "measured", "eq7", "rolling_sim", "tyre_sim", "rolling_onset", "tyre_onset"), "speed"),
    **dict.fromkeys(("amplitude_rad", "closure_rad", "stable_amplitude"), "angle"),
    **dict.fromkeys(("mass_kg", "N"), "mass"),
    "period": "time",
    "inertia_kgm2": "inertia",
    "K": "stiffness",
    "frequency": "angular_speed",
}
"""The quantities of the study's CSV files and their dimensions: each column names its unit (the one rule,
:func:`designer.textfiles.dict_rows`: ``speed_m_per_s``, ``period_s``, ``K_N_per_m``, ``frequency_rad_per_s``);
labels, flags, factors and counts keep their names."""


def _csv(path: Path, rows: list[dict]) -> None:
    path.write_text(csv_text(dict_rows(rows, list(rows[0]), "{:.6g}", quantities=CSV_QUANTITIES)), "utf-8", newline="")


def _png(fig, path: Path) -> None:
    """The figure as a PNG file (110 dpi), closed afterwards."""
    import matplotlib.pyplot as plt

    try:
        path.write_bytes(png_bytes(fig, dpi=110))
    finally:
        plt.close(fig)


def limit_cycle_files(study: Any, folder) -> list[str]:
    """Write the files of :data:`FILES` into ``folder`` as they are (a folder the caller prepared, e.g. the
    temporary folder of :func:`designer.output.output_folder`).  Returns the names written."""
    out = Path(folder)
    data = study.to_dict()
    rows = [  # bifurcation.csv: one row per periodic orbit, brush tyre then rolling tyre
        {
            "model": model,
            "kind": "stable" if o["stable"] else "unstable",
            "speed": o["speed"],
            "amplitude_rad": o["amplitude"],
            "amplitude_deg": math.degrees(o["amplitude"]),
            "period": o["period"],
            "max_abs_multiplier": o["max_abs_multiplier"],
            "closure_rad": o["closure"],
        }
        for model, diagram in (("brush tyre", study.bifurcation), ("rolling tyre", study.rolling))
        for o in diagram.to_dict()["orbits"]
    ]
    _csv(out / "bifurcation.csv", rows)
    keys = ("bifurcation", "rolling", "friction", "knock_safe", "measured", "rolling_limit")
    bifurcation = stamped("bifurcation.json", finite({k: data[k] for k in keys if k in data}))
    (out / "bifurcation.json").write_text(json.dumps(bifurcation, indent=1))
    _png(_figures.bifurcation_figure(study), out / "bifurcation.png")
    rows = [  # table1.csv: one row per Table 1 wheel, measured and predicted critical speeds [m/s]
        {
            "wheel": r.wheel,
            "name": r.name,
            "inertia_kgm2": r.inertia,
            "mass_kg": r.mass,
            "measured": "" if r.measured is None else r.measured,
            "eq7": r.eq7,
            "rolling_sim": r.rolling_sim,
            "tyre_sim": r.tyre_sim,
            "flagged_below_3.8": " ".join(r.flagged),
        }
        for r in study.table1.rows
    ]
    _csv(out / "table1.csv", rows)
    _png(_figures.table1_figure(study.table1), out / "table1.png")
    _csv(out / "stiffness_mass_map.csv", data["map"]["rows"])
    _png(_figures.map_figure(study.stiffness_mass_map), out / "stiffness_mass_map.png")
    blocks = _text(study)
    (out / "limit_cycles.md").write_text(_blocks.to_markdown(blocks))
    (out / "limit_cycles.html").write_text(_blocks.to_html(blocks))
    return list(FILES)


__all__ = ["FILES", "limit_cycle_files"]
