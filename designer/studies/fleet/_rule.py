"""The stock table and the vectorised rule of a fleet: every chair x every stock caster at once.

Part of :mod:`designer.studies.fleet._fleet`: the stock casters as arrays with
V_c and its quantile (:func:`stock_table`), F_turn, P and feasibility of every caster for every chair
(:func:`evaluate_chairs`), the buildable front and the rule per chair (:func:`recommend_chairs`), and the
Monte Carlo P(shimmy) of the chosen casters (:func:`_mc_task`).  Every number of a caster comes from the
model's evaluator (:func:`designer.model.evaluate`, :func:`designer.model.shimmy_probability`).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from designer.data.paper import INCH
from designer.display import shown
from designer.errors import ProblemError
from designer.model import VARIABLES, evaluate, shimmy_probability
from designer.physics.acceptance import LawCaster, exact_probability
from designer.physics.turning import MODES, SURFACES
from designer.problem import Stock
from designer.studies.recommend import CandidateTable, select_rows, stock_candidates
from designer.studies.spec import tolerance_corners

from designer.studies.fleet._table import Fleet


# --------------------------------------------------------------------------- the stock


@dataclass
class StockTable(CandidateTable):
    """Every stock caster of the base problem as arrays (one entry per combination), SI: the recommendation's
    :class:`~designer.studies.recommend.CandidateTable` with every variable discrete, and its speeds.

    Attributes
    ----------
    trail, diameter, groove, damping : the design [m, m, m, N·m/rad]
    inertia : I_w of the wheel [kg·m²]
    measured : whether that I_w was measured (else the wheel is known by its diameter: the risk law applies
        Table 1's prediction interval)
    extrapolated : d outside Table 1's 4–8 in (the inertia fit and Eq. 7's check extrapolate)
    wheel : wheel name per caster (catalogue) or ""
    critical_speed : V_c, Eq. 7 [m/s]
    confident_speed : what the risk bound compares with (1 + margin) V_target: the speed reached with
        probability 1 − α (``shimmy_speed_quantile``), or V_c itself when the risk bound is off [m/s]
    swept_radius : T + d/2 [m]
    note : where the stock comes from
    """

    trail: np.ndarray
    diameter: np.ndarray
    groove: np.ndarray
    damping: np.ndarray
    inertia: np.ndarray
    measured: np.ndarray = field(default=None)
    critical_speed: np.ndarray = field(default=None)
    confident_speed: np.ndarray = field(default=None)
    swept_radius: np.ndarray = field(default=None)
    extrapolated: np.ndarray = field(default=None)


DEFAULT_STOCK = {
    "diameters": [3.0, 4.0, 5.0, 6.0, 8.0],
    "grooves": [0.0, 0.25, 0.5625],
    "trail_step": 0.25,
    "dampings": [1.3, 2.0, 3.0],
}
"""Stock used when the base problem declares none [in, in, in, N·m/rad]: common caster sizes, the
tyre profiles of the paper (plain, 1/4 in, 9/16 in groove), fork holes every 1/4 in, bare bearing and
two friction washers.  Values outside the problem's bounds are left out."""


