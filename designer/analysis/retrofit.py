"""Retrofit: the smallest safe change to the caster you have.

A clinician or wheelchair user does not design a caster from scratch; they ask
what to change on the one that shimmies.  :func:`fix` answers with numbers:

1. **Diagnosis** of the current caster: V_c (Eq. 7, on the effective trail of a
   tilted stem, :func:`designer.physics.geometry.effective_trail`), the speed
   it reaches with probability 1 − α, P(shimmy at V_target) by Monte Carlo
   with its standard error, turning effort and sill force.
2. **Calibration** (optional): an observed shimmy onset V_obs on this caster
   replaces the population model error.  The caster's own factor
   k = V_obs / V_c,Eq.7(current) multiplies Eq. 7 for every modified caster;
   the remaining scatter is the onset's own uncertainty (σ of its log,
   default 5 %, normal) together with the scatter of M_f/θ0, K_s and I_w of
   the risk bound (kept in full: conservative for the parts you keep, whose
   deviation is already inside V_obs).
3. **Fixes** ranked by the rule of :data:`RULE`: every candidate changes one or
   more of the four parts (washer = damping c_f, tyre = groove B, fork hole =
   trail T, wheel = diameter d with I_w from the inertia model, or a
   catalogue wheel) to values that exist (:func:`part_options`), meets the
   risk bound and the swept-radius limit.

Everything is deterministic except the reported P(shimmy), a Monte Carlo
estimate with its own seed (feasibility and ranking use the quantile).
``docs/retrofit.md`` has the derivations and the worked Eq. 8 example.

Modules: :mod:`designer.analysis.retrofit_diagnosis` computes the numbers of a caster and of every
candidate (V_c, the quantile, F_turn, P, the Monte Carlo, the calibration); :mod:`designer.analysis.retrofit_options`
decides what each part can become and enumerates the combinations; this module holds the records, reads
the input and ranks (:func:`fix`).
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass, field

import numpy as np

from designer.data.paper import INCH, WALKING_SPEED
from designer.errors import InputError
from designer.model import Conditions, Design, check_design
from designer.physics.geometry import effective_trail
from designer.physics.uncertainty import MC_TARGET_SE, Uncertainty
from designer.units import parse_quantity
from designer.problem import INERTIA_RANGE
from designer.problem import load_problem
from designer.analysis.retrofit_diagnosis import (
    _calibrated,
    _current_inertia,
    _evaluate,
    _feasible,
    _mc,
    _mc_many,
    _risk_of,
)
from designer.analysis.retrofit_options import GRID_STEP, PART_VARIABLE, PARTS, _enumerate, _show, part_options


ONSET_SCATTER = 0.05
"""σ of log V_obs [-]: a shimmy onset seen on a push or a ramp is known to about ±5 % (our estimate)."""

REPORT_SAMPLES = 50_000
"""Monte Carlo draws of the reported P(shimmy): SE <= 0.1 percentage point at 5 %."""

MAX_STEM_ANGLE = math.radians(30.0)
"""Largest stem tilt accepted [rad]: seat-angle and dump changes tilt the stem by a few degrees."""


RULE = (
    "fewest parts changed first; within the same number of parts, the smallest loss "
    "w_turn·ΔF_turn + w_threshold·ΔP [N] (the problem's [objective] weights; a negative loss is a gain), "
    "ties broken by the smaller ΔF_turn, then the smaller ΔP, then the higher speed reached with "
    "probability 1 − α"
)
"""The ranking rule, as printed in every output."""


# --------------------------------------------------------------------------- records


@dataclass(frozen=True)
class Change:
    """One design variable changed by a part: ``before`` -> ``after`` [SI]."""

    part: str
    variable: str
    before: float
    after: float
    name: str | None = None  # a catalogue wheel's name

    def describe(self) -> str:
        """``fork hole: trail 1.500 in -> 2.000 in``."""
        return (
            f"{self.part}: {self.variable} {_show(self.variable, self.before)} -> {_show(self.variable, self.after)}"
            + (f" ({self.name})" if self.name else "")
        )

    def as_dict(self) -> dict:
        out = {
            "part": self.part,
            "variable": self.variable,
            "from": self.before,
            "to": self.after,
            "unit": _UNITS[self.variable],
        }
        if self.name:
            out["name"] = self.name
        return out


@dataclass(frozen=True)
class CasterState:
    """A caster (the current one or a fix) and its numbers.

    Attributes
    ----------
    design : Design (trail = fork offset e [m], diameter, groove, damping)
    inertia : I_w [kg·m²]
    effective_trail : T_eff = e + (d/2) sin φ [m] (what Eq. 7 and the turning effort see)
    turning_effort : F_turn [N] (Eq. 9 on T_eff)
    threshold_force : P [N] (Eq. 4A)
    swept_radius : T + d/2 [m]
    critical_speed : V_c of Eq. 7 [m/s]
    calibrated_critical_speed : k·V_c [m/s] (= critical_speed without calibration)
    confident_speed : speed reached with probability 1 − α under the model in force [m/s]
    meets_risk_bound : confident_speed >= V_req (and the swept-radius limit)
    shimmy_probability, shimmy_probability_se : Monte Carlo P(V_c,true < V_target) and its SE [-]
    changes : the parts changed against the current caster (empty for the current one)
    """

    design: Design
    inertia: float
    effective_trail: float
    turning_effort: float
    threshold_force: float
    swept_radius: float
    critical_speed: float
    calibrated_critical_speed: float
    confident_speed: float
    meets_risk_bound: bool
    shimmy_probability: float = math.nan
    shimmy_probability_se: float = math.nan
    changes: tuple[Change, ...] = ()
    cost_turning_effort: float = 0.0
    cost_threshold_force: float = 0.0
    loss: float = 0.0

    @property
    def parts_changed(self) -> int:
        """Number of parts changed (a catalogue wheel is one part)."""
        return len({c.part for c in self.changes})

    def as_dict(self) -> dict:
        """JSON-ready record, SI units."""
        out = {
            "design": self.design.as_dict(),
            "inertia": self.inertia,
            "effective_trail": self.effective_trail,
            "objectives": {"turning_effort": self.turning_effort, "threshold_force": self.threshold_force},
            "turning_effort": self.turning_effort,
            "threshold_force": self.threshold_force,
            "swept_radius": self.swept_radius,
            "critical_speed": self.critical_speed,
            "calibrated_critical_speed": self.calibrated_critical_speed,
            "confident_speed": self.confident_speed,
            "meets_risk_bound": bool(self.meets_risk_bound),
            "shimmy_probability": self.shimmy_probability,
            "shimmy_probability_se": self.shimmy_probability_se,
        }
        if self.changes:
            out["parts_changed"] = self.parts_changed
            out["changes"] = [c.as_dict() for c in self.changes]
            out["cost"] = {
                "turning_effort": self.cost_turning_effort,
                "threshold_force": self.cost_threshold_force,
                "loss": self.loss,
            }
        return out


@dataclass(frozen=True)
class Calibration:
    """The model error of one caster, from its observed shimmy onset.

    Attributes
    ----------
    observed_onset : V_obs [m/s]
    predicted_onset : V_c of Eq. 7 for the current caster [m/s]
    factor : k = V_obs / V_c,Eq.7 [-]; multiplies Eq. 7 for every modified caster
    scatter : σ of log V_obs [-] (replaces the population model error)
    """

    observed_onset: float
    predicted_onset: float
    factor: float
    scatter: float

    @property
    def shift(self) -> float:
        """How far calibration moved the current caster's V_c [m/s] (V_obs − V_c,Eq.7)."""
        return self.observed_onset - self.predicted_onset

    def describe(self) -> str:
        return (
            f"calibrated on the observed onset {self.observed_onset:.3f} m/s: Eq. 7 predicted "
            f"{self.predicted_onset:.3f} m/s, so V_c moved by {self.shift:+.3f} m/s ({self.factor - 1:+.1%}); "
            f"every fix is evaluated with Eq. 7 × k = {self.factor:.4f}; the population model error is "
            f"replaced by the onset's own scatter (σ = {self.scatter:.3f} of the log, normal), the scatter of "
            f"M_f/θ0, K_s and I_w is kept"
        )

    def as_dict(self) -> dict:
        return {
            "observed_onset": self.observed_onset,
            "predicted_onset": self.predicted_onset,
            "factor": self.factor,
            "shift": self.shift,
            "scatter": self.scatter,
        }


