"""The scalarised optimum of a problem: solve, certify, explain.

``optimise(problem)`` minimises J = w_turn F_turn + w_threshold P subject to
V_c >= (1 + margin) V_target (Eq. 7), the bounds and the swept-radius limit.
It solves the exact CasADi/IPOPT NLP from several starts (the best points of
a vectorised Sobol sample of the box, the two design families' corners and
the geometric program's answer), keeps the best, and cross-checks it with the
cvxpy geometric program and scipy's SLSQP.  The returned :class:`Solution`
prints the design, objectives, constraint margins, sensitivities and the
solver agreement.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from designer.display import unit_text
from designer.units import percent
from designer.errors import InertiaExtrapolationWarning, InfeasibleError, InputError, ModelRangeWarning, SolverError
from designer.model import VARIABLES, Caster, Design, OfCaster
from designer.parameters import OUTPUTS, PARAMETERS
from designer.problem import Problem, check_weights, problem_argument
from designer.reprs import Key, Record, dataframe, si_frame
from designer.solvers import PRIMARY, Optimum, one_solve_at_a_time, solver
from designer.solvers.base import wheel_of
from designer.solvers.nlp import PARAMETER_INFO, max_critical_speed
import warnings
from typing import TYPE_CHECKING, Any

from designer.boundary import Count, checked

if TYPE_CHECKING:  # the GP's record for the checker only: designer.solvers.gp loads cvxpy
    from designer.solvers.gp import GPResult

ACTIVE_TOL = 1e-6


@dataclass(frozen=True, kw_only=True)
class Solution(Record):
    """The optimum of a caster problem and everything an engineer asks about it.

    Attributes
    ----------
    problem : the problem solved (for a catalog problem: the chosen wheel's variant)
    caster : the evaluator's row of the optimum (:class:`designer.model.Caster`, under the solved problem's
        conditions, with J for ``weights`` and the risk at V_req): ``design``, ``objectives``, ``critical_speed``
        and ``shimmy_probability`` (``_se``) are read from it
    design : optimal design (SI)
    objectives : {"turning_effort": F_turn [N], "threshold_force": P [N], "weighted": J [N]} of the caster
    critical_speed : V_c at the optimum [m/s] (Eq. 7)
    constraints : {name: margin}, margin >= 0 feasible (shimmy in m/s, swept radius in m, bounds in SI)
    active : names of the active constraints and bounds
    sensitivities : {parameter: d log J / d log p} from the NLP multipliers
    cross_check : {solver: J [N]} from every solver that was run
    status : "optimal" or a solver status
    wheel : chosen Table 1 wheel for a catalog problem, else None
    timings : {"build": s, "solve": s, "cross_check": s}
    weights : (w_turn, w_threshold) of the J that was minimised (``--weights`` or the problem's)
    shimmy_probability, shimmy_probability_se : Monte Carlo P(V_c,true < V_req) at the optimum and its SE [-]
        (computed by :func:`optimise` with the model's evaluator; None without a risk bound): ``str()`` shows them
        and runs nothing
    """

    problem: Problem
    caster: Caster = field(repr=False)
    constraints: dict[str, float]
    active: list[str]
    sensitivities: dict[str, float]
    cross_check: dict[str, float] = field(default_factory=dict)
    gp: GPResult | None = None
    status: str = "optimal"
    wheel: str | None = None
    timings: dict[str, float] = field(default_factory=dict)
    starts: int = 0
    weights: tuple[float, ...] = ()

    design = OfCaster()
    critical_speed = OfCaster()
    shimmy_probability = OfCaster()
    shimmy_probability_se = OfCaster()

    @property
    def objectives(self) -> dict[str, float]:
        """{"turning_effort": F_turn [N], "threshold_force": P [N], "weighted": J [N]}, read from the caster."""
        c: Any = self.caster  # one Caster: its fields are Python floats
        return {"turning_effort": c.turning_effort, "threshold_force": c.threshold_force, "weighted": c.weighted}

    _keys = (
        *(
            Key("problem", "problem.name"),
            "design",
            "objectives",
            Key("weights", lambda s: [float(w) for w in s.weights]),
        ),
        *("critical_speed", Key("required_speed", "problem.required_speed"), "constraints", "active"),
        *("sensitivities", Key("gp_duals", "gp_duals()"), "cross_check", "status", "wheel", "timings"),
    )
    """The keys of ``designer run --json``'s solution."""

    def __post_init__(self) -> None:
        if not self.weights:
            object.__setattr__(self, "weights", tuple(self.problem.weights))  # frozen: set once, while built

    def gp_duals(self) -> dict[str, float]:
        """d log J / d log p from the geometric program's duals, where the GP defines them.

        Under a risk bound they are the duals of the GP's conservative bound (V_req times a quantile factor
        fixed over the box, :func:`designer.solvers.gp.robust_speed_factor` in ``_terms``), not of the exact
        quantile the NLP's multipliers hold, so the printout shows them only for a nominal problem, where the two
        are equal (``tests/studies/optimum``)."""
        duals = getattr(self.gp, "duals", None) or {}
        return {k: float(v) for k, v in duals.items()}

    def agreement(self) -> float:
        """Largest relative difference of J between the solvers that ran."""
        values = [v for v in self.cross_check.values() if v is not None and np.isfinite(v)]
        if len(values) < 2:
            return 0.0
        ref = self.objectives["weighted"]
        return float(max(abs(v - ref) for v in values) / abs(ref))

    def _repr_lines(self) -> list[str]:
        """Two lines: the design (inches) and the objectives and V_c (the full account: ``print(solution)``)."""
        d, o = self.design, self.objectives
        return [
            f"Solution({self.problem.name!r}, {self.status}): {d.describe()}",
            f"  F_turn {o['turning_effort']:.4g} N, P {o['threshold_force']:.4g} N, J {o['weighted']:.4g} N, "
            f"V_c {self.critical_speed:.4g} m/s (required {self.problem.required_speed:.4g})",
        ]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The optimum as a compact table with units (notebooks; no solver or Monte Carlo runs)."""
        d, o = self.design, self.objectives
        return ([("wheel (Table 1)", self.wheel, "")] if self.wheel else []) + [
            *d.variable_rows(),
            OUTPUTS["turning_effort"].row(f"{o['turning_effort']:.4g}"),
            OUTPUTS["threshold_force"].row(f"{o['threshold_force']:.4g}"),
            (f"weighted J ({self.weights[0]:g}, {self.weights[1]:g})", f"{o['weighted']:.4g}", "N"),
            OUTPUTS["critical_speed"].row(f"{self.critical_speed:.4g}"),
            ("required speed", f"{self.problem.required_speed:.4g}", "m/s"),
            ("active", ", ".join(self.active) or "none", ""),
            ("solver agreement (relative J gap)", f"{self.agreement():.1e}", ""),
        ]

    def to_pandas(self, wide: bool = False) -> Any:
        """The optimum as a pandas DataFrame (pandas: the ``notebook`` extra).

        Long form (default, like GPkit's solution table): one row per quantity with columns ``kind``
        ("design", "objective", "performance", "margin", "sensitivity", "cross_check"), ``name``, ``value``,
        ``unit`` and ``active`` (the constraint or bound is active).  Margins are >= 0 when met (shimmy in
        m/s, lengths in m, damping in N·m/rad); sensitivities are d log J / d log p [-].  ``wide=True``: one
        row with the columns of :meth:`Front.to_pandas <designer.studies.front._front.Front.to_pandas>`
        (``trail_m``, ..., ``turning_effort_N``, ``threshold_force_N``, ``critical_speed_m_s``) plus
        ``weighted_N``, ``margin_<name>`` and ``sensitivity_<name>``; units in ``df.attrs["units"]``.
        """
        d, o = self.design, self.objectives
        objectives = {k: o[k] for k in ("turning_effort", "threshold_force", "weighted")}
        attrs = {
            "problem": self.problem.name,
            "status": self.status,
            "weights": tuple(self.weights),
            "wheel": self.wheel,
        }
        if wide:
            record = {**d.to_dict(), **objectives, "critical_speed": self.critical_speed}
            units = {}
            for name, value in self.constraints.items():
                record[f"margin_{name}"], units[f"margin_{name}"] = float(value), _margin_unit(name)
            for name, value in self.sensitivities.items():
                record[f"sensitivity_{name}"], units[f"sensitivity_{name}"] = float(value), "-"
            return si_frame("Solution.to_pandas", [record], list(record), units, **attrs)
        rows = [("design", v, float(x), PARAMETERS[v].unit) for v, x in d.to_dict().items()]
        rows += [("objective", k, float(v), "N") for k, v in objectives.items()]
        rows += [
            ("performance", "critical_speed", float(self.critical_speed), "m/s"),
            ("performance", "required_speed", float(self.problem.required_speed), "m/s"),
        ]
        rows += [("margin", k, float(v), _margin_unit(k)) for k, v in self.constraints.items()]
        rows += [("sensitivity", k, float(v), "-") for k, v in self.sensitivities.items()]
        rows += [("cross_check", k, float(v) if v is not None else math.nan, "N") for k, v in self.cross_check.items()]
        active = set(self.active)
        records = [
            {"kind": kind, "name": name, "value": value, "unit": unit, "active": kind == "margin" and name in active}
            for kind, name, value, unit in rows
        ]
        return dataframe(
            "Solution.to_pandas",
            records,
            ["kind", "name", "value", "unit", "active"],
            {"value": "the row's unit column"},
            **attrs,
        )

    def __str__(self) -> str:
        d = self.design
        p = self.problem
        lines = [f"Optimum of {p.name!r}: {p.title}", ""]
        if self.wheel:
            lines.append(f"  chosen wheel          Table 1 wheel {self.wheel}")
        lines += [
            *d.variable_lines(24),
            "",
            f"  turning effort        {self.objectives['turning_effort']:8.3f} N",
            f"  sill force            {self.objectives['threshold_force']:8.3f} N",
            f"  weighted J            {self.objectives['weighted']:8.3f} N   (weights {self.weights[0]:g}, {self.weights[1]:g})",
            (
                f"  critical speed V_c    {self.critical_speed:8.3f} m/s (Eq. 7; required {p.required_speed:.3f}, "
                f"margin {self.constraints['shimmy']:+.3g} m/s)"
                if p.risk is None
                else f"  critical speed V_c    {self.critical_speed:8.3f} m/s (Eq. 7); held with probability "
                f"{percent(1 - float(p.risk.probability))}: V_q {p.required_speed + self.constraints['shimmy']:.3f} m/s "
                f"(required {p.required_speed:.3f}, margin {self.constraints['shimmy']:+.2e} m/s)"
            ),
            "",
        ]
        u, prob, se = p.conditions.uncertainty, self.shimmy_probability, self.shimmy_probability_se
        if u is not None and prob is not None and se is not None:
            lines += [
                f"  risk bound: P(V_c < {p.required_speed:.3g} m/s) <= {u.probability:.1%} (exact quantile "
                f"of the first-order law, t_{u.model_error_dof} model error); Monte Carlo {prob:.2%} ± {se:.2%} "
                f"(seed {u.seed}, at least {u.samples} samples, SE <= 0.1 pp)",
                "",
            ]
        lines += ["  active constraints:   " + (", ".join(self.active) if self.active else "none"), ""]
        duals = self.gp_duals()
        ranked = sorted(self.sensitivities.items(), key=lambda kv: -abs(kv[1]))
        beside = bool(p.risk is None and duals)  # the GP's duals beside the NLP's multipliers
        lines.append(
            "  sensitivities d log J / d log p (largest first; NLP multipliers"
            + (", GP duals beside):" if beside else "):")
        )
        if duals and not beside:
            lines.append(  # one line: the terminal wraps it at its width (designer.cli._terminal)
                "  (the GP's duals are not shown: they belong to its conservative risk bound, V_req times a "
                "quantile factor fixed over the diameter range, not to this optimum's exact bound)"
            )
        for name, value in ranked[:10]:
            desc = PARAMETER_INFO.get(name, ("", "", "bound"))[2]
            gp = ("  " + (f"{duals[name]:+8.4f}" if name in duals else "       –")) if beside else ""
            lines.append(f"    {name:24s} {value:+8.4f}{gp}   {desc}")
        lines += ["", "  solver agreement (J in N):"]
        for name, value in self.cross_check.items():
            shown = "n/a" if value is None or not np.isfinite(value) else f"{value:.6f}"
            lines.append(f"    {name:24s} {shown}")
        lines.append(f"    largest relative gap     {self.agreement():.1e}")
        return "\n".join(lines)


@dataclass(frozen=True, kw_only=True)
class ConstraintMargins(Record):
    """The margins of a design against its problem's constraints and bounds (:func:`constraint_margins`).

    Attributes
    ----------
    margins : {name: margin}, >= 0 when met: ``shimmy`` (the speed held with the problem's confidence minus the
        required speed) [m/s], ``swept_radius`` [m] when the problem limits it, ``<variable>.min`` and
        ``<variable>.max`` of every free variable (SI: m, N·m/rad)
    active : the names whose margin is within :data:`ACTIVE_TOL` of zero (relative to the required speed, the
        swept-radius limit or the bound)
    """

    margins: dict[str, float]
    active: list[str]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        return [
            (name + (" (active)" if name in self.active else ""), f"{value:+.4g}", _margin_unit(name))
            for name, value in self.margins.items()
        ]


def constraint_margins(problem: Problem, design: Design, values: Mapping[str, Any]) -> ConstraintMargins:
    """Margins (>= 0 feasible) of every constraint and bound, and the active ones (``to_dict()``: ``margins`` and
    ``active``; the function returned them as a pair before)."""
    margins = margins_many(problem, design.as_array(), values)[0]
    scale = {"shimmy": problem.required_speed, "swept_radius": problem.swept_radius_max or 1.0}
    active = []
    for name, margin in margins.items():
        ref = scale.get(name, max(abs(problem.bounds[name.split(".")[0]].high), 1e-3) if "." in name else 1.0)
        if abs(margin) <= ACTIVE_TOL * ref:
            active.append(name)
    return ConstraintMargins(margins={k: float(v) for k, v in margins.items()}, active=active)


def margins_many(problem: Problem, designs: np.ndarray, values: Any) -> list[dict[str, float]]:
    """The ``margins`` of :func:`constraint_margins` of many designs at once, one array operation a constraint:
    ``designs`` SI rows in VARIABLES order, ``values`` their evaluated :class:`~designer.model.Casters` (or one
    caster's mapping); a {name: margin} each [m/s, m, SI]."""
    x = np.asarray(designs, float).reshape(-1, len(VARIABLES))
    columns = {"shimmy": np.asarray(values["confident_speed"], float) - problem.required_speed}
    if problem.swept_radius_max is not None:
        columns["swept_radius"] = problem.swept_radius_max - np.asarray(values["swept_radius"], float)
    for i, var in enumerate(VARIABLES):
        b = problem.bounds[var]
        if not b.fixed:
            columns[f"{var}.min"], columns[f"{var}.max"] = x[:, i] - b.low, b.high - x[:, i]
    lists = {k: np.broadcast_to(c, (len(x),)).tolist() for k, c in columns.items()}
    return [{k: c[j] for k, c in lists.items()} for j in range(len(x))]


MAX_START_SAMPLES = 2**20
"""Largest Sobol sample :func:`optimise` chooses its NLP starts from (memory grows with it: about 0.3 kB a design)."""


@checked(samples=Count(1, MAX_START_SAMPLES, what="Sobol designs (the NLP starts are chosen among them)"))
@one_solve_at_a_time
def optimise(
    problem: Problem, weights: Sequence[float] | None = None, cross_check: bool = True, samples: int = 1024
) -> Solution:
    """Minimise J = w_turn F_turn + w_threshold P of ``problem`` (docs/model.md#problems).

    Parameters
    ----------
    problem : a :class:`~designer.problem.Problem` (catalog problems are
        solved per wheel and the best wheel kept)
    weights : (w_turn, w_threshold); default the problem's
    cross_check : also solve with the cvxpy GP and scipy SLSQP and report J of each
    samples : size of the Sobol sample used to choose NLP starts

    Returns
    -------
    Solution

    Raises
    ------
    InfeasibleError
        The target speed is out of reach: the message gives the highest
        reachable V_c, the design reaching it and the bounds to relax.
    SolverError
        IPOPT failed from every start although the problem is feasible.
    """
    problem = problem_argument(problem)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaExtrapolationWarning)
        warnings.filterwarnings("ignore", category=UserWarning, module="cvxpy")  # GP cross-check, polished below
        solution = _optimise(problem, weights, cross_check, samples)
    # once, and only if the reported optimum uses an extrapolated diameter
    for message in problem.model_warnings([solution.design.diameter]):
        warnings.warn(message, ModelRangeWarning, stacklevel=2)
    return solution


def _optimise(problem: Problem, weights: Sequence[float] | None, cross_check: bool, samples: int) -> Solution:
    w = check_weights(problem.weights if weights is None else weights, "weights", error=InputError)
    primary = solver(PRIMARY, samples=samples)
    build = solve = 0.0
    candidates: list[tuple[Optimum, Design, Optimum | None]] = []
    for variant in problem.variants():
        gp = _gp(variant, w) if cross_check else None
        # every family's GP answer is an NLP start (docs/model.md#solvers)
        starts = [d.as_array() for d in gp.result.designs.values()] if gp is not None else []
        found = primary.optimum(variant, w, starts=starts)
        build += found.build_seconds
        solve += found.seconds
        if found.success and found.design is not None:
            candidates.append((found, found.design, gp))
    if not candidates:
        raise diagnose_infeasible(problem)
    found, design, gp = min(candidates, key=lambda c: c[0].objective)
    variant = found.problem
    # the optimum by the model's evaluator; its risk (Monte Carlo at V_req) when the problem has a bound
    values = variant.evaluate(design, weights=w, risk=None if problem.risk is None else problem.required_speed)
    held = constraint_margins(variant, design, values)
    checks = {PRIMARY: values.weighted}
    t0 = time.perf_counter()
    if cross_check:
        # SLSQP on the chosen variant, from the NLP optimum and random starts
        checks["scipy-slsqp"] = solver("scipy-slsqp").optimum(variant, w, starts=[design]).objective
        if gp is not None:
            from designer.solvers import gp as gp_module

            try:
                checks["cvxpy-gp"] = float(gp_module.polish(variant, gp.result, w)[1])
            except Exception:
                checks["cvxpy-gp"] = float("nan")
    wheel = wheel_of(variant) if problem.wheels else None
    return Solution(
        problem=variant if problem.wheels else problem,
        caster=values,
        constraints=held.margins,
        active=held.active,
        sensitivities=dict(found.sensitivities),
        cross_check=checks,
        gp=None if gp is None else gp.result,
        wheel=wheel,
        timings={"build": build, "solve": solve, "cross_check": time.perf_counter() - t0},
        starts=found.solves,
        weights=tuple(w),
    )


def _gp(problem: Problem, weights: Sequence[float]) -> Optimum | None:
    """The GP/SGP optimum (:data:`~designer.solvers.CROSS_CHECKS`), or None if cvxpy is missing, the GP fails or
    finds nothing feasible.

    For robust problems the GP bounds the quantile constraint conservatively
    (see ``designer.solvers.gp._solve``); its polished answer is still a cross-check.
    """
    try:
        found = solver("cvxpy-gp").optimum(problem, weights)
    except Exception:  # the GP is a cross-check (cvxpy missing included); its failure is reported, not fatal
        return None
    return found if found.success else None


def diagnose_infeasible(problem: Problem) -> Exception:
    """Explain why no feasible design was found: the highest speed the shimmy constraint can reach inside the
    bounds (V_q of the risk bound, or Eq. 7's V_c for a nominal problem) against the one required."""
    found = [(*max_critical_speed(variant), variant) for variant in problem.variants()]
    v, design, active, variant = max(found, key=lambda row: row[0])  # the first of equal maxima, as before
    if v < problem.required_speed * (1 - 1e-6):
        relax = ", ".join(active) if active else "the variable bounds"
        wheel = f" with wheel {wheel_of(variant)}" if problem.wheels else ""
        risk = problem.risk
        what = (
            "critical speed (Eq. 7)"
            if risk is None
            else f"speed held with probability {percent(1 - float(risk.probability))} (V_q of the risk bound)"
        )
        return InfeasibleError(
            f"target speed {problem.required_speed:.3g} m/s (shimmy.target_speed × (1 + margin)) is out of reach: "
            f"the highest {what} inside the bounds is {v:.3f} m/s{wheel} at {design.describe()}; "
            f"relax {relax} or lower shimmy.target_speed",
            best={"critical_speed": v, "design": design.to_dict(), "active": active},
        )
    return SolverError(
        f"IPOPT found no optimum of {problem.name!r} from any start although V_c up to {v:.3f} m/s is reachable; "
        f"run with --debug and report it"
    )


def _margin_unit(name: str) -> str:
    """SI unit of a constraint margin of :func:`constraint_margins`: the shimmy margin a speed (m/s), the others
    their quantity's from the table (the swept radius and the length bounds m, the damping bounds N·m/rad)."""
    return unit_text("critical_speed" if name == "shimmy" else name.split(".")[0])
