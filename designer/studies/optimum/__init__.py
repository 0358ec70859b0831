"""The scalarised optimum J = w_turn F_turn + w_threshold P under the shimmy constraint (Eq. 7).

Modules
-------
_optimise  :func:`optimise` (multi-start NLP, GP and SLSQP cross-checks) and its :class:`Solution`
"""

from __future__ import annotations

from designer.studies.optimum._optimise import (
    ConstraintMargins,
    Solution,
    constraint_margins,
    diagnose_infeasible,
    margins_many,
    optimise,
)

__all__ = ["ConstraintMargins", "Solution", "constraint_margins", "diagnose_infeasible", "margins_many", "optimise"]