@dataclass
class FixResult:
    """Diagnosis of the current caster and the ranked fixes.

    Attributes
    ----------
    problem : the problem's name
    target_speed, required_speed : V_target and (1 + margin) V_target [m/s]
    probability : α of the risk bound (None: the nominal bound V_c >= V_req)
    stem_angle : φ [rad]
    calibration : Calibration | None
    current : CasterState of the caster as it is
    fixes : ranked CasterState list (all found, or the first ``limit``)
    found : how many fixes were found before the limit
    rule : the ranking rule
    stock : where each part's candidates came from
    """

    problem: str
    target_speed: float
    required_speed: float
    probability: float | None
    stem_angle: float
    calibration: Calibration | None
    current: CasterState
    fixes: list[CasterState]
    found: int
    rule: str = RULE
    stock: dict = field(default_factory=dict)
    scatter: dict = field(default_factory=dict)

    @property
    def single_part_fix_exists(self) -> bool:
        """True if some fix changes one part only."""
        return any(f.parts_changed == 1 for f in self.fixes)

    @property
    def needs_fix(self) -> bool:
        """False when the current caster already meets the risk bound and the swept-radius limit."""
        return not self.current.meets_risk_bound

    def summary(self) -> str:
        """One sentence generated from the numbers."""
        if not self.needs_fix:
            return "The current caster already meets the risk bound and the swept-radius limit: no fix needed."
        if not self.fixes:
            return "No fix from the stock meets the risk bound and the swept-radius limit."
        best = self.fixes[0]
        lead = "" if best.parts_changed == 1 else f"No single-part fix exists; the best {best.parts_changed}-part fix: "
        return (
            lead
            + describe_changes(best.changes)
            + (
                f" (ΔF_turn {best.cost_turning_effort:+.2f} N, ΔP {best.cost_threshold_force:+.2f} N, "
                f"P(shimmy) {best.shimmy_probability:.2%} ± {best.shimmy_probability_se:.2%})"
            )
        )

    def as_dict(self) -> dict:
        """JSON-ready: ``current``, ranked ``fixes`` and the assumptions, SI units."""
        return {
            "problem": self.problem,
            "target_speed": self.target_speed,
            "required_speed": self.required_speed,
            "risk_probability": self.probability,
            "stem_angle": self.stem_angle,
            "calibration": None if self.calibration is None else self.calibration.as_dict(),
            "scatter": self.scatter,
            "rule": self.rule,
            "stock": self.stock,
            "needs_fix": self.needs_fix,
            "single_part_fix_exists": self.single_part_fix_exists,
            "summary": self.summary(),
            "current": self.current.as_dict(),
            "fixes_found": self.found,
            "fixes": [f.as_dict() for f in self.fixes],
        }

    def __repr__(self) -> str:
        return (
            f"FixResult({self.problem!r}, current V_c {self.current.critical_speed:.3f} m/s, "
            f"P(shimmy) {self.current.shimmy_probability:.1%}, {self.found} fixes; {self.summary()})"
        )


