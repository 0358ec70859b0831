"""The caster model: one design, its operating conditions, and everything computed from them.

:func:`performance` is the single place where the physics functions are
combined; the solvers (CasADi, cvxpy, scipy, optuna), the checks and the
reports all call it, so a formula is never written twice.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import math
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

from designer import parameters
from designer.display import label, number, quantity, shown, unit_text
from designer.errors import InputError
from designer.reprs import Record, frozen
from designer.physics.types import Scalar, batch_or_symbol
from designer.physics.geometry import swept_radius
from designer.physics.inertia import InertiaModel, PowerLaw
from designer.physics.shimmy import (
    DynamicsParameters,
    critical_shimmy_speed,
)
from designer.physics.threshold import threshold_force_ratio
from designer.physics.turning import (
    DEFAULT_TURNING,
    MODES,
    SURFACES,
    TurningConstants,
    added_damper_moment,
    sliding_turning_moment,
)
from designer.physics.uncertainty import Uncertainty, shimmy_speed_quantile
from designer.units import outside_range, parse_quantity

VARIABLES = parameters.VARIABLES
"""The design variables x = (T, d, B, c_f), in this order everywhere (from :mod:`designer.parameters`)."""

VARIABLE_UNITS = {p.name: p.unit for p in parameters.VARIABLE_TABLE}
"""SI unit of each design variable."""

MODEL_RANGE = parameters.MODEL_RANGE
"""Physically sensible ranges [SI] (low ends: 1 mm trail, 10 mm wheel diameter): beyond
them the paper's model does not apply, and a value there usually means inches
were written as metres."""


GRAVITY = 9.80665
"""Standard gravity g [m/s²] (CGPM 1901): the weight m g of the user and the chair."""

MASS_RANGE = parameters.MASS_RANGE
"""Mass of the user plus the chair [kg] the problem file and the fleet table accept (:mod:`designer.parameters`)."""


def caster_load(mass: Scalar, front_fraction: Scalar) -> Scalar:
    """Load L [N] on one front caster from the mass of the user plus the chair: L = m g f / 2.

    The one conversion of the package: the problem file's ``[conditions] mass`` and ``front_fraction`` and
    the fleet table's columns of the same names both use it (the paper gives L directly: 178 N per caster
    in its tests, Appendix C).

    Parameters
    ----------
    mass : m, user plus chair [kg] (float or array)
    front_fraction : f, the share of the weight on the two front casters [-], 0 < f <= 1

    Returns
    -------
    L [N], the load on each of the two front casters (same shape as the arguments).
    """
    return mass * GRAVITY * front_fraction / 2


FAMILIES = {
    (False, False): "bare fork",
    (True, False): "groove",
    (False, True): "damper",
    (True, True): "groove+damper",
}
"""Design family by (groove used, damper added): which mechanism stabilises the caster (Eq. 7)."""


def check_design(
    design: Design, prefix: str = "", error: type[Exception] = InputError, given: Mapping[str, object] | None = None
) -> None:
    """Raise ``error`` if a design's T, d, B or c_f [SI] is outside :data:`MODEL_RANGE`.

    ``given`` maps a variable to what the user wrote ("5in"): the message then gives the range in
    that unit instead of asking whether inches were written as metres (:func:`designer.units.outside_range`).
    """
    for name in VARIABLES:
        value = getattr(design, name)
        lo, hi = MODEL_RANGE[name]
        if not math.isfinite(value) or value < lo or (value == 0 and name in ("trail", "diameter")) or value > hi:
            written, dimension = (given or {}).get(name, value), parameters.PARAMETERS[name].dimension
            raise error(outside_range(f"{prefix}{name}", written, value, lo, hi, dimension))


@dataclass(frozen=True)
class Design(Record):
    """One caster design x = (T, d, B, c_f) in SI units (strings with units are accepted and converted).

    Attributes
    ----------
    trail : T [m]
    diameter : d [m]
    groove : B [m] (0: single tread)
    damping : c_f [N·m/rad] (bare fork 1.3)
    """

    trail: float
    diameter: float
    groove: float
    damping: float

    _units = VARIABLE_UNITS

    def __post_init__(self) -> None:
        # Units at the edge: strings such as "2 in" or "1.3 N*m/rad" are converted to SI here.

        for entry in parameters.VARIABLE_TABLE:
            name = entry.name
            value = getattr(self, name)
            if type(value) is not float or not math.isfinite(value):  # a finite float is SI as it is (solvers' rows)
                value = parse_quantity(value, entry.dimension, name)  # the one rule: units.real_number
            positive = name in ("trail", "diameter")
            # a solver may return −1e-12 on a zero bound: tolerate round-off, not real negatives
            if value < -1e-9 or (positive and value <= 0):
                raise InputError(f"{name} = {value:g}: must be {'positive' if positive else 'non-negative'}")
            object.__setattr__(self, name, value)

    def as_array(self) -> np.ndarray:
        """The design as a float array in :data:`VARIABLES` order."""
        return np.array([self.trail, self.diameter, self.groove, self.damping], dtype=float)

    @classmethod
    def from_array(cls, x: npt.ArrayLike) -> "Design":
        """Build from a sequence in :data:`VARIABLES` order."""
        return cls(*(float(v) for v in np.asarray(x, dtype=float).ravel()[:4]))

    def _repr_lines(self) -> list[str]:
        """Two lines: the SI constructor call and the sizes in inches (the industry's unit)."""
        si = ", ".join(f"{p.name}={getattr(self, p.name):.6g}" for p in parameters.VARIABLE_TABLE)
        sizes = ", ".join(
            f"{p.symbol} {shown(getattr(self, p.name), p.name, 'in')}" for p in parameters.VARIABLE_TABLE[:3]
        )
        return [f"Design({si})", f"  {sizes}, c_f {self.damping:.4g} N·m/rad"]

    def variable_rows(self) -> list[tuple[Any, Any, Any]]:
        """T, d, B in inches and mm and c_f [N·m/rad] as (label, value, unit) rows, names, units and precisions from
        the parameter table: the design block of every record's HTML (a recommendation, an optimum, this design)."""
        return [
            (f"{p.name} {p.symbol}", _inches(getattr(self, p.name), p.name), unit_text(p.name, "in"))
            for p in parameters.VARIABLE_TABLE
        ]

    def variable_lines(self, width: int) -> list[str]:
        """T, d, B in inches and mm and c_f as text lines, the label column ``width`` characters wide (two spaces
        of indent included), names, units and precisions from the parameter table: the design block of
        ``print(recommendation)`` and ``print(solution)``."""
        lines = []
        for p in parameters.VARIABLE_TABLE:
            value = getattr(self, p.name)
            mm = f"   {number(value, p.name, 'mm'):>8} mm" if p.dimension == "length" else ""
            lines.append(
                f"{f'  {p.name} {p.symbol}':<{width}}{number(value, p.name, 'in'):>8} {unit_text(p.name, 'in')}{mm}"
            )
        return lines

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """T, d, B in inches and mm, c_f [N·m/rad] and the swept radius (notebooks); names and units from the table."""
        rs = float(swept_radius(self.trail, self.diameter))
        return [*self.variable_rows(), (label("swept_radius"), _inches(rs, "swept_radius"), "in")]

    def describe(self) -> str:
        """One line in inches (the industry's unit) and SI: "T = 2.500 in, ..., c_f = 1.30 N·m/rad"."""
        return ", ".join(
            f"{p.symbol} = {shown(getattr(self, p.name), p.name, 'in')}" for p in parameters.VARIABLE_TABLE
        )


def _inches(value: float, name: str) -> str:
    """A quantity [SI] of the parameter table in the inch system, a length with millimetres beside it:
    "2.500 (63.50 mm)", "1.30"."""
    mm = f" ({shown(value, name, 'mm')})" if quantity(name).dimension == "length" else ""
    return number(value, name, "in") + mm


CONDITION_NUMBERS = ("load", "threshold_height", "disturbance_angle", "slip_coefficient")
"""The number fields of :class:`Conditions`, each an entry of the parameter table (unit, range, hint)."""

CONDITION_CHOICES = {"surface": SURFACES, "turning_mode": MODES}
"""The categorical fields of :class:`Conditions` and their allowed values."""


def condition_refusal(name: str, value: Any, label: str | None = None) -> str | None:
    """Why ``value`` [SI] is refused for the conditions' field ``name``, as one line starting with ``label``
    (default ``name``), or None when it is accepted: the one set of rules of the problem file
    (``conditions.load``, ...) and of the API (``Conditions(load=...)``).

    Numbers: finite; load L, sill height h and slip coefficient K_s positive, θ0 between 0 and 90 deg
    (exclusive), each within the parameter table's range (:data:`designer.parameters.PARAMETERS`, with its
    hint); ``surface`` and ``turning_mode`` one of their choices.
    """
    label = name if label is None else label
    if name in CONDITION_CHOICES:
        allowed = CONDITION_CHOICES[name]
        return None if value in allowed else f"{label} = {value!r}: expected one of {', '.join(allowed)}"
    p = parameters.PARAMETERS[name]
    shown = f"{label} = {value:g} {p.unit}".rstrip()
    if not math.isfinite(value):
        return f"{label} = {value}: must be finite"
    if name == "disturbance_angle":
        return None if 0 < value < math.pi / 2 else f"{shown}: must be between 0 and 90 deg"
    if value <= 0:
        return f"{shown}: must be positive"
    assert p.range is not None, name
    low, high = p.range
    if not low <= value <= high:
        return f"{shown}: outside the model's range {low:g} to {high:g} {p.unit}".rstrip() + f" ({p.hint})"
    return None


@dataclass(frozen=True)
class Conditions:
    """Fixed operating conditions and model constants of a caster.

    Attributes
    ----------
    load : caster load L [N]
    threshold_height : door-sill height h [m]
    surface : "tile" | "carpet"
    turning_mode : "chair" | "pivot"
    disturbance_angle : design disturbance θ0 [rad] (20°, Appendix C)
    slip_coefficient : K_s [N] (1250, Appendix C)
    inertia : the I_w(d) model
    turning : constants of the turning model (docs/model.md#turning-effort)
    dynamics : K, fork and bearing-block masses of the third-order model
    uncertainty : optional :class:`designer.physics.uncertainty.Uncertainty` (the risk law); then the shimmy
        constraint uses the α-quantile of V_c instead of its nominal value
    constants : the model constants of the parameter table that have no field above, by name
        (:func:`designer.parameters.location`); read any constant with :meth:`constant`
    """

    load: float = parameters.default("load")
    threshold_height: float = parameters.default("threshold_height")
    surface: str = "tile"
    turning_mode: str = "chair"
    disturbance_angle: float = parameters.default("disturbance_angle")
    slip_coefficient: float = parameters.default("slip_coefficient")
    inertia: InertiaModel = field(default_factory=PowerLaw)
    turning: TurningConstants = DEFAULT_TURNING
    dynamics: DynamicsParameters = DynamicsParameters()
    uncertainty: Uncertainty | None = None
    constants: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        # the API's boundary: a user's Conditions(load=-5) is refused as the problem file's conditions.load = -5
        for name in (*CONDITION_NUMBERS, *CONDITION_CHOICES):
            value = getattr(self, name)
            if batch_or_symbol(value):
                continue
            if name in CONDITION_NUMBERS:  # a number [SI] or a string with units
                value = parse_quantity(value, parameters.PARAMETERS[name].dimension, name)
            reason = condition_refusal(name, value)
            if reason is not None:
                raise InputError(reason)
            object.__setattr__(self, name, value)
        for name, kinds, expected in (
            ("inertia", InertiaModel, "a InertiaModel, e.g. PowerLaw()"),
            ("turning", TurningConstants, "a TurningConstants, e.g. TurningConstants()"),
            ("dynamics", DynamicsParameters, "a DynamicsParameters, e.g. DynamicsParameters()"),
            ("uncertainty", (Uncertainty, type(None)), "None or an Uncertainty"),
            ("constants", Mapping, "a mapping of constant names to values"),
        ):
            if not isinstance(getattr(self, name), kinds):
                raise InputError(f"{name} = {getattr(self, name)!r}: expected {expected}")
        object.__setattr__(self, "constants", frozen(self.constants))

    def replace(self, **changes: Any) -> "Conditions":
        """A copy with some fields changed (checked again)."""
        return dataclasses.replace(self, **changes)

    def constant(self, name: str) -> Any:
        """The value [SI] of the model constant ``name`` of :data:`designer.parameters.PARAMETERS`
        (a float, or a CasADi symbol inside the solvers), wherever it is kept: a field above, or
        :attr:`constants` (its table default when the problem did not give it)."""
        entry = parameters.PARAMETERS.get(name)
        where = parameters.location(entry) if entry is not None else None
        if where is None or not where.startswith("conditions."):
            raise KeyError(f"{name!r} is not a model constant of designer/parameters.py's CONSTANT_TABLE")
        return parameters.read_path(self, where.split(".", 1)[1])


def turning_moment(groove: Scalar, damping: Scalar, conditions: Conditions) -> Scalar:
    """M_turn + M_d [N·m]: the sliding turning moment of the tyre (groove B [m]) and the moment of the added
    damper (c_f [N·m/rad]) at the disturbance angle (docs/model.md#turning-effort).  Floats, arrays, CasADi."""
    c = conditions
    moment: Scalar = sliding_turning_moment(c.load, groove, c.surface, c.turning_mode, c.turning) + added_damper_moment(
        damping, c.disturbance_angle, c.turning
    )
    return moment


def turning_effort(trail: Scalar, groove: Scalar, damping: Scalar, conditions: Conditions) -> Scalar:
    """F_turn [N] (Eq. 9): :func:`turning_moment` over the trail T [m], alone (the closed form's searches along
    the shimmy constraint compare it at thousands of designs without the rest of :func:`performance`)."""
    effort: Scalar = turning_moment(groove, damping, conditions) / trail
    return effort


def weighted_terms(turning_effort: Scalar, threshold_force: Scalar, weights: Any) -> tuple[Scalar, Scalar]:
    """The two terms of the weighted objective, (w_turn F_turn, w_threshold P) [N], for ``weights``
    (w_turn, w_threshold): the report says when one dominates.  Floats, arrays, CasADi."""
    return weights[0] * turning_effort, weights[1] * threshold_force


def weighted(turning_effort: Scalar, threshold_force: Scalar, weights: Any) -> Scalar:
    """J = w_turn F_turn + w_threshold P [N] (docs/model.md#problems): the weighted objective, written once
    for every solver, study and record (floats, arrays and CasADi symbols)."""
    turning, threshold = weighted_terms(turning_effort, threshold_force, weights)
    return turning + threshold


def performance(
    trail: Scalar,
    diameter: Scalar,
    groove: Scalar,
    damping: Scalar,
    conditions: Conditions,
    inertia: Scalar | None = None,
    measured: Any = None,
    wheel_diameter: Scalar | None = None,
) -> dict[str, Scalar]:
    """Every performance quantity of the caster, as expressions of the design.

    Works on floats, NumPy arrays (vectorised over many designs) and CasADi
    symbols.  Keys and equations:

    - ``inertia`` I_w(d) [kg·m²] (inertia model, docs/model.md#wheel-inertia; or ``inertia`` when given:
      a measured wheel)
    - ``critical_speed`` V_c [m/s] (Eq. 7)
    - ``threshold_force_ratio`` P/L [-] (Eq. 4A)
    - ``threshold_force`` P [N] (Eq. 4A)
    - ``turning_moment`` M_turn + M_d [N·m] (docs/model.md#turning-effort)
    - ``turning_effort`` F_turn [N] (Eq. 9, moment / trail)
    - ``swept_radius`` R_s [m] (T + d/2)
    - ``confident_speed`` V_q [m/s]: the speed the shimmy constraint compares with V_req, the speed
      reached with probability 1 − α when the conditions carry a risk law
      (:func:`designer.physics.uncertainty.shimmy_speed_quantile`), else V_c itself

    ``measured`` says which wheels were measured (True, False, or one flag per caster; numeric only): default,
    the inertia model's own (``Catalog``, ``Fixed``: measured; power law, disc: known by the diameter) when
    ``inertia`` is None, else measured.  ``wheel_diameter`` is the diameter the inertia prediction is taken at
    (default ``diameter``): the risk law scatters a wheel known by its diameter by Table 1's prediction of I_w,
    a measured one by the measurement's scatter.
    """
    c = conditions
    if measured is None:  # the inertia model's own (catalogue, fixed: measured); a given I_w is measured
        measured = bool(getattr(c.inertia, "measured", False)) if inertia is None else True
    if inertia is None:
        inertia = c.inertia(diameter)
    critical_speed = critical_shimmy_speed(trail, inertia, groove, damping, c.slip_coefficient)
    if c.uncertainty is None:
        confident_speed = critical_speed
    else:
        wheel = diameter if wheel_diameter is None else wheel_diameter
        confident_speed = shimmy_speed_quantile(
            trail, inertia, groove, damping, c.slip_coefficient, c.uncertainty, diameter=wheel, measured=measured
        )
    ratio = threshold_force_ratio(diameter, c.threshold_height)
    moment = turning_moment(groove, damping, c)
    return {
        "inertia": inertia,
        "critical_speed": critical_speed,
        "confident_speed": confident_speed,
        "threshold_force_ratio": ratio,
        "threshold_force": c.load * ratio,
        "turning_moment": moment,
        "turning_effort": moment / trail,  # Eq. 9, as turning_effort (the moment once in a CasADi graph)
        "swept_radius": swept_radius(trail, diameter),
    }
