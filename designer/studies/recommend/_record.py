"""The :class:`Recommendation` record: one caster to build, its numbers and the fronts behind it, with its
text, JSON, HTML and drawing views.  Built by :func:`designer.studies.recommend._recommend.recommend` (which re-exports it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from designer.units import percent
from designer.display import quantity, shown
from designer.units import INCH, written_size
from designer.model import VARIABLES, Caster, OfCaster
from designer.parameters import OUTPUTS
from designer.plots.caster import caster_svg, plot_caster
from designer.problem import Problem
from designer.reprs import Key, Record, si_frame
from designer.studies.acceptance import box_short
from designer.studies.spec import limit_shown

if TYPE_CHECKING:  # the front's record for the checker only: designer.studies.front loads casadi
    from designer.studies.front import Front
    from designer.studies.spec import Spec


@dataclass(frozen=True, kw_only=True)
class Recommendation(Record):
    """One caster to build, its numbers, and the fronts behind it (SI units).

    Attributes
    ----------
    caster : the evaluator's row of this caster (:class:`designer.model.Caster`, under the problem's conditions):
        ``design``, ``turning_effort``, ``threshold_force``, ``critical_speed``, ``swept_radius``, ``inertia``,
        ``measured`` and ``extrapolated`` below are read from it
    design : the caster (trail, diameter, groove, damping)
    turning_effort : F_turn [N] (Eq. 9 with the turning model)
    threshold_force : P, force to climb the sill [N] (Eq. 4A)
    critical_speed : V_c of Eq. 7 [m/s]
    confident_speed : the speed reached with probability 1 − α, V_q [m/s]: the exact law's α-quantile of V_c,true
        (:func:`designer.physics.acceptance.exact_speed_quantile`), not the solvers' conservative bound
    shimmy_probability : P(V_c,true < V_target) by the exact law (quadrature) [-]
    shimmy_probability_mc : the same by Monte Carlo (own seed: ``mc_seed``, ``mc_samples`` draws), an
        independent check [-]
    shimmy_probability_se : the Monte Carlo's standard error [-]
    swept_radius : T + d/2 [m]
    swept_radius_max : the footrest limit [m] (None: no limit)
    rule : how it was chosen
    alternatives : every other caster of the buildable front, by increasing turning effort (the same record
        type), each with its role
    buildable : the buildable risk-bounded front (a :class:`designer.studies.front.Front`)
    front : the continuous risk-bounded front when the caller had it (:func:`designer.report_data` passes its
        front to :func:`~designer.studies.recommend.recommend`), else None: no attribute computes it
        (``designer.pareto_front(rec.problem)`` does)
    wheel : the wheel's name (catalogue) or None
    inertia : I_w [kg·m²]
    role : "recommended" | "easiest to turn" | "between the ends" | "easiest over the sill" | "if measured"
    note : what to know (e.g. a short front)
    measured : the wheel's I_w was measured (a catalogue wheel, a stock wheel listed with its inertia); else the
        wheel is known by its diameter and the risk law scatters its I_w by Table 1's prediction interval
    extrapolated : d lies outside Table 1's 4–8 in (the power law and Eq. 7's check extrapolate)
    risk : where P(shimmy) comes from: {"probability" (exact), "monte_carlo", "se", "sources", "dominant"}
        (:func:`designer.physics.uncertainty.law_sources`); None for an alternative
    spec : the spec a factory inspects against (:class:`designer.studies.spec.Spec`): nominal parts, each
        part's acceptance limit with the others at nominal (``spec.limits``), exact and Monte Carlo P, and the
        worst corner of ``[tolerances]``; None for the "if measured" variant
    enforced : with ``[tolerances] enforce = true``: {"changed", "unenforced" (the rule's pick without it:
        design, forces, worst-corner P), "costs_turning_effort", "costs_threshold_force" [N]}; else None
    if_measured : the recommendation for wheels measured and accepted up to their power-law value (each
        candidate evaluated as a measured wheel at exactly that value), never worse in J than this one:
        {"design", "turning_effort", "threshold_force", "shimmy_probability", "shimmy_probability_se",
        "inertia", "extrapolated", "saves_turning_effort", "saves_threshold_force"}; None when every wheel is
        measured already
    """

    caster: Caster = field(repr=False)
    confident_speed: float
    shimmy_probability: float
    shimmy_probability_se: float
    rule: str
    alternatives: list[Recommendation] = field(default_factory=list)
    buildable: Front | None = field(default=None, repr=False)
    wheel: str | None = None
    role: str = "recommended"
    note: str = ""
    mc_samples: int = 0
    mc_seed: int = 0
    problem: Problem | None = field(default=None, repr=False)
    front: Front | None = field(default=None, repr=False)
    shimmy_probability_mc: float = math.nan
    risk: dict[str, Any] | None = None
    spec: Spec | None = None
    if_measured: dict[str, Any] | None = None
    enforced: dict[str, Any] | None = None

    design = OfCaster()
    turning_effort = OfCaster()
    threshold_force = OfCaster()
    critical_speed = OfCaster()
    swept_radius = OfCaster()
    inertia = OfCaster()
    measured = OfCaster()
    extrapolated = OfCaster()
    # the problem's numbers, read from it (never copied)
    swept_radius_max = property(lambda self: self.problem.swept_radius_max)
    target_speed = property(lambda self: self.problem.target_speed)
    required_speed = property(lambda self: self.problem.required_speed)
    alpha = property(lambda self: None if self.problem.risk is None else self.problem.risk.probability)
    weights = property(lambda self: tuple(self.problem.weights))

    _keys = (
        *("design", "turning_effort", "threshold_force", "critical_speed", "confident_speed", "shimmy_probability"),
        *("shimmy_probability_mc", "shimmy_probability_se", "mc_samples", "mc_seed", "swept_radius"),
        *("swept_radius_max", "rule", "role", "wheel", "extrapolated", "measured"),
        *(Key(name, omit="none") for name in ("risk", "if_measured", "enforced", "spec")),
        Key("alternatives", option="alternatives"),
    )
    """The JSON record of ``designer run --json`` (SI): ``risk``, ``if_measured``, ``enforced`` and ``spec`` only when
    set; ``to_dict(alternatives=True)`` adds the alternatives (each without its own)."""

    def lines(self) -> list[str]:
        """The caster as text lines (inches and SI)."""
        d = self.design
        risk = (
            f"P(shimmy at {self.target_speed:.3g} m/s) = {self.shimmy_probability:.2%} (exact law; Monte Carlo "
            f"{self.shimmy_probability_mc:.2%} ± {self.shimmy_probability_se:.2%}, {self.mc_samples} draws, "
            f"seed {self.mc_seed})"
        )
        limit = (
            "no limit"
            if self.swept_radius_max is None
            else f"limit {shown(self.swept_radius_max, 'swept_radius', 'in')}"
        )
        radius = f"{shown(self.swept_radius, 'swept_radius', 'in')} ({limit})"
        level = f"{percent(1 - self.alpha)}" if self.alpha is not None else "95% (default scatter; no risk bound)"
        extra = []
        if self.extrapolated:
            extra.append(
                f"  warning: d = {shown(d.diameter, 'diameter', 'in')} lies outside Table 1's 4–8 in: the inertia fit and Eq. 7's "
                "check are extrapolated (the risk law's prediction interval widens with it)"
            )
        if self.risk is not None:
            extra.append(f"  {self.risk['dominant']}")
        if self.spec is not None:
            extra += spec_lines(self.spec)
        design = d.variable_lines(22)
        design[1] += f"   wheel {self.wheel}" if self.wheel else ""
        return [
            *design,
            f"  turning effort      {self.turning_effort:8.3f} N",
            f"  sill force          {self.threshold_force:8.3f} N",
            f"  V_c (Eq. 7)         {self.critical_speed:8.3f} m/s",
            f"  speed reached with probability {level}: {self.confident_speed:.3f} m/s "
            f"(required {self.required_speed:.3f})",
            f"  {risk}",
            f"  swept radius        {radius}",
            *extra,
        ]

    def headline(self, length: Callable[[float], str] | None = None) -> str:
        """One sentence: what to build for any wheel of its size, and what measuring the wheel allows.

        ``length`` writes a length [m] (default: as written in inches, ``"7 in"``, ``"2 1/2 in"``)."""
        size = length if length is not None else (lambda x: written_size(x, "in"))
        d = self.design
        kind = "The measured wheel" if self.measured else f"Any {size(d.diameter)} wheel"
        text = (
            f"{kind}: build T {size(d.trail)}, B {size(d.groove)}, c_f {d.damping:.3g} N·m/rad "
            f"(P(shimmy) {100 * self.shimmy_probability:.1f} %)."
        )
        m = self.if_measured
        if m is None:
            return text
        md = m["design"]
        if all(abs(md[k] - getattr(d, k)) <= 1e-12 for k in md):
            return text + (
                f" Measuring the wheel (accepted at or under {m['inertia']:.3g} kg·m²) changes no part; its risk is "
                f"{100 * m['shimmy_probability']:.1f} %."
            )
        gains = []  # both changes, a cost as plainly as a saving (J never rises, but one force may)
        for key, easier, harder in (
            ("saves_turning_effort", "easier to turn", "harder to turn"),
            ("saves_threshold_force", "easier over the sill", "harder over the sill"),
        ):
            if abs(m[key]) > 1e-9:
                gains.append(f"{abs(m[key]):.2g} N {easier if m[key] > 0 else harder}")
        return text + (
            f" If you measure the wheel: a {size(md['diameter'])} wheel measured at or under {m['inertia']:.3g} kg·m² "
            f"(Table 1's power law at that size) lets you build T {size(md['trail'])}, B {size(md['groove'])}, "
            f"c_f {md['damping']:.3g} N·m/rad instead"
            + (f", {' and '.join(gains)}" if gains else "")
            + f" (P(shimmy) {100 * m['shimmy_probability']:.1f} %)."
        )

    def enforced_sentence(self) -> str:
        """What ``[tolerances] enforce = true`` did: kept the rule's pick (it holds at its worst corner), or
        changed it, with the rule's pick's worst-corner P and what the change costs in turning effort and sill
        force (a saving said as one)."""
        e = self.enforced
        if e is None:
            return ""
        free = e["unenforced"]
        alpha = self.alpha if self.alpha is not None else self.spec.alpha if self.spec is not None else math.nan
        if not e["changed"]:
            return (
                f"[tolerances] enforce = true: the rule's pick holds at its worst corner "
                f"(P(shimmy) {free['worst_corner_probability']:.2%} <= {percent(alpha)}), so it stays."
                + self.price_sentence()
            )
        d = free["design"]
        costs = []
        for key, name in (("costs_threshold_force", "sill force"), ("costs_turning_effort", "turning effort")):
            value = e[key]
            more = "more" if value > 0 else "less"
            costs.append(f"{abs(value):.2f} N {more} {name}" if abs(value) >= 0.005 else f"the same {name}")
        return (
            f"[tolerances] enforce = true changed the caster: the rule's pick without it ({_parts(d)}) "
            f"reaches P(shimmy) {free['worst_corner_probability']:.2%} at its worst corner, above {percent(alpha)}; "
            f"this one holds there, with {' and '.join(costs)} "
            f"({free['turning_effort']:.2f} → {self.turning_effort:.2f} N turning, "
            f"{free['threshold_force']:.1f} → {self.threshold_force:.1f} N over the sill)." + self.price_sentence()
        )

    def price_sentence(self) -> str:
        """The price of the tolerances apart from the rule's choice: the least-J caster that holds the bound at
        its worst corner against the least-J caster without tolerances ("" when not computed)."""
        price = (self.enforced or {}).get("price")
        if not price:
            return ""
        free, hold = price["least_objective_without_tolerances"], price["least_objective_holding"]

        def caster(x: dict[str, Any]) -> str:
            return f"{_parts(x['design'])}, J = {x['objective']:.2f} N"

        if hold is None:
            return " No buildable caster holds at its worst corner: the tolerances cannot be met."
        if price["objective_price"] <= 1e-9:
            return (
                f" The tolerances cost nothing in J: the least-J caster ({caster(free)}) holds at its worst corner "
                f"({hold['worst_corner_probability']:.2%}); any difference from it is the rule's choice."
            )
        return (
            f" Price of the tolerances: the least-J caster that holds at its worst corner ({caster(hold)}, "
            f"{hold['worst_corner_probability']:.2%} there) against the least-J caster without them ({caster(free)}, "
            f"{free['worst_corner_probability']:.2%} at its worst corner): {price['objective_price']:.2f} N of J; "
            "the rest of any difference between the picks is the rule's choice."
        )

    def __str__(self) -> str:
        p = self.problem
        head = [f"Build this caster for {p.name!r} ({self.rule}):" if p is not None else f"Build this ({self.rule}):"]
        out = head + self.lines()
        if self.enforced is not None:
            out += ["", self.enforced_sentence()]
        if self.if_measured is not None:
            out += ["", self.headline()]
        for alt in self.alternatives:
            out += ["", f"Alternative: {alt.role}"] + alt.lines()
        if self.note:
            out += ["", f"Note: {self.note}"]
        return "\n".join(out)

    def to_pandas(self) -> Any:
        """One row per caster, the recommendation then its alternatives: ``role``, ``wheel``, the design [SI],
        F_turn, P [N], V_c, the speed at 1 − α and the swept radius, P(shimmy) and its SE, whether the wheel's
        I_w is measured and whether d lies outside Table 1; units in ``df.attrs["units"]``."""
        numbers = (
            *("turning_effort", "threshold_force", "critical_speed", "confident_speed", "swept_radius"),
            *("shimmy_probability", "shimmy_probability_se", "measured", "extrapolated"),
        )
        rows = [
            {"role": rec.role, "wheel": rec.wheel, **rec.design.to_dict(), **{n: getattr(rec, n) for n in numbers}}
            for rec in (self, *self.alternatives)
        ]
        return si_frame("Recommendation.to_pandas", rows, list(rows[0]), rule=self.rule)

    def _repr_lines(self) -> list[str]:
        """Two lines: the caster (inches) and its numbers; the rule and alternatives: ``print(rec)``."""
        d = self.design
        return [
            f"Recommendation({self.role}): {_parts(d.to_dict())}",
            f"  F_turn {self.turning_effort:.4g} N, P {self.threshold_force:.4g} N, V_c {self.critical_speed:.4g} m/s, "
            f"P(shimmy) {self.shimmy_probability:.2%} ± {self.shimmy_probability_se:.2%}",
        ]

    def draw(self, ax: Any = None, sill_height: float | None = None) -> Any:
        """The recommended caster to scale: side view (wheel, fork, trail, sill) and top view (swept circle).

        Returns ``(ax_side, ax_top)`` (matplotlib Axes; ``ax``: None for a new figure, one Axes for the side
        view only, or a pair).  ``sill_height`` [m] defaults to the problem's threshold height h.  Same
        geometry as the report's SVG drawing (:mod:`designer.plots.caster`).
        """
        d = self.design
        h = (
            sill_height
            if sill_height is not None
            else (self.problem.conditions.threshold_height if self.problem is not None else 0.5 * INCH)
        )
        name = f" for {self.problem.name!r}" if self.problem is not None else ""
        title = f"{self.role} caster{name}: T {shown(d.trail, 'trail', 'in')}, d {shown(d.diameter, 'diameter', 'in')}"
        return plot_caster(*self._geometry(h), title=title, ax=ax)

    def _geometry(self, sill_height: float) -> tuple[float, float, float, float, float | None]:
        """What the drawings take: T, d, B, the sill's height h [m] and the swept-radius limit R_max [m] or None."""
        d = self.design
        return d.trail, d.diameter, d.groove, sill_height, self.swept_radius_max

    def _html_title(self) -> str:
        title = f"Build this caster for {self.problem.name!r}" if self.problem is not None else "Build this caster"
        return f"{title} ({self.role})"

    def _html_caption(self) -> str:
        text = self.rule
        if self.risk is not None:
            text += f" {self.risk['dominant']}"
        if self.if_measured is not None:
            text += f" {self.headline()}"
        return text + (f" Note: {self.note}" if self.note else "")

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The caster as a compact table with units (notebooks; no solver runs)."""
        d = self.design
        rows: list[tuple[Any, Any, Any]] = [("wheel", self.wheel, "")] if self.wheel else []
        outputs = ("turning_effort", "threshold_force", "critical_speed", "confident_speed")
        rows += d.variable_rows() + [
            OUTPUTS[n].row(f"{getattr(self, n):.4g}", "Eq. 7" * (n == "critical_speed")) for n in outputs
        ]
        rows += [
            ("required speed", f"{self.required_speed:.4g}", "m/s"),
            ("P(shimmy) (exact law)", f"{self.shimmy_probability:.3%}", ""),
            (
                "P(shimmy) (Monte Carlo check)",
                f"{self.shimmy_probability_mc:.2%} ± {self.shimmy_probability_se:.2%}",
                "",
            ),
            (
                "swept radius (limit)",
                f"{self.swept_radius * 1000:.1f}"
                + (f" ({self.swept_radius_max * 1000:.1f})" if self.swept_radius_max is not None else ""),
                "mm",
            ),
        ]
        if self.extrapolated:
            rows.append(("outside Table 1's 4–8 in", "yes: the inertia fit and Eq. 7's check extrapolate", ""))
        if self.spec is not None:
            rows.append(("spec: bearing friction moment M_f = c_f θ0", f"{self.spec.friction_moment:.3f}", "N·m"))
            for lim in self.spec.limits:
                rows.append(
                    (f"limit: {lim.part} {lim.side}", "none" if lim.value is None else f"{lim.value:.4g}", lim.unit)
                )
        return rows

    def _html_extra(self) -> str:
        """The caster drawn to scale beside the table (needs the problem's sill)."""
        if self.problem is None:
            return ""
        geometry = self._geometry(self.problem.conditions.threshold_height)
        return str(caster_svg(*geometry, scale=17.0, label=f"{self.role} caster"))


def _parts(d: dict[str, float]) -> str:
    """A design {trail, diameter, groove, damping} [SI] in one phrase: "T 2.000 in, d 6.000 in, B 0.750 in, c_f 1.30
    N·m/rad" (the parameter table's symbols and precisions)."""
    return ", ".join(f"{quantity(k).symbol} {shown(d[k], k, 'in')}" for k in VARIABLES)


def spec_lines(spec: Spec) -> list[str]:
    """The spec as text lines: each limit (others at nominal), and the worst corner when there are tolerances."""
    out = [
        f"  spec: M_f = c_f θ0 = {spec.friction_moment:.3f} N·m (θ0 = {spec.disturbance_angle * 180 / math.pi:.0f}°)"
    ]
    if spec.joint is not None:
        out.append(
            f"  accept when every part is inside the joint box (P <= α at all {spec.joint.corners} corners): "
            + box_short(spec.joint)
        )
    short = {"trail": "T", "groove": "B", "friction_moment": "M_f", "wheel_inertia": "I_w"}
    one = ", ".join(
        f"{short[lim.part]} {'>=' if lim.side == 'min' else '<='} "
        + limit_shown(lim.value, lim.unit, lim.side).split(" (")[0]
        + (" (footrest" + (", no window" if lim.no_window else "") + ")" if lim.protects == "footrest" else "")
        for lim in spec.limits
        if lim.value is not None
    )
    out.append(f"  one part at a time (others at nominal): {one}")
    if spec.corner is not None:
        c = spec.corner
        out.append(
            f"  worst corner of the tolerances: P(shimmy) {c['probability']:.2%} (nominal {c['nominal_probability']:.2%}"
            f", bound {percent(spec.alpha)}): {'holds' if c['holds'] else 'does NOT hold'}"
        )
    return out