# --------------------------------------------------------------------------- input


_KEYS = {
    "t": "trail",
    "trail": "trail",
    "d": "diameter",
    "diameter": "diameter",
    "b": "groove",
    "groove": "groove",
    "c": "damping",
    "c_f": "damping",
    "cf": "damping",
    "damping": "damping",
}
_UNITS = {"trail": "m", "diameter": "m", "groove": "m", "damping": "N*m/rad", "inertia": "kg*m**2"}


def parse_current(text: str, option: str = "--current") -> Design:
    """Parse ``"T=1.5in,d=7.75in,B=0.5625in,c=1.3"`` into a :class:`Design` [SI].

    Keys: T (trail), d (diameter), B (groove), c (damping, N·m/rad); values
    with units, plain numbers in SI.  InputError names the piece that fails.
    """

    if not isinstance(text, str) or not text.strip():
        raise InputError(f'{option} {text!r}: expected T=..,d=..,B=..,c=.. (e.g. "T=1.5in,d=7.75in,B=0.5625in,c=1.3")')
    values: dict[str, float] = {}
    for piece in text.split(","):
        if "=" not in piece:
            raise InputError(
                f"{option} {text!r}: {piece.strip()!r} is not KEY=VALUE "
                f'(keys T, d, B, c; e.g. "T=1.5in,d=7.75in,B=0.5625in,c=1.3")'
            )
        key, value = (s.strip() for s in piece.split("=", 1))
        name = _KEYS.get(key.lower())
        if name is None:
            raise InputError(
                f"{option}: unknown key {key!r} in {text!r}; keys are T (trail), d (diameter), B (groove), c (damping)"
            )
        if name in values:
            raise InputError(f"{option}: {key!r} given twice in {text!r}")
        value = re.sub(r"^([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*([A-Za-z].*)$", r"\1 \2", value)
        try:
            number = float(value)
        except ValueError:
            number = None
        dimension = "damping" if name == "damping" else "length"
        values[name] = parse_quantity(number if number is not None else value, dimension, f"{option} {key}")
    missing = [k for k, n in (("T", "trail"), ("d", "diameter"), ("B", "groove"), ("c", "damping")) if n not in values]
    if missing:
        raise InputError(f"{option} {text!r}: missing {', '.join(missing)} (give T, d, B and c)")
    try:
        return Design(**values)
    except InputError as exc:
        raise InputError(f"{option}: {exc}") from None


