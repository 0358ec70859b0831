"""The records of the limit-cycle study's knocks: :class:`KnockResult` (what one knock does) and
:class:`OnsetBracket` (the speed bracket of a knock's onset).  Built by
:mod:`~designer.studies.dynamics.limit_cycles._system` and :mod:`~designer.studies.dynamics.limit_cycles._knock`;
the periodic orbits' records are in :mod:`~designer.studies.dynamics.limit_cycles._orbits`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from designer.reprs import Record


@dataclass(frozen=True, kw_only=True)
class KnockResult(Record):
    """What a knock does: the trace, the amplitudes and the verdict.

    Attributes
    ----------
    t, theta : time [s] and caster angle θ [rad] (empty unless ``record``)
    extrema : (t [s], θ [rad]) at the reversals
    early_amplitude : mean half peak-to-peak over two periods after the aligning transient [rad]
    late_amplitude : the same over the last two periods (0 if the motion stopped) [rad]
    shimmy : True if the knock ends in sustained shimmy: |θ| reached the limit, or the caster still
        reverses at least 3 times in the last two periods with late ≥ 0.5 early (a decaying
        Coulomb-damped motion stops in finite time; a slow creep of a sliding tyre is not shimmy)
    reason : "end", "limit" (|θ| reached ``angle_limit``) or "rest" (the caster stopped)
    """

    t: np.ndarray
    theta: np.ndarray
    extrema: np.ndarray
    early_amplitude: float
    late_amplitude: float
    shimmy: bool
    reason: str
    speed: float = 0.0
    angle: float = 0.0

    _units = {**dict.fromkeys(("theta", "early_amplitude", "late_amplitude", "angle"), "rad"), "t": "s", "speed": "m/s"}


@dataclass(frozen=True, kw_only=True)
class OnsetBracket(Record):
    """Knock onset by bisection: the knock decays at ``low`` and is sustained at ``high`` [m/s]."""

    low: float
    high: float
    evaluations: int

    _units = {"low": "m/s", "high": "m/s", "speed": "m/s"}
    _keys = ("low", "high", "speed", "evaluations")
    """The bracket, its geometric mean and the number of knock simulations."""

    @property
    def speed(self) -> float:
        """Geometric mean of the bracket [m/s]."""
        return math.sqrt(self.low * self.high)
