"""Closed-form ε-constraint optima of a non-robust continuous problem.

For min F_turn s.t. P <= ε, V_c >= V_req (Eq. 7), R_s <= R_max and the box the
subproblem has structure (valid when ``conditions.uncertainty is None``, the
turning moment is positive and its coefficients in B and c_f are >= 0):

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

Every model quantity comes from :func:`designer.model.performance`; only the two
inversions (P = ε for d, the Eq. 7 constraint for B or c_f through
:func:`designer.physics.shimmy.critical_speed_terms`) are written here.
"""
from __future__ import annotations

import warnings

import numpy as np

from designer.model import performance
from designer.physics.geometry import swept_radius
from designer.physics.shimmy import critical_speed_terms


def applicable(problem) -> bool:
    """Whether the closed form holds for ``problem`` (continuous, non-robust, monotone cost)."""
    if problem.wheels or problem.conditions.uncertainty is not None:
        return False
    c = problem.conditions
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    if c.turning.groove_coefficient < 0 or c.disturbance_angle <= 0 or c.slip_coefficient <= 0:
        return False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        # positive moment everywhere in the box (F = M/T falls with T); it is linear, so the corner suffices
        m = performance(hi[0], hi[1], lo[2], lo[3], c)["turning_moment"]
        # I_w non-decreasing in d (checked on a grid of the box)
        d = np.linspace(lo[1], hi[1], 65)
        inertia = np.asarray(performance(hi[0], d, lo[2], lo[3], c)["inertia"], float) + 0 * d
    return bool(m > 0 and np.all(np.diff(inertia) >= -1e-15 * np.abs(inertia[1:])))


def diameter_at(problem, eps) -> np.ndarray:
    """The diameter d at which P(d) = ε (Eq. 4A inverted): r(x − 2) = 2√(x − 1), r = ε/L, x = d/h.

    With y = √(x − 1): r y² − 2 y − r = 0, y = (1 + √(1 + r²))/r.  NaN for ε <= 0.
    """
    c = problem.conditions
    r = np.asarray(eps, float) / c.load
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.where(r > 0, (1 + np.sqrt(1 + r * r)) / r, np.nan)
    return (y * y + 1) * c.threshold_height


def _values(problem, x):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return performance(x[..., 0], x[..., 1], x[..., 2], x[..., 3], problem.conditions)


CANDIDATES = ("groove from Eq. 7 at the least damping", "damping from Eq. 7 at the least groove",
              "damping from Eq. 7 at the widest groove", "groove from Eq. 7 at the most damping")
"""The ends of the shimmy constraint curve in (B, c_f) at a given (T, d), in the order compared: F_turn
is concave along the curve, so its minimum is at one of them (docs/model.md)."""


def designs_at_diameter(problem, d, candidates=None) -> tuple[np.ndarray, np.ndarray]:
    """Least-F_turn designs at given diameters (T, B, c_f optimal): ((N, 4) designs, feasible mask).

    ``candidates`` : indices into :data:`CANDIDATES` to compare (default all four; fewer only to
    measure what one of them is worth).
    """
    d = np.asarray(d, float).ravel()
    n = len(d)
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    t = np.full(n, hi[0])
    if problem.swept_radius_max is not None:
        # R_s = T + d/2 is linear in T: T_max = R_max − R_s(0, d), from the geometry alone (the whole
        # model at T = 0 would divide by zero in F_turn = M/T)
        t = np.minimum(t, problem.swept_radius_max - np.asarray(swept_radius(0.0, d), float))
    ok = t >= lo[0] * (1 - 1e-12)
    t = np.maximum(t, lo[0])
    probe = np.column_stack([t, d, np.ones(n), np.ones(n)])
    inertia = np.asarray(_values(problem, probe)["inertia"], float) + 0 * d
    a, b = critical_speed_terms(t, inertia, 1.0, 1.0, problem.conditions.slip_coefficient)  # per unit c_f, B²
    need = problem.required_speed ** 2
    (b_lo, c_lo), (b_hi, c_hi) = (lo[2], lo[3]), (hi[2], hi[3])
    with np.errstate(divide="ignore", invalid="ignore"):
        # c_f from the constraint at a given B; B from it at a given c_f
        c_at = lambda bb: np.maximum(c_lo, (need - b * bb * bb) / a)  # noqa: E731
        b_at = lambda cc: np.maximum(b_lo, np.sqrt(np.maximum(0.0, (need - a * cc) / b)))  # noqa: E731
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
    cost = np.asarray(_values(problem, x)["turning_effort"], float)
    cost = np.where(np.stack(feas), cost, np.inf)
    best = np.argmin(cost, axis=0)
    designs = x[best, np.arange(n)]
    feasible = ok & np.isfinite(cost[best, np.arange(n)])
    return designs, feasible


