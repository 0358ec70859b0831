"""Geometric programming with cvxpy (``gp=True``): cross-check, global certificate, duals.

docs/model.md#solvers, cvxpy paragraph.  With the *added* damping c_d = c_f − c_0 as the
variable, every quantity of the model is a posynomial of the positive
variables (T, d, B, c_d):

- turning effort (docs/model.md#turning-effort, Eq. 9)
  F_turn = (m_mode k_surface L (1 + κB) + c_d θ0) / T;
- threshold force (Eq. 1 = Eq. 4A expanded in s = h/d)
  P = L · 2 s^½ Σ_{k<=N} c_k s^k, every c_k > 0 (truncated; it *under*-estimates
  the exact P by at most L·2 s^½ (2s)^(N+1)/(1 − 2s), and N is chosen so that
  this is below :data:`SERIES_TOLERANCE` relative over the diameter range);
- wheel inertia (docs/model.md#wheel-inertia): a monomial C d^n (power law), a posynomial
  (disc) or a constant (fixed / catalog wheel);
- swept radius T + d/2 <= R_max.

The shimmy constraint (Eq. 7), V_c >= V_req = (1 + margin) V_target, squared
and multiplied by I_w,

    V_req² I_w(d) <= (4/π)(c_0 + c_d) T² + K_s B² T / 2,

is "posynomial <= posynomial", a signomial constraint.  Where the right side
has a single term (B = 0 and c_d = 0: the bare fork) it is a GP constraint and
the GP optimum is the *global* optimum of that family.  Otherwise the right
side r(x) = Σ u_i(x) is condensed at the current point x0 to the monomial

    r̂(x) = r(x0) Π_j (x_j / x0_j)^{g_j},   g_j = ∂ log r / ∂ log x_j (x0),

which is the AM–GM condensation Π (u_i/α_i)^{α_i}, α_i = u_i(x0)/r(x0): the
tangent plane of the convex log r(e^y), so r̂ <= r everywhere.  Each GP is
therefore an inner approximation: every iterate is feasible for the exact
model, the objective never increases, and the fixed point is a KKT point of
the exact (truncated-series) problem: sequential GP, a local method.

The design space is split into families by whether B and c_d are fixed at 0
(no term) or free (with a tiny positive floor): "bare fork" (B = 0, c_d = 0),
"groove", "damper", "groove+damper".  Each family is solved and the best is
returned; ``exact`` marks the families whose GP is exact (global).

Dual sensitivities.  cvxpy solves the log-log transformed problem: minimise
log J(e^y) subject to log f_i(e^y) − log g_i(e^y) <= 0, with multipliers
λ_i >= 0 (``constraint.dual_value``).  By the envelope theorem, for any fixed
parameter p,

    d log J* / d log p = ∂ log J/∂ log p + Σ_i λ_i ∂ (log f_i − log g_i)/∂ log p,

all partial derivatives at the optimum x* with x held.  Examples: the target
speed enters the shimmy constraint as V² on the left, so its sensitivity is
2 λ_shimmy; R_max enters as (T + d/2)/R_max <= 1, so it is −λ_swept; an active
upper bound x <= b gives d log J/d log b = −λ.  The partial derivatives are
taken numerically (central difference in log p, step 1e-5) on the same term
function the GP is built from (:func:`gp_terms`), with the *exact* right side
of the shimmy constraint (at an SGP fixed point the condensed and exact sides
agree in value and log-gradient).  The names are those of
:data:`designer.solvers.nlp.PARAMETER_INFO` plus ``"<variable>.min|max"`` for
active bounds, as :meth:`CasterNLP.sensitivities`.  One difference in meaning:
the GP holds c_d = c_f − c_0 (its variable) when c_0 changes, so its
``bare_fork_damping`` sensitivity equals the NLP's ``bare_fork_damping`` plus
``damping.min`` when the damping bound sits at c_0.

Public API: :func:`solve_gp`, :class:`GPResult`, :func:`polish`,
:func:`gp_starts` (cheap NLP starts).
"""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np

