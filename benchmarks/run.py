"""Speed and quality of the exact front side by side with the alternatives (issue 6).

    python -m benchmarks.run [--quick] [--problems indoor-manual sports-court ...] [--out benchmarks]

One process, one run, the same model (:func:`designer.model._caster.performance`) for
every method, on the shipped problems:

- this tool's exact ε-constraint front (:func:`designer.studies.front._pareto.pareto_front`),
  N = 25, 51, 101 points, cold (import measured once in a subprocess, plus
  NLP and solver builds) and warm (solvers built);
- pymoo NSGA-II on a vectorised ``pymoo.core.problem.Problem`` that calls the
  model on the whole population (population 100; 100 and 300 generations, 50 and 150 with ``--quick``;
  constraints V_c >= V_req and the swept radius as G <= 0);
- optuna NSGA-II with its default operators and with the best operators of
  issue 5 (``designer.studies.explore.Operators.for_budget``);
- scipy SLSQP ε-constraint loop on the same ε grid as the exact 101-point
  front (warm-started from the previous point, finite-difference gradients);
- a dense grid over the four variables, non-dominated filter;
- only the current code runs: the exact front as it was before issue 6 (commit
  LEGACY_COMMIT) is not run again; its "before" speed is quoted from the committed
  full-run results (``benchmarks/results.json``, where it was measured) beside
  this run's "after".

Quality: objectives normalised by the ideal and nadir of the exact 101-point
front; hypervolume with reference point (1.1, 1.1) in normalised units,
reported as HV / HV_exact101; IGD+ against the exact 101-point front (same
normalisation).  Only feasible, non-dominated points of a method count.

Then the speed guards of issue 44 (:mod:`benchmarks.speed`, one cold run each with ``--quick``, three
otherwise): the main job's CPU and its ratio to ``python -c "import numpy"``, the spec batch's CPU (``designer
fix ... --json --top 0``), each beside the ``--before`` checkout's when given, and the studio's last saved
key-press-to-redraw medians.

Writes ``results.md``, ``results.json`` and ``scaling.png`` into ``--out`` (default ``benchmarks/`` for
the full run, ``benchmarks/quick/`` for ``--quick``).
"""

from __future__ import annotations

import argparse
import datetime
import json
import re
import os
import platform
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PROBLEMS = ("indoor-manual", "sports-court", "powered-chair")
LEGACY_COMMIT = "085d726"
"""The commit of the exact front before issue 6, whose speed the committed results quote (never run again)."""
COMMITTED_RESULTS = ROOT / "benchmarks" / "results.json"
"""The committed full run: where the "before" numbers are quoted from."""
REFERENCE = np.array([1.1, 1.1])

FULL = dict(
    points=(25, 51, 101),
    exact_repeats=7,
    cold_repeats=5,
    ga_repeats=5,
    optuna_trials=(2000, 5000),
    optuna_repeats=3,
    pymoo_generations=(100, 300),
    slsqp_repeats=5,
    grid=(41, 401, 31, 41),
    grid_repeats=3,
    throughput_n=1_000_000,
    scaling_points=(11, 25, 51, 101, 201, 401),
    scaling_configs=(1, 10, 100),
    scaling_repeats=3,
)
QUICK = dict(
    points=(25, 51, 101),
    exact_repeats=2,
    cold_repeats=1,
    ga_repeats=1,
    optuna_trials=(200, 500),
    optuna_repeats=1,
    pymoo_generations=(50, 150),
    slsqp_repeats=1,
    grid=(21, 101, 16, 21),
    grid_repeats=1,
    throughput_n=100_000,
    scaling_points=(11, 51, 101),
    scaling_configs=(1, 5),
    scaling_repeats=1,
)
"""A smoke run (tests/test_benchmarks.py runs it): every method and table, small budgets, one repeat."""


# --------------------------------------------------------------------------- helpers


def timed(fn, repeats: int):
    """Run ``fn`` ``repeats`` times: (list of wall times [s], list of results)."""
    times, results = [], []
    for r in range(repeats):
        t0 = time.perf_counter()
        results.append(fn(r))
        times.append(time.perf_counter() - t0)
    return times, results


def stats(times) -> dict:
    return {
        "median_s": float(statistics.median(times)),
        "min_s": float(min(times)),
        "max_s": float(max(times)),
        "repeats": len(times),
    }


def fast_nondominated(f: np.ndarray) -> np.ndarray:
    """Non-dominated rows of a large (N, 2) array (minimisation), vectorised: sort, running minimum."""
    if len(f) == 0:
        return f.reshape(0, 2)
    order = np.lexsort((f[:, 1], f[:, 0]))
    g = f[order]
    best = np.minimum.accumulate(g[:, 1])
    keep = np.ones(len(g), bool)
    keep[1:] = g[1:, 1] < best[:-1]
    return g[keep]


def confident_speed(values: dict):
    return values.get("confident_speed", values["critical_speed"])


def feasible_mask(problem, values: dict, tol: float = 0.0) -> np.ndarray:
    ok = confident_speed(values) >= problem.required_speed * (1 - tol)
    if problem.swept_radius_max is not None:
        ok &= values["swept_radius"] <= problem.swept_radius_max * (1 + tol)
    return ok & np.isfinite(values["turning_effort"]) & np.isfinite(values["threshold_force"])


