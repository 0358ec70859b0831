"""Which solver runs where: the one dispatcher of the package.

Every solver implements the protocol of :mod:`designer.solvers.base`.  This module names them
(:data:`SOLVERS`), gives one by name (:func:`solver`, loading only that solver's library), and decides for the
studies:

- the weighted optimum (:func:`designer.studies.optimum.optimise`): the :data:`PRIMARY` solver, the NLP, with
  the :data:`CROSS_CHECKS` beside it (the GP's designs are also starts of the NLP);
- a front's ε-points (:func:`designer.studies.front.pareto_front`): :func:`front_solver`, the NLP whose sweep
  starts from the closed form where that applies (a free diameter and
  :func:`~designer.solvers.closed_form.applicable`), else from the sample of the box.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from designer.errors import InputError
from designer.problem import Problem
from designer.solvers.base import Solver
from designer.solvers.closed_form import applicable

if TYPE_CHECKING:  # the NLP's class for the checker only: designer.solvers.nlp loads casadi
    from designer.solvers.nlp import NLPSolver

SOLVERS = ("closed-form", "casadi-ipopt", "cvxpy-gp", "scipy-slsqp")
"""Every solver of the protocol, by the name results use (``Optimum.solver``, ``Solution.cross_check``)."""

PRIMARY = "casadi-ipopt"
"""The solver whose optimum is reported: the exact NLP."""

CROSS_CHECKS = ("scipy-slsqp", "cvxpy-gp")
"""The solvers an optimum is cross-checked with (``optimise(cross_check=True)``), in the order reported."""

_HOMES = {
    "closed-form": ("designer.solvers.closed_form", "CLOSED_FORM"),
    "casadi-ipopt": ("designer.solvers.nlp", "NLP"),
    "cvxpy-gp": ("designer.solvers.gp", "GP"),
    "scipy-slsqp": ("designer.solvers.slsqp", "SLSQP"),
}
"""Each solver's module and default instance (imported only when that solver is asked for)."""

FRONT_STRATEGIES = ("auto", "nlp")
"""``pareto_front(strategy=...)``: "auto" (the NLP confirming the closed form where it applies) or "nlp"."""


def solver(name: str, **options: Any) -> Solver:
    """The solver called ``name`` (one of :data:`SOLVERS`); its library (casadi, cvxpy, scipy) loads now.

    With ``options`` a new instance of that solver with them (``samples`` for the NLP's sample of starts,
    ``random_starts`` and ``seed`` for SLSQP), else the shared default one.
    """
    if name not in _HOMES:
        raise InputError(f"solver = {name!r}: expected one of {', '.join(SOLVERS)}")
    module, instance = _HOMES[name]
    found: Solver = getattr(importlib.import_module(module), instance)
    return type(found)(**options) if options else found


def front_solver(problem: Problem, requested: str = "auto") -> NLPSolver:
    """The solver of one continuous problem's front: the NLP, sweeping from the closed form where it applies.

    ``requested="auto"``: from the closed form when the diameter is free (a catalog wheel fixes it: one
    point per wheel) and :func:`~designer.solvers.closed_form.applicable` holds, else from the sample;
    ``"nlp"``: from the sample everywhere (the cross-check of the tests).
    """
    if requested not in FRONT_STRATEGIES:
        raise InputError(f"strategy = {requested!r}: expected one of {', '.join(FRONT_STRATEGIES)}")
    from designer.solvers.nlp import NLPSolver

    structured = requested == "auto" and not problem.bounds["diameter"].fixed and applicable(problem)
    return NLPSolver(structured=structured)


__all__ = ["CROSS_CHECKS", "FRONT_STRATEGIES", "PRIMARY", "SOLVERS", "front_solver", "solver"]
