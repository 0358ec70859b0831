"""``designer pareto PROBLEM``: exact Pareto front, checks and report (docs/commands.md, docs/commands.md#reports).

Computes everything once with :func:`designer.pipeline.report_data` (the front,
the front for a 10 % higher target speed for check 8c, the recommendation, the
weighted optimum, the paper checks and check 8, the groove–damper table), hands
it to :func:`designer.report.write_report`, which renders ``results/<problem>/``,
and prints where to open it.  ``--cross-check`` adds the GP and SLSQP
cross-check of the weighted optimum (about 1 s of CPU; off in the main job).  Exit 1 if a front
check fails (after the report is written); errors of :mod:`designer.errors`
propagate to the one-line handler of :mod:`designer.cli`.
"""
from __future__ import annotations

import time
import warnings
from pathlib import Path

from designer.commands._common import check_output_folder, eprint, print_json

from designer.pipeline import TIGHTER_FACTOR  # noqa: F401  (re-exported: check 8c's factor)
from designer.pipeline import report_data
from designer.errors import InputError
from designer.problem import load_problem
from designer.problem import POINTS_RANGE
from designer.problem import problem_files


def register(sub) -> None:
    p = sub.add_parser("pareto", help="exact Pareto front of turning effort vs threshold force, with a report",
                       description="Exact Pareto front of (turning effort, threshold force) under V_c >= V_req "
                                   "(Eq. 7), the weighted optimum, the paper checks and check 8, written as a "
                                   "report (index.html, report.md, front.csv, front.json, checks.json) into "
                                   "results/<problem>/. Exit 1 if a check of the front fails.")
    p.add_argument("problem", nargs="?", help="problem file (TOML), e.g. problems/indoor-manual.toml")
    p.add_argument("--points", type=int, default=None, help="number of front points (default: the problem's [pareto])")
    p.add_argument("--out", default=None, help="report folder (default results/<problem name>; with --all: the "
                                               "parent folder, default results)")
    p.add_argument("--all", action="store_true", help="regenerate the reports of every problem in problems/ "
                                                      "(or the folder given as PROBLEM)")
    p.add_argument("--json", action="store_true", help="print a machine-readable summary on stdout")
    p.add_argument("--cross-check", action="store_true",
                   help="also solve the weighted optimum with the geometric program (cvxpy) and SLSQP and report "
                        "the agreement (about 1 s more)")
    p.add_argument("--force", action="store_true", help="write the report into the --out folder even if it is not "
                                                        "a report of this tool (files the report does not own are "
                                                        "kept)")
    p.set_defaults(func=run)


def _progress():
    """A transient rich progress bar on stderr, or None without rich."""
    try:
        # late import: loads rich only when this runs
        from rich.console import Console
        # late import: loads rich only when this runs
        from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn
    except ImportError:  # pragma: no cover - rich is a dependency
        return None
    progress = Progress(TextColumn("{task.description}"), BarColumn(), TaskProgressColumn(), TimeElapsedColumn(),
                        console=Console(stderr=True), transient=True)
    return progress


def compute_and_write(problem, points=None, out=None, progress=None, force=False, cross_check=False) -> dict:
    """Front, optimum, tighter front, checks and report of ``problem``; returns a summary dict.

    Parameters
    ----------
    problem : designer.problem.Problem
    points : number of front points (default the problem's)
    out : report folder (default ``results/<problem.name>``)
    force : replace ``out`` even if it is not a report of this tool
    cross_check : also run the GP/SLSQP cross-check of the weighted optimum
    progress : optional rich Progress to show the sweeps on

    Returns
    -------
    dict with the report folder, index.html path, counts, optimum and check results
    """
    t0 = time.perf_counter()

    def tracker(label):
        if progress is None:
            return None
        task = progress.add_task(label, total=None)

        def update(done, total):
            progress.update(task, completed=done, total=total)

        return update

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        summary = _compute(problem, points, out, tracker, force, cross_check)
    seen = set()
    for w in caught:
        text = str(w.message)
        if "inertia power law used at" in text or "inertia fit" in text and "extrapolated" in text or text in seen:
            continue
        seen.add(text)
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    # once for the problem, and only if a design the report shows (front point, optimum) is extrapolated
    for message in problem.model_warnings(summary.pop("reported_diameters")):
        warnings.warn(message + " (the report says so in its model section)", UserWarning, stacklevel=2)
    summary["seconds"] = time.perf_counter() - t0
    return summary


