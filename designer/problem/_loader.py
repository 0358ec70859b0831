"""The problem-file loader: TOML text or a dict with the problem-file schema -> a validated :class:`Problem`.

Schema: docs/problem-file.md (:data:`designer.problem._core.SCHEMA` lists the keys that are not quantities;
the quantities come from :mod:`designer.parameters`).  Every error is one line naming the key, the value
and the reason.  :mod:`designer.problem._core` holds the :class:`Problem` record and its validation.
"""

from __future__ import annotations

import contextlib
import difflib
import math
import os
import re
import tomllib
from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Any, Callable, NoReturn, TypeVar

from designer.data.paper import TABLE1
from designer import parameters
from designer.errors import ProblemError
from designer.textfiles import read_input_text
from designer.model import (
    CONDITION_CHOICES,
    CONDITION_NUMBERS,
    MASS_RANGE,
    MODEL_RANGE,
    VARIABLES,
    Conditions,
    caster_load,
    condition_refusal,
)
from designer.physics.inertia import Catalog, Disc, Fixed, InertiaModel, PowerLaw
from designer.physics.turning import MODES, SURFACES
from designer.units import InputError, example, outside_range, parse_quantity, real_number
from designer.physics.uncertainty import Uncertainty

from designer.problem._stock import read_stock
from designer.problem._core import (
    inches,
    parsed,
    show_key,
    DEFAULT_BOUNDS,
    DEFAULT_MAX_THRESHOLD_INCREASE,
    DEFAULT_MAX_TURNING_INCREASE,
    INERTIA_MODELS,
    MAX_SAMPLES,
    PROBABILITY_RANGE,
    SCHEMA,
    VARIABLE_DIMENSIONS,
    TOLERANCE_MAX_LENGTH,
    Bound,
    Problem,
    Tolerances,
)

_D = TypeVar("_D")
"""The default of an optional quantity: a float, or None for 'not given'."""


def problem_files(where: str | Path = "problems") -> list[Path]:
    """The problem files in folder ``where`` (sorted), or ``[where]`` if it is a file.

    Raises InputError if the folder holds no ``*.toml`` file.
    """
    path = Path(where)
    if path.is_file():
        return [path]
    files = sorted(path.glob("*.toml"))
    if not files:
        raise InputError(f"{where}: no problem files (*.toml) found")
    return files


MAX_PROBLEM_BYTES = 2**20
"""A problem file is a few kB of TOML; a larger one (or an endless one such as /dev/zero) is refused unread."""


def shipped_folder() -> Traversable:
    """The folder of the shipped example problems (package data: ``designer/data/problems``)."""
    return resources.files("designer.data") / "problems"


def example_names() -> list[str]:
    """The names of the shipped example problems, sorted (``"indoor-manual"``, ``"paper-invacare"``, ...)."""
    return sorted(e.name[: -len(".toml")] for e in shipped_folder().iterdir() if e.name.endswith(".toml"))


def problem_path(spec: str | Path) -> Path:
    """The problem file that ``spec`` names: the path itself when it exists, else the shipped example problem
    of that name (``"indoor-manual"`` or ``"indoor-manual.toml"`` without a folder), from any working folder.

    A path that is neither is returned as it is (:func:`load_problem` then says there is no such file and
    lists the shipped names).
    """
    path = Path(spec)
    if os.path.lexists(path) or path.parent != Path("."):
        return path
    name = path.name.removesuffix(".toml")
    if name in example_names():
        return Path(str(shipped_folder() / f"{name}.toml"))
    return path


def problem_argument(value: Any, argument: str = "problem") -> Problem:
    """The API's problem argument (``designer.optimise``, ``pareto_front``, ``recommend``, ``fix``, ``fleet``,
    ``explore``): a :class:`Problem` as it is, a problem file's path or a shipped problem's name read by
    :func:`load_problem` (its rules and messages); anything else is one InputError line naming ``argument``."""
    if isinstance(value, Problem):
        return value
    if isinstance(value, (str, os.PathLike)):
        return load_problem(os.fspath(value))
    raise InputError(
        f"{argument} = {value!r}: expected a designer.Problem, a problem file's path or a shipped problem's name "
        f"(e.g. designer.load_problem('problems/indoor-manual.toml'))"
    )


