"""The spec a factory can inspect against: each part's acceptance limit, the risk at the worst corner of the
tolerance box, and P(shimmy) as an exact number (docs/problem-file.md#tolerances).

For one caster of a problem (the recommendation, an alternative, a fleet part number, a retrofit fix):

- :func:`caster_specs` builds the :class:`Spec` of each caster: the nominal parts, the acceptance limit of each inspectable
  part with the others at nominal (:func:`designer.physics.acceptance.acceptance_limits`: trail min and max,
  groove min, bearing friction moment M_f = c_f θ0 min, measured wheel inertia max), how to measure each,
  P(shimmy) from the exact law with the Monte Carlo beside it, and, with ``[tolerances]``, the worst corner
  (a retrofit's fixes, a fleet's part numbers, a recommendation and its alternatives: their limits searched in
  one batch);
- :func:`corner_probabilities` gives the worst-corner P of many casters (``enforce = true`` screens with it).

Limits and corners are at the bound's speed V_req = (1 + margin) V_target and the problem's risk law (the
default scatter when the bound is off); the reported P(shimmy) is at V_target, like the Monte Carlo's.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from designer.parameters import PARAMETERS
from designer.physics.acceptance import (
    Corner,
    Edge,
    LawCaster,
    PartLimit,
    acceptance_limits_many,
    exact_probability,
    friction_moment,
    worst_corner,
)
from designer.model import Design, scatter_of
from designer.physics.geometry import effective_trail
from designer.physics.uncertainty import Uncertainty
from designer.studies.acceptance import UNITS, JointLimits, joint_limits_many
from designer.problem import Problem, Tolerances
from designer.units import limit_shown
from designer.reprs import Key, Record

SPEC_PROBABILITY = {
    "exact": "probability",
    "monte_carlo": "mc_probability",
    "monte_carlo_se": "mc_se",
    "monte_carlo_samples": "mc_samples",
    "monte_carlo_seed": "mc_seed",
    "at_speed": "target_speed",
}
"""The keys of a spec's ``shimmy_probability`` record and the attributes they hold."""

MEASURE = {
    "trail": "floor distance from the stem axis (extended down) to the tyre's contact point, caster loaded and "
    "trailing straight (square and rule)",
    "diameter": "across the tyre at two right angles (calliper or tape), the mean",
    "groove": "width between the tyre's two tread lands at the contact patch (calliper)",
    "friction_moment": "steady moment to swivel the fork slowly about its stem, stem bearing under the caster load, "
    "tyre on a free-turning plate (torque gauge, or spring scale at lever arm r: M_f = F r)",
    "wheel_inertia": "about a diameter, by compound pendulum: wheel hung at its rim, swung about an axis in its "
    "plane; I = m g a τ²/(4π²) − m a² (a: axis to hub, τ: period)",
}
"""How goods-in measures each part (the inspection sheet's last column)."""

CORNER_KEYS = ("edges", "probability", "nominal_probability", "holds")
"""The keys of a spec's worst corner (the :class:`~designer.physics.acceptance.Corner` fields it keeps)."""


PART_LABELS = {
    "trail": "trail T",
    "diameter": "wheel diameter d",
    "groove": "groove B",
    "friction_moment": "bearing friction moment M_f = c_f θ0",
    "wheel_inertia": "measured wheel inertia I_w",
}
"""What the spec calls each part (text, report, sheet), in the sheet's order."""

_PARTS = {"damping": "friction_moment", "inertia": "wheel_inertia"}
"""The physics' part names that the spec states otherwise (c_f as M_f = c_f θ0; I_w as the wheel's inertia)."""


