"""Closed-form ε-constraint optima of a continuous problem, nominal or risk-bounded.

For min F_turn s.t. P <= ε, V_c >= V_req (Eq. 7), R_s <= R_max and the box the
subproblem has structure (valid when the turning moment is positive and its
coefficients in B and c_f are >= 0):

- P (Eq. 4A) depends on d only and decreases with it; F_turn does not depend on
  d; I_w(d) does not decrease with d and R_s = T + d/2 grows with it.  So the
  feasible set in (T, B, c_f) shrinks as d grows and the optimum takes the
  smallest admissible diameter d = max(d_lo, d(ε)), d(ε) the diameter of P = ε.
- At fixed (B, c_f) F_turn = M/T falls and V_c rises with T: T = min(T_hi, R_max − d/2).
- At fixed (T, d) the cost M(B, c_f) is linear with non-negative coefficients and
  the constraint a·c_f + b·B² >= V_req² (a, b from Eq. 7) is linear in c_f and convex
  in B, so along the constraint curve the cost is concave in B: the optimum is at
  an end of the curve inside the box (or at (B_lo, c_lo) when that is feasible).
  Candidates: c_f = c_lo, c_f = c_hi (B from the constraint), B = B_lo, B = B_hi
  (c_f from the constraint), each clipped to the box; the cheapest feasible wins.

The risk bound (``conditions.uncertainty``; :mod:`designer.physics.uncertainty`) replaces V_c by its
α-quantile V_q = V_c exp(−Q(σ_m, σ_r)).  It is *not* the nominal constraint with a tightened target: σ_r
depends on the design through the elasticities of V_c in c_f and K_s, i.e. through the friction share
s = a/(a + b) of V_c² = a + b (a = 4 c_f T²/(π I_w), b = K_s B² T/(2 I_w)); only with σ_c = σ_K = 0 is
the factor a constant.  It is exact to write the bound as

    a + b >= V_req² G(s),   log G(s) = 2 Q(σ_m, σ_r(s)),

G a function of s and the scatter alone (a measured wheel's σ_I enters as a constant; for a wheel known by
its diameter, Table 1's prediction scale at d enters too, a constant at fixed d, so G = G(s; d) and every
step below is taken at the row's own d): on a ray of fixed share V_q grows as √(a + b).  So the structure
above carries over:

- I_w scales a and b alike (s unchanged): V_q ∝ I_w^−½ falls with d, the smallest admissible d wins (for a
  wheel known by its diameter the prediction scale narrows towards Table 1's middle as d grows, but
  I_w ∝ d^3.5 dominates: d log V_q / d log d is about −1.4 to −1.9 over 2–9 in; :func:`applicable` checks it);
- with |s (log G)'| < 1 and |(1 − s)(log G)'| < 1 on [0, 1] (:func:`applicable` asks for <= 0.8; about
  0.2 for the default scatter) V_q rises with T, c_f and B, so T is again the largest admissible and
  the optimum lies on the constraint curve (or at the corner (B_lo, c_lo) when that is feasible);
- the curve is c_f(s) = s V_req² G(s)/a₁, B(s)² = (1 − s) V_req² G(s)/b₁ (a₁, b₁ per unit c_f, B²),
  c_f rising and B falling with s; where it meets each edge of the box is a fixed point of a map that
  contracts by the same factor (:func:`_edge_shares`);
- F_turn along the curve is no longer concave in general (G bends it), so the cheapest point is
  searched on a grid of s between the box edges, refined by golden section, and compared with both
  edges (:func:`_risk_designs`).

Every model quantity comes from :func:`designer.model._caster.performance` and the V_c quantile from
:mod:`designer.physics.uncertainty`; only the inversions (P = ε for d, the shimmy constraint for B or
c_f through :func:`designer.physics.shimmy.critical_speed_terms`, the curve's shares) are written here.
"""

from __future__ import annotations

import functools
import math
import time
import warnings
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.model import VARIABLES, Design, performance, turning_effort, weighted
from designer.physics.geometry import swept_radius
from designer.physics.shimmy import critical_shimmy_speed, critical_speed_terms
from designer.physics.threshold import threshold_force
from designer.physics.uncertainty import Uncertainty, shimmy_speed_quantile
from designer.problem import Problem
from designer.solvers.base import NO_CAPS, Caps, Designs, Optimum, best_variant, objectives_of, no_optimum, weights_of

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

CONTRACTION = 0.8
"""Largest |s (log G)'| and |(1 − s)(log G)'| for which the risk-bounded closed form is used (< 1 is needed:
then V_q rises with T, c_f and B, and the edge maps of :func:`_edge_shares` contract)."""
SHARE_GRID = 33
"""Grid of friction shares between the box edges on which F_turn along the risk-bounded curve is compared."""
GOLDEN_STEPS = 60
"""Golden-section steps refining an interior grid minimum (0.618⁶⁰ ≈ 3e-13 of a grid cell)."""


