"""Groove against damper: what each mechanism costs in turning effort to stop shimmy.

For a problem's conditions and a few wheel diameters, the least turning
effort F_turn [N] that reaches the required critical speed V_req (Eq. 7)

- by the groove alone (damping held at its lower bound, the bare fork),
- by the damper alone (groove held at its lower bound, usually B = 0),
- by the optimum mix (both free),

each solved exactly with :func:`designer.analysis.optimise.optimise` on the problem
restricted to that diameter (the trail is free in every case).  Nothing here
re-types an equation: the NLP and :func:`designer.model.performance` do the
physics.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from designer.errors import DesignerError
from designer.problem import Bound, Problem

MECHANISMS = ("groove alone", "damper alone", "optimum mix")
"""The three ways of reaching V_req compared in the trade-off figure."""


@dataclass
class TradeoffRow:
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
    effort: dict = field(default_factory=dict)
    designs: dict = field(default_factory=dict)


def _restricted(problem: Problem, diameter: float, mechanism: str) -> Problem:
    bounds = dict(problem.bounds)
    bounds["diameter"] = Bound(diameter, diameter)
    if mechanism == "groove alone":
        low = problem.bounds["damping"].low
        bounds["damping"] = Bound(low, low)
    elif mechanism == "damper alone":
        low = problem.bounds["groove"].low
        bounds["groove"] = Bound(low, low)
    return problem.replace(bounds=bounds)


def diameters_for(problem: Problem, count: int = 25) -> list[tuple[Problem, float, str | None]]:
    """(sub-problem, diameter [m], wheel) triples to compare: catalog wheels, the fixed d, or a grid over the bounds."""
    if problem.wheels:
        return [(v, v.bounds["diameter"].low, v.conditions.inertia.wheel.key) for v in problem.variants()]
    b = problem.bounds["diameter"]
    if b.fixed:
        return [(problem, b.low, None)]
    return [(problem, float(d), None) for d in np.linspace(b.low, b.high, count)]


def groove_damper_tradeoff(problem: Problem, count: int = 25, samples: int = 128) -> list[TradeoffRow]:
    """Least F_turn reaching V_req by groove alone, damper alone and both, at several diameters.

    Parameters
    ----------
    problem : the design problem (its load, surface, sill, target and bounds)
    count : number of diameters across the diameter bounds (ignored for a
        fixed diameter or a catalog of wheels)
    samples : Sobol sample size for the NLP's starting points

    Returns
    -------
    list of TradeoffRow, by increasing diameter
    """
    from designer.analysis.optimise import optimise

    rows = []
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="inertia power law used at")
        for sub, d, wheel in diameters_for(problem, count):
            row = TradeoffRow(d, wheel)
            for mechanism in MECHANISMS:
                try:
                    sol = optimise(_restricted(sub, d, mechanism), weights=(1.0, 0.0), cross_check=False,
                                   samples=samples)
                except DesignerError:
                    row.effort[mechanism], row.designs[mechanism] = None, None
                    continue
                f = float(sol.objectives["turning_effort"])
                row.effort[mechanism] = f if np.isfinite(f) else None
                row.designs[mechanism] = sol.design
            rows.append(row)
    rows.sort(key=lambda r: (r.diameter, r.wheel or ""))
    return rows