from designer import parameters
from designer.errors import check_interrupt
from designer.model import FAMILIES, Conditions, Design, performance
from designer.physics.geometry import swept_radius
from designer.physics.inertia import Catalog, Disc, Fixed, PowerLaw, disc_inertia, power_law_inertia
from designer.physics.threshold import (
    threshold_force_ratio,
    threshold_series_coefficients,
    threshold_series_remainder_bound,
)
from designer.physics.turning import sliding_turning_moment
from designer.problem import Problem
from designer.physics.uncertainty import log_speed_quantile
from designer.errors import InfeasibleError
from designer.solvers.nlp import BIG, CasterNLP

SERIES_TOLERANCE = 1e-9
"""Target bound on the relative truncation error of the P series over the diameter range [-]."""
MAX_ORDER = 400
"""Highest series order used (reached only for d close to 2h)."""
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


# --------------------------------------------------------------------------- result


@dataclass
class GPResult:
    """The GP / sequential-GP optimum of a problem.

    Attributes
    ----------
    design : the optimum (SI); c_f = c_0 + c_d; B and c_d are exactly 0 in the
        families that fix them, a tiny floor (see :data:`FLOOR`) otherwise
    objective : J = w_turn F_turn + w_threshold P [N] of ``design`` with the
        exact model (:func:`designer.model.performance`, exact Eq. 4A)
    gp_objective : the GP's own optimal value [N] (truncated P series)
    family : "bare fork" | "groove" | "damper" | "groove+damper"
    exact : True if the family's GP is exact (single-term right side of the
        shimmy constraint): ``design`` is then the global optimum of the family
        (to the series truncation error)
    iterations : SGP iterations (GP solves) of the returned family's best start
    duals : d log J / d log p from the GP multipliers (module docstring), keyed
        as :data:`designer.solvers.nlp.PARAMETER_INFO` plus active bounds
    truncation_error : bound on the relative error of the P series at ``design`` [-]
    status : "optimal", "converged" (SGP), "max_iterations" or "infeasible"
    families : per family, (family, objective J [N] or nan, exact, status);
        catalog problems prefix the family with the wheel ("C: groove")
    wheel : Table 1 wheel key for catalog problems, else None
    problem : the continuous problem (catalog variant) that ``design`` solves
    designs : {family label: Design} of every family that solved
    order : order N of the P series
    seconds : wall time of the whole solve
    solves : number of GP solves in total
    """

    design: Design
    objective: float
    gp_objective: float
    family: str
    exact: bool
    iterations: int
    duals: dict
    truncation_error: float
    status: str
    families: list
    wheel: str | None = None
    problem: Problem | None = field(default=None, repr=False)
    designs: dict = field(default_factory=dict, repr=False)
    order: int = 0
    seconds: float = 0.0
    solves: int = 0

    def as_start(self) -> np.ndarray:
        """The design as an SI array in VARIABLES order (an NLP start)."""
        return self.design.as_array()


# --------------------------------------------------------------------------- parameters


def _parameters(problem: Problem) -> dict:
    """The fixed parameters of a continuous problem, named as in :mod:`designer.parameters`."""
    if not isinstance(problem.conditions.inertia, (PowerLaw, Disc, Catalog, Fixed)):  # pragma: no cover
        raise TypeError(f"inertia model {type(problem.conditions.inertia).__name__}: not expressible as a GP")
    return parameters.solver_values(problem)


@dataclass(frozen=True)
class _Constants:
    """Everything fixed in the GP: the conditions, V_req and R_max."""

    conditions: Conditions
    required_speed: float
    swept_radius_max: float | None


