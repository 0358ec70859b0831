"""Notebook reprs: warm time of ``repr(obj)`` and ``obj._repr_html_()`` for every result record.

Issues 17 and 27 ask that no repr runs a solver or takes over 50 ms warm.  One object of every record class of
the result protocol (:class:`designer.reprs.Record`; tests/test_records.py checks the same list is complete
there) is built once (solvers run here, outside the timing), each repr is called once to warm, then
``--repeats`` times; the table gives the median and the largest time [ms], the length of the text
[characters], and flags a median over the 50 ms goal.  Nothing is asserted: timings depend on the machine
(the load average is printed with them).  Writes ``benchmarks/notebook_reprs.md`` and
``benchmarks/notebook_reprs.json``.

    python benchmarks/notebook_reprs.py [--repeats 20]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
import warnings
from pathlib import Path

import designer

HERE = Path(__file__).resolve().parent
GOAL_MS = 50.0
"""The goal for a warm repr or ``_repr_html_`` (median) [ms]."""


def objects() -> dict:
    """One object of every result record, for the indoor-manual example (built once, solvers run here)."""
    # late import: optuna, the fleet rule, the retrofit and the limit cycles, only for this benchmark
    from designer.model import design_columns, evaluate
    from designer.solvers import Caps, front_solver, solver
    from designer.studies.calibrate import EXAMPLES_DIR, calibrate_file
    from designer.studies.checks import check_eq8
    from designer.studies.dynamics import onset_speed
    from designer.studies.dynamics.limit_cycles import (
        appendix_c_caster,
        caster_dynamics,
        continue_orbits,
        knock_onset_speed,
        simulate_knock,
    )
    from designer.studies.explore import Operators, explore, search_space
    from designer.studies.fleet import example_fleet, fleet
    from designer.studies.front import groove_damper_tradeoff
    from designer.studies.retrofit import fix

    problem = designer.example_problem("indoor-manual")
    front = designer.pareto_front(problem, points=41)
    rec = designer.recommend(problem)
    nlp = solver("casadi-ipopt").optimum(problem)
    fronts = front_solver(problem)
    ends = fronts.ends_designs(problem, fronts.front_ends(problem))
    design_c, conditions_c = appendix_c_caster()
    rolling = caster_dynamics(design_c, conditions_c, 2.0, None)
    branch = continue_orbits(rolling, [0.15, 0.16, 0.17])
    retrofit = fix(problem, "T=1.25in,d=8in,B=0,c=1.3", shimmied_at=1.5)
    fleet_result = fleet(example_fleet(50), problem, skus=3, monte_carlo=False)
    return {
        "Problem": problem,
        "Design": rec.design,
        "Optimum": nlp,
        "Optimum (none)": solver("scipy-slsqp").optimum(problem, caps=Caps(threshold=1.0)),
        "Designs (41 ε)": solver("closed-form").front_designs(problem, [*_between(ends.epsilon, 41)]),
        "NLPResult": nlp.result,
        "GPResult": solver("cvxpy-gp").optimum(problem.nominal()).result,
        "Front (41 points)": front,
        "FrontPoint": front.points[20],
        "TradeoffRow": groove_damper_tradeoff(problem)[12],
        "Solution": designer.optimise(problem, cross_check=True),
        "Recommendation": rec,
        "CandidateValues (41 designs)": evaluate(
            design_columns(front.designs()), problem.conditions, risk=problem.target_speed
        ),
        "SimulationResult": designer.simulate(rec.design, problem.conditions, speed=problem.target_speed),
        "OnsetResult": onset_speed(rec.design, problem.conditions),
        "PeriodicOrbit": branch.orbits[0],
        "Branch (3 orbits)": branch,
        "KnockResult": simulate_knock(rolling, 0.349, record=True),
        "OnsetBracket": knock_onset_speed(rolling, 0.349),
        "ExploreResult (48 trials)": explore(problem, trials=48, seed=0, compare=False),
        "Operators": Operators.for_budget(500),
        "SearchSpace": search_space(designer.example_problem("catalog-retrofit")),
        "CalibrationResult": calibrate_file("turning", EXAMPLES_DIR / "turning_tile.csv"),
        "Check": check_eq8(),
        "FixResult": retrofit,
        "CasterState": retrofit.fixes[0],
        "Change": retrofit.fixes[0].changes[0],
        "Calibration": retrofit.calibration,
        "FleetResult (50 chairs)": fleet_result,
        "KMedianSolution": fleet_result.skus,
    }


def _between(ends, n: int) -> list[float]:
    """``n`` values from the first to the last of ``ends``, evenly spaced."""
    a, b = (float(v) for v in ends)
    return [a + (b - a) * i / (n - 1) for i in range(n)]


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
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    slow = [r["object"] for r in rows if max(r["repr_ms"], r["html_ms"] or 0.0) > GOAL_MS]
    lines = [
        "# Notebook reprs: warm time (benchmarks/notebook_reprs.py)",
        "",
        f"One object of every result record; median and largest of {args.repeats} calls after one warm call; "
        f"goal: median under {GOAL_MS:.0f} ms, no solver (tests/test_records.py runs every repr with the solvers "
        f"patched to raise). Load average at the end: {load} (2 CPUs). Over the goal: {', '.join(slow) or 'none'}.",
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
