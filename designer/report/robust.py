"""Render the price-of-safety report (``designer robust``): index.html, robust.md, robust.json, figures/.

Render only: takes the :class:`designer.reportdata.RobustData` that :func:`designer.pipeline.robust_data`
computed (nominal and risk-bounded fronts, Monte Carlo P(shimmy) per point) and writes the same look as
the Pareto report (shared stylesheet), with one title used by the page and by its figure.
"""

from __future__ import annotations

import base64
import contextlib
import dataclasses
import json
from pathlib import Path

import numpy as np

from designer.display import number, percent, shown
from designer.jsonsafe import finite, stamped
from designer.reportdata import RobustData
from designer.report.agreement import compare_json, keep_agreeing
from designer.report.formatting import fmt
from designer.report.resolution import resolved, split_run
from designer.output import output_folder
from designer.report.writer import RUN_FILE, _render, _write_json
from designer.plots.figures import png_bytes
from designer.plots.fronts import draw_fronts
from designer.report.figures import curve

OWNED = frozenset({"index.html", "robust.md", "robust.json", "figures", "robust_fronts.png", RUN_FILE})
"""What a robust report owns in its folder (anything else there is kept on replace)."""
FIGURE = "figures/robust_fronts.png"


def title(data: RobustData) -> str:
    """The report's title, also the title of its figure (one source, so they cannot disagree)."""
    return f"Price of safety: {data.problem.name}, nominal against risk-bounded (α = {percent(data.uncertainty.probability)})"