def stock_table(problem) -> StockTable:
    """All stock combinations of the base problem, with V_c, its quantile and the swept radius.

    The enumeration is :func:`designer.studies.recommend.stock_candidates` (the single owner): the
    problem's ``[stock]`` when it declares one, otherwise :data:`DEFAULT_STOCK` within its bounds (the
    table's ``note`` says so).  Every variable must be discrete: a part number is a design tuple.
    """

    if getattr(problem, "stock", None) is not None:
        cand = stock_candidates(problem)
        note = "the base problem's [stock]"
    else:
        cand = stock_candidates(problem, _default_stock(problem))
        note = "the base problem has no [stock]; default stock within its bounds (docs/fleet.md)"
    stock_key = {"trail": "trail_step", "diameter": "diameters", "groove": "grooves", "damping": "dampings"}
    for key in ("trail", "diameter", "groove", "damping"):
        if getattr(cand, key) is None:
            raise ProblemError(
                f"{problem.source or problem.name}: stock.{stock_key[key]}: missing, so {key} stays "
                f"continuous; a fleet's part numbers are stock casters, so list every variable in "
                f"[stock] (docs/fleet.md)"
            )
    table = StockTable(
        **vars(cand)
        | {"note": note, "inertia": np.asarray(cand.inertia, float), "measured": np.asarray(cand.measured, bool)}
    )
    values = evaluate(
        {name: getattr(table, name) for name in VARIABLES},
        problem.conditions,
        inertia=table.inertia,
        measured=table.measured,
    )
    for key in ("critical_speed", "confident_speed", "swept_radius"):
        setattr(table, key, getattr(values, key))
    table.extrapolated = np.asarray(values.extrapolated, bool)
    tol = getattr(problem, "tolerances", None)
    if tol is not None:
        # a stock caster serves a chair only if it holds at the worst corner of the stated tolerances (trail − ±,
        # groove − ±, M_f − its fraction, the diameter at either edge, a measured wheel at the accepted I_w): its
        # confident_speed becomes the least over its nominal and its corners (the risk bound's V_q, a conservative
        # screen used to choose, never printed) and its swept radius T + d/2 grows by ± trail + ± d/2
        speeds = [np.asarray(table.confident_speed, float)]
        for corner in tolerance_corners(problem, {k: getattr(table, k) for k in (*VARIABLES, "inertia", "measured")}):
            with warnings.catch_warnings(action="ignore", category=UserWarning):
                at = evaluate(
                    {k: corner[k] for k in VARIABLES},
                    problem.conditions,
                    inertia=corner["inertia"],
                    measured=corner["measured"],
                )
            speeds.append(np.asarray(at.confident_speed, float))
        table.confident_speed = np.minimum.reduce(speeds)
        table.swept_radius = np.asarray(table.swept_radius, float) + (tol.trail or 0.0) + (tol.diameter or 0.0) / 2
    return table


def _default_stock(problem):
    """:data:`DEFAULT_STOCK` within the problem's bounds, as a :class:`designer.problem.Stock`."""

    b = problem.bounds

    def within(values, name):
        lo, hi = b[name].low, b[name].high
        kept = [v for v in values if lo - 1e-12 <= v <= hi + 1e-12]
        return tuple(kept or [lo])

    step = DEFAULT_STOCK["trail_step"] * INCH
    lo, hi = b["trail"].low, b["trail"].high
    trails = tuple(lo + step * np.arange(int(math.floor((hi - lo) / step + 1e-9)) + 1))
    return Stock(
        diameters=None
        if problem.wheels or b["diameter"].fixed
        else within([v * INCH for v in DEFAULT_STOCK["diameters"]], "diameter"),
        grooves=within([v * INCH for v in DEFAULT_STOCK["grooves"]], "groove"),
        trail_step=step,
        trails=trails,
        dampings=within(DEFAULT_STOCK["dampings"], "damping"),
    )


# --------------------------------------------------------------------------- vectorised recommendation