def _check_inputs(problem, current: Design, inertia, shimmied_at, stem_angle, onset_scatter) -> None:
    """InputError (one line naming the value) for a caster or observation the model cannot take."""
    check_design(current, "current ", error=InputError)
    h = problem.conditions.threshold_height
    if current.diameter <= 2 * h:
        raise InputError(
            f"current diameter = {current.diameter / INCH:.3g} in: must exceed twice the sill height "
            f"({2 * h / INCH:.3g} in); d/h <= 2 cannot climb the sill (Eq. 4A)"
        )
    c0 = problem.conditions.turning.bare_fork_damping
    if current.damping < c0 - 1e-12:
        raise InputError(
            f"current damping = {current.damping:g} N·m/rad: below the bare ball-bearing fork's "
            f"{c0:g} N·m/rad (Eq. 11C), the least spindle damping a caster has"
        )
    if inertia is not None:
        if not (
            isinstance(inertia, (int, float))
            and math.isfinite(inertia)
            and INERTIA_RANGE[0] <= inertia <= INERTIA_RANGE[1]
        ):
            raise InputError(
                f"inertia = {inertia!r} kg·m²: must be between {INERTIA_RANGE[0]:g} and "
                f"{INERTIA_RANGE[1]:g} kg·m² (Table 1: 0.00026 to 0.0046)"
            )
    if not (isinstance(stem_angle, (int, float)) and math.isfinite(stem_angle) and abs(stem_angle) <= MAX_STEM_ANGLE):
        raise InputError(
            f"stem angle = {format(math.degrees(stem_angle), '.4g') if isinstance(stem_angle, (int, float)) else repr(stem_angle)}"
            f" deg: must be within ±{math.degrees(MAX_STEM_ANGLE):.0f} deg of vertical"
        )
    t_eff = effective_trail(current.trail, current.diameter / 2, stem_angle)
    if t_eff <= 0:
        raise InputError(
            f"stem angle = {math.degrees(stem_angle):.3g} deg: the effective trail "
            f"{t_eff / INCH:.3g} in is not positive (the wheel would lead the stem)"
        )
    if shimmied_at is not None:
        if not (isinstance(shimmied_at, (int, float)) and math.isfinite(shimmied_at)):
            raise InputError(f"shimmied at = {shimmied_at!r}: expected a speed in m/s")
        if shimmied_at < WALKING_SPEED:
            raise InputError(
                f"shimmied at = {shimmied_at:g} m/s: below walking speed ({WALKING_SPEED:g} m/s); "
                f"a caster that shimmies that slowly is broken (loose bearing, bent fork), not "
                f"described by Eq. 7; or was the speed in km/h?"
            )
        if shimmied_at > 10.0:
            raise InputError(
                f"shimmied at = {shimmied_at:g} m/s: above 10 m/s, no wheelchair goes that fast; "
                f"was it given in km/h or mph?"
            )
    if not (math.isfinite(onset_scatter) and 0 < onset_scatter <= 1):
        raise InputError(f"onset scatter = {onset_scatter!r}: σ of the log onset must be in (0, 1]")


