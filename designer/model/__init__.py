"""The caster model: one design, its operating conditions, and everything computed from them.

:func:`performance` is the one place where the physics functions are combined for a design; the solvers
(CasADi, cvxpy, scipy, optuna), the studies and the reports all call the model, so a formula is never
written twice.

Modules
-------
_caster  :class:`Design`, :class:`Conditions`, :func:`performance`, :func:`evaluate`, the design families
"""

from __future__ import annotations

from designer.model._caster import (
    FAMILIES,
    MODEL_RANGE,
    VARIABLE_UNITS,
    VARIABLES,
    Conditions,
    Design,
    check_design,
    evaluate,
    performance,
)

__all__ = [
    "FAMILIES",
    "MODEL_RANGE",
    "VARIABLES",
    "VARIABLE_UNITS",
    "Conditions",
    "Design",
    "check_design",
    "evaluate",
    "performance",
]
