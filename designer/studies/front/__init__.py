"""Exact Pareto fronts of turning effort F_turn against threshold force P (Eq. 7 constraint, Eq. 4A, Eq. 9).

Modules
-------
_front       :class:`Front` and :class:`FrontPoint`: the front as data (indicators, knee, pandas, plots)
_pareto      :func:`pareto_front`: the ε-constraint sweep of a problem (its ε-points: :func:`designer.solvers.front_solver`)
_indicators  hypervolume and IGD+ (reference point and normalisation stated)
_tradeoff    the groove-damper trade-off table, in closed form
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from designer.studies.front._front import Front, FrontPoint, family_of
from designer.studies.front._indicators import hypervolume_2d, igd_plus, nondominated, normalise
from designer.studies.front._tradeoff import TradeoffRow, groove_damper_tradeoff

if TYPE_CHECKING:  # for the checker and the API docs; at run time served by __getattr__ below
    from designer.studies.front._pareto import pareto_front


def __getattr__(name: str) -> Any:
    """:func:`pareto_front` on first use: its solvers load CasADi, which a front's record, its indicators and
    explore's trials do not need."""
    if name == "pareto_front":
        from designer.studies.front._pareto import pareto_front

        return pareto_front
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "Front",
    "FrontPoint",
    "TradeoffRow",
    "family_of",
    "groove_damper_tradeoff",
    "hypervolume_2d",
    "igd_plus",
    "nondominated",
    "normalise",
    "pareto_front",
]