def robust_speed_factor(problem: Problem, groove: bool) -> tuple[float, bool]:
    """Factor on V_req that makes the GP's shimmy constraint imply the robust one, and whether it is exact.

    A problem with an uncertainty (``[robust]``, :mod:`designer.analysis.robust`)
    requires V_c(x) exp(−Q_{1−α}(σ_m, σ_r(x))) >= V_req (Q the quantile of σ_m t_ν + σ_r Z,
    :func:`designer.physics.uncertainty.log_speed_quantile`), with σ_r² =
    (e_c σ_c)² + (e_K σ_K)² + (σ_I/2)² and elasticities e_c = a/(2(a+b)),
    e_K = b/(2(a+b)) of Eq. 7 (a the damping term, b the groove term).  σ_V
    depends on x, which no GP can express, so the GP uses its largest value:
    e_c + e_K = 1/2 and the convex sum of squares peaks at a vertex, so
    σ_V <= sqrt(σ_m² + max(σ_c, σ_K)²/4 + σ_I²/4), conservative (every GP
    point meets the robust constraint).  Without a groove term (b = 0)
    e_c = 1/2 exactly and the factor is exact.

    Returns
    -------
    (factor, exact) : factor >= 1 on V_req [-]; True if it is not a bound.
    """
    u = getattr(problem.conditions, "uncertainty", None)
    if u is None:
        return 1.0, True

    e2 = (max(u.damping, u.slip_coefficient) if groove else u.damping) ** 2 / 4
    rest = math.sqrt(e2 + u.inertia**2 / 4)  # the quantile grows with the normal part: its largest value bounds it
    return math.exp(float(log_speed_quantile(u.model_error, rest, u))), not groove or u.slip_coefficient <= u.damping


def _constants(problem: Problem, params: dict, speed_factor: float = 1.0) -> _Constants:
    """Conditions rebuilt from ``params`` (so a parameter can be perturbed)."""
    conditions = parameters.with_solver_values(problem, params)
    return _Constants(conditions, (1 + problem.margin) * params["target_speed"] * speed_factor,
                      params.get("swept_radius_max"))


def series_order(problem: Problem, tolerance: float = SERIES_TOLERANCE) -> tuple[int, float]:
    """Smallest order N of the P series with relative truncation error below ``tolerance``.

    The bound (:func:`threshold_series_remainder_bound`, over the exact Eq. 4A)
    grows with s = h/d, so it is evaluated at the smallest diameter of the
    problem (of its catalog wheels, for a catalog problem).

    Returns
    -------
    (N, bound) : the order and the relative error bound at the smallest diameter [-]
        (N is capped at :data:`MAX_ORDER`; the bound then tells how far off it is).
    """
    d_min = min(v.bounds["diameter"].low for v in problem.variants())
    h = problem.conditions.threshold_height
    s = h / d_min
    exact = float(threshold_force_ratio(d_min, h))
    for order in range(0, MAX_ORDER + 1):
        bound = float(threshold_series_remainder_bound(s, order)) / exact
        if bound < tolerance:
            return order, bound
    return MAX_ORDER, bound


# --------------------------------------------------------------------------- the posynomials (ONE place)


def _is_zero(x) -> bool:
    return isinstance(x, (int, float)) and x == 0


def _inertia(diameter, model):
    """I_w(d) through the physics functions: monomial, posynomial or constant (docs/model.md#wheel-inertia)."""
    if isinstance(model, PowerLaw):
        c, n = model.constants()
        return power_law_inertia(diameter, c, n)
    if isinstance(model, Disc):
        return disc_inertia(diameter, model.tyre_width, model.density)
    if isinstance(model, Catalog):
        return model.wheel.inertia
    return model.inertia  # Fixed


