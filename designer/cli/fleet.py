"""``designer fleet FLEET.csv``: a caster for every chair of a product line, and the fewest part numbers.

``designer fleet --example N`` writes a plausible fleet of N chairs instead (ranges: docs/fleet.md).
"""

from __future__ import annotations

from pathlib import Path

from designer.cli._common import eprint, print_json
from designer.studies.fleet import (
    EXAMPLE_RANGES,
    example_fleet,
    fleet_data,
    fleet_recommendations,
    read_fleet,
    write_fleet_csv,
)
from designer.errors import InputError
from designer.problem import load_problem


def register(sub) -> None:
    p = sub.add_parser(
        "fleet",
        help="per-chair recommendations for a fleet and K part numbers (exact K-median; Dask optional)",
        description="Reads FLEET.csv (name, load | mass + front_fraction, threshold_height, target_speed, "
        "swept_radius_max, surface, turning_mode[, count]; units in the header or the cells), gives "
        "every chair the recommendation of its own problem (vectorised over chairs x stock), and with "
        "--skus K chooses K stock casters minimising the count-weighted regret. Writes fleet.csv, "
        "fleet.json and a report to results/fleet/<name>/ by default.",
    )
    p.add_argument("fleet", nargs="?", help="the fleet table (CSV)")
    p.add_argument("--example", type=int, metavar="N", help="write an example fleet of N chairs and stop")
    p.add_argument("--seed", type=int, default=0, help="seed of --example (default 0)")
    p.add_argument("--skus", type=int, metavar="K", help="choose K part numbers for the fleet")
    p.add_argument("--k-max", type=int, metavar="N", help="regret curve up to K = N (default max(K, 8))")
    p.add_argument(
        "--problem",
        default=None,
        help="base problem: bounds, stock, risk, weights (default problems/indoor-manual.toml)",
    )
    p.add_argument("--out", default=None, help="output folder (with --example: the CSV file to write)")
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="run the per-chair work on a Dask cluster (tcp://host:8786, or 'local' for 2 local workers)",
    )
    p.add_argument(
        "--no-monte-carlo",
        action="store_true",
        help="skip the reported Monte Carlo P(shimmy) per chair (the screening stays deterministic)",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def run(args) -> int:

    if args.example is not None:
        if args.fleet is not None:
            raise InputError(f"--example {args.example}: writes a fleet; do not also give FLEET.csv ({args.fleet})")
        fleet = example_fleet(args.example, seed=args.seed)
        path = write_fleet_csv(fleet, args.out or f"fleet-example-{args.example}.csv")
        if args.json:
            print_json(
                {
                    "fleet": str(path),
                    "chairs": len(fleet),
                    "ranges": {k: {"range": r, "source": s} for k, (r, s) in EXAMPLE_RANGES.items()},
                }
            )
        else:
            print(f"wrote {path} ({len(fleet)} chairs)")
            for key, (span, source) in EXAMPLE_RANGES.items():
                print(f"  {key}: {span} ({source})")
        return 0
    if args.fleet is None:
        raise InputError("designer fleet: give FLEET.csv, or --example N to write one")
    if args.skus is not None and args.skus < 1:
        raise InputError(f"--skus {args.skus}: expected 1 or more part numbers")
    if args.k_max is not None and not 1 <= args.k_max <= 50:
        raise InputError(f"--k-max {args.k_max}: expected 1 to 50")
    problem_path = args.problem or "problems/indoor-manual.toml"
    if args.problem is None and not Path(problem_path).exists():
        raise InputError(
            "--problem: give the base problem file (bounds, stock, risk, weights), "
            "e.g. --problem problems/indoor-manual.toml"
        )
    problem = load_problem(problem_path)
    fleet = read_fleet(args.fleet)
    result = fleet_recommendations(
        fleet, problem, skus=args.skus, k_max=args.k_max, scheduler=args.scheduler, monte_carlo=not args.no_monte_carlo
    )
    data = fleet_data(result)
    out = Path(args.out) if args.out else Path("results") / "fleet" / Path(args.fleet).stem
    # late import: loads matplotlib (via designer.report.fleet) only when this runs
    from designer.report.fleet import json_data, write_fleet_report

    write_fleet_report(data, out)
    if args.json:
        print_json(json_data(data))
    else:
        print(
            f"{data['feasible_chairs']} of {data['chairs']} chairs have a caster "
            f"({len(result.stock)} stock casters; {data['rule']})"
        )
        for name, seconds in data["timings"].items():
            print(f"  {name}: {seconds:.2f} s")
        if data["k"] is not None:
            if data["regret"] is None:
                print(f"K = {data['k']}: no {data['k']} stock casters serve every feasible chair")
            else:
                print(f"K = {data['k']}: total regret {data['regret']:.4g} ({data['sku_status']})")
                for s in data["skus"]:
                    d = s["design"]
                    print(
                        f"  SKU {s['id']}: T {d['trail'] / 0.0254:.3f} in, d {d['diameter'] / 0.0254:.3f} in, "
                        f"B {d['groove'] / 0.0254:.4f} in, c_f {d['damping']:.2f} N·m/rad: "
                        f"{s['chairs']} chairs, {s['count']} units"
                    )
        print(f"report: {out / 'index.html'}")
    if data["feasible_chairs"] < data["chairs"]:
        eprint(
            f"designer: note: {data['chairs'] - data['feasible_chairs']} chairs have no feasible stock caster "
            f"(status column of {out / 'fleet.csv'})"
        )
    return 0
