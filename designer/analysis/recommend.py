"""Build this caster: one safe, buildable recommendation, by a stated rule, with the front behind it.

1. **The stock** (:func:`stock_candidates`): every combination of the parts of ``[stock]`` (fork holes,
   wheels or diameters, groove profiles, friction washers); a variable the stock leaves out stays
   continuous within its bounds, a fixed variable (or a catalogue wheel) is one part.
2. **Deterministic screening** (:func:`risk_screen`): the risk bound V_q(x) >= (1 + margin) V_target,
   V_q the speed reached with probability 1 − α (:func:`designer.physics.uncertainty.shimmy_speed_quantile`;
   V_c of Eq. 7 itself with ``[robust] enabled = false``), the swept radius T + d/2 <= R_max and the sill
   (d > 2h, Eq. 4A).  No random numbers: a tighter α can never make a caster look better.
3. **The buildable front**: all-discrete stock is evaluated exactly (vectorised); with continuous
   variables left, each stock combination's continuous rest is solved exactly (the NLP of
   :mod:`designer.analysis.pareto`: one point when the diameter is stock, since then P is fixed; its
   sub-front otherwise).  The non-dominated set in (F_turn, P) is kept.
4. **The rule** (:func:`select_rows`, vectorised so ``designer fleet`` uses the same code): the knee of
   the buildable front (the point farthest from the chord between its ends, objectives normalised to
   the front's range, on the ideal side; fewer than three points: the end with the least J = w_turn F + w_threshold P), or with
   ``[objective] max_threshold_force`` / ``max_turning_effort`` the best on the other objective within
   the cap.  Alternatives: the easiest to turn and the easiest over the sill.
5. **Reported risk**: P(shimmy at V_target) by a separate Monte Carlo of the same distribution with its
   own seed and SE <= 0.1 percentage point (:func:`designer.physics.uncertainty.shimmy_probability_mc`).

Steps 1 and 2 live in :mod:`designer.analysis.recommend_stock` (re-exported here); this module holds the
rule, the :class:`Recommendation` record and :func:`recommend`.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from designer.data.paper import INCH
from designer.errors import InfeasibleError
from designer.model import Design
from designer.physics.geometry import swept_radius
from designer.physics.inertia import Fixed
from designer.physics.shimmy import critical_shimmy_speed
from designer.physics.uncertainty import Uncertainty, shimmy_probability_mc, shimmy_speed_quantile
from designer.plots.caster import caster_svg, plot_caster
from designer.reprs import html_table
from designer.problem import Bound
from pathlib import Path
from designer.problem import load_problem
from designer.analysis.recommend_stock import (
    CandidateTable,
    ScreenedTable,
    candidate_table,
    confident_speed,
    objectives,
    risk_screen,
    stock_candidates,
)

__all__ = [
    "RULES",
    "CandidateTable",
    "Recommendation",
    "ScreenedTable",
    "candidate_table",
    "confident_speed",
    "objectives",
    "recommend",
    "risk_screen",
    "rule_text",
    "select_rows",
    "stock_candidates",
    "weights_meaning",
]

RULES = {
    "knee": "knee of the buildable risk-bounded front",
    "cap_threshold": "least turning effort with sill force <= {cap:.1f} N",
    "cap_turning": "least sill force with turning effort <= {cap:.2f} N",
    "end": "least J = {w0:g} F_turn + {w1:g} P of a buildable front of fewer than three points (no knee)",
}
"""How the recommendation is chosen (the text of ``Recommendation.rule``)."""


# --------------------------------------------------------------------------- the rule (vectorised)


# long: one vectorised pass over rows (screen, buildable front, knee rule, alternatives)
def select_rows(f: np.ndarray, p: np.ndarray, ok: np.ndarray, weights=(1.0, 1.0), cap_p=None, cap_f=None) -> dict:
    """The buildable front of each row and the rule's choice, vectorised over rows (chairs).

    Parameters
    ----------
    f, p : (rows, casters) turning effort and sill force [N]
    ok : (rows, casters) feasible (risk bound, swept radius, sill)
    weights : (w_turn, w_threshold) for ``best_j``
    cap_p, cap_f : cap on P or on F_turn [N] (at most one): the rule is then the best on the other objective

    Returns
    -------
    dict of (rows,) arrays: ``choice``, ``easiest_turn``, ``easiest_sill``, ``best_j`` (column indices, −1 if
    the row has nothing feasible or nothing within the cap), ``front_size``, ``over_cap`` (a front exists but
    no point is within the cap), and (rows, casters) ``front`` (membership of the buildable front).
    """
    f = np.atleast_2d(np.asarray(f, float))
    p = np.atleast_2d(np.asarray(p, float))
    ok = np.atleast_2d(np.asarray(ok, bool))
    n, s = f.shape
    fm = np.where(ok, f, np.inf)
    pm = np.where(ok, p, np.inf)
    # each row's casters by P ascending, ties by F ascending (infeasible last)
    order = np.lexsort((fm, pm), axis=-1)
    fs = np.take_along_axis(fm, order, axis=1)
    ps = np.take_along_axis(pm, order, axis=1)
    previous = np.concatenate([np.full((n, 1), np.inf), np.minimum.accumulate(fs, axis=1)[:, :-1]], axis=1)
    front = np.isfinite(fs) & (fs < previous)
    size = front.sum(axis=1)
    has = size > 0
    rows = np.arange(n)
    first = np.argmax(front, axis=1)  # least P on the front
    last = s - 1 - np.argmax(front[:, ::-1], axis=1)  # least F on the front (largest P)
    easiest_sill = np.where(has, order[rows, first], -1)
    easiest_turn = np.where(has, order[rows, last], -1)
    w = np.asarray(weights, float)
    with np.errstate(invalid="ignore"):
        j = np.where(ok, w[0] * f + w[1] * p, np.inf)
    best_j = np.where(has, np.argmin(j, axis=1), -1)
    over_cap = np.zeros(n, bool)
    if cap_p is not None or cap_f is not None:
        within = front & ((ps <= cap_p * (1 + 1e-12)) if cap_p is not None else (fs <= cap_f * (1 + 1e-12)))
        key = fs if cap_p is not None else ps
        pick = np.argmin(np.where(within, key, np.inf), axis=1)
        anywhere = within.any(axis=1)
        choice = np.where(anywhere, order[rows, pick], -1)
        over_cap = has & ~anywhere
    else:
        # knee in the front's order of decreasing P: a = largest-P end (least F), b = least-P end
        fa, pa = fs[rows, last], ps[rows, last]
        fb, pb = fs[rows, first], ps[rows, first]
        with np.errstate(invalid="ignore"):
            span_f = np.where(fb - fa > 0, fb - fa, 1.0)
            span_p = np.where(pa - pb > 0, pa - pb, 1.0)
            nf = (fs - fa[:, None]) / span_f[:, None]
            np_ = (ps - pb[:, None]) / span_p[:, None]
            a_p = (pa - pb) / span_p  # normalised ends: a = (0, a_p), b = (b_f, 0)
            b_f = (fb - fa) / span_f
        chord_f, chord_p = b_f, -a_p
        norm = np.hypot(chord_f, chord_p)
        with np.errstate(invalid="ignore", divide="ignore"):
            dist = np.abs(chord_f[:, None] * (np_ - a_p[:, None]) - chord_p[:, None] * nf) / norm[:, None]
            below = nf * chord_p[:, None] - (np_ - a_p[:, None]) * chord_f[:, None]
        dist = np.where(below >= 0, dist, -dist)
        dist = np.where(front, dist, -np.inf)
        # the first maximum in the decreasing-P order (as Front.knee)
        knee = s - 1 - np.argmax(dist[:, ::-1], axis=1)
        small = (size < 3) | ~(norm > 0)
        # no knee on fewer than three points: the end with the least J = w_turn F + w_threshold P (the problem's
        # weights, their stated meaning), the easiest-to-turn end on a tie
        w_ = np.asarray(weights, float)
        with np.errstate(invalid="ignore"):
            j_last = w_[0] * fa + w_[1] * pa
            j_first = w_[0] * fb + w_[1] * pb
        end = np.where(j_first < j_last, first, last)
        pick = np.where(small, end, knee)
        choice = np.where(has, order[rows, pick], -1)
    member = np.zeros((n, s), bool)
    np.put_along_axis(member, order, front, axis=1)
    return {
        "choice": choice,
        "easiest_turn": easiest_turn,
        "easiest_sill": easiest_sill,
        "best_j": best_j,
        "front_size": size,
        "over_cap": over_cap,
        "front": member,
    }


def rule_text(problem, front_size: int) -> str:
    """The rule in words (what ``Recommendation.rule`` says)."""
    if problem.max_threshold_force is not None:
        return RULES["cap_threshold"].format(cap=problem.max_threshold_force)
    if problem.max_turning_effort is not None:
        return RULES["cap_turning"].format(cap=problem.max_turning_effort)
    return RULES["knee"] if front_size >= 3 else RULES["end"].format(w0=problem.weights[0], w1=problem.weights[1])


def weights_meaning(weights) -> str:
    """What the weights of J = w_turn F_turn + w_threshold P mean, in one sentence."""
    w_turn, w_threshold = (float(x) for x in weights)
    if w_turn == 0:
        return "J = P: the weights ignore turning effort"
    return (
        f"J = {w_turn:g} F_turn + {w_threshold:g} P: 1 N of sill force is worth {w_threshold / w_turn:g} N "
        f"of turning effort"
    )


# --------------------------------------------------------------------------- the recommendation


@dataclass
class Recommendation:
    """One caster to build, its numbers, and the fronts behind it (SI units).

    Attributes
    ----------
    design : the caster (trail, diameter, groove, damping)
    turning_effort : F_turn [N] (Eq. 9 with the turning model)
    threshold_force : P, force to climb the sill [N] (Eq. 4A)
    critical_speed : V_c of Eq. 7 [m/s]
    confident_speed : the speed reached with probability 1 − α, V_q [m/s]
    shimmy_probability : P(V_c,true < V_target) by Monte Carlo (own seed) [-]
    shimmy_probability_se : its standard error [-]
    swept_radius : T + d/2 [m]
    swept_radius_max : the footrest limit [m] (None: no limit)
    rule : how it was chosen
    alternatives : [easiest to turn, easiest over the sill] (the same record type; fewer if the front is short)
    buildable : the buildable risk-bounded front (a :class:`designer.analysis.pareto.Front`)
    front : the continuous risk-bounded front (computed on first access)
    wheel : the wheel's name (catalogue) or None
    inertia : I_w [kg·m²]
    role : "recommended" | "easiest to turn" | "easiest over the sill"
    note : what to know (e.g. a short front)
    """

    design: Design
    turning_effort: float
    threshold_force: float
    critical_speed: float
    confident_speed: float
    shimmy_probability: float
    shimmy_probability_se: float
    swept_radius: float
    swept_radius_max: float | None
    rule: str
    alternatives: list = field(default_factory=list)
    buildable: object = None
    wheel: str | None = None
    inertia: float = math.nan
    role: str = "recommended"
    note: str = ""
    target_speed: float = math.nan
    required_speed: float = math.nan
    alpha: float | None = None
    mc_samples: int = 0
    mc_seed: int = 0
    weights: tuple = (1.0, 1.0)
    problem: object = field(default=None, repr=False)
    _front: object = field(default=None, repr=False)

    @property
    def front(self):
        """The continuous risk-bounded front of the problem (:func:`designer.analysis.pareto.pareto_front`)."""
        if self._front is None and self.problem is not None:
            # late import: loads casadi (via designer.analysis.pareto) only when this runs
            from designer.analysis.pareto import pareto_front

            self._front = pareto_front(self.problem)
        return self._front

    def to_dict(self, alternatives: bool = False) -> dict:
        """The JSON record of ``designer run --json`` (SI)."""
        out = {
            "design": self.design.as_dict(),
            "turning_effort": self.turning_effort,
            "threshold_force": self.threshold_force,
            "critical_speed": self.critical_speed,
            "confident_speed": self.confident_speed,
            "shimmy_probability": self.shimmy_probability,
            "shimmy_probability_se": self.shimmy_probability_se,
            "swept_radius": self.swept_radius,
            "swept_radius_max": self.swept_radius_max,
            "rule": self.rule,
            "role": self.role,
            "wheel": self.wheel,
        }
        if alternatives:
            out["alternatives"] = [a.to_dict() for a in self.alternatives]
        return out

    def lines(self) -> list[str]:
        """The caster as text lines (inches and SI)."""
        d = self.design
        risk = (
            f"P(shimmy at {self.target_speed:.3g} m/s) = {self.shimmy_probability:.2%} ± "
            f"{self.shimmy_probability_se:.2%} (Monte Carlo, {self.mc_samples} samples, seed {self.mc_seed})"
        )
        radius = (
            f"{self.swept_radius / INCH:.3f} in (limit {self.swept_radius_max / INCH:.3f} in)"
            if self.swept_radius_max is not None
            else f"{self.swept_radius / INCH:.3f} in (no limit)"
        )
        level = f"{1 - self.alpha:.0%}" if self.alpha is not None else "95% (default scatter; no risk bound)"
        return [
            f"  trail T             {d.trail / INCH:8.3f} in   {d.trail * 1000:8.2f} mm",
            f"  diameter d          {d.diameter / INCH:8.3f} in   {d.diameter * 1000:8.2f} mm"
            + (f"   wheel {self.wheel}" if self.wheel else ""),
            f"  groove B            {d.groove / INCH:8.3f} in   {d.groove * 1000:8.2f} mm",
            f"  damping c_f         {d.damping:8.3f} N·m/rad",
            f"  turning effort      {self.turning_effort:8.3f} N",
            f"  sill force          {self.threshold_force:8.3f} N",
            f"  V_c (Eq. 7)         {self.critical_speed:8.3f} m/s",
            f"  speed reached with probability {level}: {self.confident_speed:.3f} m/s "
            f"(required {self.required_speed:.3f})",
            f"  {risk}",
            f"  swept radius        {radius}",
        ]

    def __str__(self) -> str:
        p = self.problem
        head = [f"Build this caster for {p.name!r} ({self.rule}):" if p is not None else f"Build this ({self.rule}):"]
        out = head + self.lines()
        for alt in self.alternatives:
            out += ["", f"Alternative: {alt.role}"] + alt.lines()
        if self.note:
            out += ["", f"Note: {self.note}"]
        return "\n".join(out)

    def __repr__(self) -> str:
        """Two lines: the caster (inches) and its numbers; the rule and alternatives: ``print(rec)``."""
        d = self.design
        return (
            f"Recommendation({self.role}): T {d.trail / INCH:.3f} in, d {d.diameter / INCH:.3f} in, "
            f"B {d.groove / INCH:.3f} in, c_f {d.damping:.3g} N·m/rad\n"
            f"  F_turn {self.turning_effort:.4g} N, P {self.threshold_force:.4g} N, V_c {self.critical_speed:.4g} m/s, "
            f"P(shimmy) {self.shimmy_probability:.2%} ± {self.shimmy_probability_se:.2%}"
        )

    def draw(self, ax=None, sill_height: float | None = None):
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
        return plot_caster(
            d.trail,
            d.diameter,
            d.groove,
            h,
            self.swept_radius_max,
            title=f"{self.role} caster{name}: T {d.trail / INCH:.3f} in, d {d.diameter / INCH:.3f} in",
            ax=ax,
        )

    def _repr_html_(self) -> str:
        """The caster as a compact HTML table with units beside its drawing to scale (notebooks; no solver runs)."""
        d = self.design
        rows = ([("wheel", self.wheel, "")] if self.wheel else []) + [
            ("trail T", f"{d.trail / INCH:.3f} ({d.trail * 1000:.2f} mm)", "in"),
            ("diameter d", f"{d.diameter / INCH:.3f} ({d.diameter * 1000:.2f} mm)", "in"),
            ("groove B", f"{d.groove / INCH:.3f} ({d.groove * 1000:.2f} mm)", "in"),
            ("damping c_f", f"{d.damping:.4g}", "N·m/rad"),
            ("turning effort F_turn", f"{self.turning_effort:.4g}", "N"),
            ("sill force P", f"{self.threshold_force:.4g}", "N"),
            ("critical speed V_c (Eq. 7)", f"{self.critical_speed:.4g}", "m/s"),
            ("confident speed V_q", f"{self.confident_speed:.4g}", "m/s"),
            ("required speed", f"{self.required_speed:.4g}", "m/s"),
            ("P(shimmy) (Monte Carlo)", f"{self.shimmy_probability:.2%} ± {self.shimmy_probability_se:.2%}", ""),
            (
                "swept radius (limit)",
                f"{self.swept_radius * 1000:.1f}"
                + (f" ({self.swept_radius_max * 1000:.1f})" if self.swept_radius_max is not None else ""),
                "mm",
            ),
        ]
        drawing = ""
        if self.problem is not None:
            drawing = caster_svg(
                d.trail,
                d.diameter,
                d.groove,
                self.problem.conditions.threshold_height,
                self.swept_radius_max,
                scale=17.0,
                label=f"{self.role} caster",
            )
        title = f"Build this caster for {self.problem.name!r}" if self.problem is not None else "Build this caster"
        return html_table(
            f"{title} ({self.role})",
            rows,
            caption=self.rule + (f" Note: {self.note}" if self.note else ""),
            extra=drawing,
        )


@dataclass
class _Buildable:
    """The buildable candidates before the rule: arrays over candidates (all feasible)."""

    designs: np.ndarray  # (n, 4)
    inertia: np.ndarray
    wheel: np.ndarray
    turning_effort: np.ndarray
    threshold_force: np.ndarray
    critical_speed: np.ndarray
    design_speed: np.ndarray
    swept_radius: np.ndarray


def _discrete_buildable(problem) -> tuple[_Buildable, ScreenedTable]:
    t = candidate_table(problem)
    cand = t.candidates
    k = t.feasible
    designs = np.column_stack([cand.trail, cand.diameter, cand.groove, cand.damping])[k]
    return _Buildable(
        designs,
        cand.inertia[k],
        cand.wheel[k],
        t.turning_effort[k],
        t.threshold_force[k],
        t.critical_speed[k],
        t.design_speed[k],
        t.swept_radius[k],
    ), t


def _sub_problem(problem, row: dict, inertia, wheel):
    """The problem with one stock combination's parts fixed (the rest continuous)."""

    bounds = dict(problem.bounds)
    for name, value in row.items():
        if value is not None:
            bounds[name] = Bound(value, value)
    conditions = problem.conditions
    if row["diameter"] is not None and inertia is not None and (wheel or problem.wheels):
        conditions = conditions.replace(inertia=Fixed(float(inertia)))
    return dataclasses.replace(problem, bounds=bounds, conditions=conditions, wheels=(), stock=None, source=None)


