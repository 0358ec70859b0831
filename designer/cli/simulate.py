"""``designer simulate``: time-domain shimmy after a knock, Coulomb spindle friction (Appendix B)."""

from __future__ import annotations

import math
import warnings
from functools import partial

from designer import Conditions, Design, TyreParameters, bifurcation_diagram, knock_safe_speed, simulate
from designer.cli._common import api_named, count_option, end_progress_line, eprint, inertia_option
from designer.cli._common import print_json, progress_line, quantity_option, ranged_option
from designer.display import number, percent, shown
from designer.parameters import VARIABLE_TABLE
from designer.errors import InputError
from designer.output import check_file, output_folder, PLOT
from designer.studies.dynamics.limit_cycles import limit_cycle_study
from designer.plots.simulation import bifurcation_axes
from designer.studies.dynamics import onset_speed, scaled_budget, work_limit
from designer.studies import dynamics


def register(sub) -> None:
    p = sub.add_parser(
        "simulate",
        help="simulate caster shimmy in time (Coulomb spindle friction)",
        description="Integrate the two-degree-of-freedom caster of Appendix B (Eq. 3B, 4B, 6B) with true Coulomb "
        "spindle friction M_f sgn(θ'), M_f = c_f θ0, from a knock θ_i (Eq. 24B), and compare with Eq. 7 "
        "(critical speed), Eq. 4/29B (amplitude) and Eq. 15B (frequency). "
        "--report DIR regenerates the comparison report (results/simulation).",
    )
    p.add_argument("--trail", help="trail T (e.g. 2.5in)")
    p.add_argument("--diameter", default="8 in", help="wheel diameter d (default 8 in; sets I_w unless --inertia)")
    p.add_argument("--groove", default="0 in", help="groove width B (default 0, single tread)")
    p.add_argument("--damping", default="1.3 N*m/rad", help="spindle friction damping c_f = M_f/θ0 (default 1.3)")
    p.add_argument("--speed", help="wheelchair speed V (e.g. 2.5m/s)")
    p.add_argument("--angle", default="20 deg", help="initial (knock) angle θ_i (default 20 deg)")
    p.add_argument("--angular-velocity", default="0", help="initial θ'_i in rad/s (default 0)")
    p.add_argument(
        "--disturbance-angle", default="20 deg", help="design θ0 that defines M_f = c_f θ0 (default 20 deg, App. C)"
    )
    p.add_argument(
        "--load",
        default="178 N",
        help="caster load L (used by the brush tyre of --bifurcation and --knock-safe --tyre; default 178 N)",
    )
    p.add_argument("--inertia", default=None, help="wheel I_w [kg·m²], e.g. 0.00127 (default: Table 1 power law of d)")
    p.add_argument("--slip-coefficient", default="1250 N", help="tyre slip coefficient K_s (default 1250 N)")
    p.add_argument("--duration", default=None, help="simulated time in s (default: transient + 24 periods)")
    p.add_argument("--find-onset", action="store_true", help="also find the onset speed by bisection")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="plot θ(t) (as Fig. 1C)")
    p.add_argument(
        "--report",
        default=None,
        metavar="DIR",
        help="regenerate the simulated-onset vs Eq. 7 report into DIR (e.g. results/simulation)",
    )
    p.add_argument("--json", action="store_true", help="machine-readable output")
    _register_limit_cycles(p)
    p.set_defaults(func=run)


def _register_limit_cycles(p) -> None:
    """Options of the study beyond onset: the brush tyre, the bifurcation diagram and the knock-safe speed."""
    g = p.add_argument_group("beyond onset (brush tyre, periodic orbits, knock-safe speed)")
    g.add_argument(
        "--bifurcation",
        action="store_true",
        help="periodic orbits against speed (stable and unstable branches, brush tyre; the rolling "
        "tyre's branch beside it); --plot draws the diagram",
    )
    g.add_argument(
        "--knock-safe", action="store_true", help="highest speed at which a knock of --angle decays (and of twice it)"
    )
    g.add_argument(
        "--tyre",
        action="store_true",
        help="use the brush tyre for --knock-safe (default: the paper's rolling tyre, Eq. 6B)",
    )
    g.add_argument("--friction-coefficient", default="0.7", help="tyre-floor μ of the brush tyre (default 0.7)")
    g.add_argument("--cornering-stiffness", default="1250", help="brush tyre C in N/rad (default K_s = 1250)")
    g.add_argument("--wheel-mass", default="0.444 kg", help="wheel mass M_W for the brush tyre (default 0.444 kg)")
    g.add_argument("--max-speed", default="4 m/s", help="upper speed of --bifurcation (default 4 m/s)")
    g.add_argument(
        "--points", type=int, default=DEFAULT_POINTS, help="orbits on the unstable branch of --bifurcation (default 24)"
    )


