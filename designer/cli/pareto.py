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

import contextlib
import sys

from pathlib import Path

from designer.cli._common import PROBLEM_HELP, count_option, eprint, print_json, ranged_option

from designer.errors import InputError
from designer import load_problem
from designer.problem import POINTS_RANGE, problem_files
from types import SimpleNamespace

from designer.cli.run import caster_line, symbol_shown
from designer.display import shown
from designer.report.text import plain_rule


def register(sub) -> None:
    p = sub.add_parser(
        "pareto",
        help="exact risk-bounded Pareto front of turning effort vs threshold force, with a report",
        description="Exact risk-bounded Pareto front of (turning effort, threshold force): P(V_c < V_target) "
        "<= α with Eq. 7's scatter (V_c >= V_target alone when [robust] enabled = false); the caster to build, "
        "the weighted optimum, the paper checks and check 8, written as a "
        "report (index.html, report.md, front.csv, front.json, checks.json) into "
        "results/<problem>/. Exit 1 if a check of the front fails.",
    )
    p.add_argument("problem", nargs="?", help=PROBLEM_HELP)
    p.add_argument("--target-speed", default=None, help="override shimmy.target_speed, e.g. 3m/s (as run takes it)")
    p.add_argument("--points", type=int, default=None, help="number of front points (default: the problem's [pareto])")
    p.add_argument(
        "--out",
        default=None,
        help="report folder (default results/<problem name>; with --all: the parent folder, default results)",
    )
    p.add_argument(
        "--all",
        action="store_true",
        help="regenerate the reports of every problem in problems/ (or the folder given as PROBLEM)",
    )
    p.add_argument("--json", action="store_true", help="print a machine-readable summary on stdout")
    p.add_argument(
        "--cross-check",
        action="store_true",
        help="also solve the weighted optimum with the geometric program (cvxpy) and SLSQP and report "
        "the agreement (about 1 s more)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="write the report's files into the --out folder even over files of those names that its "
        "manifest does not prove the tool's (yours, edited, or of an older release); every other file "
        "there is left as it is",
    )
    p.set_defaults(func=run)


def _progress():
    """A transient rich progress bar on stderr, or None without a terminal to show it on (a
    transient bar never shows elsewhere: rich need not be imported, 0.03 s of CPU)."""
    if not sys.stderr.isatty():
        return None
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn

    console = Console(stderr=True)
    if not console.is_terminal:  # a log file or a pipe: no bar (an interruption leaves one line there)
        return None
    columns = (TextColumn("{task.description}"), BarColumn(), TaskProgressColumn(), TimeElapsedColumn())
    return Progress(*columns, console=console, transient=True)


def _forces(values: dict, units: str) -> str:
    """The two forces of a caster by their symbols: "F_turn 7.012 N, P 98.48 N"."""
    return ", ".join(symbol_shown(values[n], n, units) for n in ("turning_effort", "threshold_force"))


def _print_summary(s: dict, problem) -> None:
    print(
        f"{s['problem']}: {s['points']} front points ({s['failed_points']} failed), "
        f"checks {s['checks_passed']}/{s['checks_total']} pass"
        + (f", FAILING: {', '.join(s['failing_checks'])}" if s["failing_checks"] else "")
        + f" [{shown(s['seconds'], dimension='time')}]"
    )
    rec = s.get("recommendation")
    if rec is not None:
        why = plain_rule(problem, SimpleNamespace(rule=rec["rule"]))
        print(
            f"  the caster to build: {caster_line(rec['design'], problem.units)}; {_forces(rec, problem.units)} ({why})"
        )
    opt = s["optimum"]
    if opt is not None:
        wheel = f"wheel {opt['wheel']}, " if opt.get("wheel") else ""
        print(
            f"  with any sizes: {wheel}{caster_line(opt['design'], problem.units)}; "
            f"{_forces(opt['objectives'], problem.units)}"
        )
    for line in s.get("moved", {}).values():  # files of the existing report whose values moved (the rest kept)
        print(f"  rewritten: {line}")
    print(f"  open: {Path(s['index_html']).resolve()}")


def run(args) -> int:
    count_option(args.points, "--points", *POINTS_RANGE, ", as [pareto] points in a problem file")
    speed = ranged_option(args.target_speed, "target_speed", "--target-speed")
    if args.all:
        files = problem_files(args.problem or "problems")
        parent = Path(args.out or "results")
        jobs = [(p, parent / p.name) for p in map(load_problem, files)]
    else:
        if not args.problem:
            raise InputError("designer pareto: give a PROBLEM file, or --all")
        problem = load_problem(args.problem)
        jobs = [(problem, Path(args.out) if args.out else None)]
    if speed is not None:
        jobs = [(p.replace(target_speed=speed), out) for p, out in jobs]
    from designer.jobs import compute_and_write

    from designer.report.writer import check_target  # exit 7 for a file or an unwritable place, 2 for a foreign folder

    for problem, out in jobs:  # refuse a foreign or unwritable --out folder before the work, not after
        target = out if out is not None else Path("results") / problem.name
        check_target(target, args.force)
    summaries = []
    progress = _progress()
    with progress if progress is not None else contextlib.nullcontext():  # Progress stops itself on the way out
        for problem, out in jobs:
            summaries.append(compute_and_write(problem, args.points, out, progress, args.force, args.cross_check))
            if not args.json:
                _print_summary(summaries[-1], problem)
    if args.json:
        print_json(summaries if args.all else summaries[0])
    bad = [s for s in summaries if s["failing_front_checks"]]
    for s in bad:
        eprint(
            f"designer: check failed on the front of {s['problem']}: {', '.join(s['failing_front_checks'])} "
            f"(report written to {s['report']})"
        )
    return 1 if bad else 0