def _compute(problem, points, out, tracker, force=False, cross_check=False) -> dict:
    # late import: loads matplotlib (via designer.report) only when this runs
    from designer.report import write_report

    t0 = time.perf_counter()
    data = report_data(problem, points, cross_check=cross_check, progress=tracker,
                       run_meta={"command": "designer pareto", "points_option": points, "wall_seconds": None})
    folder = write_report(data, out, force=force)
    wall = time.perf_counter() - t0
    checks = data.checks
    failing = [c.name for c in checks if not c.passed]
    failing_front = [c.name for c in checks if not c.passed and c.name.startswith("8")]
    rec = data.recommendation
    return {
        "problem": problem.name,
        "report": str(folder),
        "index_html": str(Path(folder) / "index.html"),
        "points": len(data.front.points),
        "failed_points": len(data.front.failed),
        "recommendation": _rec_dict(rec) if rec is not None else None,
        "optimum": data.solution.to_dict() if data.solution is not None else None,
        "checks_passed": len(checks) - len(failing),
        "checks_total": len(checks),
        "failing_checks": failing,
        "failing_front_checks": failing_front,
        "seconds": wall,
        "reported_diameters": [p.design.diameter for p in data.front.points]
        + ([data.solution.design.diameter] if data.solution is not None else []),
    }


def _rec_dict(rec) -> dict:
    """The recommendation as the JSON shape of issue 11 (SI)."""
    to_dict = getattr(rec, "to_dict", None)
    if callable(to_dict):
        return to_dict()
    return {"design": rec.design.as_dict(), "turning_effort": rec.turning_effort,
            "threshold_force": rec.threshold_force, "critical_speed": rec.critical_speed,
            "shimmy_probability": rec.shimmy_probability, "shimmy_probability_se": rec.shimmy_probability_se,
            "rule": rec.rule}


def _print_summary(s: dict) -> None:
    print(f"{s['problem']}: {s['points']} front points ({s['failed_points']} failed), "
          f"checks {s['checks_passed']}/{s['checks_total']} pass"
          + (f", FAILING: {', '.join(s['failing_checks'])}" if s["failing_checks"] else "")
          + f" [{s['seconds']:.1f} s]")
    rec = s.get("recommendation")
    if rec is not None:
        d = rec["design"]
        print(f"  build this: T = {d['trail'] / 0.0254:.3f} in, d = {d['diameter'] / 0.0254:.3f} in, "
              f"B = {d['groove'] / 0.0254:.3f} in, c_f = {d['damping']:.3f} N·m/rad; "
              f"F_turn {rec['turning_effort']:.3f} N, P {rec['threshold_force']:.2f} N ({rec['rule']})")
    opt = s["optimum"]
    if opt is not None:
        d = opt["design"]
        wheel = f"wheel {opt['wheel']}, " if opt.get("wheel") else ""
        print(f"  weighted optimum: {wheel}T = {d['trail'] / 0.0254:.3f} in, d = {d['diameter'] / 0.0254:.3f} in, "
              f"B = {d['groove'] / 0.0254:.3f} in, c_f = {d['damping']:.3f} N·m/rad; "
              f"F_turn {opt['objectives']['turning_effort']:.3f} N, P {opt['objectives']['threshold_force']:.2f} N")
    print(f"  open: {Path(s['index_html']).resolve()}")


def run(args) -> int:


    if args.points is not None and not POINTS_RANGE[0] <= args.points <= POINTS_RANGE[1]:
        raise InputError(f"--points {args.points}: must be a whole number from {POINTS_RANGE[0]} to {POINTS_RANGE[1]}, "
                         f"as [pareto] points in a problem file")
    if args.all:

        files = problem_files(args.problem or "problems")
        parent = Path(args.out or "results")
        jobs = [(load_problem(f), None) for f in files]
        jobs = [(p, parent / p.name) for p, _ in jobs]
    else:
        if not args.problem:
            raise InputError("designer pareto: give a PROBLEM file, or --all")
        problem = load_problem(args.problem)
        jobs = [(problem, Path(args.out) if args.out else None)]
    # late import: loads matplotlib (via designer.report.writer) only when this runs
    from designer.report.writer import check_target

    for problem, out in jobs:  # refuse a foreign or unwritable --out folder before the work, not after
        target = out if out is not None else Path("results") / problem.name
        check_output_folder(target)
        check_target(target, args.force)
    summaries = []
    progress = _progress()
    if progress is not None:
        progress.start()
    try:
        for problem, out in jobs:
            summaries.append(compute_and_write(problem, args.points, out, progress, args.force,
                                                args.cross_check))
            if not args.json:
                _print_summary(summaries[-1])
    finally:
        if progress is not None:
            progress.stop()
    if args.json:
        print_json(summaries if args.all else summaries[0])
    bad = [s for s in summaries if s["failing_front_checks"]]
    for s in bad:
        eprint(f"designer: check failed on the front of {s['problem']}: {', '.join(s['failing_front_checks'])} "
               f"(report written to {s['report']})")
    return 1 if bad else 0
