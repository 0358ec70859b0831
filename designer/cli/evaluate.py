"""``designer evaluate``: analyse one caster (docs/commands.md)."""

from __future__ import annotations

import math
import warnings

import designer
from designer import Conditions, Design, knock_safe_speed
from designer.cli._common import choice_option, inertia_option, print_json, quantity_option, ranged_option
from designer.cli._terminal import console as terminal_console
from designer.errors import InputError
from designer.display import MISSING, percent, shown
from designer.parameters import MODES, OUTPUT_TABLE, PARAMETERS, SURFACES, VARIABLE_TABLE, Parameter
from designer.units import COMMON_UNITS, INCH, written_size
from designer.problem import PHYSICAL_RANGE
from designer.studies.checks import knock_safe_table1_error


LBF, MPH = COMMON_UNITS["lbf"][1], COMMON_UNITS["mph"][1]
"""The pound-force [N] and the mile per hour [m/s] of the table's US units."""


def register(sub) -> None:
    p = sub.add_parser(
        "evaluate",
        help="analyse one caster design",
        description="Analyse one caster: critical shimmy speed (Eq. 7), threshold force (Eq. 4A), "
        "turning effort, swept radius, shimmy frequency (Eq. 15B). Quantities take units: "
        "--trail 2in, --diameter 203.2mm, --damping '1.3 N*m/rad'.",
    )
    p.add_argument("--trail", required=True, help="trail T (e.g. 2in)")
    p.add_argument("--diameter", required=True, help="wheel diameter d (e.g. 8in)")
    p.add_argument("--groove", required=True, help="groove width B (0 for a single tread)")
    p.add_argument("--damping", required=True, help="spindle friction damping c_f = M_f/θ0 (bare fork 1.3 N*m/rad)")
    p.add_argument("--load", default=None, help="caster load L per front caster (default 178 N, the paper's)")
    p.add_argument("--threshold-height", default=None, help="door-sill height h (default 0.5 in)")
    p.add_argument("--target-speed", default=None, help="speed to check for shimmy (optional)")
    p.add_argument("--surface", default="tile", help="tile | carpet").completion_choices = SURFACES
    p.add_argument("--turning-mode", default="chair", help="chair | pivot").completion_choices = MODES
    p.add_argument("--disturbance-angle", default="20 deg", help="design disturbance θ0 (default 20 deg)")
    p.add_argument("--slip-coefficient", default="1250 N", help="tyre slip coefficient K_s (default 1250 N)")
    p.add_argument("--inertia", default=None, help="override I_w [kg·m²] (default: Table 1 power law of d)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument(
        "--verbose", action="store_true", help="the full table: each quantity's source, where the risk comes from"
    )
    p.add_argument(
        "--knock-safe",
        action="store_true",
        help="also simulate the knock-safe speed for knocks of "
        "θ0 and 2 θ0 (Coulomb friction, rolling tyre; about 1-2 s)",
    )
    p.set_defaults(func=run)