def _continuous_buildable(problem) -> _Buildable:
    """Each stock combination's continuous rest solved exactly (NLP), then pooled."""
    # late import: loads casadi (via designer.analysis.pareto) only when this runs
    from designer.analysis.pareto import pareto_front

    cand = stock_candidates(problem)
    rows = []
    for j in range(len(cand)):
        row = cand.design(j)
        inertia = None if cand.inertia is None else float(cand.inertia[j])
        sub = _sub_problem(problem, row, inertia, cand.wheel[j])
        points = 2 if row["diameter"] is not None else min(21, problem.pareto_points)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                front = pareto_front(sub, points=points)
        except InfeasibleError:
            continue
        for pt in front:
            rows.append((pt.design.as_array(), float(sub.conditions.inertia(pt.design.diameter)), cand.wheel[j]))
    if not rows:
        empty = np.zeros(0)
        return _Buildable(np.zeros((0, 4)), empty, np.zeros(0, dtype=object), empty, empty, empty, empty, empty)
    x = np.array([r[0] for r in rows])
    inertia = np.array([r[1] for r in rows])
    c = problem.conditions
    v = critical_shimmy_speed(x[:, 0], inertia, x[:, 2], x[:, 3], c.slip_coefficient)
    q = np.asarray(confident_speed(x[:, 0], inertia, x[:, 2], x[:, 3], c.slip_coefficient, problem.risk), float)
    f, p = objectives(problem, x[:, 0], x[:, 1], x[:, 2], x[:, 3])
    r = swept_radius(x[:, 0], x[:, 1])
    return _Buildable(
        x,
        inertia,
        np.array([r_[2] for r_ in rows], dtype=object),
        np.asarray(f, float),
        np.asarray(p, float),
        np.asarray(v, float),
        q,
        np.asarray(r, float),
    )


