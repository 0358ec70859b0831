"""``designer init PATH``: start a problem file from a few answers (docs/commands.md, docs/problem-file.md).

At a terminal it asks for the load (or the mass and the front fraction), the sill, the floor, the target
speed and the units, each with its default; an option answers its question (``--sill 3/4in``), ``--defaults``
or a standard input that is not a terminal asks nothing.  Every other value (the design ranges, the swept
radius) is the shipped default problem's (``indoor-manual``).  The file is checked by the problem loader
before it is written, and an existing file is never replaced.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

from designer import load_problem, problem_from_toml
from designer.cli._common import quantity_option
from designer.display import shown
from designer.errors import DesignerError, InputError
from designer.output import FileKind, check_file, write_file
from designer.parameters import MASS_RANGE, PARAMETERS, SURFACES
from designer.problem import REPORT_UNITS
from designer.units import INCH

NEW_FILE = FileKind("a new file", new_only=True)
"""What designer init writes: only a new (or empty) file; no existing file is ever its to replace."""

DEFAULT_PROBLEM = "indoor-manual"
"""The shipped problem whose values are the defaults of ``designer init``."""

FRONT_FRACTION = 0.4
"""Default share f of the user-plus-chair weight on the two front casters [-]: the paper's test load of
178 N per caster (Appendix C) is f = 2 x 178 N / (90 kg x 9.80665 m/s^2) = 0.40 for a 75 kg user in a
15 kg chair (the default problem's chair)."""

FRONT_FRACTION_TYPICAL = (0.2, 0.4)
"""Typical range of f for manual chairs [-] (our estimate from the statics, not the paper's): f is the
distance from the rear axle to the centre of mass over the wheelbase; a rigid chair set up with its rear axle
forward under the user (easy to tip, light casters) is near 0.2, a folding chair with the axle behind the
backrest near 0.4.  Weigh the chair: f = (weight on the two front casters) / (total weight)."""

FRONT_FRACTION_NOTE = (
    f"the share of the user-plus-chair weight on the two front casters: typically "
    f"{FRONT_FRACTION_TYPICAL[0]:g} to {FRONT_FRACTION_TYPICAL[1]:g} for a manual chair (rear axle forward: "
    f"{FRONT_FRACTION_TYPICAL[0]:g}; behind the backrest: {FRONT_FRACTION_TYPICAL[1]:g}); measure it with a "
    "scale under the front casters"
)
"""The words that explain the front fraction, in the prompt and in the file written."""


def register(sub) -> None:
    p = sub.add_parser(
        "init",
        help="start a commented problem file from a few answers",
        description="Write a commented problem file: asks for the load (or mass and front fraction), the sill, "
        "the floor, the target speed and the units at a terminal; options answer the questions; without a "
        "terminal, or with --defaults, writes the defaults (the shipped indoor-manual problem). Never "
        "replaces a file. Then: designer run PATH.",
    )
    p.add_argument("path", metavar="PATH", help="the problem file to write (TOML), e.g. my-chair.toml")
    p.add_argument("--load", default=None, help="load per front caster, e.g. 178N (default the paper's 178 N)")
    p.add_argument(
        "--mass",
        default=None,
        help="the user plus the chair, e.g. 110kg for a 95 kg user in a 15 kg chair (instead of --load)",
    )
    p.add_argument(
        "--front-fraction", default=None, help=f"with --mass (default {FRONT_FRACTION:g}): {FRONT_FRACTION_NOTE}"
    )
    p.add_argument("--sill", default=None, help="door-sill height, e.g. 3/4in or 19mm (default 1/2 in)")
    p.add_argument("--floor", default=None, help="tile | carpet (default tile)").completion_choices = SURFACES
    p.add_argument("--target-speed", default=None, help="speed without shimmy, e.g. 2.5m/s (default 2.5 m/s)")
    p.add_argument(
        "--units", default=None, help="in | mm: the unit of the lengths written (default in)"
    ).completion_choices = REPORT_UNITS
    p.add_argument("--defaults", action="store_true", help="ask nothing: the options given, else the defaults")
    p.set_defaults(func=run)


@dataclass(frozen=True)
class Answers:
    """The answers a problem file is written from (SI): either ``load`` or ``mass`` and ``front_fraction``."""

    load: float | None
    mass: float | None
    front_fraction: float | None
    sill: float
    floor: str
    target_speed: float
    units: str


def run(args) -> int:
    """Write the problem file ``args.path`` from the answers; exit 0, or 7 if it exists or cannot be written."""
    path = Path(args.path)
    check_file(path, "PATH", example="my-chair.toml", kind=NEW_FILE)  # before any question; never over anything
    interactive = sys.stdin is not None and sys.stdin.isatty() and not args.defaults
    answers = _ask(args) if interactive else _answers(vars(args))
    text = problem_text(answers, path.stem)
    load = _check(text, path).conditions.load  # L = m g f / 2 of the loader when given the mass
    write_file(path, text, "PATH", example="my-chair.toml", kind=NEW_FILE)
    by_mass = answers.mass is not None
    print(f"wrote {path}: {shown(load, 'load')} per front caster" + (" = m g f / 2" if by_mass else ""))
    if by_mass:
        f = answers.front_fraction
        print(f"  with m = {answers.mass:g} kg (user plus chair), front fraction f = {f:g}")
        if not interactive and args.front_fraction is None:
            low, high = FRONT_FRACTION_TYPICAL
            print(f"  f = {f:g} is the default (typically {low:g} to {high:g}); weigh yours: --front-fraction")
    print(f"next: designer run {path}")
    return 0


SILL_RANGE = (0.1 * INCH, 2 * INCH)
"""Door-sill heights ``designer init`` accepts [m]: a floor transition to a 2 in step (the US accessibility limit
for a door threshold is 1/2 in, 3/4 in for an existing sliding door: 2010 ADA Standards 404.2.5; a higher step
is climbed by no caster of the shipped stock, whose largest wheel, 8 in, needs d > 2 h)."""

_QUESTIONS = (
    ("mass", "User plus chair mass, e.g. 90 kg (empty: give the load instead)"),
    ("front_fraction", "Front fraction f: weight on the front casters / total (0.2–0.4)"),
    ("load", "Load per front caster, e.g. 178 N"),
    ("sill", "Door-sill height, e.g. 1/2 in or 13 mm"),
    ("floor", "Floor (tile or carpet)"),
    ("target_speed", "Fastest speed without shimmy, e.g. 2.5 m/s"),
    ("units", "Units of the lengths in the file (in or mm)"),
)
"""What ``designer init`` asks at a terminal, in order (an option given answers its question); each prompt with
its default fits 80 columns and names no option."""

_KINDS = {
    "mass": ("mass", "kg", 1.0, MASS_RANGE, "e.g. 90 kg"),
    "front_fraction": ("dimensionless", "", 1.0, (0.0, 1.0), "e.g. 0.3"),
    "load": ("force", "N", 1.0, PARAMETERS["load"].range, "e.g. 178 N"),
    "sill": ("length", "in", INCH, SILL_RANGE, "e.g. 1/2 in or 13 mm"),
    "target_speed": ("speed", "m/s", 1.0, PARAMETERS["target_speed"].range, "e.g. 2.5 m/s"),
}
"""Each numeric question: its dimension, the unit its range is said in (and that unit in SI), its range [SI] (the
parameter table's where it has one) and an example answer."""

_CHOICES = {"floor": (SURFACES, "a floor this tool knows"), "units": (REPORT_UNITS, "a unit system it writes")}
"""Each question with a fixed set of answers, and what a wrong answer is not."""


def reply_reason(key: str, reply: str, units: str = "in") -> str | None:
    """Why ``reply`` to the question ``key`` cannot be taken, in plain words ("not a number", "out of range
    0.1–2 in", "not a floor this tool knows: tile or carpet"), or None when it can; ``units``: the system a length's
    range is said in."""
    if key in _CHOICES:
        allowed, what = _CHOICES[key]
        return None if reply in allowed else f"not {what}: {' or '.join(allowed)}"
    dimension, unit, factor, (low, high), example = _KINDS[key]
    if not any(ch.isdigit() for ch in reply):
        return f"not a number; {example}"
    try:
        value = quantity_option(reply, dimension, "answer")
    except InputError:
        return f"not a {'number' if dimension == 'dimensionless' else dimension}; {example}"
    if dimension == "length" and units == "mm":
        unit, factor = "mm", 0.001
    if not low < value <= high if key == "front_fraction" else not low <= value <= high:
        span = f"{low / factor:.3g}–{high / factor:.3g}{' ' + unit if unit else ''}"
        return f"out of range {span}" + (" (above 0)" if key == "front_fraction" else "")
    return None


def _ask(args) -> Answers:
    """Ask each question an option did not answer; an empty answer takes the default, a bad one asks again."""
    given = dict(vars(args))
    defaults = _defaults()
    for key, question in _QUESTIONS:
        by_mass = given.get("mass") is not None  # the front fraction with the mass, else the load
        if given.get(key) is not None or key == ("load" if by_mass else "front_fraction"):
            continue
        default = f"{FRONT_FRACTION:g}" if key == "front_fraction" else (defaults.get(key) or "")
        while True:
            try:
                reply = input(f"{question} [{default or 'none'}]: ").strip()
            except EOFError:
                reply = ""
            given[key] = reply or (default if key != "mass" else None)
            reason = reply_reason(key, reply, given.get("units") or defaults["units"]) if reply else None
            if reason is not None:
                print(f"  {reply!r}: {reason}", file=sys.stderr)
                continue
            try:
                _answers({**given, **{k: None for k, _ in _QUESTIONS if k not in given}})
                break
            except InputError as exc:
                print(f"  {exc}", file=sys.stderr)
    return _answers(given)


def _defaults() -> dict[str, str]:
    """The defaults of the questions, as written answers: the shipped default problem's values."""
    p = load_problem(DEFAULT_PROBLEM)
    return {
        "load": f"{p.conditions.load:g} N",
        "sill": f"{p.conditions.threshold_height / INCH:g} in",
        "floor": p.conditions.surface,
        "target_speed": f"{p.target_speed:g} m/s",
        "units": p.units,
    }


def _answers(given: dict) -> Answers:
    """The answers from the options (or replies) in ``given``, each checked as its reply (:func:`reply_reason`)
    and named by its option; the rest defaults."""
    mass, fraction = given.get("mass"), given.get("front_fraction")
    if given.get("load") is not None and (mass is not None or fraction is not None):
        raise InputError("--load and --mass: give the load per caster, or the mass and --front-fraction, not both")
    if fraction is not None and mass is None:
        raise InputError(f"--front-fraction {fraction}: needs --mass (load = mass g front_fraction / 2)")
    replies = {key: given.get(key) or _defaults().get(key) for key, _ in _QUESTIONS}
    replies |= {"mass": mass, "front_fraction": fraction or f"{FRONT_FRACTION:g}"} if mass is not None else {}
    replies |= {"load": None} if mass is not None else {"mass": None, "front_fraction": None}
    units, values = replies["units"], {}
    for key, reply in sorted(replies.items(), key=lambda item: item[0] != "units"):  # the units first
        reason = None if reply is None else reply_reason(key, reply, units)
        if reason is not None:
            raise InputError(f"--{key.replace('_', '-')} {reply}: {reason}")
        values[key] = reply if reply is None or key in _CHOICES else quantity_option(reply, _KINDS[key][0], "answer")
    return Answers(**values)


def problem_text(a: Answers, name: str) -> str:
    """The problem file's TOML for the answers ``a``: a comment line above every key it writes (what the key
    means, its unit, where its value came from); the design ranges and the swept radius from the default problem."""
    base = load_problem(DEFAULT_PROBLEM)
    # a length [m] as the file writes it: "0.75 in" or "19.05 mm" (to 1e-6 of the unit)
    L = lambda v: f'"{round(v / INCH, 6):g} in"' if a.units == "in" else f'"{round(v * 1000, 6):g} mm"'  # noqa: E731
    if a.load is not None:
        load = [
            "# load: the weight on one front caster (the paper tested at 178 N, Appendix C)",
            f'load = "{a.load:g} N"',
        ]
    else:
        load = [
            "# mass: the user plus the chair; the load per front caster is L = mass g front_fraction / 2",
            f'mass = "{a.mass:g} kg"',
            f"# front_fraction: {FRONT_FRACTION_NOTE}",
            f"front_fraction = {a.front_fraction:g}",
        ]
    b, stock = base.bounds, base.stock
    assert stock is not None  # the shipped default problem has a [stock] section
    lengths = lambda values: "[" + ", ".join(L(v) for v in values) + "]"  # noqa: E731
    lines = [
        "# A problem file written by designer init; every key is explained in docs/problem-file.md.",
        "# Check it, then: designer run THIS-FILE",
        "# name: the problem's name in reports and results/<name>/",
        f'name = "{name}"',
        "# title: one line describing the chair",
        f'title = "{name}: {a.floor} floor, {L(a.sill)[1:-1]} sills"',
        "",
        "[conditions]",
        *load,
        "# threshold_height: the door sill or floor transition the caster must climb (Eq. 4A)",
        f"threshold_height = {L(a.sill)}",
        "# surface: the floor the chair turns on, tile or carpet (turning effort, Fig. 7)",
        f'surface = "{a.floor}"',
        "# turning_mode: chair (turning the chair in place) or pivot (a non-rolling wheel, the drill-press test)",
        f'turning_mode = "{base.conditions.turning_mode}"',
        "",
        "[shimmy]",
        "# target_speed: the fastest the chair goes (a fast push, a ramp) and must not shimmy at (Eq. 7)",
        f'target_speed = "{a.target_speed:g} m/s"',
        "",
        "[variables]",
        "# the ranges the design may take: trail T, wheel diameter d, groove width B, spindle damping c_f",
        "# trail: the fork's offset behind the stem",
        f"trail = {{ min = {L(b['trail'].low)}, max = {L(b['trail'].high)} }}",
        "# diameter: the wheel's outer diameter (Table 1's wheels are 4 to 8 in)",
        f"diameter = {{ min = {L(b['diameter'].low)}, max = {L(b['diameter'].high)} }}",
        "# groove: the width of the tread's groove (0 for a single tread)",
        f"groove = {{ min = {L(b['groove'].low)}, max = {L(b['groove'].high)} }}",
        "# damping: the spindle friction damping M_f/theta0 (1.3 N*m/rad is the bare fork, Eq. 11C)",
        f'damping = {{ min = "{b["damping"].low:g} N*m/rad", max = "{b["damping"].high:g} N*m/rad" }}',
        "",
        "[constraints]",
        "# swept_radius_max: the room the swivelling caster has (T + d/2), e.g. clear of the footrests",
        f"swept_radius_max = {L(base.swept_radius_max)}",
        "",
        "[stock]",
        "# the parts a seating shop can fit (the shipped problem's): the recommendation is built from them;",
        "# change them to what you can buy (docs/problem-file.md#stock)",
        "# diameters: the wheel sizes on offer",
        f"diameters = {lengths(stock.diameters)}",
        "# grooves: the tyre grooves on offer (0: a single tread)",
        f"grooves = {lengths(stock.grooves)}",
        "# trail_step: the spacing of the fork's axle holes (the trails on offer, within the trail's range)",
        f"trail_step = {L(stock.trail_step)}",
        "# dampings: the bare bearing (1.3 N*m/rad) and the friction washers on offer",
        "dampings = [" + ", ".join(f'"{c:g} N*m/rad"' for c in stock.dampings) + "]",
        "",
        "[report]",
        "# units: how reports write sizes, in (to 1/16) or mm",
        f'units = "{a.units}"',
    ]
    return "\n".join(lines) + "\n"


def _check(text: str, path: Path):
    """The problem of ``text``, or InputError (exit 2) if the problem loader refuses it: nothing is written then."""
    try:
        return problem_from_toml(text, source=str(path), default_name=path.stem)
    except DesignerError as exc:
        raise InputError(f"the answers do not make a valid problem: {exc}") from None