def analyse(args) -> tuple[Design, Conditions, dict, float | None]:
    """Parse the options and evaluate; InputError names the option on bad input."""
    # trail, diameter, groove, damping: each parsed first (a unit error before a sign error)
    values = {p.name: quantity_option(getattr(args, p.name), p.dimension, f"--{p.name}") for p in VARIABLE_TABLE}
    for name, value in values.items():
        allow_zero = name in ("groove", "damping")
        if value < 0 or (value == 0 and not allow_zero):
            given = getattr(args, name)
            raise InputError(
                f"--{name} {given!r} ({value:g} {'N·m/rad' if name == 'damping' else 'm'}): must be "
                f"{'non-negative' if allow_zero else 'positive'}"
            )
    design = Design(**{name: ranged_option(getattr(args, name), name, f"--{name}") for name in values})
    c0 = PARAMETERS["bare_fork_damping"].default
    if design.damping < c0:
        raise InputError(
            f"--damping {design.damping:g} N·m/rad: below the bare ball-bearing fork's {c0:g} N·m/rad "
            f"(Eq. 11C), the least spindle damping a caster has; the added damper moment would be negative"
        )
    load = quantity_option(args.load or "178 N", "force", "--load")
    height = quantity_option(args.threshold_height or "0.5 in", "length", "--threshold-height")
    if load <= 0:
        raise InputError(f"--load {args.load}: must be positive")
    if height <= 0:
        raise InputError(f"--threshold-height {args.threshold_height}: must be positive")
    _in_range("--load", "conditions.load", load)
    _in_range("--threshold-height", "conditions.threshold_height", height)
    if design.diameter <= 2 * height:
        raise InputError(
            f"--diameter {args.diameter}: must exceed twice the threshold height ({2 * height / INCH:.3g} in); "
            f"d/h = {design.diameter / height:.3g} <= 2 cannot climb the sill (Eq. 4A)"
        )
    inertia_model = inertia_option(args.inertia)
    angle = quantity_option(args.disturbance_angle, "angle", "--disturbance-angle")
    if not 0 < angle < 1.5708:
        raise InputError(f"--disturbance-angle {args.disturbance_angle}: must be between 0 and 90 deg")
    slip = quantity_option(args.slip_coefficient, "force", "--slip-coefficient")
    if slip <= 0:
        raise InputError(f"--slip-coefficient {args.slip_coefficient}: must be positive")
    _in_range("--slip-coefficient", "shimmy.slip_coefficient", slip)
    conditions = Conditions(
        load=load,
        threshold_height=height,
        surface=choice_option(args.surface, SURFACES, "--surface"),
        turning_mode=choice_option(args.turning_mode, MODES, "--turning-mode"),
        disturbance_angle=angle,
        slip_coefficient=slip,
        inertia=inertia_model,
    )
    speed = quantity_option(args.target_speed, "speed", "--target-speed")
    if speed is not None and speed <= 0:
        raise InputError(f"--target-speed {args.target_speed}: must be positive")
    if speed is not None:
        _in_range("--target-speed", "shimmy.target_speed", speed)

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        caster = designer.evaluate(design, conditions, speed, risk=speed)
    values = dict(caster, risk_law=caster.risk_law)  # and where the risk comes from (None without a speed)
    values["warnings"] = [str(w.message) for w in caught]
    values["sources"] = {  # where the load and the sill came from: shown beside them
        "load": "--load" if args.load else "default: the paper's test load (App. C)",
        "threshold_height": "--threshold-height" if args.threshold_height else "default: a 1/2 in sill (Fig. 2A)",
    }
    return design, conditions, values, speed


def _in_range(option: str, key: str, value: float) -> None:
    """InputError naming ``option`` if ``value`` is outside the problem file's range for ``key``."""
    low, high, unit, hint = PHYSICAL_RANGE[key]
    if not low <= value <= high:
        raise InputError(f"{option} {value:g} {unit}: outside the model's range {low:g} to {high:g} {unit} ({hint})")


def run(args) -> int:
    """``designer evaluate``: the caster's numbers as a table (or ``--json``); exit 0."""
    design, conditions, values, speed = analyse(args)
    out = _results(design, conditions, values, speed, args.knock_safe)
    if args.json:
        print_json(out)
        return 0
    if args.verbose:
        _print_table(design, conditions, values, speed, out, args.knock_safe)
    else:
        _print_screen(design, conditions, values, speed, out, args.knock_safe)
    return 0


