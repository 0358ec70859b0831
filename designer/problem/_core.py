"""The :class:`Problem` record and its validation: bounds, stock, risk, constraint margins, ranges, SCHEMA.

A :class:`Problem` is immutable and validated on construction; every error is one line naming the key,
the value and the reason.  The problem-file loader (TOML -> Problem) is :mod:`designer.problem._loader`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import re
import warnings
from dataclasses import dataclass, field
from collections.abc import Mapping
from typing import Any, Callable, Iterable, NoReturn


from designer.data.paper import INCH, TABLE1
from designer import display, parameters
from designer.errors import InputError, ProblemError
from designer.reprs import Key, Keyed, Record, frozen
from designer.display import number, percent, shown, unit_text
from designer.units import outside_range, parse_quantity, real_number, whole_number
from designer.model import (
    CONDITION_CHOICES,
    CONDITION_NUMBERS,
    FAMILIES,
    MODEL_RANGE,
    VARIABLES,
    Conditions,
    Design,
    condition_refusal,
    evaluate,
)
from designer.physics.inertia import Catalog
from designer.physics.uncertainty import Uncertainty

DEFAULT_BOUNDS = parameters.DEFAULT_BOUNDS
"""Bounds used for a variable the problem file does not mention [SI] (from :mod:`designer.parameters`)."""

VARIABLE_DIMENSIONS = {p.name: p.dimension for p in parameters.VARIABLE_TABLE}

PHYSICAL_RANGE = parameters.checked_ranges()
"""Ranges [SI] (inclusive) of the fixed quantities: outside them the model's numbers overflow or
mean nothing, and a value there is almost always a unit mistake.  (low, high, unit, hint), by
problem-file key, from the entries of :mod:`designer.parameters` that have a hint."""

_BY_KEY = {p.key: p.name for p in parameters.PARAMETERS.values() if p.key}
"""Table entry name by problem-file key."""

INERTIA_RANGE = (1e-9, 10.0)
"""Wheel moments of inertia [kg·m²] the model accepts at the diameter bounds (Table 1: 0.26e-3 to 4.6e-3)."""

WEIGHT_RANGE = (1e-6, 1e6)
"""The larger objective weight must lie in this range (weights are relative: scale them near 1)."""

POINTS_RANGE = (3, 2001)
"""Allowed number of Pareto front points, in a problem file ([pareto] points) and on the command line (--points)."""

PROBABILITY_RANGE = (1e-3, 0.5)
"""Allowed risk bound α of [robust] probability: 0.001 <= α < 0.5.  Below 0.001 the bound is no longer
computed to its stated accuracy: the (1 − α)-quantile of the model error's Student t (ν = 5) plus the
normal rest is a fitted Chebyshev series shifted up by its largest error against the exact quadrature, and
that shift grows from 6e-5 at α = 0.001 to 0.06 at 1e-4 and 7 at 1e-6 (a bound far stricter than the α
asked for); below about 1e-16, 1 − α rounds to 1 and the quantile is infinite (NaN in the solvers).
Reachable: at α = 0.001 the t_5 model error alone (scale 0.1075) asks V_c >= 1.9 × V_req, which the shipped
problems' bounds give.  From 0.5 up the bound would allow shimmy more often than not."""

MAX_SAMPLES = 10_000_000
"""Largest Monte Carlo sample of [robust] (memory grows with it)."""


def parsed(value: Any, dimension: str, key: str, fail: Callable[[str], NoReturn]) -> float:
    """:func:`designer.units.parse_quantity` of ``value`` named ``key``; its InputError raised through ``fail``
    (the problem's one-line error, with the file's name)."""
    try:
        return parse_quantity(value, dimension, key)
    except InputError as exc:
        fail(str(exc))


def inches(value: float) -> str:
    """A length [m] in inches, as the problem file's messages say it ("2.500 in": :func:`designer.display.shown`)."""
    return shown(value, dimension="length", units="in")


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
        raise ProblemError(
            f"{prefix}{key} = {value:g} {unit}".rstrip()
            + f": outside the model's range {low:g} to {high:g} {unit}".rstrip()
            + f" ({hint})"
        )


