"""Check 8 on a computed Pareto front: the trade-off, the active shimmy constraint, the tighter target dominated."""

from __future__ import annotations

import dataclasses
import functools

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from designer.display import number, shown
from designer.problem import Problem
from designer.solvers.base import wheel_of
from designer.studies.checks._record import NOT_APPLICABLE, Check

if TYPE_CHECKING:  # record and solver types for the checker only: designer.studies.front loads casadi
    from designer.studies.front import Front, FrontPoint


def front_checks(front: Front, tighter: Front | None = None, tol: float = 1e-6) -> list[Check]:
    """Check 8 on a computed front: monotone trade-off, shimmy active where it can be, tighter target dominated.

    Parameters
    ----------
    front : designer.studies.front._pareto.Front
    tighter : optional front of the same problem with a higher V_target
    """
    checks = [_tradeoff_check(front.points, tol), _shimmy_active_check(front.problem, front.points, tol)]
    if tighter is not None:
        checks.append(_tighter_check(front, tighter))
    return [dataclasses.replace(c, kind="front") for c in checks]  # records do not change: new ones


def _tradeoff_check(pts: Sequence[FrontPoint], tol: float) -> Check:
    """8a: along decreasing threshold force P the diameter d and the turning effort F_turn do not fall."""
    check = functools.partial(
        Check,
        name="8a trade-off",
        claim="along decreasing threshold force the diameter grows and the turning effort grows",
    )
    if len(pts) < 2:
        return check(
            expected="monotone",
            got=f"{len(pts)} point(s): nothing to compare",
            passed=True,
            detail="a front with fixed diameter or one dominant catalog wheel has a single point",
        )
    p = np.array([x.threshold_force for x in pts])
    d = np.array([x.design.diameter for x in pts])
    f = np.array([x.turning_effort for x in pts])
    order = np.argsort(-p)
    dd = np.diff(d[order])
    df = np.diff(f[order])
    bad_d = int(np.sum(dd < -tol * d.max()))
    bad_f = int(np.sum(df < -tol * f.max()))
    return check(
        expected="d and F_turn non-decreasing as P falls",
        got=f"{bad_d} diameter and {bad_f} effort reversals in {len(pts)} points",
        passed=bad_d == 0 and bad_f == 0,
        detail=f"d {number(d.min(), 'diameter', 'in')}–{shown(d.max(), 'diameter', 'in')}, "
        f"F_turn {number(f.min(), 'turning_effort')}–{shown(f.max(), 'turning_effort')}",
    )


def _shimmy_active_check(problem: Problem, pts: Sequence[FrontPoint], tol: float) -> Check:
    """8b: the shimmy constraint (Eq. 7) is active wherever it can be."""
    # shimmy active wherever it can be: inactive only at the bare minimum-effort caster for that d
    lo = problem.lower()
    loose = [
        x
        for x in pts
        if x.margins.get("shimmy", x.critical_speed - problem.required_speed) > tol * problem.required_speed
    ]
    offending = sum(
        not (x.design.groove <= lo.groove + 1e-9 and x.design.damping <= lo.damping * (1 + 1e-9)) for x in loose
    )
    return Check(
        name="8b shimmy active",
        claim="the shimmy constraint is active wherever it can be",
        expected="inactive only on bare-fork designs (no groove, no damper)",
        got=f"{len(loose)} of {len(pts)} points inactive, {offending} of them with groove or damper",
        passed=offending == 0,
        detail="a groove or damper that is not needed for V_c only adds turning effort",
    )


def _tighter_check(front: Front, tighter: Front) -> Check:
    """8c: the front of a higher V_target is weakly dominated by ``front`` (not applicable when the tighter
    target is out of reach of the bounds)."""
    problem = front.problem
    check = functools.partial(
        Check,
        name="8c tighter target",
        claim="tightening V_target moves the front outward",
        expected="every point of the tighter front weakly dominated by the looser front",
    )
    if not tighter.points:
        from designer.solvers.nlp import max_critical_speed

        # the highest V_q (risk bound) or V_c inside the bounds, over the catalog wheels, by IPOPT
        speed = max(max_critical_speed(v)[0] for v in tighter.problem.variants())
        return check(
            got=f"not applicable: the tighter target is out of reach (highest {'V_c' if problem.risk is None else 'V_q'} "
            f"{shown(speed, 'critical_speed')} < {shown(tighter.problem.required_speed, 'critical_speed')} required)",
            passed=True,
            detail=f"tighter target {tighter.problem.target_speed:.3g} m/s vs {problem.target_speed:.3g} "
            f"m/s: no design inside the bounds reaches it, so there is no tighter front to compare",
            outcome=NOT_APPLICABLE,
        )
    worse, total = dominated_by_problem(problem, tighter)
    cmp = front.compare(tighter)
    return check(
        got=f"{total - worse} of {total} dominated; HV {cmp['hypervolume_self']:.4f} vs "
        f"{cmp['hypervolume_other']:.4f} (looser's normalisation)",
        passed=worse == 0 and total > 0,
        detail=f"tighter target {tighter.problem.target_speed:.3g} m/s vs {problem.target_speed:.3g} m/s; "
        f"exact test: the looser problem's min F_turn at each tighter point's P",
    )


def dominated_by_problem(problem: Problem, other_front: Front, rel_tol: float = 1e-7) -> tuple[int, int]:
    """Count points of ``other_front`` NOT weakly dominated by ``problem``'s exact front.

    For each point q, solves the ε-constraint NLP of ``problem`` at ε = P(q) from q's design
    (:func:`_dominated_in_batch`: warm from q's multipliers first, then cold for the points not yet seen
    dominated); q is dominated if the optimum's F_turn <= F_turn(q).
    Returns (number not dominated, number of points).
    """
    points = other_front.points
    found = _dominated_in_batch(problem, points, rel_tol)
    found |= _dominated_in_batch(problem, points, rel_tol, warm=False, skip=found)
    return len(points) - len(found), len(points)


def _dominated_in_batch(
    problem: Problem, points: Sequence[FrontPoint], rel_tol: float, warm: bool = True, skip: set[int] | None = None
) -> set[int]:
    """Indices of ``points`` (but ``skip``) that ``problem`` is seen to dominate: the NLPs of
    :func:`dominated_by_problem` in one batch per variant (of q's wheel, for a catalog problem), warm
    (``solve_many`` from q's multipliers as an optimum) or cold from q's design; a successful block with
    F_turn <= F_turn(q)(1 + ``rel_tol``) is a feasible design dominating q."""
    from designer.solvers.nlp import shared_nlp

    found: set[int] = set()
    for variant in problem.variants():
        wheel = wheel_of(variant) if problem.wheels else None
        idx = [k for k, q in enumerate(points) if k not in (skip or ()) and (wheel is None or q.wheel == wheel)]
        if not idx:
            continue
        nlp = shared_nlp(variant, same_scaling=True)  # the front's compiled NLP: the same solves as a new build
        x = np.array([points[k].design.as_array() for k in idx])
        caps = np.array([points[k].threshold_force * (1 + 1e-12) for k in idx])
        starts = dict(zip(("lam_g0", "lam_x0"), nlp.multipliers_many(x, (1.0, 0.0), caps))) if warm else {}
        results = nlp.solve_many(x, (1.0, 0.0), caps, **starts)
        f = nlp.objectives_many([r.design for r in results])[:, 0]
        found.update(
            k for k, r, fk in zip(idx, results, f) if r.success and fk <= points[k].turning_effort * (1 + rel_tol)
        )
    return found