@dataclass(frozen=True, kw_only=True)
class Limit(Record):
    """One part's acceptance limit (SI), with the others at nominal.

    Attributes
    ----------
    part : "trail", "groove", "friction_moment" (M_f = c_f θ0) or "wheel_inertia"
    side : "min" or "max"
    value : the limit [unit], None when there is none inside the part's range (``reason`` says why)
    nominal : the part's nominal value [unit]
    unit : SI unit
    probability : P(V_c,true < V_req) at the limit [-] (α up to the root's tolerance); None for a geometric
        limit or none
    reason : what sets the limit ("risk", "swept radius") or why there is none
    measure : how goods-in measures the part
    """

    part: str
    side: str
    value: float | None
    nominal: float
    unit: str
    probability: float | None
    reason: str
    measure: str

    def shown_in(self, units: str) -> str:
        """The limit for an inspector with lengths in the problem's ``units`` first ("in": "2.209 in (56.11 mm)"),
        rounded toward the safe side (:func:`limit_shown`)."""
        return limit_shown(self.value, self.unit, self.side, units)

    @property
    def key(self) -> str:
        """The part and the side: "trail_min", "wheel_inertia_max" (the JSON key)."""
        return f"{self.part}_{self.side}"

    @property
    def protects(self) -> str | None:
        """What the limit protects: "risk" (P = α), "footrest" (T + d/2 <= R_max, d at its tolerance's upper edge),
        None when there is no limit."""
        if self.value is None:
            return None
        return "footrest" if self.reason == "swept radius" else "risk"

    @property
    def no_window(self) -> bool:
        """The limit leaves no window on its side of nominal (a max at or below nominal, a min at or above)."""
        if self.value is None:
            return False
        gap = self.value - self.nominal if self.side == "max" else self.nominal - self.value
        return gap <= 1e-12 * max(abs(self.nominal), 1e-12)


