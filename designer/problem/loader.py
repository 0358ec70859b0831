"""The problem-file loader: TOML text or a dict with the problem-file schema -> a validated :class:`Problem`.

Schema: docs/problem-file.md (:data:`designer.problem.core.SCHEMA` lists the keys that are not quantities;
the quantities come from :mod:`designer.parameters`).  Every error is one line naming the key, the value
and the reason.  :mod:`designer.problem.core` holds the :class:`Problem` record and its validation.
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from pathlib import Path
from typing import Any, Callable, NoReturn, TypeVar

from designer.data.paper import INCH, TABLE1
from designer import parameters
from designer.errors import ProblemError, read_input_text
from designer.model import MODEL_RANGE, VARIABLE_UNITS, VARIABLES, Conditions
from designer.physics.inertia import Catalog, Disc, Fixed, InertiaModel, PowerLaw
from designer.physics.shimmy import DynamicsParameters
from designer.physics.turning import MODES, SURFACES, TurningConstants
from designer.units import InputError, outside_range, parse_quantity
from designer.physics.uncertainty import Uncertainty

from designer.problem.core import (
    DEFAULT_BOUNDS,
    INERTIA_MODELS,
    INERTIA_RANGE,
    MAX_SAMPLES,
    SCHEMA,
    VARIABLE_DIMENSIONS,
    Bound,
    Problem,
    Stock,
    StockWheel,
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


def load_problem(path: str | Path) -> Problem:
    """Read and validate a problem file (TOML, docs/problem-file.md).

    Raises
    ------
    ProblemError
        One line: the file, the key, the value and the reason (TOML syntax
        errors with their line number).
    """
    path = Path(path)
    text = read_input_text(path, "problem file", ".toml")
    return problem_from_toml(text, source=str(path), default_name=path.stem)


def problem_from_toml(text: str, source: str | None = None, default_name: str = "problem") -> Problem:
    """Parse TOML text into a validated :class:`Problem` (see :func:`load_problem`)."""
    prefix = f"{source}: " if source else ""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ProblemError(f"{prefix}TOML syntax error: {exc}") from None
    except ValueError as exc:  # e.g. an integer literal of more than 4300 digits
        raise ProblemError(f"{prefix}cannot read the file: {exc}") from None
    return problem_from_dict(data, source=source, default_name=default_name)


class _Reader:
    """The problem-file dict with its one-line errors: each reader names the key, the value and the reason."""

    def __init__(self, data: dict[str, Any], prefix: str) -> None:
        self.data = data
        self.prefix = prefix

    def fail(self, msg: str) -> NoReturn:
        raise ProblemError(self.prefix + msg)

    def section(self, name: str) -> dict[str, Any]:
        value = self.data.get(name, {})
        if not isinstance(value, dict):
            self.fail(f"[{name}] must be a table, got {type(value).__name__}")
        return value

    def quantity(self, sec: str, key: str, dimension: str, default: _D) -> float | _D:
        table = self.data if sec == "" else self.section(sec)
        if key not in table:
            return default
        try:
            return parse_quantity(table[key], dimension, f"{sec}.{key}" if sec else key)
        except InputError as exc:
            self.fail(str(exc))

    def text_value(self, sec: str, key: str, default: str) -> str:
        table = self.data if sec == "" else self.section(sec)
        value = table.get(key, default)
        if not isinstance(value, str):
            self.fail(f"{(sec + '.') if sec else ''}{key} = {value!r}: expected a string")
        return value

    def number(self, sec: str, key: str, default: float) -> float:
        table = self.section(sec)
        value = table.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(f"{sec}.{key} = {value!r}: expected a number")
        if isinstance(value, int) and abs(value) > 1e300:
            self.fail(f"{sec}.{key}: an integer of about {int(value.bit_length() * 0.30103)} digits is too large")
        if not math.isfinite(value):
            self.fail(f"{sec}.{key} = {value!r}: must be finite")
        return float(value)


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
    turning = _turning(r)
    dynamics = _dynamics(r)
    inertia, wheels = _inertia(r.section("inertia"), r.quantity, r.fail)

    uncertainty = _uncertainty(r.section("robust"), r.fail)  # on by default: no [robust] gives the default scatter

    conditions = Conditions(
        uncertainty=uncertainty,
        load=r.quantity("conditions", "load", "force", parameters.default("load")),
        threshold_height=r.quantity("conditions", "threshold_height", "length", parameters.default("threshold_height")),
        surface=r.text_value("conditions", "surface", "tile"),
        turning_mode=r.text_value("conditions", "turning_mode", "chair"),
        disturbance_angle=r.quantity("shimmy", "disturbance_angle", "angle", parameters.default("disturbance_angle")),
        slip_coefficient=r.quantity("shimmy", "slip_coefficient", "force", parameters.default("slip_coefficient")),
        inertia=inertia,
        turning=turning,
        dynamics=dynamics,
    )
    if "target_speed" not in r.section("shimmy"):
        r.fail("shimmy.target_speed: missing; give the speed the caster must not shimmy below, e.g. '2.5 m/s'")

    bounds = _bounds(r, turning)
    if wheels:
        wheels = _catalog_within(r, bounds, wheels)

    weights = (r.number("objective", "turning_effort", 1.0), r.number("objective", "threshold_force", 1.0))
    caps = _caps(r)
    stock = (
        _stock(r.section("stock"), bounds, inertia, wheels, conditions.threshold_height, r.fail)
        if "stock" in data
        else None
    )
    points = r.section("pareto").get("points", 41)
    if isinstance(points, bool) or not isinstance(points, int):
        r.fail(f"pareto.points = {points!r}: expected an integer")

    choices = _choices(r)

    target_speed = r.quantity("shimmy", "target_speed", "speed", None)
    assert target_speed is not None  # the key is present (checked above)
    return Problem(
        name=name,
        title=title,
        description=description,
        conditions=conditions,
        target_speed=target_speed,
        margin=r.quantity("shimmy", "margin", "dimensionless", 0.0),
        bounds=bounds,
        swept_radius_max=r.quantity("constraints", "swept_radius_max", "length", None),
        weights=weights,
        pareto_points=points,
        wheels=wheels,
        choices=choices,
        stock=stock,
        max_threshold_force=caps["max_threshold_force"],
        max_turning_effort=caps["max_turning_effort"],
        source=source,
    )


def _turning(r: _Reader) -> TurningConstants:
    """[turning]: the constants of the turning model (docs/model.md#turning-effort), each positive."""
    tdef = TurningConstants()
    turning = TurningConstants(
        tile_moment_per_load=r.quantity("turning", "tile_moment_per_load", "length", tdef.tile_moment_per_load),
        carpet_factor=r.quantity("turning", "carpet_factor", "dimensionless", tdef.carpet_factor),
        groove_coefficient=r.quantity("turning", "groove_coefficient", "per_length", tdef.groove_coefficient),
        mode_factors={
            "chair": r.quantity("turning", "chair_factor", "dimensionless", tdef.mode_factors["chair"]),
            "pivot": r.quantity("turning", "pivot_factor", "dimensionless", tdef.mode_factors["pivot"]),
        },
        bare_fork_damping=r.quantity("turning", "bare_fork_damping", "damping", tdef.bare_fork_damping),
    )
    for key, value in (
        ("tile_moment_per_load", turning.tile_moment_per_load),
        ("carpet_factor", turning.carpet_factor),
        ("chair_factor", turning.mode_factors["chair"]),
        ("pivot_factor", turning.mode_factors["pivot"]),
        ("bare_fork_damping", turning.bare_fork_damping),
    ):
        if value <= 0:
            r.fail(f"turning.{key} = {value:g}: must be positive")
    if turning.groove_coefficient < 0:
        r.fail(f"turning.groove_coefficient = {turning.groove_coefficient:g} 1/m: must be non-negative")
    return turning


def _dynamics(r: _Reader) -> DynamicsParameters:
    """[dynamics]: frame stiffness and fork masses of the third-order model, each positive when given."""
    ddef = DynamicsParameters()
    dynamics = DynamicsParameters(
        frame_stiffness=r.quantity("dynamics", "frame_stiffness", "stiffness", None),
        fork_mass=r.quantity("dynamics", "fork_mass", "mass", ddef.fork_mass),
        bearing_block_mass=r.quantity("dynamics", "bearing_block_mass", "mass", ddef.bearing_block_mass),
    )
    for key, stated in (
        ("frame_stiffness", dynamics.frame_stiffness),
        ("fork_mass", dynamics.fork_mass),
        ("bearing_block_mass", dynamics.bearing_block_mass),
    ):
        if stated is not None and stated <= 0:
            r.fail(f"dynamics.{key} = {stated:g}: must be positive")
    return dynamics


def _bounds(r: _Reader, turning: TurningConstants) -> dict[str, Bound]:
    """[variables]: {min, max} or one value (fixed) per design variable; the defaults for the others."""
    bounds = {}
    variables = r.section("variables")
    for var in VARIABLES:
        if var not in variables:
            lo, hi = DEFAULT_BOUNDS[var]
            if var == "damping":
                lo = turning.bare_fork_damping
                hi = max(hi, lo)
            bounds[var] = Bound(lo, hi)
            continue
        bounds[var] = _bound(r, var, variables[var])
    return bounds


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
        try:
            lo = parse_quantity(spec["min"], dim, f"variables.{var}.min")
            hi = parse_quantity(spec["max"], dim, f"variables.{var}.max")
        except InputError as exc:
            r.fail(str(exc))
        given = {f"variables.{var}.min": (spec["min"], lo), f"variables.{var}.max": (spec["max"], hi)}
    else:
        try:
            lo = hi = parse_quantity(spec, dim, f"variables.{var}")
        except InputError as exc:
            r.fail(str(exc))
        given = {f"variables.{var}": (spec, lo)}
    for key, (text, value) in given.items():  # said in the user's unit (validate() repeats it in SI)
        if value > MODEL_RANGE[var][1]:
            r.fail(outside_range(key, text, value, *MODEL_RANGE[var], dim))
    return Bound(lo, hi)


def _catalog_within(r: _Reader, bounds: dict[str, Bound], wheels: tuple[str, ...]) -> tuple[str, ...]:
    """The catalog wheels within ``variables.diameter`` (when given); the diameter bounds become theirs."""
    d_lo, d_hi = bounds["diameter"].low, bounds["diameter"].high
    if "diameter" in r.section("variables"):
        kept = tuple(k for k in wheels if d_lo - 1e-9 <= Catalog.from_key(k).fixed_diameter <= d_hi + 1e-9)
        if not kept:
            r.fail(
                f"variables.diameter = [{d_lo / INCH:.3g}, {d_hi / INCH:.3g}] in: no catalog wheel in {list(wheels)} fits"
            )
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
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float))
            or abs(value) > 1e300
            or not math.isfinite(value)
        ):
            fail(f"robust.{key} = {value!r}: expected a finite number")
        values[key] = float(value)
    if not 0 < values["probability"] < 0.5:
        fail(f"robust.probability = {values['probability']:g}: must be between 0 and 0.5 (e.g. 0.05 for 5 %)")
    for key in ("model_error", "damping", "slip_coefficient", "inertia"):
        if not 0 <= values[key] <= 2:
            fail(f"robust.{key} = {values[key]:g}: the standard deviation of the log must be between 0 and 2")
    for key, low, high in (("samples", 100, MAX_SAMPLES), ("seed", 0, 2**32 - 1), ("model_error_dof", 0, 1000)):
        value = table.get(key, getattr(defaults, key))
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            hint = " (0 = a normal model error)" if key == "model_error_dof" else ""
            fail(f"robust.{key} = {value!r}: expected an integer from {low} to {high}{hint}")
        values[key] = value
    if not enabled:
        return None
    return Uncertainty(**values)


