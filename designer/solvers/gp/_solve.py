"""Geometric programming with cvxpy (``gp=True``): cross-check, global certificate, duals.

docs/model.md#solvers, cvxpy paragraph.  With the *added* damping c_d = c_f − c_0 as the
variable, every quantity of the model is a posynomial of the positive
variables (T, d, B, c_d):

- turning effort (docs/model.md#turning-effort, Eq. 9)
  F_turn = (m_mode k_surface L (1 + κB) + c_d θ0) / T;
- threshold force (Eq. 1 = Eq. 4A expanded in s = h/d)
  P = L · 2 s^½ Σ_{k<=N} c_k s^k, every c_k > 0 (truncated; it *under*-estimates
  the exact P by at most L·2 s^½ (2s)^(N+1)/(1 − 2s), and N is chosen so that
  this is below :data:`~designer.solvers.gp._terms.SERIES_TOLERANCE` relative over the diameter range);
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
function the GP is built from (:func:`~designer.solvers.gp._terms.gp_terms`), with the *exact* right side
of the shimmy constraint (at an SGP fixed point the condensed and exact sides
agree in value and log-gradient).  The names are those of
:data:`designer.solvers.nlp.PARAMETER_INFO` plus ``"<variable>.min|max"`` for
active bounds, as :meth:`CasterNLP.sensitivities`.  One difference in meaning:
the GP holds c_d = c_f − c_0 (its variable) when c_0 changes, so its
``bare_fork_damping`` sensitivity equals the NLP's ``bare_fork_damping`` plus
``damping.min`` when the damping bound sits at c_0.

Public API: :func:`solve_gp`, :class:`GPResult` (its ``designs``: NLP starts), :func:`polish`.
The terms are in :mod:`designer.solvers.gp._terms`, one family's sequential GP and duals in
:mod:`designer.solvers.gp._family`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.model import Design
from designer.physics.threshold import threshold_force_ratio, threshold_series_remainder_bound
from designer.problem import Problem
from designer.errors import InfeasibleError
from designer.reprs import Record
from designer.solvers.base import NO_CAPS, Caps, Designs, Optimum, found_optimum, optima_designs, weights_of, wheel_of
from designer.solvers.nlp import BIG, CasterNLP
from designer.solvers.gp._family import MAX_ITERATIONS, _Family
from designer.solvers.gp._terms import series_order

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

__all__ = ["GP", "GPResult", "GPSolver", "polish", "solve_gp"]

# --------------------------------------------------------------------------- result


@dataclass(frozen=True, kw_only=True)
class GPResult(Record):
    """The GP / sequential-GP optimum of a problem.

    Attributes
    ----------
    design : the optimum (SI); c_f = c_0 + c_d; B and c_d are exactly 0 in the
        families that fix them, a tiny floor (see :data:`~designer.solvers.gp._family.FLOOR`) otherwise
    objective : J = w_turn F_turn + w_threshold P [N] of ``design`` with the
        exact model (:func:`designer.model._caster.performance`, exact Eq. 4A)
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
    duals: dict[str, float]
    truncation_error: float
    status: str
    families: list[tuple[str, float, bool, str]]
    wheel: str | None = None
    problem: Problem | None = field(default=None, repr=False)
    designs: dict[str, Design] = field(default_factory=dict, repr=False)
    order: int = 0
    seconds: float = 0.0
    solves: int = 0

    _units = {"objective": "N", "gp_objective": "N", "seconds": "s"}


# --------------------------------------------------------------------------- public API


def _solve_continuous(
    problem: Problem,
    weights: tuple[float, float],
    threshold_cap: float | None,
    order: int,
    s_max: float,
    max_iterations: int,
    record: list[tuple[Problem, Design]] | None = None,
    turning_cap: float | None = None,
) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = []
    b = problem.bounds  # the families the bounds allow: (groove_free, damper_free)
    c0 = problem.conditions.turning.bare_fork_damping
    groove_options = [False] if b["groove"].high <= 0 else ([True] if b["groove"].low > 0 else [False, True])
    cd_lo, cd_hi = b["damping"].low - c0, b["damping"].high - c0
    damper_options = [False] if cd_hi <= 1e-12 else ([True] if cd_lo > 1e-12 else [False, True])
    for groove_free, damper_free in [(g, c) for c in damper_options for g in groove_options]:
        fam = _Family(problem, groove_free, damper_free, weights, threshold_cap, order, s_max, turning_cap)
        best: tuple[str, dict[str, float], float, int, dict[str, float]] | None = None
        starts: list[dict[str, float] | None] = [None] if fam.single else list(fam.start_points())
        for start in starts:
            status, values, j, iterations = fam.run(start, max_iterations, record)
            if values is None:
                continue
            # the multipliers belong to the last GP solved: read them now if its variables hold ``values`` (a
            # failed last solve leaves them empty: its duals are of no solution)
            held = all(
                v.value is not None and abs(float(v.value) - values[k]) <= 1e-14 * abs(values[k])
                for k, v in fam.variables.items()
            )
            duals = fam.duals(values) if held else {}
            if best is None or j < best[2] - 1e-12 * abs(j):
                best = (status, values, j, iterations, duals)
        row = dict(family=fam.name, exact=fam.exact, status="infeasible", solves=fam.solves)
        if best is not None:
            row["status"], values, j, row["iterations"], duals = best
            row["design"] = design = fam.design(values)
            row.update(gp_objective=j, objective=float(problem.evaluate(design).J(weights)), duals=duals or {})
        rows.append(row)
    return rows


