"""``designer fix PROBLEM --current ...``: diagnose a caster that shimmies and rank the safe changes, cheapest first."""

from __future__ import annotations


from designer.cli._terminal import console as terminal_console, table
from designer.cli._common import PROBLEM_HELP, api_named, parts_text, print_json, quantity_option, ranged_option
from designer import fix, load_problem
from designer.studies.retrofit import ONSET_SCATTER, parse_current
from designer.display import header, number, percent, shown
from designer.errors import InputError
from designer.studies.spec import PART_LABELS
from designer.units import written_size


API_NAMES = {"current ": "--current ", "shimmied at": "--shimmied-at", "stem angle": "--stem-angle"}
API_NAMES |= {"inertia": "--inertia", "onset scatter": "--onset-scatter"}
"""How :func:`designer.fix`'s messages name an argument, and the option it came from on the command line."""

LIMITS = {"max_threshold_increase": "sill force", "max_turning_increase": "turning effort"}
"""The [retrofit] limits a command-line option overrides, each with the force it limits."""


def register(sub) -> None:
    p = sub.add_parser(
        "fix",
        help="retrofit: the cheapest safe change to the caster you have",
        description="Diagnose the current caster (V_c of Eq. 7, P(shimmy at V_target) with its standard error, "
        "turning effort, sill force) and rank the fixes from the problem's [stock] (washer, tyre, fork hole, "
        "wheel): among those that meet the risk bound and the swept-radius limit and keep the sill force and the "
        "turning effort within [retrofit] max_threshold_increase and max_turning_increase (default +10 % each), "
        "the cheapest first ([stock] costs), then the "
        "smallest loss in J = w_turn F_turn + w_threshold P; the others are listed apart. The answer comes "
        "first, in words; the table fits the terminal (COLUMNS), --wide shows every column. See docs/retrofit.md.",
    )
    p.add_argument("problem", help=PROBLEM_HELP + ": the chair, V_target, the risk bound and [stock]")
    p.add_argument("--target-speed", default=None, help="override shimmy.target_speed, e.g. 3m/s (as run takes it)")
    p.add_argument(
        "--current",
        required=True,
        help='the caster as it is, e.g. "T=1.5in,d=7.75in,B=0.5625in,c=1.3" (T = fork trail with the '
        "stem vertical, d = wheel diameter, B = groove, c = spindle damping in N*m/rad)",
    )
    for option, default, text in (
        (
            "--inertia",
            None,
            "measured I_w of the current wheel [kg·m²], e.g. 0.00127 (default: the problem's inertia model)",
        ),
        ("--shimmied-at", None, "observed shimmy onset of this caster, e.g. 2.1m/s: calibrates the model error for it"),
        ("--stem-angle", "0 deg", "stem tilt from vertical, e.g. 4deg (positive: top leans back, more trail)"),
    ):
        p.add_argument(option, default=default, help=text)
    p.add_argument(
        "--onset-scatter", type=float, default=None, help="σ of the log of the observed onset (default 0.05)"
    )
    for key, what in LIMITS.items():
        option, fraction = "--" + key.replace("_", "-"), "e.g. 0.15 or '15 %%' (default the problem's, 10 %%)"
        text = f"override [retrofit] {key}: how much a fix may raise the {what}, {fraction}"
        p.add_argument(option, default=None, metavar="FRACTION", help=text)
    p.add_argument("--top", type=int, default=10, help="fixes to list (0: all found; default 10)")
    p.add_argument("--wide", action="store_true", help="every column of the table (wider than 80 characters)")
    p.add_argument(
        "--verbose",
        action="store_true",
        help="the details: the current caster, the parts on offer, the rule, the tables",
    )
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=run)


