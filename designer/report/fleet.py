"""Render a fleet run (``designer fleet``): fleet.csv, fleet.json, report.md + figures/*.svg, index.html, run.json.

Takes the plain data of :func:`designer.studies.fleet._fleet.fleet_data`; computes nothing but formatting.
As the Pareto report's, the pages and fleet.json hold no date, seconds or versions: those are in
``run.json`` (:func:`designer.studies.fleet._fleet.fleet_run` plus the library versions), so the same
fleet gives the same files.
The look is the Pareto report's: the same stylesheet (``_style.html.j2``), a first screen that answers
(the number of part numbers in words, the part numbers, the regret curve), SVG figures drawn on
:mod:`designer.plots.svg` and inlined in the page with each point's numbers on hover, report.md linking
the same ``figures/*.svg``.  Files go to a temporary folder inside the target and are renamed into place
when complete (:func:`designer.output.output_folder`); nothing else in the folder is touched.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from designer.display import MISSING, percent, shown
from designer.parameters import VARIABLES, dimensions
from designer.textfiles import csv_text as write_csv_text, dict_rows
from designer.jsonsafe import finite, stamped
from designer.output import output_folder
from designer.versions import versions
from designer.plots.fleet import figure_distributions, figure_regret
from designer.report.formatting import fmt
from designer.units import limit_shown, resolved, written_size
from designer.report.writer import _render

CSV_COLUMNS = (
    "name",
    *VARIABLES,
    "turning_effort",
    "threshold_force",
    "shimmy_probability",
    "shimmy_probability_mc",
    "shimmy_probability_se",
    "sku",
    "sku_turning_effort",
    "sku_threshold_force",
    "sku_shimmy_probability",
    "sku_shimmy_probability_mc",
    "sku_shimmy_probability_se",
    "knee_regret_N",
    "sku_regret_N",
    "status",
)
"""The rows' keys written to fleet.csv: a quantity's column carries its unit in its name, its dimension from the
parameter table (:func:`designer.parameters.dimensions`; :func:`designer.units.csv_column`: ``trail_in`` or
``trail_mm`` as the base problem writes lengths, ``turning_effort_N``); the sku_* and *_regret_N columns only
with part numbers."""

OWNED = frozenset({"fleet.csv", "fleet.json", "report.md", "index.html", "figures", "run.json"})
"""What a fleet report owns in its folder (anything else there is never touched)."""


def csv_text(data: dict) -> str:
    """fleet.csv: one row per chair, each quantity in the unit its column names (lengths as the base problem
    writes them, ``data["length_units"]``); a part number with its sizes (``3: T 2 1/2 in, d 6 in, B 3/4 in,
    c_f 1.3 N·m/rad``); empty cells where a chair has no caster."""
    units = data.get("length_units", "in")
    keys = [c for c in CSV_COLUMNS if not (c.startswith("sku") or "regret" in c) or data.get("k") is not None]
    labels = {s["id"]: sku_label(s, units) for s in data.get("skus") or []}
    rows = [{**r, "sku": labels.get(r["sku"], r["sku"])} if r.get("sku") is not None else r for r in data["rows"]]
    # the one CSV writer (designer.textfiles): each quantity's column names its unit; chair names and part
    # numbers kept from formulas
    return write_csv_text(dict_rows(rows, keys, "{:.6g}", quantities=dimensions(keys), units=units))


def sku_label(sku: dict, units: str = "in") -> str:
    """A part number with its sizes: ``"3: T 2 1/2 in, d 6 in, B 3/4 in, c_f 1.3 N·m/rad"`` (a catalogue wheel's
    name after d)."""
    d = sku["design"]
    wheel = f" ({sku['wheel']})" if sku.get("wheel") else ""
    return (
        f"{sku['id']}: T {written_size(d['trail'], units)}, d {written_size(d['diameter'], units)}{wheel}, "
        f"B {written_size(d['groove'], units)}, c_f {d['damping']:.3g} N·m/rad"
    )


def run_data(run: dict | None) -> dict | None:
    """run.json: the run's date, stage and per-K seconds, scheduler, and the library versions."""
    return None if run is None else stamped("run.json", finite({**run, "versions": versions()}))


