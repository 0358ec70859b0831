"""Problem files (TOML) -> validated, immutable :class:`Problem` objects.

Schema: docs/problem-file.md.  Every quantity is a number in SI units or a string with
units ("2 in", "20 deg"); a design variable given one value instead of
``{min, max}`` is fixed.  Everything is checked before any solve, and every
error is one line naming the key, the value and the reason.
"""
from __future__ import annotations

import dataclasses
import difflib
import hashlib
import json
import math
import re
import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, NoReturn

from designer.data.paper import INCH, TABLE1
from designer import parameters
from designer.errors import ProblemError
from designer.reprs import html_table
from designer.model import MODEL_RANGE, VARIABLE_UNITS, VARIABLES, Conditions, Design
from designer.physics.inertia import Catalog, Disc, Fixed, InertiaModel, PowerLaw
from designer.physics.shimmy import DynamicsParameters
from designer.physics.turning import MODES, SURFACES, TurningConstants
from designer.units import InputError, outside_range, parse_quantity
from designer.physics.uncertainty import Uncertainty

DEFAULT_BOUNDS = parameters.DEFAULT_BOUNDS
"""Bounds used for a variable the problem file does not mention [SI] (from :mod:`designer.parameters`)."""

VARIABLE_DIMENSIONS = {p.name: p.dimension for p in parameters.VARIABLE_TABLE}

PHYSICAL_RANGE = parameters.checked_ranges()
"""Ranges [SI] (inclusive) of the fixed quantities: outside them the model's numbers overflow or
mean nothing, and a value there is almost always a unit mistake.  (low, high, unit, hint), by
problem-file key, from the entries of :mod:`designer.parameters` that have a hint."""

INERTIA_RANGE = (1e-9, 10.0)
"""Wheel moments of inertia [kg·m²] the model accepts at the diameter bounds (Table 1: 0.26e-3 to 4.6e-3)."""

WEIGHT_RANGE = (1e-6, 1e6)
"""The larger objective weight must lie in this range (weights are relative: scale them near 1)."""

POINTS_RANGE = (3, 2001)
"""Allowed number of Pareto front points, in a problem file ([pareto] points) and on the command line (--points)."""

MAX_SAMPLES = 10_000_000
"""Largest Monte Carlo sample of [robust] (memory grows with it)."""


def check_range(key: str, value: float, prefix: str = "") -> None:
    """Raise :class:`ProblemError` if ``value`` [SI] is outside :data:`PHYSICAL_RANGE` of ``key``.

    Parameters
    ----------
    key : "section.key" of :data:`PHYSICAL_RANGE`
    value : the value in SI units
    prefix : text put before the message (the file name)
    """
    low, high, unit, hint = PHYSICAL_RANGE[key]
    if not math.isfinite(value) or not low <= value <= high:
        raise ProblemError(f"{prefix}{key} = {value:g} {unit}".rstrip() +
                           f": outside the model's range {low:g} to {high:g} {unit}".rstrip() + f" ({hint})")


def check_weights(weights, key: str = "objective", error=ProblemError) -> tuple[float, float]:
    """Validate objective weights (w_turn, w_threshold); returns them as floats.

    Raises ``error`` (default :class:`ProblemError`) unless there are two finite,
    non-negative numbers whose larger lies in :data:`WEIGHT_RANGE`.
    """
    try:
        w = tuple(float(v) for v in weights)
    except (TypeError, ValueError, OverflowError):
        raise error(f"{key} = {weights!r}: expected two numbers (w_turn, w_threshold)") from None
    if len(w) != 2 or any((not math.isfinite(x)) or x < 0 for x in w) or sum(w) <= 0:
        raise error(f"{key} = {list(weights)}: weights must be finite, non-negative and not all zero")
    if not WEIGHT_RANGE[0] <= max(w) <= WEIGHT_RANGE[1]:
        raise error(f"{key} = {list(w)}: the larger weight must be between {WEIGHT_RANGE[0]:g} and "
                    f"{WEIGHT_RANGE[1]:g}; weights are relative, scale them to about 1")
    return w


# Allowed keys per section: key -> dimension (or a type tag).
SCHEMA: dict[str, dict[str, str]] = {
    "": {"name": "str", "title": "str", "description": "str"},
    "conditions": {"load": "force", "threshold_height": "length", "surface": "surface", "turning_mode": "mode"},
    "shimmy": {
        "target_speed": "speed",
        "margin": "dimensionless",
        "disturbance_angle": "angle",
        "slip_coefficient": "force",
    },
    "inertia": {
        "model": "str",
        "coefficient": "float",
        "exponent": "float",
        "tyre_width": "length",
        "density": "density",
        "wheel": "str",
        "wheels": "list",
        "inertia": "inertia",
    },
    "variables": {name: "bound" for name in VARIABLES},
    "constraints": {"swept_radius_max": "length"},
    "objective": {"turning_effort": "float", "threshold_force": "float", "max_threshold_force": "force",
                  "max_turning_effort": "force"},
    "pareto": {"points": "int"},
    "turning": {
        "tile_moment_per_load": "length",
        "carpet_factor": "dimensionless",
        "groove_coefficient": "per_length",
        "chair_factor": "dimensionless",
        "pivot_factor": "dimensionless",
        "bare_fork_damping": "damping",
    },
    "dynamics": {"frame_stiffness": "stiffness", "fork_mass": "mass", "bearing_block_mass": "mass"},
    "choices": {"surface": "list", "turning_mode": "list", "wheel": "list"},
    "robust": {"enabled": "bool", "probability": "float", "model_error": "float", "model_error_dof": "int",
               "damping": "float", "slip_coefficient": "float", "inertia": "float", "samples": "int", "seed": "int"},
    "stock": {"diameters": "list", "grooves": "list", "trail_step": "length", "dampings": "list", "wheels": "list"},
}

