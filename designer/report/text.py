"""The report's sentences, each generated from the data it states (tests assert them against the data).

:func:`build_lines` writes the "Build this" paragraph of the first screen from the
:class:`~designer.studies.recommend._recommend.Recommendation`; :func:`summary_lines` the bullet list under it;
:func:`weights_line` what the weighted optimum is and is not.  Nothing here computes a design.
"""

from __future__ import annotations

import numpy as np

from designer.display import label, number, percent, quantity, shown
from designer.data.paper import BARE_FORK_DAMPING
from designer.report.formatting import size
from designer.model import weighted_terms

DOMINANCE = 5.0
"""A weighted term this many times the other one dominates J (the report then says so)."""
AT_END = 0.01
"""A weighted optimum within this fraction of the front's P (or F_turn) range from an end is "at" that end."""
OBJECTIVES = ("turning_effort", "threshold_force")
"""The two objectives, in the order of ``Front.objectives()``'s columns and of the weights."""
ACTIVE_REL = 1e-6
"""A design with V_c within this relative distance of V_req sits on the shimmy constraint."""


def caster_sentence(rec, units: str = "in") -> str:
    """What to build, in words, sizes as the user writes them (``units``: "in" to 1/16, "mm" to 0.1):
    "a 7 in wheel with a 1/2 in groove in a fork of 2 1/2 in trail, on the bare fork's bearing (no friction
    washer)"."""
    d = rec.design
    wheel = f" ({rec.wheel})" if getattr(rec, "wheel", None) else ""
    wheel_size = size(d.diameter, units)
    article = "an" if wheel_size.startswith(("8", "11", "18", "≈ 8", "≈ 11", "≈ 18")) else "a"
    groove = "a plain tyre (no groove)" if d.groove <= 1e-9 else f"a {size(d.groove, units)} groove"
    damping = "on the bare fork's bearing (no friction washer)"
    if d.damping > BARE_FORK_DAMPING * (1 + 1e-6):
        damping = f"with a friction washer giving c_f = {shown(d.damping, 'damping')}"
    return f"{article} {wheel_size} wheel{wheel} with {groove} in a fork of {size(d.trail, units)} trail, {damping}"


PLAIN_RULES = {
    "knee": "the best balance between turning and the sill among {what}",
    "cap_threshold": "the easiest to turn among {what} that climb the sill with at most {cap}",
    "cap_turning": "the easiest over the sill among {what} that turn with at most {cap}",
    "end": "the best of the few casters {what} allow ({j})",
    "concave": "the lowest combined force among {what} ({j})",
}
"""The recommendation's rule in plain words, by kind (the precise rule: docs/model.md#the-recommendation)."""


def combined_force(weights) -> str:
    """What the problem's weights add up, in words: "turning effort plus sill force, a newton of each counted
    alike" for (1, 1); "2 × turning effort + 1 × sill force, the problem's weights" otherwise."""
    w0, w1 = (float(w) for w in weights)
    if w0 == w1:
        return "turning effort plus sill force, a newton of each counted alike"
    return f"{w0:g} × turning effort + {w1:g} × sill force, the problem's weights"


def plain_rule(problem, rec) -> str:
    """How the caster was chosen, in plain words: "the best balance between turning and the sill among the
    parts you can buy" for the knee of the buildable front (``[stock]``; "the sizes allowed" without one)."""
    what = "the parts you can buy" if getattr(problem, "stock", None) is not None else "the sizes allowed"
    if problem.max_threshold_force is not None:
        return PLAIN_RULES["cap_threshold"].format(what=what, cap=shown(problem.max_threshold_force, "threshold_force"))
    if problem.max_turning_effort is not None:
        return PLAIN_RULES["cap_turning"].format(what=what, cap=shown(problem.max_turning_effort, "turning_effort"))
    if rec.rule.startswith("knee"):
        return PLAIN_RULES["knee"].format(what=what)
    j = combined_force(problem.weights)
    if rec.rule.startswith("least J") and "has no knee" in rec.rule:
        return PLAIN_RULES["concave"].format(what=what, j=j)
    if rec.rule.startswith("least J"):
        return PLAIN_RULES["end"].format(what="the parts" if problem.stock is not None else "the sizes", j=j)
    return f"chosen by the rule: {rec.rule}"