def _missing(path: Path) -> bool:
    """True only when nothing is at ``path`` (not for a name too long or a link loop: their own reasons)."""
    try:
        os.lstat(path)
    except FileNotFoundError:
        return True
    except OSError:
        return False
    return False


def load_problem(path: str | os.PathLike[str]) -> Problem:
    """Read and validate a problem file (TOML, docs/problem-file.md); at most :data:`MAX_PROBLEM_BYTES` are read.

    ``path`` may also be the name of a shipped example problem (``"indoor-manual"``) when no such file exists
    (:func:`problem_path`): what ``designer run indoor-manual`` reads from any folder.

    Raises
    ------
    ProblemError
        One line: the file, the key, the value and the reason (TOML syntax
        errors with their line number); for a missing file, the shipped names.
    """
    given = Path(path)
    path = problem_path(given)
    if given.parent == Path(".") and _missing(path):  # a link loop, a name too long: read_input_text says so
        raise ProblemError(
            f"{given}: no such problem file, nor a shipped problem of that name ({', '.join(example_names())})"
        )
    text = read_input_text(path, "problem file", ".toml", limit=MAX_PROBLEM_BYTES)
    shipped = path != given  # a shipped problem by its name: the name is what the user wrote, and reads it again
    return problem_from_toml(text, source=str(given if shipped else path), default_name=path.stem)


def problem_from_toml(text: str, source: str | None = None, default_name: str = "problem") -> Problem:
    """Parse TOML text into a validated :class:`Problem` (see :func:`load_problem`)."""
    prefix = f"{source}: " if source else ""
    text = text.removeprefix("\ufeff")  # a UTF-8 byte-order mark (Windows editors write one): not TOML, not content
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ProblemError(f"{prefix}TOML syntax error: {exc}") from None
    except ValueError as exc:  # e.g. an integer literal of more than 4300 digits
        raise ProblemError(f"{prefix}cannot read the file: {exc}") from None
    except RecursionError:  # tomllib reads nested arrays and inline tables by recursion
        raise ProblemError(
            f"{prefix}nested too deeply to read (brackets or inline tables thousands of levels deep); a problem "
            f"file has sections of keys and short lists"
        ) from None
    try:
        return problem_from_dict(data, source=source, default_name=default_name)
    except RecursionError:  # a nested value echoed in a message
        raise ProblemError(f"{prefix}a value nested too deeply to read; a problem file has short lists") from None


class _Reader:
    """The problem-file dict with its one-line errors: each reader names the key, the value and the reason."""

    def __init__(self, data: dict[str, Any], prefix: str) -> None:
        self.data = data
        self.prefix = prefix

    def fail(self, msg: str) -> NoReturn:
        raise ProblemError(self.prefix + msg)

    def section(self, name: str) -> dict[str, Any]:
        """The table ``[name]`` (empty when absent; the top level for "")."""
        value = self.data.get(name, {}) if name else self.data
        if not isinstance(value, dict):
            self.fail(f"[{name}] must be a table, got {type(value).__name__}")
        return value

    def quantity(self, sec: str, key: str, dimension: str, default: _D) -> float | _D:
        table = self.section(sec)
        if key not in table:
            return default
        return parsed(table[key], dimension, f"{sec}.{key}" if sec else key, self.fail)

    def text_value(self, sec: str, key: str, default: str) -> str:
        value = self.section(sec).get(key, default)
        if not isinstance(value, str):
            self.fail(f"{(sec + '.') if sec else ''}{key} = {value!r}: expected a string")
        return value

    def number(self, sec: str, key: str, default: float) -> float:
        value = self.section(sec).get(key, default)
        try:  # the package's one rule for a number (designer.units.real_number), as the API's
            return real_number(value, f"{sec}.{key}")
        except InputError as exc:
            self.fail(str(exc))