for _parameter in parameters.PARAMETERS.values():  # every key of the table is a key of the problem file
    if _parameter.key and not _parameter.key.startswith("variables."):
        _section, _key = _parameter.key.split(".", 1)
        SCHEMA.setdefault(_section, {})[_key] = _parameter.dimension

INERTIA_MODELS = ("table1-power-law", "disc", "catalog", "fixed")
NAME_PATTERN = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


@dataclass(frozen=True)
class Bound:
    """Bounds of one design variable [SI]; ``low == high`` means fixed."""

    low: float
    high: float

    @property
    def fixed(self) -> bool:
        return self.low == self.high


@dataclass(frozen=True)
class StockWheel:
    """A wheel on offer ([stock].wheels): name, diameter [m], groove [m] (None: from [stock].grooves or
    continuous) and measured I_w [kg·m²] (None: from the [inertia] model)."""

    name: str
    diameter: float
    groove: float | None = None
    inertia: float | None = None


@dataclass(frozen=True)
class Stock:
    """The parts that can be built ([stock]); a variable left ``None`` stays continuous within its bounds.

    Attributes
    ----------
    diameters : wheel diameters on offer [m] (I_w from the [inertia] model)
    grooves : tyre groove widths on offer [m]
    trail_step : fork-hole spacing [m]; the trails are variables.trail.min + k · step up to .max
    trails : the fork holes [m] (from ``trail_step`` and the trail bounds)
    dampings : spindle dampings on offer [N·m/rad] (bare bearing and friction washers)
    wheels : a catalogue of named wheels (instead of diameters and grooves)
    """

    diameters: tuple[float, ...] | None = None
    grooves: tuple[float, ...] | None = None
    trail_step: float | None = None
    trails: tuple[float, ...] | None = None
    dampings: tuple[float, ...] | None = None
    wheels: tuple[StockWheel, ...] | None = None

    def describe(self) -> str:
        """One line in inches and N·m/rad: what is on offer (``continuous`` where nothing is listed)."""
        def inches(values):
            return "continuous" if values is None else ", ".join(f"{v / INCH:g}" for v in values) + " in"

        parts = []
        if self.wheels is not None:
            parts.append("wheels " + ", ".join(w.name for w in self.wheels))
        else:
            parts.append(f"diameters {inches(self.diameters)}")
        if self.wheels is None or all(w.groove is None for w in self.wheels):
            parts.append(f"grooves {inches(self.grooves)}")
        parts.append("trails continuous" if self.trails is None else
                     f"trails {self.trails[0] / INCH:g} to {self.trails[-1] / INCH:g} in every "
                     f"{(self.trail_step or 0.0) / INCH:g} in ({len(self.trails)} holes)")
        parts.append("dampings continuous" if self.dampings is None else
                     "dampings " + ", ".join(f"{v:g}" for v in self.dampings) + " N·m/rad")
        return "; ".join(parts)

    def to_dict(self) -> dict:
        """Plain data in SI units."""
        return {"diameters": None if self.diameters is None else list(self.diameters),
                "grooves": None if self.grooves is None else list(self.grooves),
                "trail_step": self.trail_step,
                "trails": None if self.trails is None else list(self.trails),
                "dampings": None if self.dampings is None else list(self.dampings),
                "wheels": None if self.wheels is None else [dataclasses.asdict(w) for w in self.wheels]}


