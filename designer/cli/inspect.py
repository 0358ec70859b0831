"""``designer inspect PROBLEM measured.csv [--json]`` and ``designer inspect PROBLEM --template FILE``: a verdict on
each measured caster (exact P(shimmy) at the required speed, pass/fail against α, the part that drives it) and on
the lot; or the empty form an inspector fills in (docs/inspection.md)."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

from designer import load_problem, recommend
from designer.cli._common import PROBLEM_HELP, print_json
from designer.display import percent, shown
from designer.errors import InputError
from designer.output import check_file, FileKind, write_file
from designer.studies.inspect import inspect, read_measured, template_text

EXIT_BAD_ROWS = 2
"""Exit code when some rows could not be graded (after the good rows are graded and printed)."""

_DRIVER = {"trail": "trail T", "groove": "groove B", "friction_moment": "friction M_f", "wheel_inertia": "inertia I_w"}


def register(sub) -> None:
    p = sub.add_parser(
        "inspect",
        help="grade measured casters against the risk bound (goods-in inspection), or write the empty form",
        description="Goods-in inspection: for each measured caster of MEASURED (CSV, one row per caster, units in "
        "the header: serial, trail_mm, diameter_mm, groove_mm, friction_moment_N_m or damping_N_m_per_rad, "
        "wheel_inertia_kg_m2) the exact P(shimmy) at the problem's required speed with the wheel's I_w as "
        "measured, pass/fail against α and the part that drives it; for the lot how many pass, the worst caster "
        "and the fraction above α. Bad rows are named one per line on stderr after the good rows are graded, "
        "then exit 2; the file is only read. --template FILE writes the empty form in the problem's units "
        "(never over an existing file: exit 7).",
    )
    p.add_argument("problem", help=PROBLEM_HELP)
    p.add_argument("measured", nargs="?", default=None, help="the measured casters (CSV)")
    p.add_argument("--template", default=None, metavar="FILE", help="write the empty inspection form to FILE")
    p.add_argument("--json", action="store_true", help="print the verdicts as JSON")
    p.set_defaults(func=run)


def _template(problem_arg: str, out: str) -> int:
    path = Path(out)
    kind = FileKind("an inspection form written by designer inspect", new_only=True)  # never over anything
    check_file(path, "--template", "measured.csv", kind=kind)
    problem = load_problem(problem_arg)
    write_file(path, template_text(problem), "--template", "measured.csv", kind=kind)
    print(f"inspection form: {path.resolve()} (fill one row per caster, then: designer inspect {problem_arg} {path})")
    return 0


def run(args) -> int:
    if args.template is not None:
        if args.measured is not None:
            raise InputError("designer inspect: give either MEASURED or --template FILE, not both")
        return _template(args.problem, args.template)
    if args.measured is None:
        raise InputError("designer inspect: MEASURED missing: a CSV of measured casters (--template FILE writes one)")
    problem = load_problem(args.problem)
    read_measured(args.measured, float(problem.conditions.disturbance_angle))  # a header error before the solve
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the recommendation's own warnings are run's to say
        rec = recommend(problem)
    result = inspect(problem, args.measured, rec)
    if args.json:
        print_json(result.to_dict())
    else:
        _print(result, rec)
    for bad in result.bad_rows:
        print(bad.line(result.source), file=sys.stderr)
    return EXIT_BAD_ROWS if result.bad_rows else 0


def _print(result, rec) -> None:
    lot = result.lot()
    print(
        f"{result.source}: P(shimmy at {shown(result.speed, 'target_speed')}) of each caster by the exact law, "
        f"wheel I_w as measured; bound α = {percent(result.alpha)}"
    )
    print(f"  {'serial':<12} {'P(shimmy)':>9}  verdict  {'driver':<13} joint box  one at a time")
    for c in result.casters:
        foot = "" if c.fits_footrest in (None, True) else "  (hits the footrest: T + d/2 > R_max)"
        print(
            f"  {c.serial[:12]:<12} {percent(c.shimmy_probability):>9}  {'pass' if c.passed else 'FAIL':<7}  "
            f"{_DRIVER[c.driver]:<13} {'inside' if c.in_joint_box else 'outside':<10} "
            f"{'inside' if c.in_one_at_a_time else 'outside'}{foot}"
        )
    if lot["graded"]:
        worst = lot["worst"]
        print(
            f"Lot: {lot['passed']} of {lot['graded']} pass; worst {worst['serial']} at "
            f"{percent(worst['shimmy_probability'])} (driver: {_DRIVER[worst['driver']]}); fraction above α "
            f"{percent(lot['fraction_above_alpha'])} ± {percent(lot['fraction_above_alpha_se'])} (binomial SE); mean "
            f"P(shimmy) {percent(lot['mean_shimmy_probability'])}"
        )
    print(
        "Driver: the part that, put back to the nominal of the recommended caster, lowers P the most. A caster "
        "inside the joint box always passes; one inside the one-at-a-time limits may not."
    )
    if result.bad_rows:
        print(f"{len(result.bad_rows)} rows could not be graded (listed on stderr)")