def gp_terms(trail, diameter, groove, added_damping, constants: _Constants, order: int, s_max: float) -> dict:
    """The posynomials of the GP, written once; works on cvxpy, float and complex values.

    Parameters
    ----------
    trail : T [m]
    diameter : d [m]
    groove : B [m]; the number 0 drops its terms (fixed-at-zero family)
    added_damping : c_d = c_f − c_0 [N·m/rad]; the number 0 drops its term
    constants : conditions, V_req [m/s], R_max [m]
    order : order N of the threshold series
    s_max : largest s = h/d of the problem (for the remainder monomial)

    Returns
    -------
    dict with
        ``turning_effort`` F_turn [N] (Eq. 9, docs/model.md#turning-effort; calls
        :func:`sliding_turning_moment`; the added damper moment
        (c_f − c_0) θ0 of :func:`added_damper_moment` is c_d θ0);
        ``threshold_force`` P [N], Eq. 4A series to order N (underestimates);
        ``threshold_remainder`` monomial upper bound of the omitted terms [N],
        L · 2 s^½ (2s)^(N+1) / (1 − 2 s_max);
        ``inertia`` I_w [kg·m²];
        ``shimmy_lhs`` V_req² I_w [N·m²/... = kg·m⁴/s²];
        ``shimmy_rhs`` list of the monomials of (4/π)(c_0 + c_d) T² + K_s B² T/2
        (Eq. 7 multiplied by I_w) [kg·m⁴/s²];
        ``swept_radius`` T + d/2 [m].
    """
    c = constants.conditions
    moment = sliding_turning_moment(c.load, groove, c.surface, c.turning_mode, c.turning)
    if not _is_zero(added_damping):
        moment = moment + added_damping * c.disturbance_angle
    s = c.threshold_height * diameter**-1
    coefficients = threshold_series_coefficients(order)
    ratio = sum(2 * float(ck) * s ** (k + 0.5) for k, ck in enumerate(coefficients))
    inertia = _inertia(diameter, c.inertia)
    rhs = [4 / np.pi * c.turning.bare_fork_damping * trail**2]
    if not _is_zero(added_damping):
        rhs.append(4 / np.pi * added_damping * trail**2)
    if not _is_zero(groove):
        rhs.append(c.slip_coefficient * groove**2 * trail / 2)
    return {
        "turning_effort": moment / trail,
        "threshold_force": c.load * ratio,
        "threshold_remainder": c.load * 2 * s**0.5 * (2 * s) ** (order + 1) / (1 - 2 * s_max),
        "inertia": inertia,
        "shimmy_lhs": constants.required_speed**2 * inertia,
        "shimmy_rhs": rhs,
        "swept_radius": swept_radius(trail, diameter),
    }


def _objective(terms: dict, weights) -> object:
    """J = w_turn F_turn + w_threshold P from the terms (a zero weight drops its term)."""
    parts = []
    if weights[0] > 0:
        parts.append(weights[0] * terms["turning_effort"])
    if weights[1] > 0:
        parts.append(weights[1] * terms["threshold_force"])
    return parts[0] if len(parts) == 1 else parts[0] + parts[1]


# --------------------------------------------------------------------------- one family