def _infeasible_message(problem, table: ScreenedTable | None) -> str:
    """Exit-4 text: the closest stock combination and what to relax."""
    risk = problem.risk
    bound = (
        f"P(shimmy below {problem.required_speed:.3g} m/s) <= {risk.probability:g}"
        if risk is not None
        else f"V_c >= {problem.required_speed:.3g} m/s"
    )
    if table is None or not len(table.candidates):
        return (
            f"{problem.name}: no stock combination meets the risk bound {bound}; relax the stock "
            f"(more groove, stronger friction washers, longer fork holes), robust.probability or "
            f"shimmy.target_speed"
        )
    cand = table.candidates
    ratio = table.design_speed / problem.required_speed
    pool = np.flatnonzero(table.radius_ok & np.isfinite(table.threshold_force))
    if not len(pool):
        j = int(np.argmin(table.swept_radius))
        return (
            f"{problem.name}: no stock combination fits the swept radius {problem.swept_radius_max / INCH:.3f} in; "
            f"the smallest is {table.swept_radius[j] / INCH:.3f} in (T + d/2); relax "
            f"constraints.swept_radius_max or stock smaller wheels or shorter fork holes"
        )
    j = int(pool[np.argmax(ratio[pool])])
    d = cand.design(j)
    relax = []
    if d["groove"] >= cand.groove.max() * (1 - 1e-12) and problem.bounds["groove"].high > 0:
        relax.append("a wider groove (stock.grooves)")
    if d["damping"] >= cand.damping.max() * (1 - 1e-12):
        relax.append("a stronger friction washer (stock.dampings)")
    if d["trail"] >= cand.trail.max() * (1 - 1e-12):
        relax.append(
            "a longer fork (variables.trail.max)"
            if problem.swept_radius_max is None or table.swept_radius[j] < problem.swept_radius_max * (1 - 1e-9)
            else "a larger swept radius (constraints.swept_radius_max)"
        )
    relax.append(
        "a smaller wheel (lighter: less inertia)" if d["diameter"] > cand.diameter.min() else "a lighter wheel"
    )
    relax.append(f"robust.probability (now {risk.probability:g})" if risk is not None else "shimmy.margin")
    relax.append("shimmy.target_speed")
    wheel = f" (wheel {cand.wheel[j]})" if cand.wheel[j] else ""
    return (
        f"{problem.name}: no stock combination meets the risk bound {bound}; the closest is "
        f"T = {d['trail'] / INCH:.3f} in, d = {d['diameter'] / INCH:.3f} in{wheel}, B = {d['groove'] / INCH:.3f} in, "
        f"c_f = {d['damping']:.3g} N·m/rad, reaching {table.design_speed[j]:.3f} m/s with probability "
        f"{1 - (risk.probability if risk is not None else 0):.0%} (needs {problem.required_speed:.3f}); relax: "
        + ", ".join(relax)
    )