def _retrofit_limits(r: Any, data: dict[str, Any]) -> tuple[float, float]:
    """``[retrofit] max_threshold_increase`` and ``max_turning_increase`` [-]; a bare number of 1 or more is
    refused (``5`` meant as 5 % would be +500 %: write ``"5 %"``)."""
    for key in ("max_threshold_increase", "max_turning_increase"):
        raw = r.section("retrofit").get(key) if "retrofit" in data else None
        if isinstance(raw, (int, float)) and not isinstance(raw, bool) and raw >= 1:
            r.fail(
                f"retrofit.{key} = {raw!r}: a bare number is a fraction (0.05 = 5 %); write "
                f'"{raw} %" for {raw} % or "{100 * raw:g} %" for a {raw:g}-fold rise'
            )
    increase = r.quantity("retrofit", "max_threshold_increase", "dimensionless", DEFAULT_MAX_THRESHOLD_INCREASE)
    turning = r.quantity("retrofit", "max_turning_increase", "dimensionless", DEFAULT_MAX_TURNING_INCREASE)
    return increase, turning


def problem_from_dict(data: dict[str, Any], source: str | None = None, default_name: str = "problem") -> Problem:
    """Build a validated :class:`Problem` from a dict with the problem-file schema.

    The sections are read in a fixed order (names, [turning], [dynamics], [inertia], [robust], the
    conditions, [variables], [objective], [stock], [pareto], [choices], [shimmy]), so the first error
    reported for a file with several is always the same.
    """
    prefix = f"{source}: " if source else ""
    r = _Reader(data, prefix)
    if not isinstance(data, dict):
        r.fail("a problem must be a table of sections")
    _check_keys(data, prefix)

    name = r.text_value("", "name", default_name)
    title = r.text_value("", "title", name)
    description = r.text_value("", "description", "")

    # turning constants and dynamics first: conditions need them
    constants = {**_positive_constants(r, "turning"), **_positive_constants(r, "dynamics")}
    inertia, wheels = _inertia(r.section("inertia"), r.quantity, r.fail)

    uncertainty = _uncertainty(r.section("robust"), r.fail)  # on by default: no [robust] gives the default scatter

    constants.update(_constants(r, "conditions"))
    by_mass = _load_from_mass(r)
    if by_mass is not None:
        constants["load"] = by_mass
    constants.update(_constants(r, "shimmy"))
    constants.update(_constants(r, "constraints"))
    conditions = _conditions(r, constants, uncertainty, inertia)
    if "target_speed" not in r.section("shimmy"):
        r.fail("shimmy.target_speed: missing; give the speed the caster must not shimmy below, e.g. '2.5 m/s'")

    variables = r.section("variables")  # {min, max} or one value (fixed) per design variable; else the defaults
    bounds = {v: _bound(r, v, variables[v]) if v in variables else Bound(*DEFAULT_BOUNDS[v]) for v in VARIABLES}
    if "damping" not in variables:  # from the bare fork's damping
        bare = conditions.turning.bare_fork_damping
        bounds["damping"] = Bound(bare, max(DEFAULT_BOUNDS["damping"][1], bare))
    if wheels:
        wheels = _catalog_within(r, bounds, wheels)

    weights = (r.number("objective", "turning_effort", 1.0), r.number("objective", "threshold_force", 1.0))
    caps = _caps(r)
    stock = read_stock(r.section("stock"), bounds, inertia, wheels, r.fail) if "stock" in data else None
    points = r.section("pareto").get("points", 41)
    if isinstance(points, bool) or not isinstance(points, int):
        r.fail(f"pareto.points = {points!r}: expected an integer")

    increase, turning = _retrofit_limits(r, data)

    target_speed = _value(r, "target_speed")
    assert target_speed is not None  # the key is present (checked above)
    return Problem(
        name=name,
        title=title,
        description=description,
        conditions=conditions,
        target_speed=target_speed,
        margin=_value(r, "margin"),
        bounds=bounds,
        swept_radius_max=_value(r, "swept_radius_max"),
        weights=weights,
        pareto_points=points,
        wheels=wheels,
        choices=_choices(r),
        stock=stock,
        max_threshold_force=caps["max_threshold_force"],
        max_turning_effort=caps["max_turning_effort"],
        source=source,
        units=_report_units(r),
        max_threshold_increase=increase,
        max_turning_increase=turning,
        tolerances=_tolerances(r) if "tolerances" in data else None,
    )