class _Family:
    """The (S)GP of one family of one continuous problem, built once (DPP), solved many times."""

    VARS = ("trail", "diameter", "groove", "added_damping")

    def __init__(self, problem: Problem, groove_free: bool, damper_free: bool, weights, threshold_cap,
                 order: int, s_max: float):
        self.problem = problem
        self.name = FAMILIES[(groove_free, damper_free)]
        self.weights = weights
        self.order, self.s_max = order, s_max
        self.params = _parameters(problem)
        groove_present = groove_free or problem.bounds["groove"].low > 0
        self.speed_factor, self.speed_exact = robust_speed_factor(problem, groove_present)
        self.constants = _constants(problem, self.params, self.speed_factor)
        c0 = problem.conditions.turning.bare_fork_damping
        b = problem.bounds
        # box of each variable in GP form (c_d = c_f - c_0)
        self.box = {
            "trail": (b["trail"].low, b["trail"].high),
            "diameter": (b["diameter"].low, b["diameter"].high),
            "groove": (b["groove"].low, b["groove"].high),
            "added_damping": (max(b["damping"].low - c0, 0.0), max(b["damping"].high - c0, 0.0)),
        }
        free = {"trail": True, "diameter": True, "groove": groove_free, "added_damping": damper_free}
        self.x = {}
        self.floor = {}
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
        self.variables = {k: v for k, v in self.x.items() if isinstance(v, cp.Variable)}
        terms = gp_terms(self.x["trail"], self.x["diameter"], self.x["groove"], self.x["added_damping"],
                         self.constants, order, s_max)
        self.terms = terms
        constraints = {}
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
        self.infeasible_constant = False
        if _constant(lhs) and _constant(rhs):
            self.infeasible_constant |= _value(lhs) > _value(rhs)
        else:
            constraints["shimmy"] = lhs <= rhs
        for name, var in self.variables.items():
            lo, hi = self.box[name]
            constraints[f"{name}.max"] = var <= hi
            constraints[f"{name}.min"] = var >= (lo if lo > 0 else self.floor[name])
        if self.constants.swept_radius_max is not None:
            if _constant(terms["swept_radius"]):
                self.infeasible_constant |= _value(terms["swept_radius"]) > self.constants.swept_radius_max * (1 + 1e-12)
            else:
                constraints["swept_radius"] = terms["swept_radius"] <= self.constants.swept_radius_max
        self.threshold_cap = threshold_cap
        if threshold_cap is not None:
            capped = terms["threshold_force"] + terms["threshold_remainder"]
            if _constant(capped):
                self.infeasible_constant |= _value(capped) > threshold_cap
            else:
                constraints["threshold_cap"] = capped <= threshold_cap
        self.constraints = constraints
        objective = _objective(terms, weights)
        if _constant(objective) and "trail" in self.variables:
            # nothing in J depends on a variable (e.g. w_turn = 0 with d fixed): any feasible point is optimal;
            # a negligible T⁻¹ term makes the answer definite (the longest feasible trail)
            objective = objective + 1e-12 * _value(objective) * self.box["trail"][1] * self.variables["trail"] ** -1
        self.cp_problem = cp.Problem(cp.Minimize(objective), list(constraints.values()))
        self.solves = 0

    # ----------------------------------------------------------------- helpers
    def full(self, values: dict) -> dict:
        """Values of all four GP variables (floats) given the free ones."""
        return {k: (values[k] if k in self.variables else float(v)) for k, v in self.x.items()}

    def design(self, values: dict) -> Design:
        x = self.full(values)
        c0 = self.problem.conditions.turning.bare_fork_damping
        return Design(x["trail"], x["diameter"], x["groove"], c0 + x["added_damping"])

    def float_terms(self, values: dict, constants: _Constants | None = None) -> dict:
        x = self.full(values)
        return gp_terms(x["trail"], x["diameter"], x["groove"], x["added_damping"],
                        constants or self.constants, self.order, self.s_max)

    def condense(self, values: dict) -> None:
        """Set the condensed monomial r̂ of the shimmy right side at ``values`` (AM–GM)."""
        x = self.full(values)
        r0 = sum(float(np.real(u)) for u in self.float_terms(values)["shimmy_rhs"])
        log_k = math.log(r0)
        eps = 1e-30
        for k in self.rhs_variables:
            shifted = dict(x)
            shifted[k] = x[k] * (1 + 1j * eps)  # complex step: Im(r)/eps = ∂r/∂log x_k
            rc = sum(gp_terms(shifted["trail"], shifted["diameter"], shifted["groove"], shifted["added_damping"],
                              self.constants, self.order, self.s_max)["shimmy_rhs"])
            g = float(np.imag(rc)) / eps / r0
            self.g_param[k].value = g
            log_k -= g * math.log(x[k])
        self.k_param.value = math.exp(log_k)

    def solve_once(self) -> tuple[str, dict | None, float]:
        self.solves += 1
        try:
            return self._solve_once()
        finally:
            check_interrupt()  # Clarabel runs in Rust: the SIGINT flag

    def _solve_once(self) -> tuple[str, dict | None, float]:
        with warnings.catch_warnings():
            # "may be inaccurate": Clarabel stopped short of the tight tolerances above;
            # such a point is still checked against the exact model by the caller
            warnings.simplefilter("ignore", UserWarning)
            try:
                self.cp_problem.solve(gp=True, solver=cp.CLARABEL, **SOLVER_OPTIONS)
            except cp.error.SolverError:
                try:
                    self.cp_problem.solve(gp=True, solver=cp.CLARABEL)
                except cp.error.SolverError:
                    return "solver_error", None, math.nan
        status = self.cp_problem.status
        if status not in _OK:
            return status, None, math.nan
        values = {k: float(v.value) for k, v in self.variables.items()}
        return status, values, float(self.cp_problem.value)

    def start_points(self) -> list[dict]:
        """SGP starts: the corner that maximises the shimmy right side, and the geometric centre."""
        starts = []
        corner = {}
        for k in self.variables:
            lo, hi = self.box[k]
            lo = lo if lo > 0 else self.floor[k]
            corner[k] = lo if k == "diameter" else hi
        if "trail" in corner and self.constants.swept_radius_max is not None:
            d = self.full(corner)["diameter"]
            corner["trail"] = float(np.clip(self.constants.swept_radius_max - d / 2, *self.box["trail"]))
        starts.append(corner)
        centre = {}
        for k in self.variables:
            lo, hi = self.box[k]
            lo = lo if lo > 0 else self.floor[k] * 1e3
            centre[k] = math.sqrt(lo * hi)
        starts.append(centre)
        return starts

    def run(self, start: dict, max_iterations: int = MAX_ITERATIONS, record=None):
        """SGP from ``start`` (or one GP if exact). Returns (status, values, gp J, iterations)."""
        if self.infeasible_constant:
            return "infeasible", None, math.nan, 0
        if self.single:
            status, values, j = self.solve_once()
            if values is not None and record is not None:
                record.append((self.problem, self.design(values)))
            return ("optimal" if values is not None else status), values, j, 1
        x0 = dict(start)
        best = None
        for it in range(1, max_iterations + 1):
            self.condense(x0)
            status, values, j = self.solve_once()
            if values is None:
                return (status if best is None else "converged"), best and best[0], best[1] if best else math.nan, it
            if record is not None:
                record.append((self.problem, self.design(values)))
            best = (values, j)
            # change relative to each variable's range (a floor at solver precision must not count)
            step = max((abs(values[k] - x0[k]) / self.box[k][1] for k in values), default=0.0)
            if step <= STEP_TOLERANCE:
                return "converged", values, j, it
            x0 = values
        return "max_iterations", best[0], best[1], max_iterations

    # ----------------------------------------------------------------- duals
    def duals(self, values: dict) -> dict:
        """d log J*/d log p from the GP multipliers (module docstring).

        Parameters are perturbed by ±1e-5 in log at fixed x (central
        difference on :func:`gp_terms`); bounds come straight from their
        multipliers.  ``bare_fork_damping`` is returned with the bounds of
        c_f held (the NLP's meaning): the GP's own derivative (c_d held)
        minus the share of the c_d bounds that move when c_0 does.
        """
        lam = {}
        for name, con in self.constraints.items():
            dv = con.dual_value
            lam[name] = 0.0 if dv is None else float(np.asarray(dv).ravel()[0])
        x = self.full(values)
        out = {}
        step = 1e-5
        for pname, pvalue in self.params.items():
            logs = []
            for sign in (+1, -1):
                params = dict(self.params)
                params[pname] = pvalue * math.exp(sign * step)
                logs.append(self._log_parts(x, _constants(self.problem, params, self.speed_factor)))
            (j_p, g_p), (j_m, g_m) = logs
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
            j0, _ = self._log_parts(x, self.constants)
            jc, gc = self._log_parts({**x, "added_damping": 1j * eps}, self.constants)
            mu = float(np.imag(jc)) / eps + sum(lam.get(k, 0.0) * float(np.imag(v)) / eps for k, v in gc.items())
            if not damping_fixed and abs(mu * c0) > 1e-9:
                out["damping.min"] = mu * c0
            out["bare_fork_damping"] -= mu * c0
        if "threshold_cap" in self.constraints:
            out["threshold_cap"] = -lam["threshold_cap"]
        return out

    def _log_parts(self, x: dict, consts: _Constants):
        """log J and log(f_i/g_i) of the parameter-dependent constraints at x (exact shimmy side).

        Works on float and complex values (complex step).
        """
        t = gp_terms(x["trail"], x["diameter"], x["groove"], x["added_damping"], consts, self.order, self.s_max)
        j = np.log(_objective(t, self.weights) + 0j)
        g = {}
        if "shimmy" in self.constraints:
            g["shimmy"] = np.log(t["shimmy_lhs"] + 0j) - np.log(sum(t["shimmy_rhs"]) + 0j)
        if "swept_radius" in self.constraints:
            g["swept_radius"] = np.log(t["swept_radius"] / consts.swept_radius_max + 0j)
        if "threshold_cap" in self.constraints:
            g["threshold_cap"] = np.log((t["threshold_force"] + t["threshold_remainder"]) / self.threshold_cap + 0j)
        return j, g


