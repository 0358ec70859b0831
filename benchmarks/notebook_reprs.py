"""Notebook reprs: warm time of ``repr(obj)`` and ``obj._repr_html_()`` for every object that has them.

Issue 17 asks that no repr runs a solver or takes over 50 ms warm.  Each object is built once (solvers run
here, outside the timing), each repr is called once to warm, then ``--repeats`` times; the table gives the
median and the largest time [ms] and the length of the text [characters].  Writes
``benchmarks/notebook_reprs.md`` and ``benchmarks/notebook_reprs.json``.

    python benchmarks/notebook_reprs.py [--repeats 20]
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
import warnings
from pathlib import Path

import designer

HERE = Path(__file__).resolve().parent


def objects() -> dict:
    """The objects of the notebook API for the indoor-manual example (built once, solvers run here)."""
    # late import: optuna and the fleet rule, only for this benchmark
    from designer.studies.explore import explore
    from designer.studies.fleet import example_fleet, fleet  # late import: the fleet rule (benchmark only)

    problem = designer.example_problem("indoor-manual")
    front = designer.pareto_front(problem, points=41)
    rec = designer.recommend(problem)
    return {
        "Problem": problem,
        "Design": rec.design,
        "Front (41 points)": front,
        "Solution": designer.optimise(problem, cross_check=False),
        "Recommendation": rec,
        "SimulationResult": designer.simulate(rec.design, problem.conditions, speed=problem.target_speed),
        "ExploreResult (48 trials)": explore(problem, trials=48, seed=0, compare=False),
        "FleetResult (50 chairs)": fleet(example_fleet(50), problem, monte_carlo=False),
    }


def time_ms(call, repeats: int) -> tuple[float, float, int]:
    """(median, max) wall time [ms] of ``call()`` after one warm call, and the length of its result."""
    text = call()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        call()
        times.append((time.perf_counter() - t0) * 1000)
    return statistics.median(times), max(times), len(text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=20)
    args = parser.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        objs = objects()
    rows = []
    for name, obj in objs.items():
        r = time_ms(lambda: repr(obj), args.repeats)
        h = time_ms(obj._repr_html_, args.repeats) if hasattr(obj, "_repr_html_") else None
        rows.append(
            {
                "object": name,
                "repr_ms": r[0],
                "repr_max_ms": r[1],
                "repr_chars": r[2],
                "html_ms": h[0] if h else None,
                "html_max_ms": h[1] if h else None,
                "html_chars": h[2] if h else None,
            }
        )
    lines = [
        "# Notebook reprs: warm time (benchmarks/notebook_reprs.py)",
        "",
        f"Median and largest of {args.repeats} calls after one warm call; goal: under 50 ms, no solver.",
        "",
        "| object | repr [ms] (max) | repr [chars] | _repr_html_ [ms] (max) | HTML [chars] |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        html = (
            f"{r['html_ms']:.2f} ({r['html_max_ms']:.2f}) | {r['html_chars']}" if r["html_ms"] is not None else "– | –"
        )
        lines.append(f"| {r['object']} | {r['repr_ms']:.3f} ({r['repr_max_ms']:.3f}) | {r['repr_chars']} | {html} |")
    text = "\n".join(lines) + "\n"
    (HERE / "notebook_reprs.md").write_text(text, encoding="utf-8")
    (HERE / "notebook_reprs.json").write_text(json.dumps(rows, indent=2) + "\n", encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