@dataclass(frozen=True)
class Problem:
    """A validated caster design problem (immutable).

    Attributes
    ----------
    name : identifier, safe as a folder name (results/<name>/)
    title : one-line description for reports
    conditions : load, sill, surface, turning mode and model constants
    target_speed : V_target [m/s]; the constraint is V_c >= (1 + margin) V_target
    margin : relative safety margin on the target speed [-]
    bounds : {variable: Bound}, SI
    swept_radius_max : optional limit on T + d/2 [m]
    weights : (w_turn, w_threshold) of J = w_turn F_turn + w_threshold P
    pareto_points : default number of points on the front
    wheels : Table 1 wheels to choose from when the inertia model is a catalog
    stock : the parts that can be built ([stock]), or None (every variable continuous)
    max_threshold_force : cap on P [N]: the recommendation is the least F_turn within it
    max_turning_effort : cap on F_turn [N]: the recommendation is the least P within it
    choices : categorical options for exploration {"surface": (...), ...}
    description : free text (whose chair, why these numbers)
    source : the file it was read from, if any
    """

    name: str
    title: str
    conditions: Conditions
    target_speed: float
    margin: float = 0.0
    bounds: dict = field(default_factory=lambda: {k: Bound(*v) for k, v in DEFAULT_BOUNDS.items()})
    swept_radius_max: float | None = None
    weights: tuple[float, float] = (1.0, 1.0)
    pareto_points: int = 41
    wheels: tuple[str, ...] = ()
    choices: dict = field(default_factory=dict)
    stock: Stock | None = None
    max_threshold_force: float | None = None
    max_turning_effort: float | None = None
    description: str = ""
    source: str | None = None

    def __post_init__(self):
        _validate(self, prefix=f"{self.source}: " if self.source else "")

    @property
    def risk(self):
        """The risk bound in force: an :class:`~designer.physics.uncertainty.Uncertainty` (P(V_c,true <
        (1 + margin) V_target) <= α), or None for the nominal Eq. 7 constraint (``[robust] enabled = false``)."""
        return self.conditions.uncertainty

    def nominal(self) -> "Problem":
        """The same problem without the risk bound: V_c (Eq. 7) >= (1 + margin) V_target (``enabled = false``)."""
        if self.conditions.uncertainty is None:
            return self
        return dataclasses.replace(self, conditions=self.conditions.replace(uncertainty=None))

    @property
    def required_speed(self) -> float:
        """(1 + margin) · V_target [m/s]: what V_c must reach."""
        return (1 + self.margin) * self.target_speed

    def replace(self, **changes) -> "Problem":
        """A validated copy with some fields changed (e.g. ``target_speed=3.0``)."""
        return dataclasses.replace(self, **changes)

    def lower(self) -> Design:
        """Lower bounds as a :class:`Design`."""
        return Design(*(self.bounds[v].low for v in VARIABLES))

    def upper(self) -> Design:
        """Upper bounds as a :class:`Design`."""
        return Design(*(self.bounds[v].high for v in VARIABLES))

    def variants(self) -> list["Problem"]:
        """Continuous sub-problems: one per catalog wheel (diameter and I_w fixed), else [self]."""
        if not self.wheels:
            return [self]
        out = []
        for key in self.wheels:
            model = Catalog.from_key(key)
            d = model.fixed_diameter
            bounds = dict(self.bounds)
            bounds["diameter"] = Bound(d, d)
            out.append(
                dataclasses.replace(
                    self, conditions=self.conditions.replace(inertia=model), bounds=bounds, wheels=()
                )
            )
        return out

    def model_warnings(self, diameters=None) -> list[str]:
        """Where the problem leaves the data its model rests on (said once, not per evaluation).

        With ``diameters`` [m] (those of the designs the tool reports): a warning only if one of them
        lies outside the inertia fit's data (Table 1, 4–8 in); without: if the diameter bounds do.
        """
        out = []
        model = self.conditions.inertia
        data = model.data_range()
        if data is not None and not self.wheels and diameters is not None:
            outside = [float(d) for d in diameters if not data[0] * 0.999 <= float(d) <= data[1] * 1.001]
            if outside:
                out.append(
                    f"{self.name}: a reported design uses d = {min(outside) / INCH:.3g}"
                    + (f"–{max(outside) / INCH:.3g}" if max(outside) > min(outside) else "")
                    + f" in, outside the Table 1 inertia fit ({data[0] / INCH:.0f}–{data[1] / INCH:.0f} in): "
                    f"its I_w is extrapolated"
                )
        elif data is not None and not self.wheels:
            b = self.bounds["diameter"]
            if b.low < data[0] * 0.999 or b.high > data[1] * 1.001:
                out.append(
                    f"{self.name}: the Table 1 inertia fit ({data[0] / INCH:.0f}–{data[1] / INCH:.0f} in) is "
                    f"extrapolated for diameters in {b.low / INCH:.3g}–{b.high / INCH:.3g} in"
                )
        return out

    def __repr__(self) -> str:
        """One line: name, required speed, load, sill, risk bound (the full record: :meth:`to_dict`)."""
        c, u = self.conditions, self.conditions.uncertainty
        risk = f"risk α = {u.probability:.3g}" if u is not None else "nominal V_c"
        return (f"Problem({self.name!r}: V_target {self.target_speed:.3g} m/s, required {self.required_speed:.3g} m/s, "
                f"load {c.load:.4g} N, sill {c.threshold_height * 1000:.3g} mm, {c.surface}, {risk}; "
                f"{'stock' if self.stock is not None else 'continuous'})")

    def _repr_html_(self) -> str:
        """The problem as a compact HTML table with units (notebooks); no solver runs."""
        c, u = self.conditions, self.conditions.uncertainty
        rows = [("target speed V_target", f"{self.target_speed:.4g}", "m/s"),
                ("required speed (1 + margin) V_target", f"{self.required_speed:.4g}", "m/s"),
                ("load", f"{c.load:.4g}", "N"),
                ("sill height", f"{c.threshold_height * 1000:.4g}", "mm"),
                ("surface / turning", f"{c.surface} / {c.turning_mode}", ""),
                ("risk bound α", f"{u.probability:.3g}" if u is not None else "off (nominal Eq. 7)", "")]
        for v in VARIABLES:
            b, unit = self.bounds[v], VARIABLE_UNITS.get(v, "")
            if unit == "m":
                rows.append((f"{v} bounds", f"{b.low * 1000:.4g} – {b.high * 1000:.4g}", "mm"))
            else:
                rows.append((f"{v} bounds", f"{b.low:.4g} – {b.high:.4g}", unit))
        if self.swept_radius_max is not None:
            rows.append(("swept radius max", f"{self.swept_radius_max * 1000:.4g}", "mm"))
        rows.append(("weights (w_turn, w_threshold)", f"{self.weights[0]:g}, {self.weights[1]:g}", ""))
        return html_table(f"Problem {self.name!r}", rows, caption=self.title)

    def digest(self) -> str:
        """SHA-256 of the problem's canonical content (for report metadata)."""
        return hashlib.sha256(json.dumps(self.to_dict(), sort_keys=True, default=str).encode()).hexdigest()[:16]

    def to_dict(self) -> dict:
        """Plain-data description of the problem in SI units."""
        c = self.conditions
        return {
            "name": self.name,
            "title": self.title,
            "load": c.load,
            "threshold_height": c.threshold_height,
            "surface": c.surface,
            "turning_mode": c.turning_mode,
            "disturbance_angle": c.disturbance_angle,
            "slip_coefficient": c.slip_coefficient,
            "inertia": c.inertia.describe(),
            "target_speed": self.target_speed,
            "margin": self.margin,
            "bounds": {k: [b.low, b.high] for k, b in self.bounds.items()},
            "swept_radius_max": self.swept_radius_max,
            "weights": list(self.weights),
            "wheels": list(self.wheels),
            "robust": None if c.uncertainty is None else dataclasses.asdict(c.uncertainty),
            "stock": None if self.stock is None else self.stock.to_dict(),
            "max_threshold_force": self.max_threshold_force,
            "max_turning_effort": self.max_turning_effort,
            "turning": {
                "tile_moment_per_load": c.turning.tile_moment_per_load,
                "carpet_factor": c.turning.carpet_factor,
                "groove_coefficient": c.turning.groove_coefficient,
                "mode_factors": c.turning.mode_factors,
                "bare_fork_damping": c.turning.bare_fork_damping,
            },
        }


