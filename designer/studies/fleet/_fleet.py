"""Product lines: a caster for every chair of a fleet, and the fewest part numbers for all of them.

A fleet is a table of chair configurations (``FLEET.csv``, one row per chair: load, sill height, target
speed, swept-radius limit, surface, turning mode, units sold).  The base problem gives everything else:
bounds, stock, risk bound, weights.  For each chair this module computes the recommendation of
``designer.recommend`` vectorised over chairs × stock casters:

1. every stock caster is screened against the chair's own constraints, deterministically:
   the risk bound ``shimmy_speed_quantile >= (1 + margin) V_target`` (V_c of Eq. 7 lowered by the
   scatter of the model, ``docs/fleet.md``), the swept radius T + d/2 <= R_max, and d/h > 2 (Eq. 4A);
2. turning effort F_turn (Eq. 9 with the turning model) and sill force P (Eq. 4A) of every caster for
   every chair, as (chairs × casters) arrays;
3. the buildable front of each chair (non-dominated feasible casters) and the rule of the base problem
   (the knee by default, or a cap on one objective), plus the two alternatives (easiest to turn,
   easiest over the sill).

V_c, its quantile and the swept radius depend on the caster only, so they are computed once per stock
caster; load, sill and speed enter per chair.  The reported P(shimmy) of each chair's caster is a
separate Monte Carlo estimate (:func:`monte_carlo`), timed on its own: that is the part worth a cluster.
With ``scheduler`` (a Dask address or ``"local"``) both run on Dask workers in chunks of chairs; the
client keeps reading, validation, the stock table, the K-median program and the report.

Modules: :mod:`designer.studies.fleet._table` reads the fleet (FLEET.csv, example fleets),
:mod:`designer.studies.fleet._rule` holds the stock table, the vectorised rule and the Monte Carlo,
:mod:`designer.studies.fleet._kmedian` the K-median program; this module runs them over a fleet
(:func:`fleet_recommendations`, :func:`choose_skus`, :func:`fleet`).
"""

from __future__ import annotations

import dataclasses
import datetime
import math
import re
import time
from dataclasses import dataclass, field
import os
import urllib.parse
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

from designer.boundary import Count, Quantity, checked
from designer.errors import InputError
from designer.model import VARIABLES, Design, scatter_of
from designer.parameters import OUTPUTS, VARIABLE_TABLE
from designer.reprs import Key, Record, dataframe

from designer.studies.fleet._kmedian import ColumnDominance, KMedianSolution, kmedian_curve
from designer.problem import Problem, example_problem, problem_argument
from designer.solvers import one_solve_at_a_time
from designer.studies.recommend import rule_text, weights_meaning
from designer.studies.spec import Spec, caster_specs, mc_draws
from designer.studies.fleet._table import Fleet, read_fleet
from designer.studies.fleet._rule import (
    StockTable,
    _mc_task,
    _split,
    evaluate_chairs,
    recommend_chairs,
    stock_table,
)

_LIFETIME = "designer.children"
"""Dask preload module of the local cluster's workers: each ends with its parent process."""

CHUNK = 5000
"""Chairs per chunk of vectorised work (bounds memory: chunk × casters × 8 bytes per array)."""

MAX_K = 50
"""Largest ``k_max`` (``--k-max``): the regret curve's mixed-integer solves grow with K."""

DEFAULT_MAX_REGRET = 2.0
"""Default ``--max-regret`` [N]: the suggested number of part numbers is the smallest K whose mean regret
(J with the part number − the chair's least J, averaged over the units sold) is at most this.  2 N is
about 1.5 % of a typical J = F_turn + P (≈ 140 N on the example fleets) and about the smallest
turning-effort difference the paper measured (a grooved tyre's 10 %: ≈ 1.2 N at the median F_turn);
docs/fleet.md, "How many part numbers"."""


# --------------------------------------------------------------------------- the whole fleet


_FLEET_UNITS = {
    **{p.name: (p.column, p.unit) for p in VARIABLE_TABLE},
    "extrapolated": ("extrapolated", "-"),
    **{
        pre + key: (pre + key + ("_N" if unit == "N" else ""), unit)
        for pre in ("", "sku_")
        for key, unit in (("turning_effort", "N"), ("threshold_force", "N"))
        + tuple((f"shimmy_probability{tail}", "-") for tail in ("", "_mc", "_se"))
    },
    **{key: (key, "N") for key in ("knee_regret_N", "sku_regret_N")},
}
"""fleet.csv column -> (DataFrame column with its SI unit, unit) for :meth:`FleetResult.to_pandas`."""