def run(args) -> int:
    changes = {"target_speed": ranged_option(args.target_speed, "target_speed", "--target-speed")}  # before the file
    for key in LIMITS:  # each checked as its option (a fraction from 0 to 10), so the problem stays valid
        changes[key] = _increase(getattr(args, key), "--" + key.replace("_", "-"))
    if args.top < 0:
        raise InputError(f"--top {args.top}: must be 0 (all) or a positive number")
    problem = load_problem(args.problem)
    if any(v is not None for v in changes.values()):
        problem = problem.replace(**{k: v for k, v in changes.items() if v is not None})
    current = parse_current(args.current)
    inertia = quantity_option(args.inertia, "inertia", "--inertia")
    shimmied = quantity_option(args.shimmied_at, "speed", "--shimmied-at")
    angle = quantity_option(args.stem_angle, "angle", "--stem-angle")
    with api_named(API_NAMES):  # name the option the value came from
        result = fix(
            problem,
            current,
            inertia=inertia,
            shimmied_at=shimmied,
            stem_angle=angle,
            onset_scatter=ONSET_SCATTER if args.onset_scatter is None else args.onset_scatter,
            limit=args.top or None,
            specs=None if args.json else 1,  # --json: each listed fix's limits; the text: the best fix's
        )
    if args.json:
        print_json(result.to_dict())
    elif args.verbose or args.wide:
        _print(result, problem, args.wide, args.top)
    else:
        _print_screen(result, problem)
    return 0


def _increase(text: str | None, option: str) -> float | None:
    """``--max-threshold-increase`` or ``--max-turning-increase``: a fraction from 0 to 10 (``0.15`` or
    ``"15 %"``); InputError naming it."""
    if text is None:
        return None
    value = quantity_option(text, "dimensionless", option)
    if not 0 <= value <= 10:
        raise InputError(f"{option} {text}: must be from 0 to 10 (0.1 or '10 %')")
    if value >= 1 and "%" not in text:  # '5' meant as 5 % would silently allow +500 %
        raise InputError(
            f"{option} {text}: a bare number is a fraction (0.05 = 5 %); write '{text} %' for "
            f"{text} % or '{100 * value:g} %' for a {value:g}-fold rise"
        )
    return float(value)


def _print(result, problem, wide: bool = False, top: int = 10) -> None:
    """The text output: the answer first, in words; the current caster; what each part can become; the rule; the
    fixes within the limits (sill force, turning effort), then those beyond them (each table fits the console's width)."""
    from rich.markup import escape

    console = terminal_console(wide)
    alpha = result.probability
    conf = f"{percent(1 - alpha)}" if alpha is not None else "nominal"
    console.print(f"[bold]{escape(result.summary())}[/bold]")
    # the problem's risk bound and the current caster: V_c, the speed reached with ``conf``, P(shimmy), costs
    cur = result.current
    d = cur.design
    units = problem.units
    console.print(
        escape(
            f"{problem.title} ({problem.name}): risk bound {_bound(result)}; swept radius "
            + (f"<= {written_size(problem.swept_radius_max, units)}" if problem.swept_radius_max else "not limited")
        )
    )
    console.print(escape(f"Current caster: {parts_text(d, units)}, I_w = {shown(cur.inertia, 'inertia')}"))
    if result.stem_angle:
        console.print(
            f"  stem tilted {_plus(result.stem_angle, shown(result.stem_angle, 'disturbance_angle'))}: effective trail "
            f"{escape(written_size(cur.effective_trail, units))} (fork {escape(written_size(d.trail, units))} + (d/2) "
            "sin φ, docs/retrofit.md)"
        )
    text = f"  V_c (Eq. 7) = {shown(cur.critical_speed, 'critical_speed')}"
    if result.calibration is not None:
        text += f"; calibrated: {shown(cur.calibrated_critical_speed, 'critical_speed')}"
    console.print(
        text + f"; speed reached with {conf}: {shown(cur.confident_speed, 'critical_speed')}; P(shimmy at "
        f"{shown(result.target_speed, 'target_speed')}) = {percent(cur.shimmy_probability)} "
        f"(exact law; {_mc_text(cur)})"
    )
    console.print(
        f"  turning effort {shown(cur.turning_effort, 'turning_effort')}, sill force "
        f"{shown(cur.threshold_force, 'threshold_force')}, swept radius "
        f"{escape(written_size(cur.swept_radius, units))}: "
        + ("[green]meets the risk bound[/green]" if cur.meets_risk_bound else "[red]does not meet the risk bound[/red]")
    )
    if result.calibration is not None:
        console.print(f"  [bold]Calibration[/bold]: {escape(result.calibration.describe())}.")
    if cur.extrapolated:
        console.print(
            escape(
                f"  warning: d = {written_size(d.diameter, units)} lies outside Table 1's 4–8 in: the inertia fit and "
                "Eq. 7's check are extrapolated (the risk law's prediction interval widens with it)"
            )
        )
    if result.if_measured is not None:
        console.print(escape(_if_measured_text(result)))
    if not result.needs_fix:
        return
    console.print("Parts on offer (what each part can become; cost):")
    for part, text in result.stock.items():
        console.print(f"  {part:<10} {escape(text)}")
    console.print(escape(f"Rule: {result.rule}."))
    limit = (
        f"+{percent(result.max_threshold_increase)} sill force and +{percent(result.max_turning_increase)} "
        "turning effort"
    )
    listed = list(result.fixes)
    if result.fixes:
        title = f"Fixes within {limit} ({result.found} found, {len(result.fixes)} shown)"
        _print_table(console, result, result.fixes, title, wide, conf)
    else:
        console.print(f"No fix keeps within {limit} of the current caster's.")
    if result.beyond:
        apart = result.beyond if not result.fixes or wide else result.beyond[: min(3, top or 3)]
        listed += apart
        found = f"{result.found_beyond} found, {len(apart)} shown"
        _print_table(
            console, result, apart, f"Beyond the limits, listed apart ({found}; --json --top 0 lists all)", wide, conf
        )
    if any(f.extrapolated for f in listed):
        console.print("* a wheel outside Table 1's 4–8 in: its I_w and Eq. 7 are extrapolated (docs/retrofit.md).")
    best = result.best
    if best is not None and best.spec is not None:
        for line in _spec_lines(best, result):
            console.print(escape(line))