# --------------------------------------------------------------------------- candidates


# --------------------------------------------------------------------------- evaluation


# --------------------------------------------------------------------------- the analysis


# long by its docstring (every argument documented); the body: diagnosis, then _ranked fixes, then the records
def fix(
    problem,
    current,
    inertia: float | None = None,
    shimmied_at: float | None = None,
    stem_angle: float = 0.0,
    *,
    onset_scatter: float = ONSET_SCATTER,
    limit: int | None = None,
    samples: int | None = None,
    seed: int | None = None,
) -> FixResult:
    """Diagnose a caster that shimmies and rank the smallest safe changes to it.

    Parameters
    ----------
    problem : Problem (or a path to a problem file): load, sill, V_target, the
        risk bound, bounds, the swept-radius limit and ``[stock]``
    current : Design (or ``"T=1.5in,d=7.75in,B=0.5625in,c=1.3"``) of the caster
        as it is; T is the fork offset (the trail with the stem vertical) [m]
    inertia : the current wheel's measured I_w [kg·m²]; default the problem's inertia model
    shimmied_at : observed shimmy onset V_obs [m/s] of this caster; calibrates
        the model error (see :class:`Calibration`)
    stem_angle : stem tilt φ from vertical [rad], positive when its top leans
        back; the effective trail is e + (d/2) sin φ (:func:`effective_trail`)
    onset_scatter : σ of log V_obs [-] (default 0.05)
    limit : keep the first ``limit`` fixes (None: all found)
    samples, seed : Monte Carlo of the reported P(shimmy) (default: the risk bound's, at least 50 000 draws
        and more until the SE is 0.1 percentage point; its own seed, never one that ranks)

    Returns
    -------
    FixResult with ``.current`` and the ranked ``.fixes`` (rule :data:`RULE`).

    Fixes change one or two parts; three- and four-part fixes are searched
    only when no one- or two-part fix exists.  Feasibility is deterministic:
    the speed reached with probability 1 − α (the quantile of the risk bound,
    times k when calibrated) >= (1 + margin) V_target, and T + d/2 <= the
    swept-radius limit.  Equations: Eq. 7 (V_c), Eq. 4A (P), Eq. 9 (F_turn).
    """
    if isinstance(problem, str) or hasattr(problem, "__fspath__"):
        problem = load_problem(problem)
    if isinstance(current, str):
        current = parse_current(current, "current")
    stem_angle = float(stem_angle)
    _check_inputs(problem, current, inertia, shimmied_at, stem_angle, onset_scatter)
    conditions = problem.conditions
    if inertia is None:
        inertia = _current_inertia(problem, current)
    inertia = float(inertia)
    bound, report_u = _risk_of(problem)
    samples = int(samples or max(REPORT_SAMPLES, report_u.samples))
    seed = int(report_u.seed if seed is None else seed)

    base = {
        "trail": current.trail,
        "diameter": current.diameter,
        "groove": current.groove,
        "damping": current.damping,
        "inertia": inertia,
    }
    raw = _evaluate({k: np.array([v]) for k, v in base.items()}, conditions, stem_angle, 1.0, bound)
    calibration = None
    factor = 1.0
    if shimmied_at is not None:
        predicted = float(raw["critical_speed"][0])
        factor = float(shimmied_at) / predicted
        calibration = Calibration(float(shimmied_at), predicted, factor, float(onset_scatter))
        if bound is not None:
            bound = _calibrated(bound, onset_scatter)
        report_u = _calibrated(report_u, onset_scatter)
    now = _evaluate({k: np.array([v]) for k, v in base.items()}, conditions, stem_angle, factor, bound)
    setting = _Setting(
        conditions,
        stem_angle,
        factor,
        bound,
        report_u,
        samples,
        seed,
        problem.required_speed,
        problem.target_speed,
        problem.swept_radius_max,
        problem.weights,
    )

    current_state = setting.state(now, 0, (current, inertia))
    options, sources = part_options(problem, current, inertia)
    stock_note = {part: sources[part] for part in PARTS}
    scatter = {
        "bound": None if bound is None else dataclasses.asdict(bound),
        "reported": dataclasses.asdict(report_u) | {"samples": samples, "seed": seed},
    }
    result = FixResult(
        problem.name,
        problem.target_speed,
        setting.v_req,
        None if bound is None else bound.probability,
        stem_angle,
        calibration,
        current_state,
        [],
        0,
        RULE,
        stock_note,
        scatter,
    )
    if current_state.meets_risk_bound:
        return result

    cands, values, chosen, result.found = _ranked(options, sources, base, setting, current_state, limit)
    shared = _mc_many(
        values["effective_trail"][chosen],
        cands["inertia"][chosen],
        cands["groove"][chosen],
        cands["damping"][chosen],
        conditions.slip_coefficient,
        setting.v_target / factor,
        report_u,
        samples,
        seed,
    )
    fixes = []
    for n, j in enumerate(chosen):
        design = Design(
            float(cands["trail"][j]), float(cands["diameter"][j]), float(cands["groove"][j]), float(cands["damping"][j])
        )
        changes = _changes(current, inertia, cands, j, options["wheel"])
        fixes.append(
            setting.state(
                values,
                j,
                (design, float(cands["inertia"][j])),
                changes,
                (
                    values["turning_effort"][j] - current_state.turning_effort,
                    values["threshold_force"][j] - current_state.threshold_force,
                ),
                (float(shared[0][n]), float(shared[1][n])),
            )
        )
    result.fixes = fixes
    return result