class Quality:
    """HV ratio and IGD+ against the exact 101-point front, on its normalisation."""

    def __init__(self, exact_objectives: np.ndarray):
        from designer.studies.front import hypervolume_2d, normalise

        self.ideal = exact_objectives.min(axis=0)
        self.nadir = exact_objectives.max(axis=0)
        self.exact = normalise(exact_objectives, self.ideal, self.nadir)
        self.hv_exact = hypervolume_2d(self.exact, REFERENCE)

    def __call__(self, objectives: np.ndarray) -> dict:
        from designer.studies.front import hypervolume_2d, igd_plus, normalise

        f = fast_nondominated(np.asarray(objectives, float).reshape(-1, 2))
        if len(f) == 0:
            return {"hv_ratio": 0.0, "igd_plus": float("inf"), "front_points": 0}
        g = normalise(f, self.ideal, self.nadir)
        return {
            "hv_ratio": hypervolume_2d(g, REFERENCE) / self.hv_exact,
            "igd_plus": igd_plus(g, self.exact),
            "front_points": int(len(f)),
        }


def median_quality(qs: list[dict]) -> dict:
    return {
        "hv_ratio": float(np.median([q["hv_ratio"] for q in qs])),
        "hv_ratio_min": float(np.min([q["hv_ratio"] for q in qs])),
        "hv_ratio_max": float(np.max([q["hv_ratio"] for q in qs])),
        "igd_plus": float(np.median([q["igd_plus"] for q in qs])),
        "front_points": int(np.median([q["front_points"] for q in qs])),
    }


# --------------------------------------------------------------------------- methods


