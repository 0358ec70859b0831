"""Render a fleet run (``designer fleet``): fleet.csv, fleet.json, report.md + figures/, index.html.

Takes the plain data of :func:`designer.studies.fleet._fleet.fleet_data`; computes nothing but formatting.
Files go to a temporary folder beside the target and are renamed into place when complete.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import shutil
import tempfile
from pathlib import Path

from designer.jsonsafe import finite

CSV_COLUMNS = (
    "name",
    "trail",
    "diameter",
    "groove",
    "damping",
    "turning_effort",
    "threshold_force",
    "shimmy_probability",
    "shimmy_probability_se",
    "sku",
    "sku_turning_effort",
    "sku_threshold_force",
    "sku_shimmy_probability",
    "knee_regret_N",
    "sku_regret_N",
    "status",
)
"""Columns of fleet.csv (SI, as front.csv); the sku_* and *_regret_N columns only with part numbers."""

INCH = 0.0254


def csv_text(data: dict) -> str:
    """fleet.csv: one row per chair (SI units; empty cells where a chair has no caster)."""
    rows = data["rows"]
    columns = [c for c in CSV_COLUMNS if not (c.startswith("sku") or "regret" in c) or data.get("k") is not None]
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(columns)
    for r in rows:
        writer.writerow(
            ["" if r.get(c) is None else (f"{r[c]:.6g}" if isinstance(r[c], float) else r[c]) for c in columns]
        )
    return buf.getvalue()


def json_data(data: dict) -> dict:
    """What ``--json`` prints and fleet.json holds (no figure arrays)."""
    out = {k: v for k, v in data.items() if k != "distributions"}
    return finite(out)


def _figures(data: dict) -> dict:
    # matplotlib: heavy, loaded only when a report is written
    from designer.plots.fleet import figure_distributions, figure_regret

    figs = {"distributions": figure_distributions(data["distributions"], data.get("alpha"))}
    curve = data.get("regret_curve") or []
    if curve:
        figs["regret"] = figure_regret(
            [c["k"] for c in curve],
            [c["mean_regret_N"] if c["mean_regret_N"] is not None else float("nan") for c in curve],
            data.get("k"),
        )
    out = {}
    for name, fig in figs.items():
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=100)
        out[name] = buf.getvalue()
    return out


def markdown(data: dict) -> str:
    """report.md of a fleet run (figures as figures/<name>.png)."""
    lines = [f"# Fleet: {data['chairs']} chairs ({data['units']} units), base problem {data['problem']}", ""]
    lines += _summary(data)
    lines += ["", "![distributions](figures/distributions.png)", ""]
    if data.get("regret_curve"):
        lines += ["## Part numbers", "", "![regret curve](figures/regret.png)", ""]
        lines += [
            "| K | mean regret per unit [N] | worst chair [N] | total regret Σ count · regret [N] | status | solve [s] |",
            "|---:|---:|---:|---:|---|---:|",
        ]
        for c in data["regret_curve"]:
            regret = "–" if c["total_regret_N"] is None else f"{c['total_regret_N']:.6g}"
            mean = "–" if c["mean_regret_N"] is None else f"{c['mean_regret_N']:.3f}"
            worst = "–" if c["worst_regret_N"] is None else f"{c['worst_regret_N']:.2f}"
            lines.append(f"| {c['k']} | {mean} | {worst} | {regret} | {c['status']} | {c['seconds']:.2f} |")
        lines += [
            "",
            "| SKU | trail [in] | diameter [in] | groove [in] | damping [N·m/rad] | chairs | units |",
            "|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for s in data["skus"]:
            d = s["design"]
            lines.append(
                f"| {s['id']} | {d['trail'] / INCH:.3f} | {d['diameter'] / INCH:.3f} | "
                f"{d['groove'] / INCH:.4f} | {d['damping']:.3f} | {s['chairs']} | {s['count']} |"
            )
    bad = [r for r in data["rows"] if r["status"] != "ok"]
    if bad:
        lines += ["", f"## Chairs without a caster ({len(bad)})", "", "| chair | why |", "|---|---|"]
        for r in bad[:200]:
            lines.append(f"| {r['name']} | {r['status']} |")
        if len(bad) > 200:
            lines.append(f"| … | {len(bad) - 200} more in fleet.csv |")
    lines += ["", "## Timings", "", "| stage | wall time [s] |", "|---|---:|"]
    for k, v in data["timings"].items():
        lines.append(f"| {k} | {v:.3f} |")
    return "\n".join(lines) + "\n"


def _summary(data: dict) -> list[str]:
    out = [
        f"- {data['feasible_chairs']} of {data['chairs']} chairs have a stock caster that meets their own "
        f"risk bound, swept-radius limit and sill; the others are listed below with the reason.",
        f"- Rule per chair: {data['rule']}. Stock: {data['stock']['casters']} casters ({data['stock']['note']}).",
        f"- Objective: {data['objective']}.",
        f"- {data['regret_definition']}.",
    ]
    if data.get("risk"):
        out.append(
            f"- Risk bound: P(V_c < (1 + {data['risk']['margin']:g}) V_target) <= "
            f"{data['risk']['probability']:.0%}, decided by the deterministic quantile; the reported "
            f"P(shimmy) is a Monte Carlo estimate ({data['monte_carlo']['samples']} samples per chair)."
        )
    else:
        out.append(
            "- No risk bound in the base problem: casters are screened on the nominal V_c >= V_target "
            "(Eq. 7); the P(shimmy) column says what risk each one carries."
        )
    if data.get("k") is not None:
        if data.get("total_regret_N") is None:
            out.append(
                f"- K = {data['k']}: no {data['k']} stock casters serve every feasible chair ({data['sku_status']})."
            )
        else:
            out.append(
                f"- K = {data['k']} part numbers: each unit sold loses {data['mean_regret_N']:.3f} N of J on "
                f"average against its chair's least-J stock caster (total {data['total_regret_N']:.6g} N over "
                f"the units sold, {data['sku_status']})."
            )
    return out


def _html(data: dict, figures: dict) -> str:
    def img(name):
        if name not in figures:
            return ""
        return f'<img alt="{name}" src="data:image/png;base64,{base64.b64encode(figures[name]).decode()}">'

    body = [
        f"<h1>Fleet: {data['chairs']} chairs ({data['units']} units), base problem "
        f"{html.escape(str(data['problem']))}</h1>",
        "<ul>",
    ]
    body += [f"<li>{html.escape(line[2:])}</li>" for line in _summary(data)]
    body += ["</ul>", img("distributions")]
    if data.get("regret_curve"):
        body += [
            "<h2>Part numbers</h2>",
            img("regret"),
            "<table><tr><th>SKU</th><th>trail [in]</th>"
            "<th>diameter [in]</th><th>groove [in]</th><th>damping [N·m/rad]</th><th>chairs</th>"
            "<th>units</th></tr>",
        ]
        for s in data["skus"]:
            d = s["design"]
            body.append(
                f"<tr><td>{s['id']}</td><td>{d['trail'] / INCH:.3f}</td><td>{d['diameter'] / INCH:.3f}</td>"
                f"<td>{d['groove'] / INCH:.4f}</td><td>{d['damping']:.3f}</td><td>{s['chairs']}</td>"
                f"<td>{s['count']}</td></tr>"
            )
        body.append("</table>")
    bad = [r for r in data["rows"] if r["status"] != "ok"]
    if bad:
        body += [f"<h2>Chairs without a caster ({len(bad)})</h2><table><tr><th>chair</th><th>why</th></tr>"]
        body += [f"<tr><td>{html.escape(r['name'])}</td><td>{html.escape(r['status'])}</td></tr>" for r in bad[:200]]
        body.append("</table>")
    style = (
        "body{font-family:sans-serif;max-width:1200px;margin:2em auto}img{max-width:100%}"
        "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
    )
    return (
        f"<!doctype html><html><head><meta charset='utf-8'><title>Fleet report</title><style>{style}</style>"
        f"</head><body>{''.join(body)}</body></html>\n"
    )


def write_fleet_report(data: dict, out_dir) -> Path:
    """Write fleet.csv, fleet.json, report.md, figures/*.png and index.html into ``out_dir`` (atomically)."""
    out = Path(out_dir)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}-", dir=out.parent))
    try:
        figures = _figures(data)
        (tmp / "figures").mkdir()
        for name, png in figures.items():
            (tmp / "figures" / f"{name}.png").write_bytes(png)
        (tmp / "fleet.csv").write_text(csv_text(data), encoding="utf-8")
        (tmp / "fleet.json").write_text(json.dumps(json_data(data), indent=1), encoding="utf-8")
        (tmp / "report.md").write_text(markdown(data), encoding="utf-8")
        (tmp / "index.html").write_text(_html(data, figures), encoding="utf-8")
        if out.exists():
            old = out.with_name(f".{out.name}.old")
            shutil.rmtree(old, ignore_errors=True)
            out.rename(old)
            tmp.rename(out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out
