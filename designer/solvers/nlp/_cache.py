"""One compiled NLP per problem structure, shared by the fronts, the weighted optimum and check 8c.

Building a :class:`~designer.solvers.nlp.CasterNLP` (CasADi graph, IPOPT interface, the batched solvers of
:meth:`~designer.solvers.nlp.CasterNLP.solve_many`) costs far more CPU than most of its solves.  Problems
that differ only in parameter values (target speed, caster load) can use one build:
:meth:`~designer.solvers.nlp.CasterNLP.for_problem` gives each its own view.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from designer.problem import Problem
from designer.solvers.nlp._casadi import CasterNLP

SHARED_SIZE = 32
"""How many compiled NLP structures :func:`shared_nlp` keeps (the least recently used are dropped)."""

SHARED: dict[str, CasterNLP] = {}
"""The compiled NLPs of :func:`shared_nlp`, by :func:`structure_key` (least recently used first)."""


def structure_key(problem: Problem) -> str:
    """What fixes a compiled :class:`CasterNLP`: every field of the problem but its target speed, caster load and
    names (those are parameter values, or not used by the NLP)."""
    fields = {
        f.name: getattr(problem, f.name)
        for f in dataclasses.fields(problem)
        if f.name not in ("target_speed", "name", "title", "description", "source", "conditions")
    }
    c = problem.conditions
    return repr((fields, {f.name: getattr(c, f.name) for f in dataclasses.fields(c) if f.name != "load"}))


def shared_nlp(
    problem: Problem, *, same_scaling: bool = False, build: Callable[[Problem], CasterNLP] | None = None
) -> CasterNLP:
    """The NLP of ``problem`` from one compiled build per structure (:func:`structure_key`; the last
    :data:`SHARED_SIZE` kept in :data:`SHARED`).

    The first problem of a structure is built (``build(problem)``, default :class:`CasterNLP`); later ones get
    :meth:`CasterNLP.for_problem` views of that build, with their own parameter values (the build itself is
    never changed).  The objective and ε-constraint scales stay those of the first problem (any O(1) scaling
    gives the same optimum to IPOPT's tolerance).  ``same_scaling=True`` returns a view only when its scales
    (:meth:`CasterNLP.references`) are the ones a build of ``problem`` would have, so every solve is the
    one of a fresh build to the bit, and otherwise a fresh build (not kept).
    """
    build = CasterNLP if build is None else build
    key = structure_key(problem)
    base = SHARED.pop(key, None)
    if base is None:
        base = nlp = build(problem)
    else:
        nlp = base.for_problem(problem)
        if same_scaling and nlp.references() != (base.f_ref, base.p_ref):
            nlp = build(problem)
    SHARED[key] = base
    while len(SHARED) > SHARED_SIZE:
        SHARED.pop(next(iter(SHARED)))
    return nlp


__all__ = ["SHARED", "SHARED_SIZE", "shared_nlp", "structure_key"]
