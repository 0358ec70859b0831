"""``designer simulate``: time-domain shimmy after a knock, Coulomb spindle friction (Appendix B)."""
from __future__ import annotations

import math
import sys

from designer.commands._common import eprint, print_json, quantity_option
from designer.errors import InputError
from designer.model import Conditions, Design
from designer.physics.inertia import Fixed, PowerLaw


def register(sub) -> None:
    p = sub.add_parser(
        "simulate", help="simulate caster shimmy in time (Coulomb spindle friction)",
        description="Integrate the two-degree-of-freedom caster of Appendix B (Eq. 3B, 4B, 6B) with true Coulomb "
                    "spindle friction M_f sgn(θ'), M_f = c_f θ0, from a knock θ_i (Eq. 24B), and compare with Eq. 7 "
                    "(critical speed), Eq. 4/29B (amplitude) and Eq. 15B (frequency). "
                    "--report DIR regenerates the comparison report (results/simulation).")
    p.add_argument("--trail", help="trail T (e.g. 2.5in)")
    p.add_argument("--diameter", default="8 in", help="wheel diameter d (default 8 in; sets I_w unless --inertia)")
    p.add_argument("--groove", default="0 in", help="groove width B (default 0, single tread)")
    p.add_argument("--damping", default="1.3 N*m/rad", help="spindle friction damping c_f = M_f/θ0 (default 1.3)")
    p.add_argument("--speed", help="wheelchair speed V (e.g. 2.5m/s)")
    p.add_argument("--angle", default="20 deg", help="initial (knock) angle θ_i (default 20 deg)")
    p.add_argument("--angular-velocity", default="0", help="initial θ'_i in rad/s (default 0)")
    p.add_argument("--disturbance-angle", default="20 deg",
                   help="design θ0 that defines M_f = c_f θ0 (default 20 deg, App. C)")
    p.add_argument("--load", default="178 N", help="caster load L (recorded; the shimmy model does not use it)")
    p.add_argument("--inertia", default=None, help="wheel I_w in kg*m**2 (default: Table 1 power law of d)")
    p.add_argument("--slip-coefficient", default="1250 N", help="tyre slip coefficient K_s (default 1250 N)")
    p.add_argument("--duration", default=None, help="simulated time in s (default: transient + 24 periods)")
    p.add_argument("--find-onset", action="store_true", help="also find the onset speed by bisection")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="plot θ(t) (as Fig. 1C)")
    p.add_argument("--report", default=None, metavar="DIR",
                   help="regenerate the simulated-onset vs Eq. 7 report into DIR (e.g. results/simulation)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=run)


def _positive(option, text, dimension, allow_zero=False):
    value = quantity_option(text, dimension, option)
    if value < 0 or (value == 0 and not allow_zero):
        raise InputError(f"{option} {text}: must be {'non-negative' if allow_zero else 'positive'}")
    return value


def parse(args) -> tuple[Design, Conditions, float, float, float, float | None]:
    """Options → (design, conditions, speed, angle, angular velocity, duration); InputError on bad input."""
    for option, value in (("--trail", args.trail), ("--speed", args.speed)):
        if value is None:
            raise InputError(f"{option}: missing; required unless --report is given")
    design = Design(
        trail=_positive("--trail", args.trail, "length"),
        diameter=_positive("--diameter", args.diameter, "length"),
        groove=_positive("--groove", args.groove, "length", allow_zero=True),
        damping=_positive("--damping", args.damping, "damping", allow_zero=True),
    )
    _positive("--load", args.load, "force")
    speed = _positive("--speed", args.speed, "speed")
    angle = _positive("--angle", args.angle, "angle")
    if angle >= math.pi / 2:
        raise InputError(f"--angle {args.angle}: must be below 90 deg (small-angle model)")
    theta0 = _positive("--disturbance-angle", args.disturbance_angle, "angle")
    if theta0 >= math.pi / 2:
        raise InputError(f"--disturbance-angle {args.disturbance_angle}: must be below 90 deg")
    try:
        omega0 = float(args.angular_velocity)
    except ValueError:
        raise InputError(f"--angular-velocity {args.angular_velocity!r}: expected a number in rad/s") from None
    if not math.isfinite(omega0):
        raise InputError(f"--angular-velocity {args.angular_velocity}: must be finite")
    inertia = PowerLaw() if args.inertia is None else Fixed(_positive("--inertia", args.inertia, "inertia"))
    slip = _positive("--slip-coefficient", args.slip_coefficient, "force")
    duration = None
    if args.duration is not None:
        try:
            duration = float(args.duration)
        except ValueError:
            raise InputError(f"--duration {args.duration!r}: expected a number of seconds") from None
        if not math.isfinite(duration) or duration <= 0 or duration > 60:
            raise InputError(f"--duration {args.duration}: must be between 0 and 60 s")
    conditions = Conditions(disturbance_angle=theta0, slip_coefficient=slip, inertia=inertia)
    return design, conditions, speed, angle, omega0, duration


def run(args) -> int:
    from designer.analysis.simulate import onset_speed, simulate, write_simulation_report

    if args.report is not None:
        result = write_simulation_report(
            args.report, progress=None if args.json else lambda i, n: print(f"\rcase {i}/{n}", end="", file=sys.stderr, flush=True))
        if not args.json:
            eprint("")
        summary = result["summary"]
        if args.json:
            print_json({"report": args.report, "summary": summary})
        else:
            a = summary["all"]
            print(f"wrote {args.report}/report.md, onset.csv, onset.json, onset.png: {summary['cases']} cases, "
                  f"simulated onset vs Eq. 7 from {100 * a['min_error']:+.1f} % to {100 * a['max_error']:+.1f} %")
        return 0

    design, conditions, speed, angle, omega0, duration = parse(args)
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = simulate(design, conditions, speed, angle=angle, angular_velocity=omega0, duration=duration)
        onset = onset_speed(design, conditions, angle=angle, angular_velocity=omega0) if args.find_onset else None
    out = {"design": design.as_dict(), **result.as_dict()}
    if onset is not None:
        out["onset_speed"] = onset.speed
        out["onset_bracket"] = [onset.low, onset.high]
        out["onset_relative_error"] = onset.relative_error
    out["warnings"] = [str(w.message) for w in caught]
    if args.plot:
        _plot(result, args.plot, onset)
        out["plot"] = args.plot
    if args.json:
        print_json(out)
        return 0
    verdict = "GROWS (shimmy)" if result.grows else "decays"
    print(f"Caster: {design.describe()}, I_w = {result.inertia:.4g} kg·m², M_f = {result.friction_moment:.3f} N·m")
    print(f"knock θ_i = {math.degrees(angle):.1f}°, θ'_i = {omega0:g} rad/s, V = {speed:.3f} m/s: {verdict}")
    print(f"  amplitude after transient {result.early_amplitude:.4f} rad (Eq. 4/29B: {result.predicted_amplitude:.4f}),"
          f" late {result.late_amplitude:.4f} rad; late/θ_i = {result.amplitude_ratio:.3f}, "
          f"late/early = {result.growth_ratio:.3f}{' (|θ| reached 1 rad)' if result.diverged else ''}")
    freq = "n/a (motion stopped)" if not math.isfinite(result.frequency) else f"{result.frequency:.1f} rad/s"
    print(f"  frequency {freq} (Eq. 15B: {result.predicted_frequency:.1f} rad/s)")
    print(f"  Eq. 7 critical speed (c_f,eff = M_f/θ_i): {result.critical_speed:.3f} m/s")
    if onset is not None:
        print(f"  simulated onset {onset.speed:.3f} m/s (bracket {onset.low:.3f}–{onset.high:.3f}), "
              f"{100 * onset.relative_error:+.1f} % vs Eq. 7")
    if args.plot:
        print(f"  plot: {args.plot}")
    for w in out["warnings"]:
        print(f"warning: {w}")
    return 0


def _plot(result, path, onset=None) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    if not str(path).lower().endswith((".png", ".svg", ".pdf")):
        raise InputError(f"--plot {path}: expected a .png, .svg or .pdf file name")
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(result.t, np.degrees(result.theta), lw=1)
    amp = math.degrees(result.predicted_amplitude)
    ax.axhline(amp, color="tab:red", ls="--", lw=0.8, label=f"Eq. 29B amplitude ±{amp:.1f}°")
    ax.axhline(-amp, color="tab:red", ls="--", lw=0.8)
    ax.axhline(0, color="k", lw=0.5)
    title = (f"V = {result.speed:.2f} m/s: {'grows' if result.grows else 'decays'}; Eq. 7 V_c = "
             f"{result.critical_speed:.2f} m/s")
    if onset is not None:
        title += f", simulated onset {onset.speed:.2f} m/s"
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("caster angle θ [deg]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    from designer.plots.figures import save_figure

    save_figure(fig, path, dpi=110)
