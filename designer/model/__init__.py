"""The caster model: one design, its operating conditions, and everything computed from them.

:func:`evaluate` is the one door to the model for numbers: one caster or a batch in, :class:`Casters`
(one :class:`Caster`) out, with the limits, J and the risk on request.  :func:`performance` is the one place
where the physics functions are combined for a design, on floats, arrays or CasADi symbols: :func:`evaluate`
calls it, and the solvers build it into their programs, so a formula is never written twice.

Modules
-------
_caster      :class:`Design`, :class:`Conditions`, :func:`performance`, the design families
_candidates  :func:`evaluate`, :class:`Casters`, :class:`Caster`: the one evaluator (performance, constraint
             values and feasibility with one tolerance, J, the risk by Monte Carlo or the exact law)
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
    performance,
    turning_effort,
    weighted,
    weighted_terms,
)
from designer.model._candidates import (
    FEASIBILITY_TOLERANCE,
    Caster,
    Casters,
    OfCaster,
    critical_speed,
    design_columns,
    evaluate,
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
    "Caster",
    "Casters",
    "OfCaster",
    "critical_speed",
    "design_columns",
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
    "turning_effort",
    "weighted",
    "weighted_terms",
]