@dataclass(frozen=True)
class _Setting:
    """What every caster of one retrofit is judged with: the conditions, the risk model and the rule's numbers."""

    conditions: Conditions
    stem_angle: float
    factor: float
    bound: Uncertainty | None
    report_u: Uncertainty
    samples: int
    seed: int
    v_req: float
    v_target: float
    r_max: float | None
    weights: tuple[float, float]

    def state(self, values, j, design, changes=(), cost=(0.0, 0.0), mc=None) -> CasterState:
        """Caster ``j`` of the evaluated ``values`` as a :class:`CasterState` (its P(shimmy) topped up if needed)."""
        ok = values["confident_speed"][j] >= self.v_req * (1 - 1e-12) and (
            self.r_max is None or values["swept_radius"][j] <= self.r_max * (1 + 1e-12)
        )
        if mc is None or not mc[1] <= MC_TARGET_SE:  # one caster, or a shared draw too coarse for it: top up
            mc = _mc(
                (values["effective_trail"][j], float(design[1]), design[0].groove, design[0].damping),
                self.conditions,
                self.v_target,
                self.factor,
                self.report_u,
                self.samples,
                self.seed,
            )
        p, se = mc
        weights = self.weights
        return CasterState(
            design[0],
            float(design[1]),
            float(values["effective_trail"][j]),
            float(values["turning_effort"][j]),
            float(values["threshold_force"][j]),
            float(values["swept_radius"][j]),
            float(values["critical_speed"][j]),
            float(values["calibrated_critical_speed"][j]),
            float(values["confident_speed"][j]),
            bool(ok),
            p,
            se,
            tuple(changes),
            float(cost[0]),
            float(cost[1]),
            float(weights[0] * cost[0] + weights[1] * cost[1]),
        )


