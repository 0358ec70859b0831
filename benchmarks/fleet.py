"""Fleet benchmark (issue "Product lines"): per-chair recommendations vectorised, on Dask, and as a loop.

    python -m benchmarks.fleet [--quick] [--out benchmarks]

Measures, on example fleets of ``designer fleet --example`` and the base problem problems/indoor-manual.toml:

- the vectorised recommendation (deterministic risk screening over the stock, the front, the rule) of
  1 000, 10 000 and 100 000 chairs in-process (median of repeats);
- the same for 1 000 and 10 000 chairs on a 2-worker ``distributed.LocalCluster`` (cluster start timed
  apart; a warm-up run first);
- a loop of ``designer.recommend`` over a random subset of chairs, extrapolated per chair to the fleet
  sizes (said so in the output), and the ratio loop / vectorised;
- the reported per-chair Monte Carlo P(shimmy) (SE <= 0.1 pp) in-process and on the cluster, timed apart;
- the exact K-median regret curve K = 1…8 on 1 000 chairs.

Writes ``fleet.md`` and ``fleet.json`` into ``--out`` (``benchmarks/`` for the full run, ``benchmarks/quick/``
for ``--quick``).  Targets (issue): 10 000 chairs <= 5 s, 100 000 <= 60 s, >= 100x faster than the loop.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
STOCK = """
[stock]
diameters = ["3 in", "4 in", "5 in", "6 in", "8 in"]
grooves = ["0 in", "0.25 in", "0.5625 in"]
trail_step = "0.25 in"
dampings = ["1.3 N*m/rad", "2 N*m/rad", "3 N*m/rad"]
"""


def _time(fn, repeats):
    times = []
    out = None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), min(times), max(times), out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    from designer.studies.fleet import _fleet as fl  # the benchmark times internals: stock_table, _monte_carlo, ...

    out = Path(args.out) if args.out else ROOT / "benchmarks" / ("quick" if args.quick else "")
    out.mkdir(parents=True, exist_ok=True)
    from designer.model import scatter_of
    from designer.problem import problem_from_toml

    text = (ROOT / "problems" / "indoor-manual.toml").read_text()
    if "[stock]" not in text:  # the 315-caster stock of the tests (5 wheels, 3 grooves, 7 fork holes, 3 washers)
        text += STOCK
    base = problem_from_toml(text, default_name="indoor-manual")
    sizes = (1000, 10000) if args.quick else (1000, 10000, 100000)
    repeats = 1 if args.quick else 3
    started = time.perf_counter()
    load0 = os.getloadavg()
    res: dict = {
        "problem": "indoor-manual",
        "stock": len(fl.stock_table(base)),
        "inprocess": {},
        "dask": {},
        "loop": {},
        "monte_carlo": {},
        "kmedian": {},
    }
    fleets = {n: fl.example_fleet(n, seed=7) for n in sizes}

    for n in sizes:
        reps = 1 if n >= 100000 else repeats
        med, lo, hi, r = _time(lambda: fl.fleet_recommendations(fleets[n], base, monte_carlo=False), reps)
        res["inprocess"][n] = {"median": med, "min": lo, "max": hi, "repeats": reps, "feasible": int(r.feasible.sum())}
        print(f"in-process {n}: {med:.3f} s")

    # loop of designer.recommend over a subset, extrapolated
    from designer.studies.recommend import recommend

    subset = 10 if args.quick else 30
    if recommend is not None:
        rng = np.random.default_rng(1)
        pick = rng.choice(1000, subset, replace=False)
        f = fleets[1000]
        recommend(f.problem(base, int(pick[0])))  # warm-up (imports, builds)
        t = time.perf_counter()
        for i in pick:
            recommend(f.problem(base, int(i)))
        per = (time.perf_counter() - t) / subset
        res["loop"] = {
            "chairs_timed": subset,
            "per_chair": per,
            "extrapolated": {n: per * n for n in sizes},
            "ratio": {n: per * n / res["inprocess"][n]["median"] for n in sizes},
        }
        print(f"loop of designer.recommend: {per * 1000:.1f} ms per chair (over {subset} chairs)")
    else:
        res["loop"] = {"note": "designer.recommend is not available in this checkout"}

    # Monte Carlo per chair, in-process; speeds made distinct (no two chairs share a (caster, speed) pair)
    mc_n = 200 if args.quick else 1000
    sub = fleets[1000].subset(np.arange(mc_n))
    sub.target_speed = sub.target_speed + np.random.default_rng(5).uniform(0, 0.01, mc_n)
    r = fl.fleet_recommendations(sub, base, monte_carlo=False)
    t = time.perf_counter()
    p, se = fl._monte_carlo(None, r.stock, base, r.chairs["choice"], sub.target_speed, chunk=250)
    mc_in = time.perf_counter() - t
    u = scatter_of(base.conditions)
    ok = r.chairs["choice"] >= 0
    distinct = len(np.unique(np.stack([r.chairs["choice"][ok], sub.target_speed[ok]], axis=1), axis=0))
    res["monte_carlo"]["inprocess"] = {
        "chairs": mc_n,
        "distinct": distinct,
        "seconds": mc_in,
        "per_chair": mc_in / mc_n,
        "per_estimate": mc_in / distinct,
        "samples": u.samples,
        "max_se_pp": float(np.nanmax(se) * 100),
    }
    print(f"Monte Carlo in-process {mc_n}: {mc_in:.2f} s, max SE {np.nanmax(se) * 100:.3f} pp")

    from distributed import Client, LocalCluster

    t = time.perf_counter()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    res["dask"]["start"] = time.perf_counter() - t
    try:
        fl.fleet_recommendations(fleets[1000], base, scheduler=client, monte_carlo=False)  # warm-up
        for n in (1000, 10000):
            med, lo, hi, _ = _time(
                lambda: fl.fleet_recommendations(fleets[n], base, scheduler=client, monte_carlo=False), repeats
            )
            res["dask"][n] = {"median": med, "min": lo, "max": hi, "repeats": repeats}
            print(f"dask 2 workers {n}: {med:.3f} s")
        t = time.perf_counter()
        p2, _ = fl._monte_carlo(client, r.stock, base, r.chairs["choice"], sub.target_speed, chunk=250)
        mc_d = time.perf_counter() - t
        assert np.array_equal(p, p2, equal_nan=True)
        res["monte_carlo"]["dask"] = {
            "chairs": mc_n,
            "seconds": mc_d,
            "per_chair": mc_d / mc_n,
            "speedup": mc_in / mc_d,
        }
        print(f"Monte Carlo dask {mc_n}: {mc_d:.2f} s")
    finally:
        client.close()
        cluster.close()

    # K-median regret curve: exact MIP on 1000 chairs, against greedy + swap with the Lagrangian bound;
    # the heuristic path alone on 10 000 chairs
    from designer.studies.fleet import solve_kmedian

    k_max = 4 if args.quick else 8
    r = fl.fleet_recommendations(fleets[1000], base, monte_carlo=False)
    t = time.perf_counter()
    fl.choose_skus(r, 3, k_max=k_max)
    cost, w = r.regret_cost["regret"], fleets[1000].count[r.feasible]
    curve = {}
    for k, s in r.curve.items():
        h = solve_kmedian(cost, w, k, exact_limit=0)
        curve[k] = {
            "regret": s.regret,
            "status": s.status,
            "seconds": s.seconds,
            "heuristic": h.regret,
            "bound": h.lower_bound,
            "heuristic_status": h.status,
            "heuristic_seconds": h.seconds,
        }
    res["kmedian"] = {"chairs": 1000, "seconds": time.perf_counter() - t, "candidates": r.candidates, "curve": curve}
    r = fl.fleet_recommendations(fleets[10000], base, monte_carlo=False)
    t = time.perf_counter()
    fl.choose_skus(r, 3, k_max=k_max)
    res["kmedian_10000"] = {
        "chairs": 10000,
        "seconds": time.perf_counter() - t,
        "candidates": r.candidates,
        "curve": {
            k: {"regret": s.regret, "status": s.status, "seconds": s.seconds, "bound": s.lower_bound}
            for k, s in r.curve.items()
        },
    }
    print(f"K-median curves: {res['kmedian']['seconds']:.1f} s, {res['kmedian_10000']['seconds']:.1f} s")

    res["meta"] = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "machine": f"{platform.platform()}, {os.cpu_count()} CPUs",
        "load_start": load0,
        "load_end": os.getloadavg(),
        "wall": time.perf_counter() - started,
        "quick": args.quick,
    }
    (out / "fleet.json").write_text(json.dumps(res, indent=1, default=float))
    (out / "fleet.md").write_text(_markdown(res))
    print(f"wrote {out / 'fleet.md'}")
    return 0


def _markdown(res) -> str:
    m = res["meta"]
    lines = [
        '# Fleet benchmark: per-chair recommendations (issue "Product lines")',
        "",
        f"Generated by `python -m benchmarks.fleet` on {m['date']}, {m['machine']}; load average at start "
        f"{[round(x, 2) for x in m['load_start']]}, at end {[round(x, 2) for x in m['load_end']]} (a shared "
        f"machine: absolute times are noisy). Base problem {res['problem']}, {res['stock']} stock casters; "
        f"example fleets (`designer fleet --example N`, seed 7).",
        "",
        "## Vectorised recommendation (deterministic risk screening, front, rule)",
        "",
        "| chairs | in-process [s] | 2-worker LocalCluster [s] | loop of designer.recommend [s] | ratio loop / in-process |",
        "|---:|---:|---:|---:|---:|",
    ]
    loop = res["loop"]
    for n, v in res["inprocess"].items():
        d = res["dask"].get(n)
        ext = loop.get("extrapolated", {}).get(n)
        ratio = loop.get("ratio", {}).get(n)
        dask_cell = "–" if d is None else f"{d['median']:.3f}"
        ext_cell = "–" if ext is None else f"{ext:.0f} (extrapolated)"
        ratio_cell = "–" if ratio is None else f"{ratio:,.0f}x"
        lines.append(
            f"| {n:,} | {v['median']:.3f} [{v['min']:.3f}–{v['max']:.3f}] | {dask_cell} | {ext_cell} | {ratio_cell} |"
        )
    lines.append("")
    if "per_chair" in loop:
        lines.append(
            f"The loop was timed over {loop['chairs_timed']} random chairs of the 1 000-chair fleet "
            f"({loop['per_chair'] * 1000:.1f} ms per chair, after one warm-up call) and extrapolated "
            f"linearly to each fleet size."
        )
    else:
        lines.append(f"Loop: {loop.get('note')}.")
    lines.append(f"LocalCluster start: {res['dask']['start']:.1f} s (not included above; a warm-up run first).")
    mc = res["monte_carlo"]
    lines += [
        "",
        "## Reported Monte Carlo P(shimmy) per chair (timed apart)",
        "",
        f"- In-process: {mc['inprocess']['chairs']} chairs in {mc['inprocess']['seconds']:.2f} s: "
        f"{mc['inprocess']['distinct']} distinct (caster, V_target) pairs (speeds jittered so that no two "
        f"chairs share one), "
        f"{mc['inprocess']['per_estimate'] * 1000:.2f} ms per estimate of {mc['inprocess']['samples']} "
        f"samples, largest SE {mc['inprocess']['max_se_pp']:.3f} pp: chairs that get the same caster share one "
        f"seeded draw (docs/fleet.md), so 10 000 chairs take about "
        f"{mc['inprocess']['per_estimate'] * 10000:.0f} s in-process.",
    ]
    if "dask" in mc:
        lines.append(
            f"- 2-worker LocalCluster: {mc['dask']['seconds']:.2f} s for the same chairs "
            f"({mc['dask']['speedup']:.2f}x; identical numbers)."
        )
    k = res["kmedian"]
    lines += [
        "",
        "## K-median: exact MIP (scipy.optimize.milp / HiGHS) against greedy + swap, 1 000 chairs",
        "",
        f"{k['candidates']} useful candidate casters after pruning. Regret = Σ count · (J − own best J) [N·units].",
        "",
        "| K | MIP regret | status | MIP [s] | greedy + swap | Lagrangian bound | status | [s] |",
        "|---:|---:|---|---:|---:|---:|---|---:|",
    ]
    for kk, v in k["curve"].items():
        lines.append(
            f"| {kk} | {v['regret']:.8g} | {v['status']} | {v['seconds']:.2f} | {v['heuristic']:.8g} | "
            f"{v['bound']:.8g} | {v['heuristic_status']} | {v['heuristic_seconds']:.2f} |"
        )
    k = res["kmedian_10000"]
    lines += [
        "",
        f"10 000 chairs ({k['candidates']} useful casters; beyond the MIP's size limit, so greedy + swap "
        f"with the Lagrangian bound): regret curve in {k['seconds']:.1f} s.",
        "",
        "| K | regret | bound | status | [s] |",
        "|---:|---:|---:|---|---:|",
    ]
    for kk, v in k["curve"].items():
        lines.append(f"| {kk} | {v['regret']:.8g} | {v['bound']:.8g} | {v['status']} | {v['seconds']:.2f} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    raise SystemExit(main())