def _changes(fix, units: str) -> str:
    """A fix's changes for the table, one part a line: ``wheel 8 -> 7 in``, ``hole 1 1/4 -> 2 1/2 in``,
    ``washer c_f 1.3 -> 2`` (a wheel outside Table 1's 4–8 in marked ``*``)."""
    lines = []
    for c in fix.changes:
        if c.variable == "inertia":
            continue
        part = "hole" if c.part == "fork hole" else c.part
        if c.variable == "damping":
            lines.append(f"{part} c_f {c.before:g} -> {c.after:g}")
            continue
        before, after = written_size(c.before, units), written_size(c.after, units)
        name = f" {c.name}" if c.name else ""
        lines.append(
            f"{part}{name} {before.rsplit(' ', 1)[0]} -> {after}"
            + (" *" if c.part == "wheel" and fix.extrapolated else "")
        )
    return "\n".join(lines)


def _print_table(console, result, fixes, title: str, wide: bool, conf: str) -> None:
    """One table of fixes: rank, the changes (one part a line, sizes as the problem writes them), the parts' cost,
    F_turn and P against the current caster, P(shimmy); ``wide`` adds I_w, the loss, V_c, V_q and the swept
    radius."""
    from rich import box

    names = ["#", "change: from -> to", "cost", header("turning_effort"), header("threshold_force")]
    names += ["P(shimmy)" + (" (MC ± SE)" if wide else "")]
    if wide:
        calibrated = " / ×k" if result.calibration else ""
        names += [header("inertia"), "loss [N]", f"V_c Eq. 7{calibrated}", f"V at {conf}", "swept"]
    # the changes never wrap inside a size ("2 1/2 in"): the numbers give way
    columns = [
        (n, {"justify": "left" if i == 1 else "right", "overflow": "fold", "no_wrap": i == 1})
        for i, n in enumerate(names)
    ]
    rows = []
    for rank, f in enumerate(fixes, 1):
        risk = percent(f.shimmy_probability) + (
            f" ({percent(f.shimmy_probability_mc)} ± {percent(f.shimmy_probability_se, digits=2)})" if wide else ""
        )
        turning = number(f.cost_turning_effort, "turning_effort", digits=1)  # a change: to 0.1 N
        increase = percent(f.threshold_increase, digits=2)
        cells = [str(rank), _changes(f, result.units), f"{f.parts_cost:g}"]
        cells += [f"{number(f.turning_effort, 'turning_effort')} ({_plus(f.cost_turning_effort, turning)})"]
        cells += [f"{number(f.threshold_force, 'threshold_force')} ({_plus(f.threshold_increase, increase)})", risk]
        if wide:
            v_c = number(f.critical_speed, "critical_speed")
            v_c += f" / {number(f.calibrated_critical_speed, 'critical_speed')}" if result.calibration else ""
            cells += [number(f.inertia, "inertia"), _plus(f.loss, number(f.loss, "weighted")), v_c]
            cells += [number(f.confident_speed, "confident_speed"), written_size(f.swept_radius, result.units)]
        rows.append(cells)
    console.print(table(title, columns, rows, box=box.SIMPLE_HEAD, pad_edge=False))


