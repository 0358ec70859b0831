"""Shimmy beyond onset: knocks, periodic orbits, Floquet multipliers, knock-safe speed.

Two caster models, both with exact Coulomb spindle friction M_f sgn θ'
(stick–slip handled by events, as ``designer.studies.dynamics._simulate``):

``rolling`` (``tyre=None``): the paper's Appendix B model, the tyre rolls
without lateral slip (Eq. 6B).  State (X, θ, θ'):

    X'  = −T θ' − V θ
    θ'' = [T K X − (N T V + K_s B²/(2V)) θ' − M_f sgn θ'] / (I_w + N T²)

``tyre`` (a :class:`~designer.physics.tyre.TyreParameters`): the contact may
slip; the floor force F(σ) is the brush model of ``designer.physics.tyre``
(saturating at μ L).  Wheel mass M_W at the contact point, fork + bearing
block N at the spindle (Eq. 9B–11B, 14B).  State (X, X', θ, θ'):

    (N + M_W) X'' + M_W T θ''          = F − K X
    M_W T X'' + (I_w + M_W T²) θ''     = T F − M_f sgn θ' − K_s B² θ'/(2V)
    F = F_brush(σ),  σ = (X' + T θ' + V θ)/V

Eliminating F between the two lines gives I_w θ'' = T K X + N T X'' − M_f sgn θ'
− K_s B² θ'/(2V), and with Eq. 7B (X'' = −T θ'' − V θ') this is the rolling model:
with the saturation removed and C → ∞ the tyre model reduces to the paper's.

Stick (θ' = 0): the moment the spindle must hold is T K X (rolling) or
T (N F + M_W K X)/(N + M_W) (tyre); the caster sticks while it is at most M_f.

Docs: docs/limit-cycles.md.  Modules: :mod:`~designer.studies.dynamics.limit_cycles._system` (equations,
integration, knocks), :mod:`~designer.studies.dynamics.limit_cycles._knock` (onset, knock-safe speed),
:mod:`~designer.studies.dynamics.limit_cycles._results` (the room's records: knocks, orbits, studies),
:mod:`~designer.studies.dynamics.limit_cycles._orbits` (periodic orbits), :mod:`~designer.studies.dynamics.limit_cycles._studies`
(bifurcation diagram, Table 1, (K, N) map).

Periodic orbits are found by shooting on the Poincaré section θ' = 0 at a
maximum of θ (end of a positive slip).  Both models are odd-symmetric
(y → −y), so a symmetric orbit is a fixed point of the half-period map
G = −H (H: from a maximum to the next minimum); the amplitude A = θ_max is the
continuation parameter and the speed V an unknown, which follows the branch
round its fold.  Floquet multipliers (full period) are the squared eigenvalues
of DG (finite differences); the orbit is confirmed by integrating one full
period from it (closure) and by perturbed simulations.
"""

from __future__ import annotations

from designer.studies.dynamics.limit_cycles._results import (
    BifurcationDiagram,
    Branch,
    ErrorStats,
    FrictionPoint,
    KnockResult,
    KnockSafe,
    LimitCycleStudy,
    MapCell,
    OnsetBracket,
    OnsetScan,
    PeriodicOrbit,
    RollingLimitCheck,
    StiffnessMassMap,
    Table1Comparison,
    Table1Row,
)
from designer.studies.dynamics.limit_cycles._system import caster_dynamics, simulate_knock
from designer.studies.dynamics.limit_cycles._knock import (
    knock_onset_speed,
    knock_safe_speed,
    knock_safe_speeds,
)
from designer.studies.dynamics.limit_cycles._orbits import continue_orbits, periodic_orbit
from designer.studies.dynamics.limit_cycles._studies import (
    appendix_c_caster,
    bifurcation_diagram,
    limit_cycle_study,
    stiffness_mass_map,
)

__all__ = [
    "KnockResult",
    "OnsetBracket",
    "PeriodicOrbit",
    "Branch",
    "BifurcationDiagram",
    "ErrorStats",
    "FrictionPoint",
    "KnockSafe",
    "LimitCycleStudy",
    "MapCell",
    "OnsetScan",
    "RollingLimitCheck",
    "StiffnessMassMap",
    "Table1Comparison",
    "Table1Row",
    "caster_dynamics",
    "simulate_knock",
    "knock_onset_speed",
    "knock_safe_speed",
    "knock_safe_speeds",
    "periodic_orbit",
    "continue_orbits",
    "bifurcation_diagram",
    "stiffness_mass_map",
    "appendix_c_caster",
    "limit_cycle_study",
]
