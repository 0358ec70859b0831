"""``designer robust PROBLEM``: nominal and robust fronts side by side (robust design)."""

from __future__ import annotations

from pathlib import Path

from designer import load_problem
from designer.pipeline import ROBUST_POINTS, robust_data
from designer.output import check_folder
from designer.cli._common import PROBLEM_HELP, count_option
from designer.display import percent, shown


def register(sub) -> None:
    p = sub.add_parser(
        "robust",
        help="compare the nominal and the risk-bounded fronts: the price of safety",
        description="For any problem: the front with V_c >= target (Eq. 7 alone) and the front with "
        "P(V_c < target) <= α (its risk bound, or the default one), the price of safety, "
        "and a Monte Carlo check of every point. Writes results/robust/<name>/ by default.",
    )
    p.add_argument("problem", help=PROBLEM_HELP)
    p.add_argument(
        "--points",
        type=int,
        default=ROBUST_POINTS,
        help=f"points per front (default {ROBUST_POINTS}, not pareto's 41: it solves two fronts and runs two "
        "Monte Carlo checks per point)",
    )
    p.add_argument("--out", default=None, help="output folder (default results/robust/<name>)")
    p.set_defaults(func=run)


def run(args) -> int:
    from designer.report.robust import OWNED, write_robust_report

    count_option(args.points, "--points", 2, 501)
    problem = load_problem(args.problem)
    out = Path(args.out) if args.out else Path("results") / "robust" / problem.name

    check_folder(out, owned=OWNED, command="designer robust")  # before the fronts
    data = robust_data(problem, args.points)
    write_robust_report(data, out)
    extra = [r["extra_effort"] for r in data.rows if r["extra_effort"] == r["extra_effort"]]
    probs = [r["probability_mc"] for r in data.rows]
    print(f"risk-bounded front: {len(data.robust)} points; nominal: {len(data.nominal)} points")
    if extra:
        lo, hi = (0.0 if abs(v) < 5e-4 else v for v in (min(extra), max(extra)))  # no "-0.000"
        lo, hi = (("+" if v > 0 else "") + shown(v, "turning_effort") for v in (lo, hi))
        print(f"price of safety: {lo} to {hi} turning effort at equal threshold force")
    if probs:
        print(
            f"Monte Carlo P(shimmy) on the risk-bounded front: {percent(min(probs))}–{percent(max(probs))} "
            f"(target {percent(data.uncertainty.probability)})"
        )
    for line in data.run.get("moved", {}).values():  # files of the existing report whose values moved
        print(f"rewritten: {line}")
    print(f"report: {(out / 'index.html').resolve()} (Markdown: {out / 'robust.md'})")
    return 0
