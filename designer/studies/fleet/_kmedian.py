"""K part numbers for a fleet: the weighted K-median over stock casters, solved to proven optimality.

Chairs i (weight w_i = units sold) are clients, stock casters j are facilities.  The cost of giving
chair i caster j is its regret r_ij = J_ij − min_j' J_ij' >= 0 (J = w_turn F_turn + w_threshold P of the
base problem), or +inf when caster j breaks chair i's own risk bound, swept-radius limit or sill
(d/h > 2).  The problem is

    minimise   Σ_i w_i min_{j ∈ S} r_ij   over sets S of K casters, every chair served (a finite r_ij).

How it is solved (:func:`kmedian_curve`, :func:`solve_kmedian`); every step is exact:

1. **Reduction.**  A caster allowed for no chair is dropped, and so is a caster whose column is dominated
   by another one (allowed wherever it is, r no larger anywhere; of equal columns the first is kept):
   swapping it for its dominator never makes a set worse.  Chairs with identical cost rows are merged
   into one client whose weight is the sum of their counts.
2. **Feasibility.**  The fewest casters that serve every chair (a set cover over the distinct patterns
   of allowed casters, solved by HiGHS) decide which K are feasible at all: below it, "infeasible" is
   proved, not guessed.
3. **Incumbent.**  Greedy (from the K − 1 solution) and 1-swap local search give a set S and its value U.
4. **Lagrangian bound.**  Relaxing "every chair served once" with multipliers λ gives, for every λ,

       L(λ) = Σ_i λ_i + (sum of the K smallest ρ_j),   ρ_j = Σ_i min(0, w_i r_ij − λ_i)  <=  optimum,

   the linear-programming bound of the classical K-median program.  λ is improved by subgradient steps
   (Polyak's step toward U); the casters the relaxation opens are also tried as incumbents.  When
   L(λ) reaches U (relative :data:`TOLERANCE`) the incumbent is proved optimal: status
   ``"optimal-by-bound"``.
5. **Elimination and exact MIP.**  Otherwise the same λ fixes casters: forcing caster j open (closed)
   changes the relaxation to L(λ) + ρ_j − ρ_(K) (to L(λ) − ρ_j + ρ_(K+1)); when that exceeds U, no set
   as good as the incumbent contains j (omits j), so j is removed (fixed open).  The few casters left go
   to an exact mixed-integer program solved by HiGHS (``scipy.optimize.milp``, relative gap 0), in the
   compact *radius* form: for each client sort its costs over the remaining casters,
   r_(1) <= r_(2) <= …; its cost is r_(1) + Σ_t (r_(t+1) − r_(t)) [none of its t cheapest casters is
   open].  With binary y_j and one continuous u_T >= 1 − Σ_{j ∈ T} y_j, u_T >= 0 per distinct set T of
   "t cheapest casters" (clients sharing a set share its u, their coefficients add up), plus a cover row
   Σ_{j allowed} y_j >= 1 per distinct allowed pattern and Σ_j y_j = K, the program's optimum is the
   K-median optimum over those casters.  HiGHS's proof (dual bound = incumbent) then proves the whole
   problem: status ``"optimal"``, with the bound reported.  A MIP stopped by ``time_limit`` reports
   ``"time limit"`` with its gap.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from designer.reprs import Record

TOLERANCE = 1e-9
"""Relative gap at which a value is called optimal: value − lower bound <= TOLERANCE · max(1, value)."""

LAGRANGIAN_ITERATIONS = 300
"""Most subgradient steps per K before the remaining casters go to the exact MIP."""


@dataclass(frozen=True, kw_only=True)
class KMedianSolution(Record):
    """One K: the chosen casters, the assignment, the regret and its proof.

    Attributes
    ----------
    k : number of part numbers asked for
    chosen : stock indices of the K casters (sorted)
    assignment : per chair, the stock index it gets (its cheapest chosen caster)
    regret : the count-weighted total regret Σ w_i r_i [objective units: N with the base problem's weights]
    status : "optimal" (HiGHS MIP after elimination), "optimal-by-bound" (the Lagrangian bound meets the
        value), "time limit" (MIP stopped early; see ``gap``), or "infeasible" (proved: fewer casters than
        the smallest set that serves every chair)
    lower_bound : proven lower bound on the least regret [same units]
    gap : regret − lower_bound (<= TOLERANCE · regret when optimal)
    seconds : wall time of the solve [s]
    method : how optimality was proved, in words
    candidates : useful casters after the reduction (stocking more than these changes nothing)
    """

    k: int
    chosen: list[int] = field(default_factory=list)
    assignment: np.ndarray | None = None
    regret: float = math.inf
    status: str = "infeasible"
    lower_bound: float = math.nan
    gap: float = math.nan
    seconds: float = 0.0
    message: str = ""
    method: str = ""
    candidates: int = 0

    _units = {"regret": "N", "lower_bound": "N", "gap": "N", "seconds": "s"}


# --------------------------------------------------------------------------- reduction


class ColumnDominance:
    """Which columns of a cost matrix are dominated, from its rows given in blocks (exact; memory of a block).

    Column a dominates column b when cost[:, a] <= cost[:, b] on every row (+inf = not allowed) and, if the
    two are equal, a < b; a dominated column, or one allowed on no row, is never needed by a K-median (the
    module docstring).  The candidate pairs come from a sample of the first block's rows: for each column b
    its ``per_column`` likeliest dominators (those that dominate the most columns on the sample); every
    block then keeps the pairs that hold on all its rows, so a pair left holds on every row seen.  A column
    whose candidates all fail is kept (never dropped without proof; keeping one more column changes no
    optimum).
    """

    def __init__(self, n: int, sample_rows: int = 256, per_column: int = 32):
        self.n, self.sample_rows, self.per_column = n, sample_rows, per_column
        self.alive = np.zeros(n, bool)
        self.pa: np.ndarray | None = None
        self.pb = np.zeros(0, int)
        self.eq = np.zeros(0, bool)

    def add(self, block: np.ndarray) -> None:
        """Take the next rows (rows × n)."""
        block = np.asarray(block, float)
        if not len(block):
            return
        self.alive |= np.isfinite(block).any(axis=0)
        if self.pa is None:
            self.pa, self.pb = self._candidates(block)
            self.eq = np.ones(len(self.pa), bool)
        le, eq = self._verify(block, self.pa, self.pb)
        self.pa, self.pb, self.eq = self.pa[le], self.pb[le], (self.eq & eq)[le]

    def _candidates(self, block: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        rows = np.random.default_rng(0).choice(len(block), min(self.sample_rows, len(block)), replace=False)
        sample = block[np.sort(rows)]
        parts_a: list[np.ndarray] = []
        parts_b: list[np.ndarray] = []
        for a0 in range(0, self.n, 64):  # (a, b) with a <= b on the sample, in blocks of 64 a's
            a, b = np.nonzero(np.all(sample[:, a0 : a0 + 64, None] <= sample[:, None, :], axis=0))
            a += a0
            parts_a.append(a[a != b])
            parts_b.append(b[a != b])
        pa, pb = np.concatenate(parts_a), np.concatenate(parts_b)
        strength = np.bincount(pa, minlength=self.n)
        order = np.lexsort((pa, -strength[pa], pb))  # per b, its strongest dominators first
        pa, pb = pa[order], pb[order]
        first = np.r_[0, np.flatnonzero(pb[1:] != pb[:-1]) + 1] if len(pb) else np.zeros(0, int)
        rank = np.arange(len(pb)) - np.repeat(first, np.diff(np.r_[first, len(pb)]))
        keep = rank < self.per_column
        return pa[keep], pb[keep]

    @staticmethod
    def _verify(block: np.ndarray, pa: np.ndarray, pb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per pair: column a <= column b on every row of ``block``, and equal on every row (pairs by a)."""
        le, eq = np.zeros(len(pa), bool), np.zeros(len(pa), bool)
        if not len(pa):
            return le, eq
        order = np.argsort(pa, kind="stable")
        starts = np.flatnonzero(np.r_[True, pa[order][1:] != pa[order][:-1]])
        for s, e in zip(starts, np.r_[starts[1:], len(order)]):
            idx = order[s:e]
            col, other = block[:, [pa[idx[0]]]], block[:, pb[idx]]
            le[idx] = np.all(col <= other, axis=0)
            eq[idx] = np.all(col == other, axis=0)
        return le, eq

    def undominated(self) -> np.ndarray:
        """Indices of the columns to keep: allowed on some row and dominated by no other column."""
        keep = self.alive.copy()
        if self.pa is not None:
            keep[self.pb[~self.eq | (self.pa < self.pb)]] = False
        return np.flatnonzero(keep)


def prune_candidates(cost: np.ndarray, block_rows: int = 5000) -> np.ndarray:
    """Indices of the columns worth keeping: feasible for some chair and not dominated by another column
    (:class:`ColumnDominance` over blocks of ``block_rows`` rows).  The K-median optimum is unchanged."""
    cost = np.asarray(cost, float)
    dominance = ColumnDominance(cost.shape[1])
    for a in range(0, max(len(cost), 1), block_rows):
        dominance.add(cost[a : a + block_rows])
    return dominance.undominated()


def aggregate_rows(cost: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Merge chairs with identical cost rows: (distinct rows, summed weights, row of each chair)."""
    cost = np.ascontiguousarray(cost, float)
    keys = cost.view(np.dtype((np.void, cost.dtype.itemsize * cost.shape[1]))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    return cost[first], np.bincount(inverse.ravel(), weights=weights, minlength=len(first)), inverse.ravel()


class _Instance:
    """The reduced problem: distinct client rows × useful casters, and its feasible pairs."""

    def __init__(self, cost: np.ndarray, weights: np.ndarray):
        self.cols = prune_candidates(cost)
        self.full = np.asarray(cost, float)[:, self.cols]
        self.sub, self.w, self.inverse = aggregate_rows(self.full, np.asarray(weights, float))
        self.m, self.n = self.sub.shape
        self.ii, self.jj = np.nonzero(np.isfinite(self.sub))  # pairs by client (row-major order)
        self.wc = self.w[self.ii] * self.sub[self.ii, self.jj]
        self.counts = np.bincount(self.ii, minlength=self.m)  # allowed casters per client (>= 1 when served)
        self.starts = np.r_[0, np.cumsum(self.counts)[:-1]]
        self._red = np.empty(len(self.wc))
        self.served = np.isfinite(self.sub).any(axis=1).all() if self.n else False
        self.cover = _min_cover(np.isfinite(self.sub)) if self.served else []

    def served_by(self, red: np.ndarray, isopen: np.ndarray) -> np.ndarray:
        """Per client, how many open casters the relaxation assigns it (pairs with negative reduced cost)."""
        hit = (red < 0) & isopen[self.jj]
        return np.add.reduceat(hit.view(np.uint8), self.starts, dtype=np.int64)

    def value(self, chosen: Iterable[int] | np.ndarray) -> float:
        """Σ w_i min_{j ∈ chosen} cost_ij (+inf if some chair is unserved)."""
        v = self.sub[:, list(chosen)].min(axis=1)
        return float(self.w @ v) if np.all(np.isfinite(v)) else math.inf

    def relaxation(self, lam: np.ndarray, k: int) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
        """L(λ), ρ, the K casters the relaxation opens, and the reduced costs min(0, w c − λ) of the pairs
        (a buffer reused by the next call)."""
        red = np.subtract(self.wc, np.repeat(lam, self.counts), out=self._red)
        np.minimum(red, 0.0, out=red)
        rho = np.bincount(self.jj, weights=red, minlength=self.n)
        opened = np.argpartition(rho, k - 1)[:k] if k < self.n else np.arange(self.n)
        return float(lam.sum() + rho[opened].sum()), rho, opened, red


def _min_cover(allowed: np.ndarray) -> list[int]:
    """A smallest set of columns serving every row of ``allowed`` (set cover over its distinct rows, HiGHS).

    Its size is the fewest part numbers that serve every chair; exact (HiGHS proves the cover minimal).
    """
    # scipy.optimize: heavy, loaded only when a K-median is solved
    from scipy.optimize import Bounds, LinearConstraint, milp

    patterns = np.unique(allowed, axis=0)
    n = allowed.shape[1]
    res = milp(
        np.ones(n),
        constraints=[LinearConstraint(patterns.astype(float), 1, np.inf)],
        integrality=np.ones(n),
        bounds=Bounds(0, 1),
        options={"disp": False, "mip_rel_gap": 0.0},
    )
    if res.status != 0:  # not proved minimal (never seen: a few hundred rows): no K is called infeasible
        return []
    return [int(j) for j in np.flatnonzero(res.x > 0.5)]


# --------------------------------------------------------------------------- incumbent


def _greedy(inst: _Instance, k: int, start: Iterable[int]) -> list[int]:
    """Extend ``start`` to k casters, each time the one that serves the most unserved weight, then the least total."""
    chosen = [int(j) for j in start][:k]
    current = inst.sub[:, chosen].min(axis=1) if chosen else np.full(inst.m, np.inf)
    allowed = np.isfinite(inst.sub)
    while len(chosen) < k:
        unserved = ~np.isfinite(current)
        cand = np.minimum(current[:, None], inst.sub)
        totals = inst.w @ np.where(np.isfinite(cand), cand, 0.0)
        if unserved.any():  # cover the unserved weight first (ties: the least total)
            cover = (inst.w[unserved] + 1e-9) @ allowed[unserved]
            totals = np.where(cover == cover.max(), totals, np.inf)
        totals[chosen] = np.inf
        j = int(np.argmin(totals))
        chosen.append(j)
        current = np.minimum(current, inst.sub[:, j])
    return chosen


def _local_search(inst: _Instance, chosen: Iterable[int], max_sweeps: int = 100) -> tuple[list[int], float]:
    """1-swap local search (first improvement per position) until no swap lowers the value."""
    chosen = [int(j) for j in chosen]
    value = inst.value(chosen)
    for _ in range(max_sweeps):
        improved = False
        for pos in range(len(chosen)):
            rest = chosen[:pos] + chosen[pos + 1 :]
            base = inst.sub[:, rest].min(axis=1) if rest else np.full(inst.m, np.inf)
            cand = np.minimum(base[:, None], inst.sub)
            served = np.isfinite(cand).all(axis=0)
            totals = np.where(served, inst.w @ np.where(served[None, :], cand, 0.0), np.inf)
            totals[chosen] = np.inf
            j = int(np.argmin(totals))
            if totals[j] < value - 1e-12 * max(1.0, abs(value)):
                chosen[pos], value, improved = j, float(totals[j]), True
        if not improved:
            break
    return sorted(chosen), value


# --------------------------------------------------------------------------- bound and proof


def _subgradient(
    inst: _Instance, k: int, upper: float, chosen: list[int], lam: np.ndarray, iterations: int
) -> tuple[float, np.ndarray, float, list[int]]:
    """Improve λ toward the incumbent's value; returns (bound, λ, upper, chosen) with the best of each."""
    best, best_lam = -math.inf, lam
    theta, stall = 1.0, 0
    isopen = np.zeros(inst.n, bool)
    tried: set[tuple[int, ...]] = set()  # open sets already valued (the relaxation repeats them)
    for it in range(iterations):
        value, rho, opened, red = inst.relaxation(lam, k)
        if value > best:
            best, best_lam, stall = value, lam, 0
        else:
            stall += 1
            if stall >= 15:
                theta, stall = theta / 2, 0
        isopen[:] = False
        isopen[opened] = True
        g = 1.0 - inst.served_by(red, isopen)  # before `red`'s buffer is reused by another relaxation
        key = tuple(sorted(int(j) for j in opened))
        candidate = math.inf if key in tried else inst.value(key)
        tried.add(key)
        if candidate < upper:
            upper, chosen = candidate, list(key)
        if upper - best <= TOLERANCE * max(1.0, abs(upper)) or theta < 1e-6:
            break
        if it % 10 == 9 and len(_eliminate(inst, best_lam, k, upper)[0]) <= k + 8:
            break  # few enough casters left for a quick exact MIP
        norm = float(g @ g)
        if norm == 0:  # the relaxation serves every client once: its value is attained, L = optimum
            break
        lam = lam + theta * (upper - value) / norm * g
    return best, best_lam, upper, chosen


def _eliminate(inst: _Instance, lam: np.ndarray, k: int, upper: float) -> tuple[np.ndarray, np.ndarray]:
    """(casters that may be in a set as good as ``upper``, the subset that must be in every such set)."""
    value, rho, opened, _ = inst.relaxation(lam, k)
    if k >= inst.n:
        return np.arange(inst.n), np.arange(inst.n)
    ordered = np.sort(rho)
    kth, next_ = ordered[k - 1], ordered[k]
    isopen = np.zeros(inst.n, bool)
    isopen[opened] = True
    margin = TOLERANCE * max(1.0, abs(upper))
    closed = ~isopen & (value + rho - kth > upper + margin)
    forced = isopen & (value - rho + next_ > upper + margin)
    return np.flatnonzero(~closed), np.flatnonzero(forced)


def radius_mip(
    cost: np.ndarray, weights: np.ndarray, k: int, fixed_open: Iterable[int] = (), time_limit: float = 120.0
) -> tuple[Any, np.ndarray | None, float]:
    """Exact K-median over the columns of ``cost`` by HiGHS in the radius form (module docstring, step 5).

    Returns (scipy result, chosen columns or None, constant): the optimum is ``result.fun + constant`` and
    HiGHS's dual bound ``result.mip_dual_bound + constant``.
    """
    # scipy.optimize / scipy.sparse: heavy, loaded only when a K-median needs the MIP
    from scipy.optimize import Bounds, LinearConstraint, milp
    from scipy.sparse import csr_matrix

    cost = np.asarray(cost, float)
    weights = np.asarray(weights, float)
    m, n = cost.shape
    order = np.argsort(cost, axis=1, kind="stable")
    ranked = np.take_along_axis(cost, order, axis=1)
    constant = float(weights @ ranked[:, 0])
    with np.errstate(invalid="ignore"):
        step = np.diff(ranked, axis=1)  # r_(t+1) − r_(t); inf past the allowed casters, nan between infs
    fixed = np.zeros(n, bool)
    fixed[list(fixed_open)] = True
    # the t cheapest casters are surely hit when they include a fixed one or number more than n − k
    hit = np.logical_or.accumulate(fixed[order], axis=1)[:, :-1] | (np.arange(1, n)[None, :] > n - k)
    ii, tt = np.nonzero(np.isfinite(step) & (step > 0) & ~hit)
    rank = np.empty_like(order)
    np.put_along_axis(rank, order, np.broadcast_to(np.arange(n), (m, n)), axis=1)
    member = rank[ii] <= tt[:, None]
    _, first, inverse = np.unique(np.packbits(member, axis=1), axis=0, return_index=True, return_inverse=True)
    coef = np.bincount(inverse.ravel(), weights=weights[ii] * step[ii, tt])
    sets = member[first]
    s = len(first)
    r, c = np.nonzero(sets)
    radius = csr_matrix((np.ones(len(r) + s), (np.r_[r, np.arange(s)], np.r_[c, n + np.arange(s)])), shape=(s, n + s))
    patterns = np.unique(np.isfinite(cost), axis=0)
    pr, pc = np.nonzero(patterns)
    cover = csr_matrix((np.ones(len(pr)), (pr, pc)), shape=(len(patterns), n + s))
    count = csr_matrix((np.ones(n), (np.zeros(n, int), np.arange(n))), shape=(1, n + s))
    rows = [LinearConstraint(cover, 1, np.inf), LinearConstraint(count, k, k)]
    if s:
        rows.append(LinearConstraint(radius, 1, np.inf))
    res = milp(
        np.r_[np.zeros(n), coef],
        constraints=rows,
        integrality=np.r_[np.ones(n), np.zeros(s)],
        bounds=Bounds(np.r_[fixed.astype(float), np.zeros(s)], np.r_[np.ones(n), np.full(s, np.inf)]),
        options={"time_limit": time_limit, "mip_rel_gap": 0.0, "disp": False},
    )
    chosen = None if res.x is None else np.flatnonzero(res.x[:n] > 0.5)
    return res, chosen, constant


# --------------------------------------------------------------------------- one K, and the curve


def _solve(
    inst: _Instance, k: int, start: list[int], lam: np.ndarray | None, time_limit: float
) -> tuple[KMedianSolution, np.ndarray | None]:
    t0 = time.perf_counter()
    out = KMedianSolution(k=k, candidates=inst.n)
    if not inst.served:
        return replace(out, message="some chair has no allowed caster", seconds=time.perf_counter() - t0), lam
    if k < len(inst.cover):
        message = f"no {k} casters serve every chair: the fewest that do are {len(inst.cover)} (set cover, HiGHS)"
        return replace(out, message=message, method="set cover (HiGHS)", seconds=time.perf_counter() - t0), lam
    if k >= inst.n:  # every useful caster stocked: each chair gets its own best (regret 0)
        return _finish(inst, out, list(range(inst.n)), None, "optimal", "all useful casters", t0), lam
    chosen = _greedy(inst, k, start)
    if not math.isfinite(inst.value(chosen)):
        chosen = _greedy(inst, k, inst.cover)
    chosen, upper = _local_search(inst, chosen)
    if lam is None or len(lam) != inst.m:
        lam = inst.w * inst.sub[:, chosen].min(axis=1)
    bound, lam, upper2, chosen2 = _subgradient(inst, k, upper, chosen, lam, LAGRANGIAN_ITERATIONS)
    if upper2 < upper:
        chosen, upper = _local_search(inst, chosen2)
    if upper - bound <= TOLERANCE * max(1.0, abs(upper)):
        return _finish(inst, out, chosen, bound, "optimal-by-bound", "Lagrangian bound", t0), lam
    keep, forced = _eliminate(inst, lam, k, upper)
    res, picked, constant = radius_mip(
        inst.sub[:, keep], inst.w, k, np.searchsorted(keep, forced), time_limit=max(1.0, time_limit)
    )
    method = f"Lagrangian elimination ({inst.n} -> {len(keep)} casters) + HiGHS MIP"
    mip_bound = getattr(res, "mip_dual_bound", None)
    mip_bound = -math.inf if mip_bound is None or not math.isfinite(mip_bound) else mip_bound + constant
    if picked is not None and len(picked) == k and inst.value(keep[picked]) < upper:
        chosen, upper = sorted(int(j) for j in keep[picked]), inst.value(keep[picked])
    # no set better than `upper` lies outside `keep`: the MIP's bound holds globally up to `upper`
    bound = max(bound, min(upper, mip_bound))
    status = "optimal" if upper - bound <= TOLERANCE * max(1.0, abs(upper)) else "time limit"
    return replace(_finish(inst, out, chosen, bound, status, method, t0), message=str(res.message)), lam


def _finish(
    inst: _Instance,
    out: KMedianSolution,
    chosen: Iterable[int],
    bound: float | None,
    status: str,
    method: str,
    t0: float,
) -> KMedianSolution:
    columns = np.array(sorted(chosen), int)
    pick = columns[np.argmin(inst.full[:, columns], axis=1)]
    regret = inst.value(columns)
    lower = regret if bound is None else min(float(bound), regret)
    if regret - lower <= len(inst.full) * np.finfo(float).eps * max(1.0, abs(regret)):
        lower = regret  # a bound equal to the value up to the rounding of a sum of one regret a chair: no gap
    return replace(
        out,
        chosen=[int(inst.cols[j]) for j in columns],
        assignment=inst.cols[pick],
        regret=regret,
        lower_bound=lower,
        gap=regret - lower,
        status=status,
        method=method,
        seconds=time.perf_counter() - t0,
    )


def kmedian_curve(
    cost: np.ndarray, weights: np.ndarray, ks: Iterable[int], time_limit: float = 120.0, until: float | None = None
) -> dict[int, KMedianSolution]:
    """The K-median for every K in ``ks`` (ascending), sharing the reduction and warm starts.

    Parameters
    ----------
    cost : (chairs, casters) regrets r_ij >= 0 [objective units], +inf where caster j is not allowed
    weights : (chairs,) counts w_i >= 0
    ks : the numbers of part numbers (each >= 1)
    time_limit : limit of each exact MIP [s]; a MIP stopped by it gives status "time limit"
    until : if given, go on past ``max(ks)`` (K + 1, K + 2, …) until the optimal total regret is at most
        ``until`` [objective units] or every useful caster is stocked

    Returns
    -------
    dict K -> :class:`KMedianSolution`, each proved optimal or infeasible unless a time limit hit.
    """
    t0 = time.perf_counter()
    inst = _Instance(cost, weights)
    setup = time.perf_counter() - t0
    out: dict[int, KMedianSolution] = {}
    start: list[int] = []
    lam: np.ndarray | None = None
    todo = sorted(ks)
    k = todo[0] if todo else 1
    while todo or (until is not None and out and k <= inst.n and out[max(out)].regret > until):
        out[k], lam = _solve(inst, k, start, lam, time_limit)
        if out[k].chosen:
            start = [int(np.flatnonzero(inst.cols == j)[0]) for j in out[k].chosen]
        if todo and todo[0] == k:
            todo.pop(0)
        k = todo[0] if todo else k + 1
    if out:
        first = out[min(out)]  # the shared reduction, counted once
        out[min(out)] = replace(first, seconds=first.seconds + setup)
    return out


def solve_kmedian(cost: np.ndarray, weights: np.ndarray, k: int, time_limit: float = 120.0) -> KMedianSolution:
    """Choose ``k`` columns of ``cost`` minimising Σ_i w_i min_{j chosen} cost_ij, every row served.

    Parameters
    ----------
    cost : (chairs, casters) regrets r_ij >= 0 [objective units], +inf where caster j is not allowed
    weights : (chairs,) counts w_i >= 0
    k : number of casters to choose (>= 1)
    time_limit : limit of the exact MIP [s]

    Returns
    -------
    KMedianSolution, proved optimal ("optimal" or "optimal-by-bound") or infeasible, unless the time limit hit.
    """
    return kmedian_curve(cost, weights, [k], time_limit=time_limit)[k]
