"""Groove against damper: what each mechanism costs in turning effort to stop shimmy.

For a problem's conditions and a few wheel diameters, the least turning
effort F_turn [N] that reaches the required critical speed V_req (Eq. 7)

- by the groove alone (damping held at its lower bound, the bare fork),
- by the damper alone (groove held at its lower bound, usually B = 0),
- by the optimum mix (both free),

each solved exactly and vectorised over the diameters, with no NLP (the trail is free
in every case):

- nominal problems (V_c >= V_req): the closed form of
  :func:`designer.solvers.closed_form.designs_at_diameter` on the problem with the
  other mechanism held at its lower bound;
- risk-bounded problems (the α-quantile of V_c >= V_req): the same structure
  (trail at its largest admissible value, then the cheapest point of the constraint
  curve in the (B, c_f) box), with the constraint curve found by vectorised bisection
  on :func:`designer.model._caster.performance`'s ``confident_speed`` at the box's edges and on a
  grid of grooves.

Nothing here re-types an equation: :func:`designer.model._caster.performance` does the physics.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.model import Design, performance
from designer.parameters import named
from designer.problem import Bound, Problem
from designer.reprs import Record
from designer.solvers import closed_form
from designer.solvers.base import wheel_of

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

MECHANISMS = ("groove alone", "damper alone", "optimum mix")
"""The three ways of reaching V_req compared in the trade-off figure."""
BISECTIONS = 60
"""Bisection steps of the risk-bounded constraint curve (2⁻⁶⁰ of the box: below float precision)."""
GROOVE_GRID = 33
"""Grooves tried along the risk-bounded constraint curve for the optimum mix (besides the edges)."""


@dataclass(frozen=True, kw_only=True)
class TradeoffRow(Record):
    """Least turning effort at one diameter for each mechanism.

    Attributes
    ----------
    diameter : wheel diameter d [m]
    wheel : Table 1 wheel letter for catalog problems, else None
    effort : {mechanism: F_turn [N] or None when V_req cannot be reached}
    designs : {mechanism: Design or None}
    """

    diameter: float
    wheel: str | None
    effort: dict[str, float | None] = field(default_factory=dict)
    designs: dict[str, Design | None] = field(default_factory=dict)

    _units = {"diameter": "m", **{f"effort.{m}": "N" for m in MECHANISMS}}


def _restricted(problem: Problem, mechanism: str) -> Problem:
    """The problem with the other mechanism held at its lower bound (bare fork or no groove)."""
    bounds = dict(problem.bounds)
    held = {"groove alone": "damping", "damper alone": "groove"}.get(mechanism)
    if held is not None:
        bounds[held] = Bound(bounds[held].low, bounds[held].low)
    return problem.replace(bounds=bounds)


def diameters_for(problem: Problem, count: int = 25) -> list[tuple[Problem, float, str | None]]:
    """(sub-problem, diameter [m], wheel) triples to compare: catalog wheels, the fixed d, or a grid over the bounds."""
    if problem.wheels:
        return [(v, v.bounds["diameter"].low, wheel_of(v)) for v in problem.variants()]
    b = problem.bounds["diameter"]
    if b.fixed:
        return [(problem, b.low, None)]
    return [(problem, float(d), None) for d in np.linspace(b.low, b.high, count)]


def _values(problem: Problem, trail: Any, diameter: Any, groove: Any, damping: Any) -> dict[str, Any]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return performance(trail, diameter, groove, damping, problem.conditions)


def _least(
    problem: Problem,
    speed: Callable[..., Any],
    lo: npt.ArrayLike,
    hi: npt.ArrayLike,
    fixed_args: tuple[np.ndarray, ...],
    which: int,
) -> np.ndarray:
    """Least value in [lo, hi] of argument ``which`` (2 = B, 3 = c_f) with speed >= V_req; NaN where none.

    ``speed(x)`` is the constraint's speed [m/s], increasing in the argument; vectorised bisection.
    """
    need = problem.required_speed
    low = np.broadcast_to(np.asarray(lo, float), fixed_args[0].shape).copy()
    high = np.broadcast_to(np.asarray(hi, float), fixed_args[0].shape).copy()

    def ok(v: np.ndarray) -> np.ndarray:
        args = list(fixed_args)
        args[which] = v
        reached: np.ndarray = np.asarray(speed(*args), float) >= need
        return reached

    at_lo, at_hi = ok(low), ok(high)
    a, b = low.copy(), high.copy()
    for _ in range(BISECTIONS):
        mid = 0.5 * (a + b)
        good = ok(mid)
        b = np.where(good, mid, b)
        a = np.where(good, a, mid)
    least: np.ndarray = np.where(at_lo, low, np.where(at_hi, b, np.nan))
    return least


def designs_at_diameters(problem: Problem, d: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Least-F_turn designs reaching V_req at diameters ``d`` [m]: ((N, 4) designs, feasible mask).

    Nominal problems use the closed form of :func:`designer.solvers.closed_form.designs_at_diameter`;
    risk-bounded ones the same structure with a bisected constraint curve (module docstring).
    """
    d = np.asarray(d, float).ravel()
    if closed_form.applicable(problem):
        return closed_form.designs_at_diameter(problem, d)
    n = len(d)
    lo, hi = problem.lower(), problem.upper()
    t, reach = closed_form.largest_trail(problem, d)
    grooves = np.unique(np.concatenate([[lo.groove, hi.groove], np.linspace(lo.groove, hi.groove, GROOVE_GRID)]))
    m = len(grooves)
    tt, dd = np.repeat(t, m), np.repeat(d, m)
    bb = np.tile(grooves, n)

    def speed(t_: Any, d_: Any, b_: Any, c_: Any) -> Any:
        return _values(problem, t_, d_, b_, c_)["confident_speed"]

    c_at_b = _least(problem, speed, lo.damping, hi.damping, (tt, dd, bb, np.full(n * m, lo.damping)), 3)
    b_at_c = [
        _least(problem, speed, lo.groove, hi.groove, (t, d, np.full(n, lo.groove), np.full(n, c)), 2)
        for c in (lo.damping, hi.damping)
    ]
    cand_b = np.concatenate([bb.reshape(n, m), np.column_stack([b_at_c[0], b_at_c[1]])], axis=1)
    ends = np.column_stack([np.full(n, lo.damping), np.full(n, hi.damping)])
    cand_c = np.concatenate([c_at_b.reshape(n, m), ends], axis=1)
    k = cand_b.shape[1]
    ok = np.isfinite(cand_b) & np.isfinite(cand_c)
    safe_b, safe_c = np.where(ok, cand_b, lo.groove), np.where(ok, cand_c, lo.damping)
    tk, dk = np.repeat(t, k).reshape(n, k), np.repeat(d, k).reshape(n, k)
    cost = np.asarray(_values(problem, tk, dk, safe_b, safe_c)["turning_effort"], float)
    cost = np.where(ok, cost, np.inf)
    best = np.argmin(cost, axis=1)
    rows = np.arange(n)
    designs = np.column_stack([t, d, safe_b[rows, best], safe_c[rows, best]])
    return designs, reach & np.isfinite(cost[rows, best])


