"""Independent cross-check with scipy's SLSQP on the same model.

SLSQP sees only the NumPy evaluation of :func:`designer.model._caster.performance`
(finite-difference gradients), a different formulation and algorithm from
the CasADi/IPOPT NLP, so agreement between the two is meaningful.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.optimize import minimize

from designer.errors import check_interrupt
from designer.model import Design, performance, weighted
from designer.parameters import named
from designer.problem import Problem
from designer.solvers.base import (
    NO_CAPS,
    Caps,
    Designs,
    Optimum,
    best_variant,
    found_optimum,
    optima_designs,
    weights_of,
)

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt


def slsqp(
    problem: Problem,
    weights: Sequence[float] | None = None,
    starts: Sequence[Any] = (),
    random_starts: int = 5,
    seed: int = 0,
    threshold_cap: float | None = None,
    turning_cap: float | None = None,
) -> tuple[Design | None, float]:
    """Minimise J = w_turn F_turn + w_threshold P with SLSQP from several starts.

    Parameters
    ----------
    problem : a continuous problem (no catalog choice)
    weights : (w_turn, w_threshold); default the problem's
    starts : designs (or SI arrays) to start from, e.g. the NLP optimum
    random_starts : additional uniform random starts in the box
    threshold_cap : optional ε-constraint P <= ε [N]
    turning_cap : optional ε-constraint F_turn <= ε [N]

    Returns
    -------
    (design, J) : best feasible design and its objective [N]; (None, nan) if none.
    """
    w = np.asarray(problem.weights if weights is None else weights, float)
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    scale = np.maximum(hi, np.array([0.01, 0.05, 0.005, 1.0]))
    c = problem.conditions

    def perf(z: npt.ArrayLike) -> dict[str, Any]:
        x = np.asarray(z) * scale
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return performance(**named(x), conditions=c)

    f_ref = float(perf((lo + hi) / 2 / scale)["turning_effort"])
    p_ref = float(perf((lo + hi) / 2 / scale)["threshold_force"])

    def objective(z: np.ndarray) -> float:
        v = perf(z)
        return float(weighted(v["turning_effort"], v["threshold_force"], w) / weighted(f_ref, p_ref, w))

    cons = [{"type": "ineq", "fun": lambda z: float(perf(z)["confident_speed"]) / problem.required_speed - 1}]
    # the upper limits: R_s <= R_max (relative), the ε caps P <= ε_P, F_turn <= ε_F (scaled by the box centre's)
    limits = (("swept_radius", problem.swept_radius_max, None), ("threshold_force", threshold_cap, p_ref))
    upper = [(k, cap, ref) for k, cap, ref in (*limits, ("turning_effort", turning_cap, f_ref)) if cap is not None]
    for key, cap, ref in upper:
        if ref is None:
            cons.append({"type": "ineq", "fun": lambda z, k=key, m=cap: 1 - float(perf(z)[k]) / m})
        else:
            cons.append({"type": "ineq", "fun": lambda z, k=key, m=cap, r=ref: (m - float(perf(z)[k])) / r})
    rng = np.random.default_rng(seed)
    all_starts = [np.asarray(s.as_array() if isinstance(s, Design) else s, float) for s in starts]
    all_starts += [lo + rng.random(4) * (hi - lo) for _ in range(random_starts)]
    bounds = list(zip(lo / scale, hi / scale))
    best: tuple[Design | None, float] = (None, float("nan"))
    for start in all_starts:
        z0 = np.clip(start / scale, lo / scale, hi / scale)
        res = minimize(
            objective, z0, method="SLSQP", bounds=bounds, constraints=cons, options={"ftol": 1e-12, "maxiter": 500}
        )
        check_interrupt()
        z = np.clip(res.x, lo / scale, hi / scale)
        v = perf(z)
        feasible = float(v["confident_speed"]) >= problem.required_speed * (1 - 1e-7)
        if not (feasible and all(float(v[k]) <= cap * (1 + 1e-7) for k, cap, _ in upper)):
            continue
        j = float(weighted(v["turning_effort"], v["threshold_force"], w))
        if best[0] is None or j < best[1]:
            best = (Design.from_array(z * scale), j)
    return best


class SLSQPSolver:
    """SLSQP as a solver of the protocol (:class:`designer.solvers.base.Solver`): :func:`slsqp` from the given
    starts and :attr:`random_starts` uniform ones, per catalog wheel; ``front_designs`` solves min F_turn s.t.
    P <= ε at each ε the same way (the previous ε's optimum is a start of the next)."""

    name = "scipy-slsqp"
    tolerance = 1e-4

    def __init__(self, random_starts: int = 5, seed: int = 0):
        self.random_starts, self.seed = random_starts, seed

    def applicable(self, problem: Problem) -> bool:
        """SLSQP takes every problem (a catalog one per wheel)."""
        return True

    def optimum(
        self,
        problem: Problem,
        weights: Sequence[float] | None = None,
        caps: Caps = NO_CAPS,
        *,
        starts: Sequence[Any] = (),
    ) -> Optimum:
        """The best feasible SLSQP optimum (J by the NumPy model) from ``starts`` and the random starts."""
        w = weights_of(problem, weights)

        def one(variant: Problem) -> Optimum:
            t0 = time.perf_counter()
            design, j = slsqp(variant, w, starts, self.random_starts, self.seed, caps.threshold, caps.turning)
            if design is None:
                return found_optimum(self.name, variant, w, caps, None, status="infeasible")
            solves, seconds = len(starts) + self.random_starts, time.perf_counter() - t0
            return found_optimum(self.name, variant, w, caps, design, objective=j, solves=solves, seconds=seconds)

        return best_variant(problem, one)

    def front_designs(self, problem: Problem, eps: npt.ArrayLike) -> Designs:
        """min F_turn s.t. P <= ε at each ε of a continuous problem (warm from the previous ε's optimum)."""
        e = np.asarray(eps, float).ravel()
        found: list[Optimum] = []
        for cap in e:
            start = [] if not found or found[-1].design is None else [found[-1].design]
            found.append(self.optimum(problem, (1.0, 0.0), Caps(threshold=float(cap)), starts=start))
        return optima_designs(self.name, problem, e, found, solves=len(e) * (1 + self.random_starts))


SLSQP = SLSQPSolver()
"""SLSQP's :class:`~designer.solvers.base.Solver`."""

__all__ = ["SLSQP", "SLSQPSolver", "slsqp"]
