"""One family of the GP (bare fork, groove, damper, groove+damper): the sequential GP and its duals.

Part of :mod:`designer.solvers.gp._solve` (the method is in its docstring).
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import cvxpy as cp
import numpy as np

from designer.errors import check_interrupt
from designer.model import FAMILIES, Design
from designer.problem import Problem

from designer.solvers.gp._terms import _Constants, _constants, _objective, _parameters, gp_terms, robust_speed_factor


FLOOR = 1e-6
"""Floor of a free B or c_d whose lower bound is 0, relative to its upper bound."""
MAX_ITERATIONS = 200
"""Most SGP iterations per family and start."""
STEP_TOLERANCE = 1e-9
"""Stop the SGP when no variable changes by more than this fraction of its upper bound."""
BACKOFF = 1e-9
"""Relative back-off on V_req² in the GP, so that solver tolerance never makes V_c < V_req."""
SOLVER_OPTIONS = {"tol_gap_abs": 1e-11, "tol_gap_rel": 1e-11, "tol_feas": 1e-11, "tol_ktratio": 1e-9}
"""Clarabel tolerances (tighter than its defaults)."""

_OK = (cp.OPTIMAL, cp.OPTIMAL_INACCURATE)


# --------------------------------------------------------------------------- one family


class _Family:
    """The (S)GP of one family of one continuous problem, built once (DPP), solved many times."""

    VARS = ("trail", "diameter", "groove", "added_damping")

    def __init__(
        self,
        problem: Problem,
        groove_free: bool,
        damper_free: bool,
        weights: tuple[float, float],
        threshold_cap: float | None,
        order: int,
        s_max: float,
        turning_cap: float | None = None,
    ):
        self.problem = problem
        self.turning_cap = turning_cap
        self.name = FAMILIES[(groove_free, damper_free)]
        self.weights = weights
        self.order, self.s_max = order, s_max
        self.params = _parameters(problem)
        groove_present = groove_free or problem.bounds["groove"].low > 0
        self.speed_factor, self.speed_exact = robust_speed_factor(problem, groove_present)
        self.constants = _constants(problem, self.params, self.speed_factor)
        self._build_variables(groove_free, damper_free)
        self.terms = terms = self._terms(self.x)
        constraints: dict[str, Any] = {}
        self.infeasible_constant = False
        # the shimmy constraint (Eq. 7, V_req² side <= the damping side): a GP constraint when the right side is one
        # monomial (``single``), else its condensation k·Π x^g with parameters updated at every SGP step; when both
        # sides are constant it only sets ``infeasible_constant``
        rhs_terms = terms["shimmy_rhs"]
        self.rhs_variables = [k for k in ("trail", "groove", "added_damping") if k in self.variables]
        lhs = terms["shimmy_lhs"] * (1 + BACKOFF)
        variable_terms = [u for u in rhs_terms if not _constant(u)]
        self.single = len(rhs_terms) == 1 or not variable_terms  # a GP constraint: no condensation
        self.exact = self.single and self.speed_exact
        if self.single:
            rhs = rhs_terms[0] if len(rhs_terms) == 1 else float(sum(_value(u) for u in rhs_terms))
        else:
            self.k_param = cp.Parameter(pos=True, value=1.0)
            self.g_param = {k: cp.Parameter(value=1.0) for k in self.rhs_variables}
            rhs = self.k_param
            for k in self.rhs_variables:
                rhs = rhs * self.variables[k] ** self.g_param[k]
        if _constant(lhs) and _constant(rhs):
            self.infeasible_constant |= _value(lhs) > _value(rhs)
        else:
            constraints["shimmy"] = lhs <= rhs
        # the box of each variable, the swept-radius limit and the caps on the threshold force P and the turning
        # effort F_turn (a constant that breaks a limit sets ``infeasible_constant``)
        for name, var in self.variables.items():
            lo, hi = self.box[name]
            constraints[f"{name}.max"] = var <= hi
            constraints[f"{name}.min"] = var >= (lo if lo > 0 else self.floor[name])
        self.threshold_cap = threshold_cap
        for name, limit, slack in (
            ("swept_radius", self.constants.swept_radius_max, 1 + 1e-12),
            ("threshold_cap", threshold_cap, 1),
            ("turning_cap", self.turning_cap, 1),
        ):
            if limit is None:
                continue
            limited = _limited(terms, name)
            if _constant(limited):
                self.infeasible_constant |= _value(limited) > limit * slack
            else:
                constraints[name] = limited <= limit
        self.constraints = constraints
        objective: Any = _objective(terms, weights)  # J = w_turn F_turn + w_threshold P in GP form
        if _constant(objective) and "trail" in self.variables:
            # nothing in J depends on a variable (e.g. w_turn = 0 with d fixed): any feasible point is optimal;
            # a negligible T⁻¹ term makes the answer definite (the longest feasible trail)
            objective = objective + 1e-12 * _value(objective) * self.box["trail"][1] * self.variables["trail"] ** -1
        self.cp_problem: Any = cp.Problem(cp.Minimize(objective), list(constraints.values()))
        self.solves = 0

    def _build_variables(self, groove_free: bool, damper_free: bool) -> None:
        """The box of each GP variable (c_d = c_f − c_0) and the variables ``x``: 0 for a part the family
        lacks, a float for a fixed one, else a positive cvxpy Variable (floored when its lower bound is 0)."""
        c0 = self.problem.conditions.turning.bare_fork_damping
        b = self.problem.bounds
        self.box: dict[str, tuple[float, float]] = {
            **{k: (b[k].low, b[k].high) for k in ("trail", "diameter", "groove")},
            "added_damping": (max(b["damping"].low - c0, 0.0), max(b["damping"].high - c0, 0.0)),
        }
        free = {"trail": True, "diameter": True, "groove": groove_free, "added_damping": damper_free}
        self.x: dict[str, Any] = {}
        self.floor: dict[str, float] = {}
        for name in self.VARS:
            lo, hi = self.box[name]
            if not free[name]:
                self.x[name] = 0
            elif lo == hi:
                self.x[name] = float(lo)
            else:
                self.x[name] = cp.Variable(pos=True, name=name)
                if lo <= 0:
                    self.floor[name] = FLOOR * hi
        self.variables: dict[str, Any] = {k: v for k, v in self.x.items() if isinstance(v, cp.Variable)}

    # ----------------------------------------------------------------- helpers
    def full(self, values: dict[str, float]) -> dict[str, float]:
        """Values of all four GP variables (floats) given the free ones."""
        return {k: (values[k] if k in self.variables else float(v)) for k, v in self.x.items()}

    def design(self, values: dict[str, float]) -> Design:
        x = self.full(values)
        c0 = self.problem.conditions.turning.bare_fork_damping
        return Design(x["trail"], x["diameter"], x["groove"], c0 + x["added_damping"])

    def _terms(self, x: dict[str, Any], constants: _Constants | None = None) -> dict[str, Any]:
        """:func:`gp_terms` of the four GP variables ``x`` (cvxpy, float or complex values)."""
        c = constants or self.constants
        return gp_terms(x["trail"], x["diameter"], x["groove"], x["added_damping"], c, self.order, self.s_max)

    def float_terms(self, values: dict[str, float], constants: _Constants | None = None) -> dict[str, Any]:
        return self._terms(self.full(values), constants)

    def condense(self, values: dict[str, float]) -> None:
        """Set the condensed monomial r̂ of the shimmy right side at ``values`` (AM–GM)."""
        x = self.full(values)
        r0 = sum(float(np.real(u)) for u in self.float_terms(values)["shimmy_rhs"])
        log_k = math.log(r0)
        eps = 1e-30
        for k in self.rhs_variables:
            shifted: dict[str, Any] = dict(x)
            shifted[k] = x[k] * (1 + 1j * eps)  # complex step: Im(r)/eps = ∂r/∂log x_k
            rc = sum(self._terms(shifted)["shimmy_rhs"])
            g = float(np.imag(rc)) / eps / r0
            self.g_param[k].value = g
            log_k -= g * math.log(x[k])
        self.k_param.value = math.exp(log_k)

    def solve_once(self) -> tuple[str, dict[str, float] | None, float]:
        self.solves += 1
        with warnings.catch_warnings():
            # "may be inaccurate": Clarabel stopped short of the tight tolerances above;
            # such a point is still checked against the exact model by the caller
            warnings.simplefilter("ignore", UserWarning)
            try:
                try:
                    self.cp_problem.solve(gp=True, solver=cp.CLARABEL, **SOLVER_OPTIONS)
                except cp.error.SolverError:
                    self.cp_problem.solve(gp=True, solver=cp.CLARABEL)
            except cp.error.SolverError:
                return "solver_error", None, math.nan
            finally:
                check_interrupt()  # Clarabel runs in Rust: the SIGINT flag
        status = str(self.cp_problem.status)
        if status not in _OK:
            return status, None, math.nan
        values = {k: float(v.value) for k, v in self.variables.items()}
        return status, values, float(self.cp_problem.value)

    def start_points(self) -> list[dict[str, float]]:
        """SGP starts: the corner that maximises the shimmy right side, and the geometric centre."""
        corner: dict[str, float] = {}
        centre: dict[str, float] = {}
        for k in self.variables:
            lo, hi = self.box[k]
            corner[k] = hi if k != "diameter" else lo if lo > 0 else self.floor[k]
            centre[k] = math.sqrt((lo if lo > 0 else self.floor[k] * 1e3) * hi)
        if "trail" in corner and self.constants.swept_radius_max is not None:
            d = self.full(corner)["diameter"]
            corner["trail"] = float(np.clip(self.constants.swept_radius_max - d / 2, *self.box["trail"]))
        return [corner, centre]

    def run(
        self,
        start: dict[str, float] | None,
        max_iterations: int = MAX_ITERATIONS,
        record: list[tuple[Problem, Design]] | None = None,
    ) -> tuple[str, dict[str, float] | None, float, int]:
        """SGP from ``start`` (or one GP if exact). Returns (status, values, gp J, iterations)."""
        if self.infeasible_constant:
            return "infeasible", None, math.nan, 0
        if self.single:
            status, values, j = self.solve_once()
            if values is not None and record is not None:
                record.append((self.problem, self.design(values)))
            return ("optimal" if values is not None else status), values, j, 1
        x0 = dict(start or {})
        best: tuple[dict[str, float], float] | None = None
        for it in range(1, max_iterations + 1):
            self.condense(x0)
            status, values, j = self.solve_once()
            if values is None:
                if best is None:
                    return status, None, math.nan, it
                return "converged", best[0], best[1], it
            if record is not None:
                record.append((self.problem, self.design(values)))
            best = (values, j)
            # change relative to each variable's range (a floor at solver precision must not count)
            step = max((abs(values[k] - x0[k]) / self.box[k][1] for k in values), default=0.0)
            if step <= STEP_TOLERANCE:
                return "converged", values, j, it
            x0 = values
        if best is None:  # max_iterations < 1: nothing was solved
            return "max_iterations", None, math.nan, 0
        return "max_iterations", best[0], best[1], max_iterations

    # ----------------------------------------------------------------- duals
    def duals(self, values: dict[str, float]) -> dict[str, float]:
        """d log J*/d log p from the GP multipliers (module docstring).

        Parameters are perturbed by ±1e-5 in log at fixed x (central
        difference on :func:`gp_terms`); bounds come straight from their
        multipliers.  ``bare_fork_damping`` is returned with the bounds of
        c_f held (the NLP's meaning): the GP's own derivative (c_d held)
        minus the share of the c_d bounds that move when c_0 does.
        """
        lam: dict[str, float] = {}
        for name, con in self.constraints.items():
            dv = con.dual_value
            lam[name] = 0.0 if dv is None else float(np.asarray(dv).ravel()[0])
        x = self.full(values)
        out = {}
        step = 1e-5
        for pname, pvalue in self.params.items():
            shifted = ({**self.params, pname: pvalue * math.exp(sign * step)} for sign in (+1, -1))
            (j_p, g_p), (j_m, g_m) = (
                self._log_parts(x, _constants(self.problem, q, self.speed_factor)) for q in shifted
            )
            d = (j_p - j_m) / (2 * step)
            for name, value in g_p.items():
                d += lam.get(name, 0.0) * (value - g_m[name]) / (2 * step)
            out[pname] = float(np.real(d))
        c0 = self.problem.conditions.turning.bare_fork_damping
        damping_bound = self.problem.bounds["damping"]
        damping_fixed = damping_bound.low == damping_bound.high
        for name in self.variables:
            lo, hi = self.box[name]
            for side, sign, bound in (("max", -1.0, hi), ("min", +1.0, lo if lo > 0 else self.floor[name])):
                lam_b = lam.get(f"{name}.{side}", 0.0)
                if abs(lam_b) < 1e-9:
                    continue
                s_b = sign * lam_b  # d log J* / d log(bound of the GP variable)
                if name == "added_damping":
                    # the bound on c_f = c_0 + c_d; a floor stands for c_f >= c_0
                    c_f_bound = c0 + (bound if (side == "max" or lo > 0) else 0.0)
                    out[f"damping.{side}"] = s_b * c_f_bound / bound
                    out["bare_fork_damping"] -= s_b * c0 / bound
                elif side == "max" or lo > 0:  # a floor is not a bound of the problem
                    out[f"{name}.{side}"] = s_b
        if isinstance(self.x["added_damping"], int) and self.box["added_damping"][0] == 0:
            # c_d fixed at 0 by the family: its multiplier μ = ∂L/∂c_d at c_d = 0 (complex step)
            eps = 1e-30
            jc, gc = self._log_parts({**x, "added_damping": 1j * eps}, self.constants)
            mu = float(np.imag(jc)) / eps + sum(lam.get(k, 0.0) * float(np.imag(v)) / eps for k, v in gc.items())
            if not damping_fixed and abs(mu * c0) > 1e-9:
                out["damping.min"] = mu * c0
            out["bare_fork_damping"] -= mu * c0
        for cap in ("threshold_cap", "turning_cap"):
            if cap in self.constraints:
                out[cap] = -lam[cap]
        return out

    def _log_parts(self, x: dict[str, Any], consts: _Constants) -> tuple[Any, dict[str, Any]]:
        """log J and log(f_i/g_i) of the parameter-dependent constraints at x (exact shimmy side).

        Works on float and complex values (complex step).
        """
        t = self._terms(x, consts)
        objective: Any = _objective(t, self.weights)
        j = np.log(objective + 0j)
        g: dict[str, Any] = {}
        if "shimmy" in self.constraints:
            g["shimmy"] = np.log(t["shimmy_lhs"] + 0j) - np.log(sum(t["shimmy_rhs"]) + 0j)
        caps = (consts.swept_radius_max, self.threshold_cap, self.turning_cap)
        for name, limit in zip(("swept_radius", "threshold_cap", "turning_cap"), caps):
            if name in self.constraints:
                g[name] = np.log(_limited(t, name) / limit + 0j)
        return j, g


def _limited(terms: dict[str, Any], name: str) -> Any:
    """The side of the limit ``name`` ("swept_radius", "threshold_cap", "turning_cap") that is capped: R_s, the P
    series with its remainder bound, F_turn."""
    if name == "threshold_cap":
        return terms["threshold_force"] + terms["threshold_remainder"]
    return terms["turning_effort" if name == "turning_cap" else name]


def _constant(expr: Any) -> bool:
    if isinstance(expr, (int, float, np.floating)):
        return True
    variables: Any = expr.variables if isinstance(expr, cp.Expression) else None
    return variables is not None and not variables()


def _value(expr: Any) -> float:
    value: Any = expr.value if isinstance(expr, cp.Expression) else expr
    return float(value)