def _record(problem, b: _Buildable, i: int, rule: str, role: str, samples=None, seed=None) -> Recommendation:
    u = problem.risk if problem.risk is not None else Uncertainty()
    x = b.designs[i]
    c = problem.conditions
    p, se = shimmy_probability_mc(
        float(x[0]),
        float(b.inertia[i]),
        float(x[2]),
        float(x[3]),
        c.slip_coefficient,
        problem.target_speed,
        u,
        samples=samples,
        seed=seed,
    )
    n = max(
        int(u.samples if samples is None else samples), math.ceil(max(p * (1 - p), 1e-12) / 0.001**2) if p > 0 else 0
    )
    q = (
        b.design_speed[i]
        if problem.risk is not None
        else float(shimmy_speed_quantile(x[0], b.inertia[i], x[2], x[3], c.slip_coefficient, u))
    )
    return Recommendation(
        design=Design.from_array(x),
        turning_effort=float(b.turning_effort[i]),
        threshold_force=float(b.threshold_force[i]),
        critical_speed=float(b.critical_speed[i]),
        confident_speed=float(q),
        shimmy_probability=p,
        shimmy_probability_se=se,
        swept_radius=float(b.swept_radius[i]),
        swept_radius_max=problem.swept_radius_max,
        rule=rule,
        wheel=str(b.wheel[i]) or None,
        inertia=float(b.inertia[i]),
        role=role,
        target_speed=problem.target_speed,
        required_speed=problem.required_speed,
        alpha=None if problem.risk is None else problem.risk.probability,
        mc_samples=n,
        mc_seed=int(u.seed if seed is None else seed),
        weights=tuple(problem.weights),
        problem=problem,
    )