def _validate(problem: Problem, prefix: str = "") -> None:  # noqa: C901 - a flat list of independent checks, each one line
    def fail(msg: str) -> NoReturn:
        raise ProblemError(prefix + msg)

    if not isinstance(problem.name, str) or not NAME_PATTERN.match(problem.name):
        fail(
            f"name = {problem.name!r}: must be 1–64 letters, digits, '-', '_' or '.', starting with a letter "
            f"or digit (it names the results folder)"
        )
    if problem.target_speed <= 0:
        fail(f"shimmy.target_speed = {problem.target_speed:g} m/s: must be positive")
    if problem.margin < 0 or problem.margin > 10:
        fail(f"shimmy.margin = {problem.margin:g}: must be between 0 and 10 (a fraction, 0.2 = 20 %)")
    c = problem.conditions
    if c.load <= 0:
        fail(f"conditions.load = {c.load:g} N: must be positive")
    if c.threshold_height <= 0:
        fail(f"conditions.threshold_height = {c.threshold_height:g} m: must be positive")
    for key, value in (("conditions.load", c.load), ("conditions.threshold_height", c.threshold_height),
                       ("shimmy.target_speed", problem.target_speed),
                       ("shimmy.slip_coefficient", c.slip_coefficient),
                       ("turning.tile_moment_per_load", c.turning.tile_moment_per_load),
                       ("turning.carpet_factor", c.turning.carpet_factor),
                       ("turning.chair_factor", c.turning.mode_factors["chair"]),
                       ("turning.pivot_factor", c.turning.mode_factors["pivot"]),
                       ("turning.groove_coefficient", c.turning.groove_coefficient),
                       ("turning.bare_fork_damping", c.turning.bare_fork_damping)):
        if value > 0 or key == "turning.groove_coefficient":
            check_range(key, value, prefix)
    if not 0 < c.disturbance_angle < math.pi / 2:
        fail(f"shimmy.disturbance_angle = {c.disturbance_angle:g} rad: must be between 0 and 90 deg")
    if c.slip_coefficient <= 0:
        fail(f"shimmy.slip_coefficient = {c.slip_coefficient:g} N: must be positive")
    if c.surface not in SURFACES:
        fail(f"conditions.surface = {c.surface!r}: expected one of {', '.join(SURFACES)}")
    if c.turning_mode not in MODES:
        fail(f"conditions.turning_mode = {c.turning_mode!r}: expected one of {', '.join(MODES)}")
    for name in VARIABLES:
        if name not in problem.bounds:
            fail(f"variables.{name}: missing bounds")
        b = problem.bounds[name]
        key = f"variables.{name}"
        lo, hi = MODEL_RANGE[name]
        for label, value in (("min", b.low), ("max", b.high)):
            if not math.isfinite(value):
                fail(f"{key}.{label} = {value}: must be finite")
            if value < 0 or (value == 0 and name in ("trail", "diameter", "damping")):
                fail(f"{key}.{label} = {value:g}: must be positive")
            if value > hi:
                fail(
                    f"{key}.{label} = {value:g} {VARIABLE_UNITS[name]}: outside the model's range "
                    f"(at most {hi:g}); were inches written as metres? write e.g. '2 in'"
                )
        if b.low > b.high:
            shown = (f" ({b.low / INCH:.4g} in > {b.high / INCH:.4g} in)" if VARIABLE_DIMENSIONS[name] == "length"
                     else "")
            fail(f"{key} = [{b.low:g}, {b.high:g}]: min is greater than max{shown}")
    h = c.threshold_height
    if not problem.wheels and problem.bounds["diameter"].low <= 2 * h:
        fail(
            f"variables.diameter.min = {problem.bounds['diameter'].low / INCH:.3g} in: must exceed twice the "
            f"threshold height ({2 * h / INCH:.3g} in); a wheel with d <= 2h cannot climb the sill (Eq. 4A)"
        )
    for key in problem.wheels:
        wheel = next((w for w in TABLE1 if w.key == key), None)
        if wheel is None:
            fail(f"inertia.wheels: unknown Table 1 wheel {key!r}; valid wheels are {', '.join(w.key for w in TABLE1)}")
        if wheel.diameter <= 2 * h:
            fail(f"inertia.wheels: wheel {key} (d = {wheel.diameter / INCH:.0f} in) cannot climb a "
                 f"{h / INCH:.3g} in sill (d/h <= 2, Eq. 4A)")
    c0 = c.turning.bare_fork_damping
    if problem.bounds["damping"].low < c0 - 1e-12:
        fail(
            f"variables.damping.min = {problem.bounds['damping'].low:g} N·m/rad: below the bare fork's "
            f"{c0:g} N·m/rad (Eq. 11C); set [turning] bare_fork_damping if your fork differs"
        )
    if problem.swept_radius_max is not None:
        r = problem.swept_radius_max
        if not r > 0:
            fail(f"constraints.swept_radius_max = {r:g} m: must be positive")
        check_range("constraints.swept_radius_max", r, prefix)
        smallest = problem.bounds["trail"].low + problem.bounds["diameter"].low / 2
        if problem.wheels:
            smallest = problem.bounds["trail"].low + min(Catalog.from_key(k).fixed_diameter for k in problem.wheels) / 2
        if r < smallest:
            fail(
                f"constraints.swept_radius_max = {r / INCH:.3g} in: smaller than the smallest possible "
                f"T + d/2 = {smallest / INCH:.3g} in; raise it or lower the trail/diameter minimum"
            )
    check_weights(problem.weights, prefix + "objective")
    if not problem.wheels:
        for label, d in (("min", problem.bounds["diameter"].low), ("max", problem.bounds["diameter"].high)):
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # extrapolation is reported where the model is used
                    inertia = float(c.inertia(d))
            except (OverflowError, ZeroDivisionError, ValueError):
                inertia = math.nan
            if not (math.isfinite(inertia) and INERTIA_RANGE[0] <= inertia <= INERTIA_RANGE[1]):
                fail(f"inertia: I_w = {inertia:g} kg·m² at variables.diameter.{label} = {d:g} m "
                     f"({c.inertia.describe()}): outside {INERTIA_RANGE[0]:g} to {INERTIA_RANGE[1]:g} kg·m²; "
                     f"check the inertia model's constants and the diameter bounds")
    if not isinstance(problem.pareto_points, int) or not POINTS_RANGE[0] <= problem.pareto_points <= POINTS_RANGE[1]:
        fail(f"pareto.points = {problem.pareto_points!r}: must be an integer from {POINTS_RANGE[0]} to {POINTS_RANGE[1]}")