# long: the docstring documents every argument and the result (the body is under 55 lines)
def solve_gp(
    problem: Problem,
    weights: Sequence[float] | None = None,
    threshold_cap: float | None = None,
    max_iterations: int = MAX_ITERATIONS,
    record: list[tuple[Problem, Design]] | None = None,
    turning_cap: float | None = None,
) -> GPResult:
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
    turning_cap : optional ε-cap F_turn <= ε [N] (a posynomial constraint)

    Returns
    -------
    GPResult

    Raises
    ------
    designer.errors.InfeasibleError
        No family of any variant has a feasible GP.
    """

    t0 = time.perf_counter()
    w = weights_of(problem, weights)
    order, _ = series_order(problem)
    variants = problem.variants()
    s_max = max(v.conditions.threshold_height / v.bounds["diameter"].low for v in variants)
    candidates: list[tuple[float, str, str | None, Problem, dict[str, Any]]] = []
    families: list[tuple[str, float, bool, str]] = []
    solves = 0
    for variant in variants:
        wheel = wheel_of(variant) if problem.wheels else None
        rows = _solve_continuous(variant, w, threshold_cap, order, s_max, max_iterations, record, turning_cap)
        for row in rows:
            solves += row["solves"]
            label = row["family"] if wheel is None else f"{wheel}: {row['family']}"
            families.append((label, row.get("objective", math.nan), row["exact"], row["status"]))
            if "design" in row:
                candidates.append((row["objective"], label, wheel, variant, row))
    if not candidates:
        raise InfeasibleError(  # the target speed and the caps asked for
            f"{problem.name}: no geometric-programming family is feasible (target speed "
            f"{problem.required_speed:.3g} m/s"
            + (f", P <= {threshold_cap:.4g} N" if threshold_cap else "")
            + (f", F_turn <= {turning_cap:.4g} N" if turning_cap else "")
            + ")"
        )
    _, _, wheel, variant, row = min(candidates, key=lambda c: c[0])
    design = row["design"]
    h = variant.conditions.threshold_height
    s = h / design.diameter
    truncation = float(threshold_series_remainder_bound(s, order) / threshold_force_ratio(design.diameter, h))
    return GPResult(
        **{
            k: row[k]
            for k in ("design", "objective", "gp_objective", "family", "exact", "iterations", "duals", "status")
        },
        truncation_error=truncation,
        families=families,
        wheel=wheel,
        problem=variant,
        designs={label: r["design"] for _, label, _, _, r in candidates},
        order=order,
        seconds=time.perf_counter() - t0,
        solves=solves,
    )


def polish(
    problem: Problem, gp_result: GPResult, weights: Sequence[float] | None = None, threshold_cap: float | None = None
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

    w = weights_of(problem, weights)
    variant = gp_result.problem if gp_result.problem is not None else problem
    if variant.wheels:
        variant = (
            variant.variants()[0]
            if gp_result.wheel is None
            else next(v for v in variant.variants() if wheel_of(v) == gp_result.wheel)
        )
    nlp = CasterNLP(variant)
    result = nlp.solve(gp_result.design, w, BIG if threshold_cap is None else threshold_cap)
    best = (gp_result.design, float(variant.evaluate(gp_result.design).J(w)))
    if result.success:
        j = float(variant.evaluate(result.design).J(w))
        if j <= best[1]:
            best = (result.design, j)
    return best


# --------------------------------------------------------------------------- the solver protocol


class GPSolver:
    """The geometric program as a solver of the protocol (:class:`designer.solvers.base.Solver`).

    ``optimum`` is :func:`solve_gp` (every family, every catalog wheel; J of the GP design by the exact model,
    the duals as sensitivities, the :class:`GPResult` as ``result``); ``front_designs`` solves min F_turn s.t.
    P <= ε by :func:`solve_gp` at each ε.  Not polished: the GP design itself (feasible for the exact model).
    """

    name = "cvxpy-gp"
    tolerance = 1e-4

    def applicable(self, problem: Problem) -> bool:
        """The GP takes every problem (risk-bounded ones conservatively: :func:`~designer.solvers.gp._terms.robust_speed_factor`)."""
        return True

    def optimum(
        self,
        problem: Problem,
        weights: Sequence[float] | None = None,
        caps: Caps = NO_CAPS,
        *,
        starts: Sequence[Any] = (),
    ) -> Optimum:
        """The best family's GP optimum (``starts`` are not needed: each family starts from its corners)."""
        w = weights_of(problem, weights)
        try:
            r = solve_gp(problem, w, caps.threshold, turning_cap=caps.turning)
        except InfeasibleError:
            return found_optimum(self.name, problem, w, caps, None, status="infeasible")
        return found_optimum(
            self.name,
            r.problem if r.problem is not None else problem,
            w,
            caps,
            r.design,
            objective=r.objective,
            status=r.status,
            wheel=r.wheel,
            sensitivities=dict(r.duals),
            solves=r.solves,
            seconds=r.seconds,
            result=r,
        )

    def front_designs(self, problem: Problem, eps: npt.ArrayLike) -> Designs:
        """min F_turn s.t. P <= ε by :func:`solve_gp` at each ε of a continuous problem."""
        e = np.asarray(eps, float).ravel()
        found = [self.optimum(problem, (1.0, 0.0), Caps(threshold=float(cap))) for cap in e]
        multipliers, solves = tuple(o.sensitivities for o in found), sum(o.solves for o in found)
        return optima_designs(self.name, problem, e, found, multipliers=multipliers, solves=solves)


GP = GPSolver()
"""The geometric program's :class:`~designer.solvers.base.Solver`."""