def _buildable_front(problem, b: _Buildable, member: np.ndarray):
    """The buildable front as a :class:`designer.analysis.pareto.Front` (decreasing P)."""
    # late import: loads casadi (via designer.analysis.pareto) only when this runs
    from designer.analysis.pareto import Front, FrontPoint, family_of

    idx = np.flatnonzero(member)
    idx = idx[np.argsort(-b.threshold_force[idx], kind="stable")]
    points = []
    for i in idx:
        d = Design.from_array(b.designs[i])
        points.append(
            FrontPoint(
                d,
                float(b.turning_effort[i]),
                float(b.threshold_force[i]),
                float(b.critical_speed[i]),
                {"shimmy": float(b.design_speed[i] - problem.required_speed)},
                float(b.threshold_force[i]),
                "stock",
                True,
                {},
                family_of(problem, d),
                str(b.wheel[i]) or None,
            )
        )
    return Front(
        problem, points, [], {"method": "exhaustive over the stock; continuous rest solved exactly", "buildable": True}
    )


def recommend(problem, samples: int | None = None, seed: int | None = None) -> Recommendation:
    """``designer.recommend``: the caster to build for ``problem``, by the problem's rule.

    Parameters
    ----------
    problem : a :class:`designer.problem.Problem` or a path to a problem file
    samples, seed : Monte Carlo sample (a minimum) and seed of the reported P(shimmy) (default the
        problem's ``[robust]`` ones: 50 000, seed 20111)

    Returns
    -------
    Recommendation (with two alternatives, the buildable front and, on access, the continuous front)

    Raises
    ------
    InfeasibleError (exit 4)
        No stock combination meets the risk bound (the message names the closest and what to relax),
        or none is within the cap of ``[objective]``.
    """

    if isinstance(problem, (str, Path)):
        problem = load_problem(problem)
    table = None
    if stock_candidates(problem).discrete:
        b, table = _discrete_buildable(problem)
    else:
        b = _continuous_buildable(problem)
    if not len(b.turning_effort):
        # late import: loads casadi, cvxpy, jinja2, scipy (via designer.analysis.optimise) only when this runs
        from designer.analysis.optimise import _diagnose

        error = _diagnose(problem)  # out of reach of the whole box: that is the message, not the stock's
        if isinstance(error, InfeasibleError):
            raise error
        raise InfeasibleError(_infeasible_message(problem, table))
    sel = select_rows(
        b.turning_effort[None, :],
        b.threshold_force[None, :],
        np.ones((1, len(b.turning_effort)), bool),
        problem.weights,
        problem.max_threshold_force,
        problem.max_turning_effort,
    )
    size = int(sel["front_size"][0])
    choice = int(sel["choice"][0])
    if choice < 0:
        cap = (
            f"objective.max_threshold_force = {problem.max_threshold_force:.1f} N"
            if problem.max_threshold_force is not None
            else f"objective.max_turning_effort = {problem.max_turning_effort:.2f} N"
        )
        lo = int(sel["easiest_sill"][0]) if problem.max_threshold_force is not None else int(sel["easiest_turn"][0])
        best = (
            f"the least sill force buildable is {b.threshold_force[lo]:.2f} N"
            if problem.max_threshold_force is not None
            else f"the least turning effort buildable is {b.turning_effort[lo]:.3f} N"
        )
        raise InfeasibleError(
            f"{problem.name}: no buildable caster within the risk bound meets {cap}; {best}; "
            f"raise the cap or widen the stock"
        )
    rule = rule_text(problem, size)
    rec = _record(problem, b, choice, rule, "recommended", samples, seed)
    rec.buildable = _buildable_front(problem, b, sel["front"][0])
    alts = []
    for key, role in (("easiest_turn", "easiest to turn"), ("easiest_sill", "easiest over the sill")):
        i = int(sel[key][0])
        if i >= 0 and i != choice:  # a short front: give what there is, not the same caster twice
            alts.append(_record(problem, b, i, rule, role, samples, seed))
    rec.alternatives = alts
    notes = []
    if size < 3:
        notes.append(
            f"the buildable front has {size} point{'s' if size != 1 else ''}: "
            + (
                "the recommendation is the one with the least J (weights: "
                + weights_meaning(problem.weights)
                + ") and the only alternative the other end"
                if size == 2
                else "one stock caster is best on both objectives, so there is no alternative"
            )
        )
    if problem.risk is None:
        notes.append(
            f"no risk bound ([robust] enabled = false): this caster shimmies at {problem.target_speed:.3g} m/s "
            f"with probability {rec.shimmy_probability:.1%} ± {rec.shimmy_probability_se:.1%} under the "
            f"default scatter"
        )
    rec.note = "; ".join(notes)
    return rec
