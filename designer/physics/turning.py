"""Turning effort of a caster: sliding moment of the tyre plus spindle friction.

Default model of docs/model.md#turning-effort, calibrated to the paper's measurements
("Turning resistance due to a grooved wheelchair caster wheel", Figs. 7–12):

M_turn = m_mode · k_surface · L · (1 + κ B)      sliding turning moment [N·m]
M_d    = (c_f − c_0) θ0                          added spindle friction [N·m]
F_turn = (M_turn + M_d) / T                      lateral force at the spindle [N]

The last line is the paper's relation "turning moment = F_c × trail" (Eq. 9
and the text after it): doubling the trail halves the effort.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from designer.data.paper import DISTURBANCE_ANGLE
from designer.errors import InputError
from designer.reprs import frozen
from designer.parameters import MODES as MODES, SURFACES as SURFACES, default  # the choices, the defaults: one table
from designer.physics.types import Scalar


@dataclass(frozen=True)
class TurningConstants:
    """The constants of the turning model; calibrate them from your own rig.

    Attributes
    ----------
    tile_moment_per_load : k_tile [m], sliding turning moment per newton of
        caster load on vinyl tile (drill-press test, Fig. 7A).  0.005 m equals
        a friction coefficient of about 0.7 over a 20 × 24 mm contact patch.
    carpet_factor : k_carpet / k_tile [-]; "approximately double" (Fig. 7).
    groove_coefficient : κ [1/m]; a ½ in groove tyre (B = 9/16 in in Eq. 8)
        needs 10 % more moment than the same tyre ungrooved: κ = 0.10/(9/16 in).
    mode_factors : m_mode [-]; ``pivot`` = 1.0 (non-rolling wheel, drill
        press); ``chair`` = 0.5 (turning a wheelchair in place is "about 50
        percent" of the drill-press moment, Figs. 10–12).
    bare_fork_damping : c_0 [N·m/rad], the bare ball-bearing fork of Eq. 11C,
        whose bearing friction the paper found negligible in turning.
    """

    tile_moment_per_load: float = default("tile_moment_per_load")
    carpet_factor: float = default("carpet_factor")
    groove_coefficient: float = default("groove_coefficient")
    mode_factors: Mapping[str, float] = field(
        default_factory=lambda: {"chair": default("chair_factor"), "pivot": default("pivot_factor")}
    )
    bare_fork_damping: float = default("bare_fork_damping")

    def __post_init__(self) -> None:
        object.__setattr__(self, "mode_factors", frozen(self.mode_factors))  # read-only, as the record

    def surface_factor(self, surface: str) -> float:
        """k_surface / k_tile for ``surface`` (tile 1, carpet ``carpet_factor``)."""
        if surface == "tile":
            return 1.0
        if surface == "carpet":
            return self.carpet_factor
        raise InputError(f"surface = {surface!r}: expected one of {', '.join(SURFACES)}")

    def mode_factor(self, mode: str) -> float:
        """m_mode for turning ``mode`` (chair | pivot)."""
        try:
            return self.mode_factors[mode]
        except KeyError:
            raise InputError(f"turning_mode = {mode!r}: expected one of {', '.join(MODES)}") from None


DEFAULT_TURNING = TurningConstants()


def sliding_turning_moment(
    load: Scalar,
    groove: Scalar,
    surface: str = "tile",
    mode: str = "chair",
    constants: TurningConstants = DEFAULT_TURNING,
) -> Scalar:
    """Sliding turning moment of the tyre about the spindle [N·m] (docs/model.md#turning-effort; Fig. 7).

    M_turn = m_mode · k_surface · L · (1 + κ B).

    Parameters
    ----------
    load : caster load L [N]
    groove : groove width B [m]
    surface : "tile" or "carpet" (carpet ≈ 2 × tile, Fig. 7)
    mode : "chair" (0.5) or "pivot" (1.0)
    """
    k_surface = constants.tile_moment_per_load * constants.surface_factor(surface)
    return constants.mode_factor(mode) * k_surface * load * (1 + constants.groove_coefficient * groove)


def added_damper_moment(
    damping: Scalar, disturbance_angle: Scalar = DISTURBANCE_ANGLE, constants: TurningConstants = DEFAULT_TURNING
) -> Scalar:
    """Spindle friction moment added by a damper, M_d = (c_f − c_0) θ0 [N·m].

    The paper: "increasing caster-spindle frictional damping also inhibits
    caster shimmy, but at the expense of increased caster turning effort".
    M_f = c_f θ0 is the friction moment of Eq. 7; the bare fork's share c_0 θ0
    is negligible in turning (paper, Fig. 11 discussion).
    """
    return (damping - constants.bare_fork_damping) * disturbance_angle


def turning_effort(
    trail: Scalar,
    groove: Scalar,
    damping: Scalar,
    load: Scalar,
    surface: str = "tile",
    mode: str = "chair",
    disturbance_angle: Scalar = DISTURBANCE_ANGLE,
    constants: TurningConstants = DEFAULT_TURNING,
) -> Scalar:
    """Lateral force at the spindle to turn the caster, F_turn [N] (Eq. 9; docs/model.md#turning-effort).

    F_turn = (M_turn + M_d) / T.  Worked case (tile, chair, L = 178 N, T = 2 in,
    c_f = 1.3): B = 0 gives 8.76 N, B = 9/16 in gives 9.64 N.

    Parameters
    ----------
    trail : trail T [m]
    groove : groove width B [m]
    damping : spindle friction damping c_f [N·m/rad]
    load : caster load L [N]
    """
    moment = sliding_turning_moment(load, groove, surface, mode, constants) + added_damper_moment(
        damping, disturbance_angle, constants
    )
    return moment / trail
