"""Solvers for caster design problems: one protocol, four solvers, one dispatcher.

Every solver answers ``optimum(problem, weights, caps) -> Optimum`` and ``front_designs(problem, eps) -> Designs``
(:mod:`designer.solvers.base`); :mod:`designer.solvers.dispatch` says which runs where.

Modules (each solver imported on its own, so that loading one does not load another's library)
-------
base         the protocol: :class:`Solver`, the records :class:`Optimum`, :class:`Designs`, :class:`Caps`
dispatch     the one dispatcher: :func:`solver` by name, :func:`front_solver` for a front, the primary solver
             and the cross-checks
closed_form  closed-form ε-optima and weighted optimum where the structure allows ("closed-form"; numpy)
nlp          CasADi/IPOPT exact NLP, built once per problem structure, multi-start, the front's ε-sweeps
             ("casadi-ipopt", the primary)
gp           cvxpy geometric programming: global certificate and duals ("cvxpy-gp")
slsqp        SciPy SLSQP on the NumPy model from the NLP optimum and random starts ("scipy-slsqp")
"""

from __future__ import annotations

from designer.solvers.base import NO_CAPS, SOLVE_LOCK, Caps, Designs, Optimum, Solver, one_solve_at_a_time
from designer.solvers.dispatch import CROSS_CHECKS, FRONT_STRATEGIES, PRIMARY, SOLVERS, front_solver, solver

__all__ = [
    "SOLVE_LOCK",
    "one_solve_at_a_time",
    "CROSS_CHECKS",
    "FRONT_STRATEGIES",
    "NO_CAPS",
    "PRIMARY",
    "SOLVERS",
    "Caps",
    "Designs",
    "Optimum",
    "Solver",
    "front_solver",
    "solver",
]