# --------------------------------------------------------------------------- loading


def problem_files(where="problems") -> list[Path]:
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


def load_problem(path) -> Problem:
    """Read and validate a problem file (TOML, docs/problem-file.md).

    Raises
    ------
    ProblemError
        One line: the file, the key, the value and the reason (TOML syntax
        errors with their line number).
    """
    path = Path(path)
    if not path.exists():
        raise ProblemError(f"{path}: no such problem file")
    if path.is_dir():
        raise ProblemError(f"{path}: is a folder, expected a .toml problem file")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ProblemError(f"{path}: cannot read it ({exc.__class__.__name__}: {exc})") from None
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


def problem_from_dict(data: dict, source: str | None = None, default_name: str = "problem") -> Problem:  # noqa: C901 - reads the sections in order; each branch is one key's rule
    """Build a validated :class:`Problem` from a dict with the problem-file schema."""
    prefix = f"{source}: " if source else ""

    def fail(msg: str):
        raise ProblemError(prefix + msg)

    if not isinstance(data, dict):
        fail("a problem must be a table of sections")
    _check_keys(data, prefix)

    def section(name: str) -> dict:
        value = data.get(name, {})
        if not isinstance(value, dict):
            fail(f"[{name}] must be a table, got {type(value).__name__}")
        return value

    def quantity(sec: str, key: str, dimension: str, default):
        table = data if sec == "" else section(sec)
        if key not in table:
            return default
        try:
            return parse_quantity(table[key], dimension, f"{sec}.{key}" if sec else key)
        except InputError as exc:
            fail(str(exc))

    def text_value(sec: str, key: str, default: str) -> str:
        table = data if sec == "" else section(sec)
        value = table.get(key, default)
        if not isinstance(value, str):
            fail(f"{(sec + '.') if sec else ''}{key} = {value!r}: expected a string")
        return value

    def number(sec: str, key: str, default: float) -> float:
        table = section(sec)
        value = table.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            fail(f"{sec}.{key} = {value!r}: expected a number")
        if isinstance(value, int) and abs(value) > 1e300:
            fail(f"{sec}.{key}: an integer of about {int(value.bit_length() * 0.30103)} digits is too large")
        if not math.isfinite(value):
            fail(f"{sec}.{key} = {value!r}: must be finite")
        return float(value)

    name = text_value("", "name", default_name)
    title = text_value("", "title", name)
    description = text_value("", "description", "")

    # turning constants and dynamics first: conditions need them
    tdef = TurningConstants()
    turning = TurningConstants(
        tile_moment_per_load=quantity("turning", "tile_moment_per_load", "length", tdef.tile_moment_per_load),
        carpet_factor=quantity("turning", "carpet_factor", "dimensionless", tdef.carpet_factor),
        groove_coefficient=quantity("turning", "groove_coefficient", "per_length", tdef.groove_coefficient),
        mode_factors={
            "chair": quantity("turning", "chair_factor", "dimensionless", tdef.mode_factors["chair"]),
            "pivot": quantity("turning", "pivot_factor", "dimensionless", tdef.mode_factors["pivot"]),
        },
        bare_fork_damping=quantity("turning", "bare_fork_damping", "damping", tdef.bare_fork_damping),
    )
    for key, value in (
        ("tile_moment_per_load", turning.tile_moment_per_load),
        ("carpet_factor", turning.carpet_factor),
        ("chair_factor", turning.mode_factors["chair"]),
        ("pivot_factor", turning.mode_factors["pivot"]),
        ("bare_fork_damping", turning.bare_fork_damping),
    ):
        if value <= 0:
            fail(f"turning.{key} = {value:g}: must be positive")
    if turning.groove_coefficient < 0:
        fail(f"turning.groove_coefficient = {turning.groove_coefficient:g} 1/m: must be non-negative")

    ddef = DynamicsParameters()
    dynamics = DynamicsParameters(
        frame_stiffness=quantity("dynamics", "frame_stiffness", "stiffness", None),
        fork_mass=quantity("dynamics", "fork_mass", "mass", ddef.fork_mass),
        bearing_block_mass=quantity("dynamics", "bearing_block_mass", "mass", ddef.bearing_block_mass),
    )
    for key, value in (("frame_stiffness", dynamics.frame_stiffness), ("fork_mass", dynamics.fork_mass),
                       ("bearing_block_mass", dynamics.bearing_block_mass)):
        if value is not None and value <= 0:
            fail(f"dynamics.{key} = {value:g}: must be positive")

    inertia, wheels = _inertia(section("inertia"), quantity, fail)

    uncertainty = _uncertainty(section("robust"), fail)  # on by default: no [robust] gives the default scatter

    conditions = Conditions(
        uncertainty=uncertainty,
        load=quantity("conditions", "load", "force", parameters.default("load")),
        threshold_height=quantity("conditions", "threshold_height", "length", parameters.default("threshold_height")),
        surface=text_value("conditions", "surface", "tile"),
        turning_mode=text_value("conditions", "turning_mode", "chair"),
        disturbance_angle=quantity("shimmy", "disturbance_angle", "angle", parameters.default("disturbance_angle")),
        slip_coefficient=quantity("shimmy", "slip_coefficient", "force", parameters.default("slip_coefficient")),
        inertia=inertia,
        turning=turning,
        dynamics=dynamics,
    )
    if "target_speed" not in section("shimmy"):
        fail("shimmy.target_speed: missing; give the speed the caster must not shimmy below, e.g. '2.5 m/s'")

    bounds = {}
    variables = section("variables")
    for var in VARIABLES:
        if var not in variables:
            lo, hi = DEFAULT_BOUNDS[var]
            if var == "damping":
                lo = turning.bare_fork_damping
                hi = max(hi, lo)
            bounds[var] = Bound(lo, hi)
            continue
        spec = variables[var]
        dim = VARIABLE_DIMENSIONS[var]
        if isinstance(spec, dict):
            extra = set(spec) - {"min", "max"}
            if extra:
                fail(f"variables.{var}: unknown key {sorted(extra)[0]!r}; expected 'min' and 'max' or a single value")
            if "min" not in spec or "max" not in spec:
                missing = "min" if "min" not in spec else "max"
                fail(f"variables.{var}.{missing}: missing; give both min and max, or a single value to fix it")
            try:
                lo = parse_quantity(spec["min"], dim, f"variables.{var}.min")
                hi = parse_quantity(spec["max"], dim, f"variables.{var}.max")
            except InputError as exc:
                fail(str(exc))
            given = {f"variables.{var}.min": (spec["min"], lo), f"variables.{var}.max": (spec["max"], hi)}
        else:
            try:
                lo = hi = parse_quantity(spec, dim, f"variables.{var}")
            except InputError as exc:
                fail(str(exc))
            given = {f"variables.{var}": (spec, lo)}
        for key, (text, value) in given.items():  # said in the user's unit (validate() repeats it in SI)
            if value > MODEL_RANGE[var][1]:
                fail(outside_range(key, text, value, *MODEL_RANGE[var], dim))
        bounds[var] = Bound(lo, hi)
    if wheels:
        d_lo, d_hi = bounds["diameter"].low, bounds["diameter"].high
        if "diameter" in variables:
            kept = tuple(k for k in wheels if d_lo - 1e-9 <= Catalog.from_key(k).fixed_diameter <= d_hi + 1e-9)
            if not kept:
                fail(f"variables.diameter = [{d_lo / INCH:.3g}, {d_hi / INCH:.3g}] in: no catalog wheel in {list(wheels)} fits")
            wheels = kept
        diameters = [Catalog.from_key(k).fixed_diameter for k in wheels]
        bounds["diameter"] = Bound(min(diameters), max(diameters))

    objective = section("objective")
    weights = (number("objective", "turning_effort", 1.0), number("objective", "threshold_force", 1.0))
    caps = {}
    for key in ("max_threshold_force", "max_turning_effort"):
        value = quantity("objective", key, "force", None)
        if value is not None and not (math.isfinite(value) and 0 < value < 1e5):
            fail(f"objective.{key} = {value:g} N: must be a positive force below 1e5 N")
        caps[key] = value
    if caps["max_threshold_force"] is not None and caps["max_turning_effort"] is not None:
        fail("objective: give max_threshold_force or max_turning_effort, not both (the recommendation caps one "
             "objective and minimises the other)")
    stock = _stock(section("stock"), bounds, inertia, wheels, conditions.threshold_height, fail) \
        if "stock" in data else None
    points = section("pareto").get("points", 41)
    if isinstance(points, bool) or not isinstance(points, int):
        fail(f"pareto.points = {points!r}: expected an integer")
    del objective

    choices = {}
    for key, allowed in (("surface", SURFACES), ("turning_mode", MODES), ("wheel", tuple(w.key for w in TABLE1))):
        if key in section("choices"):
            values = section("choices")[key]
            if not isinstance(values, list) or not values or any(v not in allowed for v in values):
                fail(f"choices.{key} = {values!r}: expected a non-empty list from {', '.join(allowed)}")
            choices[key] = tuple(values)

    return Problem(
        name=name,
        title=title,
        description=description,
        conditions=conditions,
        target_speed=quantity("shimmy", "target_speed", "speed", None),
        margin=quantity("shimmy", "margin", "dimensionless", 0.0),
        bounds=bounds,
        swept_radius_max=quantity("constraints", "swept_radius_max", "length", None),
        weights=weights,
        pareto_points=points,
        wheels=wheels,
        choices=choices,
        stock=stock,
        max_threshold_force=caps["max_threshold_force"],
        max_turning_effort=caps["max_turning_effort"],
        source=source,
    )