def json_text(data: dict, run: dict | None = None) -> str:
    """What ``--json`` prints and fleet.json holds, as text: ``data`` without the figure arrays (with ``"run"``
    last when given), one chair per line in ``rows``.

    The rows (one per chair, thousands) are written by the C encoder, one line each; a row that holds a
    NaN or an infinity goes through :func:`designer.jsonsafe.finite` first (NaN and infinities are null).
    """
    head = stamped("fleet.json", {k: v for k, v in data.items() if k not in ("distributions", "rows")})
    if run is not None:
        head["run"] = run_data(run)
    text = json.dumps(head, indent=1, ensure_ascii=False)
    rows = []
    for row in data["rows"]:
        row = {k: resolved(v) if type(v) is float else v for k, v in row.items()}  # 0.1778, not 0.17779999999999999
        try:
            rows.append(json.dumps(row, ensure_ascii=False, allow_nan=False))
        except ValueError:
            rows.append(json.dumps(finite(row), ensure_ascii=False))
    body = "[\n  " + ",\n  ".join(rows) + "\n ]" if rows else "[]"
    return text[:-2] + ',\n "rows": ' + body + "\n}" if head else '{\n "rows": ' + body + "\n}"


# --------------------------------------------------------------------------- figures


def _figures(data: dict) -> list[dict]:
    """The report's figures: name, title, caption, SVG text (drawn on the SVG canvas, no matplotlib)."""
    out = []
    curve = data.get("regret_curve") or []
    if curve:
        suggested = (data.get("suggested_skus") or {}).get("count")
        hover = [
            f"K = {c['k']}: {c['status']}"
            if c["mean_regret_N"] is None
            else f"K = {c['k']}: mean regret {c['mean_regret_N']:.3f} N, worst chair {c['worst_regret_N']:.2f} N; "
            f"{c['status']} ({c['method']})"
            for c in curve
        ]
        mean = [c["mean_regret_N"] if c["mean_regret_N"] is not None else math.nan for c in curve]
        limit = (data.get("suggested_skus") or {}).get("max_regret_N")
        fig = figure_regret([c["k"] for c in curve], mean, data.get("k"), suggested, limit, hover)
        caption = (
            "Least mean regret per unit sold against the number of part numbers K, every point proved optimal (hover "
            "a point for its numbers and proof). The dashed line is --max-regret; the suggested count is the first K "
            "on or below it."
        )
        out.append(_figure("regret", "The regret curve", caption, fig))
    caption = (
        "Each chair's own recommendation (the rule of the base problem on its buildable front): how many chairs get "
        "each trail, wheel, groove and damper, and the spread of their turning effort, sill force and reported "
        "P(shimmy) (hover a bar for its count)."
    )
    fig = figure_distributions(data["distributions"], data.get("alpha"))
    return [*out, _figure("distributions", "What each chair's own recommendation is", caption, fig)]


def _figure(name: str, title: str, caption: str, fig) -> dict:
    """One figure of the report: its name, title, caption, SVG text (ids ``fleet-<name>``) and file."""
    svg = fig.to_svg(f"fleet-{name}", title)
    return {"name": name, "title": title, "caption": caption, "svg": svg, "file": f"figures/{name}.svg"}


# --------------------------------------------------------------------------- context


def _sku_rows(data: dict) -> list[dict]:
    rows = []
    for s in data["skus"]:
        d = s["design"]
        sizes = {  # as the user writes sizes
            f"{key}_{units}": written_size(d[name], units)
            for key, name in (("T", "trail"), ("d", "diameter"), ("B", "groove"))
            for units in ("in", "mm")
        }
        rows.append(
            {"id": s["id"], "wheel": s.get("wheel"), **sizes, "c_f": shown(d["damping"], "damping")}
            | {"chairs": s["chairs"], "units": f"{s['count']:,}"}
            | _sku_spec(s.get("spec"))
        )
    return rows