def lead_sentence(data) -> str:
    """The first screen's first sentence, in plain words: why this caster, the two forces and the risk: "The
    lowest combined force among the parts you can buy (...): it turns with 7.9 N of effort and climbs the 1/2 in
    sill with 107 N; at 2.5 m/s it shimmies with probability 2.98 % (the bound is 5 %)."."""
    problem, rec = data.problem, data.recommendation
    units = getattr(problem, "units", "in")
    forces = (
        f"it turns with {shown(rec.turning_effort, 'turning_effort')} of effort and climbs the "
        f"{size(problem.conditions.threshold_height, units)} sill with {shown(rec.threshold_force, 'threshold_force')}"
    )
    if rec.alpha is None:
        risk = f"no risk bound is set (Eq. 7 alone: stable to {shown(rec.critical_speed, 'critical_speed')})"
    else:
        risk = (
            f"at {shown(rec.target_speed, 'target_speed')} it shimmies with probability "
            f"{percent(rec.shimmy_probability)} (the bound is {percent(rec.alpha)})"
        )
    text = plain_rule(problem, rec)
    return f"{text[0].upper()}{text[1:]}: {forces}; {risk}."


def _count(n: int, noun: str) -> str:
    """``n`` and ``noun``, plural unless ``n`` is 1 ("1 caster", "3 casters")."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def front_count_sentence(rec) -> str:
    """How many casters the buildable front has and how many are shown beside the caster to build, counted from
    ``rec`` (its buildable front when it has one, else itself and its alternatives): "The buildable front has 3
    casters: the caster to build (first row) and the 2 others, by turning effort."."""
    shown = len(rec.alternatives)
    front = getattr(rec, "buildable", None)
    total = len(front.points) if front is not None else 1 + shown
    others = "the other" if shown == 1 else f"the {shown} others"
    tail = "" if shown < 2 else ", by turning effort"
    if shown == 0:
        return f"The buildable front has {_count(total, 'caster')}: the caster to build."
    return f"The buildable front has {_count(total, 'caster')}: the caster to build (first row) and {others}{tail}."


def risk_sentence(rec) -> str:
    """The shimmy risk of ``rec``: the bound it meets (or that it has none) and the Monte Carlo estimate."""
    mc = (
        f"P(shimmy at {shown(rec.target_speed, 'target_speed')}) = {percent(rec.shimmy_probability)} by the exact law "
        f"(its Monte Carlo: {percent(rec.shimmy_probability_mc)} ± {percent(rec.shimmy_probability_se)}, "
        f"{rec.mc_samples:,} draws, seed {rec.mc_seed})"
    )
    v_c = shown(rec.critical_speed, "critical_speed")
    if rec.alpha is None:
        return (
            f"No risk bound ([robust] enabled = false): by Eq. 7 it is stable to V_c = {v_c}, "
            f"but under the default scatter of the model it has {mc}."
        )
    within = rec.shimmy_probability <= rec.alpha
    return (
        f"With probability {percent(1 - rec.alpha)} it stays free of shimmy up to "
        f"{shown(rec.confident_speed, 'confident_speed')} (needed: {shown(rec.required_speed, 'critical_speed')}; "
        f"Eq. 7 alone gives V_c = {v_c}); {mc}, "
        + ("within" if within else "ABOVE")
        + f" the bound α = {percent(rec.alpha)}."
    )