def _uncertainty(table: dict, fail):
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
        if isinstance(value, bool) or not isinstance(value, (int, float)) or abs(value) > 1e300 \
                or not math.isfinite(value):
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


def _stock_values(table: dict, key: str, dimension: str, variable: str, bounds: dict, fail) -> tuple[float, ...]:
    """A [stock] list in SI, each value inside ``variable``'s bounds (deduplicated, sorted)."""
    values = table[key]
    if isinstance(values, (str, int, float)) or not isinstance(values, list):
        fail(f"stock.{key} = {values!r}: expected a list, e.g. [\"4 in\", \"5 in\"]")
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
            shown = (f"{v / INCH:.4g} in outside variables.{variable} = [{b.low / INCH:.4g}, {b.high / INCH:.4g}] in"
                     if dimension == "length" else
                     f"{v:g} {unit} outside variables.{variable} = [{b.low:g}, {b.high:g}] {unit}")
            fail(f"stock.{key}[{i}] = {raw!r}: {shown}; widen the bounds or drop the part")
        out.append(min(max(v, b.low), b.high))
    return tuple(sorted(set(out)))


def _stock(table: dict, bounds: dict, inertia, catalog: tuple, sill: float,  # noqa: C901 - one rule per [stock] key
           fail: Callable[[str], NoReturn]) -> Stock:
    """Parse [stock] against the bounds and the inertia model (one-line errors, exit 3)."""
    if not table:
        fail("[stock] is empty; list diameters, grooves, trail_step or dampings (a key left out stays continuous)")
    model = getattr(inertia, "name", "")
    if "diameters" in table or "wheels" in table:
        key = "diameters" if "diameters" in table else "wheels"
        if catalog:
            fail(f"stock.{key}: not allowed with [inertia] model = \"catalog\"; the wheel stock is "
                 f"[inertia].wheels ({', '.join(catalog)})")
        if model == "fixed" or isinstance(inertia, Fixed):
            fail(f"stock.{key}: not allowed with [inertia] model = \"fixed\"; a fixed inertia is one measured "
                 f"wheel, so the diameter is fixed (set variables.diameter to it)")
    if "diameters" in table and "wheels" in table:
        fail("stock: give diameters (and grooves) or wheels, not both")
    diameters = _stock_values(table, "diameters", "length", "diameter", bounds, fail) if "diameters" in table else None
    grooves = _stock_values(table, "grooves", "length", "groove", bounds, fail) if "grooves" in table else None
    dampings = _stock_values(table, "dampings", "damping", "damping", bounds, fail) if "dampings" in table else None
    trails = step = None
    if "trail_step" in table:
        try:
            step = parse_quantity(table["trail_step"], "length", "stock.trail_step")
        except InputError as exc:
            fail(str(exc))
        b = bounds["trail"]
        span = max(b.high - b.low, 0.0)  # inverted bounds are validate()'s one-line error, not the step's
        if not step > 0 or not math.isfinite(step):
            fail(f"stock.trail_step = {table['trail_step']!r}: must be a positive length, e.g. \"0.25 in\"")
        if b.low > b.high:
            pass  # inverted trail bounds: validate() names variables.trail (min greater than max)
        elif span <= 0:
            fail(f"stock.trail_step = {table['trail_step']!r}: variables.trail is fixed at {b.low / INCH:.4g} in; "
                 f"leave trail_step out")
        elif step > span * (1 + 1e-9):
            fail(f"stock.trail_step = {step / INCH:.4g} in: larger than the trail range "
                 f"{b.low / INCH:.4g} to {b.high / INCH:.4g} in ({span / INCH:.4g} in); use a smaller step")
        count = int(math.floor(span / step + 1e-9)) + 1
        if count > 10_000:
            fail(f"stock.trail_step = {step / INCH:.4g} in: {count} fork holes; use a step of at least "
                 f"{span / 10_000 / INCH:.3g} in")
        trails = tuple(min(b.low + k * step, b.high) for k in range(count))
    wheels = None
    if "wheels" in table:
        raw = table["wheels"]
        if not isinstance(raw, list):
            fail(f"stock.wheels = {raw!r}: expected a list of {{name, diameter, groove, inertia}} tables")
        if not raw:
            fail("stock.wheels = []: empty; list at least one wheel, or leave the key out")
        out, names = [], set()
        for i, w in enumerate(raw):
            if not isinstance(w, dict):
                fail(f"stock.wheels[{i}] = {w!r}: expected a table such as "
                     f"{{ name = \"Frog 5\", diameter = \"5 in\", groove = \"0.25 in\" }}")
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
            g = (_stock_values({"groove": [w["groove"]]}, "groove", "length", "groove", bounds, fail)[0]
                 if "groove" in w else None)
            inertia_w = None
            if "inertia" in w:
                try:
                    inertia_w = parse_quantity(w["inertia"], "inertia", f"stock.wheels[{i}].inertia")
                except InputError as exc:
                    fail(str(exc))
                if not INERTIA_RANGE[0] <= inertia_w <= INERTIA_RANGE[1]:
                    fail(f"stock.wheels[{i}].inertia = {inertia_w:g} kg·m²: outside {INERTIA_RANGE[0]:g} to "
                         f"{INERTIA_RANGE[1]:g} kg·m²")
            out.append(StockWheel(name.strip(), d, g, inertia_w))
        given = [w.groove is not None for w in out]
        if any(given) and not all(given):
            fail("stock.wheels: give a groove for every wheel or for none (then [stock].grooves or continuous)")
        if all(given) and grooves is not None:
            fail("stock: the wheels give their grooves; leave stock.grooves out")
        wheels = tuple(out)
    return Stock(diameters=diameters, grooves=grooves, trail_step=step, trails=trails, dampings=dampings,
                 wheels=wheels)


