"""``designer fix PROBLEM --current ...``: diagnose a caster that shimmies and rank the smallest safe changes."""

from __future__ import annotations

import math

from designer.cli._common import PROBLEM_HELP, print_json, quantity_option, ranged_option
from designer.data.paper import INCH
from designer.studies.retrofit import ONSET_SCATTER, fix, parse_current
from designer.errors import InputError
from designer.problem import load_problem
from designer.studies.retrofit import describe_changes


def register(sub) -> None:
    p = sub.add_parser(
        "fix",
        help="retrofit: the smallest safe change to the caster you have",
        description="Diagnose the current caster (V_c of Eq. 7, P(shimmy at V_target) with its standard error, "
        "turning effort, sill force) and rank the fixes from the problem's [stock]: one part changed "
        "(washer, tyre, fork hole, wheel) before two, then by the smallest weighted loss in turning "
        "effort and sill force. Every fix meets the risk bound and the swept-radius limit. "
        "See docs/retrofit.md.",
    )
    p.add_argument("problem", help=PROBLEM_HELP + ": the chair, V_target, the risk bound and [stock]")
    p.add_argument("--target-speed", default=None, help="override shimmy.target_speed, e.g. 3m/s (as run takes it)")
    p.add_argument(
        "--current",
        required=True,
        help='the caster as it is, e.g. "T=1.5in,d=7.75in,B=0.5625in,c=1.3" (T = fork trail with the '
        "stem vertical, d = wheel diameter, B = groove, c = spindle damping in N*m/rad)",
    )
    p.add_argument(
        "--inertia",
        default=None,
        help="measured I_w of the current wheel [kg·m²], e.g. 0.00127 (default: the problem's inertia model)",
    )
    p.add_argument(
        "--shimmied-at",
        default=None,
        help="observed shimmy onset of this caster, e.g. 2.1m/s: calibrates the model error for it",
    )
    p.add_argument(
        "--stem-angle",
        default="0 deg",
        help="stem tilt from vertical, e.g. 4deg (positive: top leans back, more trail)",
    )
    p.add_argument(
        "--onset-scatter", type=float, default=None, help="σ of the log of the observed onset (default 0.05)"
    )
    p.add_argument("--top", type=int, default=10, help="fixes to list (0: all found; default 10)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=run)


def run(args) -> int:

    speed = ranged_option(args.target_speed, "target_speed", "--target-speed")  # options before the file
    problem = load_problem(args.problem)
    if speed is not None:
        problem = problem.replace(target_speed=speed)
    current = parse_current(args.current)
    inertia = None if args.inertia is None else quantity_option(args.inertia, "inertia", "--inertia")
    shimmied = None if args.shimmied_at is None else quantity_option(args.shimmied_at, "speed", "--shimmied-at")
    angle = quantity_option(args.stem_angle, "angle", "--stem-angle")
    if args.top < 0:
        raise InputError(f"--top {args.top}: must be 0 (all) or a positive number")
    try:
        result = fix(
            problem,
            current,
            inertia=inertia,
            shimmied_at=shimmied,
            stem_angle=angle,
            onset_scatter=ONSET_SCATTER if args.onset_scatter is None else args.onset_scatter,
            limit=args.top or None,
        )
    except InputError as exc:  # name the option the value came from
        text = str(exc)
        for prefix, option in (
            ("current ", "--current "),
            ("shimmied at", "--shimmied-at"),
            ("stem angle", "--stem-angle"),
            ("inertia", "--inertia"),
            ("onset scatter", "--onset-scatter"),
        ):
            if text.startswith(prefix):
                text = option + text[len(prefix) :]
                break
        raise InputError(text) from None
    if args.json:
        print_json(result.to_dict())
        return 0
    _print(result, problem)
    return 0


def _length(value: float) -> str:
    return f"{value / INCH:.3f} in"


def _print(result, problem) -> None:
    """The text output: the risk bound, the current caster's diagnosis, then the ranked fixes."""
    from rich.console import Console

    console = Console(width=max(Console().width, 170), highlight=False)
    alpha = result.probability
    conf = f"{1 - alpha:.0%}" if alpha is not None else "nominal"
    _print_current(console, result, problem, conf)
    if not result.fixes:
        return
    _print_fixes(console, result, conf)


def _print_current(console, result, problem, conf: str) -> None:
    """The problem's risk bound and the current caster: V_c, the speed reached with ``conf``, P(shimmy), costs."""
    from rich.markup import escape

    cur = result.current
    d = cur.design
    alpha = result.probability
    bound = (
        f"P(shimmy at {result.required_speed:.2f} m/s) <= {alpha:.0%}"
        if alpha is not None
        else f"V_c >= {result.required_speed:.2f} m/s (nominal: [robust] enabled = false)"
    )
    console.print(
        f"[bold]{problem.title}[/bold] ({problem.name}): risk bound {bound}; swept radius "
        + (f"<= {_length(problem.swept_radius_max)}" if problem.swept_radius_max else "not limited")
    )
    console.print(
        f"[bold]Current caster[/bold]: T = {_length(d.trail)}, d = {_length(d.diameter)}, "
        f"B = {_length(d.groove)}, c_f = {d.damping:.3g} N·m/rad, I_w = {cur.inertia:.4g} kg·m²"
    )
    if result.stem_angle:
        console.print(
            f"  stem tilted {math.degrees(result.stem_angle):+.2f} deg: effective trail "
            f"{_length(cur.effective_trail)} (fork {_length(d.trail)} + (d/2) sin φ, docs/retrofit.md)"
        )
    console.print(f"  V_c (Eq. 7) = {cur.critical_speed:.3f} m/s", end="")
    if result.calibration is not None:
        console.print(f"; calibrated: {cur.calibrated_critical_speed:.3f} m/s", end="")
    console.print(
        f"; speed reached with {conf}: {cur.confident_speed:.3f} m/s; P(shimmy at {result.target_speed:.2f} "
        f"m/s) = {cur.shimmy_probability:.2%} ± {cur.shimmy_probability_se:.2%} (Monte Carlo, 1 SE)"
    )
    console.print(
        f"  turning effort {cur.turning_effort:.2f} N, sill force {cur.threshold_force:.2f} N, swept radius "
        f"{_length(cur.swept_radius)}: "
        + ("[green]meets the risk bound[/green]" if cur.meets_risk_bound else "[red]does not meet the risk bound[/red]")
    )
    if result.calibration is not None:
        console.print(f"  [bold]Calibration[/bold]: {escape(result.calibration.describe())}.")
    console.print(f"[bold]{escape(result.summary())}[/bold]")


def _print_fixes(console, result, conf: str) -> None:
    """The rule, the stock and the table of ranked fixes (costs against the current caster)."""
    from rich.markup import escape

    from rich.table import Table

    console.print(escape(f"Rule: {result.rule}."))
    console.print(escape("Stock: " + "; ".join(f"{part}: {src}" for part, src in result.stock.items())))
    table = Table(
        title=f"Fixes ({result.found} found, {len(result.fixes)} shown; costs against the current caster)",
        title_justify="left",
    )
    for col, just in (
        ("#", "right"),
        ("parts", "right"),
        ("change: from -> to", "left"),
        ("I_w [kg·m²]", "right"),
        ("F_turn [N]", "right"),
        ("P [N]", "right"),
        ("loss [N]", "right"),
        ("V_c Eq. 7" + (" / ×k" if result.calibration else ""), "right"),
        (f"V at {conf}", "right"),
        ("P(shimmy) ± SE", "right"),
        ("swept", "right"),
    ):
        table.add_column(col, justify=just, no_wrap=col.startswith("change"))
    for rank, f in enumerate(result.fixes, 1):
        text = escape(describe_changes(f.changes, "\n", inertia=False))
        v_c = f"{f.critical_speed:.3f}" + (f" / {f.calibrated_critical_speed:.3f}" if result.calibration else "")
        table.add_row(
            str(rank),
            str(f.parts_changed),
            text,
            f"{f.inertia:.3g}",
            f"{f.turning_effort:.2f} ({f.cost_turning_effort:+.2f})",
            f"{f.threshold_force:.2f} ({f.cost_threshold_force:+.2f})",
            f"{f.loss:+.2f}",
            v_c,
            f"{f.confident_speed:.3f}",
            f"{f.shimmy_probability:.2%} ± {f.shimmy_probability_se:.2%}",
            _length(f.swept_radius),
        )
    console.print(table)