def check_weights(
    weights: Iterable[float], key: str = "objective", error: type[Exception] = ProblemError
) -> tuple[float, float]:
    """Validate objective weights (w_turn, w_threshold); returns them as floats.

    Raises ``error`` (default :class:`ProblemError`) unless there are two finite,
    non-negative numbers whose larger lies in :data:`WEIGHT_RANGE`.
    """
    try:  # each weight by the API's one rule for numbers (a boolean is not a weight)
        w = tuple(real_number(v, f"{key}[{i}]") for i, v in enumerate(weights))
    except InputError as exc:
        raise error(f"{key} = {weights!r}: expected two numbers (w_turn, w_threshold); {exc}") from None
    except TypeError:
        raise error(f"{key} = {weights!r}: expected two numbers (w_turn, w_threshold)") from None
    bad = [(n, x) for n, x in zip(("w_turn", "w_threshold"), w) if not (math.isfinite(x) and x >= 0)]
    if len(w) != 2 or bad or sum(w) <= 0:
        reason = f"{bad[0][0]} = {bad[0][1]:g} must be a finite non-negative number" if bad else ""
        raise error(f"{key} = {list(weights)}: {reason or 'expected two weights, not all zero'}")
    if not WEIGHT_RANGE[0] <= max(w) <= WEIGHT_RANGE[1]:
        raise error(
            f"{key} = {list(w)}: the larger weight must be between {WEIGHT_RANGE[0]:g} and "
            f"{WEIGHT_RANGE[1]:g}; weights are relative, scale them to about 1"
        )
    return w


SCHEMA: dict[str, dict[str, str]] = {
    "": {"name": "str", "title": "str", "description": "str"},
    "conditions": {"surface": "surface", "turning_mode": "mode", "mass": "mass", "front_fraction": "dimensionless"},
    "inertia": {"model": "str", "wheel": "str", "wheels": "list"},
    "variables": {name: "bound" for name in VARIABLES},
    "objective": {
        "turning_effort": "float",
        "threshold_force": "float",
        "max_threshold_force": "force",
        "max_turning_effort": "force",
    },
    "pareto": {"points": "int"},
    "choices": {"surface": "list", "turning_mode": "list", "wheel": "list"},
    "robust": {"enabled": "bool", **{f.name: str(f.type) for f in dataclasses.fields(Uncertainty)}},
    "stock": {
        **dict.fromkeys(("diameters", "grooves", "dampings", "wheels"), "list"),
        "trail_step": "length",
        "costs": "table",
    },
    "report": {"units": "str"},
    "retrofit": {"max_threshold_increase": "dimensionless", "max_turning_increase": "dimensionless"},
    "tolerances": {
        **dict.fromkeys(("trail", "groove", "diameter"), "length"),
        "friction_moment": "dimensionless",
        "stem_angle": "angle",
        "wheel": "str",
        "enforce": "bool",
    },
}
"""Allowed keys per section: key -> dimension (or a type tag).  The model constants' keys are added from
the parameter table just below, so a new constant needs no line here."""

for _parameter in parameters.PARAMETERS.values():  # every key of the table is a key of the problem file
    if _parameter.key and not _parameter.key.startswith("variables."):
        _section, _key = _parameter.key.split(".", 1)
        SCHEMA.setdefault(_section, {})[_key] = _parameter.dimension

INERTIA_MODELS = ("table1-power-law", "disc", "catalog", "fixed")
REPORT_UNITS = ("in", "mm")
"""``[report] units``: sizes in inches (to 1/16) or millimetres (to 0.1)."""
NAME_PATTERN = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


