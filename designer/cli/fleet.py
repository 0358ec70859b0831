"""``designer fleet FLEET.csv``: a caster for every chair of a product line, and the fewest part numbers.

``designer fleet --example N`` writes a plausible fleet of N chairs instead (ranges: docs/fleet.md).
"""

from __future__ import annotations

from pathlib import Path

from designer.output import check_file, check_folder
from designer.cli._common import (
    SEED_MAX,
    parts_text,
    say,
    count_option,
    eprint,
    print_json,
    quantity_option,
)
from designer.studies.fleet import (
    DEFAULT_MAX_REGRET,
    EXAMPLE_KIND,
    EXAMPLE_RANGES,
    MAX_CHAIRS,
    example_fleet,
    fleet_data,
    fleet_recommendations,
    fleet_run,
    read_fleet,
    write_fleet_csv,
)
from designer.errors import InputError
from designer import example_problem, load_problem
from designer.problem import tolerances_option
from designer.display import number, shown


def register(sub) -> None:
    p = sub.add_parser(
        "fleet",
        help="per-chair recommendations for a fleet and how many part numbers it needs (K-median proved optimal)",
        description="Reads FLEET.csv (name, load | mass + front_fraction, threshold_height, target_speed, "
        "swept_radius_max, surface, turning_mode[, count]; units in the header or the cells), gives "
        "every chair the recommendation of its own problem (vectorised over chairs x stock), solves the "
        "K-median of part numbers for K = 1..8 (each proved optimal) and says on the first line how many "
        "part numbers keep the mean regret within --max-regret. Writes fleet.csv, fleet.json and a report "
        "to results/fleet/<name>/ by default.",
    )
    p.add_argument("fleet", nargs="?", help="the fleet table (CSV)")
    p.add_argument("--example", type=int, metavar="N", help="write an example fleet of N chairs and stop")
    p.add_argument("--seed", type=int, default=0, help="seed of --example (default 0)")
    p.add_argument(
        "--skus",
        type=int,
        metavar="K",
        help="choose K part numbers (default: the suggested count, the fewest within --max-regret)",
    )
    p.add_argument(
        "--max-regret",
        default=None,
        metavar="FORCE",
        help=f"the suggested count is the fewest part numbers whose mean regret on J = F_turn + P is at most "
        f"this (default {DEFAULT_MAX_REGRET:g} N, about 1 %% of J; plain numbers are N, '0.5 lbf' works)",
    )
    p.add_argument("--k-max", type=int, metavar="N", help="regret curve up to K = N (default max(K, 8))")
    p.add_argument("--no-skus", action="store_true", help="per-chair recommendations only (no part numbers)")
    for option, metavar, text in (
        ("--problem", None, "base problem: bounds, stock, risk, weights (default the shipped indoor-manual problem)"),
        (
            "--tolerances",
            "SPEC",
            "manufacturing tolerances every part number must hold at its worst corner, replacing the base "
            "problem's [tolerances], e.g. 'trail=1.5mm,groove=0.4mm,diameter=1mm,friction_moment=30%%'",
        ),
        ("--out", None, "output folder (with --example: the CSV file to write)"),
        (
            "--scheduler",
            "ADDRESS",
            "run the per-chair work on a Dask cluster (tcp://host:8786, or 'local' for 2 local workers)",
        ),
    ):
        p.add_argument(option, default=None, metavar=metavar, help=text)
    p.add_argument(
        "--no-monte-carlo",
        action="store_true",
        help="skip the reported Monte Carlo P(shimmy) per chair (the screening stays deterministic)",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument(
        "--verbose", action="store_true", help="the details: the ranking rule, the regret per K, the timings"
    )
    p.set_defaults(func=run)


def run(args) -> int:
    count_option(args.seed, "--seed", 0, SEED_MAX)
    count_option(args.example, "--example", 1, MAX_CHAIRS, " chairs (docs/fleet.md)")
    if args.example is not None:
        if args.fleet is not None:
            raise InputError(f"--example {args.example}: writes a fleet; do not also give FLEET.csv ({args.fleet})")
        target = args.out or f"fleet-example-{args.example}.csv"
        # before the fleet is made
        check_file(target, "--out", example=f"fleet-example-{args.example}.csv", kind=EXAMPLE_KIND)
        fleet = example_fleet(args.example, seed=args.seed)
        path = write_fleet_csv(fleet, target)
        ranges = {key: {"range": span, "source": source} for key, (span, source) in EXAMPLE_RANGES.items()}
        if args.json:
            print_json({"fleet": str(path), "chairs": len(fleet), "ranges": ranges})
        else:
            note = say(path)  # onto stderr when the fleet went to stdout
            note(f"wrote {path} ({len(fleet)} chairs)")
            for key, r in ranges.items():
                note(f"  {key}: {r['range']} ({r['source']})")
        return 0
    if args.fleet is None:
        raise InputError("designer fleet: give FLEET.csv, or --example N to write one")
    if args.skus is not None and args.skus < 1:
        raise InputError(f"--skus {args.skus}: expected 1 or more part numbers")
    if args.skus is not None and args.no_skus:
        raise InputError(f"--skus {args.skus}: not with --no-skus (which skips the part numbers)")
    count_option(args.k_max, "--k-max", 1, 50)
    max_regret = quantity_option(args.max_regret, "force", "--max-regret", DEFAULT_MAX_REGRET)
    problem = example_problem("indoor-manual") if args.problem is None else load_problem(args.problem)
    if args.tolerances is not None:
        problem = problem.replace(tolerances=tolerances_option(args.tolerances))
    fleet = read_fleet(args.fleet)
    out = Path(args.out) if args.out else Path("results") / "fleet" / Path(args.fleet).stem
    from designer.report.fleet import OWNED, json_text, write_fleet_report

    check_folder(out, owned=OWNED, command="designer fleet")  # before the work
    result = fleet_recommendations(
        fleet,
        problem,
        skus=None if args.no_skus else args.skus or "auto",
        k_max=args.k_max,
        scheduler=args.scheduler,
        monte_carlo=not args.no_monte_carlo,
        max_regret=max_regret,
    )
    data, run_info = fleet_data(result), fleet_run(result)
    write_fleet_report(data, out, run_info)
    if args.json:
        print(json_text(data, run_info))
    else:
        (_print if args.verbose else _print_screen)(data, run_info, len(result.stock), out, problem.units)
    if data["feasible_chairs"] < data["chairs"]:
        eprint(
            f"designer: note: {data['chairs'] - data['feasible_chairs']} chairs have no feasible stock caster "
            f"(status column of {out / 'fleet.csv'})"
        )
    return 0


SHOWN_SKUS = 12
"""Part numbers listed on the first screen (the rest: ``--verbose``, the report)."""


def _print_screen(data: dict, run_info: dict, stock: int, out: Path, units: str) -> None:
    """The answer in one screen (at most 24 lines at 80 columns): how many part numbers, why that many, each part
    number, what it costs the chairs, what next; the rule, the regret per K and the timings behind ``--verbose``."""
    if data["answer"]:
        print(data["answer"])
    else:
        print(f"{data['feasible_chairs']} of {data['chairs']} chairs have a caster ({stock} stock casters)")
    curve = [c["mean_regret_N"] for c in data["regret_curve"]]
    if data["k"] is not None and data["mean_regret_N"] is not None:
        k = data["k"]
        steps = sorted({1, (k + 1) // 2} - {k})
        fewer = "".join(
            f"{_force(curve[j - 1])} with {j} part number{'s' if j > 1 else ''}, "
            for j in steps
            if j <= len(curve) and curve[j - 1] is not None
        )
        asked = "" if k == data["suggested_skus"]["count"] else f" Shown: {k} part numbers as asked (--skus)."
        print(
            "Why: a part number per chair would give each its own best caster (least turning effort plus sill "
            f"force); sharing adds force, on average {fewer}{_force(data['mean_regret_N'])} with {k}.{asked}"
        )
        for sku in data["skus"][:SHOWN_SKUS]:
            print(_part_line(sku, units))
        if len(data["skus"]) > SHOWN_SKUS:
            print(f"  and {len(data['skus']) - SHOWN_SKUS} more part numbers (the report, --verbose)")
        print(
            f"Cost: {_force(data['mean_regret_N'])} more force per unit sold than each chair's own best caster, "
            f"{_force(data['worst_regret_N'])} for the worst-served chair."
            + (" " + data["tolerance_price"]["sentence"] if data.get("tolerance_price") else "")
        )
    if data["k"] is None:
        print(f"Next: open {out / 'index.html'} (each chair's caster); without --no-skus: the part numbers.")
    else:
        print(
            f"Next: open {out / 'index.html'} (each part number's acceptance limits for goods-in); "
            "--skus K to choose another count; --verbose for the rule and the timings."
        )


def _force(value) -> str:
    """A force [N] of the fleet's answer (a regret): :func:`designer.display.shown`."""
    return shown(value, dimension="force")


def _part_line(sku: dict, units: str) -> str:
    """One part number: its four parts in the problem's units, the chairs it serves and the units sold."""
    chairs = sku["chairs"]
    parts = parts_text(sku["design"], units)
    return f"  part {sku['id']}: {parts}: {chairs} chair{'s' if chairs != 1 else ''}, {sku['count']} units"


def _print(data: dict, run_info: dict, stock: int, out: Path, units: str) -> None:
    """The answer first (how many part numbers), then the part numbers, the chairs and the timings; lines
    wrapped to the terminal's width (``COLUMNS``; 80 when not a terminal)."""
    if data["answer"]:
        print(data["answer"])
        print(f"  {data['answer_detail']}")
        print(f"  rule: {data['suggested_skus']['rule']}")
        if data.get("tolerance_price"):
            print(f"  {data['tolerance_price']['sentence']}")
    print(
        f"{data['feasible_chairs']} of {data['chairs']} chairs have a caster ({stock} stock casters; own "
        f"recommendation: {data['rule']})"
    )
    if data["k"] is not None:
        k = data["k"]
        asked = "" if k == data["suggested_skus"]["count"] else " (asked with --skus)"
        if data["mean_regret_N"] is None:
            print(f"K = {k}{asked}: no {k} stock casters serve every chair that has a caster")
        else:
            print(
                f"K = {k}{asked}: mean regret {_force(data['mean_regret_N'])} per unit sold, worst chair "
                f"{_force(data['worst_regret_N'])}, total {_force(data['total_regret_N'])} over {data['served_units']} "
                f"units ({data['sku_status']})"
            )
            for sku in data["skus"]:
                print(_part_line(sku, units))
            if data["skus"] and "spec" in data["skus"][0]:
                print(
                    "  what goods-in accepts for each (acceptance limits from the exact law at the most demanding "
                    "chair it serves) and its P(shimmy): the report, fleet.json skus[].spec"
                )
        curve = ", ".join(number(c["mean_regret_N"], dimension="force") for c in data["regret_curve"])
        statuses = " or ".join(sorted({c["status"] for c in data["regret_curve"]}))
        print(f"  mean regret [N] for K = 1…{len(data['regret_curve'])}: {curve} (each {statuses})")
    print(
        "  time [s]: "
        + ", ".join(f"{name} {number(seconds, dimension='time')}" for name, seconds in run_info["timings"].items())
    )
    print(f"report: {out / 'index.html'}")