def structured_front_designs(problem, eps_array) -> tuple[np.ndarray, np.ndarray]:
    """ε-constraint optima min F_turn s.t. P <= ε for every ε: ((N, 4) designs, feasible mask).

    Raises ValueError when the closed form does not apply (see :func:`applicable`).
    """
    if not applicable(problem):
        raise ValueError("the closed-form ε-optima need a continuous, non-robust problem with a positive moment")
    eps = np.asarray(eps_array, float).ravel()
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    with np.errstate(invalid="ignore"):
        d = np.maximum(lo[1], diameter_at(problem, eps))
    reach = np.isfinite(d) & (d <= hi[1] * (1 + 1e-12))
    d = np.where(reach, np.minimum(d, hi[1]), hi[1])
    designs, feasible = designs_at_diameter(problem, d)
    return designs, feasible & reach


def structured_ends(problem, rel: float = 1e-9, rounds: int = 9):
    """The two lexicographic ends in closed form: (min F then min P, min P then min F) designs, or None.

    End A: d_lo's optimum F*, then the largest d whose optimum keeps F_turn <= F*(1 + rel) (bisection:
    F*(d) is non-decreasing).  End B: the largest feasible diameter (bisection: feasibility shrinks
    with d) gives the least P; the end is the ε-optimum at ε = P_min (1 + rel).  ``rel`` is the
    tolerance of the NLP's second lexicographic stage (:func:`designer.analysis.sweeps.lexicographic_ends`).
    """
    if not applicable(problem):
        raise ValueError("the closed-form ends need a continuous, non-robust problem with a positive moment")
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    x_lo, ok_lo = designs_at_diameter(problem, [lo[1]])
    if not ok_lo[0]:
        return None
    f_min = float(_values(problem, x_lo[0])["turning_effort"])

    def largest(pred):
        """Largest d in [d_lo, d_hi] with pred(d) (pred monotone: true then false), by grid refinement."""
        a, b = lo[1], hi[1]
        if pred(np.array([b]))[0]:
            return b
        for _ in range(rounds):
            grid = np.linspace(a, b, 65)
            ok = pred(grid)
            k = int(np.flatnonzero(ok).max()) if ok.any() else 0
            a, b = grid[k], grid[min(k + 1, 64)]
            if b - a <= 1e-15 * b:
                break
        return a

    def flat(dd):
        x, ok = designs_at_diameter(problem, dd)
        return ok & (np.asarray(_values(problem, x)["turning_effort"], float) <= f_min * (1 + rel))

    def feasible(dd):
        return designs_at_diameter(problem, dd)[1]

    d_a, d_b = largest(flat), largest(feasible)
    xa, _ = designs_at_diameter(problem, [d_a])
    xb, _ = designs_at_diameter(problem, [d_b])
    p_min = float(_values(problem, xb[0])["threshold_force"])
    xb, ok = structured_front_designs(problem, [p_min * (1 + rel)])
    return xa[0], xb[0]
