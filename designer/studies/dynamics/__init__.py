"""Shimmy in time: simulation of the third-order model with Coulomb friction, onset speeds, limit cycles.

Modules
-------
_simulate     :func:`simulate` and :func:`onset_speed` (Eq. 12B with exact Coulomb friction)
_result       :class:`SimulationResult`, :class:`OnsetResult`, :class:`OnsetStudy`
_onset_study  the committed onset study (``designer simulate --report``)
_work         the work budget of a study (:func:`work_limit`) and the model's speeds
limit_cycles  knocks, periodic orbits, Floquet multipliers, knock-safe speeds (a subpackage)
"""

from __future__ import annotations

from designer.studies.dynamics._onset_study import write_simulation_report
from designer.studies.dynamics._result import OnsetResult, OnsetStudy, SimulationResult
from designer.studies.dynamics._simulate import onset_speed, simulate
from designer.studies.dynamics._work import MAX_EVALUATIONS, SPEED_RANGE, WorkLimitError, scaled_budget, work_limit

__all__ = [
    "MAX_EVALUATIONS",
    "OnsetResult",
    "OnsetStudy",
    "SPEED_RANGE",
    "SimulationResult",
    "WorkLimitError",
    "onset_speed",
    "scaled_budget",
    "simulate",
    "work_limit",
    "write_simulation_report",
]