def import_seconds() -> float:
    """Import cost of the package and its solver stack, measured once in a fresh interpreter."""
    code = (
        "import time, warnings; warnings.simplefilter('ignore'); t = time.perf_counter(); "
        "import designer, designer.studies.front._pareto, designer.problem, casadi; print(time.perf_counter() - t)"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def exact_method(problem, points: int, repeats: int, cold_repeats: int, import_s: float):
    import designer.studies.front._pareto as pareto
    from designer.solvers.nlp import SHARED

    def cold(_):
        SHARED.clear()
        return pareto.pareto_front(problem, points)

    cold_times, _ = timed(cold, cold_repeats)
    pareto.pareto_front(problem, points)  # warm: the cache holds the built solvers
    warm_times, fronts = timed(lambda _: pareto.pareto_front(problem, points), repeats)
    front = fronts[-1]
    return {
        "warm": stats(warm_times),
        "cold": {
            **stats([t + import_s for t in cold_times]),
            "import_s": import_s,
            "build_and_solve_median_s": float(statistics.median(cold_times)),
        },
        "nlp_solves": int(front.meta["nlp_solves"]),
        "model_evaluations": None,
        "ms_per_point_warm": 1e3 * statistics.median(warm_times) / points,
        "points": len(front),
        "failed": len(front.failed),
    }, front


def quoted_before(path: Path = COMMITTED_RESULTS) -> dict:
    """Per problem, the "before" numbers of the exact front (commit LEGACY_COMMIT), quoted from ``path``.

    They were measured once, in the full run that ran the old code; a later full run writes them into its
    results.json again with where they came from, so they stay quotable.  Empty if the file or the entry is
    missing (then the report has no before/after line).
    """
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    out = {}
    for name, res in (data.get("problems") or {}).items():
        lg = res.get("legacy") or {}
        if "ms_per_point_before" not in lg:
            continue
        versions = data.get("versions") or {}
        out[name] = {
            "points": lg["points"],
            "ms_per_point_before": lg["ms_per_point_before"],
            "nlp_solves_before": lg["nlp_solves_before"],
            "commit": lg.get("commit", LEGACY_COMMIT),
            "measured_on": lg.get("measured_on", data.get("date")),
            "measured_at": lg.get("measured_at", versions.get("git")),
        }
    return out


class PymooCaster:
    """pymoo Problem: the whole population through the one model, constraints as G <= 0."""

    def __new__(cls, problem, counter):
        from pymoo.core.problem import Problem as PymooProblem

        lo, hi = problem.lower().as_array(), problem.upper().as_array()
        n_ieq = 1 + (problem.swept_radius_max is not None)

        class _Caster(PymooProblem):
            def __init__(self):
                super().__init__(n_var=4, n_obj=2, n_ieq_constr=n_ieq, xl=lo, xu=hi)

            def _evaluate(self, x, out, *args, **kwargs):
                counter[0] += len(x)
                v = problem.evaluate(np.asarray(x, float))
                out["F"] = np.column_stack([v["turning_effort"], v["threshold_force"]])
                g = [1 - confident_speed(v) / problem.required_speed]
                if problem.swept_radius_max is not None:
                    g.append(v["swept_radius"] / problem.swept_radius_max - 1)
                out["G"] = np.column_stack(g)

        return _Caster()


def pymoo_method(problem, generations: int, repeats: int, quality: Quality):
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize

    counts, qs = [], []

    def run(seed):
        counter = [0]
        res = minimize(
            PymooCaster(problem, counter), NSGA2(pop_size=100), ("n_gen", generations), seed=seed, verbose=False
        )
        counts.append(counter[0])
        return res

    times, results = timed(run, repeats)
    for res in results:
        if res.F is None:
            qs.append(quality(np.zeros((0, 2))))
            continue
        cv = np.asarray(res.CV).ravel() if res.CV is not None else np.zeros(len(res.F))
        qs.append(quality(np.asarray(res.F)[cv <= 0]))
    return {"time": stats(times), "model_evaluations": int(np.median(counts)), **median_quality(qs)}


def optuna_method(problem, trials: int, operators: str, repeats: int, quality: Quality):
    import optuna

    from designer.model import VARIABLES

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    note = ""

    def sampler(seed):
        nonlocal note
        if operators == "optuna":
            note = "optuna.samplers.NSGAIISampler defaults (population 50, uniform crossover)"
            return optuna.samplers.NSGAIISampler(seed=seed)
        try:
            from designer.studies.explore import Operators

            ops = Operators.for_budget(trials)
            note = f"designer.studies.explore.Operators.for_budget({trials}): {ops.to_dict()}"
            return ops.sampler(seed)
        except Exception as exc:  # explore not usable: SBX crossover, population ≈ √N
            from optuna.samplers.nsgaii import SBXCrossover

            pop = int(min(100, max(20, round(np.sqrt(trials)))))
            note = f"fallback ({type(exc).__name__}): NSGAIISampler(SBXCrossover(eta=15), population {pop})"
            return optuna.samplers.NSGAIISampler(seed=seed, population_size=pop, crossover=SBXCrossover(eta=15.0))

    def objective(trial):
        x = np.array([[trial.suggest_float(name, lo[i], hi[i]) for i, name in enumerate(VARIABLES)]])
        v = problem.evaluate(x)
        trial.set_constraint("shimmy", float(1 - confident_speed(v)[0] / problem.required_speed))
        if problem.swept_radius_max is not None:
            trial.set_constraint("swept_radius", float(v["swept_radius"][0] / problem.swept_radius_max - 1))
        return float(v["turning_effort"][0]), float(v["threshold_force"][0])

    def run(seed):
        study = optuna.create_study(directions=["minimize", "minimize"], sampler=sampler(seed))
        study.optimize(objective, n_trials=trials)
        return study

    times, studies = timed(run, repeats)
    qs = []
    for study in studies:
        f = []
        for t in study.trials:
            c = getattr(t, "constraints", None) or {}
            values = c.values() if isinstance(c, dict) else c
            if t.values is not None and all(v <= 0 for v in values):
                f.append(t.values)
        qs.append(quality(np.array(f, float).reshape(-1, 2)))
    return {"time": stats(times), "model_evaluations": trials, "operators": note, **median_quality(qs)}


def slsqp_method(problem, eps_values, repeats: int, quality: Quality):
    from scipy.optimize import minimize

    from designer.model import performance

    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    scale = np.where(hi > 0, hi, 1.0)
    req = problem.required_speed

    def run(_):
        count = [0]
        memo = {}

        def perf(z):
            key = z.tobytes()
            if key not in memo:
                memo.clear()
                count[0] += 1
                x = z * scale
                memo[key] = performance(x[0], x[1], x[2], x[3], problem.conditions)
            return memo[key]

        z = (lo + hi) / 2 / scale
        out = []
        for eps in eps_values:
            cons = [
                {"type": "ineq", "fun": lambda z, e=eps: 1 - perf(z)["threshold_force"] / e},
                {"type": "ineq", "fun": lambda z: confident_speed(perf(z)) / req - 1},
            ]
            if problem.swept_radius_max is not None:
                cons.append({"type": "ineq", "fun": lambda z: 1 - perf(z)["swept_radius"] / problem.swept_radius_max})
            res = minimize(
                lambda z: perf(z)["turning_effort"],
                z,
                method="SLSQP",
                constraints=cons,
                bounds=list(zip(lo / scale, hi / scale)),
                options={"ftol": 1e-10, "maxiter": 200},
            )
            x = res.x * scale
            v = performance(x[0], x[1], x[2], x[3], problem.conditions)
            ok = bool(feasible_mask(problem, {k: np.atleast_1d(val) for k, val in v.items()}, 1e-6)[0])
            if res.success and ok and v["threshold_force"] <= eps * (1 + 1e-6):
                out.append((float(v["turning_effort"]), float(v["threshold_force"])))
                z = res.x
        return np.array(out).reshape(-1, 2), count[0]

    times, results = timed(run, repeats)
    f, evals = results[-1]
    return {
        "time": stats(times),
        "model_evaluations": int(evals),
        "solved": int(len(f)),
        "of": int(len(eps_values)),
        **quality(f),
    }


def grid_front(problem, shape) -> tuple[np.ndarray, int]:
    """Dense grid over (T, d, B, c_f), the one model vectorised chunk by chunk, non-dominated filter."""

    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    axes = [np.linspace(lo[i], hi[i], n) if hi[i] > lo[i] else np.array([lo[i]]) for i, n in enumerate(shape)]
    t, b, c = (a.ravel() for a in np.meshgrid(axes[0], axes[2], axes[3], indexing="ij"))
    per_d = len(t)
    chunk = max(1, 2_000_000 // per_d)
    fronts, count = [], 0
    for start in range(0, len(axes[1]), chunk):
        ds = axes[1][start : start + chunk]
        x = np.column_stack([np.tile(t, len(ds)), np.repeat(ds, per_d), np.tile(b, len(ds)), np.tile(c, len(ds))])
        v = problem.evaluate(x)
        count += len(x)
        ok = feasible_mask(problem, v)
        fronts.append(fast_nondominated(np.column_stack([v["turning_effort"][ok], v["threshold_force"][ok]])))
    return fast_nondominated(np.concatenate(fronts)), count


def grid_method(problem, shape, repeats: int, quality: Quality):
    times, results = timed(lambda _: grid_front(problem, shape), repeats)
    f, count = results[-1]
    return {"time": stats(times), "model_evaluations": int(count), "grid": list(shape), **quality(f)}


# --------------------------------------------------------------------------- model and NLP costs


def model_throughput(problem, n: int, repeats: int = 5) -> dict:
    from designer.solvers.nlp import sample_designs

    x = sample_designs(problem, 1 << int(np.ceil(np.log2(n))), seed=1)[:n]
    times, _ = timed(lambda _: problem.evaluate(x), repeats)
    return {"designs": n, **stats(times), "designs_per_second": n / statistics.median(times)}


def nlp_costs(problem, repeats: int = 20) -> dict:
    from designer.solvers.nlp import CasterNLP, box_sample, lexicographic_ends

    t0 = time.perf_counter()
    nlp = CasterNLP(problem)
    build = time.perf_counter() - t0
    ends = lexicographic_ends(nlp, problem, box_sample(problem))
    end_a, end_b = ends.a, ends.b
    batch_build = nlp.build_seconds - build
    p_a, p_b = nlp.objectives(end_a.design)[1], nlp.objectives(end_b.design)[1]
    eps = 0.5 * (p_a + p_b)
    centre = (problem.lower().as_array() + problem.upper().as_array()) / 2
    ref = nlp.solve(centre, (1.0, 0.0), eps)
    cold_t, cold_r = timed(lambda _: nlp.solve(centre, (1.0, 0.0), eps), repeats)
    eps2 = eps * (1 - 1e-3)
    warm_t, warm_r = timed(
        lambda _: nlp.solve(ref.design, (1.0, 0.0), eps2, lam_g0=ref.lam_g, lam_x0=ref.lam_x), repeats
    )
    k = 64
    eps_k = np.linspace(p_a, p_b, k + 2)[1:-1]
    starts = np.tile(centre, (k, 1))
    batch = nlp.solve_many(starts, (1.0, 0.0), eps_k)
    bc_t, _ = timed(lambda _: nlp.solve_many(starts, (1.0, 0.0), eps_k), 5)
    xs = np.array([r.design.as_array() for r in batch])
    lg, lx = np.array([r.lam_g for r in batch]), np.array([r.lam_x for r in batch])
    bw_t, bw_r = timed(lambda _: nlp.solve_many(xs, (1.0, 0.0), eps_k * (1 - 1e-3), lam_g0=lg, lam_x0=lx), 5)
    return {
        "nlp_build_s": build,
        "batch_solver_build_s": batch_build,
        "batch_sizes": list(CasterNLP.BATCH_SIZES),
        "single_cold": {**stats(cold_t), "iterations": cold_r[-1].iterations},
        "single_warm": {**stats(warm_t), "iterations": warm_r[-1].iterations},
        "batch64_cold_per_block": {**{k_: v / k if k_.endswith("_s") else v for k_, v in stats(bc_t).items()}},
        "batch64_warm_per_block": {
            **{k_: v / k if k_.endswith("_s") else v for k_, v in stats(bw_t).items()},
            "iterations": bw_r[-1][0].iterations,
        },
    }


# --------------------------------------------------------------------------- scaling


def strategy_costs(problem, repeats: int = 5) -> dict:
    """The default front of ``problem`` (risk-bounded, and its nominal twin) by each sweep strategy, warm: CPU
    seconds (median of ``repeats``, this process only) and the NLP block solves of one front."""
    from designer.studies.front import pareto_front

    out = {}
    for label, p in (("risk-bounded", problem if problem.risk is not None else None), ("nominal", problem.nominal())):
        if p is None:
            continue
        for strategy in ("nlp", "auto"):
            front = pareto_front(p, strategy=strategy)  # warm: the solvers are built
            cpu = []
            for _ in range(repeats):
                c0 = time.process_time()
                front = pareto_front(p, strategy=strategy)
                cpu.append(time.process_time() - c0)
            out[f"{label}, {front.meta['strategy']}"] = {
                "cpu_median_s": float(statistics.median(cpu)),
                "nlp_solves": int(front.meta["nlp_solves"]),
                "points": len(front),
            }
    return out


def configurations(problem, count: int) -> list:
    """``count`` chair configurations: caster load 120…300 N × target speed 1.8…2.8 m/s (a grid, row by row)."""
    side = int(np.ceil(np.sqrt(count)))
    loads = np.linspace(120.0, 300.0, side)
    speeds = np.linspace(1.8, 2.8, side)
    out = []
    for load in loads:
        for speed in speeds:
            if len(out) < count:
                out.append(
                    problem.replace(target_speed=float(speed), conditions=problem.conditions.replace(load=float(load)))
                )
    return out


def scaling(problems: dict, cfg: dict) -> dict:
    import designer.studies.front._pareto as pareto
    from designer.solvers.nlp import SHARED

    by_points = {}
    for name, problem in problems.items():
        rows = []
        for n in cfg["scaling_points"]:
            pareto.pareto_front(problem, n)
            times, fronts = timed(lambda _: pareto.pareto_front(problem, n), cfg["scaling_repeats"])
            rows.append(
                {
                    "points": n,
                    **stats(times),
                    "ms_per_point": 1e3 * statistics.median(times) / n,
                    "nlp_solves": fronts[-1].meta["nlp_solves"],
                }
            )
        by_points[name] = rows
    base = problems.get("indoor-manual") or next(iter(problems.values()))
    batch = []
    for count in cfg["scaling_configs"]:
        configs = configurations(base, count)
        SHARED.clear()
        t0 = time.perf_counter()
        fronts = [pareto.pareto_front(p, 25) for p in configs]
        cold = time.perf_counter() - t0
        times, _ = timed(lambda _: [pareto.pareto_front(p, 25) for p in configs], cfg["scaling_repeats"])
        batch.append(
            {
                "configurations": count,
                "points_each": 25,
                "cold_s": cold,
                **stats(times),
                "ms_per_configuration": 1e3 * statistics.median(times) / count,
                "valid_points": int(sum(len(f) for f in fronts)),
            }
        )
    return {"by_points": by_points, "by_configurations": batch}


def figure(results: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sc = results["scaling"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes[0]
    for name, rows in sc["by_points"].items():
        n = [r["points"] for r in rows]
        t = [r["median_s"] for r in rows]
        ax.loglog(n, t, "o-", label=f"exact front, {name}")
    n = np.array(
        [min(r["points"] for r in rows) for rows in sc["by_points"].values()]
        + [max(r["points"] for r in rows) for rows in sc["by_points"].values()],
        float,
    )
    lo_n, hi_n = n.min(), n.max()
    first = next(iter(sc["by_points"].values()))
    t_ref = first[-1]["median_s"]
    ax.loglog([lo_n, hi_n], [t_ref * lo_n / hi_n, t_ref], "k:", lw=1, label="slope 1 (linear in N)")
    few, many = sorted(results["config"]["pymoo_generations"])
    first = results["problems"][next(iter(results["problems"]))]["methods"]
    for g, style in ((many, "--"), (few, "-.")):
        ax.axhline(first[f"pymoo NSGA-II {g} gen"]["time"]["median_s"], ls=style, lw=0.8, color="grey")
    ax.text(
        lo_n,
        first[f"pymoo NSGA-II {many} gen"]["time"]["median_s"] * 1.1,
        f"pymoo NSGA-II, {many} / {few} generations (first problem)",
        fontsize=8,
        color="grey",
    )
    ax.set_xlabel("points on the front N")
    ax.set_ylabel("warm wall time [s] (median)")
    ax.set_title("Exact front: time vs number of points")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1]
    rows = sc["by_configurations"]
    c = [r["configurations"] for r in rows]
    ax.loglog(c, [r["median_s"] for r in rows], "o-", label="warm (one NLP build shared)")
    ax.loglog(c, [r["cold_s"] for r in rows], "s--", label="cold (incl. the one build)")
    ax.loglog([c[0], c[-1]], [rows[-1]["median_s"] * c[0] / c[-1], rows[-1]["median_s"]], "k:", lw=1, label="slope 1")
    ax.set_xlabel("chair configurations (load × target speed), 25-point front each")
    ax.set_ylabel("wall time [s]")
    ax.set_title("Batch of problems")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------- report


def versions() -> dict:
    import importlib.metadata as md

    out = {"python": platform.python_version()}
    for pkg in ("numpy", "scipy", "casadi", "pymoo", "optuna", "matplotlib"):
        try:
            out[pkg] = md.version(pkg)
        except md.PackageNotFoundError:
            out[pkg] = None
    try:
        out["caster-designer"] = md.version("caster-designer")
        out["git"] = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
        ).stdout.strip()
    except Exception:
        pass
    return out


def fmt_time(t: dict) -> str:
    def f(s):
        return f"{s * 1e3:.1f} ms" if s < 1 else f"{s:.2f} s"

    return f"{f(t['median_s'])} [{f(t['min_s'])}–{f(t['max_s'])}]"


def markdown(results: dict) -> str:
    m = results["machine"]
    lines = [
        "# Benchmarks: exact front vs NSGA-II (pymoo, optuna), SLSQP and a dense grid",
        "",
        f"Generated by `python -m benchmarks.run{' --quick' if results['quick'] else ''}` on {results['date']}, "
        f"wall time of the whole run {results['run_seconds']:.0f} s.",
        "",
        f"Machine: {m['platform']}, {m['processor'] or m['machine']}, {m['cpu_count']} CPUs; "
        f"load average at start {m['load_start']}, at end {m['load_end']} (a shared machine: other jobs ran at "
        f"the same time, so absolute times are noisy; ratios measured in the same run are more robust).",
        "",
        "Versions: " + ", ".join(f"{k} {v}" for k, v in results["versions"].items()),
        "",
        "## Method",
        "",
        "Every method uses the one model `designer.model._caster.performance` (the GA and grid through its vectorised "
        "form over the whole population / grid chunk). Quality is measured against the exact 101-point front: "
        "objectives (F_turn, P) normalised by its ideal and nadir, hypervolume with reference point (1.1, 1.1) "
        "in normalised units, reported as **HV / HV_exact101**, and **IGD+** against it (0 = reaches the "
        "exact front everywhere). Only feasible (V_c >= V_req, R_s <= R_max), non-dominated points count. "
        "Times are wall times: median [min–max] over the repeats shown. *Cold* = import of the package "
        f"(measured once in a fresh interpreter: {results['import_s'] * 1e3:.0f} ms) + NLP and batched-solver "
        "builds + solve; *warm* = solvers already built (a second front of the same problem in one process). "
        "GA quality is the median over the repeats (one seed each; min–max of the HV ratio in the JSON).",
        "",
    ]
    cfg = results["config"]
    lines += [
        f"Repeats: exact warm {cfg['exact_repeats']}, exact cold {cfg['cold_repeats']}, pymoo "
        f"{cfg['ga_repeats']}, optuna {cfg['optuna_repeats']} (the slowest; fewer repeats), SLSQP "
        f"{cfg['slsqp_repeats']}, grid {cfg['grid_repeats']}.",
        "",
    ]
    for name, res in results["problems"].items():
        lines += [
            f"## {name}",
            "",
            "| method | time | model evaluations / NLP solves | HV / HV_exact101 | IGD+ | points |",
            "|---|---|---|---|---|---|",
        ]
        for method, r in res["methods"].items():
            t = r.get("time") or r.get("warm")
            evals = r.get("model_evaluations")
            ev = f"{evals:,}" if evals else f"{r['nlp_solves']} NLP solves"
            lines.append(
                f"| {method} | {fmt_time(t)} | {ev} | {r['hv_ratio']:.5f} | {r['igd_plus']:.2e} | "
                f"{r.get('front_points', r.get('points', ''))} |"
            )
            if "cold" in r:
                lines.append(f"| ↳ same, cold | {fmt_time(r['cold'])} | | | | |")
        lines.append("")
        sp = res["speedup"]
        few, many = sorted(cfg["pymoo_generations"])
        lines += [
            f"Exact 101-point front (warm) vs NSGA-II: {sp[f'vs_pymoo_{many}']:.0f}× faster than pymoo {many} gen "
            f"(HV ratio {sp[f'pymoo_{many}_hv']:.4f}), {sp[f'vs_pymoo_{few}']:.0f}× faster than pymoo {few} gen "
            f"(HV ratio {sp[f'pymoo_{few}_hv']:.4f}), {sp['vs_optuna_best']:.0f}× faster than optuna with the "
            f"best operators at {sp['optuna_trials']} trials (HV ratio {sp['optuna_best_hv']:.4f}), "
            f"{sp['vs_optuna_default']:.0f}× faster than optuna's defaults (HV ratio "
            f"{sp['optuna_default_hv']:.4f}). Cold (import + build + solve) vs pymoo {many} gen: "
            f"{sp[f'cold_vs_pymoo_{many}']:.1f}×.",
            "",
        ]
        if res.get("legacy"):
            lg = res["legacy"]
            lines += [
                f"Before / after issue 6 (exact front, {lg['points']} points, warm, "
                f"{lg.get('front', 'as configured')}: the problems had no risk bound then): "
                f"{lg['ms_per_point_before']:.2f} ms per point before (commit {lg['commit']}, "
                f"{lg['nlp_solves_before']} IPOPT solves; measured on {lg['measured_on']} at {lg['measured_at']} "
                f"in a full run, quoted here: the old code is not run again) → {lg['ms_per_point_after']:.2f} ms per "
                f"point now, in this run ({lg['speedup']:.1f}×; a ratio across two runs, so only as good as their "
                f"loads are alike).",
                "",
            ]
    th = results["throughput"]
    nc = results["nlp"]
    lines += [
        "## Model and NLP costs (indoor-manual)",
        "",
        f"- Vectorised model (`Problem.evaluate` → `model.evaluate` → `performance` on NumPy arrays): {th['designs_per_second']:.3g} "
        f"designs/s ({th['designs']:,} designs in {th['median_s'] * 1e3:.1f} ms, median of {th['repeats']}).",
        f"- NLP build (CasADi SX + IPOPT): {nc['nlp_build_s'] * 1e3:.1f} ms; batched solvers "
        + (f"({', '.join(map(str, nc['batch_sizes']))} blocks, " if nc.get("batch_sizes") else "(")
        + f"cold and warm variants, built lazily as needed): {nc['batch_solver_build_s'] * 1e3:.0f} ms.",
        f"- One IPOPT solve, cold (box centre, no multipliers): {fmt_time(nc['single_cold'])}, "
        f"{nc['single_cold']['iterations']} iterations.",
        f"- One IPOPT solve, warm (neighbouring optimum and its multipliers, ε 0.1 % tighter): "
        f"{fmt_time(nc['single_warm'])}, {nc['single_warm']['iterations']} iterations.",
        f"- Batched (64 blocks in one block-diagonal NLP), per block: cold {fmt_time(nc['batch64_cold_per_block'])}, "
        f"warm {fmt_time(nc['batch64_warm_per_block'])} ({nc['batch64_warm_per_block']['iterations']} iterations).",
        "",
        "## Scaling",
        "",
        "![scaling](scaling.png)",
        "",
        "Warm time of the exact front against the number of points:",
        "",
        "| problem | N | time | ms / point | NLP block solves |",
        "|---|---|---|---|---|",
    ]
    for name, rows in results["scaling"]["by_points"].items():
        for r in rows:
            lines.append(f"| {name} | {r['points']} | {fmt_time(r)} | {r['ms_per_point']:.2f} | {r['nlp_solves']} |")
    lines += [
        "",
        "A batch of chair configurations (indoor-manual, caster load 120–300 N × target speed "
        "1.8–2.8 m/s), a 25-point front each, computed one after the other in one process; load and target "
        "speed are parameters of the NLP, so all configurations share one build:",
        "",
        "| configurations | cold (incl. build) | warm | ms / configuration | valid points |",
        "|---|---|---|---|---|",
    ]
    for r in results["scaling"]["by_configurations"]:
        lines.append(
            f"| {r['configurations']} | {r['cold_s']:.2f} s | {fmt_time(r)} | {r['ms_per_configuration']:.1f} "
            f"| {r['valid_points']} |"
        )
    lines += [
        "",
        "## What the exact front does (designer/studies/front/_pareto.py, designer/solvers/nlp/_sweep.py)",
        "",
        "ε-constraint sweep (min F_turn s.t. P <= ε) on the CasADi/IPOPT NLP built once per problem structure: "
        "the two lexicographic ends, then ε evenly spaced between them (pass 1), then ε re-spaced by arc length "
        "along pass 1 (pass 2). How an ε-point is solved is the front solver's sweep "
        "(`designer.solvers.front_solver`):",
        "",
        "- **structured** (wherever `designer.solvers.closed_form.applicable` holds, nominal and risk-bounded): the "
        "closed-form ε-optima (smallest admissible d, largest admissible T, the cheapest point of the shimmy "
        "constraint's curve in the (B, c_f) box) space pass 1 as they are, and one warm batched NLP solve confirms "
        "each point of pass 2 and the ends (the NLP's result is what is reported); a point whose solve fails or "
        "disagrees by more than 1e-9 goes through the NLP sweep.",
        "- **nlp** (catalog wheels, a fixed diameter, a risk bound whose quantile varies too fast, or "
        '`strategy="nlp"`): the points of a pass are solved together as block-diagonal NLPs (CasADi `map`, '
        + "/".join(map(str, results["nlp"].get("batch_sizes") or ()))
        + " blocks per IPOPT call), pass 1 from the best feasible point of a vectorised Sobol sample under each ε, "
        "pass 2 warm from the neighbouring pass-1 optimum with its multipliers (`warm_start_init_point`, small "
        "μ); family restarts (grooved / damped) on every tenth point and at every family switch, where the "
        "neighbours are re-solved from each other's optimum until nothing improves.",
        "",
    ]
    strategies = results.get("strategies")
    if strategies:
        lines += [
            f"The default front of {strategies['problem']} by each strategy, warm, in this run (CPU of this "
            f"process, median of {results['config']['exact_repeats']}):",
            "",
            "| front, strategy | CPU | NLP block solves | points |",
            "|---|---|---|---|",
        ]
        lines += [
            f"| {name} | {1e3 * r['cpu_median_s']:.0f} ms | {r['nlp_solves']} | {r['points']} |"
            for name, r in strategies.items()
            if name != "problem"
        ]
        lines.append("")
    return "\n".join(lines)


# --------------------------------------------------------------------------- main


BEGIN, END = "<!-- benchmarks.run: begin -->", "<!-- benchmarks.run: end -->"
"""The part of results.md this run writes; the other benchmarks write theirs between their own markers."""


def write_markdown(path: Path, text: str) -> None:
    """Put ``text`` into ``path`` between :data:`BEGIN` and :data:`END`, keeping the rest of the file (the
    sections of benchmarks.coldstart, main_job, fleet and studio_latency).  A file without the markers yet keeps
    everything from its first other section marker on; a new file is the block alone."""
    block = f"{BEGIN}\n{text.rstrip()}\n{END}\n"
    old = path.read_text(encoding="utf-8") if path.exists() else ""
    if BEGIN in old and END in old:
        head, rest = old.split(BEGIN, 1)
        after = rest.split(END, 1)[1].lstrip("\n")
        new = head + block + ("\n" + after if after else "")
    else:
        other = re.search(r"^<!-- [^\n]*: begin -->$", old, re.M)
        new = block + ("\n" + old[other.start() :] if other else "")
    path.write_text(new, encoding="utf-8")


def _span(values, fmt: str) -> str:
    """``"a–b"`` of ``values`` formatted by ``fmt`` (one value when they round alike)."""
    lo, hi = fmt.format(min(values)), fmt.format(max(values))
    return lo if lo == hi else f"{lo}–{hi}"


def show(results: dict) -> list[str]:
    """A saved full run in a few lines at most 80 wide (docs/benchmarks.md shows them): per method, how much
    faster the exact 101-point front (warm) is and the method's hypervolume against it, as ranges over the
    problems; then the exact front's cost per point and the cold start."""
    problems = results["problems"]
    exact = {name: res["methods"]["exact front N=101"] for name, res in problems.items()}
    others = [m for m in next(iter(problems.values()))["methods"] if not m.startswith("exact front")]
    lines = [
        f"full run {results['date'][:10]} ({results['machine']['cpu_count']} CPUs): {', '.join(problems)}",
        "exact 101-point front (warm) against:",
        f"  {'method':<35}{'exact is':>17}{'their HV ratio':>16}",
    ]
    for method in others:
        ratios, hv = [], []
        for name, res in problems.items():
            r = res["methods"][method]
            ratios.append((r.get("time") or r["warm"])["median_s"] / exact[name]["warm"]["median_s"])
            hv.append(r["hv_ratio"])
        lines.append(f"  {method:<35}{_span(ratios, '{:.0f}') + '× faster':>17}{_span(hv, '{:.3f}'):>16}")
    per_point = [e["ms_per_point_warm"] for e in exact.values()]
    front_ms = [1e3 * e["warm"]["median_s"] for e in exact.values()]
    cold = [res["speedup"][f"cold_vs_pymoo_{max(results['config']['pymoo_generations'])}"] for res in problems.values()]
    lines += [
        f"exact front, warm: {_span(per_point, '{:.2f}')} ms per point, {_span(front_ms, '{:.0f}')} ms per front",
        f"cold (import {results['import_s']:.2f} s + build + solve): {_span(cold, '{:.1f}')}× faster than pymoo "
        f"{max(results['config']['pymoo_generations'])} gen",
    ]
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--quick",
        action="store_true",
        help="smaller budgets, one repeat: a smoke run (about 25 s of CPU; < 2 min on 2 shared cores)",
    )
    parser.add_argument("--problems", nargs="+", default=list(PROBLEMS))
    parser.add_argument(
        "--out",
        default=None,
        help="output folder (default: benchmarks/ for a full run; benchmarks/quick/ for --quick, "
        "so a quick run never overwrites the committed full-run results)",
    )
    parser.add_argument("--show", action="store_true", help="print the summary of the run saved in --out; run nothing")
    parser.add_argument(
        "--before",
        type=Path,
        help="a checkout of earlier code with its own .venv: the speed guards (benchmarks.speed) measure it beside",
    )
    args = parser.parse_args(argv)
    if args.show:
        folder = Path(args.out) if args.out else Path(__file__).resolve().parent
        print("\n".join(show(json.loads((folder / "results.json").read_text(encoding="utf-8")))))
        return 0
    if args.out is None:
        here = Path(__file__).resolve().parent
        args.out = str(here / "quick" if args.quick else here)
    warnings.simplefilter("ignore")
    cfg = QUICK if args.quick else FULL
    t_run = time.perf_counter()
    load_start = os.getloadavg() if hasattr(os, "getloadavg") else None
    import_s = import_seconds()

    from designer.problem import load_problem

    problems = {name: load_problem(ROOT / "problems" / f"{name}.toml") for name in args.problems}
    before = quoted_before()  # read before this run may write its own results.json over the file
    results = {"quick": args.quick, "config": cfg, "import_s": import_s, "problems": {}}
    for name, problem in problems.items():
        methods = {}
        exact = {}
        for n in cfg["points"]:
            exact[n] = exact_method(problem, n, cfg["exact_repeats"], cfg["cold_repeats"], import_s)
        ref_front = exact[101][1] if 101 in exact else exact[max(exact)][1]
        quality = Quality(ref_front.objectives())
        for n, (r, front) in exact.items():
            methods[f"exact front N={n}"] = {**r, **quality(front.objectives())}
        for g in cfg["pymoo_generations"]:
            methods[f"pymoo NSGA-II {g} gen"] = pymoo_method(problem, g, cfg["ga_repeats"], quality)
        for trials in cfg["optuna_trials"]:
            for ops, label in (("optuna", "defaults"), ("tuned", "best operators")):
                methods[f"optuna NSGA-II {label} {trials}"] = optuna_method(
                    problem, trials, ops, cfg["optuna_repeats"], quality
                )
        eps = np.array([p.threshold_force for p in ref_front])
        methods["scipy SLSQP ε-loop (101 ε)"] = slsqp_method(problem, eps, cfg["slsqp_repeats"], quality)
        methods[f"dense grid {'×'.join(map(str, cfg['grid']))}"] = grid_method(
            problem, cfg["grid"], cfg["grid_repeats"], quality
        )
        res = {"methods": methods}
        warm101 = methods["exact front N=101"]["warm"]["median_s"]
        cold101 = methods["exact front N=101"]["cold"]["median_s"]
        top = max(cfg["optuna_trials"])
        ga = {g: methods[f"pymoo NSGA-II {g} gen"] for g in cfg["pymoo_generations"]}
        res["speedup"] = {
            **{f"vs_pymoo_{g}": r["time"]["median_s"] / warm101 for g, r in ga.items()},
            f"cold_vs_pymoo_{max(ga)}": ga[max(ga)]["time"]["median_s"] / cold101,
            "vs_optuna_best": methods[f"optuna NSGA-II best operators {top}"]["time"]["median_s"] / warm101,
            "vs_optuna_default": methods[f"optuna NSGA-II defaults {top}"]["time"]["median_s"] / warm101,
            **{f"pymoo_{g}_hv": r["hv_ratio"] for g, r in ga.items()},
            "optuna_best_hv": methods[f"optuna NSGA-II best operators {top}"]["hv_ratio"],
            "optuna_default_hv": methods[f"optuna NSGA-II defaults {top}"]["hv_ratio"],
            "optuna_trials": top,
        }
        quote = before.get(name)
        if quote:  # the problems had no risk bound at LEGACY_COMMIT: the same, nominal front now
            now, _ = exact_method(problem.nominal(), quote["points"], cfg["exact_repeats"], 1, import_s)
            res["legacy"] = {
                **quote,
                "front": "nominal",
                "ms_per_point_after": now["ms_per_point_warm"],
                "speedup": quote["ms_per_point_before"] / now["ms_per_point_warm"],
            }
        results["problems"][name] = res
        for method, r in methods.items():
            t = r.get("time") or r.get("warm")
            print(
                f"{name:14s} {method:38s} time {t['median_s'] * 1e3:10.1f} ms  HV ratio {r['hv_ratio']:.5f}  "
                f"IGD+ {r['igd_plus']:.2e}",
                flush=True,
            )
        if "legacy" in res:
            lg = res["legacy"]
            print(
                f"{name:14s} nominal exact front before issue 6 (N={lg['points']}, quoted from {lg['measured_on']}): "
                f"{lg['ms_per_point_before']:.2f} ms/point -> now {lg['ms_per_point_after']:.2f} ms/point "
                f"({lg['speedup']:.1f}x)",
                flush=True,
            )
    base = problems.get("indoor-manual") or next(iter(problems.values()))
    results["throughput"] = model_throughput(base, cfg["throughput_n"])
    results["nlp"] = nlp_costs(base)
    results["scaling"] = scaling(problems, cfg)
    results["strategies"] = {"problem": base.name, **strategy_costs(base, cfg["exact_repeats"])}
    print(
        f"model throughput {results['throughput']['designs_per_second']:.3g} designs/s; one NLP solve cold "
        f"{results['nlp']['single_cold']['median_s'] * 1e3:.2f} ms, warm {results['nlp']['single_warm']['median_s'] * 1e3:.2f} ms; "
        f"batched per block cold {results['nlp']['batch64_cold_per_block']['median_s'] * 1e3:.3f} ms, warm "
        f"{results['nlp']['batch64_warm_per_block']['median_s'] * 1e3:.3f} ms",
        flush=True,
    )
    # the speed guards of issue 44 (benchmarks.speed): the main job's CPU against the numpy import's, the spec
    # batch's CPU, each beside the before checkout's when given, and the studio's last saved medians
    from benchmarks import speed

    results["speed"] = speed.measure(1 if args.quick else 3, args.before)
    print("\n".join(speed.summary(results["speed"])), flush=True)
    results["run_seconds"] = time.perf_counter() - t_run
    results["date"] = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
    results["machine"] = {
        "platform": platform.platform(),
        "machine": platform.machine(),
        "processor": platform.processor(),
        "cpu_count": os.cpu_count(),
        "load_start": [round(v, 2) for v in load_start] if load_start else None,
        "load_end": [round(v, 2) for v in os.getloadavg()] if load_start else None,
    }
    results["versions"] = versions()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps(results, indent=2, default=float))
    figure(results, out / "scaling.png")
    text = markdown(results)
    if "speed" in results:
        text = text.rstrip() + "\n\n### Speed guards (issue 44, `benchmarks.speed`)\n\n```text\n"
        text += "\n".join(speed.summary(results["speed"])) + "\n```\n"
    write_markdown(out / "results.md", text)
    print(
        f"wrote {out / 'results.md'}, {out / 'results.json'}, {out / 'scaling.png'} in {results['run_seconds']:.0f} s"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