def groove_damper_tradeoff(problem: Problem, count: int = 25) -> list[TradeoffRow]:
    """Least F_turn reaching V_req by groove alone, damper alone and both, at several diameters.

    Parameters
    ----------
    problem : the design problem (its load, surface, sill, target, risk bound and bounds)
    count : number of diameters across the diameter bounds (ignored for a
        fixed diameter or a catalog of wheels)

    Returns
    -------
    list of TradeoffRow, by increasing diameter
    """
    groups: dict[int, tuple[Problem, list[tuple[float, str | None]]]] = {}
    for sub, d, wheel in diameters_for(problem, count):
        groups.setdefault(id(sub), (sub, []))[1].append((d, wheel))
    rows: list[TradeoffRow] = []
    for sub, items in groups.values():
        ds = np.array([d for d, _ in items])
        found = {}
        for mechanism in MECHANISMS:
            restricted = _restricted(sub, mechanism) if mechanism != "optimum mix" else sub
            designs, feasible = designs_at_diameters(restricted, ds)
            effort = np.asarray(_values(sub, **named(designs))["turning_effort"], float)
            found[mechanism] = (designs, feasible & np.isfinite(effort), effort)
        for i, (d, wheel) in enumerate(items):
            ok = {mechanism: bool(f[i]) for mechanism, (_, f, _) in found.items()}
            row = TradeoffRow(  # built once: a record does not change
                diameter=float(d),
                wheel=wheel,
                effort={m: float(e[i]) if ok[m] else None for m, (_, _, e) in found.items()},
                designs={m: Design.from_array(x[i]) if ok[m] else None for m, (x, _, _) in found.items()},
            )
            rows.append(row)
    rows.sort(key=lambda r: (r.diameter, r.wheel or ""))
    return rows