@dataclass(frozen=True)
class Bound:
    """Bounds of one design variable [SI]; ``low == high`` means fixed."""

    low: float
    high: float

    def __post_init__(self) -> None:
        for name in ("low", "high"):
            value = getattr(self, name)
            if type(value) is not float:  # a float as it is (a NaN is refused by the problem, with its key)
                try:  # else the package's one rule for a number: NumPy scalars and 0-d arrays, never a boolean
                    value = real_number(value, name)
                except InputError:
                    raise InputError(f"Bound({name}={value!r}): expected a number [SI]") from None
            object.__setattr__(self, name, value)

    @property
    def fixed(self) -> bool:
        return self.low == self.high


PART_KINDS = ("washer", "tyre", "fork hole", "wheel")
"""The four kinds of part a retrofit changes, cheapest first (``[stock] costs`` keys: ``washer``, ``tyre``,
``fork_hole``, ``wheel``)."""

DEFAULT_PART_COSTS = {"washer": 1.0, "tyre": 2.0, "fork hole": 3.0, "wheel": 4.0}
"""Cost of one part of each kind when ``[stock] costs`` leaves it out, in the order of price a seating shop
sees (a friction washer, a tyre, another fork hole or a new fork, a wheel); relative units, any currency."""

DEFAULT_MAX_THRESHOLD_INCREASE = 0.10
"""``[retrofit] max_threshold_increase``: a fix may raise the sill force by at most 10 % of the current caster's
(a clinician's limit: about 10 N on a 100 N sill force, what a user notices over a door sill)."""
DEFAULT_MAX_TURNING_INCREASE = 0.10
"""``[retrofit] max_turning_increase``: a fix may raise the turning effort by at most 10 % of the current
caster's (a cheap fix that makes the chair much harder to turn is not one a clinician fits)."""


@dataclass(frozen=True)
class StockWheel:
    """A wheel on offer ([stock].wheels): name, diameter [m], groove [m] (None: from [stock].grooves or
    continuous), measured I_w [kg·m²] (None: from the [inertia] model) and its cost (None: [stock] costs'
    wheel)."""

    name: str
    diameter: float
    groove: float | None = None
    inertia: float | None = None
    cost: float | None = None