def radius_sentence(rec, units: str = "in") -> str:
    """The swept radius against the footrest limit (sizes in ``units``)."""
    if rec.swept_radius_max is None:
        return (
            f"It sweeps a circle of radius T + d/2 = {size(rec.swept_radius, units)} (the problem sets no "
            "footrest limit)."
        )
    spare = rec.swept_radius_max - rec.swept_radius
    return (
        f"It sweeps a circle of radius T + d/2 = {size(rec.swept_radius, units)} against the footrest limit "
        f"{size(rec.swept_radius_max, units)} ("
        + (f"{size(spare, units)} to spare" if spare > 1e-9 else "at the limit")
        + ")."
    )


def stock_sentence(price: dict | None, has_stock: bool) -> str:
    """The price of stock: the buildable caster's turning effort against the continuous front at equal sill force."""
    if not has_stock:
        return (
            "The problem declares no [stock]: every size is continuous, so the caster is a point of the "
            "continuous front and its sizes are not rounded to parts."
        )
    if price is None:
        return (
            "The continuous front does not reach the recommendation's sill force, so the price of stock is not "
            "read off here (see the front figure)."
        )
    parts = []
    if abs(price["extra"]) >= 5e-4:
        parts.append(
            f"{price['extra']:+.3f} N ({price['relative']:+.1%}) of turning effort at its sill force "
            f"{shown(price['threshold_force'], 'threshold_force')} (continuous front: "
            f"{shown(price['turning_effort_continuous'], 'turning_effort')})"
        )
    extra_p = price.get("extra_threshold")
    if extra_p is not None and abs(extra_p) >= 5e-3:
        parts.append(
            f"{extra_p:+.2f} N of sill force at its turning effort "
            f"{shown(price['turning_effort_buildable'], 'turning_effort')} (continuous front: "
            f"{shown(price['threshold_force_continuous'], 'threshold_force')})"
        )
    if not parts:
        return "Buying parts costs nothing here: this stock caster lies on the continuous front."
    return "What buying parts costs against any sizes (the continuous front): " + "; ".join(parts) + "."


def build_lines(data) -> list[str]:
    """The "Build this" details under the lead sentence (empty without a recommendation): the forces and the
    risk in full, the swept radius, then the rule by its precise name (the lead said it in plain words)."""
    rec = data.recommendation
    if rec is None:
        return []
    problem = data.problem
    units = getattr(problem, "units", "in")
    out = [
        f"Turning effort F_turn = {shown(rec.turning_effort, 'turning_effort')}; sill force over the "
        f"{size(problem.conditions.threshold_height, units)} sill P = {shown(rec.threshold_force, 'threshold_force')}.",
        risk_sentence(rec),
        radius_sentence(rec, units),
    ]
    if getattr(rec, "note", ""):
        out.append(f"Note: {rec.note}.")
    out.append(f"The rule by its name: {rec.rule} (see Terms).")
    return out


def weights_line(problem, solution, front) -> str:
    """What the weighted optimum is, with the weights' meaning; says when one term dominates and where it sits."""
    s = solution
    w = problem.weights
    f_opt, p_opt = s.objectives["turning_effort"], s.objectives["threshold_force"]
    meaning = (
        f"J = {w[0]:g} F_turn + {w[1]:g} P: 1 N of sill force is worth {w[1] / w[0]:g} N of turning effort"
        if w[0] > 0
        else f"J = {w[1]:g} P: the weights ignore turning effort"
    )
    wheel = f" (Table 1 wheel {s.wheel})" if s.wheel else ""
    line = (
        f"Weighted optimum{wheel} of {meaning}: {s.design.describe()}; F_turn {shown(f_opt, 'turning_effort')}, "
        f"P {shown(p_opt, 'threshold_force')}, V_c {shown(s.critical_speed, 'critical_speed')}."
    )
    f_part, p_part = weighted_terms(f_opt, p_opt, w)
    if min(f_part, p_part) > 0 and max(f_part, p_part) > DOMINANCE * min(f_part, p_part):
        k = int(p_part > f_part)  # the objective J mostly follows: 0 turning effort, 1 sill force
        big, small = OBJECTIVES[k], OBJECTIVES[1 - k]
        name = quantity(big).symbol
        line += (
            f" Here the {quantity(big).description} term is {max(f_part, p_part) / min(f_part, p_part):.0f}× the "
            f"{quantity(small).description} term, so J mostly follows {name}"
        )
        if len(front.points) >= 2:
            values = front.objectives()[:, k]
            lo, hi = float(values.min()), float(values.max())
            frac = ((f_opt, p_opt)[k] - lo) / (hi - lo) if hi > lo else 0.0
            if frac <= AT_END:
                line += f": the optimum is the least-{name} end of the front ({name} = {shown(lo, big)})"
            else:
                line += (
                    f", yet the optimum is not the least-{name} end: its {name} is {frac:.0%} of the front's "
                    f"{name} range above the least ({shown(lo, big)})"
                )
        line += ". It is not the recommendation; scale the weights or cap one objective ([objective]) to change it."
    return line