def _bound(result) -> str:
    """The risk bound of the problem: "P(shimmy at 2.500 m/s) <= 5 %", or the nominal "V_c >= ..."."""
    speed = shown(result.required_speed, "critical_speed")
    if result.probability is None:
        return f"V_c >= {speed} (nominal: [robust] enabled = false)"
    return f"P(shimmy at {speed}) <= {percent(result.probability)}"


def _plus(value: float, text: str) -> str:
    """A change ``value`` shown as ``text`` (:mod:`designer.display`) with its sign: "+0.722", "-6.073"."""
    return ("+" if value > 0 else "") + text


def _print_screen(result, problem) -> None:
    """The answer in one screen (at most 24 lines at 80 columns): the answer, then Why, Cost, Inspect and Next (words
    generated from the result's numbers); the tables, the parts on offer and the rule are behind ``--verbose``."""
    from rich.markup import escape

    console = terminal_console()
    cur, best = result.current, result.best
    if not result.needs_fix:  # why, in one sentence: its risk against the bound (or V_c against the speed), the room
        speed = shown(result.target_speed, "target_speed", digits=1)
        risk = f"it is stable to {shown(cur.critical_speed, 'critical_speed')} (needed {speed})"
        if result.probability is not None:
            risk = (
                f"at {speed} it shimmies with probability {percent(cur.shimmy_probability)} "
                f"(allowed {percent(result.probability)})"
            )
        room = " and it fits the footrests" if problem.swept_radius_max is not None else ""
        console.print(f"[bold]No fix needed:[/bold] {escape(f'the caster as it is meets the limits: {risk}{room}.')}")
        return
    console.print(f"[bold]{escape(result.summary())}[/bold]")
    why = (
        f"the caster as it is ({parts_text(cur.design, problem.units)}) has P(shimmy at "
        f"{shown(result.target_speed, 'critical_speed')}) = {percent(cur.shimmy_probability)} (exact; Monte Carlo "
        f"{percent(cur.shimmy_probability_mc)} ± {percent(cur.shimmy_probability_se, digits=2)}) against the risk bound "
        f"{_bound(result)}; V_c (Eq. 7) {shown(cur.critical_speed, 'critical_speed')}"
    )
    paragraphs = [("Why", why)]
    if best is not None:  # the sum of the [stock] costs of its parts, in the unit they are written in
        parts = sorted({c.part for c in best.changes if c.variable != "inertia"})
        cost = (
            f"{best.parts_cost:g} in the unit the problem's [stock] costs are written in (relative units: "
            f"docs/problem-file.md), the sum for the {len(parts)} part{'s' if len(parts) != 1 else ''} changed: "
            + ", ".join(parts)
        )
        paragraphs += [("Cost", cost), ("Inspect", _inspect_text(best, result, problem))]
    calibrates = " (the onset calibrates Eq. 7 for this chair)" if result.calibration is None else ""
    next_steps = (  # fit and ride; calibrate with the speed it shimmied at; where the other fixes are
        f"fit the parts and ride at {shown(result.target_speed, 'critical_speed')}; if it shimmies, rerun with "
        f"--shimmied-at SPEED{calibrates}. Other fixes: {max(result.found - 1, 0)} more within the limits, "
        f"{result.found_beyond} beyond them; --verbose shows the tables, the parts on offer and the ranking rule; "
        "--json --top 0 lists all"
    )
    for head, text in paragraphs + [("Next", next_steps)]:
        console.print(f"[bold]{head}:[/bold] {escape(text)}")