def _sku_spec(spec: dict | None) -> dict:
    """A part number's spec, compactly: P(shimmy) exact with the Monte Carlo beside it at the most demanding
    chair's V_target, and each acceptance limit (others at nominal) rounded toward the safe side ("none": no
    limit inside the part's range)."""
    if spec is None:
        return {}
    lim, units = spec["limits"], spec["units"]

    def limit(key: str) -> str:
        return limit_shown(lim.get(key), units.get(key, ""), key.rsplit("_", 1)[1])

    def bound(sign: str, key: str) -> str:
        """``≥ 16.76 mm (0.660 in)``, or ``none`` (no limit inside the part's range: nothing to compare with)."""
        text = limit(key)
        return text if text == "none" else f"{sign} {text}"

    p = spec["shimmy_probability"]
    low, high = limit("trail_min"), limit("trail_max")
    trail = "; ".join(x for x in (bound("≥", "trail_min"), bound("≤", "trail_max")) if x != "none") or "none"
    if "none" not in (low, high):  # "48.37 mm (1.905 in)" and "51.30 mm (2.020 in)" as one range
        (low_mm, low_in), (high_mm, high_in) = (x.removesuffix(" in)").split(" mm (") for x in (low, high))
        trail = f"{low_mm}–{high_mm} mm ({low_in}–{high_in} in)"
    return {
        "at": shown(p["at_speed"], "target_speed"),
        "p": percent(p["exact"]),
        "mc": f"{percent(p['monte_carlo'])} ± {percent(p['monte_carlo_se'])}",
        "draws": f"{p['monte_carlo_samples']:,} draws, seed {p['monte_carlo_seed']}",
        "T_lim": trail,
        "B_lim": bound("≥", "groove_min"),
        "M_lim": bound("≥", "friction_moment_min"),
        "I_lim": bound("≤", "wheel_inertia_max"),
    }


def _curve_rows(data: dict) -> list[dict]:
    return [
        {
            "k": c["k"],
            "mean": fmt(c["mean_regret_N"], ".3f"),
            "worst": fmt(c["worst_regret_N"], ".2f"),
            "total": fmt(c["total_regret_N"], ".6g"),
            "bound": fmt(c["lower_bound_N"] if c["total_regret_N"] is not None else None, ".6g"),
            "gap": fmt(c["gap_N"] if c["total_regret_N"] is not None else None, ".1e"),
            "status": c["status"],
            "method": c["method"],
            "mark": c["k"] == data.get("k"),
        }
        for c in data["regret_curve"]
    ]


def _headline(data: dict) -> dict:
    """The first screen: the answer, the numbers behind it, the rule, and which part numbers are listed."""
    lines = []
    s = data.get("suggested_skus")
    if data.get("answer_detail"):
        lines.append(data["answer_detail"][0].upper() + data["answer_detail"][1:] + ".")
    if s is not None:
        lines.append(f"Rule: {s['rule']}.")
    if data.get("tolerance_price"):
        lines.append(data["tolerance_price"]["sentence"])
    if data.get("k") is not None and (s is None or data["k"] != s["count"]):
        if data.get("mean_regret_N") is None:
            lines.append(f"K = {data['k']} asked with --skus: no {data['k']} stock casters serve every chair.")
        else:
            lines.append(
                f"Listed below: the K = {data['k']} part numbers asked with --skus: mean regret "
                f"{data['mean_regret_N']:.2f} N per unit sold, worst chair {data['worst_regret_N']:.2f} N; "
                f"{data['sku_status']} ({data['sku_proof']})."
            )
    if data.get("k") is not None:
        lines.append(
            "Each chair gets the part number with its least J among them; regret = J with the part number − the "
            "chair's least J over the stock casters allowed for it (risk bound, footrest clearance, sill), with "
            + data["objective"].split(":")[0]
            + "."
        )
    return {
        "answer": data.get("answer")
        or f"{data['feasible_chairs']} of {data['chairs']} chairs have a caster (no part numbers asked)",
        "lines": lines,
    }