@dataclass(frozen=True, kw_only=True)
class Spec(Record):
    """The spec of one caster (SI): nominal parts, acceptance limits, exact risk, worst corner.

    Attributes
    ----------
    trail, diameter, groove : T, d, B [m]
    damping : c_f [N·m/rad]
    friction_moment : M_f = c_f θ0 [N·m]
    disturbance_angle : θ0 [rad] (Eq. 7's; M_f is stated so goods-in needs no θ0)
    inertia : I_w [kg·m²] the risk law uses (the power law's at d for a wheel known by its diameter)
    measured : the wheel's I_w was measured (else known by its diameter: Table 1's prediction scatter)
    limits : :class:`Limit` records, trail min and max, groove min, friction_moment min, wheel_inertia max
    probability : P(shimmy at V_target) by the exact law (quadrature) [-]
    mc_probability, mc_se : the Monte Carlo's P and standard error [-] (an independent check)
    mc_samples, mc_seed : its draws and seed
    target_speed, required_speed : V_target and the bound's V_req [m/s]
    alpha : α [-]
    tolerances : the problem's ``[tolerances]`` (None: none given)
    stem_angle : φ [rad] of a tilted stem (a retrofit's ``--stem-angle``): the trail is then the fork offset e
        and the risk law sees e + (d/2) sin φ; 0 for an upright stem
    calibration : k = V_obs / V_c,Eq.7 of a retrofit calibrated by an observed onset (1: none); the limits and
        P are then the calibrated law's
    corner : the worst corner (None without tolerances): {"edges" {part: value [SI]}, "probability",
        "nominal_probability", "holds"}
    """

    trail: float
    diameter: float
    groove: float
    damping: float
    friction_moment: float
    disturbance_angle: float
    inertia: float
    measured: bool
    limits: list[Limit]
    probability: float
    mc_probability: float
    mc_se: float
    mc_samples: int
    mc_seed: int
    target_speed: float
    required_speed: float
    alpha: float
    tolerances: Tolerances | None = None
    corner: dict[str, Any] | None = None
    stem_angle: float = 0.0
    calibration: float = 1.0
    joint: JointLimits | None = None

    _keys = (
        *(Key(f"nominal.{n}", n) for n in ("trail", "diameter", "groove", "friction_moment")),
        Key("nominal.wheel_inertia", "inertia"),
        Key("limits", lambda s: {lim.key: lim.value for lim in s.limits}),
        Key("units", lambda s: {lim.key: lim.unit for lim in s.limits} | {"nominal": "SI (m, N·m, kg·m²)"}),
        Key("no_limit", lambda s: {lim.key: lim.reason for lim in s.limits if lim.value is None}),
        Key(
            "limit_probability", lambda s: {lim.key: lim.probability for lim in s.limits if lim.probability is not None}
        ),
        *("disturbance_angle", "damping", "measured"),
        *(Key(f"shimmy_probability.{k}", n) for k, n in SPEC_PROBABILITY.items()),
        *("alpha", "required_speed", "tolerances", Key("worst_corner", "corner")),
        Key("joint", omit="none"),
        Key("**", lambda s: {"stem_angle": s.stem_angle} if s.stem_angle else {}),  # a tilted stem's retrofit
        Key("**", lambda s: {"calibration": s.calibration} if s.calibration != 1.0 else {}),  # a calibrated law
    )
    """The JSON record (SI): nominal parts, ``limits`` by part and side with ``units`` beside them (None: no limit
    inside the range, ``no_limit`` says why), the exact and Monte Carlo P, tolerances and worst corner."""

    def limit(self, part: str, side: str) -> Limit:
        """The :class:`Limit` of ``part`` on ``side`` ("trail", "min")."""
        for lim in self.limits:
            if lim.part == part and lim.side == side:
                return lim
        raise KeyError(f"{part}_{side}: no such limit (have {', '.join(x.key for x in self.limits)})")

    def parts(self) -> list[dict[str, Any]]:
        """One row per part, in :data:`PART_LABELS`' order: {"part", "label", "nominal" [SI], "unit",
        "tolerance" (± [SI], a fraction for the friction moment, the accepted I_w for the wheel, None: none given;
        "catalogue" for a catalogue wheel), "limits" [:class:`Limit`], "measure"}."""
        tol = self.tolerances
        spread: dict[str, Any] = {}
        if tol is not None:
            spread = {part: getattr(tol, part) for part in ("trail", "groove", "diameter", "friction_moment")}
            spread["wheel_inertia"] = "catalogue" if tol.wheel is None else tol.wheel
        nominal = {part: getattr(self, "inertia" if part == "wheel_inertia" else part) for part in PART_LABELS}
        return [
            {
                "part": part,
                "label": label,
                "nominal": nominal[part],
                "unit": UNITS[part],
                "tolerance": spread.get(part),
                "limits": [lim for lim in self.limits if lim.part == part],
                "measure": MEASURE[part],
            }
            for part, label in PART_LABELS.items()
        ]

    def _repr_lines(self) -> list[str]:
        shown = ", ".join(f"{lim.key} {lim.value:.4g} {lim.unit}" for lim in self.limits if lim.value is not None)
        corner = (
            ""
            if self.corner is None
            else f"; worst corner P {self.corner['probability']:.2%} ({'holds' if self.corner['holds'] else 'fails'})"
        )
        return [f"Spec(P(shimmy) {self.probability:.3%} exact{corner})", f"  limits: {shown}"]


def law_caster(problem: Problem, design: Design, inertia: float, measured: bool, offset: float = 0.0) -> LawCaster:
    """The caster as the risk law sees it: a wheel known by its diameter keeps d (Table 1's prediction); the trail
    is the one the tyre sees, T + ``offset`` ((d/2) sin φ of a tilted stem, :func:`stem_offset`)."""
    return LawCaster(
        design.trail + offset,
        inertia,
        design.groove,
        design.damping,
        float(problem.conditions.slip_coefficient),
        None if measured else design.diameter,
    )


def stem_offset(design: Design, stem_angle: float) -> float:
    """What a stem tilted by φ adds to the fork offset e: T_eff − e = (d/2) sin φ [m] (0 upright)."""
    if not stem_angle:
        return 0.0
    return float(effective_trail(design.trail, design.diameter / 2, stem_angle)) - design.trail


