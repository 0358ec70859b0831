"""Nominal against risk-bounded design: the price of safety, checked by Monte Carlo.

The uncertainty model itself (the lognormal scatter, the V_c quantile and the
Monte Carlo estimate) lives in :mod:`designer.physics.uncertainty`; this module
compares the nominal and the risk-bounded Pareto fronts of one problem.
"""

from __future__ import annotations

import numpy as np
from designer.physics.uncertainty import Uncertainty, shimmy_probability_mc

# --------------------------------------------------------------------------- nominal vs robust


def robust_comparison(problem, points: int = 21) -> dict:
    """Nominal and risk-bounded Pareto fronts of the same problem, and the price of safety.

    The risk-bounded problem is ``problem`` with its risk bound (every problem carries one by default;
    with ``[robust] enabled = false`` the default :class:`Uncertainty` is used); the nominal problem is
    the same without it.  Returns a dict with both fronts, the Monte Carlo probability of shimmy (with its
    SE, own seed) of every risk-bounded point and of the nominal point at the same sill force, and the
    price of safety: the extra turning effort at equal threshold force (interpolated on the nominal front).
    """
    # late import: loads casadi (via designer.studies.front._pareto) only when this runs
    from designer.studies.front import pareto_front

    u = problem.risk if problem.risk is not None else Uncertainty()
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
        inertia = float(cond.inertia(d.diameter))
        p_mc, se = shimmy_probability_mc(
            d.trail, inertia, d.groove, d.damping, cond.slip_coefficient, problem.required_speed, u
        )
        p_nom = (
            shimmy_probability_mc(*_nominal_design_args(nominal, point, cond), problem.required_speed, u)[0]
            if len(nominal)
            else float("nan")
        )
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


def _nominal_design_args(nominal, point, cond):
    """Nominal front design at the robust point's threshold force (nearest point), as Eq. 7 arguments."""
    f = nominal.objectives()
    i = int(np.argmin(np.abs(f[:, 1] - point.threshold_force)))
    d = nominal.points[i].design
    return d.trail, float(cond.inertia(d.diameter)), d.groove, d.damping, cond.slip_coefficient