def _own(data: dict) -> dict:
    own = data.get("own_recommendation") or {}
    out = {"meaning": own.get("meaning", ""), "numbers": []}
    if "part_number_better_on_J" in own:
        n = data["feasible_chairs"]
        out["numbers"] = [
            f"The own recommendation is the chair's least-J caster for {own['recommendation_is_least_J']} of {n} "
            f"chairs; on average it is {own['mean_recommendation_regret_N']:.2f} N of J above the least J "
            f"(knee_regret_N in fleet.csv).",
            f"With the K = {data['k']} part numbers, {own['part_number_better_on_J']} of {n} chairs get a part "
            f"number better on J than their own recommendation (sku_regret_N < knee_regret_N), and "
            f"{own['part_number_is_the_recommendation']} get exactly their own recommendation.",
        ]
    return out


def _summary(data: dict) -> list[str]:
    out = [
        f"{data['feasible_chairs']} of {data['chairs']} chairs have a stock caster that meets their own risk bound, "
        f"footrest clearance and sill; the others are listed below with the reason.",
        f"Own recommendation per chair: the {data['rule']} of the chair's own problem (the base problem "
        f"{data['problem']} with the chair's load, sill, target speed, clearance, surface and turning mode).",
        f"Stock: {data['stock']['casters']} casters ({data['stock']['note']}); "
        f"{data['stock'].get('useful_for_skus') or MISSING} can matter for part numbers (the others are "
        f"dominated on regret).",
        f"Objective: {data['objective']}.",
    ]
    if data.get("risk"):
        out.append(
            f"Risk bound: P(V_c < (1 + {data['risk']['margin']:g}) V_target) <= {percent(data['risk']['probability'])}, "
            f"decided by the deterministic quantile; the reported P(shimmy) is a Monte Carlo estimate "
            f"({data['monte_carlo']['samples']} samples per chair)."
        )
    else:
        out.append(
            "No risk bound in the base problem: casters are screened on the nominal V_c >= V_target (Eq. 7); "
            "the P(shimmy) column says what risk each one carries."
        )
    return out


def _context(data: dict, figures: list[dict]) -> dict:
    bad = [r for r in data["rows"] if r["status"] != "ok"]
    return {
        "title": f"Fleet: {data['chairs']:,} chairs ({data['units']:,} units sold)",
        "data": data,
        "headline": _headline(data),
        "skus": _sku_rows(data),
        "curve": _curve_rows(data) if data.get("regret_curve") else [],
        "own": _own(data),
        "summary": _summary(data),
        "figures": figures,
        "first": figures[0] if figures and figures[0]["name"] == "regret" else None,
        "others": [f for f in figures if f["name"] != "regret"],
        "bad": bad[:200],
        "bad_more": max(0, len(bad) - 200),
        "bad_total": len(bad),
    }


def write_fleet_report(data: dict, out_dir, run: dict | None = None, option: str = "--out") -> Path:
    """Write fleet.csv, fleet.json, report.md, figures/*.svg, index.html and (given ``run``, from
    :func:`designer.studies.fleet._fleet.fleet_run`) run.json into ``out_dir`` (atomically).

    Only these names (:data:`OWNED`) are replaced; the user's files in the folder are never touched, and a
    folder holding an owned name without being a fleet report is refused (OutputError, exit 7).
    """
    with output_folder(out_dir, OWNED, option=option, command="designer fleet") as tmp:
        figures = _figures(data)
        (tmp / "figures").mkdir()
        for item in figures:
            (tmp / item["file"]).write_text(item["svg"] + "\n", encoding="utf-8")
        (tmp / "fleet.csv").write_text(csv_text(data), encoding="utf-8")
        (tmp / "fleet.json").write_text(json_text(data) + "\n", encoding="utf-8")
        context = _context(data, figures)  # report.md links figures/<name>.svg, index.html holds them inline
        (tmp / "report.md").write_text(_render("fleet.md.j2", context, False), encoding="utf-8")
        (tmp / "index.html").write_text(_render("fleet.html.j2", context, True), encoding="utf-8")
        if run is not None:
            (tmp / "run.json").write_text(json.dumps(run_data(run), indent=1) + "\n", encoding="utf-8")
    return Path(out_dir)