def _stock_values(
    table: dict[str, Any],
    key: str,
    dimension: str,
    variable: str,
    bounds: dict[str, Bound],
    fail: Callable[[str], NoReturn],
) -> tuple[float, ...]:
    """A [stock] list in SI, each value inside ``variable``'s bounds (deduplicated, sorted)."""
    values = table[key]
    if isinstance(values, (str, int, float)) or not isinstance(values, list):
        fail(f'stock.{key} = {values!r}: expected a list, e.g. ["4 in", "5 in"]')
    if not values:
        fail(f"stock.{key} = []: empty; list at least one value, or leave the key out to keep {variable} continuous")
    out = []
    b = bounds[variable]
    for i, raw in enumerate(values):
        try:
            v = parse_quantity(raw, dimension, f"stock.{key}[{i}]")
        except InputError as exc:
            fail(str(exc))
        if not b.low * (1 - 1e-9) - 1e-12 <= v <= b.high * (1 + 1e-9) + 1e-12:
            unit = VARIABLE_UNITS[variable]
            shown = (
                f"{v / INCH:.4g} in outside variables.{variable} = [{b.low / INCH:.4g}, {b.high / INCH:.4g}] in"
                if dimension == "length"
                else f"{v:g} {unit} outside variables.{variable} = [{b.low:g}, {b.high:g}] {unit}"
            )
            fail(f"stock.{key}[{i}] = {raw!r}: {shown}; widen the bounds or drop the part")
        out.append(min(max(v, b.low), b.high))
    return tuple(sorted(set(out)))


