"""Exact Pareto fronts of (turning effort, threshold force) by the ε-constraint method.

For a problem, :func:`pareto_front` computes the designs that minimise the
turning effort F_turn for every cap ε on the threshold force P:

    min F_turn(x)  s.t.  P(x) <= ε,  V_c(x) >= V_req (Eq. 7; its α-quantile with a risk bound),  bounds,  R_s <= R_max

on the CasADi NLP built once per problem structure (``designer.solvers.nlp.CasterNLP``).  For each
continuous sub-problem (one per catalog wheel):

1. the two lexicographic ends are found (min F_turn then min P, min P then min F_turn);
2. pass 1 solves ε evenly spaced between the ends' P;
3. pass 2 re-spaces ε evenly by arc length along pass 1's normalised front and solves again;
4. points that fail are kept as failed (never plotted or counted); dominated points are removed.

How an ε-point is solved is the sweep strategy (:mod:`designer.studies.front._sweeps`): the closed-form ε-optima
confirmed by the NLP where they apply (``strategy="auto"``), else the NLP sweep from sample starts with
family restarts; ``strategy="nlp"`` forces the NLP sweep (the cross-check in the tests).  The front itself
(:class:`~designer.studies.front._front.Front`) is data: :mod:`designer.studies.front._front`.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from designer.studies.front._front import REFERENCE_OFFSET, Front, FrontPoint, clean, family_of
from designer.studies.front._indicators import normalise
from designer.studies.optimum import diagnose_infeasible, constraint_margins
from designer.studies.front._sweeps import choose
from designer.errors import InputError, SolverError
from designer.model import Design, evaluate
from designer.problem import POINTS_RANGE, Problem
from designer.solvers import cache
from designer.solvers.nlp import BIG, CasterNLP, evaluate_many

STRATEGY_CHOICES = ("auto", "nlp")
"""``pareto_front(strategy=...)``: "auto" (closed form confirmed by the NLP where it applies) or "nlp"."""


# --------------------------------------------------------------------------- front points


def _point(nlp: CasterNLP, problem: Problem, result, epsilon: float, wheel=None) -> FrontPoint:
    values = evaluate(result.design, problem.conditions) if result.success else None
    if values is None:
        f, p, v, _ = nlp.objectives(result.design)
        margins = {}
    else:
        f, p, v = values["turning_effort"], values["threshold_force"], values["critical_speed"]
        margins, _ = constraint_margins(problem, result.design, values)
    multipliers = {name: float(lam) for name, lam in zip(nlp.constraint_names, result.lam_g)}
    return FrontPoint(
        result.design,
        float(f),
        float(p),
        float(v),
        margins,
        float(epsilon),
        result.status,
        result.success,
        multipliers,
        family_of(problem, result.design),
        wheel,
    )


def _points(nlp: CasterNLP, problem: Problem, results, eps, wheel=None) -> list:
    """FrontPoints of many results: one vectorised model call for all successful designs."""
    out = [None] * len(results)
    ok = [i for i, r in enumerate(results) if r.success]
    if ok:
        designs = np.array([results[i].design.as_array() for i in ok])
        values = evaluate_many(problem, designs)
        columns = {
            key: np.asarray(v, float).ravel().tolist() if np.ndim(v) else [float(v)] * len(ok)
            for key, v in values.items()
        }
        for j, i in enumerate(ok):
            r = results[i]
            row = {key: column[j] for key, column in columns.items()}
            margins, _ = constraint_margins(problem, r.design, row)
            multipliers = dict(zip(nlp.constraint_names, np.asarray(r.lam_g, float).tolist()))
            out[i] = FrontPoint(
                r.design,
                row["turning_effort"],
                row["threshold_force"],
                row["critical_speed"],
                margins,
                float(eps[i]),
                r.status,
                True,
                multipliers,
                family_of(problem, r.design),
                wheel,
            )
    for i, r in enumerate(results):
        if out[i] is None:
            out[i] = _point(nlp, problem, r, eps[i], wheel)
    return out


_NLP_CACHE = cache.SHARED
"""The compiled NLPs (:data:`designer.solvers.cache.SHARED`, shared with the optimum and check 8c)."""


def _nlp(problem: Problem) -> CasterNLP:
    """The problem's NLP: a compiled structure is built once and reused (:func:`~designer.solvers.cache.shared_nlp`).

    Problems that differ only in caster load or target speed (e.g. a batch of chair configurations, or the
    tighter front of check 8c) share one build: those values are parameters of the NLP, and
    :meth:`CasterNLP.for_problem` gives each problem its own view with its own values (the cached NLP itself
    is never changed).  The scaling constants of the objective stay those of the first problem built (any
    O(1) scaling gives the same optimum to IPOPT's tolerance).
    """
    return cache.shared_nlp(problem, build=CasterNLP)


def pareto_front(problem: Problem, points: int | None = None, progress=None, strategy: str = "auto") -> Front:
    """Exact Pareto front of (turning effort, threshold force) for ``problem``.

    Parameters
    ----------
    problem : the problem (catalog problems: one point per wheel, dominated ones removed)
    points : number of points (default ``problem.pareto_points``)
    progress : optional callable ``progress(done, total)`` for long runs
    strategy : "auto" (closed-form ε-optima confirmed by the NLP where they apply, else the NLP sweep)
        or "nlp" (the NLP sweep everywhere); :mod:`designer.studies.front._sweeps`

    Returns
    -------
    Front
    """
    if points is not None and (isinstance(points, bool) or not isinstance(points, (int, np.integer))):
        raise InputError(f"points = {points!r}: expected a whole number of front points, e.g. 41")
    n = int(points or problem.pareto_points)
    if not 2 <= n <= POINTS_RANGE[1]:  # memory grows with n × the 1024-design sample: bounded, never MemoryError
        raise InputError(f"points = {n}: a front needs 2 to {POINTS_RANGE[1]} points")
    if strategy not in STRATEGY_CHOICES:
        raise InputError(f"strategy = {strategy!r}: expected one of {', '.join(STRATEGY_CHOICES)}")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="inertia power law used at")
        front = _pareto_front(problem, n, progress, strategy)
    # once, and only if a front point uses an extrapolated diameter (not because the bounds reach there)
    for message in problem.model_warnings([p.design.diameter for p in front.points]):
        warnings.warn(message, UserWarning, stacklevel=2)
    return front


# long: the per-variant steps (ends, two passes, points) and the run metadata in one readable loop
def _pareto_front(problem: Problem, n: int, progress, strategy: str) -> Front:
    t0 = time.perf_counter()
    all_points: list[FrontPoint] = []
    failed: list[FrontPoint] = []
    build = 0.0
    solves = 0
    end_statuses: set = set()
    used: dict = {}
    variants = problem.variants()
    for k, variant in enumerate(variants):
        nlp = _nlp(variant)
        kind = choose(variant, strategy)
        used[kind.name] = kind.method
        sweeper = kind(nlp, variant)
        wheel = variant.conditions.inertia.wheel.key if problem.wheels else None
        ends = sweeper.ends()
        solves += ends.solves
        if ends.a is None:
            end_statuses.update(ends.statuses)
            build += nlp.build_seconds
            continue  # infeasible variant (e.g. a catalog wheel that cannot reach the target)
        if variant.bounds["diameter"].fixed:  # P is the same for every design: the front is end B
            all_points += _points(nlp, variant, [ends.b], [BIG], wheel)
            build += nlp.build_seconds
            if progress:
                progress(k + 1, len(variants))
            continue
        p_a, p_b = (float(v) for v in nlp.objectives_many([ends.a.design, ends.b.design])[:, 1])
        eps = np.linspace(p_a, p_b, n)  # pass 1: uniform in ε
        first, done = sweeper.sweep(eps, ends)
        solves += done
        if progress:
            progress(n, 2 * n)
        good = [r for r in first if r.success]
        if len(good) >= 3:  # pass 2: uniform in arc length of pass 1
            eps2 = _respace_objectives(nlp.objectives_many([r.design for r in good])[:, :2], n)
            second, done = sweeper.sweep(eps2, ends, guide=(eps, first))
            solves += done
        else:
            second, eps2 = first, eps
        pts = _points(nlp, variant, second, eps2, wheel)
        if progress:
            progress(2 * n, 2 * n)
        all_points += [p for p in pts if p.success]
        failed += [p for p in pts if not p.success]
        build += nlp.build_seconds
    if not all_points and not failed:
        # no end of any front was found: an unreachable target gives an empty front (the report explains it),
        # but IPOPT failing on a feasible problem must not pass for one
        error = diagnose_infeasible(problem)
        if isinstance(error, SolverError):
            raise SolverError(
                f"Pareto front of {problem.name!r}: IPOPT found neither end of the front from any "
                f"start (IPOPT status: {', '.join(sorted(end_statuses)) or 'unknown'}); {error}"
            )
    valid = clean(all_points)
    meta = {
        "points_requested": n,
        "points_valid": len(valid),
        "points_failed": len(failed),
        "build_seconds": build,
        "total_seconds": time.perf_counter() - t0,
        "nlp_solves": solves,
        "strategy": "+".join(used),
        "method": "; ".join(used.values()),
        "solver": "ipopt (tol 1e-10, exact Hessian)",
    }
    return Front(problem, valid, failed, meta)


def _respace_objectives(f: np.ndarray, n: int) -> np.ndarray:
    """ε values evenly spaced by arc length along the normalised front with objectives ``f`` (F, P)."""
    ideal, nadir = f.min(axis=0), f.max(axis=0)
    g = normalise(f, ideal, nadir)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(g, axis=0).T))])
    if s[-1] <= 0:
        return f[:, 1].copy()
    targets = np.linspace(0, s[-1], n)
    return np.interp(targets, s, f[:, 1])


__all__ = ["REFERENCE_OFFSET", "STRATEGY_CHOICES", "Design", "Front", "FrontPoint", "family_of", "pareto_front"]
