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
    from designer.analysis.pareto import pareto_front

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
        p_mc, se = shimmy_probability_mc(d.trail, inertia, d.groove, d.damping, cond.slip_coefficient,
                                         problem.required_speed, u)
        p_nom = shimmy_probability_mc(*_nominal_design_args(nominal, point, cond), problem.required_speed, u)[0] \
            if len(nominal) else float("nan")
        f_nominal = float(np.interp(point.threshold_force, fn[order, 1], fn[order, 0], left=np.nan, right=np.nan))
        rows.append({
            "threshold_force": point.threshold_force,
            "turning_effort_robust": point.turning_effort,
            "turning_effort_nominal": f_nominal,
            "extra_effort": point.turning_effort - f_nominal,
            "critical_speed": point.critical_speed,
            "probability_mc": p_mc,
            "probability_mc_se": se,
            "nominal_probability_mc": p_nom,
        })
    cmp = nominal.compare(robust) if len(nominal) and len(robust) else {}
    return {"nominal": nominal, "robust": robust, "rows": rows, "compare": cmp, "uncertainty": u}


def _nominal_design_args(nominal, point, cond):
    """Nominal front design at the robust point's threshold force (nearest point), as Eq. 7 arguments."""
    f = nominal.objectives()
    i = int(np.argmin(np.abs(f[:, 1] - point.threshold_force)))
    d = nominal.points[i].design
    return d.trail, float(cond.inertia(d.diameter)), d.groove, d.damping, cond.slip_coefficient


def write_robust_report(problem, out_dir, points: int = 21) -> dict:
    """Write ``robust.md``, ``robust.json`` and ``robust_fronts.png`` comparing nominal and robust fronts.

    Files are written to a temporary folder and moved into ``out_dir`` when complete.
    """
    import json
    import os
    import shutil
    import tempfile
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result = robust_comparison(problem, points)
    out = Path(out_dir)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".robust-", dir=out.parent))
    try:
        nominal, robust, u = result["nominal"], result["robust"], result["uncertainty"]
        fig, ax = plt.subplots(figsize=(7, 4.5))
        fn, fr = nominal.objectives(), robust.objectives()
        ax.plot(fn[:, 1], fn[:, 0], "o-", ms=3, label=f"nominal: V_c >= {problem.required_speed:.2f} m/s (Eq. 7)")
        ax.plot(fr[:, 1], fr[:, 0], "s-", ms=3,
                label=f"risk-bounded: P(V_c < {problem.required_speed:.2f} m/s) <= {u.probability:.0%}")
        ax.set_xlabel("threshold force P [N]")
        ax.set_ylabel("turning effort F_turn [N]")
        ax.set_title(f"{problem.name}: the price of safety (nominal against risk-bounded)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(tmp / "robust_fronts.png", dpi=130)
        plt.close(fig)
        rows = result["rows"]
        extra = [r["extra_effort"] for r in rows if np.isfinite(r["extra_effort"])]
        probs = [r["probability_mc"] for r in rows]
        data = {
            "problem": problem.name,
            "uncertainty": {k: getattr(u, k) for k in ("probability", "model_error", "model_error_dof", "damping",
                                                       "slip_coefficient", "inertia", "samples", "seed")},
            "rows": rows,
            "compare": result["compare"],
            "nominal_front": nominal.rows(),
            "robust_front": robust.rows(),
        }
        (tmp / "robust.json").write_text(json.dumps(data, indent=2, default=float))
        nominal_p = [r["nominal_probability_mc"] for r in rows if np.isfinite(r["nominal_probability_mc"])]
        dist = f"Student-t, {u.model_error_dof} degrees of freedom" if u.model_error_dof else "normal"
        lines = [
            f"# Price of safety: {problem.title}",
            "",
            "![nominal and risk-bounded fronts](robust_fronts.png)",
            "",
            f"Risk bound: P(V_c,true < {problem.required_speed:.3g} m/s) <= {u.probability:.1%}. Model error of Eq. 7: "
            f"{dist}, scale {u.model_error:g}; lognormal M_f/θ0 (σ of the log {u.damping:g}), K_s ({u.slip_coefficient:g}), "
            f"I_w ({u.inertia:g}). The bound uses the exact quantile of the first-order law (conservative for M_f/θ0 "
            f"and K_s); each probability below is a separate Monte Carlo of the same law on the exact Eq. 7 "
            f"(at least {u.samples} samples, seed {u.seed}, drawn until the standard error is at most 0.1 percentage point).",
            "",
            f"- The risk-bounded front is dominated by the nominal one: hypervolume "
            f"{result['compare'].get('hypervolume_other', float('nan')):.4f} against "
            f"{result['compare'].get('hypervolume_self', float('nan')):.4f} (nominal front's normalisation, reference (1.1, 1.1)).",
            f"- Price of safety: {min(extra) if extra else float('nan'):.3f} to {max(extra) if extra else float('nan'):.3f} N more "
            f"turning effort at equal threshold force, over the common range.",
            f"- Monte Carlo probability of shimmy on the risk-bounded front: {min(probs):.2%} to {max(probs):.2%} "
            f"(bound {u.probability:.1%}); the nominal designs at the same sill force: "
            + (f"{min(nominal_p):.1%} to {max(nominal_p):.1%}." if nominal_p else "none to compare."),
            "- Why the gap: a nominal design sits exactly on V_c = V_req, so when the constants scatter it shimmies "
            "with the probability just stated; the risk-bounded design buys V_c above the target with more groove "
            "or damper (more turning effort) or a smaller wheel (more threshold force).",
            "",
            "| P [N] | F_turn nominal [N] | F_turn risk-bounded [N] | extra [N] | V_c risk-bounded [m/s] | P(shimmy) MC |",
            "|---:|---:|---:|---:|---:|---:|",
        ]
        for r in rows:
            lines.append(f"| {r['threshold_force']:.2f} | {r['turning_effort_nominal']:.3f} | {r['turning_effort_robust']:.3f} | "
                         f"{r['extra_effort']:.3f} | {r['critical_speed']:.3f} | {r['probability_mc']:.2%} ± {r['probability_mc_se']:.2%} |")
        (tmp / "robust.md").write_text("\n".join(lines).replace("| nan |", "| – |") + "\n")
        if out.exists():
            old = Path(tempfile.mkdtemp(prefix=".old-", dir=out.parent))
            os.replace(out, old / "x")
            os.replace(tmp, out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return result