def margin_line(problem, front) -> str:
    """For a nominal problem with no margin: how many front designs sit on V_c = V_req, and why that is thin."""
    if not front.points or problem.margin != 0 or problem.conditions.uncertainty is not None:
        return ""
    v = np.array([p.critical_speed for p in front.points])
    on = int(np.sum(np.abs(v / problem.required_speed - 1) <= ACTIVE_REL))
    n = len(v)
    where = "every front design sits" if on == n else f"{on} of {n} front designs sit" if on else "no front design sits"
    tail = "" if on == n else f" (the others are stable beyond it: V_c up to {shown(v.max(), 'critical_speed')})"
    return (
        f"No risk bound and no safety margin: {where} exactly at V_c = V_req = "
        f"{shown(problem.required_speed, 'critical_speed')} "
        f"of Eq. 7{tail}. Eq. 7 matched Table 1's measured critical speeds only to RMS 10.3 % (worst −16 %); "
        f"set [robust] (the default) or shimmy.margin before building a caster."
    )


def summary_lines(data) -> list[str]:
    """The bullets under "Build this": the front, the margin, the weighted optimum, the checks."""
    problem, front = data.problem, data.front
    out = []
    if front.points:
        d = np.array([p.design.diameter for p in front.points])
        kind = "within the risk bound" if problem.conditions.uncertainty is not None else "without a risk bound"
        ranges = ", ".join(
            f"{label(name)} {number(v.min(), name)}–{shown(v.max(), name)}"
            for name, v in zip(("turning_effort", "threshold_force"), front.objectives().T)
        )
        out.append(
            f"With any sizes, not only the parts (the continuous front, {kind}): {_count(len(front), 'valid point')} "
            f"(of {front.meta.get('points_requested', len(front))} requested, {len(front.failed)} failed): {ranges}, "
            f"wheel diameter {size(d.min(), problem.units)}–{size(d.max(), problem.units)}."
        )
    if data.recommendation is not None:
        out.append(stock_sentence(data.price_of_stock, getattr(problem, "stock", None) is not None))
    line = margin_line(problem, front)
    if line:
        out.append(line)
    if data.solution is not None:
        out.append(weights_line(problem, data.solution, front))
    checks = data.checks
    failed = [c.name for c in checks if not c.passed]
    out.append(
        f"Checks: {len(checks) - len(failed)} of {len(checks)} pass"
        + (f"; failing: {', '.join(failed)}." if failed else ".")
    )
    if not data.cross_checked:
        out.append(
            f"The solver cross-check (geometric program and SLSQP against the NLP) is not part of this run; "
            f"run `{data.cross_check_command}` for it."
        )
    return out


__all__ = [
    "build_lines",
    "caster_sentence",
    "lead_sentence",
    "plain_rule",
    "margin_line",
    "radius_sentence",
    "risk_sentence",
    "stock_sentence",
    "summary_lines",
    "weights_line",
]