def evaluate_chairs(chairs: dict, stock: StockTable, problem) -> dict:
    """Turning effort, sill force and feasibility of every stock caster for every chair (chairs × casters).

    Parameters
    ----------
    chairs : per-chair arrays ``load`` [N], ``threshold_height`` [m], ``target_speed`` [m/s],
        ``swept_radius_max`` [m], ``surface``, ``turning_mode`` (as :meth:`Fleet.arrays`)
    stock : the stock table
    problem : the base problem (margin, turning constants, disturbance angle, the risk bound)

    Returns
    -------
    dict of (chairs, casters) arrays: ``turning_effort`` F_turn [N] (Eq. 9 with the turning model),
    ``threshold_force`` P [N] (Eq. 4A; +inf where d/h <= 2), ``objective`` J (:meth:`Casters.J`), ``feasible`` (risk bound, swept radius,
    sill), and per-chair boolean (chairs,) ``any_risk``, ``any_radius``, ``any_sill`` for the reasons.
    """
    load = np.asarray(chairs["load"], float)
    n, s = len(load), len(stock)
    required = (1 + problem.margin) * np.asarray(chairs["target_speed"], float)
    out = {key: np.empty((n, s)) for key in ("turning_effort", "threshold_force", "objective")}
    out |= {key: np.empty((n, s), bool) for key in ("risk_ok", "radius_ok", "sill_ok")}
    designs = {name: getattr(stock, name)[None, :] for name in VARIABLES}
    for surface in SURFACES:
        for mode in MODES:
            rows = np.flatnonzero((chairs["surface"] == surface) & (chairs["turning_mode"] == mode))
            if not len(rows):
                continue
            values = evaluate(
                designs,
                problem.conditions.replace(surface=surface, turning_mode=mode),
                inertia=stock.inertia[None, :],
                measured=stock.measured[None, :],
                load=load[rows, None],
                threshold_height=np.asarray(chairs["threshold_height"], float)[rows, None],
                required_speed=required[rows, None],
                swept_radius_max=np.asarray(chairs["swept_radius_max"], float)[rows, None],
            )
            for key in out:
                out[key][rows] = values.J(problem.weights) if key == "objective" else getattr(values, key)
    effort, force, objective, risk_ok, radius_ok, sill_ok = out.values()
    if getattr(problem, "tolerances", None) is not None:  # the stock's corner speeds and toleranced swept radius
        risk_ok &= np.asarray(stock.confident_speed, float)[None, :] >= required[:, None]
        r_max = np.asarray(chairs["swept_radius_max"], float)[:, None]
        radius_ok &= ~np.isfinite(r_max) | (np.asarray(stock.swept_radius, float)[None, :] <= r_max * (1 + 1e-12))
    return {
        "turning_effort": effort,
        "threshold_force": force,
        "objective": objective,
        "feasible": risk_ok & radius_ok & sill_ok,
        "any_risk": risk_ok.any(axis=1),
        "any_radius": radius_ok.any(axis=1),
        "any_sill": sill_ok.any(axis=1),
        "required": required,
    }


# long: the vectorised rule is one pass over chairs x stock (screen, front, knee, alternatives)
def recommend_chairs(chairs: dict, stock: StockTable, problem) -> dict:
    """The recommendation of every chair, vectorised: buildable front, rule, alternatives.

    For each chair: the feasible stock casters (:func:`evaluate_chairs`), their non-dominated set in
    (F_turn, P) (the buildable front), and the stock index chosen by the base problem's rule: the knee of
    the front (the point farthest from the chord between its two ends, in objectives normalised to the
    front's range, toward the ideal point; with fewer than three points the end with the least J), or, with
    a cap on one objective, the best on the other within the cap.  Also the easiest-to-turn and
    easiest-over-the-sill ends and the least J = w_turn F_turn + w_threshold P (the regret baseline).

    Returns
    -------
    dict of (chairs,) arrays: ``choice``, ``easiest_turn``, ``easiest_sill``, ``best_j`` (stock indices,
    −1 if the chair has no feasible caster), ``front_size``, ``turning_effort`` [N], ``threshold_force`` [N]
    and ``objective`` J of the choice, ``reason`` (empty, or why the chair is infeasible).
    """
    ev = evaluate_chairs(chairs, stock, problem)
    f, p, ok = ev["turning_effort"], ev["threshold_force"], ev["feasible"]
    n, s = f.shape
    fm = np.where(ok, f, np.inf)
    rows = np.arange(n)
    # P depends on the wheel diameter only (Eq. 4A), so casters of one diameter share P and only the
    # least-F allowed one of each diameter can be on the front (ties: the lowest stock index).  Reduce
    # to one candidate per diameter first: (chairs × diameters) instead of (chairs × casters).
    _, group = np.unique(stock.diameter, return_inverse=True)
    perm = np.argsort(group, kind="stable")
    counts = np.bincount(group)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    fperm = fm[:, perm]
    gmin = np.minimum.reduceat(fperm, starts, axis=1)
    position = np.where(fperm == np.repeat(gmin, counts, axis=1), np.arange(s), s)
    gstock = perm[np.minimum(np.minimum.reduceat(position, starts, axis=1), s - 1)]
    gp = np.where(np.isfinite(gmin), np.take_along_axis(p, gstock, axis=1), np.inf)
    j = np.where(ok, ev["objective"], np.inf)
    best_j = np.where(ok.any(axis=1), np.argmin(j, axis=1), -1)
    cap_p = getattr(problem, "max_threshold_force", None)
    cap_f = getattr(problem, "max_turning_effort", None)
    # the buildable front and the rule: designer.studies.recommend.select_rows (the single owner of the rule)
    sel = select_rows(gmin, gp, np.isfinite(gmin), problem.weights, cap_p, cap_f)

    def stock_index(k):
        return np.where(k >= 0, np.take_along_axis(gstock, np.maximum(k, 0)[:, None], axis=1)[:, 0], -1)

    choice, easiest_turn, easiest_sill = (stock_index(sel[k]) for k in ("choice", "easiest_turn", "easiest_sill"))
    size, no_cap = sel["front_size"], sel["over_cap"]

    sel = np.maximum(choice, 0)
    reason = np.full(n, "", dtype=object)
    for i in np.flatnonzero(choice < 0):
        reason[i] = _reason(i, ev, stock, no_cap[i], cap_p, cap_f)
    return {
        "choice": choice,
        "easiest_turn": easiest_turn,
        "easiest_sill": easiest_sill,
        "best_j": best_j,
        "front_size": size,
        "turning_effort": np.where(choice >= 0, f[rows, sel], np.nan),
        "threshold_force": np.where(choice >= 0, p[rows, sel], np.nan),
        "objective": np.where(choice >= 0, j[rows, sel], np.nan),
        "reason": reason,
    }