def tolerances_option(text: str, option: str = "--tolerances") -> Tolerances:
    """``[tolerances]`` from a command line: ``"trail=1.5mm,groove=0.4mm,diameter=1mm,friction_moment=30%"``
    (keys and values as in a problem file's ``[tolerances]``; ``wheel=catalogue`` or an I_w); one-line InputError."""
    table: dict[str, Any] = {}
    for item in (x.strip() for x in text.split(",") if x.strip()):
        key, sep, value = item.partition("=")
        if not sep or key.strip() not in ("trail", "groove", "diameter", "friction_moment", "wheel"):
            raise InputError(
                f"{option} {text!r}: {item!r}: expected key=value with key trail, groove, diameter, friction_moment "
                "or wheel (e.g. trail=1.5mm,groove=0.4mm,friction_moment=30%)"
            )
        table[key.strip()] = value.strip()
    try:
        return _tolerances(_Reader({"tolerances": table}, f"{option}: "))
    except ProblemError as exc:
        raise InputError(str(exc)) from None


def _tolerances(r: _Reader) -> Tolerances:
    """``[tolerances]``: the ± spread of trail, groove and diameter (lengths from 0 to 1 in), of the friction
    moment (a fraction below 1: "20 %"), the wheel ("catalogue" or the largest measured I_w accepted) and
    ``enforce``.  A stem angle is refused: the problem's stem is vertical (nothing to tolerance)."""
    table = r.section("tolerances")
    if "stem_angle" in table:
        r.fail(
            f"tolerances.stem_angle = {table['stem_angle']!r}: this problem has no stem angle (its stem is vertical "
            "and T is the tyre's trail); tolerance the trail instead"
        )
    lengths = {}
    for key in ("trail", "groove", "diameter"):
        value = r.quantity("tolerances", key, "length", None)
        if value is not None and not 0 <= value <= TOLERANCE_MAX_LENGTH:
            r.fail(
                f"tolerances.{key} = {table[key]!r}: a spread must be from 0 to {TOLERANCE_MAX_LENGTH * 1000:.1f} mm "
                "(± about the nominal size)"
            )
        lengths[key] = value
    moment = r.quantity("tolerances", "friction_moment", "dimensionless", None)
    if moment is not None and not 0 <= moment < 1:
        r.fail(
            f"tolerances.friction_moment = {table['friction_moment']!r}: the spread of M_f is a fraction from 0 to "
            'below 1 (write "20 %" or 0.2); 100 % or more would leave no friction'
        )
    wheel = table.get("wheel", "catalogue")
    limit: float | None = None
    if not (isinstance(wheel, str) and wheel.strip().lower() in ("catalogue", "catalog")):
        with contextlib.suppress(InputError):  # said below, with what is expected
            limit = parse_quantity(wheel, "inertia", "tolerances.wheel")
        if limit is None or not 0 < limit < 0.1:
            r.fail(
                f'tolerances.wheel = {wheel!r}: expected "catalogue" or the largest measured wheel inertia '
                "accepted, between 0 and 0.1 kg·m² (e.g. '1.5e-3 kg*m^2')"
            )
    enforce = table.get("enforce", False)
    if not isinstance(enforce, bool):
        r.fail(f"tolerances.enforce = {enforce!r}: expected true or false")
    return Tolerances(**lengths, friction_moment=moment, wheel=limit, enforce=enforce)