def _stock(
    table: dict[str, Any],
    bounds: dict[str, Bound],
    inertia: InertiaModel,
    catalog: tuple[str, ...],
    sill: float,
    fail: Callable[[str], NoReturn],
) -> Stock:
    """Parse [stock] against the bounds and the inertia model (one-line errors, exit 3)."""
    if not table:
        fail("[stock] is empty; list diameters, grooves, trail_step or dampings (a key left out stays continuous)")
    model = getattr(inertia, "name", "")
    if "diameters" in table or "wheels" in table:
        key = "diameters" if "diameters" in table else "wheels"
        if catalog:
            fail(
                f'stock.{key}: not allowed with [inertia] model = "catalog"; the wheel stock is '
                f"[inertia].wheels ({', '.join(catalog)})"
            )
        if model == "fixed" or isinstance(inertia, Fixed):
            fail(
                f'stock.{key}: not allowed with [inertia] model = "fixed"; a fixed inertia is one measured '
                f"wheel, so the diameter is fixed (set variables.diameter to it)"
            )
    if "diameters" in table and "wheels" in table:
        fail("stock: give diameters (and grooves) or wheels, not both")
    diameters = _stock_values(table, "diameters", "length", "diameter", bounds, fail) if "diameters" in table else None
    grooves = _stock_values(table, "grooves", "length", "groove", bounds, fail) if "grooves" in table else None
    dampings = _stock_values(table, "dampings", "damping", "damping", bounds, fail) if "dampings" in table else None
    trails = step = None
    if "trail_step" in table:
        step, trails = _stock_trails(table, bounds["trail"], fail)
    wheels = _stock_wheels(table["wheels"], bounds, grooves, fail) if "wheels" in table else None
    return Stock(diameters=diameters, grooves=grooves, trail_step=step, trails=trails, dampings=dampings, wheels=wheels)