def _constant(expr) -> bool:
    if isinstance(expr, (int, float, np.floating)):
        return True
    return isinstance(expr, cp.Expression) and not expr.variables()


def _value(expr) -> float:
    return float(expr.value) if isinstance(expr, cp.Expression) else float(expr)


# --------------------------------------------------------------------------- public API


def _families(problem: Problem):
    """(groove_free, damper_free) of the families the bounds allow."""
    b = problem.bounds
    c0 = problem.conditions.turning.bare_fork_damping
    groove_options = [False] if b["groove"].high <= 0 else ([True] if b["groove"].low > 0 else [False, True])
    cd_lo, cd_hi = b["damping"].low - c0, b["damping"].high - c0
    damper_options = [False] if cd_hi <= 1e-12 else ([True] if cd_lo > 1e-12 else [False, True])
    return [(g, c) for c in damper_options for g in groove_options]


def exact_objective(problem: Problem, design: Design, weights) -> float:
    """J = w_turn F_turn + w_threshold P [N] with the exact model (:func:`designer.model.performance`)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        v = performance(design.trail, design.diameter, design.groove, design.damping, problem.conditions)
    return float(weights[0] * v["turning_effort"] + weights[1] * v["threshold_force"])


def _solve_continuous(problem: Problem, weights, threshold_cap, order, s_max, max_iterations, record=None):
    rows = []
    for groove_free, damper_free in _families(problem):
        fam = _Family(problem, groove_free, damper_free, weights, threshold_cap, order, s_max)
        best = None
        starts = [None] if fam.single else fam.start_points()
        for start in starts:
            status, values, j, iterations = fam.run(start, max_iterations, record)
            if values is None:
                continue
            # the multipliers belong to the last GP solved: read them now
            duals = fam.duals(values) if _last_solution_is(fam, values) else {}
            if best is None or j < best[2] - 1e-12 * abs(j):
                best = (status, values, j, iterations, duals)
        if best is None:
            rows.append(dict(family=fam.name, exact=fam.exact, status="infeasible", solves=fam.solves))
            continue
        status, values, j, iterations, duals = best
        design = fam.design(values)
        rows.append(dict(family=fam.name, exact=fam.exact, status=status, solves=fam.solves, design=design,
                         gp_objective=j, objective=exact_objective(problem, design, weights),
                         iterations=iterations, duals=duals or {}))
    return rows


def _last_solution_is(fam: _Family, values: dict) -> bool:
    """True if the cvxpy variables hold ``values`` (so the duals belong to them)."""
    return all(abs(float(v.value) - values[k]) <= 1e-14 * abs(values[k]) for k, v in fam.variables.items())


def solve_gp(problem: Problem, weights=None, threshold_cap: float | None = None,
             max_iterations: int = MAX_ITERATIONS, record: list | None = None) -> GPResult:
    """Minimise J = w_turn F_turn + w_threshold P by geometric programming (docs/model.md#solvers).

    Every family (bare fork, groove, damper, groove+damper, as the bounds
    allow) is solved: the bare fork as one exact GP (global optimum), the
    others by sequential GP from two starts; the best by exact-model J wins.

    Parameters
    ----------
    problem : Problem; a catalog problem is solved for each wheel of
        ``problem.variants()`` and the best wheel kept
    weights : (w_turn, w_threshold) [-]; default the problem's
    threshold_cap : optional ε-cap P <= ε [N] (Pareto points).  Because the
        truncated series *under*-estimates P, the GP imposes the series plus a
        monomial bound of its remainder, so the cap holds for the exact Eq. 4A.
    max_iterations : SGP iterations per start (1 gives the first, already
        feasible, GP: a cheap start)
    record : optional list; (continuous problem, design) of every GP iterate is appended (for tests)

    Returns
    -------
    GPResult

    Raises
    ------
    designer.errors.InfeasibleError
        No family of any variant has a feasible GP.
    """

    t0 = time.perf_counter()
    w = tuple(float(v) for v in (problem.weights if weights is None else weights))
    order, _ = series_order(problem)
    variants = problem.variants()
    s_max = max(v.conditions.threshold_height / v.bounds["diameter"].low for v in variants)
    candidates, families, solves = [], [], 0
    for variant in variants:
        wheel = variant.conditions.inertia.wheel.key if problem.wheels else None
        rows = _solve_continuous(variant, w, threshold_cap, order, s_max, max_iterations, record)
        for row in rows:
            solves += row["solves"]
            label = row["family"] if wheel is None else f"{wheel}: {row['family']}"
            families.append((label, row.get("objective", math.nan), row["exact"], row["status"]))
            if "design" in row:
                candidates.append((row["objective"], label, wheel, variant, row))
    if not candidates:
        raise InfeasibleError(
            f"{problem.name}: no geometric-programming family is feasible (target speed "
            f"{problem.required_speed:.3g} m/s" + (f", P <= {threshold_cap:.4g} N" if threshold_cap else "") + ")"
        )
    _, _, wheel, variant, row = min(candidates, key=lambda c: c[0])
    design = row["design"]
    h = variant.conditions.threshold_height
    s = h / design.diameter
    truncation = float(threshold_series_remainder_bound(s, order) / threshold_force_ratio(design.diameter, h))
    return GPResult(
        design=design, objective=row["objective"], gp_objective=row["gp_objective"], family=row["family"],
        exact=row["exact"], iterations=row["iterations"], duals=row["duals"], truncation_error=truncation,
        status=row["status"], families=families, wheel=wheel, problem=variant,
        designs={label: r["design"] for _, label, _, _, r in candidates}, order=order,
        seconds=time.perf_counter() - t0, solves=solves,
    )


def gp_starts(problem: Problem, weights=None, threshold_cap: float | None = None,
              max_iterations: int = MAX_ITERATIONS) -> list[np.ndarray]:
    """Each feasible family's GP design as an NLP start (SI arrays, VARIABLES order).

    Pass a continuous problem (one catalog variant) to get starts for its NLP.
    ``max_iterations=1`` is the cheapest (one GP per family and start, already
    feasible for the exact model); the default runs the SGP to convergence.
    Returns an empty list if no family is feasible.
    """

    try:
        result = solve_gp(problem, weights, threshold_cap, max_iterations=max_iterations)
    except InfeasibleError:
        return []
    return [d.as_array() for d in result.designs.values()]


def polish(problem: Problem, gp_result: GPResult, weights=None, threshold_cap: float | None = None
           ) -> tuple[Design, float]:
    """Exact-model polish: IPOPT (:class:`CasterNLP`) started from the GP design.

    Parameters
    ----------
    problem : the problem given to :func:`solve_gp` (for a catalog problem the
        wheel of ``gp_result`` is used)
    gp_result : a :class:`GPResult`
    weights : (w_turn, w_threshold); default the problem's
    threshold_cap : optional ε-cap P <= ε [N]

    Returns
    -------
    (design, J) : the better of the NLP optimum from the GP start and the GP
        design itself (always feasible), and its exact J [N].
    """

    w = tuple(float(v) for v in (problem.weights if weights is None else weights))
    variant = gp_result.problem if gp_result.problem is not None else problem
    if variant.wheels:
        variant = variant.variants()[0] if gp_result.wheel is None else next(
            v for v in variant.variants() if v.conditions.inertia.wheel.key == gp_result.wheel)
    nlp = CasterNLP(variant)
    result = nlp.solve(gp_result.design, w, BIG if threshold_cap is None else threshold_cap)
    best = (gp_result.design, exact_objective(variant, gp_result.design, w))
    if result.success:
        j = exact_objective(variant, result.design, w)
        if j <= best[1]:
            best = (result.design, j)
    return best
