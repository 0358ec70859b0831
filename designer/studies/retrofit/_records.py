"""The records of a retrofit: a changed part (:class:`Change`), a caster and its numbers
(:class:`CasterState`), the calibration by an observed onset (:class:`Calibration`), the whole answer
(:class:`FixResult`), the ranking rule in words (:data:`RULE`) and :func:`describe_changes`.

Part of :mod:`designer.studies.retrofit._retrofit` (which builds these records).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from designer.units import percent
from designer.data.paper import BARE_FORK_DAMPING
from designer.display import number, quantity, shown
from designer.model import Caster, OfCaster
from designer.parameters import DESIGN_UNITS, OUTPUTS, PARAMETERS, VARIABLE_TABLE
from designer.reprs import Key, Record, si_frame
from designer.units import written_size

if TYPE_CHECKING:
    from designer.studies.spec import Spec

RULE = (
    "among the fixes that meet the risk bound and the swept-radius limit and raise the sill force by at most "
    "[retrofit] max_threshold_increase and the turning effort by at most [retrofit] max_turning_increase "
    "(default 10% each), the cheapest first (the sum of the [stock] costs of the parts changed), then the "
    "smallest loss w_turn·ΔF_turn + w_threshold·ΔP [N] (a negative loss is a gain), then the smaller ΔP, the "
    "smaller ΔF_turn, the higher speed reached with probability 1 − α; the others are listed apart, the "
    "smallest overshoot of either limit first"
)
"""The ranking rule, as printed in every output."""

_UNITS = {p.name: p.ascii_unit for p in VARIABLE_TABLE} | {"inertia": PARAMETERS["wheel_inertia"].ascii_unit}
"""The SI unit of each variable in the JSON records (from the parameter table; I_w is its ``wheel_inertia``)."""


@dataclass(frozen=True, kw_only=True)
class Change(Record):
    """One design variable changed by a part: ``before`` -> ``after`` [SI]."""

    part: str
    variable: str
    before: float
    after: float
    name: str | None = None  # a catalogue wheel's name

    def describe(self) -> str:
        """``fork hole: T 1.500 -> 2.000 in`` (:func:`describe_changes` of this change alone)."""
        return describe_changes([self])

    _keys = (
        "part",
        "variable",
        Key("from", "before"),
        Key("to", "after"),
        Key("unit", lambda c: _UNITS[c.variable]),
        Key("**", lambda c: {"name": c.name} if c.name else {}),
    )
    """``part``, ``variable``, ``from``, ``to`` [SI], ``unit`` (and the catalogue wheel's ``name``)."""


_CHANGED = (
    *((key, key) for key in ("parts_changed", "changes")),
    *((f"cost.{key}", f"cost_{key}") for key in ("turning_effort", "threshold_force")),
    ("cost.loss", "loss"),
    *((key, key) for key in ("parts_cost", "threshold_increase", "turning_increase", "within_limit")),
)
"""A fix's JSON keys against the current caster and the attributes they hold (none for the current caster)."""


def _if_changed(name: str) -> Callable[[Any], Any]:
    """A caster's attribute ``name``, None for the current caster (which changes nothing: the key is left out)."""
    return lambda state: getattr(state, name) if state.changes else None


@dataclass(frozen=True, kw_only=True)
class CasterState(Record):
    """A caster (the current one or a fix) and its numbers.

    Attributes
    ----------
    caster : the evaluator's row of this caster (:class:`designer.model.Caster`, on the effective trail, calibrated,
        under the retrofit's risk bound and limits): ``design``, ``inertia``, ``effective_trail``, ``turning_effort``,
        ``threshold_force``, ``swept_radius``, ``critical_speed``, ``confident_speed``, ``meets_risk_bound``,
        ``extrapolated`` and ``measured`` are read from it
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
    shimmy_probability : P(V_c,true < V_target) by the exact law (quadrature) [-]
    shimmy_probability_mc, shimmy_probability_se : the Monte Carlo's P and its standard error beside it [-] (an
        independent check)
    mc_samples, mc_seed : the Monte Carlo's draws and seed
    spec : a fix's spec (:class:`designer.studies.spec.Spec`; computed by :func:`designer.fix` for its first
        ``specs`` fixes, else None): the acceptance
        limit of each inspectable part with the others at nominal (trail min and max, groove min, bearing
        friction moment M_f = c_f θ0 min, measured wheel inertia max), from the exact law of the retrofit
        (calibrated, on the effective trail); None for the current caster
    changes : the parts changed against the current caster (empty for the current one)
    cost_turning_effort, cost_threshold_force, loss : ΔF_turn, ΔP and w_turn ΔF_turn + w_threshold ΔP [N]
    parts_cost : the sum of the [stock] costs of the parts changed (relative units; 0 for the current caster)
    threshold_increase : ΔP / P of the current caster [-]
    turning_increase : ΔF_turn / F_turn of the current caster [-]
    within_limit : threshold_increase <= the retrofit's max_threshold_increase and turning_increase <= its
        max_turning_increase
    extrapolated : the wheel's diameter lies outside Table 1's 4–8 in (its I_w and Eq. 7 are extrapolations)
    measured : the wheel's I_w was measured (``--inertia``, a catalogue wheel); else it is known by its diameter
        (Table 1's prediction interval in the risk law)
    """

    caster: Caster = field(repr=False)
    calibrated_critical_speed: float
    shimmy_probability: float = math.nan
    shimmy_probability_mc: float = math.nan
    shimmy_probability_se: float = math.nan
    mc_samples: int = 0
    mc_seed: int | None = None
    changes: tuple[Change, ...] = ()
    cost_turning_effort: float = 0.0
    cost_threshold_force: float = 0.0
    loss: float = 0.0
    parts_cost: float = 0.0
    threshold_increase: float = 0.0
    turning_increase: float = 0.0
    within_limit: bool = True
    spec: Spec | None = field(default=None, repr=False, compare=False)

    design = OfCaster()
    inertia = OfCaster()
    effective_trail = OfCaster()
    turning_effort = OfCaster()
    threshold_force = OfCaster()
    swept_radius = OfCaster()
    critical_speed = OfCaster()
    confident_speed = OfCaster()
    extrapolated = OfCaster()
    measured = OfCaster()

    @property
    def meets_risk_bound(self) -> bool:
        """The caster meets the risk bound and the swept-radius limit (its ``feasible``)."""
        return bool(self.caster.feasible)

    @property
    def parts_changed(self) -> int:
        """Number of parts changed (a catalogue wheel is one part)."""
        return len({c.part for c in self.changes})

    _units = {
        **DESIGN_UNITS,
        **{
            n: OUTPUTS[n].unit
            for n in ("inertia", "effective_trail", "turning_effort", "threshold_force", "swept_radius")
            + ("critical_speed", "confident_speed")
        },
        "calibrated_critical_speed": OUTPUTS["critical_speed"].unit,
    }

    def _repr_lines(self) -> list[str]:
        """Two lines: the design, F_turn, P, V_c and P(shimmy); the parts changed (if any)."""
        ok = "meets the risk bound" if self.meets_risk_bound else "misses the risk bound"
        lines = [
            f"CasterState({self.design.describe()}: F_turn {self.turning_effort:.4g} N, P {self.threshold_force:.4g} N, "
            f"V_c {self.critical_speed:.4g} m/s, P(shimmy) {self.shimmy_probability:.2%}; {ok})"
        ]
        if self.changes:
            lines.append(f"  {describe_changes(self.changes)} (loss {self.loss:+.3g} N)")
        return lines

    _keys = (
        "design",
        "extrapolated",
        "measured",
        "inertia",
        "effective_trail",
        Key("objectives.turning_effort", "turning_effort"),
        Key("objectives.threshold_force", "threshold_force"),
        *("turning_effort", "threshold_force", "swept_radius", "critical_speed", "calibrated_critical_speed"),
        *("confident_speed", "meets_risk_bound", "shimmy_probability", "shimmy_probability_mc"),
        *("shimmy_probability_se", "mc_samples", "mc_seed"),
        Key("spec", omit="none"),
        *(Key(key, _if_changed(name), omit="none") for key, name in _CHANGED),
    )
    """JSON-ready record, SI units: P(shimmy) exact with the Monte Carlo beside it; a fix's ``spec`` (its
    acceptance ``limits`` by part and side, ``units`` beside them: :class:`designer.studies.spec.Spec`) and its
    changes, costs and rises against the current caster."""


@dataclass(frozen=True, kw_only=True)
class Calibration(Record):
    """The model error of one caster, from its observed shimmy onset.

    Attributes
    ----------
    observed_onset : V_obs [m/s]
    predicted_onset : V_c of Eq. 7 for the current caster [m/s]
    factor : k = V_obs / V_c,Eq.7 [-]; multiplies Eq. 7 for every modified caster
    scatter : σ of log V_obs [-] (replaces the population model error)
    shift : how far calibration moved the current caster's V_c [m/s] (V_obs − V_c,Eq.7; set from the onsets)

    Its JSON is the generic :meth:`designer.reprs.Record.to_dict`: the five fields.
    """

    observed_onset: float
    predicted_onset: float
    factor: float
    scatter: float
    shift: float = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "shift", self.observed_onset - self.predicted_onset)

    def describe(self) -> str:
        return (
            f"calibrated on the observed onset {self.observed_onset:.3f} m/s: Eq. 7 predicted "
            f"{self.predicted_onset:.3f} m/s, so V_c moved by {self.shift:+.3f} m/s ({self.factor - 1:+.1%}); "
            f"every fix is evaluated with Eq. 7 × k = {self.factor:.4f}; the population model error is "
            f"replaced by the onset's own scatter (σ = {self.scatter:.3f} of the log, normal), the scatter of "
            f"M_f/θ0, K_s and I_w is kept"
        )

    _units = {"observed_onset": "m/s", "predicted_onset": "m/s", "shift": "m/s"}


