"""Render a Pareto report folder: index.html, report.md, figures, front.csv/json, checks.json.

Render only: :func:`write_report` takes the :class:`designer.pipeline.ReportData` that
:func:`designer.pipeline.report_data` computed (front, recommendation, optimum, checks,
groove/damper table, run metadata), has :func:`designer.report.context.build_context` format
the tables once (SI and inches), draws the figures as SVG (:mod:`designer.report.figures`), renders the
two jinja2 templates and writes
all files into a temporary folder inside the target, whose entries replace the report's own files by
renames only when everything is written (:mod:`designer.output`).  An exception or a signal leaves no
half report, and files of the folder that the report does not own are never touched.
Nothing here optimises, checks or sweeps.

The data files hold every number as the solver resolves it (:mod:`designer.report.resolution`), and no
committed file holds what changes from run to run: the date, the seconds, the library versions and the solve
counts go into ``run.json`` beside the report (git-ignored), so a rerun of the same command writes the same
bytes into everything else.
"""

from __future__ import annotations

import dataclasses
import json
import re
import time
import warnings
from pathlib import Path

from markupsafe import Markup, escape

from designer.errors import InertiaExtrapolationWarning
from designer.jsonsafe import finite, stamped
from designer.model import Design
from designer.reportdata import ReportData
from designer.output import output_folder
from designer.report.agreement import keep_agreeing
from designer.report.files import REPORT_OWNED, check_target
import designer.report.figures as _figures
from designer.report.resolution import design_value, multiplier, on_scale, resolved, split_run
from designer.report.context import build_context

RUN_FILE = "run.json"
"""The run's metadata beside the report (date, seconds, versions, solve counts): git-ignored, never committed."""

# --------------------------------------------------------------------------- writing


def _render(template: str, context: dict, autoescape: bool) -> str:
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.PackageLoader("designer.report", "templates"),
        autoescape=autoescape,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        finalize=_inline_code if autoescape else None,
    )
    env.filters["md"] = _md_escape
    return env.get_template(template).render(**context)


_CODE = re.compile(r"`([^`\n]+)`")
"""Markdown inline code in the report's words (``run `designer pareto … --cross-check` for it``)."""


def _inline_code(value):
    """Every ``{{ … }}`` of an HTML template: a string's Markdown inline code (`…`) as <code>…</code>, the rest
    escaped, so no Markdown syntax shows as text; markup already safe (the SVG figures) and numbers unchanged."""
    if not isinstance(value, str) or isinstance(value, Markup) or "`" not in value:
        return value
    parts = _CODE.split(value)  # text, code, text, code, ..., text
    return Markup("").join(escape(p) if k % 2 == 0 else Markup("<code>%s</code>") % p for k, p in enumerate(parts))


def _md_escape(value) -> str:
    """Text safe in a Markdown table cell: HTML metacharacters escaped, pipes and newlines neutralised."""
    text = str(value)
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return text.replace("|", "\\|").replace("\r", " ").replace("\n", " ")


def _front_json(data: ReportData) -> dict:
    out = data.front.to_dict()
    out["run"] = split_run(data.run)[0]
    out["problem_digest"] = data.problem.digest()
    out["problem_definition"] = data.problem.to_dict()
    if data.solution is not None:
        out["optimum"] = data.solution.to_dict()
    if data.recommendation is not None:
        rec = data.recommendation
        knock = list(data.knock_safe) + [{}] * (1 + len(rec.alternatives))
        out["recommendation"] = {**rec.to_dict(), **knock[0]}
        out["alternatives"] = [{**a.to_dict(), **k} for a, k in zip(rec.alternatives, knock[1:])]
        out["price_of_stock"] = data.price_of_stock
    else:
        out["recommendation"] = None
        out["recommendation_error"] = data.recommendation_error
    if data.tighter is not None:
        out["tighter_target"] = {"target_speed": data.tighter.problem.target_speed, "points": data.tighter.rows()}
    out["degenerate_reason"] = data.degenerate_reason or None
    return _resolved(data, finite(out))


def _resolved(data: ReportData, value):
    """``value`` with its numbers as resolved (:func:`designer.report.resolution.resolved`) for ``data``'s problem."""
    return resolved(value, data.problem.bounds, {"swept_radius": data.problem.swept_radius_max})


def _resolved_front(front, bounds):
    """A copy of ``front`` whose points carry their numbers as resolved (front.csv is written from it); None: None."""

    def point(p):
        design = Design(**{k: design_value(k, v, bounds) for k, v in p.design.to_dict().items()})
        return dataclasses.replace(
            p,
            design=design,
            turning_effort=on_scale(p.turning_effort),
            threshold_force=on_scale(p.threshold_force),
            critical_speed=on_scale(p.critical_speed),
            epsilon=on_scale(p.epsilon),
            multipliers={k: multiplier(v) for k, v in p.multipliers.items()},
        )

    if front is None:
        return None
    return dataclasses.replace(front, points=[point(p) for p in front.points], failed=[point(p) for p in front.failed])


