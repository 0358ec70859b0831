"""K part numbers for a fleet: the exact weighted K-median over stock casters (mixed-integer program).

Chairs i (weight w_i = units sold) are clients, stock casters j are facilities.  The cost of giving
chair i caster j is its regret r_ij = J_ij − min_j' J_ij' >= 0 (J = w_turn F_turn + w_threshold P of the
base problem), or +inf when caster j breaks chair i's own risk bound, swept-radius limit or sill
(d/h > 2).  The program

    minimise   Σ_i Σ_j w_i r_ij x_ij
    subject to Σ_j x_ij = 1            (every chair gets one caster)
               x_ij <= y_j             (only from an open part number)
               Σ_j y_j = K             (K part numbers)
               y_j ∈ {0, 1}, 0 <= x_ij <= 1, x_ij only where r_ij < inf

is solved exactly by HiGHS (``scipy.optimize.milp``).  x may stay continuous: for integral y the best
assignment (each chair to its cheapest open caster) is integral.  Before the solve, a caster that is
feasible for no chair is dropped, and so is a caster j whose column is dominated by another one j'
(j' feasible wherever j is and r_ij' <= r_ij for every chair): replacing j by j' never makes a solution
worse, so the optimum is unchanged.  Beyond :data:`EXACT_LIMIT` feasible pairs, :func:`solve_kmedian`
uses greedy selection plus swap local search and states the gap to a Lagrangian lower bound.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass, field

import numpy as np

EXACT_LIMIT = 60_000
"""Largest number of allowed (chair, caster) pairs solved as an exact MIP (HiGHS takes 3–8 s per K at
15 000–40 000 pairs on this machine and hits a 2-minute limit at 140 000); beyond it: greedy + swap with
a Lagrangian gap bound."""


@dataclass
class KMedianSolution:
    """One K: the chosen casters, the assignment and the regret.

    Attributes
    ----------
    k : number of part numbers asked for
    chosen : stock indices of the K casters (sorted)
    assignment : per chair, the stock index it gets (-1 if none can serve it)
    regret : the count-weighted total regret Σ w_i r_i [objective units, N with weights (1, 1)]
    status : "optimal" (MIP), "optimal-by-bound" (heuristic whose value the Lagrangian bound meets),
        "heuristic" or "time limit" (with ``gap``), or "infeasible" (no K casters serve every chair)
    lower_bound : proven lower bound on the regret (= regret when optimal)
    gap : regret − lower_bound (0 when optimal)
    seconds : wall time of the solve [s]
    """

    k: int
    chosen: list = field(default_factory=list)
    assignment: np.ndarray | None = None
    regret: float = math.inf
    status: str = "infeasible"
    lower_bound: float = math.nan
    gap: float = math.nan
    seconds: float = 0.0
    message: str = ""


def prune_candidates(cost: np.ndarray) -> np.ndarray:
    """Indices of the columns worth keeping: feasible for some chair and not dominated by another column.

    Column j is dropped when some j' has cost[:, j'] <= cost[:, j] everywhere (+inf = infeasible) and,
    if the two columns are equal, j' < j.  The K-median optimum is unchanged (see the module docstring).
    """
    cost = np.asarray(cost, float)
    n = cost.shape[1]
    alive = np.isfinite(cost).any(axis=0)
    idx = np.flatnonzero(alive)
    keep = np.ones(len(idx), bool)
    sub = cost[:, idx]
    for a in range(len(idx)):
        if not keep[a]:
            continue
        # columns b dominated by a: cost[:, a] <= cost[:, b] everywhere
        le = np.all(sub[:, [a]] <= sub, axis=0)
        eq = np.all(sub[:, [a]] == sub, axis=0)
        dominated = le & (~eq | (np.arange(len(idx)) > a))
        dominated[a] = False
        keep &= ~dominated
    del n
    return idx[keep]


def solve_kmedian(
    cost: np.ndarray, weights: np.ndarray, k: int, time_limit: float = 120.0, exact_limit: int = EXACT_LIMIT
) -> KMedianSolution:
    """Choose ``k`` columns of ``cost`` minimising Σ_i w_i min_{j chosen} cost_ij, every row served.

    Parameters
    ----------
    cost : (chairs, casters) regrets r_ij >= 0 [objective units], +inf where caster j is not allowed
    weights : (chairs,) counts w_i >= 0
    k : number of casters to choose (1 <= k <= casters)
    time_limit : HiGHS time limit [s]; if it stops early the result says so (status "time limit")
    exact_limit : above this many feasible pairs use the heuristic with a Lagrangian gap bound

    Returns
    -------
    KMedianSolution (exact via ``scipy.optimize.milp`` when small enough).
    """
    start = time.perf_counter()
    cost = np.asarray(cost, float)
    weights = np.asarray(weights, float)
    cols = prune_candidates(cost)
    sub = cost[:, cols]
    out = KMedianSolution(k=k)
    if len(cols) == 0 or not np.isfinite(sub).any(axis=1).all():
        out.message = "some chair has no allowed caster"
        out.seconds = time.perf_counter() - start
        return out
    if k >= len(cols):  # every useful caster can be stocked: each chair gets its own best (regret 0 by design)
        chosen = np.arange(len(cols))
        best = _assign(sub, chosen)
        return _finish(out, cols, chosen, best, sub, weights, "optimal", start, bound=None)
    pairs = int(np.isfinite(sub).sum())
    if pairs <= exact_limit:
        out = _milp(out, cols, sub, weights, k, time_limit, start)
        if out.status != "time limit":
            return out
        # HiGHS stopped early: keep the better of its incumbent and the heuristic, with the better bound
        mip = out
        out = _heuristic(KMedianSolution(k=k), cols, sub, weights, k, start)
        if mip.regret < out.regret:
            mip.lower_bound = max(mip.lower_bound, out.lower_bound)
            out = mip
        else:
            out.lower_bound = max(out.lower_bound, mip.lower_bound if math.isfinite(mip.lower_bound) else 0.0)
        out.gap = max(0.0, out.regret - out.lower_bound)
        out.status = "optimal-by-bound" if out.gap <= 1e-9 * max(1.0, abs(out.regret)) else "time limit"
        out.seconds = time.perf_counter() - start
        return out
    return _heuristic(out, cols, sub, weights, k, start)


def _assign(sub: np.ndarray, chosen: np.ndarray) -> np.ndarray:
    """Per chair, the position in ``chosen`` of its cheapest chosen column (index into sub's columns)."""
    pick = np.argmin(sub[:, chosen], axis=1)
    return chosen[pick]


def _finish(out, cols, chosen, best, sub, weights, status, start, bound):
    values = sub[np.arange(sub.shape[0]), best]
    if not np.all(np.isfinite(values)):
        out.status = "infeasible"
        out.message = f"no {out.k} casters serve every chair"
        out.seconds = time.perf_counter() - start
        return out
    out.chosen = sorted(int(cols[j]) for j in chosen)
    out.assignment = cols[best]
    out.regret = float(np.dot(weights, values))
    out.status = status
    out.lower_bound = out.regret if bound is None else float(bound)
    out.gap = max(0.0, out.regret - out.lower_bound)
    out.seconds = time.perf_counter() - start
    return out


def _milp(out, cols, sub, weights, k, time_limit, start):
    # scipy.optimize / scipy.sparse: heavy, loaded only when a K-median is solved
    from scipy.optimize import Bounds, LinearConstraint, milp
    from scipy.sparse import coo_matrix, csr_matrix

    m, n = sub.shape
    ii, jj = np.nonzero(np.isfinite(sub))
    p = len(ii)
    # variables: y_0..y_{n-1}, then x_p for each feasible pair p = (ii[p], jj[p])
    c = np.concatenate([np.zeros(n), weights[ii] * sub[ii, jj]])
    # Σ_j x_ij = 1
    a_assign = coo_matrix((np.ones(p), (ii, n + np.arange(p))), shape=(m, n + p))
    # x_ij − y_j <= 0
    rows = np.concatenate([np.arange(p), np.arange(p)])
    colsx = np.concatenate([n + np.arange(p), jj])
    vals = np.concatenate([np.ones(p), -np.ones(p)])
    a_link = coo_matrix((vals, (rows, colsx)), shape=(p, n + p))
    # Σ_j y_j = K
    a_k = csr_matrix((np.ones(n), (np.zeros(n, int), np.arange(n))), shape=(1, n + p))
    constraints = [
        LinearConstraint(csr_matrix(a_assign), 1, 1),
        LinearConstraint(csr_matrix(a_link), -np.inf, 0),
        LinearConstraint(a_k, k, k),
    ]
    integrality = np.concatenate([np.ones(n), np.zeros(p)])
    res = milp(
        c,
        constraints=constraints,
        integrality=integrality,
        bounds=Bounds(0, 1),
        options={"time_limit": time_limit, "mip_rel_gap": 0.0, "disp": False},
    )
    if res.x is None:
        out.status = "infeasible"
        out.message = f"no {k} casters serve every chair ({res.message})"
        out.seconds = time.perf_counter() - start
        return out
    chosen = np.flatnonzero(res.x[:n] > 0.5)
    best = _assign(sub, chosen)
    status = "optimal" if res.status == 0 else "time limit"
    bound = getattr(res, "mip_dual_bound", None)
    out = _finish(
        out,
        cols,
        chosen,
        best,
        sub,
        weights,
        status,
        start,
        bound=None if status == "optimal" or bound is None else bound,
    )
    out.message = res.message
    return out


def _heuristic(out, cols, sub, weights, k, start, iterations: int = 400):
    """Greedy + 1-swap local search; gap to the Lagrangian bound (assignment constraints relaxed)."""
    chosen, value = greedy_swap(sub, weights, k)
    if not math.isfinite(value):
        out.status = "infeasible"
        out.message = f"no {k} casters found that serve every chair (greedy cover)"
        out.seconds = time.perf_counter() - start
        return out
    bound = lagrangian_bound(sub, weights, k, upper=value, iterations=iterations)
    # a bound that meets the heuristic's value (to 1e-9) proves it optimal
    status = "optimal-by-bound" if value - bound <= 1e-9 * max(1.0, abs(value)) else "heuristic"
    return _finish(out, cols, chosen, _assign(sub, chosen), sub, weights, status, start, bound=bound)


def greedy_swap(cost: np.ndarray, weights: np.ndarray, k: int, max_seconds: float = 120.0) -> tuple[np.ndarray, float]:
    """Greedy K-median (cover the unserved weight first, then the least total), improved by 1-swaps.

    Returns (chosen columns sorted, Σ w_i min_{j chosen} cost_ij); the value is +inf if the greedy cover
    leaves a chair unserved.
    """
    start = time.perf_counter()
    m, n = cost.shape
    big = np.where(np.isfinite(cost), cost, np.inf)
    allowed = np.isfinite(big)
    finite_big = np.where(allowed, big, 0.0)
    chosen: list[int] = []
    current = np.full(m, np.inf)
    for _ in range(k):
        unserved = ~np.isfinite(current)
        gain_cover = (weights[unserved] + 1e-9) @ allowed[unserved] if unserved.any() else np.zeros(n)
        if unserved.any() and gain_cover.max() > 0:
            gain_cover[chosen] = -1
            j = int(np.argmax(gain_cover))
        else:
            cand = np.minimum(current[:, None], big)
            totals = weights @ np.where(np.isfinite(cand), cand, 0.0)
            totals[chosen] = np.inf
            j = int(np.argmin(totals))
        chosen.append(j)
        current = np.minimum(current, big[:, j])
    del finite_big

    def total(cur):
        return float(np.dot(weights, cur)) if np.all(np.isfinite(cur)) else math.inf

    value = total(current)
    improved = True
    while improved and time.perf_counter() - start < max_seconds:
        improved = False
        for pos in range(k):
            rest = [c for i, c in enumerate(chosen) if i != pos]
            base = big[:, rest].min(axis=1) if rest else np.full(m, np.inf)
            cand = np.minimum(base[:, None], big)
            served = np.isfinite(cand).all(axis=0)
            totals = np.where(served, weights @ np.where(np.isfinite(cand), cand, 0.0), np.inf)
            totals[chosen] = np.inf
            j = int(np.argmin(totals))
            if totals[j] < value - 1e-12 * max(1.0, abs(value)):
                chosen[pos] = j
                current = cand[:, j]
                value = total(current)
                improved = True
    return np.array(sorted(chosen)), value


def lagrangian_bound(cost: np.ndarray, weights: np.ndarray, k: int, upper: float, iterations: int = 400) -> float:
    """Lower bound on the K-median optimum by Lagrangian relaxation of "every chair served once".

    L(λ) = Σ_i λ_i + (sum of the k smallest ρ_j), ρ_j = Σ_i min(0, w_i c_ij − λ_i), is a lower bound for
    every λ; maximised by subgradient steps of Polyak's size θ (upper − L)/‖g‖² toward the heuristic
    value ``upper`` (θ halves after 20 steps without progress).  Infinite costs never enter ρ.
    """
    wc = np.where(np.isfinite(cost), weights[:, None] * cost, np.inf)
    lam = np.min(wc, axis=1)
    best = 0.0
    theta = 2.0
    stall = 0
    for _ in range(iterations):
        with np.errstate(invalid="ignore"):
            red = np.minimum(0.0, wc - lam[:, None])
        rho = red.sum(axis=0)
        open_ = np.argpartition(rho, k - 1)[:k] if k < len(rho) else np.arange(len(rho))
        value = float(lam.sum() + rho[open_].sum())
        if value > best + 1e-9 * max(1.0, abs(best)):
            best, stall = value, 0
        else:
            stall += 1
            if stall >= 20:
                theta, stall = theta / 2, 0
                if theta < 1e-4:
                    break
        g = 1.0 - (red[:, open_] < 0).sum(axis=1)
        norm = float(np.dot(g, g))
        if norm == 0:  # λ is optimal: the relaxed solution serves every chair once
            break
        lam = lam + theta * max(upper - value, 1e-12 * max(1.0, abs(upper))) / norm * g
    return max(0.0, min(best, upper))


def brute_force_kmedian(cost: np.ndarray, weights: np.ndarray, k: int) -> tuple[float, tuple]:
    """Enumerate every k-subset of columns; (least weighted regret, its columns) with every row served.

    For tests: C(n, k) subsets, so only for small n (12 candidates and k = 3 is 220 subsets).
    """
    cost = np.asarray(cost, float)
    best = (math.inf, ())
    for subset in itertools.combinations(range(cost.shape[1]), k):
        values = cost[:, list(subset)].min(axis=1)
        if np.all(np.isfinite(values)):
            total = float(np.dot(weights, values))
            if total < best[0] - 1e-12:
                best = (total, subset)
    return best