def _stock_trails(table: dict[str, Any], b: Bound, fail: Callable[[str], NoReturn]) -> tuple[float, tuple[float, ...]]:
    """``stock.trail_step``: the step [m] and the fork holes from ``variables.trail.min`` every step up to max."""
    try:
        step = parse_quantity(table["trail_step"], "length", "stock.trail_step")
    except InputError as exc:
        fail(str(exc))
    span = max(b.high - b.low, 0.0)  # inverted bounds are validate()'s one-line error, not the step's
    if not step > 0 or not math.isfinite(step):
        fail(f'stock.trail_step = {table["trail_step"]!r}: must be a positive length, e.g. "0.25 in"')
    if b.low > b.high:
        pass  # inverted trail bounds: validate() names variables.trail (min greater than max)
    elif span <= 0:
        fail(
            f"stock.trail_step = {table['trail_step']!r}: variables.trail is fixed at {b.low / INCH:.4g} in; "
            f"leave trail_step out"
        )
    elif step > span * (1 + 1e-9):
        fail(
            f"stock.trail_step = {step / INCH:.4g} in: larger than the trail range "
            f"{b.low / INCH:.4g} to {b.high / INCH:.4g} in ({span / INCH:.4g} in); use a smaller step"
        )
    count = int(math.floor(span / step + 1e-9)) + 1
    if count > 10_000:
        fail(
            f"stock.trail_step = {step / INCH:.4g} in: {count} fork holes; use a step of at least "
            f"{span / 10_000 / INCH:.3g} in"
        )
    return step, tuple(min(b.low + k * step, b.high) for k in range(count))


def _stock_wheels(
    raw: object, bounds: dict[str, Bound], grooves: tuple[float, ...] | None, fail: Callable[[str], NoReturn]
) -> tuple[StockWheel, ...]:
    """``stock.wheels``: named wheels, each with a diameter and optionally a groove and a measured I_w."""
    if not isinstance(raw, list):
        fail(f"stock.wheels = {raw!r}: expected a list of {{name, diameter, groove, inertia}} tables")
    if not raw:
        fail("stock.wheels = []: empty; list at least one wheel, or leave the key out")
    out: list[StockWheel] = []
    names: set[str] = set()
    for i, w in enumerate(raw):
        out.append(_stock_wheel(i, w, names, bounds, fail))
    given = [w.groove is not None for w in out]
    if any(given) and not all(given):
        fail("stock.wheels: give a groove for every wheel or for none (then [stock].grooves or continuous)")
    if all(given) and grooves is not None:
        fail("stock: the wheels give their grooves; leave stock.grooves out")
    return tuple(out)