def _conditions(
    r: _Reader, constants: dict[str, Any], uncertainty: Uncertainty | None, inertia: InertiaModel
) -> Conditions:
    """The problem's :class:`Conditions`: surface, turning mode and each constant checked by the rules of
    ``Conditions`` (:func:`designer.model.condition_refusal`, the message naming the file's key), then each
    constant written where the parameter table says it lives."""
    surface = r.text_value("conditions", "surface", "tile")
    turning_mode = r.text_value("conditions", "turning_mode", "chair")
    for entry, value in [("surface", surface), ("turning_mode", turning_mode), *constants.items()]:
        # the rules of Conditions, each message naming the file's key
        key = f"conditions.{entry}" if entry in CONDITION_CHOICES else parameters.PARAMETERS[entry].key
        reason = condition_refusal(entry, value, key) if entry in (*CONDITION_CHOICES, *CONDITION_NUMBERS) else None
        if reason is not None:
            r.fail(reason)
    conditions = Conditions(uncertainty=uncertainty, inertia=inertia, surface=surface, turning_mode=turning_mode)
    for constant, value in constants.items():  # each where the parameter table says it lives
        where = parameters.location(parameters.PARAMETERS[constant])
        assert where is not None and where.startswith("conditions.")
        conditions = parameters.write_path(conditions, where.split(".", 1)[1], value)
    return conditions


def _value(r: _Reader, name: str) -> Any:
    """Entry ``name`` of the parameter table, read from its problem-file key with its dimension and default."""
    p = parameters.PARAMETERS[name]
    assert p.key is not None
    section, key = p.key.split(".", 1)
    return r.quantity(section, key, p.dimension, p.default)


def _constants(r: _Reader, section: str) -> dict[str, Any]:
    """The model constants of ``[section]`` kept on the conditions, by table name: each key of the parameter
    table read with its dimension and default (the problem-level ones, such as the target speed, are read
    by :func:`problem_from_dict` itself)."""
    entries = parameters.by_key(section).values()
    return {p.name: _value(r, p.name) for p in entries if (parameters.location(p) or "").startswith("conditions.")}


def _load_from_mass(r: _Reader) -> float | None:
    """[conditions] mass and front_fraction, the alternative to ``load``: L = m g f / 2 [N]
    (:func:`designer.model.caster_load`), or None when neither is given.  Both or neither; not with ``load``."""
    table = r.section("conditions")
    given = [key for key in ("mass", "front_fraction") if key in table]
    if not given:
        return None
    if "load" in table:
        r.fail(
            f"conditions.load and conditions.{given[0]}: give load, or mass and front_fraction, not both "
            "(load = mass g front_fraction / 2 per front caster)"
        )
    if len(given) == 1:
        missing = "front_fraction" if given[0] == "mass" else "mass"
        r.fail(
            f"conditions.{missing}: missing; conditions.{given[0]} needs it (load = mass g front_fraction / 2, "
            "e.g. mass = '110 kg', front_fraction = 0.4)"
        )
    mass = r.quantity("conditions", "mass", "mass", None)
    fraction = r.quantity("conditions", "front_fraction", "dimensionless", None)
    assert mass is not None and fraction is not None  # both keys are present (checked above)
    low, high = MASS_RANGE
    if not low <= mass <= high:
        r.fail(f"conditions.mass = {table['mass']!r}: must be {low:g} to {high:g} kg (the user plus the chair)")
    if not 0 < fraction <= 1:
        r.fail(
            f"conditions.front_fraction = {table['front_fraction']!r}: must be above 0 and at most 1 (the share "
            "of the weight on the two front casters, e.g. 0.4 or '40 %')"
        )
    load = float(caster_load(mass, fraction))
    low, high = parameters.PARAMETERS["load"].range or (0.0, math.inf)
    if not low <= load <= high:
        r.fail(
            f"conditions.mass = {table['mass']!r}, front_fraction = {table['front_fraction']!r}: a caster load of "
            f"{load:.3g} N, outside {low:g} N to {high:g} N"
        )
    return load


