"""The exact NLP of a caster problem (CasADi/IPOPT): built once per problem structure, solved many times.

Importing this package loads casadi.

Modules
-------
_casadi  :class:`CasterNLP` (the NLP with every constant, the weights and the ε caps as parameters; single and
         batched solves, multipliers, sensitivities) and the multi-start helpers (Sobol sample, best starts)
_cache   :func:`shared_nlp`: one compiled NLP per problem structure, shared by fronts, optimum and check 8c
_sweep   the ε-sweeps of a front: from the sample with family restarts, or from the closed form, confirmed
_solver  :class:`NLPSolver`, the NLP as a solver of the protocol (:mod:`designer.solvers.base`)
"""

from __future__ import annotations

from designer.solvers.nlp._cache import SHARED, shared_nlp, structure_key
from designer.solvers.nlp._casadi import (
    BIG,
    PARAMETER_INFO,
    QUIET,
    SOBOL_FILE,
    CasterNLP,
    NLPResult,
    best_starts,
    max_critical_speed,
    sample_designs,
    solve_best,
)
from designer.solvers.nlp._solver import NLP, NLPSolver
from designer.solvers.nlp._sweep import Ends, box_sample, lexicographic_ends

__all__ = [
    "BIG",
    "NLP",
    "PARAMETER_INFO",
    "QUIET",
    "SHARED",
    "SOBOL_FILE",
    "CasterNLP",
    "Ends",
    "NLPResult",
    "NLPSolver",
    "best_starts",
    "box_sample",
    "lexicographic_ends",
    "max_critical_speed",
    "sample_designs",
    "shared_nlp",
    "solve_best",
    "structure_key",
]