def _ranked(options: dict, sources: dict, base: dict, setting: _Setting, current_state: CasterState, limit: int | None):
    """The feasible fixes in the order of :data:`RULE`: (candidates, their values, chosen indices, how many found).

    One- and two-part changes first; three- and four-part ones only when none of those is feasible.
    """
    s = setting
    cands = _enumerate(options, sources, base, max_parts=2)
    values = _evaluate(cands, s.conditions, s.stem_angle, s.factor, s.bound)
    feasible = _feasible(values, s.v_req, s.r_max)
    if not np.any(feasible):
        cands = _enumerate(options, sources, base, max_parts=4, min_parts=3)
        values = _evaluate(cands, s.conditions, s.stem_angle, s.factor, s.bound)
        feasible = _feasible(values, s.v_req, s.r_max)
    idx = np.flatnonzero(feasible)
    d_turn = values["turning_effort"][idx] - current_state.turning_effort
    d_force = values["threshold_force"][idx] - current_state.threshold_force
    loss = s.weights[0] * d_turn + s.weights[1] * d_force
    order = np.lexsort(
        (cands["order"][idx], -values["confident_speed"][idx], d_force, d_turn, np.round(loss, 12), cands["parts"][idx])
    )
    chosen = idx[order] if limit is None else idx[order][:limit]
    return cands, values, chosen, len(order)


def _changes(current: Design, inertia: float, cands: dict, j: int, wheels: list) -> tuple[Change, ...]:
    out = []
    if cands["mask_washer"][j]:
        out.append(Change("washer", "damping", current.damping, float(cands["damping"][j])))
    if cands["mask_tyre"][j]:
        out.append(Change("tyre", "groove", current.groove, float(cands["groove"][j])))
    if cands["mask_fork hole"][j]:
        out.append(Change("fork hole", "trail", current.trail, float(cands["trail"][j])))
    if cands["mask_wheel"][j]:
        name = wheels[int(cands["wheel"][j])].name
        out.append(Change("wheel", "diameter", current.diameter, float(cands["diameter"][j]), name))
        if not cands["mask_tyre"][j] and abs(float(cands["groove"][j]) - current.groove) > 1e-12:
            out.append(Change("wheel", "groove", current.groove, float(cands["groove"][j])))
        if abs(float(cands["inertia"][j]) - inertia) > 1e-15:
            out.append(Change("wheel", "inertia", inertia, float(cands["inertia"][j])))
    return tuple(out)


_SYMBOL = {
    "damping": ("c_f", 1.0, "N·m/rad"),
    "groove": ("B", INCH, "in"),
    "trail": ("T", INCH, "in"),
    "diameter": ("d", INCH, "in"),
    "inertia": ("I_w", 1.0, "kg·m²"),
}


def describe_changes(changes, sep: str = "; ", inertia: bool = True) -> str:
    """``fork hole: T 1.5 -> 2 in; wheel: d 7.75 -> 6 in, I_w 0.00127 -> 0.000685 kg·m²`` (parts joined by ``sep``)."""
    by_part: dict[str, list[str]] = {}
    names = {}
    for c in changes:
        if c.name:
            names[c.part] = c.name
        if c.variable == "inertia" and not inertia:
            continue
        symbol, scale, unit = _SYMBOL[c.variable]
        by_part.setdefault(c.part, []).append(f"{symbol} {c.before / scale:.4g} -> {c.after / scale:.4g} {unit}")
    return sep.join(
        f"{part}{' (' + names[part] + ')' if part in names else ''}: {', '.join(items)}"
        for part, items in by_part.items()
    )


__all__ = [
    "fix",
    "describe_changes",
    "FixResult",
    "CasterState",
    "Change",
    "Calibration",
    "parse_current",
    "part_options",
    "RULE",
    "PARTS",
    "PART_VARIABLE",
    "GRID_STEP",
    "ONSET_SCATTER",
    "REPORT_SAMPLES",
    "MAX_STEM_ANGLE",
]