def _inspect_text(best, result, problem) -> str:
    """What to look at before fitting the best fix: the swept radius against its limit, a new wheel's inertia
    (power law or measured), an extrapolated diameter; and what measuring the current wheel would change."""
    units = problem.units
    limit = problem.swept_radius_max
    text = f"the caster's sweep T + d/2 becomes {written_size(best.swept_radius, units)}" + (
        f" (limit {written_size(limit, units)}): check it clears the footrests" if limit else ""
    )
    if any(c.part == "wheel" for c in best.changes):
        text += f"; the new wheel's I_w {shown(best.inertia, 'inertia')} is " + (
            "measured" if best.measured else "the power law's: weigh and swing it if you can"
        )
    if best.extrapolated:
        text += f"; {written_size(best.design.diameter, units)} lies outside Table 1's 4–8 in (extrapolated)"
    if best.spec is not None:  # the acceptance limits in one phrase, sizes in the problem's units, each rounded
        # toward the safe side: T 1.727–2.125 in, B >= 0.652 in, M_f >= 0.197 N·m (a part without a limit left out)
        limits = []
        for part, symbol in _SYMBOLS.items():
            lims = {
                lim.side: lim.shown_in(units).split(" (")[0]
                for lim in best.spec.limits
                if lim.part == part and lim.value is not None
            }
            if "min" in lims and "max" in lims:
                limits.append(f"{symbol} {lims['min'].rsplit(' ', 1)[0]}–{lims['max']}")
            elif lims:
                side, lim = next(iter(lims.items()))
                limits.append(f"{symbol} {'>=' if side == 'min' else '<='} {lim}")
        text += "; accept parts within " + ", ".join(limits) + " (--verbose: how to measure)"
    if result.if_measured is not None:
        text += ". " + _if_measured_text(result)
    return text


def _if_measured_text(result) -> str:
    """What measuring the current wheel would change, said so that a higher P(shimmy) reads as what it is: without
    ``--inertia`` the risk law spreads V_c over every wheel of that diameter; a caster whose median V_c is below
    the speed is then *less* surely unstable, so measuring it at the power law's value raises P(shimmy)."""
    m = result.if_measured
    p, now = m["current_shimmy_probability"], result.current.shimmy_probability
    effect = (
        "a caster whose V_c lies below the speed shimmies more surely once the wheel's scatter is gone"
        if p >= now
        else "the wheel's scatter was the risk"
    )
    return (
        f"Measuring the current wheel (--inertia) takes Table 1's scatter out of its risk: at the power law's "
        f"{shown(m['inertia'], 'inertia')}, P(shimmy) {percent(now)} → {percent(p)} as it is ({effect}); "
        + (
            "the same best fix"
            if m["summary"] == result.summary()
            else "the fix then: " + m["summary"].removeprefix("Best fix: ")
        )
    )


def _mc_text(state) -> str:
    """The Monte Carlo beside the exact P: ``Monte Carlo 61.88% ± 0.10%, 250000 draws, seed 20111``."""
    return (
        f"Monte Carlo {percent(state.shimmy_probability_mc)} ± {percent(state.shimmy_probability_se, digits=2)}, "
        f"{state.mc_samples} draws, seed {state.mc_seed}"
    )


_SYMBOLS = {"trail": "T", "groove": "B", "friction_moment": "M_f", "wheel_inertia": "I_w"}
"""The short name of each inspectable part on the one-screen answer."""


def _spec_lines(best, result) -> list[str]:
    """The best fix's spec for goods-in: P(shimmy) exact beside its Monte Carlo, then each part's acceptance limit
    with the others at nominal (the exact law gives P = α there), or why it has none, and how to measure it."""
    spec = best.spec
    out = [
        f"Inspect the parts of the best fix (acceptance limits, each with the other parts at nominal; at a risk limit the "
        f"exact law gives P(shimmy at {shown(spec.required_speed, 'critical_speed')}) = {percent(spec.alpha)}): "
        "P(shimmy at "
        f"{shown(result.target_speed, 'critical_speed')}) {percent(best.shimmy_probability)} exact ({_mc_text(best)}); "
        f"M_f = c_f θ0 = {shown(spec.friction_moment, 'turning_moment')} "
        f"(θ0 = {shown(spec.disturbance_angle, 'disturbance_angle')})"
    ]
    for part in PART_LABELS:
        for lim in (x for x in spec.limits if x.part == part):
            text = lim.shown_in(result.units)
            why = "" if lim.reason == "risk" else f" ({lim.reason})"
            out.append(f"  {lim.side} {PART_LABELS[part]}: {text}{why}")
    if spec.stem_angle:
        out.append("  the trail is the fork offset e (the tyre sees e + (d/2) sin φ)")
    out.append("  how to measure: docs/problem-file.md#tolerances; --json: listed fixes' limits")
    if spec.corner is not None:
        c = spec.corner
        out.append(
            f"  worst corner of the tolerances: P {percent(c['probability'])} (bound {percent(spec.alpha)}): "
            + ("holds" if c["holds"] else "does NOT hold")
        )
    return out