def _write_json(path: Path, value) -> None:
    text = json.dumps(value, indent=2, ensure_ascii=False, allow_nan=False, default=float)
    path.write_text(text + "\n", encoding="utf-8")


def _write_all(folder: Path, data: ReportData, t0: float, target: Path | None = None) -> None:
    (folder / "figures").mkdir()
    context = build_context(data)
    c0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaExtrapolationWarning)
        for item in context["figures"]:
            item["svg"] = _figures.svg(item["name"], data, item["title"])
            (folder / item["file"]).write_text(item["svg"] + "\n", encoding="utf-8")
    c1 = time.process_time()
    rec, bounds = data.recommendation, data.problem.bounds  # front.csv: with [stock], buildable rows as well
    buildable = _resolved_front(rec.buildable, bounds) if data.problem.stock is not None and rec is not None else None
    _resolved_front(data.front, bounds).to_csv(folder / "front.csv", buildable=buildable)
    if context["build"]["available"]:
        (folder / "figures" / "caster.svg").write_text(context["build"]["svg"] + "\n", encoding="utf-8")
        for panel in context["build"]["panels"]:
            if panel.svg:
                (folder / "figures" / f"{panel.id}.svg").write_text(panel.svg + "\n", encoding="utf-8")
    checks = [stamped("checks.json", finite(c.to_dict())) for c in data.checks]
    _write_json(folder / "checks.json", _resolved(data, checks))
    data.run["report_seconds"] = time.perf_counter() - t0
    if data.run.get("wall_seconds") is None:  # called from Python: the sum of the parts we know of
        data.run["wall_seconds"] = data.run.get("compute_wall_seconds", 0.0) + data.run["report_seconds"]
    data.run["render_cpu_seconds"] = {"figures": c1 - c0}
    context["run"] = split_run(data.run)[0]  # the pages show no date, seconds or library versions: run.json has them
    context["designer_version"] = data.run.get("versions", {}).get("caster-designer") or "(not installed)"
    _write_json(folder / "front.json", stamped("front.json", _front_json(data)))
    (folder / "index.html").write_text(_render("index.html.j2", context, autoescape=True), encoding="utf-8")
    (folder / "report.md").write_text(_render("report.md.j2", context, autoescape=False), encoding="utf-8")
    data.run["render_cpu_seconds"]["writing"] = time.process_time() - c1
    data.run["moved"] = keep_agreeing(folder, target) if target is not None else {}  # agreeing files keep their bytes
    _write_json(folder / RUN_FILE, stamped(RUN_FILE, finite(data.run)))


def write_report(data, out_dir=None, *, force: bool = False, option: str = "--out") -> Path:
    """Render ``data`` (a :class:`designer.pipeline.ReportData`) into ``out_dir``; computes nothing.

    Writes ``index.html`` (one self-contained file: the figures and the caster
    drawing as inline SVG, a point's numbers on hover, inline CSS, autoescaped), ``report.md``
    with the same ``figures/*.svg`` beside it, ``front.csv``, ``front.json`` (front,
    recommendation, indicators, the run's settings) and ``checks.json``, with every number as the solver
    resolves it (:mod:`designer.report.resolution`), and ``run.json`` (the date, seconds, library versions
    and solve counts of this run, which no other file holds).
    Everything is written into a temporary folder inside the target and
    renamed into place at the end, so an exception or a signal leaves no half
    report (and an existing report untouched).  Files in the target that a
    report does not write (e.g. ``explore.csv``, the user's notes) are never
    touched; a link to a folder is followed.

    Parameters
    ----------
    data : designer.pipeline.ReportData
        Build it with :func:`designer.pipeline.report_data` (``designer.report_data``).
    out_dir : str | Path, optional
        The report folder itself; default ``results/<problem name>``.
    force : bool
        Write the report's own names (:data:`REPORT_OWNED`) into ``out_dir`` even over files of those
        names that its manifest does not prove the tool's, unedited (by default they are refused with
        :class:`~designer.errors.OutputError`, exit 7); every other file there is left as it is.
    option : str
        How messages name the folder (the command-line option).

    Returns
    -------
    Path
        The report folder.
    """
    if not isinstance(data, ReportData):
        raise TypeError(
            "write_report renders a ReportData; build one with designer.report_data(problem) "
            "(or designer.pipeline.report_data(problem, front=front))"
        )
    t0 = time.perf_counter()
    problem = data.problem
    target = Path(out_dir) if out_dir is not None else Path("results") / problem.name
    real = check_target(target, force, option)
    # check_target decided before computing; the commit checks again under the folder's lock, with the same rule
    # (a report of this tool, an empty folder, or a foreign one only with force): another command's report
    # written meanwhile is refused, never mixed with this one
    with output_folder(target, REPORT_OWNED, option=option, force=force, command="designer pareto") as stage:
        _write_all(stage, data, t0, real)
    return target
