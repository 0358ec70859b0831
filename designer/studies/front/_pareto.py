"""Exact Pareto fronts of (turning effort, threshold force) by the ε-constraint method.

For a problem, :func:`pareto_front` computes the designs that minimise the
turning effort F_turn for every cap ε on the threshold force P:

    min F_turn(x)  s.t.  P(x) <= ε,  V_c(x) >= V_req (Eq. 7; its α-quantile with a risk bound),  bounds,  R_s <= R_max

on the CasADi NLP built once per problem structure (``designer.solvers.nlp.CasterNLP``).  For each
continuous sub-problem (one per catalog wheel):

1. the two lexicographic ends are found (min F_turn then min P, min P then min F_turn);
2. pass 1 gives the ε-optima at ε evenly spaced between the ends' P: the closed form's, unconfirmed, where it
   applies (they only space pass 2), else the NLP's;
3. pass 2 re-spaces ε evenly by arc length along pass 1's normalised front and solves every point by the NLP
   (the closed form's optima confirmed);
4. points that fail are kept as failed (never plotted or counted); dominated points are removed.

How an ε-point is solved is the front solver's (:func:`designer.solvers.front_solver`, through the solver
protocol): the closed-form ε-optima confirmed by the NLP where they apply (``strategy="auto"``), else the NLP
sweep from sample starts with family restarts; ``strategy="nlp"`` forces the NLP sweep (the cross-check in
the tests).  The front itself
(:class:`~designer.studies.front._front.Front`) is data: :mod:`designer.studies.front._front`.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

from designer.studies.front._front import REFERENCE_OFFSET, Front, FrontPoint, clean
from designer.studies.front._indicators import normalise
from designer.studies.optimum import diagnose_infeasible, margins_many
from designer.boundary import Count, checked
from designer.errors import InertiaExtrapolationWarning, InputError, ModelRangeWarning, SolverError
from designer.model import Design
from designer.problem import POINTS_RANGE, Problem, family_of, problem_argument
from designer.solvers import FRONT_STRATEGIES, Designs, front_solver, one_solve_at_a_time
from designer.solvers.base import OBJECTIVES, wheel_of
from designer.solvers.closed_form import CLOSED_FORM
from designer.solvers.nlp import BIG, Ends, NLPSolver

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

Progress: TypeAlias = Callable[[int, int], object]
"""A progress callback: ``progress(done, total)``."""

STRATEGY_CHOICES = FRONT_STRATEGIES
"""``pareto_front(strategy=...)``: "auto" (closed form confirmed by the NLP where it applies) or "nlp"."""


# --------------------------------------------------------------------------- front points


def _points(
    problem: Problem, found: Designs, wheel: str | None = None, eps: npt.ArrayLike | None = None
) -> list[FrontPoint]:
    """FrontPoints of a solver's ε-optima (``eps`` overrides their ε): the successful ones evaluated by the model
    in one vectorised call (their margins too), a failed one with the solver's own numbers and no margins."""
    caps = found.epsilon if eps is None else np.asarray(eps, float)
    out: list[FrontPoint] = []
    ok = np.flatnonzero(found.success).tolist()
    values = problem.evaluate(found.designs[ok]) if ok else None
    rows = dict(zip(ok, values.rows())) if values is not None else {}
    margins = dict(zip(ok, margins_many(problem, found.designs[ok], values))) if values is not None else {}
    for i in range(len(found)):
        design, row = found.design(i), rows.get(i)
        numbers = found.objectives[i] if row is None else [getattr(row, n) for n in OBJECTIVES]
        point = FrontPoint(
            design=design,
            **{n: float(x) for n, x in zip(OBJECTIVES, numbers)},
            margins=margins.get(i, {}),
            epsilon=float(caps[i]),
            status=found.status[i],
            success=bool(found.success[i]),
            multipliers=dict(found.multipliers[i]) if found.multipliers else {},
            family=family_of(problem, design),
            wheel=wheel,
            caster=row,
        )
        out.append(point)
    return out