def _positive_constants(r: _Reader, section: str) -> dict[str, Any]:
    """[turning] or [dynamics]: the constants of the turning model (docs/model.md#turning-effort) or the frame
    stiffness and fork masses of the third-order model, each positive when given (one whose table range starts
    at 0, the groove coefficient, non-negative)."""
    values = _constants(r, section)
    for key, p in parameters.by_key(section).items():
        value, zero = values[p.name], p.range is not None and p.range[0] == 0
        if value is not None and (value < 0 if zero else value <= 0):
            reason = "non-negative" if zero else "positive"
            r.fail(f"{section}.{key} = {value:g} {p.unit}".rstrip() + f": must be {reason}")
    return values


def _bound(r: _Reader, var: str, spec: object) -> Bound:
    """One ``variables.<var>``: a table {min, max} or a single value, in the model's range."""
    dim = VARIABLE_DIMENSIONS[var]
    if isinstance(spec, dict):
        extra = set(spec) - {"min", "max"}
        if extra:
            r.fail(f"variables.{var}: unknown key {sorted(extra)[0]!r}; expected 'min' and 'max' or a single value")
        if "min" not in spec or "max" not in spec:
            missing = "min" if "min" not in spec else "max"
            r.fail(f"variables.{var}.{missing}: missing; give both min and max, or a single value to fix it")
        lo = parsed(spec["min"], dim, f"variables.{var}.min", r.fail)
        hi = parsed(spec["max"], dim, f"variables.{var}.max", r.fail)
        given = {f"variables.{var}.min": (spec["min"], lo), f"variables.{var}.max": (spec["max"], hi)}
    else:
        lo = hi = parsed(spec, dim, f"variables.{var}", r.fail)
        given = {f"variables.{var}": (spec, lo)}
    for key, (text, value) in given.items():  # said in the user's unit (validate() repeats it in SI)
        if value > MODEL_RANGE[var][1] or 0 < value < MODEL_RANGE[var][0]:
            r.fail(outside_range(key, text, value, *MODEL_RANGE[var], dim))
    return Bound(lo, hi)


def _catalog_within(r: _Reader, bounds: dict[str, Bound], wheels: tuple[str, ...]) -> tuple[str, ...]:
    """The catalog wheels within ``variables.diameter`` (when given); the diameter bounds become theirs."""
    d_lo, d_hi = bounds["diameter"].low, bounds["diameter"].high
    if "diameter" in r.section("variables"):
        kept = tuple(k for k in wheels if d_lo - 1e-9 <= Catalog.from_key(k).fixed_diameter <= d_hi + 1e-9)
        if not kept:
            r.fail(f"variables.diameter = [{inches(d_lo)}, {inches(d_hi)}]: no catalog wheel in {list(wheels)} fits")
        wheels = kept
    diameters = [Catalog.from_key(k).fixed_diameter for k in wheels]
    bounds["diameter"] = Bound(min(diameters), max(diameters))
    return wheels


def _caps(r: _Reader) -> dict[str, float | None]:
    """[objective] max_threshold_force or max_turning_effort [N]: at most one cap, a positive force."""
    caps = {}
    for key in ("max_threshold_force", "max_turning_effort"):
        cap = r.quantity("objective", key, "force", None)
        if cap is not None and not (math.isfinite(cap) and 0 < cap < 1e5):
            r.fail(f"objective.{key} = {cap:g} N: must be a positive force below 1e5 N")
        caps[key] = cap
    if caps["max_threshold_force"] is not None and caps["max_turning_effort"] is not None:
        r.fail(
            "objective: give max_threshold_force or max_turning_effort, not both (the recommendation caps one "
            "objective and minimises the other)"
        )
    return caps


_WRITTEN_LENGTH = re.compile(r"^\s*[-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?\s*(mm|cm|m|in|inch|inches)\s*$")
"""A length written with its unit ("13 mm", "0.5 in"): the unit is the user's choice of sizes."""


