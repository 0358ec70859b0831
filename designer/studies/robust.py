"""Nominal against risk-bounded design: the price of safety, checked by Monte Carlo.

The risk law itself (the scatter, the V_c quantile) lives in :mod:`designer.physics.uncertainty` and
its Monte Carlo estimate in the model's evaluator (:func:`designer.model.evaluate`); this
module compares the nominal and the risk-bounded Pareto fronts of one problem.
"""

from __future__ import annotations

import numpy as np

from designer.model import evaluate, scatter_of

# --------------------------------------------------------------------------- nominal vs robust


ROBUST_POINTS = 21
"""Default points per front of the robust comparison (``designer robust``): fewer than a report's 41
(``[pareto] points``) because it solves two fronts and runs two Monte Carlo checks per point (the risk-bounded
point and the nominal one at the same sill force); 21 points resolve the price of safety, which varies
smoothly along the front."""


def robust_comparison(problem, points: int = ROBUST_POINTS) -> dict:
    """Nominal and risk-bounded Pareto fronts of the same problem, and the price of safety.

    The risk-bounded problem is ``problem`` with its risk bound (every problem carries one by default;
    with ``[robust] enabled = false`` the default scatter, :func:`designer.model.scatter_of`); the nominal problem is
    the same without it.  Returns a dict with both fronts, the Monte Carlo probability of shimmy (with its
    SE, own seed) of every risk-bounded point and of the nominal point at the same sill force, and the
    price of safety: the extra turning effort at equal threshold force (interpolated on the nominal front).
    """
    from designer.studies.front import pareto_front

    u = scatter_of(problem.conditions)
    problem = problem.replace(conditions=problem.conditions.replace(uncertainty=u))
    nominal_problem = problem.nominal()
    nominal = pareto_front(nominal_problem, points=points)
    robust = pareto_front(problem, points=points)
    rows = []
    fn = nominal.objectives()
    order = np.argsort(fn[:, 1])
    for point in robust:
        d = point.design
        cond = problem.conditions
        if problem.wheels:
            cond = [v for v in problem.variants() if v.conditions.inertia.wheel.key == point.wheel][0].conditions
        risk = evaluate([d], cond, risk=problem.required_speed)
        p_mc, se = float(risk.shimmy_probability[0]), float(risk.shimmy_probability_se[0])
        p_nom = float("nan")
        if len(nominal):  # the nominal front's design nearest in threshold force
            at = nominal.points[int(np.argmin(np.abs(fn[:, 1] - point.threshold_force)))].design
            p_nom = float(evaluate([at], cond, risk=problem.required_speed).shimmy_probability[0])
        # the nominal front as min F_turn s.t. P <= P_point: beyond its largest P, its least F_turn
        f_nominal = float(np.interp(point.threshold_force, fn[order, 1], fn[order, 0], left=np.nan))
        rows.append(
            {
                "threshold_force": point.threshold_force,
                "turning_effort_robust": point.turning_effort,
                "turning_effort_nominal": f_nominal,
                "extra_effort": point.turning_effort - f_nominal,
                "critical_speed": point.critical_speed,
                "probability_mc": p_mc,
                "probability_mc_se": se,
                "nominal_probability_mc": p_nom,
            }
        )
    cmp = nominal.compare(robust) if len(nominal) and len(robust) else {}
    return {"nominal": nominal, "robust": robust, "rows": rows, "compare": cmp, "uncertainty": u}