def _print_screen(design, conditions, values: dict, speed: float | None, out: dict, knock_safe: bool) -> None:
    """The caster's numbers in one screen: one line a quantity (its name, value and the paper's equation), the
    verdict at the target speed, what to do next; each source in full behind ``--verbose``."""
    lines = [f"Caster: {design.describe()}"]
    rows = _rows(conditions, values, "measured" if values["measured"] else "Table 1's power law")
    if knock_safe:
        rows.insert(4, ("knock-safe speed, θ0 / 2 θ0 knock", _knock_safe_value(out), "simulated"))
    name_width = max(len(r[0]) for r in rows)
    value_width = max(len(r[1]) for r in rows)
    for name, value, source in rows:
        short = source if len(source) <= 20 and source.startswith(("Eq.", "Table", "measured", "--")) else ""
        if source.startswith("default"):
            short = "default"
        lines.append(f"  {name:<{name_width}}  {value:>{value_width}}  {short}".rstrip())
    if speed is not None:
        risk = out["risk"]
        at = shown(speed, "target_speed")
        verdict = (
            f"At {at}: Eq. 7 alone says it {'is stable' if values['critical_speed'] >= speed else 'shimmies'}; "
            f"with the model's scatter it shimmies with probability {percent(risk['probability'])} "
            f"(± {shown(risk['se'], dimension='probability', digits=2)})."
        )
        lines.append(verdict)
    lines.append(
        "Next: designer run PROBLEM for the caster to build; --verbose: each quantity's source"
        + (" and where the risk comes from" if speed is not None else "")
        + "."
    )
    print("\n".join(lines))
    _print_warnings(design, values, out)


def _rows(conditions, values: dict, inertia_source: str) -> list[tuple[str, str, str]]:
    """(name, value, source) of the load and the sill, each with where it came from (the option or the paper's
    default), then of each listed output in the parameter table's order (I_w first, ``inertia_source`` beside it)."""
    given, sources = values["sources"], {"inertia": inertia_source}
    rows = [(PARAMETERS[n].label, shown_quantity(getattr(conditions, n), PARAMETERS[n]), given[n]) for n in given]
    return rows + [
        (p.label, shown_quantity(values[p.name], p), sources.get(p.name, p.source))
        for p in OUTPUT_TABLE
        if p.listed and p.name in values
    ]


def _knock_safe_value(out: dict) -> str:
    """The knock-safe speeds for a θ0 and a 2 θ0 knock [m/s] (the second missing at or beyond 90°)."""
    double = out["knock_safe_speed_double"]
    return f"{out['knock_safe_speed']:.3f} / " + (MISSING if double is None else f"{double:.3f}") + " m/s"


def _print_warnings(design, values: dict, out: dict) -> None:
    """The evaluation's warnings, or the extrapolation of the inertia fit when none said it."""
    for w in values["warnings"]:
        print(f"warning: {w}")
    if out["extrapolated"] and not values["warnings"]:
        print(
            f"warning: d = {written_size(design.diameter, 'in')} lies outside Table 1's 4–8 in: the inertia fit and "
            "Eq. 7's check are extrapolated"
        )


def _results(design, conditions, values: dict, speed: float | None, knock_safe: bool) -> dict:
    """The numbers of ``--json`` (SI units); the knock-safe speeds are simulated only when asked for."""
    out = {"design": design.to_dict(), "load": conditions.load, "threshold_height": conditions.threshold_height}
    out.update({p.name: values[p.name] for p in OUTPUT_TABLE if p.listed and p.name in values})
    out["extrapolated"] = bool(values["extrapolated"])
    if speed is not None:
        out["target_speed"] = speed
        out["shimmy_margin"] = values["critical_speed"] - speed
        out["stable_at_target"] = values["critical_speed"] >= speed
        out["growth_rate"] = values["growth_rate"]
        out["risk"] = {"probability": values["shimmy_probability"], "se": values["shimmy_probability_se"]}
        out["risk"].update(values["risk_law"])  # its sources, each with its share, and the dominant one
    if knock_safe:  # simulated, about 1-2 s: only on request
        theta0 = conditions.disturbance_angle
        with warnings.catch_warnings():  # the same extrapolation as the evaluation's, said once
            warnings.simplefilter("ignore", UserWarning)
            out["knock_safe_speed"] = knock_safe_speed(design, conditions)
            out["knock_safe_speed_double"] = (
                knock_safe_speed(design, conditions, angle=2 * theta0) if 2 * theta0 < 1.5708 else None
            )
        band = knock_safe_table1_error(theta0)
        out["knock_safe_table1"] = {"log_rms": band["log_rms"], "bias": band["bias"], "angle": band["angle"]}
    out["warnings"] = values["warnings"]
    return out