def _inertia(table: dict, quantity, fail) -> tuple[InertiaModel, tuple[str, ...]]:  # noqa: C901 - one branch per model
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
        fail(f"inertia.{_show_key(sorted(extra)[0])}: not used by inertia model {model!r} (it takes {', '.join(sorted(allowed - {'model'})) or 'nothing else'})")
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
        if width <= 0 or width > 0.2:
            fail(f"inertia.tyre_width = {width:g} m: must be between 0 and 0.2 m")
        if density <= 0 or density > 20000:
            fail(f"inertia.density = {density:g} kg/m³: must be between 0 and 20000")
        return Disc(width, density), ()
    if model == "fixed":
        if "inertia" not in table:
            fail("inertia.inertia: missing; the fixed model needs the measured I_w, e.g. '0.00127 kg*m**2'")
        value = quantity("inertia", "inertia", "inertia", None)
        if not 0 < value < 0.1:
            fail(f"inertia.inertia = {value:g} kg·m²: must be between 0 and 0.1 kg·m²")
        return Fixed(value), ()
    # catalog
    if "wheel" in table and "wheels" in table:
        fail("inertia: give either wheel = \"C\" or wheels = [\"A\", ...], not both")
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


def _check_keys(data: dict, prefix: str) -> None:
    for key, value in data.items():
        if key in SCHEMA[""]:
            continue
        if key not in SCHEMA:
            raise ProblemError(prefix + f"unknown section or key {key!r}{_suggest(key, list(SCHEMA) + list(SCHEMA['']))}")
        if not isinstance(value, dict):
            raise ProblemError(prefix + f"[{key}] must be a table, got {value!r}")
        for sub in value:
            if sub not in SCHEMA[key]:
                raise ProblemError(prefix + f"unknown key {key}.{_show_key(sub)}{_suggest(sub, list(SCHEMA[key]))}")


def _show_key(key) -> str:
    """A key as written in messages: plain if it is a simple word, else quoted (keeps the message one line)."""
    return key if isinstance(key, str) and re.fullmatch(r"[A-Za-z0-9_.-]+", key) else repr(key)


def _suggest(word: str, options: list[str]) -> str:
    match = difflib.get_close_matches(word, [o for o in options if o], n=1)
    return f" (did you mean {match[0]!r}?)" if match else ""