def tolerance_corners(problem: Problem, columns: dict[str, Any]) -> list[dict[str, Any]]:
    """The two worst corners of ``problem``'s ``[tolerances]`` about candidate arrays ``columns`` {trail, diameter,
    groove, damping, inertia[, measured]} [SI], as the same columns: trail − ±, groove − ±, M_f − its fraction, the
    diameter at either edge with the inertia model's I_w there (a measured wheel keeps its own), or a measured
    wheel at the accepted I_w.  What the stock screens of a fleet and a retrofit evaluate with the bound's V_q (a
    conservative screen: a caster it keeps holds at its corner by the exact law too)."""
    tol = problem.tolerances
    assert tol is not None
    t_lo = float(PARAMETERS["trail"].range[0])  # type: ignore[index]
    parts = {
        "trail": np.maximum(columns["trail"] - (tol.trail or 0.0), t_lo),
        "groove": np.maximum(columns["groove"] - (tol.groove or 0.0), 0.0),
        "damping": columns["damping"] * (1 - (tol.friction_moment or 0.0)),
    }
    measured = np.broadcast_to(np.asarray(columns.get("measured", True), bool), np.shape(columns["trail"]))
    model = problem.conditions.inertia
    out = []
    for sign in (-1.0, 1.0):
        d = columns["diameter"] + sign * (tol.diameter or 0.0)
        # a wheel's edge just outside Table 1: said for the caster itself
        with warnings.catch_warnings(action="ignore", category=UserWarning):
            inertia = np.where(measured, columns["inertia"], np.asarray(model(d), float))
        flags = measured
        if tol.wheel is not None:
            inertia, flags = np.full(np.shape(d), tol.wheel), np.ones(np.shape(d), bool)
        out.append(parts | {"diameter": d, "inertia": inertia, "measured": flags})
    return out


def risk_law(problem: Problem, law: Uncertainty | None = None) -> Uncertainty:
    """The risk law of the limits: ``law`` when given (a calibrated retrofit's), else the problem's bound, else
    the default scatter."""
    if law is not None:
        return law
    return problem.risk if problem.risk is not None else scatter_of(problem.conditions)


def caster_corner(
    problem: Problem,
    design: Design,
    inertia: float,
    measured: bool,
    *,
    law: Uncertainty | None = None,
    stem_angle: float = 0.0,
    calibration: float = 1.0,
) -> Corner | None:
    """The worst corner of ``problem``'s tolerance box about one caster (None without ``[tolerances]``)."""
    tol = problem.tolerances
    if tol is None:
        return None
    offset = stem_offset(design, stem_angle)
    caster = law_caster(problem, design, inertia, measured, offset)
    # each toleranced part's two edges: its value [SI] and the caster fields it sets (a trail's edge at the fork
    # offset, the caster's trail ``offset`` beyond it)
    out: dict[str, tuple[Edge, Edge]] = {}
    t, b, c, d = design.trail, design.groove, design.damping, design.diameter
    theta0, model = float(problem.conditions.disturbance_angle), problem.conditions.inertia

    def pair(edge: Callable[[float], Edge], low: float, high: float) -> tuple[Edge, Edge]:
        return edge(low), edge(high)

    if tol.trail is not None:
        t_lo = PARAMETERS["trail"].range[0]  # type: ignore[index]
        out["trail"] = pair(lambda x: (x, {"trail": x + offset}), max(t - tol.trail, t_lo), t + tol.trail)
    if tol.groove is not None:
        out["groove"] = pair(lambda x: (x, {"groove": x}), max(b - tol.groove, 0.0), b + tol.groove)
    if tol.friction_moment is not None:
        f = tol.friction_moment
        out["friction_moment"] = pair(lambda x: (friction_moment(x, theta0), {"damping": x}), c * (1 - f), c * (1 + f))
    if tol.diameter is not None:
        if caster.diameter is None:  # a measured wheel: its I_w does not follow its diameter
            out["diameter"] = pair(lambda x: (x, {}), d - tol.diameter, d + tol.diameter)
        else:
            # a 4 in wheel's low edge leaves Table 1 by a hair: the caster's own warning, if any, is said once elsewhere
            with warnings.catch_warnings(action="ignore", category=UserWarning):
                out["diameter"] = pair(
                    lambda x: (x, {"diameter": x, "inertia": float(model(x))}), d - tol.diameter, d + tol.diameter
                )
    if tol.wheel is not None:  # goods-in accepts wheels measured up to this I_w: the worst is at the limit
        edge: Edge = (tol.wheel, {"inertia": tol.wheel, "diameter": None})
        out["wheel_inertia"] = (edge, edge)
    return worst_corner(caster, out, problem.required_speed / calibration, risk_law(problem, law))


