"""``designer pareto PROBLEM``: exact Pareto front, checks and report (docs/commands.md, docs/commands.md#reports).

Computes the front (ε-constraint on the NLP), the weighted optimum, the front
for a 10 % higher target speed (check 8c), runs the paper checks and check 8,
writes ``results/<problem>/`` and prints where to open it.  Exit 1 if a front
check fails (after the report is written); errors of :mod:`designer.errors`
propagate to the one-line handler of :mod:`designer.cli`.
"""
from __future__ import annotations

import time
import warnings
from pathlib import Path

from designer.commands._common import check_output_folder, eprint, print_json

TIGHTER_FACTOR = 1.1
"""Check 8c tightens V_target by this factor."""


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
    p.add_argument("--force", action="store_true", help="write the report into the --out folder even if it is not "
                                                        "a report of this tool (files the report does not own are "
                                                        "kept)")
    p.set_defaults(func=run)


def _progress():
    """A transient rich progress bar on stderr, or None without rich."""
    try:
        from rich.console import Console
        from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn
    except ImportError:  # pragma: no cover - rich is a dependency
        return None
    progress = Progress(TextColumn("{task.description}"), BarColumn(), TaskProgressColumn(), TimeElapsedColumn(),
                        console=Console(stderr=True), transient=True)
    return progress


def compute_and_write(problem, points=None, out=None, progress=None, force=False) -> dict:
    """Front, optimum, tighter front, checks and report of ``problem``; returns a summary dict.

    Parameters
    ----------
    problem : designer.problem.Problem
    points : number of front points (default the problem's)
    out : report folder (default ``results/<problem.name>``)
    force : replace ``out`` even if it is not a report of this tool
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
        summary = _compute(problem, points, out, tracker, force)
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


def _compute(problem, points, out, tracker, force=False) -> dict:
    from designer.analysis.checks import front_checks, paper_checks
    from designer.errors import DesignerError
    from designer.analysis.optimise import optimise
    from designer.analysis.pareto import pareto_front
    from designer.report import write_report

    t0 = time.perf_counter()
    front = pareto_front(problem, points, progress=tracker(f"{problem.name}: front"))
    if not front.points and not front.failed:  # the problem itself is infeasible: `designer run`'s exit 4
        from designer.analysis.optimise import _diagnose

        raise _diagnose(problem)
    tighter_problem = problem.replace(target_speed=problem.target_speed * TIGHTER_FACTOR)
    n_tight = max(5, (points or problem.pareto_points) // 2)
    tighter_error = None
    try:
        tighter = pareto_front(tighter_problem, n_tight,
                               progress=tracker(f"{problem.name}: front at {tighter_problem.target_speed:.3g} m/s"))
    except DesignerError as exc:  # an unreachable tighter target only removes check 8c
        tighter, tighter_error = None, str(exc)
    solution = optimise(problem) if front.points else None
    checks = paper_checks() + front_checks(front, tighter)  # an empty tighter front: 8c not applicable
    if tighter is not None and not tighter.points:
        tighter_error = next(c.got for c in checks if c.name.startswith("8c"))
        tighter = None
    folder = write_report(problem, front, out, solution=solution, checks=checks, tighter=tighter,
                          run_meta={"command": "designer pareto", "points_option": points,
                                    "tighter_points": n_tight if tighter is not None else None,
                                    "tighter_error": tighter_error, "wall_seconds": None}, force=force)
    wall = time.perf_counter() - t0
    failing = [c.name for c in checks if not c.passed]
    failing_front = [c.name for c in checks if not c.passed and c.name.startswith("8")]
    return {
        "problem": problem.name,
        "report": str(folder),
        "index_html": str(Path(folder) / "index.html"),
        "points": len(front.points),
        "failed_points": len(front.failed),
        "optimum": solution.to_dict() if solution is not None else None,
        "checks_passed": len(checks) - len(failing),
        "checks_total": len(checks),
        "failing_checks": failing,
        "failing_front_checks": failing_front,
        "seconds": wall,
        "reported_diameters": [p.design.diameter for p in front.points]
        + ([solution.design.diameter] if solution is not None else []),
    }


def _print_summary(s: dict) -> None:
    print(f"{s['problem']}: {s['points']} front points ({s['failed_points']} failed), "
          f"checks {s['checks_passed']}/{s['checks_total']} pass"
          + (f", FAILING: {', '.join(s['failing_checks'])}" if s["failing_checks"] else "")
          + f" [{s['seconds']:.1f} s]")
    opt = s["optimum"]
    if opt is not None:
        d = opt["design"]
        wheel = f"wheel {opt['wheel']}, " if opt.get("wheel") else ""
        print(f"  weighted optimum: {wheel}T = {d['trail'] / 0.0254:.3f} in, d = {d['diameter'] / 0.0254:.3f} in, "
              f"B = {d['groove'] / 0.0254:.3f} in, c_f = {d['damping']:.3f} N·m/rad; "
              f"F_turn {opt['objectives']['turning_effort']:.3f} N, P {opt['objectives']['threshold_force']:.2f} N")
    print(f"  open: {Path(s['index_html']).resolve()}")


def run(args) -> int:
    from designer.errors import InputError
    from designer.problem import load_problem

    from designer.problem import POINTS_RANGE

    if args.points is not None and not POINTS_RANGE[0] <= args.points <= POINTS_RANGE[1]:
        raise InputError(f"--points {args.points}: must be a whole number from {POINTS_RANGE[0]} to {POINTS_RANGE[1]}, "
                         f"as [pareto] points in a problem file")
    if args.all:
        from designer.problem import problem_files

        files = problem_files(args.problem or "problems")
        parent = Path(args.out or "results")
        jobs = [(load_problem(f), None) for f in files]
        jobs = [(p, parent / p.name) for p, _ in jobs]
    else:
        if not args.problem:
            raise InputError("designer pareto: give a PROBLEM file, or --all")
        problem = load_problem(args.problem)
        jobs = [(problem, Path(args.out) if args.out else None)]
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
            summaries.append(compute_and_write(problem, args.points, out, progress, args.force))
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
