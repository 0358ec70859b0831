"""The caster model: one design, its operating conditions, and everything computed from them.

:func:`performance` is the one place where the physics functions are combined for a design; the solvers
(CasADi, cvxpy, scipy, optuna), the studies and the reports all call the model, so a formula is never
written twice.

Modules
-------
_caster      :class:`Design`, :class:`Conditions`, :func:`performance`, :func:`evaluate`, the design families
_candidates  :func:`evaluate_candidates`: the one evaluator of a batch of candidates (performance, risk bound,
             feasibility with one tolerance, the Monte Carlo risk)
"""

from __future__ import annotations

from designer.model._caster import (
    CONDITION_CHOICES,
    CONDITION_NUMBERS,
    condition_refusal,
    FAMILIES,
    GRAVITY,
    MASS_RANGE,
    MODEL_RANGE,
    VARIABLE_UNITS,
    VARIABLES,
    Conditions,
    Design,
    caster_load,
    check_design,
    evaluate,
    performance,
)
from designer.model._candidates import (
    FEASIBILITY_TOLERANCE,
    CandidateValues,
    design_columns,
    evaluate_candidates,
    scatter_of,
    shimmy_probability,
)

__all__ = [
    "CONDITION_CHOICES",
    "CONDITION_NUMBERS",
    "condition_refusal",
    "FAMILIES",
    "GRAVITY",
    "MASS_RANGE",
    "caster_load",
    "FEASIBILITY_TOLERANCE",
    "CandidateValues",
    "design_columns",
    "evaluate_candidates",
    "scatter_of",
    "shimmy_probability",
    "MODEL_RANGE",
    "VARIABLES",
    "VARIABLE_UNITS",
    "Conditions",
    "Design",
    "check_design",
    "evaluate",
    "performance",
]