MAX_ANGULAR_VELOCITY = 1000.0
"""Largest |θ'_i| of a knock [rad/s]: the small-angle model holds to |θ| = 1 rad, and at the paper's shimmy
frequencies (Eq. 15B, 80-105 rad/s) a swing of 1 rad has |θ'| of about 100 rad/s; ten times that is no knock."""

TYRE_RANGES = {
    "--friction-coefficient": ("dimensionless", 0.0, 10.0, "", "tyre-floor μ: about 0.7 for rubber on tile"),
    "--cornering-stiffness": ("force", 1.0, 1e6, "N/rad", "as K_s (1250 N, App. C): 1 to 1e6"),
    "--wheel-mass": ("mass", 0.0, 100.0, "kg", "a caster wheel of 0.444 kg (the default)"),
}
"""The brush tyre's options: (dimension, low (exclusive for 0), high, unit, what a value usually is)."""


def _run_limit_cycles(args) -> int:
    """--bifurcation / --knock-safe."""

    if args.speed is None:
        args.speed = "1 m/s"  # not used by these analyses
    design, conditions, _speed, angle, _omega0, _duration = parse(args)
    values = {}  # the brush tyre: InputError naming the option of a value outside TYRE_RANGES (low exclusive when 0)
    for option, (dimension, low, high, unit, hint) in TYRE_RANGES.items():
        text = getattr(args, option[2:].replace("-", "_"))
        value = values[option] = quantity_option(text, dimension, option)
        if not (math.isfinite(value) and (low < value if low == 0 else low <= value) and value <= high):
            raise InputError(f"{option} {text}: outside {low:g} to {high:g} {unit}".rstrip() + f" ({hint})")
    tyre = TyreParameters(
        cornering_stiffness=values["--cornering-stiffness"],
        friction_coefficient=values["--friction-coefficient"],
        load=ranged_option(args.load, "load", "--load"),
        wheel_mass=values["--wheel-mass"],
    )
    out: dict = {"design": design.to_dict(), "angle": angle}
    if args.knock_safe:
        out.update(knock_safe_speeds(design, conditions, angle, tyre if args.tyre else None))
    if args.bifurcation:
        out.update(_bifurcation(args, design, conditions, angle, tyre))
    if args.json:
        print_json(out)
        return 0
    _print_limit_cycles(args, design, angle, tyre, out)
    return 0


def knock_safe_speeds(design, conditions, angle: float, tyre) -> dict:
    """Knock-safe speeds [m/s] for knocks of ``angle`` and twice it (None at or beyond 90°); ``tyre`` None: rolling."""
    return {
        "knock_safe_speed": knock_safe_speed(design, conditions, angle=angle, tyre=tyre),
        "knock_safe_speed_double": (
            knock_safe_speed(design, conditions, angle=2 * angle, tyre=tyre) if 2 * angle < math.pi / 2 else None
        ),
        "knock_safe_model": "brush tyre" if tyre is not None else "rolling tyre (Eq. 6B)",
    }


