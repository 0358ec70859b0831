"""NSGA-II operator study for ``designer explore`` (issue 5).

Runs optuna's NSGA-II on a problem with optuna's default operators and with
candidate configurations, several seeds each, and prints the mean of:
distinct parameter sets, feasible trials, front size, hypervolume ratio
against the exact front (:func:`designer.studies.front._pareto.pareto_front`, its stated
reference point) and IGD+ (normalised by the exact front's ideal and nadir).

    python benchmarks/explore_operators.py problems/indoor-manual.toml --trials 500 2000 --seeds 3
"""

from __future__ import annotations

import argparse
import dataclasses
import time
import warnings

import numpy as np

import designer
from designer.studies.explore import Operators, explore
from designer.studies.front import pareto_front


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("problem")
    parser.add_argument("--trials", type=int, nargs="+", default=[500, 2000])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--grid", action="store_true", help="also try a grid of SBX / mutation settings")
    args = parser.parse_args()
    problem = designer.load_problem(args.problem)
    warnings.simplefilter("ignore")
    pareto_front(problem)  # warm caches (casadi)
    for n in args.trials:
        configs = {"optuna default": Operators.for_budget(n, "optuna"), "tuned": Operators.for_budget(n)}
        if args.grid:
            base = Operators.for_budget(n)
            for pop in (20, 30, 50):
                for eta_c in (2.0, 5.0, 15.0, 30.0):
                    configs[f"sbx eta={eta_c:g} pop={pop}"] = dataclasses.replace(
                        base, population_size=pop, crossover_eta=eta_c
                    )
            configs["tuned, no dedup"] = dataclasses.replace(base, deduplicate=False)
            configs["tuned, pm prob 0.5"] = dataclasses.replace(base, mutation_prob=0.5)
            configs["optuna default pop 20"] = dataclasses.replace(
                Operators.for_budget(n, "optuna"), population_size=20
            )
        print(f"\n{problem.name}: {n} trials, {args.seeds} seeds (mean ± sd)")
        print(
            f"{'operators':28s} {'distinct':>9s} {'feasible':>9s} {'front':>6s} {'HV ratio':>14s} {'IGD+':>14s} {'trials/s':>9s}"
        )
        for name, ops in configs.items():
            rows = []
            for seed in range(args.seeds):
                t0 = time.perf_counter()
                r = explore(problem, trials=n, seed=seed, operators=ops)
                rows.append(
                    (
                        r.distinct,
                        r.feasible,
                        len(r.front),
                        r.comparison["hypervolume_ratio"],
                        r.comparison["igd_plus"],
                        n / (time.perf_counter() - t0),
                    )
                )
            a = np.array(rows, float)
            m, s = a.mean(axis=0), a.std(axis=0)
            print(
                f"{name:28s} {m[0]:9.0f} {m[1]:9.0f} {m[2]:6.1f} {m[3]:7.3f} ± {s[3]:.3f} {m[4]:7.4f} ± {s[4]:.3f} {m[5]:9.0f}"
            )


if __name__ == "__main__":
    main()