def _stock_wheel(
    i: int, w: object, names: set[str], bounds: dict[str, Bound], fail: Callable[[str], NoReturn]
) -> StockWheel:
    """``stock.wheels[i]``: a table {name, diameter, groove, inertia} whose name is not in ``names`` (added)."""
    if not isinstance(w, dict):
        fail(
            f"stock.wheels[{i}] = {w!r}: expected a table such as "
            f'{{ name = "Frog 5", diameter = "5 in", groove = "0.25 in" }}'
        )
    extra = sorted(set(w) - {"name", "diameter", "groove", "inertia"})
    if extra:
        fail(f"stock.wheels[{i}].{_show_key(extra[0])}: unknown key; expected name, diameter, groove, inertia")
    for need in ("name", "diameter"):
        if need not in w:
            fail(f"stock.wheels[{i}].{need}: missing")
    name = w["name"]
    if not isinstance(name, str) or not name.strip():
        fail(f"stock.wheels[{i}].name = {name!r}: expected a non-empty string")
    if name in names:
        fail(f"stock.wheels[{i}].name = {name!r}: listed twice")
    names.add(name)
    d = _stock_values({"diameter": [w["diameter"]]}, "diameter", "length", "diameter", bounds, fail)[0]
    g = (
        _stock_values({"groove": [w["groove"]]}, "groove", "length", "groove", bounds, fail)[0]
        if "groove" in w
        else None
    )
    inertia_w = None
    if "inertia" in w:
        try:
            inertia_w = parse_quantity(w["inertia"], "inertia", f"stock.wheels[{i}].inertia")
        except InputError as exc:
            fail(str(exc))
        if not INERTIA_RANGE[0] <= inertia_w <= INERTIA_RANGE[1]:
            fail(
                f"stock.wheels[{i}].inertia = {inertia_w:g} kg·m²: outside {INERTIA_RANGE[0]:g} to "
                f"{INERTIA_RANGE[1]:g} kg·m²"
            )
    return StockWheel(name.strip(), d, g, inertia_w)


def _inertia(
    table: dict[str, Any], quantity: Callable[[str, str, str, None], float | None], fail: Callable[[str], NoReturn]
) -> tuple[InertiaModel, tuple[str, ...]]:
    model = table.get("model", "table1-power-law")
    if model not in INERTIA_MODELS:
        fail(f"inertia.model = {model!r}: expected one of {', '.join(INERTIA_MODELS)}")
    allowed = {
        "table1-power-law": {"model", "coefficient", "exponent"},
        "disc": {"model", "tyre_width", "density"},
        "catalog": {"model", "wheel", "wheels"},
        "fixed": {"model", "inertia"},
    }[model]
    extra = set(table) - allowed
    if extra:
        fail(
            f"inertia.{_show_key(sorted(extra)[0])}: not used by inertia model {model!r} (it takes {', '.join(sorted(allowed - {'model'})) or 'nothing else'})"
        )
    if model == "table1-power-law":
        coefficient = quantity("inertia", "coefficient", "dimensionless", None)
        exponent = quantity("inertia", "exponent", "dimensionless", None)
        if coefficient is not None and coefficient <= 0:
            fail(f"inertia.coefficient = {coefficient:g}: must be positive")
        if exponent is not None and not 0 < exponent < 10:
            fail(f"inertia.exponent = {exponent:g}: must be between 0 and 10")
        return PowerLaw(coefficient, exponent), ()
    if model == "disc":
        for key in ("tyre_width", "density"):
            if key not in table:
                fail(f"inertia.{key}: missing; the disc model needs tyre_width and density")
        width = quantity("inertia", "tyre_width", "length", None)
        density = quantity("inertia", "density", "density", None)
        assert width is not None and density is not None  # both keys are present (checked above)
        if width <= 0 or width > 0.2:
            fail(f"inertia.tyre_width = {width:g} m: must be between 0 and 0.2 m")
        if density <= 0 or density > 20000:
            fail(f"inertia.density = {density:g} kg/m³: must be between 0 and 20000")
        return Disc(width, density), ()
    if model == "fixed":
        if "inertia" not in table:
            fail("inertia.inertia: missing; the fixed model needs the measured I_w, e.g. '0.00127 kg*m**2'")
        value = quantity("inertia", "inertia", "inertia", None)
        assert value is not None  # the key is present (checked above)
        if not 0 < value < 0.1:
            fail(f"inertia.inertia = {value:g} kg·m²: must be between 0 and 0.1 kg·m²")
        return Fixed(value), ()
    return _catalog(table, fail)


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
                raise ProblemError(prefix + f"unknown key {key}.{_show_key(sub)}{_suggest(sub, list(SCHEMA[key]))}")


def _show_key(key: object) -> str:
    """A key as written in messages: plain if it is a simple word, else quoted (keeps the message one line)."""
    return key if isinstance(key, str) and re.fullmatch(r"[A-Za-z0-9_.-]+", key) else repr(key)


def _suggest(word: str, options: list[str]) -> str:
    match = difflib.get_close_matches(word, [o for o in options if o], n=1)
    return f" (did you mean {match[0]!r}?)" if match else ""