def corner_probabilities(
    problem: Problem, designs: list[Design], inertia: list[float], measured: list[bool]
) -> list[float]:
    """P(V_c,true < V_req) at the worst corner of each caster [-] (``[tolerances]`` required)."""
    corners = [caster_corner(problem, design, i_w, flag) for design, i_w, flag in zip(designs, inertia, measured)]
    return [corner.probability for corner in corners if corner is not None]


def mc_draws(p: float, se: float) -> int:
    """The draws behind a Monte Carlo estimate ``p`` with standard error ``se`` (the SE of
    :func:`designer.model.shimmy_probability`: sqrt(max(p(1 − p), 1/n)/n)), recovered from the two."""
    if not se > 0:
        return 0
    spread = p * (1 - p)
    n = spread / se**2
    return int(round(n if n > 0 and spread >= 1 / n else 1 / se))


def exact_shimmy_probability(problem: Problem, design: Design, inertia: float, measured: bool, speed: float) -> float:
    """P(V_c,true < speed) of one caster by the exact law (quadrature) under the problem's risk law [-]."""
    return exact_probability(law_caster(problem, design, inertia, measured), speed, risk_law(problem))


def _reason(code: str, part: str, ranges: dict[str, Any], scale: float, unit: str) -> str:
    """The physics' reason as a sentence with the range's end in the spec's unit."""
    if code == "holds at the low end":
        return f"no lower limit: P <= α down to {ranges[part][0] * scale:.4g} {unit}, the low end of the model's range"
    if code == "fails at the high end":
        return f"none holds: P > α up to {ranges[part][1] * scale:.4g} {unit}, the high end of the model's range"
    return code


def _limit(lim: Any, nominal: dict[str, float], theta0: float, offset: float, ranges: dict[str, Any]) -> Limit:
    """The physics' :class:`~designer.physics.acceptance.PartLimit` as the spec states it: c_f as M_f = c_f θ0,
    a risk-set trail on the fork offset e (the law saw e + ``offset``), the reason in words."""
    part = _PARTS.get(lim.part, lim.part)
    scale = theta0 if lim.part == "damping" else 1.0  # c_f -> M_f = c_f θ0
    value = lim.value
    if value is not None and lim.part == "trail" and lim.side == "min":
        value -= offset  # the fork offset e the tyre sees as e + (d/2) sin φ
    return Limit(
        part=part,
        side=lim.side,
        value=None if value is None else value * scale,
        nominal=nominal[lim.part] * scale,
        unit=UNITS[part],
        probability=lim.probability,
        reason=_reason(lim.reason, lim.part, ranges, scale, UNITS[part]),
        measure=MEASURE[part],
    )


def _search_limits(
    problems: list[Problem],
    designs: list[Design],
    casters: list[LawCaster],
    offsets: list[float],
    law: Uncertainty,
    calibration: float,
) -> list[list[PartLimit]]:
    """The physics' acceptance limits of casters under one risk law, all searched together
    (:func:`designer.physics.acceptance.acceptance_limits_many`): each at its problem's V_req (calibrated), its
    swept-radius limit, and the trail's range as the tyre sees it (the fork offset's range + the caster's offset)."""
    ranges: dict[str, Any] = {name: PARAMETERS[name].range for name in ("trail", "groove", "damping")}
    shift = np.asarray(offsets, dtype=float)
    ranges["trail"] = (ranges["trail"][0] + shift, ranges["trail"][1] + shift)
    return acceptance_limits_many(
        casters,
        np.array([p.required_speed for p in problems]) / calibration,
        law,
        ranges,
        [p.swept_radius_max for p in problems],
        np.array([d.diameter + ((p.tolerances and p.tolerances.diameter) or 0.0) for d, p in zip(designs, problems)]),
    )