@dataclass(frozen=True, kw_only=True)
class FleetResult(Record):
    """Per-chair recommendations of a fleet, and the part numbers when asked for.

    Attributes
    ----------
    fleet : the chairs
    stock : the stock table
    problem : the base problem
    chairs : per-chair arrays (:func:`recommend_chairs` fields, plus ``shimmy_probability`` (exact law),
        ``shimmy_probability_mc`` and ``_se`` (its Monte Carlo check))
    skus : the K-median solution for ``--skus K`` (or None), and ``curve`` K -> solution
    timings : wall times [s] per stage
    specs : one :class:`designer.studies.spec.Spec` per part number (in ``skus.chosen``'s order): its acceptance
        limits (trail min and max, groove min, bearing friction moment M_f = c_f θ0 min, measured wheel inertia
        max, each with the others at nominal, from the exact law) for the most demanding of the chairs it serves
        (the fastest V_target, the smallest swept-radius limit), and its P(shimmy) there, exact with the Monte
        Carlo beside it
    tolerance_price : with ``[tolerances]``, the suggested count with them against that of the same fleet without
        them (:func:`_tolerance_price`), else None
    """

    fleet: Fleet
    stock: StockTable
    problem: Problem
    chairs: dict[str, np.ndarray]
    skus: KMedianSolution | None = None
    curve: dict[int, KMedianSolution] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    scheduler: str | None = None
    regret_cost: dict[str, np.ndarray] | None = None
    suggested: dict[str, Any] | None = None
    candidates: int | None = None
    specs: list[Spec] = field(default_factory=list)
    tolerance_price: dict[str, Any] | None = None

    @property
    def feasible(self) -> np.ndarray:
        """Chairs with a recommendation (the others are reported with their reason)."""
        return self.chairs["choice"] >= 0

    def rows(self) -> list[dict[str, Any]]:
        """One dict per chair: the columns of fleet.csv (SI)."""
        ch, cost, out = self.chairs, self.regret_cost, []
        assignment = None if self.skus is None else self.skus.assignment
        sku_index = {} if self.skus is None else {j: i + 1 for i, j in enumerate(self.skus.chosen)}
        position = np.cumsum(self.feasible) - 1
        risks = tuple(f"shimmy_probability{x}" for x in ("", "_mc", "_se"))
        for i, k in enumerate(position):
            j = int(ch["choice"][i])
            row: dict[str, Any] = {
                "name": self.fleet.names[i],
                **(self.stock.design(j) if j >= 0 else dict.fromkeys(VARIABLES)),
            }
            row["extrapolated"] = bool(self.stock.extrapolated[j]) if j >= 0 else None
            for key in ("turning_effort", "threshold_force", *risks):
                row[key] = float(ch[key][i]) if j >= 0 and key in ch else None
            if assignment is not None and cost is not None:
                a = int(assignment[k]) if j >= 0 else -1
                col = int(np.searchsorted(cost["columns"], a))
                row["sku"] = sku_index.get(a) if a >= 0 else None
                for key in ("turning_effort", "threshold_force"):
                    row[f"sku_{key}"] = float(cost[key][k, col]) if a >= 0 else None
                for key in risks:
                    row[f"sku_{key}"] = None if f"sku_{key}" not in ch or a < 0 else float(ch[f"sku_{key}"][i])
                row["knee_regret_N"] = float(cost["knee_regret"][k]) if j >= 0 else None
                row["sku_regret_N"] = float(cost["regret"][k, col]) if a >= 0 else None
            out.append(row | {"status": "ok" if j >= 0 else str(ch["reason"][i])})
        return out

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """Chairs, part numbers, ranges of F_turn and P, the largest P(shimmy) (notebooks; the repr's too)."""
        ok = self.feasible
        f, p = self.chairs["turning_effort"][ok], self.chairs["threshold_force"][ok]
        rows: list[tuple[Any, Any, Any]] = [
            ("chairs (with a caster)", f"{len(self.fleet)} ({int(ok.sum())})", ""),
            ("part numbers (SKUs)", f"{len(self.sku_records())}" if self.skus is not None else "not asked", ""),
        ]
        if ok.any():
            rows += [
                (
                    OUTPUTS[n].label + ": min – max (median)",
                    f"{x.min():.4g} – {x.max():.4g} ({np.median(x):.4g})",
                    OUTPUTS[n].unit,
                )
                for n, x in (("turning_effort", f), ("threshold_force", p))
            ]
        shimmy = self.chairs.get("shimmy_probability")
        if shimmy is not None and ok.any():
            rows.append(("largest P(shimmy)", f"{float(np.max(shimmy[ok])):.2%}", ""))
        return rows

    def _repr_lines(self) -> list[str]:
        """Two lines: chairs, part numbers and the ranges of F_turn and P [N] (``print(fleet_data(...))``: all)."""
        head = ", ".join(
            f"{label.split(':')[0]} {value} {unit}".rstrip() for label, value, unit in self._html_rows()[:2]
        )
        rest = "; ".join(
            f"{label.split(':')[0]} {value.split(' (')[0]} {unit}".rstrip()
            for label, value, unit in self._html_rows()[2:]
        )
        return [f"FleetResult({getattr(self.problem, 'name', '?')!r}: {head})"] + ([f"  {rest}"] if rest else [])

    _keys = (Key("**", lambda r: fleet_data(r)),)
    """The plain data of ``fleet.json`` (:func:`fleet_data`): settings, part numbers, regret curve, per-chair
    rows, distributions; SI units."""

    def to_pandas(self) -> Any:
        """One row per chair, the columns of fleet.csv with SI units in their names (pandas: ``notebook`` extra).

        Columns: ``name``, ``trail_m``, ``diameter_m``, ``groove_m``, ``damping_N_m_per_rad`` (the recommended
        stock caster), ``turning_effort_N``, ``threshold_force_N``, ``shimmy_probability`` [-] and its
        ``_se``, with ``--skus``: ``sku``, ``sku_turning_effort_N``, ``sku_threshold_force_N``,
        ``sku_shimmy_probability`` (exact) with its Monte Carlo ``_mc`` and ``_se``; ``status`` ("ok" or why the chair has no caster; its numbers are then
        missing).  Units also in ``df.attrs["units"]``.
        """
        rows = self.rows()
        columns = [_FLEET_UNITS.get(c, (c, ""))[0] for c in (rows[0] if rows else ["name", "status"])]
        records = [{_FLEET_UNITS.get(k, (k, ""))[0]: v for k, v in r.items()} for r in rows]
        units = {name: unit for name, unit in _FLEET_UNITS.values() if name in columns}
        return dataframe(
            "FleetResult.to_pandas",
            records,
            columns,
            units,
            problem=getattr(self.problem, "name", None),
            skus=len(self.sku_records()) or None,
        )

    def sku_records(self) -> list[dict[str, Any]]:
        """``[{"id", "design", "wheel", "extrapolated", "chairs", "count", "spec"}]`` of the chosen part numbers
        (``extrapolated``: the wheel's d lies outside Table 1's 4–8 in, as on every design record; ``spec``: its
        acceptance limits by part and side with ``units`` beside them and its P(shimmy), exact with the Monte
        Carlo beside it, at the most demanding chair it serves: :meth:`designer.studies.spec.Spec.to_dict`)."""
        if self.skus is None or self.skus.assignment is None:
            return []
        feasible = np.flatnonzero(self.feasible)
        out = []
        for k, j in enumerate(self.skus.chosen):
            mine = feasible[self.skus.assignment == j]
            out.append(
                {
                    "id": k + 1,
                    "design": self.stock.design(j),
                    "wheel": str(self.stock.wheel[j]) or None,
                    "extrapolated": bool(self.stock.extrapolated[j]),
                    "chairs": len(mine),
                    "count": int(self.fleet.count[mine].sum()),
                }
                | ({"spec": self.specs[k].to_dict()} if k < len(self.specs) else {})
            )
        return out


