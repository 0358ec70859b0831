"""``designer run PROBLEM``: the scalarised optimum with margins, sensitivities and solver agreement."""
from __future__ import annotations

import math

from designer.commands._common import eprint, print_json
from designer.errors import InputError
from designer.analysis.optimise import optimise
from designer.problem import load_problem


def register(sub) -> None:
    p = sub.add_parser("run", help="solve a problem file for the weighted optimum",
                       description="Minimise J = w_turn F_turn + w_threshold P subject to V_c >= target (Eq. 7): "
                                   "multi-start IPOPT, cross-checked by a geometric program (cvxpy) and SLSQP.")
    p.add_argument("problem", help="problem file (TOML), e.g. problems/indoor-manual.toml")
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
    from designer.problem import check_weights

    return check_weights(values, "--weights", error=InputError)


def run(args) -> int:
    problem = load_problem(args.problem)
    if args.target_speed is not None:
        from designer.commands._common import quantity_option

        problem = problem.replace(target_speed=quantity_option(args.target_speed, "speed", "--target-speed"))
    solution = optimise(problem, parse_weights(args.weights), cross_check=not args.no_cross_check)
    if args.json:
        print_json(solution.to_dict())
    else:
        print(solution)
    if args.verbose:
        t = solution.timings
        eprint(f"timing: NLP build {t['build'] * 1000:.1f} ms, multi-start solve {t['solve'] * 1000:.1f} ms "
               f"({solution.starts} starts), cross-checks {t['cross_check'] * 1000:.1f} ms")
    return 0