def _report_units(r: _Reader) -> str:
    """[report] units = "in" | "mm"; without it, the unit the file writes its lengths in: "mm" when every length
    written with a unit is in mm, cm or m, "in" when every one is in inches, and the sill's when they mix (a sill
    given as "13 mm" is shown as 13 mm); "in" when no length has a unit."""
    table = r.section("report")
    if "units" in table:
        return str(table["units"])  # one of REPORT_UNITS: Problem's check
    written = [m.group(1) for m in map(_WRITTEN_LENGTH.match, _strings(r.data)) if m]
    metric = [u for u in written if u in ("mm", "cm", "m")]
    if metric and len(metric) < len(written):  # mixed: the sill's unit, if it has one
        sill = _WRITTEN_LENGTH.match(str(r.section("conditions").get("threshold_height", "")))
        return "mm" if sill and sill.group(1) in ("mm", "cm", "m") else "in"
    return "mm" if metric else "in"


def _strings(value: Any) -> list[str]:
    """Every string value of a problem-file table, nested tables and lists included."""
    if isinstance(value, str):
        return [value]
    values = value.values() if isinstance(value, dict) else value if isinstance(value, list) else []
    return [s for v in values for s in _strings(v)]


def _choices(r: _Reader) -> dict[str, tuple[str, ...]]:
    """[choices]: the categorical options of an exploration (surface, turning mode, Table 1 wheel)."""
    choices = {}
    for key, allowed in (("surface", SURFACES), ("turning_mode", MODES), ("wheel", tuple(w.key for w in TABLE1))):
        if key in r.section("choices"):
            values = r.section("choices")[key]
            if not isinstance(values, list) or not values or any(v not in allowed for v in values):
                r.fail(f"choices.{key} = {values!r}: expected a non-empty list from {', '.join(allowed)}")
            choices[key] = tuple(values)
    return choices


def _uncertainty(table: dict[str, Any], fail: Callable[[str], NoReturn]) -> Uncertainty | None:
    """Parse [robust]: the risk bound α and the scatter (σ of the log) of each constant.

    No section (or no key) gives the defaults of :class:`~designer.physics.uncertainty.Uncertainty`
    (α = 0.05, Table 1's model error as a Student-t on 5 degrees of freedom); ``enabled = false`` gives
    None: the nominal Eq. 7 constraint.
    """

    enabled = table.get("enabled", True)
    if not isinstance(enabled, bool):
        fail(f"robust.enabled = {enabled!r}: expected true or false")
    if not enabled:
        extra = sorted(set(table) - {"enabled", "samples", "seed"})
        if extra:
            fail(f"robust.{extra[0]}: has no effect with enabled = false (the nominal problem has no risk bound)")
    defaults = Uncertainty()
    values: dict[str, Any] = {}
    for key in ("probability", "model_error", "damping", "slip_coefficient", "inertia"):
        value = table.get(key, getattr(defaults, key))
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not abs(value) <= 1e300:  # NaN, inf
            fail(f"robust.{key} = {value!r}: expected a finite number")
        values[key] = float(value)
        if key != "probability" and not 0 <= value <= 2:
            fail(f"robust.{key} = {value:g}: the standard deviation of the log must be between 0 and 2")
    low, high = PROBABILITY_RANGE
    if not low <= values["probability"] < high:
        fail(
            f"robust.probability = {values['probability']:g}: must be from {low:g} to below {high:g} (e.g. 0.05 "
            f"for 5 %; below {low:g} the risk bound is not computed to its accuracy)"
        )
    for key, low, high in (("samples", 100, MAX_SAMPLES), ("seed", 0, 2**32 - 1), ("model_error_dof", 0, 1000)):
        value = table.get(key, getattr(defaults, key))
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            hint = " (0 = a normal model error)" if key == "model_error_dof" else ""
            fail(f"robust.{key} = {value!r}: expected an integer from {low} to {high}{hint}")
        values[key] = value
    if not enabled:
        return None
    return Uncertainty(**values)