def caster_specs(
    problems: Problem | list[Problem],
    designs: list[Design],
    inertia: list[float],
    measured: list[bool],
    monte_carlo: list[tuple[float, float, int, int]],
    *,
    law: Uncertainty | None = None,
    stem_angle: float = 0.0,
    calibration: float = 1.0,
    probability: list[float] | None = None,
) -> list[Spec]:
    """The :class:`Spec` of each caster: limits (others at nominal), exact P at V_target beside the Monte Carlo
    ``(p, se, samples, seed)`` the caller has, and the worst corner when the problem has ``[tolerances]``; the
    acceptance limits of all of them searched in one batch (the casters under one risk law together).
    ``problems``: one for all or one per caster (a fleet's part number is specified for the most demanding of its
    chairs); the other lists one entry per caster.

    A retrofit gives its own risk law ``law`` (calibrated by an observed onset), the stem's tilt φ (the trail is
    then the fork offset e, the law sees e + (d/2) sin φ) and the calibration factor k (V_c,true is k times
    Eq. 7's: P(k V_c < V) = P(V_c < V/k)); the limits are stated on the parts as built.  ``probability``: the
    exact P at V_target the caller reports (the evaluator's), so the record and its spec say one number."""
    n = len(designs)
    each = problems if isinstance(problems, list) else [problems] * n
    offsets = [stem_offset(d, stem_angle) for d in designs]
    casters = [law_caster(p, d, i, m, o) for p, d, i, m, o in zip(each, designs, inertia, measured, offsets)]
    laws = [risk_law(p, law) for p in each]
    found: list[list[PartLimit]] = [[] for _ in range(n)]
    joints: list[JointLimits] = [None] * n  # type: ignore[list-item]
    batches = [(u, float(p.conditions.slip_coefficient)) for u, p in zip(laws, each)]  # one law and K_s a batch
    for batch in dict.fromkeys(batches):
        rows = [i for i in range(n) if batches[i] == batch]
        pick = [[seq[i] for i in rows] for seq in (each, designs, casters, offsets)]
        for i, limits in zip(rows, _search_limits(*pick, batch[0], calibration)):  # type: ignore[arg-type]
            found[i] = limits
        picked = [[seq[i] for i in rows] for seq in (each, designs, inertia, measured)]
        boxes = joint_limits_many(*picked, batch[0], offsets=[offsets[i] for i in rows], calibration=calibration)  # type: ignore[arg-type]
        for i, box in zip(rows, boxes):
            joints[i] = box
    ranges = {name: PARAMETERS[name].range for name in ("trail", "groove", "damping")}
    out = []
    for i, (problem, design, caster) in enumerate(zip(each, designs, casters)):
        theta0 = float(problem.conditions.disturbance_angle)
        nominal = {"trail": design.trail, "groove": design.groove, "damping": design.damping, "inertia": inertia[i]}
        corner = caster_corner(
            problem, design, inertia[i], measured[i], law=law, stem_angle=stem_angle, calibration=calibration
        )
        p_mc, se, samples, seed = monte_carlo[i]
        out.append(
            Spec(
                trail=design.trail,
                diameter=design.diameter,
                groove=design.groove,
                damping=design.damping,
                friction_moment=friction_moment(design.damping, theta0),
                disturbance_angle=theta0,
                inertia=inertia[i],
                measured=measured[i],
                limits=[_limit(lim, nominal, theta0, offsets[i], ranges) for lim in found[i]],
                probability=exact_probability(caster, problem.target_speed / calibration, laws[i])
                if probability is None
                else float(probability[i]),
                mc_probability=p_mc,
                mc_se=se,
                mc_samples=samples,
                mc_seed=seed,
                target_speed=problem.target_speed,
                required_speed=problem.required_speed,
                alpha=float(laws[i].probability),
                tolerances=problem.tolerances,
                corner=None if corner is None else {k: getattr(corner, k) for k in CORNER_KEYS},
                stem_angle=float(stem_angle),
                calibration=float(calibration),
                joint=joints[i],
            )
        )
    return out