def _bifurcation(args, design, conditions, angle: float, tyre) -> dict:
    """Periodic orbits against speed, brush tyre and rolling tyre (``--points``, ``--max-speed``); ``--plot`` draws them."""
    points = args.points
    top = ranged_option(args.max_speed, "target_speed", "--max-speed")
    span = (min(0.3, top / 4), top)
    bif = bifurcation_diagram(design, conditions, tyre, speed_range=span, points=points)
    roll = bifurcation_diagram(
        design, conditions, None, speed_range=span, points=max(3, points // 2), max_amplitude=1.5
    )
    data = bif.to_dict()
    out = {k: data[k] for k in BIFURCATION_KEYS}
    out["rolling_branches"] = roll.to_dict()["branches"]
    if args.plot:  # its suffix checked by run before the work
        from designer.plots.figures import save_figure

        ax = bifurcation_axes(
            bif.branches,
            bif.eq7_critical_speed,
            angle / (bif.frequency * design.trail),
            roll.branches,
            bif.fold_speed,
            speed_range=span,
            title=design.describe(),
        )
        ax.figure.tight_layout()
        save_figure(ax.figure, args.plot)
        out["plot"] = args.plot
    return out


BIFURCATION_KEYS = (
    "branches fold_speed eq7_critical_speed frequency orbits stable_at_reference max_closure tyre".split()
)
"""What --bifurcation's output takes of the brush tyre's diagram (:meth:`BifurcationDiagram.to_dict`)."""

DEFAULT_POINTS = 24
"""Orbits on the unstable branch of --bifurcation by default (its work budget grows with --points over this)."""


def _print_limit_cycles(args, design, angle: float, tyre, out: dict) -> None:
    """The text output of --knock-safe and --bifurcation."""
    print(f"Caster: {design.describe()}")
    if args.knock_safe:
        double = out["knock_safe_speed_double"]
        print(
            f"knock-safe speed ({out['knock_safe_model']}): {_speed(out['knock_safe_speed'])} for a "
            f"{shown(angle, 'disturbance_angle')} knock"
            + (f", {_speed(double)} for {shown(2 * angle, 'disturbance_angle')}" if double is not None else "")
        )
    if args.bifurcation:
        print(
            f"Eq. 7 V_c = {_speed(out['eq7_critical_speed'])}; brush tyre (μ = {number(tyre.friction_coefficient)}, "
            f"C = {number(tyre.cornering_stiffness)} N/rad, L = {shown(tyre.load, 'load')}):"
        )
        for b in out["branches"]:
            print(
                f"  {b['kind']:8s} branch: V {_span(b['speed'], 'critical_speed')}, amplitude "
                f"{_span(b['amplitude'], 'shimmy_amplitude')} ({len(b['speed'])} orbits)"
            )
        fold = out["fold_speed"]
        print("  fold (lowest speed of sustained shimmy): " + (_speed(fold) if math.isfinite(fold) else "none found"))
        s = out["stable_at_reference"]
        if s is not None:
            print(
                f"  stable amplitude at {_speed(out['eq7_critical_speed'])}: "
                f"{shown(s['amplitude'], 'shimmy_amplitude')}, "
                f"max |Floquet multiplier| {number(s['max_abs_multiplier'])}"
            )
        print(f"  largest orbit closure error {shown(out['max_closure'], dimension='angle', digits=1)}")
        if args.plot:
            print(f"  plot: {args.plot}")


def _speed(value: float) -> str:
    """A speed [m/s] as every speed of the output: :func:`designer.display.shown` of V_c."""
    return shown(value, "critical_speed")


def _span(values, name: str) -> str:
    """The least and the largest of ``values`` [SI], as the parameter table shows ``name``: "0.30–2.60 m/s"."""
    return f"{number(min(values), name)}–{shown(max(values), name)}"


def parse(args) -> tuple[Design, Conditions, float, float, float, float | None]:
    """Options → (design, conditions, speed, angle, angular velocity, duration); InputError on bad input."""
    for option, value in (("--trail", args.trail), ("--speed", args.speed)):
        if value is None:
            raise InputError(f"{option}: missing; required unless --report is given")
    # the model's ranges of the parameter table, as a problem file's bounds
    design = Design(**{p.name: ranged_option(getattr(args, p.name), p.name, f"--{p.name}") for p in VARIABLE_TABLE})
    ranged_option(args.load, "load", "--load")
    speed = ranged_option(args.speed, "target_speed", "--speed")
    angle = quantity_option(args.angle, "angle", "--angle")
    if not 0 < angle < math.pi / 2:
        raise InputError(f"--angle {args.angle}: must be between 0 and 90 deg (small-angle model)")
    omega0 = quantity_option(args.angular_velocity, "angular_speed", "--angular-velocity")
    if not (math.isfinite(omega0) and abs(omega0) <= MAX_ANGULAR_VELOCITY):
        raise InputError(
            f"--angular-velocity {args.angular_velocity}: must be between -{MAX_ANGULAR_VELOCITY:g} and "
            f"{MAX_ANGULAR_VELOCITY:g} rad/s (a knock's θ'_i; App. C estimates 0.7 rad/s)"
        )
    theta0 = quantity_option(args.disturbance_angle, "angle", "--disturbance-angle")
    slip = quantity_option(args.slip_coefficient, "force", "--slip-coefficient")
    with api_named({"disturbance_angle ": "--disturbance-angle ", "slip_coefficient ": "--slip-coefficient "}):
        conditions = Conditions(disturbance_angle=theta0, slip_coefficient=slip, inertia=inertia_option(args.inertia))
    duration = quantity_option(args.duration, "time", "--duration")
    if duration is not None and not 0 < duration <= 60:
        raise InputError(f"--duration {args.duration}: must be between 0 and 60 s")
    return design, conditions, speed, angle, omega0, duration


def run(args) -> int:
    if args.plot and args.report is None:  # the plot's place, checked before the simulation
        if not str(args.plot).lower().endswith((".png", ".svg", ".pdf")):
            raise InputError(f"--plot {args.plot}: expected a .png, .svg or .pdf file name")
        check_file(args.plot, "--plot", example="plot.png", kind=PLOT)
    if (args.bifurcation or args.knock_safe) and args.report is None:
        # one budget for all the command's studies, grown with the orbits asked for (--points, default 24)
        count_option(args.points, "--points", 3, 200)  # orbits of --bifurcation
        budget = scaled_budget(args.points, DEFAULT_POINTS) if args.bifurcation else None
        with work_limit("designer simulate", budget):
            return _run_limit_cycles(args)

    if args.report is not None:
        return _report(args, dynamics.write_simulation_report)

    design, conditions, speed, angle, omega0, duration = parse(args)

    with warnings.catch_warnings(record=True) as caught, work_limit("designer simulate"):
        warnings.simplefilter("always")
        result = simulate(design, conditions, speed, angle=angle, angular_velocity=omega0, duration=duration)
        onset = onset_speed(design, conditions, angle=angle, angular_velocity=omega0) if args.find_onset else None
    out = {"design": design.to_dict(), **result.to_dict()}
    if onset is not None:
        out["onset_speed"] = onset.speed
        out["onset_bracket"] = [onset.low, onset.high]
        out["onset_relative_error"] = onset.relative_error
    out["warnings"] = [str(w.message) for w in caught]
    if args.plot:  # θ(t), its suffix checked before the work
        from designer.plots.figures import save_figure

        save_figure(result.plot(onset_speed=None if onset is None else onset.speed).figure, args.plot, dpi=110)
        out["plot"] = args.plot
    if args.json:
        print_json(out)
        return 0
    verdict = "GROWS (shimmy)" if result.grows else "decays"
    amplitude = partial(shown, name="shimmy_amplitude")
    moment = shown(result.friction_moment, "turning_moment")
    print(f"Caster: {design.describe()}, I_w = {shown(result.inertia, 'inertia')}, M_f = {moment}")
    knock = f"θ_i = {shown(angle, 'disturbance_angle')}, θ'_i = {shown(omega0, dimension='angular_speed')}"
    print(f"knock {knock}, V = {_speed(speed)}: {verdict}")
    print(
        f"  amplitude after transient {amplitude(result.early_amplitude)} (Eq. 4/29B: "
        f"{amplitude(result.predicted_amplitude)}), late {amplitude(result.late_amplitude)}; late/θ_i = "
        f"{number(result.amplitude_ratio)}, "
        f"late/early = {number(result.growth_ratio)}{' (|θ| reached 1 rad)' if result.diverged else ''}"
    )
    freq = (
        "n/a (motion stopped)" if not math.isfinite(result.frequency) else shown(result.frequency, "shimmy_frequency")
    )
    print(f"  frequency {freq} (Eq. 15B: {shown(result.predicted_frequency, 'shimmy_frequency')})")
    print(f"  Eq. 7 critical speed (c_f,eff = M_f/θ_i): {_speed(result.critical_speed)}")
    if onset is not None:
        print(
            f"  simulated onset {_speed(onset.speed)} (bracket {_span((onset.low, onset.high), 'critical_speed')}), "
            f"{percent(onset.relative_error)} vs Eq. 7"
        )
    if args.plot:
        print(f"  plot: {args.plot}")
    for w in out["warnings"]:
        print(f"warning: {w}")
    return 0


ONSET_FILES = ("onset.csv", "onset.json", "onset.png", "report.md")
"""What the simulated-onset study writes into the --report folder (beside the limit-cycle files)."""


def _report(args, write_simulation_report) -> int:
    """--report DIR: the onset study and the limit-cycle study, written into DIR at once when both are done.

    Both write into one temporary folder inside DIR (:func:`designer.output.output_folder`), checked before
    the work; an error or a signal (after minutes of work) leaves DIR as it was, never half new.
    """
    from designer.report.limit_cycles import FILES, limit_cycle_files

    owned = ONSET_FILES + FILES
    with output_folder(args.report, owned, option="--report", command="designer simulate") as tmp:
        result = write_simulation_report(
            tmp,
            progress=None if args.json else lambda i, n: progress_line(f"case {i}/{n}"),
        )
        end_progress_line()
        study = limit_cycle_study(progress=None if args.json else lambda text: eprint(f"limit cycles: {text}"))
        written = limit_cycle_files(study, tmp)
    summary = result.summary
    if args.json:
        print_json({"report": args.report, "summary": summary})
    else:
        a = summary["all"]
        print(
            f"wrote {args.report}/report.md, onset.csv, onset.json, onset.png: {summary['cases']} cases, "
            f"simulated onset vs Eq. 7 from {percent(a['min_error'])} to {percent(a['max_error'])}"
        )
        print(f"wrote {args.report}/{', '.join(written)} (shimmy beyond onset)")
    return 0