def _print_table(design, conditions, values: dict, speed: float | None, out: dict, knock_safe: bool) -> None:
    """The rich table of the text output: each quantity with its value (SI and US units) and its paper source."""
    from rich.table import Table

    table = Table(title=f"Caster: {design.describe()}", title_justify="left")
    words = [w for p in OUTPUT_TABLE if p.listed for w in p.source.split()]
    table.add_column("quantity", max_width=20)
    table.add_column("value", justify="right", max_width=20)
    table.add_column("source", min_width=max(map(len, words)))  # wrapped at words: a link is never split
    rows = _rows(conditions, values, conditions.inertia.describe())  # which inertia model: beside I_w
    if knock_safe:  # beside V_c
        theta0, band = math.degrees(conditions.disturbance_angle), out["knock_safe_table1"]
        source = (
            f"simulated (App. B); against Table 1 C–G: log RMS {band['log_rms']:.3f}, bias {band['bias']:+.3f} "
            "(a second opinion: the criterion is the Eq. 7 risk bound)"
        )
        rows.insert(2, (f"knock-safe speed, {theta0:.0f}° / {2 * theta0:.0f}° knock", _knock_safe_value(out), source))
    if speed is not None:
        rows += _speed_rows(values, speed, out["risk"])
    for row in rows:
        table.add_row(*row)
    console = terminal_console()
    console.print(table)
    if speed is not None:
        _print_sources(console, out["risk"])
    _print_warnings(design, values, out)


def shown_quantity(value: float, p: Parameter) -> str:
    """``value`` [SI] of entry ``p`` of the parameter table as the table shows it: lengths in mm and inches,
    forces in N and lbf (to the entry's ``digits``), speeds in m/s and mph, angles in rad and degrees, the rest in its SI unit."""
    if p.dimension == "length":
        return f"{value * 1000:.1f} mm ({value / INCH:.3f} in)"
    if p.dimension == "force":
        return f"{value:.{p.digits or 2}f} N ({value / LBF:.{p.digits or 2}f} lbf)"
    if p.dimension == "speed":
        return f"{value:.3f} m/s ({value / MPH:.2f} mph)"
    if p.dimension == "angle":
        return f"{value:.4g} rad ({math.degrees(value):.3g}°)"
    return f"{value:.4g} {p.unit}".rstrip()


def _speed_rows(values: dict, speed: float, risk: dict) -> list[tuple[str, str, str]]:
    """The rows at the target speed: Eq. 7's verdict alone, the growth rate (Eq. 12B), P(shimmy) ± SE."""
    verdict = "stable" if values["critical_speed"] >= speed else "SHIMMIES"
    gap = f"{verdict}, V_c − speed {values['critical_speed'] - speed:+.3f} m/s (the risk is below)"
    return [
        (f"at {speed:.2f} m/s, Eq. 7 alone", gap, "Eq. 7"),
        ("growth rate μ at that speed", f"{values['growth_rate']:+.3g} 1/s", "Eq. 12B"),
        (
            f"P(shimmy at {speed:.2f} m/s)",
            f"{100 * risk['probability']:.2f} % ± {100 * risk['se']:.2f} %",
            "Monte Carlo of the risk law (docs/model.md, Shimmy risk)",
        ),
    ]


def _print_sources(console, risk: dict) -> None:
    """Where the risk comes from: each source of the law with its share of the variance of log V_c."""
    from rich.table import Table

    table = Table(title="Where the risk comes from", title_justify="left")
    for col in ("source", "distribution of its log", "scale", "kind", "share of var log V_c"):
        table.add_column(col)
    for src in risk["sources"]:
        dist = src["distribution"] + (f", ν = {src['dof']}" if src["dof"] else "")
        table.add_row(src["name"], dist, f"{src['scale']:.4g}", src["kind"], f"{100 * src['share']:.1f} %")
    console.print(table)
    console.print(risk["dominant"])