@dataclass(frozen=True)
class Stock(Keyed):
    """The parts that can be built ([stock]); a variable left ``None`` stays continuous within its bounds.

    Attributes
    ----------
    diameters : wheel diameters on offer [m] (I_w from the [inertia] model)
    grooves : tyre groove widths on offer [m]
    trail_step : fork-hole spacing [m]; the trails are variables.trail.min + k · step up to .max
    trails : the fork holes [m] (from ``trail_step`` and the trail bounds)
    dampings : spindle dampings on offer [N·m/rad] (bare bearing and friction washers)
    wheels : a catalogue of named wheels (instead of diameters and grooves)
    costs : the cost of one part of each kind {washer, tyre, fork hole, wheel} (``[stock] costs``, defaults
        :data:`DEFAULT_PART_COSTS`), relative units
    item_costs : {variable: {value [SI]: cost}} of the items listed with their own cost
        (``{ value = "7 in", cost = 6 }`` in ``diameters``, ``grooves`` or ``dampings``)
    """

    diameters: tuple[float, ...] | None = None
    grooves: tuple[float, ...] | None = None
    trail_step: float | None = None
    trails: tuple[float, ...] | None = None
    dampings: tuple[float, ...] | None = None
    wheels: tuple[StockWheel, ...] | None = None
    costs: Mapping[str, float] = field(default_factory=lambda: dict(DEFAULT_PART_COSTS))
    item_costs: Mapping[str, Mapping[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "costs", frozen(self.costs))
        object.__setattr__(self, "item_costs", frozen(self.item_costs))

    def cost(self, kind: str, value: float | None = None) -> float:
        """The cost of one part of ``kind`` (one of :data:`PART_KINDS`), of the item ``value`` [SI] when it was
        listed with its own cost."""
        variable = {"washer": "damping", "tyre": "groove", "fork hole": "trail", "wheel": "diameter"}[kind]
        own = self.item_costs.get(variable, {})
        listed = [c for v, c in own.items() if value is not None and abs(v - value) <= 1e-9 * max(1.0, abs(value))]
        return listed[0] if listed else self.costs.get(kind, DEFAULT_PART_COSTS[kind])

    _keys = (
        "*",
        Key("item_costs", lambda s: {k: [[v, c] for v, c in sorted(d.items())] for k, d in s.item_costs.items()}),
    )
    """Plain data in SI units: every field; ``item_costs`` as ``{variable: [[value, cost], ...]}`` by value (JSON
    keys are strings, the values are numbers)."""


TOLERANCE_MAX_LENGTH = 1.0 * INCH
"""Largest spread [m] of a toleranced length (1 in): a spread of a part, not a part's size."""


@dataclass(frozen=True)
class Tolerances(Keyed):
    """``[tolerances]``: each part's manufacturing spread, ± about its nominal value (SI; None: not toleranced).

    Attributes
    ----------
    trail, groove, diameter : ± [m]
    friction_moment : relative spread of M_f = c_f θ0 [-] (0.2 = ±20 %), its loss over the caster's life
        (washers and bearings wear) included
    wheel : the largest measured wheel inertia goods-in accepts [kg·m²], or None ("catalogue": the wheel's
        inertia as the problem's inertia model gives it, at the diameter's worst edge)
    enforce : the recommendation is chosen among the casters that hold the risk bound at the worst corner
    """

    trail: float | None = None
    groove: float | None = None
    diameter: float | None = None
    friction_moment: float | None = None
    wheel: float | None = None
    enforce: bool = False


TURNING_KEYS = ("tile_moment_per_load", "carpet_factor", "groove_coefficient", "mode_factors", "bare_fork_damping")
"""The turning model's constants in :meth:`Problem.to_dict` (under ``turning``), in this order."""


@dataclass(frozen=True)
class Problem(Record):
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
    max_threshold_increase : a retrofit's limit on the sill force, relative to the current caster's [-]
    max_turning_increase : a retrofit's limit on the turning effort, relative to the current caster's [-]
    tolerances : ``[tolerances]``, the manufacturing spread of each part (:class:`Tolerances`), or None
    choices : categorical options for exploration {"surface": (...), ...}
    description : free text (whose chair, why these numbers)
    source : the file it was read from, if any
    units : how reports write sizes, "in" (to 1/16 in) or "mm" (to 0.1 mm): ``[report] units``, or the unit
        the file's lengths are written in (display only: not part of :meth:`to_dict`, the digest nor equality)
    """

    name: str
    title: str
    conditions: Conditions
    target_speed: float
    margin: float = 0.0
    bounds: Mapping[str, Bound] = field(default_factory=lambda: {k: Bound(*v) for k, v in DEFAULT_BOUNDS.items()})
    swept_radius_max: float | None = None
    weights: tuple[float, float] = (1.0, 1.0)
    pareto_points: int = 41
    wheels: tuple[str, ...] = ()
    choices: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    stock: Stock | None = None
    max_threshold_force: float | None = None
    max_turning_effort: float | None = None
    max_threshold_increase: float = DEFAULT_MAX_THRESHOLD_INCREASE
    max_turning_increase: float = DEFAULT_MAX_TURNING_INCREASE
    tolerances: Tolerances | None = None
    description: str = ""
    source: str | None = None
    units: str = field(default="in", compare=False)  # display only: equal problems may write sizes otherwise

    _keys = (
        "name",
        "title",
        *(Key(n, f"conditions.{n}") for n in ("load", "threshold_height", "surface", "turning_mode")),
        *(Key(n, f"conditions.{n}") for n in ("disturbance_angle", "slip_coefficient")),
        Key("inertia", "conditions.inertia.describe()"),
        "target_speed",
        "margin",
        Key("bounds", lambda p: {k: [b.low, b.high] for k, b in p.bounds.items()}),
        "swept_radius_max",
        "weights",
        "wheels",
        Key("robust", "conditions.uncertainty"),
        "stock",
        "max_threshold_force",
        "max_turning_effort",
        "max_threshold_increase",
        "max_turning_increase",
        *(Key(f"turning.{n}", f"conditions.turning.{n}") for n in TURNING_KEYS),
        Key("tolerances", omit="none"),
    )
    """The plain data of :meth:`to_dict` (SI): the conditions' numbers at the top level, the turning model's under
    ``turning``, ``tolerances`` only when given; the digest is of this dict."""

    def __post_init__(self) -> None:
        prefix = f"{self.source}: " if self.source else ""
        _normalise(self, prefix)
        _validate(self, prefix=prefix)

    @property
    def risk(self) -> Uncertainty | None:
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

    def replace(self, **changes: Any) -> "Problem":
        """A validated copy with some fields changed (e.g. ``target_speed=3.0``)."""
        return dataclasses.replace(self, **changes)

    def evaluate(self, designs: Any, **options: Any) -> Any:
        """:func:`designer.model.evaluate` of ``designs`` under this problem: its conditions, its limits
        (V_req = (1 + margin) V_target, the swept radius R_max) and its weights; UserWarnings of the inertia fit
        silenced (the report states an extrapolation once).  Returns Casters (a Caster for one Design)."""
        options.setdefault("weights", self.weights)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            return evaluate(
                designs,
                self.conditions,
                required_speed=self.required_speed,
                swept_radius_max=self.swept_radius_max,
                **options,
            )

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
        for model in map(Catalog.from_key, self.wheels):
            bounds = {**self.bounds, "diameter": Bound(model.fixed_diameter, model.fixed_diameter)}
            out.append(
                dataclasses.replace(self, conditions=self.conditions.replace(inertia=model), bounds=bounds, wheels=())
            )
        return out

    def model_warnings(self, diameters: Iterable[float] | None = None, front: bool = False) -> list[str]:
        """Where the problem leaves the data its model rests on (said once, not per evaluation).

        With ``diameters`` [m] (those of the designs the tool reports): a warning only if one of them
        lies outside the inertia fit's data (Table 1, 4–8 in); without: if the diameter bounds do.
        ``front``: the diameters are a front's points, and the warning says so (the recommended caster
        may well lie inside the data while the front's end does not).
        """
        data = self.conditions.inertia.data_range()
        if data is None or self.wheels:
            return []
        fit = f"the Table 1 inertia fit ({data[0] / INCH:.0f}–{data[1] / INCH:.0f} in)"
        if diameters is None:
            b = self.bounds["diameter"]
            if b.low < data[0] * 0.999 or b.high > data[1] * 1.001:
                return [
                    f"{self.name}: {fit} is extrapolated for diameters in {b.low / INCH:.3g}–{b.high / INCH:.3g} in"
                ]
            return []
        outside = [float(d) for d in diameters if not data[0] * 0.999 <= float(d) <= data[1] * 1.001]
        if not outside:
            return []
        span = f"{min(outside) / INCH:.3g}" + (f"–{max(outside) / INCH:.3g}" if max(outside) > min(outside) else "")
        uses, its = ("points of the front use", "their") if front else ("a reported design uses", "its")
        return [f"{self.name}: {uses} d = {span} in, outside {fit}: {its} I_w is extrapolated"]

    def _repr_lines(self) -> list[str]:
        """One line: name, required speed, load, sill, risk bound (the full record: :meth:`to_dict`)."""
        c, u = self.conditions, self.conditions.uncertainty
        risk = f"risk α = {u.probability:.3g}" if u is not None else "nominal V_c"
        return [
            f"Problem({self.name!r}: V_target {self.target_speed:.3g} m/s, required {self.required_speed:.3g} m/s, "
            f"load {c.load:.4g} N, sill {c.threshold_height * 1000:.3g} mm, {c.surface}, {risk}; "
            f"{'stock' if self.stock is not None else 'continuous'})"
        ]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The problem as a compact table with units (notebooks); no solver runs."""
        c, u, units = self.conditions, self.conditions.uncertainty, self.units
        given: dict[str, float | None] = {"target_speed": self.target_speed, "load": c.load}
        given |= {"threshold_height": c.threshold_height, "swept_radius_max": self.swept_radius_max}
        rows: list[tuple[Any, Any, Any]] = [
            (display.label(n), number(v, n, units), unit_text(n, units)) for n, v in given.items() if v is not None
        ]
        rows += [
            (f"{v} bounds", f"{number(b.low, v, units)} – {number(b.high, v, units)}", unit_text(v, units))
            for v, b in ((v, self.bounds[v]) for v in VARIABLES)
        ]
        return rows + [
            ("required speed (1 + margin) V_target", number(self.required_speed, "target_speed"), "m/s"),
            ("surface / turning", f"{c.surface} / {c.turning_mode}", ""),
            ("risk bound α", percent(u.probability) if u is not None else "off (nominal Eq. 7)", ""),
            ("weights (w_turn, w_threshold)", f"{self.weights[0]:g}, {self.weights[1]:g}", ""),
        ]

    def digest(self) -> str:
        """SHA-256 of the problem's canonical content (for report metadata)."""
        return hashlib.sha256(json.dumps(self.to_dict(), sort_keys=True, default=str).encode()).hexdigest()[:16]


def family_of(problem: Problem, design: Design, tol: float = 1e-6) -> str:
    """Which mechanism stabilises ``design`` within ``problem``'s bounds: groove, added damper, both or neither.

    Grooved: B above its lower bound by more than ``tol`` of max(B_hi, 1 mm); damped: c_f above the bare
    fork's c_0 by more than ``tol`` relative.  One of :data:`designer.model.FAMILIES`' names.
    """
    grooved = design.groove > problem.bounds["groove"].low + tol * max(problem.bounds["groove"].high, 1e-3)
    damped = design.damping > problem.conditions.turning.bare_fork_damping * (1 + tol)
    return FAMILIES[(grooved, damped)]


_NUMBER_FIELDS = {
    "target_speed": ("shimmy.target_speed", "speed"),
    "margin": ("shimmy.margin", "dimensionless"),
    "swept_radius_max": ("constraints.swept_radius_max", "length"),
    "max_threshold_force": ("objective.max_threshold_force", "force"),
    "max_turning_effort": ("objective.max_turning_effort", "force"),
    "max_threshold_increase": ("retrofit.max_threshold_increase", "dimensionless"),
    "max_turning_increase": ("retrofit.max_turning_increase", "dimensionless"),
}
"""The number fields of a :class:`Problem`: their problem-file keys and dimensions (None allowed where the
default is None)."""


def _normalise(problem: Problem, prefix: str) -> None:
    """The fields of a Problem built by the API as the loader gives them: numbers (or strings with units) as
    floats [SI], the bounds (Bound or a (min, max) pair) and the choices as read-only mappings, the wheels and
    the weights as tuples; a wrong type is one ProblemError line naming the field."""

    def fail(msg: str) -> NoReturn:
        raise ProblemError(prefix + msg)

    def put(name: str, value: Any) -> None:
        object.__setattr__(problem, name, value)

    for name, (key, dimension) in _NUMBER_FIELDS.items():
        value = getattr(problem, name)
        if value is None and Problem.__dataclass_fields__[name].default is None:
            continue
        put(name, parsed(value, dimension, key, fail))
    if not isinstance(problem.bounds, Mapping):
        fail(f"bounds = {problem.bounds!r}: expected a mapping of variable names to Bound(min, max) [SI]")
    bounds = {}
    for name, bound in problem.bounds.items():
        if not isinstance(bound, Bound):
            if isinstance(bound, (str, bytes)) or not isinstance(bound, Iterable) or len(list(bound)) != 2:
                fail(f"variables.{show_key(name)} = {bound!r}: expected Bound(min, max) or a (min, max) pair [SI]")
            try:
                bound = Bound(*bound)
            except InputError as exc:
                fail(f"variables.{show_key(name)}: {exc}")
        bounds[name] = bound
    put("bounds", frozen(bounds))
    if not isinstance(problem.choices, Mapping):
        fail(f"choices = {problem.choices!r}: expected a mapping of option names to lists of values")
    put("choices", frozen({k: tuple(v) for k, v in problem.choices.items()}))
    for name in ("wheels", "weights"):
        value = getattr(problem, name)
        if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
            fail(f"{name} = {value!r}: expected a sequence")
        put(name, tuple(value))
    try:  # by the API's one rule (designer.units): np.int64(41) is a count, True and 41.0 are not; nor is True a weight
        put("weights", tuple(real_number(w, f"weights[{i}]") for i, w in enumerate(problem.weights)))
        put("pareto_points", whole_number(problem.pareto_points, "pareto.points", POINTS_RANGE[0], POINTS_RANGE[1]))
    except InputError as exc:
        fail(str(exc))
    if problem.stock is not None and not isinstance(problem.stock, Stock):
        fail(f"stock = {problem.stock!r}: expected None or a Stock")


def _validate(problem: Problem, prefix: str = "") -> None:
    """Every check of a problem, in a fixed order; the first failure is raised as one ProblemError line."""

    def fail(msg: str) -> NoReturn:
        raise ProblemError(prefix + msg)

    if not isinstance(problem.name, str) or not NAME_PATTERN.match(problem.name):
        fail(
            f"name = {problem.name!r}: must be 1–64 letters, digits, '-', '_' or '.', starting with a letter "
            f"or digit (it names the results folder)"
        )
    for name, force in (("max_threshold_increase", "sill force"), ("max_turning_increase", "turning effort")):
        value = getattr(problem, name)
        if not (math.isfinite(value) and 0 <= value <= 10):
            fail(
                f"retrofit.{name} = {value:g}: must be from 0 to 10 "
                f"(0.1 or '10 %': a fix may raise the {force} by 10 % of the current caster's)"
            )
    if problem.units not in REPORT_UNITS:
        fail(f"report.units = {problem.units!r}: expected one of {', '.join(repr(u) for u in REPORT_UNITS)}")
    if problem.target_speed <= 0:
        fail(f"shimmy.target_speed = {problem.target_speed:g} m/s: must be positive")
    if problem.margin < 0 or problem.margin > 10:
        fail(f"shimmy.margin = {problem.margin:g}: must be between 0 and 10 (a fraction, 0.2 = 20 %)")
    # the conditions: load, sill, the constants of the model (in their ranges), the disturbance angle, surface, mode
    c = problem.conditions
    if not isinstance(c, Conditions):
        fail(f"conditions = {c!r}: expected a designer.Conditions, e.g. Conditions(load=178)")
    for name in (*CONDITION_NUMBERS, *CONDITION_CHOICES):  # the rules of Conditions (a copy may bypass them)
        key = f"conditions.{name}" if name in CONDITION_CHOICES else parameters.PARAMETERS[name].key
        reason = condition_refusal(name, getattr(c, name), key)
        if reason is not None:
            fail(reason)
    for key in PHYSICAL_RANGE:  # every constant the table gives a range and a hint, where the table keeps it
        if key == "constraints.swept_radius_max":
            continue  # None (no limit) or checked with the bounds
        where = parameters.location(parameters.PARAMETERS[_BY_KEY[key]])
        assert where is not None
        value = parameters.read_path(problem, where)
        if value is not None and (value > 0 or key == "turning.groove_coefficient"):
            check_range(key, value, prefix)
    for name in VARIABLES:
        _validate_bound(problem, name, fail)
    _validate_sizes(problem, prefix, fail)


def _validate_bound(problem: Problem, name: str, fail: Callable[[str], NoReturn]) -> None:
    """``variables.<name>``: present, finite, positive (or >= 0), in the model's range, min <= max."""
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
        if not lo <= value <= hi:  # as the loader says it (in the user's unit there)
            fail(outside_range(f"{key}.{label}", value, value, lo, hi, VARIABLE_DIMENSIONS[name]))
    if b.low > b.high:
        both = f" ({inches(b.low)} > {inches(b.high)})" if VARIABLE_DIMENSIONS[name] == "length" else ""
        fail(f"{key} = [{b.low:g}, {b.high:g}]: min is greater than max{both}")


def _validate_sizes(problem: Problem, prefix: str, fail: Callable[[str], NoReturn]) -> None:
    """The sizes the bounds allow: every wheel climbs the sill (d > 2h, Eq. 4A); the damping bound is not below
    the bare fork's; the swept radius limit is positive, in range and above the smallest T + d/2 of the bounds;
    I_w of the inertia model at both diameter bounds lies in :data:`INERTIA_RANGE`."""
    c = problem.conditions
    h = c.threshold_height
    if not problem.wheels and problem.bounds["diameter"].low <= 2 * h:
        fail(
            f"variables.diameter.min = {inches(problem.bounds['diameter'].low)}: must exceed twice the "
            f"threshold height ({inches(2 * h)}); a wheel with d <= 2h cannot climb the sill (Eq. 4A)"
        )
    for key in problem.wheels:
        wheel = next((w for w in TABLE1 if w.key == key), None)
        if wheel is None:
            fail(f"inertia.wheels: unknown Table 1 wheel {key!r}; valid wheels are {', '.join(w.key for w in TABLE1)}")
        if wheel.diameter <= 2 * h:
            fail(
                f"inertia.wheels: wheel {key} (d = {inches(wheel.diameter)}) cannot climb a "
                f"{inches(h)} sill (d/h <= 2, Eq. 4A)"
            )
    c0 = c.turning.bare_fork_damping
    if problem.bounds["damping"].low < c0 - 1e-12:
        fail(
            f"variables.damping.min = {problem.bounds['damping'].low:g} N·m/rad: below the bare fork's "
            f"{c0:g} N·m/rad (Eq. 11C); set [turning] bare_fork_damping if your fork differs"
        )
    if (r := problem.swept_radius_max) is not None:
        check_range("constraints.swept_radius_max", r, prefix)
        smallest = problem.bounds["trail"].low + problem.bounds["diameter"].low / 2
        if problem.wheels:
            smallest = problem.bounds["trail"].low + min(Catalog.from_key(k).fixed_diameter for k in problem.wheels) / 2
        if r < smallest:
            fail(
                f"constraints.swept_radius_max = {inches(r)}: smaller than the smallest possible "
                f"T + d/2 = {inches(smallest)}; raise it or lower the trail/diameter minimum"
            )
    check_weights(problem.weights, prefix + "objective")
    for label, d in (("min", problem.bounds["diameter"].low), ("max", problem.bounds["diameter"].high)):
        if problem.wheels:
            break  # catalogue wheels: their measured I_w
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # extrapolation is reported where the model is used
                inertia = float(c.inertia(d))
        except (OverflowError, ZeroDivisionError, ValueError):
            inertia = math.nan
        if not (math.isfinite(inertia) and INERTIA_RANGE[0] <= inertia <= INERTIA_RANGE[1]):
            fail(
                f"inertia: I_w = {inertia:g} kg·m² at variables.diameter.{label} = {d:g} m "
                f"({c.inertia.describe()}): outside {INERTIA_RANGE[0]:g} to {INERTIA_RANGE[1]:g} kg·m²; "
                f"check the inertia model's constants and the diameter bounds"
            )


def show_key(key: object) -> str:
    """A key as written in messages: plain if it is a simple word, else quoted (keeps the message one line)."""
    return key if isinstance(key, str) and re.fullmatch(r"[A-Za-z0-9_.-]+", key) else repr(key)
