"""``designer run PROBLEM``: the caster to build (the recommendation, first), then the weighted optimum of the
problem as posed with margins, sensitivities and solver agreement."""

from __future__ import annotations

import designer
from designer.cli._terminal import fit
from designer.cli._common import PROBLEM_HELP, eprint, part_text, print_json, ranged_option
from designer.errors import InputError
from designer import load_problem, recommend
from designer.problem import check_weights
from designer.studies.recommend import weights_meaning
from designer.units import written_size
from designer.display import label, percent, quantity, shown
from designer.report.text import caster_sentence, plain_rule


def register(sub) -> None:
    p = sub.add_parser(
        "run",
        help="the caster to build for a problem file, in one screen",
        description="The caster to build for a problem file, in one screen: what it is, why (the rule in plain "
        "words: the best balance between turning and the sill among the parts you can buy, or the lowest combined "
        "force), what it costs, the other casters of the trade-off and what to do next. --verbose adds each "
        "caster in full with its acceptance limits, and the weighted optimum of J = w_turn F_turn + w_threshold P "
        "under the same risk bound (multi-start IPOPT, cross-checked by a geometric program and SLSQP).",
    )
    p.add_argument("problem", help=PROBLEM_HELP)
    p.add_argument("--weights", default=None, help="w_turn,w_threshold (default: the problem's [objective])")
    p.add_argument("--target-speed", default=None, help="override shimmy.target_speed, e.g. 3m/s")
    p.add_argument("--no-cross-check", action="store_true", help="skip the GP and SLSQP cross-checks")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument(
        "--verbose",
        action="store_true",
        help="the details: each caster in full, the weighted optimum, the solvers' agreement and times",
    )
    p.set_defaults(func=run)


def parse_weights(text: str | None):
    """Parse "a,b" into two non-negative floats, not both zero (:func:`designer.problem.check_weights`)."""
    if text is None:
        return None
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise InputError(f"--weights {text!r}: expected two numbers 'w_turn,w_threshold', e.g. 1,1") from None
    if len(values) != 2:
        raise InputError(f"--weights {text}: expected two numbers 'w_turn,w_threshold', e.g. 1,1; got {len(values)}")
    return check_weights(values, "--weights", error=InputError)  # finite, non-negative, not both zero


def conditions_line(problem) -> str:
    """What the answer was computed for, in one line: the load per front caster (from ``load``, or from ``mass``
    and ``front_fraction``: L = m g f / 2), the sill, the floor and the turning mode."""
    c = problem.conditions
    return (
        f"For {shown(c.load, 'load', problem.units)} per front caster, a "
        f"{written_size(c.threshold_height, problem.units)} sill, "
        f"{c.surface} floor, {c.turning_mode} turning:"
    )


ROLES = {
    "easiest to turn": "easiest to turn",
    "between the ends": "in between",
    "easiest over the sill": "lightest over the sill",
}
"""What each other caster of the trade-off is for, as the first screen names it (the record's ``role``)."""

SOURCES = {
    "model error": "Eq. 7's own error against the paper's measured wheels",
    "wheel inertia (diameter only)": "the wheel's inertia, known from its size only",
    "wheel inertia (measured)": "the scatter of the measured wheel's inertia",
    "M_f/θ0": "the scatter of the bearing friction",
    "K_s": "the scatter of the tyre's slip",
}
"""Where the risk comes from, in plain words (``Recommendation.risk["sources"]`` names)."""


def caster_line(design, units: str) -> str:
    """The four parts by their symbols, in the problem's units: "T 2.500 in, d 7.000 in, ..." (``design``: a
    Design, or its dict)."""
    values = design if isinstance(design, dict) else design.to_dict()
    return ", ".join(symbol_shown(values[n], n, units) for n in ("trail", "diameter", "groove", "damping"))


def cost_sentence(problem, rec) -> str:
    """What the caster costs the user: the two forces, the shimmy risk, the footrests' room."""
    units = problem.units
    out = (
        f"Cost: {label('turning_effort')} {shown(rec.turning_effort, 'turning_effort', units)}, "
        f"{label('threshold_force')} {shown(rec.threshold_force, 'threshold_force', units)}"
    )
    if rec.alpha is not None:
        out += (
            f"; P(shimmy) at {shown(rec.target_speed, 'target_speed', units, digits=1)} "
            f"{percent(rec.shimmy_probability)} (allowed {percent(rec.alpha)})"
        )
    if rec.swept_radius_max is not None:
        out += (
            f"; it sweeps {written_size(rec.swept_radius, units)} of the "
            f"{written_size(rec.swept_radius_max, units)} the footrests allow"
        )
    return out + "."