def _predicted(problem: Problem) -> bool:
    """Whether the wheel is known by its diameter only (the risk law's I_w prediction depends on d)."""
    c = problem.conditions
    return c.uncertainty is not None and not bool(getattr(c.inertia, "measured", False))


@functools.lru_cache(maxsize=64)
def _bounds_box(bounds: Any) -> tuple[Design, Design]:
    """(lower, upper) of a problem's ``bounds`` (:meth:`Problem.lower`, :meth:`Problem.upper`; each builds and
    checks a :class:`Design`, about 0.1 ms, and a front reads them a few hundred times)."""
    return Design(*(bounds[v].low for v in VARIABLES)), Design(*(bounds[v].high for v in VARIABLES))


def _box(problem: Problem) -> tuple[Design, Design]:
    """The box of ``problem``: (lower, upper) bounds as designs, kept by the bounds (:func:`_bounds_box`)."""
    try:
        return _bounds_box(problem.bounds)
    except TypeError:  # bounds that cannot be a key (a mapping patched in by hand): built each time
        return problem.lower(), problem.upper()


def applicable(problem: Problem) -> bool:
    """Whether the closed form holds for ``problem`` (continuous, monotone cost; a risk bound whose G contracts,
    and, for a wheel known by its diameter, V_q falling with d).

    None of it reads the target speed: the answer is kept by what it reads (the conditions and the bounds), so
    a front, its recommendation and the next target's front check it once (:func:`_applicable_to`)."""
    if problem.wheels:
        return False
    try:
        return _applicable_to(problem.conditions, problem.bounds)
    except TypeError:  # conditions or bounds that cannot be a key (patched in by hand): checked each time
        return _applicable(problem.conditions, *_box(problem))


@functools.lru_cache(maxsize=64)
def _applicable_to(c: Any, bounds: Any) -> bool:
    """:func:`applicable` of a continuous problem with conditions ``c`` and ``bounds``, kept by them."""
    return _applicable(c, *_bounds_box(bounds))


def _applicable(c: Any, lo: Design, hi: Design) -> bool:
    """:func:`applicable` of a continuous problem with conditions ``c`` and the box ``lo``, ``hi``."""
    predicted = c.uncertainty is not None and not bool(getattr(c.inertia, "measured", False))  # as _predicted
    if c.uncertainty is not None:
        diameters = tuple(np.linspace(lo.diameter, hi.diameter, 9)) if predicted else (None,)
        if not all(_contracts(c.uncertainty, d) for d in diameters):
            return False
        if predicted and not _speed_falls_with_diameter(c, lo, hi):
            return False
    if c.turning.groove_coefficient < 0 or c.disturbance_angle <= 0 or c.slip_coefficient <= 0:
        return False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        # positive moment everywhere in the box (F = M/T falls with T); it is linear, so the corner suffices
        m = performance(hi.trail, hi.diameter, lo.groove, lo.damping, c)["turning_moment"]
        # I_w non-decreasing in d (checked on a grid of the box)
        d = np.linspace(lo.diameter, hi.diameter, 65)
        inertia = np.asarray(performance(hi.trail, d, lo.groove, lo.damping, c)["inertia"], float) + 0 * d
    return bool(m > 0 and np.all(np.diff(inertia) >= -1e-15 * np.abs(inertia[1:])))


def diameter_at(problem: Problem, eps: npt.ArrayLike) -> np.ndarray:
    """The diameter d at which P(d) = ε (Eq. 4A inverted): r(x − 2) = 2√(x − 1), r = ε/L, x = d/h.

    With y = √(x − 1): r y² − 2 y − r = 0, y = (1 + √(1 + r²))/r.  NaN for ε <= 0.
    """
    c = problem.conditions
    r = np.asarray(eps, float) / c.load
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.where(r > 0, (1 + np.sqrt(1 + r * r)) / r, np.nan)
    d: np.ndarray = (y * y + 1) * c.threshold_height
    return d


def _values(problem: Problem, x: np.ndarray) -> dict[str, Any]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return performance(x[..., 0], x[..., 1], x[..., 2], x[..., 3], problem.conditions)


def _turning_effort(problem: Problem, x: np.ndarray) -> np.ndarray:
    """F_turn [N] of designs ``x`` (..., 4) alone (Eq. 9; :func:`_values` computes every quantity)."""
    effort: np.ndarray = np.asarray(turning_effort(x[..., 0], x[..., 2], x[..., 3], problem.conditions), float)
    return effort


CANDIDATES = (
    "groove from Eq. 7 at the least damping",
    "damping from Eq. 7 at the least groove",
    "damping from Eq. 7 at the widest groove",
    "groove from Eq. 7 at the most damping",
)
"""The ends of the shimmy constraint curve in (B, c_f) at a given (T, d), in the order compared: F_turn
is concave along the curve, so its minimum is at one of them (docs/model.md)."""