def _reason(i, ev, stock, over_cap, cap_p, cap_f) -> str:
    """Why chair ``i`` gets no caster, in one phrase."""
    if over_cap:
        cap = (
            f"sill force <= {shown(cap_p, 'threshold_force')}"
            if cap_p is not None
            else f"turning effort <= {shown(cap_f, 'turning_effort')}"
        )
        return f"infeasible: no buildable caster within the cap {cap}"
    missing = []
    if not ev["any_risk"][i]:
        missing.append(
            f"risk bound (best confident speed {shown(stock.confident_speed.max(), 'confident_speed')} < required "
            f"{shown(ev['required'][i], 'confident_speed')})"
        )
    if not ev["any_radius"][i]:
        missing.append(f"swept radius (smallest {shown(stock.swept_radius.min(), 'swept_radius', 'in')})")
    if not ev["any_sill"][i]:
        missing.append(f"sill (largest wheel {shown(stock.diameter.max(), 'diameter', 'in')} <= twice the sill)")
    if missing:
        return "infeasible: no stock caster meets the " + "; ".join(missing)
    return "infeasible: no stock caster meets the risk bound, the swept radius and the sill at once"


def _split(fleet: Fleet, chunk: int) -> list[tuple[int, dict]]:
    arrays = fleet.arrays()
    return [(start, {k: v[start : start + chunk] for k, v in arrays.items()}) for start in range(0, len(fleet), chunk)]


# --------------------------------------------------------------------------- Monte Carlo of the choice


def _mc_task(
    designs: np.ndarray, inertia: np.ndarray, speeds: np.ndarray, slip: float, uncertainty, measured: np.ndarray
) -> np.ndarray:
    """P(shimmy) for each (design, speed) row, as an (n, 3) array: the exact law's (quadrature,
    :func:`designer.physics.acceptance.exact_probability`), the Monte Carlo's beside it and its SE; one task of
    the fleet's risk (in this process or on a Dask worker), the Monte Carlo by the model's
    :func:`designer.model.shimmy_probability` (each row the number of a single caster's seeded stream; a wheel
    not ``measured`` is known by its diameter)."""
    trail, diameter, groove, damping = designs.T  # the columns in VARIABLES' order
    p, se = shimmy_probability(
        trail, inertia, groove, damping, slip, speeds, uncertainty, diameter=diameter, measured=measured
    )
    exact = [
        exact_probability(LawCaster(t, float(i_w), b, c, float(slip), None if m else d), float(v), uncertainty)
        for (t, d, b, c), i_w, m, v in zip(designs.tolist(), inertia, measured, speeds)
    ]
    return np.column_stack([exact, p, se])