def fleet_recommendations(  # long: its docstring documents every argument; the body builds the record once
    fleet: Fleet,
    problem: Problem,
    skus: int | str | None = None,
    k_max: int | None = None,
    scheduler: Any = None,
    monte_carlo: bool = True,
    chunk: int = CHUNK,
    time_limit: float = 120.0,
    max_regret: float = DEFAULT_MAX_REGRET,
) -> FleetResult:
    """Recommend a caster for every chair of ``fleet`` and, with ``skus``, choose K part numbers.

    Parameters
    ----------
    fleet : the chairs (:func:`read_fleet` or :func:`example_fleet`)
    problem : the base problem (bounds, stock, risk, weights)
    skus : K, the number of part numbers; ``"auto"``: the suggested count (:func:`suggest_skus`); None:
        per-chair recommendations only
    k_max : regret curve for K = 1 … k_max (default max(K, 8), and on until the mean regret is within
        ``max_regret``; at most the number of useful casters)
    scheduler : None (in-process), a Dask scheduler address ``"tcp://host:8786"``, ``"local"`` (a
        2-worker LocalCluster), or a ``distributed.Client``
    monte_carlo : also estimate each chair's P(shimmy) (the reported number; the expensive part)
    chunk : chairs per task
    time_limit : per-K limit of the mixed-integer solve [s]
    max_regret : the suggested count's threshold on the mean regret [N] (:data:`DEFAULT_MAX_REGRET`)

    Returns
    -------
    FleetResult
    """
    if skus is not None and skus != "auto":
        if isinstance(skus, bool) or not isinstance(skus, (int, np.integer)) or skus < 1:
            raise InputError(f"--skus {skus!r}: expected a whole number of part numbers, 1 or more")
    if not (isinstance(max_regret, (int, float)) and math.isfinite(max_regret) and max_regret >= 0):
        raise InputError(f"--max-regret {max_regret!r}: expected a mean regret in N, 0 or more")
    if k_max is not None and not 1 <= k_max <= MAX_K:
        raise InputError(f"--k-max {k_max}: expected 1 to {MAX_K}")
    timings: dict[str, float] = {}
    start = time.perf_counter()
    stock = stock_table(problem)
    if isinstance(skus, (int, np.integer)) and skus > len(stock):
        raise InputError(f"--skus {skus}: larger than the stock ({len(stock)} casters); choose at most {len(stock)}")
    timings["stock"] = time.perf_counter() - start

    client, own = _client(scheduler)
    try:
        start = time.perf_counter()
        chairs = _recommend_all(client, fleet, stock, problem, chunk)
        timings["recommend"] = time.perf_counter() - start
        if monte_carlo:
            start = time.perf_counter()
            risk = _monte_carlo(
                client, stock, problem, chairs["choice"], fleet.target_speed, chunk=max(50, chunk // 20)
            )
            chairs["shimmy_probability"], chairs["shimmy_probability_mc"], chairs["shimmy_probability_se"] = risk
            timings["monte_carlo"] = time.perf_counter() - start
        # the record is built once its columns are complete, and each later step returns a new one
        result = FleetResult(
            fleet=fleet,
            stock=stock,
            problem=problem,
            chairs=chairs,
            timings=timings,
            scheduler=None if client is None else str(client.scheduler_info().get("address", "")),
        )
        if skus is not None:
            start = time.perf_counter()
            result = choose_skus(result, skus, k_max=k_max, time_limit=time_limit, max_regret=max_regret)
            timings["skus"] = time.perf_counter() - start
            if problem.tolerances is not None and result.suggested is not None and result.suggested["within"]:
                start = time.perf_counter()
                price = _tolerance_price(result, client, chunk, time_limit, max_regret)
                result = dataclasses.replace(result, tolerance_price=price)
                timings["without_tolerances"] = time.perf_counter() - start
            if monte_carlo and result.skus is not None and result.skus.assignment is not None:
                # P(shimmy) of each chair with the part number the K-median assigned it (NaN for a chair without)
                start = time.perf_counter()
                assigned = np.full(len(fleet), -1)
                assigned[result.feasible] = result.skus.assignment
                risk = _monte_carlo(client, stock, problem, assigned, fleet.target_speed, chunk=max(50, chunk // 20))
                keys = ("sku_shimmy_probability", "sku_shimmy_probability_mc", "sku_shimmy_probability_se")
                result = dataclasses.replace(result, chairs={**result.chairs, **dict(zip(keys, risk))})
                timings["sku_monte_carlo"] = time.perf_counter() - start
            if result.skus is not None and result.skus.assignment is not None:
                start = time.perf_counter()
                result = dataclasses.replace(result, specs=sku_specs(result))
                timings["specs"] = time.perf_counter() - start
            result = dataclasses.replace(result, timings=timings)
    finally:
        if own:
            cluster = getattr(client, "cluster", None)  # a local cluster ends with its client
            client.close()
            if cluster is not None:
                cluster.close()
    return result


def _tolerance_price(
    result: FleetResult, client: Any, chunk: int, time_limit: float, max_regret: float
) -> dict[str, Any]:
    """The price of the tolerances in part numbers: the suggested count with them against the suggested count of
    the same fleet and stock without them (the nominal screen, the K-median solved for K = 1, 2, … only until the
    threshold is met: no Monte Carlo, no specs), and the sentence that states it."""
    free = dataclasses.replace(result, problem=result.problem.replace(tolerances=None))
    rows = np.flatnonzero(_recommend_all(client, result.fleet, result.stock, free.problem, chunk)["choice"] >= 0)
    units = result.fleet.count[rows]
    curve = kmedian_curve(_regret_matrix(free, rows)["regret"], units, [1], time_limit, float(units.sum()) * max_regret)
    held, without = (result.suggested or {})["count"], suggest_skus(curve, float(units.sum()), max_regret)["count"]
    n = held - without
    cost = f"cost {n} part number{'s' * (n != 1)}" if n > 0 else "cost no part number"
    cost = f"need {-n} part number{'s' * (n != -1)} fewer" if n < 0 else cost
    why = " (regret is then counted from each chair's best caster that holds)" if n < 0 else ""
    text = f"The tolerances {cost}: {held} with them, {without} without{why}."
    return {"part_numbers": n, "with_tolerances": held, "without_tolerances": without, "sentence": text}


def _recommend_all(client: Any, fleet: Fleet, stock: StockTable, problem: Problem, chunk: int) -> dict[str, np.ndarray]:
    """Every chair's recommendation (:func:`recommend_chairs`) in chunks of ``chunk`` chairs, in this process
    (``client`` None) or as Dask tasks; the per-chair arrays joined in fleet order."""
    parts = _split(fleet, chunk)
    if client is None:
        results = [recommend_chairs(arrays, stock, problem) for _, arrays in parts]
    else:
        stock_f = client.scatter(stock, broadcast=True, hash=False)
        problem_f = client.scatter(problem, broadcast=True, hash=False)
        futures = [client.submit(recommend_chairs, arrays, stock_f, problem_f, pure=False) for _, arrays in parts]
        results = client.gather(futures)
    return {k: np.concatenate([r[k] for r in results]) for k in results[0]}


def sku_specs(result: FleetResult) -> list[Spec]:
    """The :class:`~designer.studies.spec.Spec` of each part number (``result.skus.chosen``'s order): the
    acceptance limits of its parts, each with the others at nominal, from the exact law, for the most demanding
    of the chairs it serves (the fastest V_target sets the risk limits, the smallest swept-radius limit the
    trail's largest: a part within them serves every one of those chairs), and its P(shimmy) at that speed,
    exact with the Monte Carlo beside it (the fleet's risk law, samples and seed)."""
    sku = result.skus
    if sku is None or sku.assignment is None:
        return []
    problem, stock, fleet = result.problem, result.stock, result.fleet
    u, slip = scatter_of(problem.conditions), problem.conditions.slip_coefficient
    feasible = np.flatnonzero(result.feasible)
    problems = []
    for j in sku.chosen:
        mine = feasible[sku.assignment == j]
        radius = fleet.swept_radius_max[mine]
        radius = radius[np.isfinite(radius)]
        problems.append(
            problem.replace(
                target_speed=float(np.max(fleet.target_speed[mine])),
                swept_radius_max=float(np.min(radius)) if radius.size else None,
            )
        )
    chosen = np.asarray(sku.chosen, int)
    designs = [Design(**stock.design(j)) for j in chosen]
    inertias, flags = [float(x) for x in stock.inertia[chosen]], [bool(x) for x in stock.measured[chosen]]
    speeds = np.array([p.target_speed for p in problems])
    risk = _mc_task(np.array([d.as_array() for d in designs]), np.array(inertias), speeds, slip, u, np.array(flags))
    monte_carlo = [(float(p_mc), float(se), mc_draws(p_mc, se), u.seed) for _, p_mc, se in risk]
    # every part number's acceptance limits searched together
    return caster_specs(problems, designs, inertias, flags, monte_carlo)


def _monte_carlo(
    client: Any, stock: StockTable, problem: Problem, choice: np.ndarray, speeds: npt.ArrayLike, chunk: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reported P(shimmy) at each chair's V_target for its caster: the exact law's, the Monte Carlo's beside it
    and its SE; NaN where there is none."""
    u = scatter_of(problem.conditions)
    slip = problem.conditions.slip_coefficient
    rows = np.flatnonzero(choice >= 0)
    out = np.full((3, len(choice)), np.nan)
    if not len(rows):
        return out[0], out[1], out[2]
    # The estimate is a deterministic function of (caster, speed) (its own fixed seed), so chairs that share
    # both share one estimate: each distinct pair is sampled once.
    pairs, inverse = np.unique(
        np.stack([choice[rows].astype(float), np.asarray(speeds, float)[rows]], axis=1), axis=0, return_inverse=True
    )
    which = pairs[:, 0].astype(int)
    designs = np.stack([stock.trail, stock.diameter, stock.groove, stock.damping], axis=1)[which]
    inertia = stock.inertia[which]
    measured = np.asarray(stock.measured, bool)[which]
    sp = pairs[:, 1]
    if client is not None:  # enough tasks to keep every worker busy
        chunk = max(1, min(chunk, -(-len(sp) // (8 * max(1, len(client.scheduler_info().get("workers", {})))))))
    pieces = [slice(a, a + chunk) for a in range(0, len(sp), chunk)]
    if client is None:
        outs = [_mc_task(designs[s], inertia[s], sp[s], slip, u, measured[s]) for s in pieces]
    else:
        futures = [
            client.submit(_mc_task, designs[s], inertia[s], sp[s], slip, u, measured[s], pure=False) for s in pieces
        ]
        outs = client.gather(futures)
    out[:, rows] = np.concatenate(outs)[np.ravel(inverse)].T
    return out[0], out[1], out[2]


def choose_skus(
    result: FleetResult,
    k: int | str,
    k_max: int | None = None,
    time_limit: float = 120.0,
    max_regret: float = DEFAULT_MAX_REGRET,
) -> FleetResult:
    """Solve the K-median over the stock for the feasible chairs: ``result`` with ``skus``, the regret curve
    and the suggested count filled in (a new record: records do not change).

    Regret of chair i with caster j: J_ij − min_j' J_ij' over the chair's own allowed stock (never
    negative), J = w_turn F_turn + w_threshold P with the base problem's weights [N]; +inf where caster j
    breaks the chair's own risk bound, swept-radius limit or sill.  Infeasible chairs are left out (and
    reported per row).  Every K of the curve is solved to proven optimality
    (:mod:`designer.studies.fleet._kmedian`); ``k="auto"`` takes the suggested count (:func:`suggest_skus`).
    """
    fleet = result.fleet
    rows = np.flatnonzero(result.feasible)
    if not len(rows):
        raise InputError("--skus: no chair of the fleet has a feasible stock caster, nothing to choose")
    regret_cost = _regret_matrix(result, rows)
    regret_cost["knee_regret"] = np.maximum(0.0, result.chairs["objective"][rows] - regret_cost["least_objective"])
    cost, columns = regret_cost["regret"], regret_cost["columns"]
    weights = fleet.count[rows]
    asked = None if k == "auto" else int(k)
    # without --k-max the curve goes on past 8 until the threshold is met, so the suggestion always exists
    until = float(weights.sum()) * max_regret if k_max is None else None
    k_max = max(asked or 1, 8) if k_max is None else max(asked or 1, k_max)
    curve = kmedian_curve(cost, weights, range(1, k_max + 1), time_limit=time_limit, until=until)
    useful = curve[1].candidates
    kept = {  # back to stock indices
        kk: dataclasses.replace(
            s,
            chosen=[int(columns[j]) for j in s.chosen],
            assignment=None if s.assignment is None else columns[s.assignment],
        )
        for kk, s in curve.items()
        if kk <= max(useful, asked or 1)
    }
    suggested = suggest_skus(kept, float(weights.sum()), max_regret)
    return dataclasses.replace(
        result,
        regret_cost=regret_cost,
        curve=kept,
        candidates=useful,
        suggested=suggested,
        skus=kept[asked if asked is not None else suggested["count"]],
    )


def suggest_skus(
    curve: dict[int, KMedianSolution], units: float, max_regret: float = DEFAULT_MAX_REGRET
) -> dict[str, Any]:
    """The suggested number of part numbers: the smallest K whose mean regret is at most ``max_regret``.

    Parameters
    ----------
    curve : K -> :class:`designer.studies.fleet._kmedian.KMedianSolution` (K = 1 … k_max)
    units : units sold of the served chairs (Σ count); the mean regret is the total regret / units [N]
    max_regret : threshold on the mean regret [N]

    Returns
    -------
    dict: ``count`` (K; the largest K of the curve when none is within, with ``within`` False),
    ``mean_regret_N`` (of that K), ``max_regret_N``, ``within``, ``rule`` (the rule in words).
    """
    rule = (
        f"the fewest part numbers whose mean regret (J with the part number − the chair's least J over its "
        f"allowed stock, averaged over the units sold) is at most {max_regret:g} N"
    )
    units = units or 1.0
    mean = {k: s.regret / units for k, s in sorted(curve.items()) if s.status != "infeasible"}
    within = [k for k, value in mean.items() if value <= max_regret]
    count = within[0] if within else max(mean, default=max(curve))
    return {
        "count": count,
        "rule": rule,
        "mean_regret_N": mean.get(count),
        "max_regret_N": max_regret,
        "within": bool(within),
    }


def _regret_matrix(result: FleetResult, rows: np.ndarray) -> dict[str, np.ndarray]:
    """Regret, F_turn and P of the chairs ``rows`` (feasible) with the casters that can matter for a K-median.

    Two passes over chunks of :data:`CHUNK` chairs: the first evaluates J of every stock caster and keeps
    only which casters dominate which (:class:`designer.studies.fleet._kmedian.ColumnDominance`; memory of
    one chunk), the second evaluates the undominated casters for every chair: chairs × useful casters in
    memory, not chairs × stock.
    """
    fleet, stock, problem = result.fleet, result.stock, result.problem
    arrays = fleet.arrays()
    parts = [rows[a : a + CHUNK] for a in range(0, len(rows), CHUNK)]

    def evaluate(part: np.ndarray, table: StockTable) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        ev = evaluate_chairs({key: v[part] for key, v in arrays.items()}, table, problem)
        return np.where(ev["feasible"], ev["objective"], np.inf), ev["turning_effort"], ev["threshold_force"]

    dominance = ColumnDominance(len(stock))
    for part in parts:
        dominance.add(evaluate(part, stock)[0])
    columns = dominance.undominated()
    per_caster = {f.name: getattr(stock, f.name) for f in dataclasses.fields(stock)}  # every per-caster array
    table = dataclasses.replace(
        stock, **{k: v[columns] for k, v in per_caster.items() if isinstance(v, np.ndarray) and len(v) == len(stock)}
    )
    j, f, p = (np.concatenate(x) for x in zip(*(evaluate(part, table) for part in parts)))
    least = j.min(axis=1)
    j -= least[:, None]
    return {"columns": columns, "turning_effort": f, "threshold_force": p, "regret": j, "least_objective": least}


def _client(scheduler: Any) -> tuple[Any, bool]:
    """(client, owned) for a scheduler address, "local", a Client, or None (in-process)."""
    if scheduler is None:
        return None, False
    try:
        # dask is optional (the `fleet` extra): imported only when a scheduler is asked for
        from distributed import Client, LocalCluster
    except ImportError:
        raise InputError(
            "--scheduler: needs dask[distributed]; install it with pip install 'caster-designer[fleet]'"
        ) from None
    if isinstance(scheduler, Client):
        return scheduler, False
    client: Any = Client  # distributed's own types: untyped calls
    if scheduler == "local":
        cluster: Any = LocalCluster
        # every worker process ends with the process that started it (designer.children; the nannies are
        # objects of this process)
        local = cluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            preload=[_LIFETIME],
        )
        return client(local), True
    _check_scheduler(scheduler)
    try:
        return client(scheduler, timeout="10s"), True
    except (OSError, TimeoutError) as exc:
        raise InputError(
            f"--scheduler {scheduler}: cannot reach the scheduler ({type(exc).__name__}: {exc}); "
            f"start one with `dask scheduler` (docs/fleet.md)"
        ) from None
    except (ValueError, TypeError) as exc:  # an address distributed's own parser refuses
        raise InputError(f"--scheduler {scheduler!r}: not a scheduler address ({exc})") from None


def _check_scheduler(scheduler: Any) -> None:
    """InputError (one line) unless ``scheduler`` is a scheduler address: ``tcp://host:port`` (also ``tls://``,
    ``ucx://``) with a host and a port from 1 to 65535 and nothing after them, or ``inproc://name``."""
    usage = "expected an address such as tcp://host:8786, or 'local'"
    if not isinstance(scheduler, str) or not re.match(r"^(tcp|tls|inproc|ucx)://\S+$", scheduler):
        raise InputError(f"--scheduler {scheduler!r}: {usage}")
    if scheduler.startswith("inproc://"):
        return
    try:
        parts = urllib.parse.urlsplit(scheduler)
        port = parts.port
    except ValueError as exc:  # "Invalid IPv6 URL", a port out of range or not a number
        raise InputError(f"--scheduler {scheduler!r}: not an address ({exc}); {usage}") from None
    if not parts.hostname or port is None or port == 0 or parts.path not in ("", "/") or parts.query or parts.fragment:
        raise InputError(f"--scheduler {scheduler!r}: {usage} (a host and a port, nothing after them)")


def fleet_data(result: FleetResult) -> dict[str, Any]:
    """Plain data of a fleet run (fleet.json; what the report renders): settings, part numbers, regret curve,
    per-chair rows, distributions.  SI units; J uses the base problem's weights.  The date and times are in
    :func:`fleet_run` (run.json)."""
    problem = result.problem
    risk = problem.risk
    u = scatter_of(problem.conditions)
    ok = result.feasible
    rows = result.rows()
    served_units = float(result.fleet.count[ok].sum()) or 1.0
    ch, choice = result.chairs, result.chairs["choice"][ok]
    # per-chair arrays of the own recommendations (chairs with a caster) for the report's figure
    dist: dict[str, Any] = {
        **{name: getattr(result.stock, name)[choice] for name in VARIABLES},
        **{key: ch[key][ok] for key in ("turning_effort", "threshold_force", "shimmy_probability") if key in ch},
    }
    sku = result.skus
    solved = sku is not None and sku.status != "infeasible"
    w = tuple(float(x) for x in problem.weights)
    return {
        "fleet": result.fleet.source,
        "length_units": problem.units,
        "chairs": len(result.fleet),
        "feasible_chairs": int(ok.sum()),
        "units": int(result.fleet.count.sum()),
        "served_units": int(result.fleet.count[ok].sum()),
        "problem": problem.name,
        "weights": list(w),
        "objective": weights_meaning(w),
        "regret_definition": "regret of a chair = J with its assigned part number − the chair's least J, the "
        "least J over the stock casters allowed for that chair (never negative); the part numbers minimise "
        "the sum over the units sold",
        "regret_unit": "N",
        "own_recommendation": _own_recommendation(result),
        "risk": None if risk is None else {"probability": risk.probability, "margin": problem.margin},
        "monte_carlo": {"samples": u.samples, "seed": u.seed},
        "rule": rule_text(problem),
        "stock": {
            "casters": len(result.stock),
            "note": result.stock.note,
            "useful_for_skus": getattr(result, "candidates", None),
        },
        "skus": result.sku_records(),
        "k": None if sku is None else sku.k,
        "total_regret_N": sku.regret if sku is not None and solved else None,
        "mean_regret_N": sku.regret / served_units if sku is not None and solved else None,
        "worst_regret_N": _worst_regret(result, sku) if solved else None,
        "sku_status": None if sku is None else sku.status,
        "sku_proof": None if sku is None else sku.method,
        "suggested_skus": result.suggested,
        "tolerance_price": result.tolerance_price,
        "answer": _answer(result)[0],
        "answer_detail": _answer(result)[1],
        "regret_curve": [  # per K the total, mean (over the served units) and worst regret [N], proof
            {
                "k": k,
                "total_regret_N": s.regret if s.status != "infeasible" else None,
                "mean_regret_N": s.regret / served_units if s.status != "infeasible" else None,
                "worst_regret_N": _worst_regret(result, s),
                "status": s.status,
                "lower_bound_N": s.lower_bound,
                "gap_N": s.gap,
                "method": s.method,
                "chosen": s.chosen,
            }
            for k, s in sorted(result.curve.items())
        ],
        "rows": rows,
        "distributions": {k: np.asarray(v, float) for k, v in dist.items()},
        "alpha": None if risk is None else risk.probability,
    }


def fleet_run(result: FleetResult) -> dict[str, Any]:
    """What a rerun changes (kept out of :func:`fleet_data`, so the same fleet gives the same fleet.json and
    report): the date, the wall seconds per stage and per K of the regret curve, the Dask scheduler."""
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "timings": dict(result.timings),
        "curve_seconds": {str(k): s.seconds for k, s in sorted(result.curve.items())},
        "scheduler": result.scheduler,
    }


def _worst_regret(result: FleetResult, solution: KMedianSolution | None) -> float | None:
    """The largest regret of one chair with the part number it is assigned [N] (None if infeasible)."""
    if solution is None or solution.assignment is None or result.regret_cost is None:
        return None
    cost = result.regret_cost
    col = np.searchsorted(cost["columns"], solution.assignment)
    return float(cost["regret"][np.arange(len(col)), col].max())


def _own_recommendation(result: FleetResult) -> dict[str, Any]:
    """What "own recommendation" means, and how the part numbers compare with it on J."""
    out: dict[str, Any] = {
        "meaning": "Each chair's own recommendation is the caster designer.recommend picks for that chair "
        "alone: the base problem's rule on the chair's buildable front (by default its knee, the balance of "
        "F_turn and P in the front's own range). It is not the chair's least J: regret is measured against "
        "the least J, so a part number can be better on J than the chair's own recommendation.",
    }
    cost, sku = result.regret_cost, result.skus
    if cost is None or sku is None or sku.assignment is None:
        return out
    col = np.searchsorted(cost["columns"], sku.assignment)
    regret = cost["regret"][np.arange(len(col)), col]
    knee = cost["knee_regret"]
    tol = 1e-9 * np.maximum(1.0, cost["least_objective"])
    out.update(
        {
            "recommendation_is_least_J": int(np.sum(knee <= tol)),
            "part_number_better_on_J": int(np.sum(regret < knee - tol)),
            "part_number_is_the_recommendation": int(
                np.sum(sku.assignment == result.chairs["choice"][result.feasible])
            ),
            "mean_recommendation_regret_N": float(
                np.dot(result.fleet.count[result.feasible], knee) / max(1, result.fleet.count[result.feasible].sum())
            ),
        }
    )
    return out


def _answer(result: FleetResult) -> tuple[str | None, str | None]:
    """(first line, second line) of the output: how many part numbers serve how many chairs within what mean
    regret, in at most 80 characters for fleets up to 10 000 chairs; then the numbers behind it."""
    s = result.suggested
    if s is None:
        return None, None
    n_ok, n = int(result.feasible.sum()), len(result.fleet)
    chairs = f"all {n} chairs" if n_ok == n else f"the {n_ok} of {n} chairs that have a caster"
    parts = "part number" if s["count"] == 1 else "part numbers"
    if s["mean_regret_N"] is None:
        return f"No {s['count']} stock casters serve {chairs}", "the fewest that do are more: see the regret curve"
    sol = result.curve[s["count"]]
    w = tuple(float(x) for x in result.problem.weights)
    j = "F_turn + P" if w == (1.0, 1.0) else f"{w[0]:g} F_turn + {w[1]:g} P"
    detail = (
        f"mean regret {s['mean_regret_N']:.2f} N per unit sold against each chair's least J = {j}; worst "
        f"chair {_worst_regret(result, sol):.2f} N; {sol.status} ({sol.method})"
    )
    if s["within"]:
        return (
            f"{s['count']} {parts} serve {chairs} within {s['max_regret_N']:g} N of their best caster on average",
            detail,
        )
    return (
        f"No K ≤ {s['count']} keeps the mean regret within {s['max_regret_N']:g} N (raise --k-max or --max-regret)",
        f"{s['count']} {parts} serve {chairs}: " + detail,
    )


@checked(
    skus=Count(1, optional=True, what="part numbers", words=("auto",)),
    k_max=Count(1, MAX_K, optional=True, what="part numbers on the regret curve"),
    max_regret=Quantity("force"),
)
@one_solve_at_a_time
def fleet(
    chairs: Fleet | str | Path,
    problem: Problem | str | Path | None = None,
    skus: int | str | None = None,
    scheduler: Any = None,
    monte_carlo: bool = True,
    k_max: int | None = None,
    max_regret: float = DEFAULT_MAX_REGRET,
) -> FleetResult:
    """``designer.fleet``: per-chair recommendations of a fleet and, with ``skus``, K part numbers.

    Parameters
    ----------
    chairs : a FLEET.csv path or a :class:`Fleet` (e.g. ``example_fleet(1000)``)
    problem : the base problem (a :class:`designer.problem.Problem` or a TOML path; default the shipped
        ``designer.example_problem("indoor-manual")``, from any folder)
    skus, scheduler, monte_carlo, k_max, max_regret : as :func:`fleet_recommendations` (``skus="auto"``:
        the suggested count)

    Returns
    -------
    FleetResult; ``fleet_data(result)`` gives the plain data of ``--json``.
    """

    if not isinstance(chairs, (Fleet, str, os.PathLike)):
        raise InputError(f"chairs = {chairs!r}: expected a Fleet or a fleet CSV file's path")
    if not isinstance(chairs, Fleet):
        chairs = read_fleet(chairs)
    problem = example_problem("indoor-manual") if problem is None else problem_argument(problem)
    return fleet_recommendations(
        chairs, problem, skus=skus, k_max=k_max, scheduler=scheduler, monte_carlo=monte_carlo, max_regret=max_regret
    )