@dataclass(frozen=True, kw_only=True)
class FixResult(Record):
    """Diagnosis of the current caster and the ranked fixes.

    Attributes
    ----------
    problem : the problem's name
    target_speed, required_speed : V_target and (1 + margin) V_target [m/s]
    probability : α of the risk bound (None: the nominal bound V_c >= V_req)
    stem_angle : φ [rad]
    calibration : Calibration | None
    current : CasterState of the caster as it is
    fixes : ranked CasterState list of the fixes within the limits (sill force and turning effort) (all found, or the first ``limit``)
    found : how many fixes within the limit were found before ``limit``
    rule : the ranking rule
    stock : what each part can become (its values, where they come from, its cost)
    beyond : the fixes beyond either limit, listed apart (the smallest overshoot first)
    found_beyond : how many of those were found
    max_threshold_increase : the sill-force limit, relative to the current caster's [-]
    max_turning_increase : the turning-effort limit, relative to the current caster's [-]
    searched : which combinations of parts were searched
    units : how sizes are written ("in" to 1/16, "mm" to 0.1)
    if_measured : without ``--inertia`` (the current wheel known by its diameter), the same retrofit for the wheel
        measured at its power-law value: {"inertia", "needs_fix", "current_shimmy_probability",
        "current_shimmy_probability_se", "fix" (the top fix or None), "summary"}
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
    stock: dict[str, str] = field(default_factory=dict)
    scatter: dict[str, Any] = field(default_factory=dict)
    beyond: list[CasterState] = field(default_factory=list)
    found_beyond: int = 0
    max_threshold_increase: float = 0.10
    max_turning_increase: float = 0.10
    searched: str = ""
    units: str = "in"
    if_measured: dict[str, Any] | None = None

    @property
    def single_part_fix_exists(self) -> bool:
        """True if some fix changes one part only."""
        return any(f.parts_changed == 1 for f in self.fixes)

    @property
    def needs_fix(self) -> bool:
        """False when the current caster already meets the risk bound and the swept-radius limit."""
        return not self.current.meets_risk_bound

    @property
    def best(self) -> CasterState | None:
        """The answer: the first fix within the limits, else the least bad beyond it (None: no fix)."""
        return self.fixes[0] if self.fixes else (self.beyond[0] if self.beyond else None)

    def summary(self) -> str:
        """The answer in words, first: "Best fix: a 7 in wheel with a 3/4 in groove in the 2 1/2 in fork hole;
        sill force 98 → 107 N (+8.6 %), turning effort 14.0 → 7.9 N; ..." (generated from the numbers)."""
        if not self.needs_fix:
            return "The current caster already meets the risk bound and the swept-radius limit: no fix needed."
        best = self.best
        if best is None:
            return "No fix from the stock meets the risk bound and the swept-radius limit."
        lead = (
            "Best fix: "
            if self.fixes
            else f"No fix keeps the sill force within +{self.max_threshold_increase:.0%} and the turning effort "
            f"within +{self.max_turning_increase:.0%}; the least bad: "
        )
        return lead + fix_sentence(best, self.current, self.units, self.probability)

    _keys = (
        *("problem", "target_speed", "required_speed", Key("risk_probability", "probability"), "stem_angle"),
        *(
            "calibration",
            "scatter",
            "rule",
            "stock",
            "needs_fix",
            "single_part_fix_exists",
            Key("summary", "summary()"),
        ),
        *("max_threshold_increase", "max_turning_increase", "searched", "current", Key("fixes_found", "found")),
        *("fixes", Key("fixes_beyond_limit_found", "found_beyond"), Key("fixes_beyond_limit", "beyond")),
        Key("if_measured", omit="none"),
    )
    """JSON-ready: ``current``, ranked ``fixes`` and the assumptions, SI units."""

    def to_pandas(self) -> Any:
        """One row per caster, the current one first then the fixes in rank order: ``rank`` (0: current),
        ``changes`` (in words), the design [SI], F_turn, P, V_c, the speed at 1 − α, P(shimmy) (exact), the
        Monte Carlo's and its SE, the
        loss [N]; units in ``df.attrs["units"]``."""
        numbers = (
            *("turning_effort", "threshold_force", "critical_speed", "confident_speed", "shimmy_probability"),
            *("shimmy_probability_mc", "shimmy_probability_se"),
        )
        rows = [
            {
                "rank": rank,
                "changes": describe_changes(state.changes) if state.changes else "current",
                **state.design.to_dict(),
                **{n: getattr(state, n) for n in numbers},
                "meets_risk_bound": bool(state.meets_risk_bound),
                "loss_N": state.loss,
            }
            for rank, state in enumerate([self.current, *self.fixes])
        ]
        return si_frame(
            "FixResult.to_pandas", rows, list(rows[0]), {"loss_N": "N"}, problem=self.problem, rule=self.rule
        )

    def _repr_lines(self) -> list[str]:
        """Two lines: the current caster (V_c, P(shimmy)) and the answer in one sentence."""
        return [
            f"FixResult({self.problem!r}, current V_c {self.current.critical_speed:.3f} m/s, "
            f"P(shimmy) {self.current.shimmy_probability:.1%}, {self.found} fixes within the limits"
            + (f", {len(self.fixes)} listed)" if len(self.fixes) < self.found else ")"),
            f"  {self.summary()}",
        ]

    def _html_caption(self) -> str:
        return self.summary()

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The current caster, then each fix (first five) with its changes, F_turn, P and P(shimmy)."""
        rows: list[tuple[Any, Any, Any]] = [
            ("current", f"{self.current.design.describe()}; P(shimmy) {self.current.shimmy_probability:.2%}", ""),
            *(
                (
                    f"fix {rank}",
                    f"{describe_changes(f.changes)}; F_turn {f.turning_effort:.4g} N, P {f.threshold_force:.4g} N, "
                    f"P(shimmy) {f.shimmy_probability:.2%}",
                    "",
                )
                for rank, f in enumerate(self.fixes[:5], start=1)
            ),
        ]
        if self.found > 5:
            rows.append(("more fixes", str(self.found - 5), ""))
        return rows


def describe_changes(changes: Iterable[Change], sep: str = "; ", inertia: bool = True, units: str | None = None) -> str:
    """``fork hole: T 1.500 -> 2.000 in; wheel: d 7.750 -> 6.000 in, I_w 0.00127 -> 0.000685 kg·m²`` (parts joined by ``sep``);
    with ``units`` ("in" or "mm") the lengths as the user writes them: ``fork hole: T 1 1/2 -> 2 in``."""
    by_part: dict[str, list[str]] = {}
    names = {}
    for c in changes:
        if c.name:
            names[c.part] = c.name
        if c.variable == "inertia" and not inertia:
            continue
        symbol = quantity(c.variable).symbol
        if units is not None and quantity(c.variable).dimension == "length":
            text = f"{symbol} {written_size(c.before, units).rsplit(' ', 1)[0]} -> {written_size(c.after, units)}"
        else:
            text = f"{symbol} {number(c.before, c.variable, 'in')} -> {shown(c.after, c.variable, 'in')}"
        by_part.setdefault(c.part, []).append(text)
    return sep.join(
        f"{part}{' (' + names[part] + ')' if part in names else ''}: {', '.join(items)}"
        for part, items in by_part.items()
    )


def fix_sentence(fix: CasterState, current: CasterState, units: str = "in", alpha: float | None = None) -> str:
    """A fix in words, the parts it changes first: "a 7 in wheel with a 3/4 in groove in the 2 1/2 in fork hole;
    sill force 98 → 107 N (+8.6 %), turning effort 14.0 → 7.9 N; P(shimmy) 2.1 % (bound 5 %); parts cost 9 ([stock]
    cost units)": the unit of the costs is the one the problem's [stock] costs are written in."""
    d = fix.design
    parts = {c.part for c in fix.changes}
    names = {c.part: c.name for c in fix.changes if c.name}
    groove_changed = abs(d.groove - current.design.groove) > 1e-12
    groove = f"a {written_size(d.groove, units)} groove" if d.groove > 1e-12 else "a plain tyre"
    text = ""
    if "wheel" in parts:
        text = f"a {written_size(d.diameter, units)} wheel" + (f" ({names['wheel']})" if "wheel" in names else "")
        if groove_changed:
            text += f" with {groove}"
    elif groove_changed:
        text = groove
    if "fork hole" in parts:
        text += (" in the " if text else "the ") + f"{written_size(d.trail, units)} fork hole"
    if "washer" in parts:
        washer = (
            "the bare bearing (no friction washer)"
            if d.damping <= BARE_FORK_DAMPING * (1 + 1e-9)
            else f"a friction washer (c_f = {d.damping:.3g} N·m/rad)"
        )
        text += (" with " if text else "") + washer
    risk = f"P(shimmy) {fix.shimmy_probability:.1%}" + (f" (bound {percent(alpha)})" if alpha is not None else "")
    out = (
        f"{text}; sill force {current.threshold_force:.0f} → {fix.threshold_force:.0f} N "
        f"({fix.threshold_increase:+.1%}), turning effort {current.turning_effort:.1f} → {fix.turning_effort:.1f} N; "
        f"{risk}; parts cost {fix.parts_cost:g} ([stock] cost units)"
    )
    if fix.extrapolated:
        out += f"; the {written_size(d.diameter, units)} wheel is outside Table 1's 4–8 in: extrapolated"
    return out
