"""``designer run PROBLEM``: the caster to build (the recommendation, first), then the weighted optimum of the
problem as posed with margins, sensitivities and solver agreement."""

from __future__ import annotations

import math
import shutil
import textwrap

from designer.cli._common import PROBLEM_HELP, eprint, print_json, ranged_option
from designer.errors import InputError
from designer.physics.scatter import inertia_prediction
from designer.studies.recommend import recommend, weights_meaning
from designer.problem import check_weights, load_problem
from designer.units import written_size


def register(sub) -> None:
    p = sub.add_parser(
        "run",
        help="the caster to build for a problem file, and its weighted optimum",
        description="Recommend one buildable caster within the risk bound (knee of the buildable "
        "front, or the cap of [objective]) with every other caster of the buildable front; then minimise "
        "J = w_turn F_turn + w_threshold P subject to the same bound: multi-start IPOPT, "
        "cross-checked by a geometric program (cvxpy) and SLSQP.",
    )
    p.add_argument("problem", help=PROBLEM_HELP)
    p.add_argument("--weights", default=None, help="w_turn,w_threshold (default: the problem's [objective])")
    p.add_argument("--target-speed", default=None, help="override shimmy.target_speed, e.g. 3m/s")
    p.add_argument("--no-cross-check", action="store_true", help="skip the GP and SLSQP cross-checks")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--verbose", action="store_true", help="print build and solve times")
    p.set_defaults(func=run)


def parse_weights(text: str | None):
    """Parse "a,b" into two non-negative floats, not both zero."""
    if text is None:
        return None
    parts = text.split(",")
    try:
        values = tuple(float(x) for x in parts)
    except ValueError:
        raise InputError(f"--weights {text!r}: expected two numbers 'w_turn,w_threshold', e.g. 1,1") from None
    if len(values) != 2:
        raise InputError(f"--weights {text}: expected two numbers 'w_turn,w_threshold', e.g. 1,1; got {len(values)}")
    for name, v in zip(("w_turn", "w_threshold"), values):
        if not math.isfinite(v) or v < 0:
            raise InputError(f"--weights {text}: {name} = {v:g} must be a finite non-negative number")
    if sum(values) <= 0:
        raise InputError(f"--weights {text}: the weights must not both be zero")

    return check_weights(values, "--weights", error=InputError)


def wrapped(text: str) -> str:
    """``text`` with every line wider than the terminal (``COLUMNS``; 80 when not a terminal) wrapped at word
    boundaries, its continuation indented two more than the line; narrower lines (the aligned tables) as they are."""
    width = max(40, shutil.get_terminal_size((80, 24)).columns)
    out = []
    for line in text.splitlines():
        if len(line) <= width:
            out.append(line)
            continue
        indent = " " * (len(line) - len(line.lstrip()))
        out.append(
            textwrap.fill(
                line.strip(),
                width,
                initial_indent=indent,
                subsequent_indent=indent + "  ",
                break_on_hyphens=False,
                break_long_words=False,
            )
        )
    return "\n".join(out)


def conditions_line(problem) -> str:
    """What the answer was computed for, in one line: the load per front caster (from ``load``, or from ``mass``
    and ``front_fraction``: L = m g f / 2), the sill, the floor and the turning mode."""
    c = problem.conditions
    return (
        f"For {c.load:.1f} N per front caster, a {written_size(c.threshold_height, problem.units)} sill, "
        f"{c.surface} floor, {c.turning_mode} turning:"
    )


def run(args) -> int:
    weights = parse_weights(args.weights)  # the options first: a bad one is named before the file is read
    speed = ranged_option(args.target_speed, "target_speed", "--target-speed")
    problem = load_problem(args.problem)
    if speed is not None:
        problem = problem.replace(target_speed=speed)
    from designer.studies.optimum import optimise

    rec = recommend(problem)  # exit 4 when no stock combination meets the risk bound
    solution = optimise(problem, weights, cross_check=not args.no_cross_check)
    used = [float(w) for w in (weights if weights is not None else problem.weights)]
    if args.json:
        data = solution.to_dict()
        data["extrapolated"] = bool(inertia_prediction().extrapolated(solution.design.diameter))
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
                conditions_line(problem),
                str(rec),
                "",
                f"Weighted optimum of the problem as posed, continuous and "
                f"{'risk-bounded' if problem.risk is not None else 'nominal'} ({weights_meaning(used)}):",
                str(solution),
            ]
        )
        print(wrapped(text))
    if args.verbose:
        t = solution.timings
        eprint(
            f"timing: NLP build {t['build'] * 1000:.1f} ms, multi-start solve {t['solve'] * 1000:.1f} ms "
            f"({solution.starts} starts), cross-checks {t['cross_check'] * 1000:.1f} ms"
        )
    return 0