def figure(data: RobustData):
    """The nominal front under the risk-bounded one (:func:`designer.plots.fronts.draw_fronts`): a Figure."""
    from matplotlib.figure import Figure  # matplotlib: heavy, loaded only when a report is drawn

    problem, u = data.problem, data.uncertainty
    fn, fr = data.nominal.objectives(), data.robust.objectives()
    fig = Figure(figsize=(7.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    v = shown(problem.required_speed, "critical_speed")
    nominal = curve("nominal", f"nominal: V_c >= {v} (Eq. 7)", fn)
    bounded = curve("risk-bounded", f"risk-bounded: P(V_c < {v}) <= {percent(u.probability)}", fr)
    draw_fronts(ax, [c for c, f in ((nominal, fn), (bounded, fr)) if len(f)])
    ax.set_title(title(data), fontsize=10)
    return fig


def sentences(data: RobustData) -> list[str]:
    """The summary, each sentence generated from the data it states."""
    u, rows, cmp = data.uncertainty, data.rows, data.compare
    out = []
    extra = np.array([r["extra_effort"] for r in rows], float)
    extra = extra[np.isfinite(extra)]
    if len(extra):
        lo, hi = (0.0 if abs(v) < 5e-4 else float(v) for v in (extra.min(), extra.max()))  # no "-0.000"
        out.append(
            f"Price of safety: {lo:+.3f} to {hi:+.3f} N of turning effort at equal sill force, over "
            f"{len(extra)} risk-bounded points (the nominal front read as min F_turn s.t. P <= P_point: "
            f"beyond its largest P, its least turning effort)."
        )
    else:
        out.append("The two fronts do not overlap in sill force, so the price of safety is not read at equal P here.")
    hv_n, hv_r = cmp.get("hypervolume_self"), cmp.get("hypervolume_other")
    if hv_n is not None and hv_r is not None and np.isfinite(hv_n) and np.isfinite(hv_r):
        rel = "smaller than" if hv_r < hv_n else "not smaller than"
        out.append(
            f"Hypervolume of the risk-bounded front {hv_r:.4f}, {rel} the nominal front's {hv_n:.4f} (the "
            f"nominal front's normalisation, reference (1.1, 1.1))."
        )
    probs = np.array([r["probability_mc"] for r in rows], float)
    ses = np.array([r["probability_mc_se"] for r in rows], float)
    if len(probs):
        worst = int(np.argmax(probs - 2 * ses))
        ok = bool(np.all(probs <= u.probability + 2 * ses))
        out.append(
            f"Monte Carlo P(shimmy below {shown(data.problem.required_speed, 'critical_speed')}) on the risk-bounded "
            f"front: {percent(probs.min())} to {percent(probs.max())} (bound α = {percent(u.probability)}; "
            + (
                "every point within α + 2 SE"
                if ok
                else f"point {worst} is ABOVE α + 2 SE: {percent(probs[worst])} ± {percent(ses[worst])}"
            )
            + ")."
        )
    nom = np.array([r["nominal_probability_mc"] for r in rows], float)
    nom = nom[np.isfinite(nom)]
    if len(nom):
        out.append(
            f"The nominal designs at the same sill force shimmy with probability {percent(nom.min())} to "
            f"{percent(nom.max())} (Monte Carlo of the same law): they sit on V_c = V_req of Eq. 7, and the "
            f"risk-bounded designs buy V_c above the target with more groove or damper (more turning effort) "
            f"or a smaller wheel (more sill force)."
        )
    return out


def bound_sentence(data: RobustData) -> str:
    """The risk bound and the law the Monte Carlo samples (the same law)."""
    u = data.uncertainty
    dof = getattr(u, "model_error_dof", None)
    law = f"Student-t, {dof} degrees of freedom" if dof else "normal"
    return (
        f"P(V_c,true < {shown(data.problem.required_speed, 'critical_speed')}) <= {percent(u.probability)}. Model "
        "error of Eq. 7: "
        f"{law}, scale {u.model_error:g}; lognormal M_f/θ0 (σ of the log {u.damping:g}), K_s "
        f"({u.slip_coefficient:g}), I_w ({u.inertia:g}). Each probability is a Monte Carlo of the same law on the "
        f"exact Eq. 7 (at least {u.samples:,} samples, seed {u.seed})"
    )


def _rows(data: RobustData) -> list[dict]:
    """The table's cells, from the rows as resolved (robust.json's numbers: no "-0.000" of a 1e-12 difference)."""
    return [
        {
            "P": number(r["threshold_force"], "threshold_force"),
            "F_nominal": number(r["turning_effort_nominal"], "turning_effort"),
            "F_robust": number(r["turning_effort_robust"], "turning_effort"),
            "extra": fmt(r["extra_effort"], "+.3f"),
            "V_c": number(r["critical_speed"], "critical_speed"),
            "p": f"{percent(r['probability_mc'])} ± {percent(r['probability_mc_se'])}",
            "p_nominal": percent(r["nominal_probability_mc"]),
        }
        for r in resolved(data.rows)
    ]


def _json(data: RobustData, page_title: str) -> dict:
    out = {
        "problem": data.problem.name,
        "title": page_title,
        "figure_title": page_title,
        "uncertainty": dataclasses.asdict(data.uncertainty),
        "rows": data.rows,
        "compare": data.compare,
        "nominal_front": data.nominal.rows(),
        "robust_front": data.robust.rows(),
        "run": split_run(data.run)[0],
    }
    return resolved(finite(out), data.problem.bounds)


def write_robust_report(data: RobustData, out_dir, option: str = "--out") -> Path:
    """Render ``data`` into ``out_dir``: index.html (self-contained), robust.md, robust.json, figures/, run.json.

    robust.json holds its numbers as the solver resolves them (:mod:`designer.report.resolution`); the run's
    date, seconds and library versions are only in run.json (git-ignored), so a rerun writes the same bytes.

    Written into a temporary folder inside the target and renamed into place when complete
    (:func:`designer.output.output_folder`); files in the target that the report does not own (:data:`OWNED`)
    are never touched, and a folder holding an owned name without being a robust report is refused (exit 7).
    """

    if not isinstance(data, RobustData):
        raise TypeError("write_robust_report renders a RobustData; build one with designer.pipeline.robust_data")
    with output_folder(out_dir, OWNED, option=option, command="designer robust") as tmp:
        page_title = title(data)
        (tmp / "figures").mkdir()
        numbers = stamped("robust.json", _json(data, page_title))
        old_json, old_png, png = Path(out_dir) / "robust.json", Path(out_dir) / FIGURE, None
        with contextlib.suppress(OSError, ValueError):  # an agreeing robust.json keeps the PNG's bytes
            if old_png.is_file() and not compare_json(json.loads(old_json.read_text(encoding="utf-8")), numbers):
                png = old_png.read_bytes()
        png = png or png_bytes(figure(data))
        (tmp / FIGURE).write_bytes(png)
        context = {
            "title": page_title,
            "problem": data.problem,
            "run": split_run(data.run)[0],
            "sentences": sentences(data),
            "rows": _rows(data),
            "figure": FIGURE,
            "figure_uri": "data:image/png;base64," + base64.b64encode(png).decode("ascii"),
            "bound": bound_sentence(data),
            "designer_version": data.run.get("versions", {}).get("caster-designer") or "(not installed)",
        }
        _write_json(tmp / "robust.json", numbers)
        (tmp / "index.html").write_text(_render("robust.html.j2", context, autoescape=True), encoding="utf-8")
        (tmp / "robust.md").write_text(_render("robust.md.j2", context, autoescape=False), encoding="utf-8")
        data.run["moved"] = keep_agreeing(tmp, Path(out_dir))  # a file that agrees keeps its bytes
        # date, seconds, versions: beside, never committed
        _write_json(tmp / RUN_FILE, stamped(RUN_FILE, finite(data.run)))
    return Path(out_dir)


__all__ = ["OWNED", "bound_sentence", "figure", "sentences", "title", "write_robust_report"]
