"""``designer explore``: multi-objective exploration with optuna's NSGA-II (docs/model.md#solvers, docs/commands.md)."""

from __future__ import annotations

import logging
from pathlib import Path

import designer
from designer.cli._terminal import console as terminal_console, table
from designer.output import check_folder
from designer.cli._common import PROBLEM_HELP, SEED_MAX, count_option, eprint, print_json
from designer.errors import QuietAfterInterrupt
from designer.display import header, number, shown
from designer.parameters import VARIABLE_TABLE

EXPLORE_FILES = ("explore.csv", "explore.json")
"""What ``designer explore`` writes into --out (explore.json marks a folder it wrote before); nothing else."""


def register(sub) -> None:
    p = sub.add_parser(
        "explore",
        help="explore the risk-bounded trade-off with optuna (NSGA-II), also over catalog wheels and choices",
        description="Multi-objective optuna study (NSGA-II, constraints via trial.set_constraint) of turning effort "
        "and threshold force, risk-bounded (P(V_c < V_target) <= α, Eq. 7 with its scatter; V_c >= (1+margin) "
        "V_target for a nominal problem), as the exact front it is compared with. Catalog wheels and the problem's "
        "[choices] are categorical. Writes explore.csv and explore.json into --out.",
    )
    p.add_argument("problem", help=PROBLEM_HELP)
    p.add_argument("--trials", type=int, default=500, help="COMPLETE trials the study ends with (default 500)")
    p.add_argument("--seed", type=int, default=0, help="sampler seed (default 0; single-worker runs are repeatable)")
    p.add_argument(
        "--storage",
        default=None,
        help="optuna storage: sqlite:///file.db, postgresql://user:pw@host/db, journal:///path/file.log "
        "(or a path ending .db / .log); default in-memory",
    )
    p.add_argument("--study", default=None, help="study name (default <problem name>-explore)")
    p.add_argument("--workers", type=int, default=1, help="processes working on the study (needs --storage)")
    p.add_argument("--resume", action="store_true", help="continue an interrupted study up to --trials")
    p.add_argument(
        "--refine",
        action="store_true",
        help="polish every front point with the exact NLP (min F_turn s.t. P <= P_candidate)",
    )
    p.add_argument(
        "--operators",
        choices=("tuned", "optuna"),
        default="tuned",
        help="NSGA-II operators: tuned (SBX + polynomial mutation, default) or optuna's defaults",
    )
    p.add_argument("--population", type=int, default=None, help="population size (default ≈ √trials, 20…100)")
    p.add_argument("--no-compare", action="store_true", help="skip the comparison with the exact front")
    p.add_argument("--out", default=None, help="output folder (default results/<problem name>/)")
    p.add_argument("--json", action="store_true", help="print explore.json to stdout")
    p.set_defaults(func=run)


MAX_POPULATION = 10_000
"""Largest --population of NSGA-II (a generation; --trials bounds the study)."""


def run(args) -> int:
    from designer.studies.explore import MAX_TRIALS, MAX_WORKERS, parse_storage, removed_if_failed

    count_option(args.population, "--population", 2, MAX_POPULATION)
    count_option(args.seed, "--seed", 0, SEED_MAX)
    count_option(args.trials, "--trials", 1, MAX_TRIALS)  # named as the option (the API names its argument)
    count_option(args.workers, "--workers", 1, MAX_WORKERS)
    spec = parse_storage(args.storage)  # exit 6 for a malformed URL or an in-memory SQLite, before the problem is read
    problem = designer.load_problem(args.problem)
    out = Path(args.out) if args.out else Path("results") / problem.name
    # before the study, not after it
    check_folder(out, owned=EXPLORE_FILES, command="designer explore")
    # after Ctrl-C, optuna's "Trial N failed ... KeyboardInterrupt" tracebacks are dropped: one line says it
    logging.getLogger("optuna.study._optimize").addFilter(_QUIET)
    with removed_if_failed(spec):  # a storage file made by this run and left empty by a failure is removed
        same = ("trials", "seed", "storage", "workers", "resume", "refine", "operators")  # options named as the API's
        result = designer.explore(
            problem,
            **{key: getattr(args, key) for key in same},
            study_name=args.study,
            population_size=args.population,
            compare=not args.no_compare,
            progress=not args.json,
        )
    csv_path, json_path = result.write(out)
    for note in result.warnings:
        eprint(f"designer: note: {note}")
    if args.json:
        print_json(result.to_dict(), kind="explore.json")  # the record explore.json holds
        return 0
    _print(result, csv_path, json_path)
    return 0