def largest_trail(problem: Problem, d: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The largest admissible trail T [m] at each diameter ``d`` [m], and whether it reaches the trail's lower bound.

    T is capped by its upper bound and by the swept-radius limit R_s = T + d/2 <= R_max (geometry,
    docs/model.md#swept-radius); where the cap falls below the lower bound the diameter is infeasible (mask
    False) and T is clipped up to the lower bound.
    """
    d = np.asarray(d, float).ravel()
    lo, hi = _box(problem)
    t = np.full(len(d), hi.trail)
    if problem.swept_radius_max is not None:
        # R_s = T + d/2 is linear in T: T_max = R_max − R_s(0, d), from the geometry alone (the whole
        # model at T = 0 would divide by zero in F_turn = M/T)
        t = np.minimum(t, problem.swept_radius_max - np.asarray(swept_radius(0.0, d), float))
    ok = t >= lo.trail * (1 - 1e-12)
    return np.maximum(t, lo.trail), ok


def designs_at_diameter(
    problem: Problem, d: npt.ArrayLike, candidates: Sequence[int] | None = None, *, search: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """Least-F_turn designs at given diameters (T, B, c_f optimal): ((N, 4) designs, feasible mask).

    ``candidates`` : indices into :data:`CANDIDATES` to compare (default all four; fewer only to
    measure what one of them is worth); nominal problems only.  Risk-bounded problems: :func:`_risk_designs`,
    and ``search=False`` only to read the mask (the curve is not searched; the designs are then an end of it).
    """
    d = np.asarray(d, float).ravel()
    n = len(d)
    lo, hi = _box(problem)
    t, ok = largest_trail(problem, d)
    with warnings.catch_warnings():  # an extrapolated I_w is reported once, by the front (pareto_front)
        warnings.simplefilter("ignore", UserWarning)
        inertia = np.asarray(problem.conditions.inertia(d), float) + 0 * d  # I_w(d), as model.performance
    # per unit c_f, B²
    a, b = (
        np.asarray(v, float) for v in critical_speed_terms(t, inertia, 1.0, 1.0, problem.conditions.slip_coefficient)
    )
    if problem.conditions.uncertainty is not None:
        designs, feasible = _risk_designs(problem, t, d, a, b, search)
        return designs, ok & feasible
    need = problem.required_speed**2
    (b_lo, c_lo), (b_hi, c_hi) = (lo.groove, lo.damping), (hi.groove, hi.damping)
    with np.errstate(divide="ignore", invalid="ignore"):
        # c_f from the constraint at a given B; B from it at a given c_f

        def c_at(bb: npt.ArrayLike) -> np.ndarray:
            bb = np.asarray(bb, float)
            c: np.ndarray = np.maximum(c_lo, (need - b * bb * bb) / a)
            return c

        def b_at(cc: npt.ArrayLike) -> np.ndarray:
            g: np.ndarray = np.maximum(b_lo, np.sqrt(np.maximum(0.0, (need - a * np.asarray(cc, float)) / b)))
            return g

        cands = [
            (b_at(c_lo), np.full(n, c_lo)),
            (np.full(n, b_lo), c_at(b_lo)),
            (np.full(n, b_hi), c_at(b_hi)),
            (b_at(c_hi), np.full(n, c_hi)),
        ]
    if candidates is not None:
        cands = [cands[i] for i in candidates]
    tol = 1e-12
    xs, feas = [], []
    for bb, cc in cands:
        bb = np.where(np.isfinite(bb), bb, np.inf)
        cc = np.where(np.isfinite(cc), cc, np.inf)
        f = (bb <= b_hi * (1 + tol) + tol) & (cc <= c_hi * (1 + tol))
        xs.append(np.column_stack([t, d, np.minimum(bb, b_hi), np.minimum(cc, c_hi)]))
        feas.append(f)
    x = np.stack(xs)  # (candidates, N, 4)
    cost = _turning_effort(problem, x)
    cost = np.where(np.stack(feas), cost, np.inf)
    best = np.argmin(cost, axis=0)
    designs = x[best, np.arange(n)]
    feasible = ok & np.isfinite(cost[best, np.arange(n)])
    return designs, feasible


def log_gain(uncertainty: Uncertainty, share: npt.ArrayLike, diameter: npt.ArrayLike | None = None) -> np.ndarray:
    """log G(s) = 2 Q_{1−α}(s): how far log V_c² must exceed log V_req² at friction share s [-].

    Evaluated by :func:`designer.physics.uncertainty.shimmy_speed_quantile` on a probe design of share
    s (T = I_w = K_s = 1, V_c = 1): G depends on s and the scatter only, and for a wheel known by its
    ``diameter`` d [m] (broadcast with s) on Table 1's prediction scale at d too (a constant at fixed d).
    """
    s = np.asarray(share, float)
    damping, groove = s * np.pi / 4, np.sqrt(2 * (1 - s))  # a = s, b = 1 − s
    v = critical_shimmy_speed(1.0, 1.0, groove, damping, 1.0)
    d = None if diameter is None else np.broadcast_to(np.asarray(diameter, float), s.shape)
    return 2 * np.log(v / shimmy_speed_quantile(1.0, 1.0, groove, damping, 1.0, uncertainty, diameter=d))


@functools.lru_cache(maxsize=64)
def _contracts(uncertainty: Uncertainty, diameter: float | None = None) -> bool:
    """Whether |s (log G)'| and |(1 − s)(log G)'| stay <= :data:`CONTRACTION` on [0, 1] (2049-point grid), for a
    measured wheel (``diameter`` None) or one known by its diameter d [m]."""
    s = np.linspace(0.0, 1.0, 2049)
    slope = np.gradient(log_gain(uncertainty, s, diameter), s)
    return bool(np.all(np.isfinite(slope)) and np.max(np.abs(slope) * np.maximum(s, 1 - s)) <= CONTRACTION)


def _speed_falls_with_diameter(conditions: Any, lo: Design, hi: Design) -> bool:
    """A wheel known by its diameter: V_q falls with d at the largest trail and each (B, c_f) corner of the box
    (I_w grows as d^3.5 while the prediction scale narrows towards Table 1's middle; 65-point grid), under
    ``conditions``."""
    d = np.linspace(lo.diameter, hi.diameter, 65)
    for groove in (lo.groove, hi.groove):
        for damping in (lo.damping, hi.damping):
            x = np.stack(np.broadcast_arrays(hi.trail, d, groove, damping), axis=-1)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                values = performance(x[..., 0], x[..., 1], x[..., 2], x[..., 3], conditions)
            v = np.asarray(values["confident_speed"], float) + 0 * d
            if np.any(np.diff(v) > 1e-12 * v[1:]):
                return False
    return True


@functools.lru_cache(maxsize=32)
def _gain_table(uncertainty: Uncertainty) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """log G and its slope on 4097 shares in [0, 1]: the starting point of :func:`_edge_shares`' Newton steps."""
    s = np.linspace(0.0, 1.0, 4097)
    lg = log_gain(uncertainty, s)
    slope = np.gradient(lg, s)
    for a in (s, lg, slope):
        a.setflags(write=False)
    return s, lg, slope


def _edge_shares(
    u: Uncertainty,
    need: float,
    a: np.ndarray,
    b: np.ndarray,
    box: tuple[tuple[float, float], tuple[float, float]],
    diameter: npt.ArrayLike | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The shares [s1, s2] of the risk-bounded curve inside the box: c_f(s) in [c_lo, c_hi], B(s) in [B_lo, B_hi].

    Each edge is a fixed point: c_f(s) = c  ⇔  s = a c/(V² G(s));  B(s) = B  ⇔  s = 1 − b B²/(V² G(s)),
    maps that contract by |s (log G)'| resp. |(1 − s)(log G)'| <= :data:`CONTRACTION` (clipped to [0, 1]: an edge the curve
    does not reach gives 0 or 1).  Solved on the tabulated G (:func:`_gain_table`), then by Newton steps on
    the exact G until a step is below 1e-15.  c_f grows and B falls with s, so s1 = max(s at c_lo, s at B_hi)
    and s2 = min(s at c_hi, s at B_lo); s1 > s2 means the curve misses the box.
    """
    (b_lo, c_lo), (b_hi, c_hi) = box
    sign = np.array([1.0, 1.0, -1.0, -1.0])[:, None]  # c_f edges: s = m; B edges: s = 1 − m; m = k/G(s)
    base = np.array([0.0, 0.0, 1.0, 1.0])[:, None]
    k = np.vstack([a * c_lo, a * c_hi, b * b_hi**2, b * b_lo**2]) / need  # (4, N)
    s = np.full(k.shape, 0.5)
    if diameter is not None:  # G depends on d too: the fixed points on the exact G (contraction <= 0.8)
        d = np.broadcast_to(np.asarray(diameter, float), k.shape)

        def step(x: np.ndarray) -> np.ndarray:
            mapped: np.ndarray = np.clip(base + sign * k * np.exp(-log_gain(u, x, d)), 0.0, 1.0)
            return mapped

        s = _secant_fixed_point(step, s)
        return np.maximum(s[0], s[2]), np.minimum(s[1], s[3])
    grid, lg_table, slope_table = _gain_table(u)
    for _ in range(120):  # on the table: contraction <= 0.8 (typically 0.2)
        nxt = np.clip(base + sign * k * np.exp(-np.interp(s, grid, lg_table)), 0.0, 1.0)
        moved = np.max(np.abs(nxt - s))
        s = nxt
        if moved <= 1e-10:
            break
    for _ in range(8):  # Newton on s − base − sign·k/G(s) = 0 with the exact G (2-3 steps from the table)
        m = k * np.exp(-log_gain(u, s))
        h = s - base - sign * m
        step = h / (1 + sign * m * np.interp(s, grid, slope_table))
        nxt = np.clip(s - step, 0.0, 1.0)
        moved = np.max(np.abs(nxt - s))
        s = nxt
        if moved <= 1e-15:
            break
    return np.maximum(s[0], s[2]), np.minimum(s[1], s[3])


def _secant_fixed_point(step: Callable[[np.ndarray], np.ndarray], s: np.ndarray, tol: float = 1e-15) -> np.ndarray:
    """The fixed points s = step(s) of a contraction on [0, 1] (elementwise), from ``s``.

    Secant steps on h(s) = s − step(s) (order 1.6: about 7 evaluations of ``step`` where the plain iteration
    at a contraction of 0.2 takes 22), each kept only where it stays in [0, 1] and else replaced by the plain
    step, which always converges; the answer is a plain step from a point whose move is below ``tol`` (after
    400 rounds without that, the last plain step).
    """
    prev, g_prev = s, step(s)
    s = g = g_prev
    for _ in range(400):
        g = step(s)
        h, h_prev = s - g, prev - g_prev
        with np.errstate(divide="ignore", invalid="ignore"):
            secant = s - h * (s - prev) / (h - h_prev)
        ok = np.isfinite(secant) & (secant >= 0.0) & (secant <= 1.0) & (h != h_prev)
        residual = np.abs(h)
        moved = float(np.max(residual[np.isfinite(residual)], initial=0.0))  # a NaN share stays NaN, not a loop
        prev, g_prev, s = s, g, np.where(ok, secant, g)
        if moved <= tol:
            break
    return g


def _law(problem: Problem) -> Uncertainty:
    """The risk law of a risk-bounded problem (ValueError for a nominal one: the curve has no quantile)."""
    law = problem.conditions.uncertainty
    if law is None:
        raise ValueError(f"{problem.name}: the risk-bounded curve needs a risk bound")
    return law


def _on_curve(
    problem: Problem, t: np.ndarray, d: np.ndarray, a: np.ndarray, b: np.ndarray, s: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Designs on the risk-bounded curve at shares ``s`` (clipped into the box) and their F_turn [N]."""
    lo, hi = _box(problem)
    wheel = np.broadcast_to(d, np.shape(s)) if _predicted(problem) else None
    big = problem.required_speed**2 * np.exp(log_gain(_law(problem), s, wheel))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.clip(s * big / a, lo.damping, hi.damping)
        g = np.clip(np.sqrt(np.maximum(0.0, (1 - s) * big / b)), lo.groove, hi.groove)
    t, d = np.broadcast_to(t, s.shape), np.broadcast_to(d, s.shape)
    x = np.stack([t, d, g, c], axis=-1)
    return x, _turning_effort(problem, x) + 0 * s


def _risk_designs(
    problem: Problem, t: np.ndarray, d: np.ndarray, a: np.ndarray, b: np.ndarray, search: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """Least-F_turn designs at (T, d) under the risk bound: ((N, 4) designs, feasible mask) (module text).

    The corner (B_lo, c_lo) when it is feasible; else the cheapest of: the curve's two ends in the box,
    its best point on a grid of :data:`SHARE_GRID` shares, refined by golden section when it is inside.
    """
    n = len(d)
    lo, hi = _box(problem)
    u = _law(problem)
    corner = np.column_stack([t, d, np.full(n, lo.groove), np.full(n, lo.damping)])
    corner_ok = np.asarray(_values(problem, corner)["confident_speed"], float) >= problem.required_speed
    box = ((lo.groove, lo.damping), (hi.groove, hi.damping))
    s1, s2 = _edge_shares(u, problem.required_speed**2, a, b, box, d if _predicted(problem) else None)
    curve_ok = s1 <= s2 + 1e-15
    s2 = np.maximum(s1, s2)
    grid = s1[:, None] + (s2 - s1)[:, None] * np.linspace(0.0, 1.0, SHARE_GRID if search else 1)[None, :]
    xs, cost = _on_curve(problem, t[:, None], d[:, None], a[:, None], b[:, None], grid)
    j = np.argmin(cost, axis=1)
    rows = np.arange(n)
    best_x, best_f = xs[rows, j], cost[rows, j]
    inside = np.flatnonzero((j > 0) & (j < grid.shape[1] - 1) & curve_ok)
    if len(inside):  # golden section on the two cells around an interior grid minimum
        lo_s, hi_s = grid[inside, j[inside] - 1], grid[inside, j[inside] + 1]
        ti, di, ai, bi = t[inside], d[inside], a[inside], b[inside]
        ratio = (np.sqrt(5) - 1) / 2
        for _ in range(GOLDEN_STEPS):
            m1, m2 = hi_s - ratio * (hi_s - lo_s), lo_s + ratio * (hi_s - lo_s)
            f1 = _on_curve(problem, ti, di, ai, bi, m1)[1]
            f2 = _on_curve(problem, ti, di, ai, bi, m2)[1]
            lo_s, hi_s = np.where(f1 <= f2, lo_s, m1), np.where(f1 <= f2, m2, hi_s)
        x_r, f_r = _on_curve(problem, ti, di, ai, bi, (lo_s + hi_s) / 2)
        better = f_r < best_f[inside]
        best_x[inside[better]], best_f[inside[better]] = x_r[better], f_r[better]
    designs = np.where(corner_ok[:, None], corner, best_x)
    return designs, corner_ok | curve_ok


def _require(problem: Problem, what: str) -> None:
    """ValueError naming ``what`` the closed form was asked for when it does not apply (:func:`applicable`)."""
    if not applicable(problem):
        raise ValueError(
            f"the closed-form {what} need a continuous problem with a positive moment "
            "(and a risk bound whose quantile factor varies slowly with the friction share)"
        )


def structured_front_designs(problem: Problem, eps_array: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """ε-constraint optima min F_turn s.t. P <= ε for every ε: ((N, 4) designs, feasible mask).

    Raises ValueError when the closed form does not apply (see :func:`applicable`).
    """
    _require(problem, "ε-optima")
    eps = np.asarray(eps_array, float).ravel()
    lo, hi = _box(problem)
    with np.errstate(invalid="ignore"):
        d = np.maximum(lo.diameter, diameter_at(problem, eps))
    reach = np.isfinite(d) & (d <= hi.diameter * (1 + 1e-12))
    d = np.where(reach, np.minimum(d, hi.diameter), hi.diameter)
    designs, feasible = designs_at_diameter(problem, d)
    return designs, feasible & reach


def structured_ends(problem: Problem, rel: float = 1e-9, rounds: int = 9) -> tuple[np.ndarray, np.ndarray] | None:
    """The two lexicographic ends in closed form: (min F then min P, min P then min F) designs, or None.

    End A: d_lo's optimum F*, then the largest d whose optimum keeps F_turn <= F*(1 + rel) (bisection:
    F*(d) is non-decreasing).  End B: the largest feasible diameter (bisection: feasibility shrinks
    with d) gives the least P; the end is the ε-optimum at ε = P_min (1 + rel).  ``rel`` is the
    tolerance of the NLP's second lexicographic stage (:func:`designer.solvers.nlp.lexicographic_ends`).
    """
    _require(problem, "ends")
    lo, hi = _box(problem)
    # the first round of both searches is one grid, whose first point is d_lo: the feasibility mask is the same
    # with or without the search
    grid = np.linspace(lo.diameter, hi.diameter, 65)
    x_grid, ok = designs_at_diameter(problem, grid)
    if not ok[0]:
        return None
    f_min = float(_turning_effort(problem, x_grid[0]))
    tested: list[tuple[np.ndarray, np.ndarray]] = []  # every design found: end A is one of them

    def flat_and_feasible(dd: np.ndarray, found: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x, ok = designs_at_diameter(problem, dd) if found is None else found
        tested.append((dd, x))
        excess = _turning_effort(problem, x) - f_min * (1 + rel)  # F*(d) − F*(d_lo)(1 + rel) [N]
        return ok & (excess <= 0), np.where(ok, excess, np.nan), ok

    def flat(dd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return flat_and_feasible(dd)[:2]

    def short(dd: np.ndarray) -> np.ndarray:
        # feasible while the box's best corner (largest T, B, c_f) reaches V_req: V_q rises with T, B and c_f
        t = largest_trail(problem, dd)[0]
        x = np.column_stack([t, dd, np.full(len(dd), hi.groove), np.full(len(dd), hi.damping)])
        speed = "confident_speed" if problem.conditions.uncertainty is not None else "critical_speed"
        missing: np.ndarray = problem.required_speed - np.asarray(_values(problem, x)[speed], float)  # [m/s]
        return missing

    def feasible(dd: np.ndarray, found: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        missing = short(dd)
        if problem.conditions.uncertainty is None:  # the candidates' own mask (cheap without a risk law)
            return designs_at_diameter(problem, dd, search=False)[1] if found is None else found, missing
        # V_q rises with T, B and c_f: the curve meets the box where its best corner is feasible (shares not needed)
        return largest_trail(problem, dd)[1] & (missing <= 0), missing

    is_flat, excess, ok = flat_and_feasible(grid, (x_grid, ok))
    d_a = _largest(flat, lo.diameter, hi.diameter, rounds, first=(is_flat, excess))
    ok, missing = feasible(grid, ok)
    d_b = float(hi.diameter) if ok[-1] else _largest(feasible, lo.diameter, hi.diameter, rounds, first=(ok, missing))
    xa = next((x[dd == d_a][0] for dd, x in reversed(tested) if np.any(dd == d_a)), None)
    xa = designs_at_diameter(problem, [d_a])[0][0] if xa is None else xa  # (a d the search did not test: none)
    p_min = float(threshold_force(d_b, problem.conditions.threshold_height, problem.conditions.load))  # Eq. 4A: d only
    xb, ok = structured_front_designs(problem, [p_min * (1 + rel)])
    return xa, xb[0]


# --------------------------------------------------------------------------- the solver protocol

WEIGHTED_GRID = 513
"""ε-grid between the front's ends on which :meth:`ClosedFormSolver.optimum` compares J before refining."""


class ClosedFormSolver:
    """The closed form as a solver (:class:`designer.solvers.base.Solver`): ε-optima and the weighted optimum.

    ``front_designs`` is :func:`structured_front_designs`.  ``optimum`` uses that the weighted optimum is an
    ε-optimum (a design with lower J would have a lower F_turn at the same P): J(ε) = w_turn F_turn(x(ε)) +
    w_threshold P(x(ε)) is compared on :data:`WEIGHTED_GRID` values of ε between the ends' P
    (:func:`structured_ends`; an ε cap lowers the upper end, a turning cap removes points) and its least value
    refined by golden section over the two grid cells around it.  A catalog problem is solved per wheel.
    """

    name = "closed-form"
    tolerance = 1e-7

    def applicable(self, problem: Problem) -> bool:
        """:func:`applicable` for every continuous variant (one per catalog wheel)."""
        return all(applicable(v) for v in problem.variants())

    def front_designs(self, problem: Problem, eps: npt.ArrayLike) -> Designs:
        """:func:`structured_front_designs` as :class:`~designer.solvers.base.Designs` (ValueError where it does
        not apply)."""
        e = np.asarray(eps, float).ravel()
        x, ok = structured_front_designs(problem, e)
        return Designs(
            solver=self.name,
            epsilon=e,
            designs=x,
            success=ok,
            objectives=objectives_of(problem, x),
            status=tuple("optimal" if k else "infeasible" for k in ok),
        )

    def optimum(
        self,
        problem: Problem,
        weights: Sequence[float] | None = None,
        caps: Caps = NO_CAPS,
        *,
        starts: Sequence[Any] = (),
    ) -> Optimum:
        """The weighted optimum in closed form (class text); ``starts`` are not needed.  ValueError where the
        closed form does not apply (:meth:`applicable`)."""
        if not self.applicable(problem):
            raise ValueError(f"{problem.name}: the closed form does not apply (designer.solvers.closed_form)")
        w = weights_of(problem, weights)
        return best_variant(problem, lambda variant: self._optimum(variant, w, caps))

    def _optimum(self, problem: Problem, w: tuple[float, float], caps: Caps) -> Optimum:
        t0 = time.perf_counter()
        ends = structured_ends(problem)
        if ends is None:
            return no_optimum(self.name, problem, w, caps, "infeasible")
        p_b, p_a = (float(v) for v in objectives_of(problem, np.array(ends))[::-1, 1])
        high = p_a if caps.threshold is None else min(p_a, caps.threshold)
        if high < p_b * (1 - 1e-12):
            return no_optimum(self.name, problem, w, caps, "infeasible")
        high = max(high, p_b)

        def cost(eps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            x, ok = structured_front_designs(problem, eps)
            f, p = objectives_of(problem, x)[:, :2].T
            if caps.turning is not None:
                ok = ok & (f <= caps.turning * (1 + 1e-12))
            return x, np.where(ok, weighted(f, p, w), np.inf)

        low = p_b
        if caps.turning is not None:  # F_turn(x(ε)) does not increase with ε: the least ε meeting the cap
            if not np.isfinite(cost(np.array([high]))[1][0]):
                return no_optimum(self.name, problem, w, caps, "infeasible")
            if not np.isfinite(cost(np.array([low]))[1][0]):
                low = _least(lambda e: np.isfinite(cost(e)[1]), low, high)
        grid = np.linspace(low, high, WEIGHTED_GRID)
        x, j = cost(grid)
        k = int(np.argmin(j))
        if not np.isfinite(j[k]):
            return no_optimum(self.name, problem, w, caps, "infeasible")
        best_x, best_j = x[k], float(j[k])
        lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
        ratio = (math.sqrt(5) - 1) / 2
        for _ in range(GOLDEN_STEPS):
            m1, m2 = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
            _, (j1, j2) = cost(np.array([m1, m2]))
            lo, hi = (lo, m2) if j1 <= j2 else (m1, hi)
        x_r, j_r = cost(np.array([(lo + hi) / 2]))
        if j_r[0] < best_j:
            best_x, best_j = x_r[0], float(j_r[0])
        return Optimum(
            solver=self.name,
            problem=problem,
            weights=w,
            caps=caps,
            design=Design.from_array(best_x),
            objective=best_j,
            success=True,
            status="optimal",
            solves=WEIGHTED_GRID + 2 * GOLDEN_STEPS + 1,
            seconds=time.perf_counter() - t0,
        )


ZOOM_POINTS = 17
"""Points of a zoomed round of :func:`_largest` (a window around the predicted boundary)."""


def _crossing(x: np.ndarray, h: np.ndarray, k: int) -> tuple[float, float]:
    """Where h crosses 0 between x[k] and x[k + 1], predicted from three values beside that cell (those after it,
    else those before it; h smooth there): (inverse quadratic interpolation, its distance from the secant's
    prediction: the error estimate); (nan, nan) without three distinct finite values."""
    for idx in ((k + 1, k + 2, k + 3), (k - 2, k - 1, k)):
        if min(idx) < 0 or max(idx) >= len(x):
            continue
        (x0, x1, x2), (h0, h1, h2) = x[list(idx)], h[list(idx)]
        if not np.all(np.isfinite([h0, h1, h2])) or h0 == h1 or h1 == h2 or h0 == h2:
            continue
        near = (x0, h0, x1, h1) if idx[0] > k else (x1, h1, x2, h2)
        secant = near[0] - near[1] * (near[2] - near[0]) / (near[3] - near[1])
        quadratic = (
            x0 * h1 * h2 / ((h0 - h1) * (h0 - h2))
            + x1 * h0 * h2 / ((h1 - h0) * (h1 - h2))
            + x2 * h0 * h1 / ((h2 - h0) * (h2 - h1))
        )
        if np.isfinite(secant) and np.isfinite(quadratic):
            return float(quadratic), float(abs(quadratic - secant))
    return math.nan, math.nan


def _largest(
    test: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    a: float,
    b: float,
    rounds: int = 9,
    first: tuple[np.ndarray, np.ndarray] | None = None,
) -> float:
    """:func:`_least` with ``largest`` (the largest x in [a, b] where the monotone predicate holds, to 1e-15
    relative), fewer rounds: ``test(x)`` gives the predicate and a value h(x) smooth where it is finite that
    crosses 0 near where the predicate turns false (F*(d) − F*(d_lo)(1 + rel), V_req − V_q).

    Each round after the first (a uniform 65-point grid, as :func:`_least`'s) predicts the boundary from h
    (:func:`_crossing`) and tests a window of :data:`ZOOM_POINTS` around it, as wide as four times the
    prediction's error estimate; the predicate alone decides: a window in which it does not turn false is dropped
    for a uniform round on what remains of the cell.  The answer is the largest point found true whose neighbour
    found false is within 1e-15 relative, as :func:`_least`'s.  ``first``: ``test`` of the first round's grid
    (``numpy.linspace(a, b, 65)``), when the caller has it."""
    grid = np.linspace(a, b, 65)
    ok, h = test(grid) if first is None else first
    if ok[-1]:
        return float(b)
    for _ in range(4 * rounds):
        k = int(np.flatnonzero(ok).max()) if ok.any() else 0
        lo_x, hi_x = float(grid[k]), float(grid[min(k + 1, len(grid) - 1)])
        if hi_x - lo_x <= 1e-15 * hi_x:
            break
        cell = hi_x - lo_x
        guess, error = _crossing(grid, h, k)
        half = max(4 * error, 4e-15 * hi_x)
        if lo_x <= guess <= hi_x and half <= cell / 8:
            window = np.linspace(max(lo_x, guess - half), min(hi_x, guess + half), ZOOM_POINTS)
            w_ok, w_h = test(window)
            if w_ok[0] and not w_ok[-1]:
                grid, ok, h = window, w_ok, w_h
                continue
            # missed: the boundary is before the window (false at its start) or after it (true at its end)
            lo_x, hi_x = (lo_x, float(window[0])) if not w_ok[0] else (float(window[-1]), hi_x)
        grid = np.linspace(lo_x, hi_x, 65)
        ok, h = test(grid)
    k = int(np.flatnonzero(ok).max()) if ok.any() else 0
    return float(grid[k])


def _least(
    pred: Callable[[np.ndarray], np.ndarray], a: float, b: float, rounds: int = 9, *, largest: bool = False
) -> float:
    """The least x in [a, b] with pred(x), pred monotone (false then true, true at b), by grid refinement; with
    ``largest`` the largest x with pred(x) (pred true then false; b when pred(b))."""
    if largest and pred(np.array([b]))[0]:
        return float(b)
    for _ in range(rounds):
        grid = np.linspace(a, b, 65)
        ok = pred(grid)
        if largest:
            k = int(np.flatnonzero(ok).max()) if ok.any() else 0
            a, b = grid[k], grid[min(k + 1, 64)]
        else:
            k = int(np.flatnonzero(ok).min()) if ok.any() else 64
            a, b = grid[max(k - 1, 0)], grid[k]
        if b - a <= 1e-15 * b:
            break
    return float(a if largest else b)


CLOSED_FORM = ClosedFormSolver()
"""The closed form's :class:`~designer.solvers.base.Solver`."""