_INERTIA_KEYS = {
    "table1-power-law": (PowerLaw, ("inertia_coefficient", "inertia_exponent")),
    "disc": (Disc, ("tyre_width", "density")),
    "fixed": (Fixed, ("wheel_inertia",)),
}
"""Each ``[inertia] model`` but the catalog: its class and the parameter-table entries it takes, in order (each
positive and within its table range; all required but the power law's, whose defaults are Table 1's fit)."""


def _inertia(
    table: dict[str, Any], quantity: Callable[[str, str, str, None], float | None], fail: Callable[[str], NoReturn]
) -> tuple[InertiaModel, tuple[str, ...]]:
    """``[inertia]``: the I_w(d) model and, for the catalog, its wheels; each key checked against the table."""
    model = table.get("model", "table1-power-law")
    if model not in INERTIA_MODELS:
        fail(f"inertia.model = {model!r}: expected one of {', '.join(INERTIA_MODELS)}")
    kind, names = _INERTIA_KEYS.get(model, (None, ()))
    entries = {parameters.PARAMETERS[n].key.split(".", 1)[1]: parameters.PARAMETERS[n] for n in names}  # type: ignore[union-attr]
    allowed = {"model", *entries} if kind is not None else {"model", "wheel", "wheels"}
    extra = set(table) - allowed
    if extra:
        fail(
            f"inertia.{show_key(sorted(extra)[0])}: not used by inertia model {model!r} (it takes {', '.join(sorted(allowed - {'model'})) or 'nothing else'})"
        )
    if kind is None:
        return _catalog(table, fail)
    values = []
    for key, p in entries.items():
        if key not in table and kind is not PowerLaw:
            fail(
                f"inertia.{key}: missing; the {model} model needs {' and '.join(entries)}, e.g. {key} = {example(p.dimension)!r}"
            )
        value = quantity("inertia", key, p.dimension, None)
        low, high = p.range or (0.0, math.inf)
        if value is not None and not low < value <= high:
            within = f"between {low:g} and {high:g} {p.unit}".rstrip() if p.range else "positive"
            fail(f"inertia.{key} = {value:g} {p.unit}".rstrip() + f": must be {within}")
        values.append(value)
    return kind(*values), ()


def _catalog(table: dict[str, Any], fail: Callable[[str], NoReturn]) -> tuple[InertiaModel, tuple[str, ...]]:
    """[inertia] model = "catalog": the Table 1 wheels named by ``wheel`` or ``wheels`` (default all of them)."""
    if "wheel" in table and "wheels" in table:
        fail('inertia: give either wheel = "C" or wheels = ["A", ...], not both')
    keys = table.get("wheels", [table["wheel"]] if "wheel" in table else [w.key for w in TABLE1])
    if isinstance(keys, str) or not isinstance(keys, list) or not keys:
        fail(f"inertia.wheels = {keys!r}: expected a non-empty list of Table 1 letters")
    valid = [w.key for w in TABLE1]
    out = []
    for key in keys:
        if not isinstance(key, str) or key.strip().upper() not in valid:
            fail(f"inertia.wheel = {key!r}: unknown Table 1 wheel; valid wheels are {', '.join(valid)}")
        out.append(key.strip().upper())
    return Catalog.from_key(out[0]), tuple(dict.fromkeys(out))


def _check_keys(data: dict[str, Any], prefix: str) -> None:
    for key, value in data.items():
        if key in SCHEMA[""]:
            continue
        if key not in SCHEMA:
            raise ProblemError(
                prefix + f"unknown section or key {key!r}{_suggest(key, list(SCHEMA) + list(SCHEMA['']))}"
            )
        if not isinstance(value, dict):
            raise ProblemError(prefix + f"[{key}] must be a table, got {value!r}")
        for sub in value:
            if sub not in SCHEMA[key]:
                raise ProblemError(prefix + f"unknown key {key}.{show_key(sub)}{_suggest(sub, list(SCHEMA[key]))}")


def _suggest(word: str, options: list[str]) -> str:
    match = difflib.get_close_matches(word, [o for o in options if o], n=1)
    return f" (did you mean {match[0]!r}?)" if match else ""
