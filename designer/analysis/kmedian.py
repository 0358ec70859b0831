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

EXACT_LIMIT = 2_000_000
"""Largest number of feasible (chair, caster) pairs solved as an exact MIP; beyond it: heuristic + bound."""


@dataclass
class KMedianSolution:
    """One K: the chosen casters, the assignment and the regret.

    Attributes
    ----------
    k : number of part numbers asked for
    chosen : stock indices of the K casters (sorted)
    assignment : per chair, the stock index it gets (-1 if none can serve it)
    regret : the count-weighted total regret Σ w_i r_i [objective units, N with weights (1, 1)]
    status : "optimal", "heuristic" (with ``gap``), or "infeasible" (no K casters serve every chair)
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


def solve_kmedian(cost: np.ndarray, weights: np.ndarray, k: int, time_limit: float = 120.0,
                  exact_limit: int = EXACT_LIMIT) -> KMedianSolution:
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
        return _milp(out, cols, sub, weights, k, time_limit, start)
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
    constraints = [LinearConstraint(csr_matrix(a_assign), 1, 1), LinearConstraint(csr_matrix(a_link), -np.inf, 0),
                   LinearConstraint(a_k, k, k)]
    integrality = np.concatenate([np.ones(n), np.zeros(p)])
    res = milp(c, constraints=constraints, integrality=integrality, bounds=Bounds(0, 1),
               options={"time_limit": time_limit, "mip_rel_gap": 0.0, "disp": False})
    if res.x is None:
        out.status = "infeasible"
        out.message = f"no {k} casters serve every chair ({res.message})"
        out.seconds = time.perf_counter() - start
        return out
    chosen = np.flatnonzero(res.x[:n] > 0.5)
    best = _assign(sub, chosen)
    status = "optimal" if res.status == 0 else "time limit"
    bound = getattr(res, "mip_dual_bound", None)
    out = _finish(out, cols, chosen, best, sub, weights, status, start,
                  bound=None if status == "optimal" or bound is None else bound)
    out.message = res.message
    return out


def _heuristic(out, cols, sub, weights, k, start, iterations: int = 200):
    """Greedy + 1-swap local search; gap to the Lagrangian bound (assignment constraints relaxed)."""
    m, n = sub.shape
    big = np.where(np.isfinite(sub), sub, np.inf)
    chosen: list[int] = []
    current = np.full(m, np.inf)
    for _ in range(k):
        with np.errstate(invalid="ignore"):
            totals = np.array([np.dot(weights, np.minimum(current, big[:, j])) if j not in chosen else np.inf
                               for j in range(n)])
        # infinite totals (some chair still unserved): prefer the column serving the most unserved weight
        if not np.isfinite(totals).any():
            unserved = ~np.isfinite(current)
            cover = np.array([np.dot(weights[unserved] + 1e-12, np.isfinite(big[unserved, j])) if j not in chosen
                              else -1 for j in range(n)])
            j = int(np.argmax(cover))
        else:
            j = int(np.argmin(totals))
        chosen.append(j)
        current = np.minimum(current, big[:, j])
    improved = True
    while improved and time.perf_counter() - start < 300:
        improved = False
        value = np.dot(weights, current)
        for pos in range(k):
            rest = [c for i, c in enumerate(chosen) if i != pos]
            base = big[:, rest].min(axis=1) if rest else np.full(m, np.inf)
            cand = np.minimum(base[:, None], big)
            with np.errstate(invalid="ignore"):
                totals = weights @ np.where(np.isfinite(cand), cand, 1e300)
            totals[chosen] = np.inf
            j = int(np.argmin(totals))
            if totals[j] < value * (1 - 1e-12) - 1e-12:
                chosen[pos] = j
                current = cand[:, j]
                value = np.dot(weights, current)
                improved = True
    bound = _lagrangian_bound(big, weights, k, iterations)
    best = _assign(sub, np.array(sorted(chosen)))
    return _finish(out, cols, np.array(sorted(chosen)), best, sub, weights, "heuristic", start, bound=bound)


def _lagrangian_bound(cost, weights, k, iterations):
    """max over λ of Σλ_i + (sum of the k smallest ρ_j), ρ_j = Σ_i min(0, w_i c_ij − λ_i): a valid lower bound."""
    wc = np.where(np.isfinite(cost), weights[:, None] * cost, np.inf)
    lam = np.min(wc, axis=1)  # start: each chair at its own best (regret 0) → bound 0
    best = -np.inf
    step = 1.0
    for _ in range(iterations):
        red = np.minimum(0.0, wc - lam[:, None])
        rho = red.sum(axis=0)
        open_ = np.argsort(rho)[:k]
        value = lam.sum() + rho[open_].sum()
        best = max(best, value)
        served = (red[:, open_] < 0).sum(axis=1)
        g = 1.0 - served
        norm = float(np.dot(g, g))
        if norm == 0:
            break
        scale = max(abs(value), 1e-9)
        lam = lam + step * scale / norm * g
        step *= 0.97
    return max(0.0, best)


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
