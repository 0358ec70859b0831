"""Compute once: a problem becomes the data of its report (:class:`ReportData`).

One function, :func:`report_data`, runs everything a Pareto report shows, in this order:

1. the front the problem asks for (risk-bounded by default, nominal with ``[robust] enabled = false``);
2. the front for V_target × 1.1 (check 8c);
3. the recommendation (:func:`designer.studies.recommend._recommend.recommend`): the caster to build,
   every other caster of the buildable front (its alternatives), the buildable and the continuous
   risk-bounded fronts; the knock-safe speeds of the recommendation and its alternatives (knocks of θ0 and 2 θ0, simulated);
4. the weighted optimum J = w_turn F_turn + w_threshold P (NLP only; the GP and SLSQP cross-check only
   with ``cross_check=True``, i.e. ``designer pareto --cross-check``);
5. the paper checks and check 8 on the front;
6. the groove–damper table, in closed form (:mod:`designer.studies.front._tradeoff`);
7. run metadata: versions, problem digest, CPU and wall seconds of every step.

The CLI (``designer pareto``, ``--all``), the Python API (``designer.report_data``) and the studio call it
and hand the result to :func:`designer.report.write_report`, which renders it and computes nothing.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import time
from collections.abc import Callable, Iterator
import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.display import shown
from designer.errors import DesignerError, InertiaExtrapolationWarning, ModelRangeWarning
from designer.problem import Problem
from designer.reportdata import ReportData, RobustData
from designer.versions import versions
from designer.studies import checks as study_checks
from designer.studies.curves import report_curves
from designer.studies.dynamics.limit_cycles import knock_safe_speeds
from designer.studies.recommend import recommend
from designer.studies.robust import ROBUST_POINTS, robust_comparison

if TYPE_CHECKING:  # record types for the checker only: designer.studies.front and .optimum load casadi
    from designer.studies.checks import Check, CheckValue
    from designer.studies.front import Front, TradeoffRow
    from designer.studies.optimum import Solution
    from designer.studies.recommend import Recommendation

TIGHTER_FACTOR = 1.1
"""Check 8c tightens V_target by this factor."""


def degenerate_reason(problem: Problem, front: Front) -> tuple[str, str]:
    """(sentence, short phrase) explaining why a front has fewer than two points; ("", "") otherwise."""
    pts = front.points
    if len(pts) >= 2:
        return "", ""
    if not pts:
        return (
            "No design on the front: every point failed or the target speed is out of reach inside the bounds "
            "(see the failed points).",
            "no feasible design",
        )
    p = pts[0]
    if problem.wheels:
        n = len(problem.wheels)
        return (
            f"Catalog problem: each of the {n} Table 1 wheels offered ({', '.join(problem.wheels)}) gives its "
            f"own front, and the wheels' fronts are merged keeping only non-dominated designs. Wheel {p.wheel} "
            f"(d = {shown(p.design.diameter, 'diameter', problem.units)}) has the lowest threshold force of the "
            f"catalog and also reaches V_req = {shown(problem.required_speed, 'critical_speed')} with the least "
            f"turning effort ({shown(p.turning_effort, 'turning_effort')}), so no other wheel is better in either "
            "objective (wheels that tie are kept once): the front is this single design.",
            f"wheel {p.wheel} is best in both objectives",
        )
    if problem.bounds["diameter"].fixed:
        return (
            f"The wheel diameter is fixed at {shown(problem.bounds['diameter'].low, 'diameter', problem.units)}, so the "
            f"threshold force P = L·P/L(d/h) (Eq. 4A) is the same, {shown(p.threshold_force, 'threshold_force')}, for "
            "every design: the two objectives do not conflict and the front is the single design of least turning "
            "effort.",
            f"fixed diameter, P = {shown(p.threshold_force, 'threshold_force')} for every design",
        )
    return (
        "One design is best in both objectives, so the front collapses to a single point.",
        "one design is best in both objectives",
    )


def price_of_stock(front: Front, recommendation: Recommendation | None) -> dict[str, float | None] | None:
    """What building from stock costs against the continuous front, in each objective.

    ``extra`` [N]: the recommendation's F_turn minus the continuous front's at equal sill force, the front read
    as the ε-constraint optimum min F_turn s.t. P <= P_rec (linear between the two points around P_rec; its
    least F_turn beyond its largest P).  ``extra_threshold`` [N]: the recommendation's P minus the front's at
    equal turning effort (min P s.t. F_turn <= F_rec; None when F_rec is below the front's least F_turn).
    Returns None when P_rec is below the front's least P or the front has fewer than two points.
    """
    if recommendation is None or len(front.points) < 2:
        return None
    f = front.objectives()
    p = float(recommendation.threshold_force)
    built = float(recommendation.turning_effort)
    by_p = np.argsort(f[:, 1])
    if p < float(f[by_p[0], 1]) * (1 - 1e-9):
        return None
    cont = float(np.interp(p, f[by_p, 1], f[by_p, 0]))
    by_f = np.argsort(f[:, 0])
    p_cont = None
    if built >= float(f[by_f[0], 0]) * (1 - 1e-9):
        p_cont = float(np.interp(built, f[by_f, 0], f[by_f, 1]))
    return {
        "threshold_force": p,
        "turning_effort_buildable": built,
        "turning_effort_continuous": cont,
        "extra": built - cont,
        "relative": (built - cont) / cont if cont > 0 else float("nan"),
        "threshold_force_continuous": p_cont,
        "extra_threshold": None if p_cont is None else p - p_cont,
    }


def card_knock_safe(problem: Problem, recommendation: Recommendation) -> list[dict[str, float]]:
    """Knock-safe speeds (θ0 and 2 θ0 knocks) of the recommendation and its alternatives, in card order [m/s]: the
    :class:`~designer.studies.dynamics.limit_cycles.KnockSafe` records as plain dicts (the report data's shape)."""

    casters = [recommendation, *(getattr(recommendation, "alternatives", None) or [])]
    # each caster's own I_w (a catalogue or stock wheel's measured one): the I_w its V_c was computed with
    speeds = knock_safe_speeds(
        [c.design for c in casters], problem.conditions, inertias=[getattr(c, "inertia", None) for c in casters]
    )
    return [k.to_dict() for k in speeds]


class _Clock:
    """CPU and wall seconds of named steps (``run["cpu"]`` and ``run["seconds"]``)."""

    def __init__(self) -> None:
        self.cpu: dict[str, float] = {}
        self.wall: dict[str, float] = {}

    @contextlib.contextmanager
    def __call__(self, name: str) -> Iterator[None]:
        cpu, wall = time.process_time(), time.perf_counter()
        try:
            yield
        finally:
            self.cpu[name] = self.cpu.get(name, 0.0) + time.process_time() - cpu
            self.wall[name] = self.wall.get(name, 0.0) + time.perf_counter() - wall


def _recommend(problem: Problem, front: Front) -> tuple[Recommendation | None, str]:
    """The recommendation of ``problem`` (its continuous front is ``front``): (Recommendation or None, reason
    when None)."""

    try:
        return recommend(problem, front=front), ""
    except DesignerError as exc:
        return None, str(exc)


def _stamp(problem: Problem) -> dict[str, Any]:
    """The run metadata every computed report starts with: the date, the library versions, the problem's digest."""
    date = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    return {"date": date, "versions": versions(), "problem_digest": problem.digest()}


# long: the pipeline's steps in order (front, optimum, recommendation, checks, trade-off)
def report_data(
    problem: Problem,
    points: int | None = None,
    *,
    front: Front | None = None,
    tighter: Front | None = None,
    recommendation: Recommendation | None = None,
    solution: Solution | None = None,
    checks: list[Check] | None = None,
    tradeoff: list[TradeoffRow] | None = None,
    cross_check: bool = False,
    with_tighter: bool = True,
    with_recommendation: bool = True,
    with_knock_safe: bool = True,
    progress: Callable[[str], Callable[[int, int], object] | None] | None = None,
    run_meta: dict[str, Any] | None = None,
) -> ReportData:
    """Compute everything the Pareto report of ``problem`` shows.

    Parameters
    ----------
    problem : designer.problem.Problem
    points : front points (default the problem's ``[pareto] points``)
    front, tighter, recommendation, solution, checks, tradeoff : optional precomputed parts (then not recomputed)
    cross_check : also run the GP and SLSQP cross-check of the weighted optimum (about 1 s of CPU)
    with_tighter : compute the V_target × 1.1 front for check 8c
    with_recommendation : compute the recommendation
    with_knock_safe : simulate the knock-safe speeds of the recommendation and its alternatives (about
        0.05–0.1 s of CPU per caster)
    progress : ``callable(label) -> callable(done, total) | None`` for the sweeps' progress bars
    run_meta : extra metadata merged into ``run``

    Returns
    -------
    ReportData
    """
    from designer.studies.optimum import optimise
    from designer.studies.front import pareto_front

    from designer.studies.front import groove_damper_tradeoff

    clock = _Clock()
    wall0 = time.perf_counter()
    track = progress or (lambda label: None)
    tighter_error: CheckValue = None
    n_tight = None
    recommendation_error = solution_error = ""
    price: dict[str, float | None] | None = None
    knock_safe: list[dict[str, float]] = []
    band: dict[str, float] | None = None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaExtrapolationWarning)
        warnings.simplefilter("ignore", ModelRangeWarning)
        with clock("front"):
            if front is None:
                front = pareto_front(problem, points, progress=track(f"{problem.name}: front"))
        if not front.points and not front.failed:  # the problem itself is infeasible: `designer run`'s exit 4
            from designer.studies.optimum import diagnose_infeasible

            raise diagnose_infeasible(problem)
        with clock("tighter"):
            if tighter is None and with_tighter and checks is None:
                tighter_problem = problem.replace(target_speed=problem.target_speed * TIGHTER_FACTOR)
                n_tight = max(5, (points or problem.pareto_points) // 2)
                bar = track(f"{problem.name}: front at {shown(tighter_problem.target_speed, 'target_speed')}")
                try:  # check 8c reads its points, never its knee
                    tighter = pareto_front(tighter_problem, n_tight, progress=bar, knee=False)
                except DesignerError as exc:  # an unreachable tighter target only removes check 8c
                    tighter, tighter_error = None, str(exc)
        with clock("recommendation"):
            if recommendation is None and with_recommendation:
                recommendation, recommendation_error = _recommend(problem, front)
            elif recommendation is None:
                recommendation_error = "not computed"
        if recommendation is not None:
            price = price_of_stock(front, recommendation)
            if with_knock_safe:
                with clock("knock_safe"):
                    knock_safe = card_knock_safe(problem, recommendation)
                    band = study_checks.knock_safe_table1_error(float(problem.conditions.disturbance_angle))
        with clock("optimum"):
            if solution is None and front.points:
                try:
                    solution = optimise(problem, cross_check=cross_check)
                except DesignerError as exc:
                    solution_error = str(exc)
            elif solution is None:
                solution_error = "no valid point on the front"
        with clock("checks"):
            if checks is None:
                # an empty tighter front: 8c not applicable
                checks = (
                    study_checks.paper_checks() + study_checks.law_checks() + study_checks.front_checks(front, tighter)
                )
        if tighter is not None and not tighter.points:
            tighter_error = next((c.got for c in checks if c.name.startswith("8c")), "no point at the tighter target")
            tighter = None
        with clock("tradeoff"):
            if tradeoff is None:
                tradeoff = groove_damper_tradeoff(problem)
        with clock("curves"):
            # the groove–damper plane's design: the weighted optimum's, else the front's weighted best point's
            best = solution if solution is not None else front.weighted_best()
            conditions = solution.problem.conditions if solution is not None else problem.conditions
            curves = report_curves(problem, front, *((best.design, conditions) if best is not None else (None, None)))
    paper_checks = [c for c in checks if not c.name.startswith("8")]
    front_checks = [c for c in checks if c.name.startswith("8")]
    reason, reason_short = degenerate_reason(problem, front)
    run = {
        **_stamp(problem),
        "front_solver": {
            k: front.meta.get(k)
            for k in ("method", "solver", "points_requested", "points_valid", "points_failed", "nlp_solves")
        },
        "front_seconds": front.meta.get("total_seconds"),
        "optimum_seconds": sum(solution.timings.values()) if solution is not None else None,
        "tighter_target_speed": tighter.problem.target_speed if tighter is not None else None,
        "tighter_seconds": tighter.meta.get("total_seconds") if tighter is not None else None,
        "tighter_points": n_tight if tighter is not None else None,
        "tighter_error": tighter_error,
        "cross_check": bool(cross_check),
        "compute_cpu_seconds": dict(clock.cpu),
        "compute_wall_seconds": time.perf_counter() - wall0,
        **(run_meta or {}),
    }
    return ReportData(
        problem=problem,
        front=front,
        tighter=tighter,
        recommendation=recommendation,
        recommendation_error=recommendation_error,
        price_of_stock=price,
        knock_safe=knock_safe,
        solution=solution,
        solution_error=solution_error,
        cross_checked=bool(solution is not None and len(getattr(solution, "cross_check", {})) > 1),
        paper_checks=paper_checks,
        front_checks=front_checks,
        checks_summary=study_checks.summary_line(paper_checks + front_checks),
        knock_safe_band=band,
        tradeoff=tradeoff,
        curves=curves,
        gaps=front.gaps(),
        degenerate_reason=reason,
        degenerate_reason_short=reason_short,
        run=run,
    )


def robust_data(problem: Problem, points: int = ROBUST_POINTS) -> RobustData:
    """Compute the price of safety of ``problem`` (:func:`designer.studies.robust.robust_comparison`)."""

    c0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaExtrapolationWarning)
        warnings.simplefilter("ignore", ModelRangeWarning)
        result = robust_comparison(problem, points)
    run = {**_stamp(problem), "points": points, "compute_cpu_seconds": time.process_time() - c0}
    parts = {k: result[k] for k in ("nominal", "robust", "rows", "compare", "uncertainty")}
    return RobustData(problem=problem, **parts, run=run)


__all__ = [
    "ReportData",
    "RobustData",
    "robust_data",
    "ROBUST_POINTS",
    "TIGHTER_FACTOR",
    "card_knock_safe",
    "degenerate_reason",
    "price_of_stock",
    "report_data",
]
