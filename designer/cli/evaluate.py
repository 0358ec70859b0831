"""``designer evaluate``: analyse one caster (docs/commands.md)."""

from __future__ import annotations

import warnings

import designer
from designer import Conditions, Design
from designer.cli._common import api_named, inertia_option, print_json, quantity_option, ranged_option
from designer.cli._terminal import console as terminal_console, table
from designer.cli.simulate import knock_safe_speeds
from designer.errors import InputError
from designer.display import label, number, percent, shown
from designer.parameters import MODES, OUTPUT_TABLE, PARAMETERS, SURFACES, VARIABLE_TABLE
from designer.units import written_size
from designer.studies.checks import knock_safe_table1_error


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
    # trail, diameter, groove, damping: each parsed, then within the parameter table's range (a problem file's)
    design = Design(**{p.name: ranged_option(getattr(args, p.name), p.name, f"--{p.name}") for p in VARIABLE_TABLE})
    c0 = PARAMETERS["bare_fork_damping"].default
    if design.damping < c0:
        raise InputError(
            f"--damping {shown(design.damping, 'damping')}: below the bare ball-bearing fork's "
            f"{shown(c0, 'damping')} (Eq. 11C), the least spindle damping a caster has; the added damper moment "
            "would be negative"
        )
    numbers = {  # each checked by Conditions as a problem file's [conditions], its message naming the option
        name: quantity_option(getattr(args, name), PARAMETERS[name].dimension, option, PARAMETERS[name].default)
        for name, option in CONDITION_OPTIONS.items()
        if name in PARAMETERS
    }
    with api_named({f"{name} ": f"{option} " for name, option in CONDITION_OPTIONS.items()}):
        conditions = Conditions(
            **numbers, surface=args.surface, turning_mode=args.turning_mode, inertia=inertia_option(args.inertia)
        )
    height = conditions.threshold_height
    if design.diameter <= 2 * height:
        raise InputError(
            f"--diameter {args.diameter}: must exceed twice the threshold height "
            f"({shown(2 * height, 'diameter', 'in')}); "
            f"d/h = {number(design.diameter / height)} <= 2 cannot climb the sill (Eq. 4A)"
        )
    speed = ranged_option(args.target_speed, "target_speed", "--target-speed")
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


CONDITION_OPTIONS = {
    name: "--" + name.replace("_", "-")
    for name in ("load", "threshold_height", "surface", "turning_mode", "disturbance_angle", "slip_coefficient")
}
"""The conditions the options set, each by its name in :class:`designer.Conditions` (whose checks name it)."""


def run(args) -> int:
    """``designer evaluate``: the caster's numbers as a table (or ``--json``); exit 0."""
    design, conditions, values, speed = analyse(args)
    out = _results(design, conditions, values, speed, args.knock_safe)
    if args.json:
        print_json(out)
    elif args.verbose:
        _print_table(design, conditions, values, speed, out)
    else:
        _print_screen(design, conditions, values, speed, out)
    return 0


def _print_screen(design, conditions, values: dict, speed: float | None, out: dict) -> None:
    """The caster's numbers in one screen: one line a quantity (its name, value and the paper's equation), the
    verdict at the target speed, what to do next; each source in full behind ``--verbose``."""
    lines = [f"Caster: {design.describe()}"]
    rows = _rows(conditions, values, "measured" if values["measured"] else "Table 1's power law", out)
    name_width = max(len(r[0]) for r in rows)
    value_width = max(len(r[1]) for r in rows)
    for name, value, source in rows:
        short = source if len(source) <= 20 and source.startswith(("Eq.", "Table", "measured", "--")) else ""
        short = next((word for word in ("default", "simulated") if source.startswith(word)), short)
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


def _rows(conditions, values: dict, inertia_source: str, out: dict) -> list[tuple[str, str, str]]:
    """(name, value, source) of the load and the sill, each with where it came from (the option or the paper's
    default), then of each listed output in the parameter table's order (I_w first, ``inertia_source`` beside it,
    the knock-safe speeds after V_c when simulated); each value through :func:`designer.display.shown`, lengths
    in inches (the paper's)."""
    given, sources = values["sources"], {"inertia": inertia_source}
    rows = [(label(n), shown(getattr(conditions, n), n, "in"), given[n]) for n in given]
    rows += [
        (p.label, shown(values[p.name], p.name, "in"), sources.get(p.name, p.source))
        for p in OUTPUT_TABLE
        if p.listed and p.name in values
    ]
    if "knock_safe_table1" in out:
        band = out["knock_safe_table1"]
        source = (
            f"simulated (App. B); against Table 1 C–G: log RMS {number(band['log_rms'])}, bias "
            f"{number(band['bias'])} (a second opinion: the criterion is the Eq. 7 risk bound)"
        )
        speeds = " / ".join(
            shown(out[key], "critical_speed") for key in ("knock_safe_speed", "knock_safe_speed_double")
        )
        rows.insert(4, ("knock-safe speed, θ0 / 2 θ0 knock", speeds, source))  # the second missing at or beyond 90°
    return rows


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
            speeds = knock_safe_speeds(design, conditions, theta0, None)
        out |= {key: speeds[key] for key in ("knock_safe_speed", "knock_safe_speed_double")}
        band = knock_safe_table1_error(theta0)
        out["knock_safe_table1"] = {"log_rms": band["log_rms"], "bias": band["bias"], "angle": band["angle"]}
    out["warnings"] = values["warnings"]
    return out


def _print_table(design, conditions, values: dict, speed: float | None, out: dict) -> None:
    """The rich table of the text output: each quantity with its value and its paper source."""
    words = [w for p in OUTPUT_TABLE if p.listed for w in p.source.split()]
    columns = [("quantity", {"max_width": 20}), ("value", {"justify": "right", "max_width": 20})]
    columns += [("source", {"min_width": max(map(len, words))})]  # wrapped at words: a link is never split
    rows = _rows(conditions, values, conditions.inertia.describe(), out)  # which inertia model: beside I_w
    if speed is not None:  # at the target speed: Eq. 7's verdict alone, the growth rate (Eq. 12B), P(shimmy) ± SE
        verdict = "stable" if values["critical_speed"] >= speed else "SHIMMIES"
        gap = f"{verdict}, V_c − speed {shown(values['critical_speed'] - speed, 'critical_speed')} (the risk is below)"
        at = shown(speed, "target_speed")
        rows += [
            (f"at {at}, Eq. 7 alone", gap, "Eq. 7"),
            ("growth rate μ at that speed", shown(values["growth_rate"], "growth_rate"), "Eq. 12B"),
            (
                f"P(shimmy at {at})",
                f"{percent(out['risk']['probability'])} ± {percent(out['risk']['se'])}",
                "Monte Carlo of the risk law (docs/model.md, Shimmy risk)",
            ),
        ]
    console = terminal_console()
    console.print(table(f"Caster: {design.describe()}", columns, rows))
    if speed is not None:
        risk = out["risk"]
        columns = ("source", "distribution of its log", "scale", "kind", "share of var log V_c")
        rows = [
            (src["name"], src["distribution"] + (f", ν = {src['dof']}" if src["dof"] else ""), number(src["scale"]))
            + (src["kind"], percent(src["share"]))
            for src in risk["sources"]
        ]
        console.print(table("Where the risk comes from", columns, rows))
        console.print(risk["dominant"])
    _print_warnings(design, values, out)