_QUIET = QuietAfterInterrupt()

OBJECTIVES = ("turning_effort", "threshold_force")
"""The two forces of the front."""


def _print(result, csv_path, json_path) -> None:
    console = terminal_console()
    ops = result.operators
    console.print(
        f"[bold]{result.problem.name}[/]: study {result.study_name!r} on {result.storage}, "
        f"{result.trials} complete trials ({result.distinct} distinct, {result.feasible} feasible), "
        f"{number(result.trials_run / max(result.seconds, 1e-9), dimension='rate')} trials/s, "
        f"{result.workers} worker(s), "
        f"seed {result.seed}"
    )
    console.print(
        f"NSGA-II: {ops.name} (population {ops.population_size}, {ops.crossover} crossover"
        f"{'' if ops.crossover != 'sbx' else f' η={ops.crossover_eta:g}'}, {ops.mutation} mutation"
        f"{'' if ops.mutation != 'polynomial' else f' η={ops.mutation_eta:g}'})"
        f"{'; fronts refined by the exact NLP' if result.refined else ''}"
    )
    cats = [c for c in ("wheel", "surface", "turning_mode") if any(c in r for r in result.front)]
    if len(result.category_fronts) > 1:
        rows = []
        for name, front in result.category_fronts.items():
            ranges = [" – ".join(number(f(r[n] for r in front), n) for f in (min, max)) for n in OBJECTIVES]
            rows.append((name, str(len(front)), *ranges) if front else (name, "0", "no feasible trial", ""))
        heads = [f"{header(n)} range" for n in OBJECTIVES]
        columns = [("category", {}), *((col, {"justify": "right"}) for col in ("points", *heads))]
        console.print(table("Front per category", columns, rows))
    names = [p.name for p in VARIABLE_TABLE] + [*OBJECTIVES, "critical_speed"]
    columns = [(col, {"justify": "right"}) for col in cats + [header(n, "in") for n in names] + ["trial"]]
    rows = [
        [str(r[c]) for c in cats]
        + [number(r[n], n, "in") for n in names]
        + [f"{r['trial']}{'*' if r['refined'] else ''}"]
        for r in result.front
    ]
    console.print(table(f"Overall front ({len(result.front)} points)", columns, rows))
    if result.refined:
        console.print("* refined by the NLP (ε-constraint at the candidate's P)")
    ref = result.reference_point
    point = f"({shown(ref[0], 'turning_effort')}, {shown(ref[1], 'threshold_force')})"
    c = result.comparison
    if "hypervolume_ratio" in c and c.get("exact_points", 0) < 2:
        best = "reaches" if c["igd_plus"] < 1e-6 else "does not reach"
        console.print(
            f"The exact front is a single point (one design dominates every other): the explored front "
            f"{best} it (IGD+ {number(c['igd_plus'])}, normalised); a hypervolume ratio says nothing here."
        )
    elif "hypervolume_ratio" in c:
        console.print(
            f"Against the exact front ({c['exact_points']} points): HV {number(c['hypervolume_explored'])} vs "
            f"{number(c['hypervolume_exact'])} N² (ratio {number(c['hypervolume_ratio'])}; reference "
            f"{point} = exact nadir + 10 % of its extent); IGD+ "
            f"{number(c['igd_plus'])} (normalised by the exact front's ideal and nadir)"
        )
    else:
        console.print(f"HV {number(result.hypervolume)} N² (reference {point}). {c.get('note', '')}")
    console.print(f"wrote {csv_path} and {json_path}")