def risk_sentence(problem, rec) -> str:
    """Where the risk comes from and what measuring the wheel would allow, in one or two plain sentences."""
    units = problem.units
    out = ""
    if rec.risk is not None and rec.risk.get("sources"):
        top = max(rec.risk["sources"], key=lambda src: src["share"])
        out = f"Most of the risk ({percent(top['share'])}) comes from {SOURCES.get(top['name'], top['name'])}."
    m = rec.if_measured
    if m is not None:
        md, d = m["design"], rec.design
        changes = [
            part_text(md[n], n, units)
            for n in ("diameter", "trail", "groove", "damping")
            if abs(md[n] - getattr(d, n)) > 1e-12
        ]
        limit = shown(m["inertia"], "inertia", units)
        if not changes:
            out += f" A wheel measured at or under {limit} changes no part."
        else:
            gains = [
                f"{shown(abs(m[key]), 'turning_effort', units, digits=1)} {easier if m[key] > 0 else harder}"
                for key, easier, harder in (
                    ("saves_turning_effort", "easier to turn", "harder to turn"),
                    ("saves_threshold_force", "easier over the sill", "harder over the sill"),
                )
                if abs(m[key]) >= 0.005
            ]
            out += (
                f" Measure the wheel: at or under {limit} it allows {', '.join(changes)}"
                + (f" ({' and '.join(gains)})" if gains else "")
                + "."
            )
    return out.strip()


def others_lines(problem, rec, most: int = 3) -> list[str]:
    """The other casters of the trade-off, each named by what it is for, with its two forces (at most ``most``:
    the two ends first; the rest counted)."""
    alts = [a for a in rec.alternatives if a.role in ROLES]
    if not alts:
        return []
    shown_alts = sorted(alts, key=lambda a: a.role == "between the ends")[:most]  # the ends first (a stable sort)
    shown_alts.sort(key=lambda a: a.turning_effort)
    units = problem.units
    out = ["Other casters on the trade-off:"]
    for a in shown_alts:
        d = a.design
        out.append(
            f"  {ROLES[a.role]}: {written_size(d.diameter, units)} wheel, T {written_size(d.trail, units)}, "
            f"B {written_size(d.groove, units)}: {symbol_shown(a.turning_effort, 'turning_effort', units)}, "
            f"{symbol_shown(a.threshold_force, 'threshold_force', units)}"
        )
    rest = len(alts) - len(shown_alts)
    if rest:
        out.append(f"  and {rest} more (--verbose)")
    return out


def symbol_shown(value: float, name: str, units: str) -> str:
    """A quantity by its symbol and value: "F_turn 7.01 N"."""
    return f"{quantity(name).symbol} {shown(value, name, units)}"


def answer(problem, rec) -> str:
    """The first screen of ``designer run``: the caster to build, why, what it costs, the others, what next."""
    units = problem.units
    name = problem.name
    out = [
        conditions_line(problem),
        f"The caster to build: {caster_sentence(rec, units)}.",
        "  " + caster_line(rec.design, units),
        f"Why: {plain_rule(problem, rec)}.",
        cost_sentence(problem, rec),
    ]
    risk = risk_sentence(problem, rec)
    if risk:
        out.append(risk)
    if rec.enforced is not None and rec.enforced["changed"]:
        out.append(
            "At the worst corner of the tolerances the first pick shimmied too often; this one holds there "
            "(--verbose: what it costs)."
        )
    if not rec.alternatives:
        out.append("No other caster you can build is better on either force.")
    out += others_lines(problem, rec)
    out.append(
        f"Next: designer spec {name} (the inspection sheet), designer pareto {name} (the report); "
        "--verbose: acceptance limits, the weighted optimum, the solvers' agreement."
    )
    return "\n".join(out)


def run(args) -> int:
    weights = parse_weights(args.weights)  # the options first: a bad one is named before the file is read
    speed = ranged_option(args.target_speed, "target_speed", "--target-speed")
    problem = load_problem(args.problem)
    if speed is not None:
        problem = problem.replace(target_speed=speed)
    rec = recommend(problem)  # exit 4 when no stock combination meets the risk bound
    used = [float(w) for w in (weights if weights is not None else problem.weights)]
    if not args.json and not args.verbose:
        text = answer(problem, rec)
        if args.weights is not None:
            text += (
                f"\n--weights {args.weights} sets the weighted optimum (--verbose shows it); the caster to build "
                "follows the problem's [objective]."
            )
        print(fit(text))  # at the terminal's width, never between a number and its unit
        return 0
    solution = designer.optimise(problem, weights, cross_check=not args.no_cross_check)
    if args.json:
        data = solution.to_dict()
        data["extrapolated"] = bool(solution.caster.extrapolated)
        data["recommendation"] = rec.to_dict()
        data["alternatives"] = [a.to_dict() for a in rec.alternatives]
        data["weights"] = used
        c = problem.conditions
        data["conditions"] = {
            "load_N": c.load,
            "threshold_height_m": c.threshold_height,
            "surface": c.surface,
            "turning_mode": c.turning_mode,
        }
        data["weights_meaning"] = weights_meaning(used)
        if rec.note:
            data["recommendation_note"] = rec.note
        print_json(data)
    else:
        text = "\n".join(
            [
                answer(problem, rec),
                "",
                "In full:",
                str(rec),
                "",
                f"Weighted optimum of the problem as posed, continuous and "
                f"{'risk-bounded' if problem.risk is not None else 'nominal'} ({weights_meaning(used)}):",
                str(solution),
            ]
        )
        print(fit(text))  # at the terminal's width, never between a number and its unit
    if args.verbose:
        t = solution.timings
        eprint(
            f"timing: NLP build {shown(t['build'], dimension='time')}, multi-start solve "
            f"{shown(t['solve'], dimension='time')} ({solution.starts} starts), cross-checks "
            f"{shown(t['cross_check'], dimension='time')}"
        )
    return 0