@checked(points=Count(2, POINTS_RANGE[1], optional=True, what="front points"))
@one_solve_at_a_time
def pareto_front(
    problem: Problem,
    points: int | None = None,
    progress: Progress | None = None,
    strategy: str = "auto",
    *,
    knee: bool = True,
) -> Front:
    """Exact Pareto front of (turning effort, threshold force) for ``problem``.

    Parameters
    ----------
    problem : the problem (catalog problems: one point per wheel, dominated ones removed)
    points : number of points (default ``problem.pareto_points``)
    progress : optional callable ``progress(done, total)`` for long runs
    strategy : "auto" (closed-form ε-optima confirmed by the NLP where they apply, else the NLP sweep)
        or "nlp" (the NLP sweep everywhere); :func:`designer.solvers.front_solver`
    knee : search the continuous front's knee (:func:`_continuous_knee`, a dozen ε-solves); False leaves
        ``continuous_knee`` None (``Front.knee`` is then the farthest sample), for a front whose knee nothing reads

    Returns
    -------
    Front
    """
    problem = problem_argument(problem)
    # points: its two ends at least (0 is refused, not the problem's 41); memory grows with n × the 1024-design sample
    n = problem.pareto_points if points is None else points
    if strategy not in STRATEGY_CHOICES:
        raise InputError(f"strategy = {strategy!r}: expected one of {', '.join(STRATEGY_CHOICES)}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaExtrapolationWarning)
        front = _pareto_front(problem, n, progress, strategy, knee)
    # once, and only if a front point uses an extrapolated diameter (not because the bounds reach there)
    for message in problem.model_warnings([p.design.diameter for p in front.points], front=True):
        warnings.warn(message, ModelRangeWarning, stacklevel=2)
    return front


# long: the per-variant steps (ends, two passes, points) and the run metadata in one readable loop
def _pareto_front(problem: Problem, n: int, progress: Progress | None, strategy: str, knee: bool = True) -> Front:
    t0 = time.perf_counter()
    report = progress or (lambda done, total: None)
    all_points: list[FrontPoint] = []
    failed: list[FrontPoint] = []
    build = 0.0
    solves = 0
    end_statuses: set[str] = set()
    used: dict[str, str] = {}
    variants = problem.variants()
    sweep: tuple[Problem, NLPSolver, Ends, Designs, str | None] | None = (
        None  # the one continuous sweep's (problem, solver, ends, second pass, wheel): its knee
    )
    for k, variant in enumerate(variants):
        solver = front_solver(variant, strategy)
        used[solver.strategy] = solver.method
        wheel = wheel_of(variant) if problem.wheels else None
        ends = solver.front_ends(variant)
        solves += ends.solves
        if ends.a is None:
            end_statuses.update(ends.statuses)
            build += solver.build_seconds(variant)
            continue  # infeasible variant (e.g. a catalog wheel that cannot reach the target)
        if variant.bounds["diameter"].fixed:  # P is the same for every design: the front is end B
            all_points += _points(variant, solver.ends_designs(variant, ends, eps=[BIG, BIG]), wheel)[1:]
            build += solver.build_seconds(variant)
            report(k + 1, len(variants))
            continue
        p_a, p_b = (float(v) for v in solver.ends_designs(variant, ends).epsilon)
        eps = np.linspace(p_a, p_b, n)  # pass 1: uniform in ε (closed-form points are not confirmed here)
        first = solver.first_pass(variant, eps, ends=ends)
        solves += first.solves
        report(n, 2 * n)
        good = first.success
        if np.count_nonzero(good) >= 3:  # pass 2: uniform in arc length of pass 1, every point solved
            eps2 = _respace_objectives(first.objectives[good, :2], n)
            second = solver.front_designs(variant, eps2, ends=ends, guide=first if first.results else None)
            solves += second.solves
        elif first.results:  # pass 1 was solved: its points are the front
            second = first
        else:
            second = solver.front_designs(variant, eps, ends=ends)
            solves += second.solves
        pts = _points(variant, second, wheel)
        sweep = (variant, solver, ends, second, wheel)
        report(2 * n, 2 * n)
        all_points += [p for p in pts if p.success]
        failed += [p for p in pts if not p.success]
        build += solver.build_seconds(variant)
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
    found = _continuous_knee(valid, *sweep) if knee and sweep is not None and len(variants) == 1 else None
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
    return Front(problem=problem, points=valid, failed=failed, meta=meta, continuous_knee=found)


KNEE_TOLERANCE = 1e-6
"""The knee's ε is found to this fraction of the front's P range [-] (far below the 1 % at which two samplings of
one front must agree: the knee then moves by less than the solver's own tolerance)."""


GOLDEN = (5**0.5 - 1) / 2
"""The golden ratio's conjugate 0.618...: each step of :func:`golden_section` keeps this fraction of the bracket."""


def golden_section(func: Callable[[float], float], low: float, high: float, tolerance: float) -> float:
    """The minimiser of a unimodal ``func`` on [low, high] to ``tolerance`` by golden-section search (one new
    evaluation a step, the bracket shrinking by 0.618; Kiefer 1953).  Hand-written rather than SciPy's bounded
    Brent: the main job's process imports no SciPy (tests/report/test_pipeline.py), and the knee needs nothing
    faster (about 25 evaluations of a cheap ε-optimum)."""
    a, b = low, high
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = func(c), func(d)
    while b - a > tolerance:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = func(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = func(d)
    return c if fc <= fd else d


def _continuous_knee(
    points: list[FrontPoint], problem: Problem, solver: NLPSolver, ends: Ends, guide: Designs, wheel: str | None
) -> FrontPoint | None:
    """The knee of the continuous front: the ε-optimum farthest from the chord between the front's two ends, in
    objectives normalised by the front's ideal and nadir, on the ideal's side; None when no point bulges toward
    the ideal (a concave or straight front) or the front has fewer than three points.

    The samples only bracket it: a bounded scalar search (:func:`golden_section`) on ε between the neighbours
    of the farthest sample solves the ε-constrained problem min F_turn s.t. P <= ε at
    each trial ε (the closed form where it applies, else the NLP warm from the sweep), and the knee's ε-optimum
    is solved and confirmed as every front point is.  So the knee is a point of the front, not of its sampling:
    11 and 41 points give the same knee."""
    if len(points) < 3:
        return None
    f = np.array([[p.turning_effort, p.threshold_force] for p in points])
    ideal, nadir = f.min(axis=0), f.max(axis=0)
    span = nadir - ideal
    if np.any(span <= 0):
        return None
    a, b = (f[0] - ideal) / span, (f[-1] - ideal) / span
    chord = b - a
    norm = float(np.hypot(*chord))

    def bulge(objectives: np.ndarray) -> np.ndarray:
        """Signed distance from the chord, positive toward the ideal [-]."""
        g = (np.atleast_2d(objectives) - ideal) / span
        return np.asarray(((g[:, 0] - a[0]) * chord[1] - (g[:, 1] - a[1]) * chord[0]) / norm, dtype=float)

    distance = bulge(f)
    i = int(np.argmax(distance))
    if distance[i] <= 0 or i in (0, len(points) - 1):
        return None
    low, high = points[i + 1].threshold_force, points[i - 1].threshold_force  # points by decreasing P
    closed = solver.strategy == "structured"

    def solved(eps: float) -> Designs:
        if closed:
            return CLOSED_FORM.front_designs(problem, [eps])
        found: Designs = solver.front_designs(
            problem, [high, eps, low], ends=ends, guide=guide if guide.results else None
        )
        return found

    def worst(eps: float) -> float:
        found = solved(eps)
        row = 1 if len(found) == 3 else 0
        if not found.success[row]:
            return 1.0  # a failed trial is never the knee
        return -float(bulge(found.objectives[row, :2])[0])

    eps = golden_section(worst, low, high, KNEE_TOLERANCE * span[1])
    found = solver.front_designs(problem, [high, eps, low], ends=ends, guide=guide if guide.results else None)
    point = _points(problem, found, wheel)[1]
    if not point.success or bulge(np.array([point.turning_effort, point.threshold_force]))[0] < distance[i]:
        return points[i]  # the search could not better the farthest sample: it is the knee to the solver's accuracy
    return point


def _respace_objectives(f: np.ndarray, n: int) -> np.ndarray:
    """ε values evenly spaced by arc length along the normalised front with objectives ``f`` (F, P)."""
    g = normalise(f, f.min(axis=0), f.max(axis=0))
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(g, axis=0).T))])
    if s[-1] <= 0:
        return f[:, 1].copy()
    targets = np.linspace(0, s[-1], n)
    eps: np.ndarray = np.interp(targets, s, f[:, 1])
    return eps


__all__ = ["REFERENCE_OFFSET", "STRATEGY_CHOICES", "Design", "Front", "FrontPoint", "family_of", "pareto_front"]
