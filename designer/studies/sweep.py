"""V_c against one part of a caster, the others held: the sweeps of a caster's card (``designer studio``).

The numbers come from the model's evaluator (:func:`designer.model.evaluate`) under the problem's own
conditions, its inertia model and its risk law; nothing here re-states an equation.
"""

from __future__ import annotations

import numpy as np

from designer.model import VARIABLES, Design, evaluate

SWEEP_POINTS = 61
"""Points of each sweep."""

SILL_CLEARANCE = 2.05
"""The smallest diameter of the diameter sweep, in sill heights: a wheel of d <= 2h cannot climb the sill
(Eq. 4A), so the sweep starts just above it."""


def speed_sweeps(problem, design: Design, inertia: float | None = None, measured: bool = False, points=SWEEP_POINTS):
    """V_c (Eq. 7) and the speed reached with probability 1 − α (the problem's risk law; V_c without one)
    against trail and against diameter around ``design`` for ``problem``, the other parts held.

    Each sweep spans the problem's bounds of its variable (±50 % of the design's value where the bounds are
    fixed), and always the design's own value.  The trail sweep keeps the caster's own wheel: ``inertia``
    [kg·m²] with its ``measured`` flag (None: the problem's inertia model at d); the diameter sweep changes
    the wheel, so each diameter takes the problem's inertia model at that diameter (a flat line there would
    say the wheel's inertia does not change with its size).

    Returns ``{"trail": sweep, "diameter": sweep}``, each ``{"x" [m], "critical_speed", "confident_speed"
    [m/s], "value" (the design's own) [m]}`` of arrays (SI).
    """
    conditions = problem.conditions
    out = {}
    for name in ("trail", "diameter"):
        b = problem.bounds[name]
        value = getattr(design, name)
        lo, hi = (b.low, b.high) if b.high > b.low else (0.5 * value, 1.5 * value)
        lo, hi = min(lo, value), max(hi, value)
        if name == "diameter":
            lo = min(max(lo, SILL_CLEARANCE * conditions.threshold_height), value)
        x = np.linspace(lo, hi, int(points))
        columns = {k: np.full(x.shape, getattr(design, k)) for k in VARIABLES}
        columns[name] = x
        own = name == "trail" and inertia is not None
        values = evaluate(
            columns,
            conditions,
            inertia=np.full(x.shape, float(inertia)) if own else None,
            measured=np.full(x.shape, bool(measured)) if own else None,
        )
        speeds = {k: np.asarray(values[k], float) for k in ("critical_speed", "confident_speed")}
        out[name] = {"x": x, **speeds, "value": value}
    return out


__all__ = ["SWEEP_POINTS", "speed_sweeps"]
