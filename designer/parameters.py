"""The one table of design variables and model constants (in the spirit of GPkit's ``Variable``).

Each entry says once: its name, symbol, SI unit, one-line description, default,
allowed range, paper source, and where it lives (its problem-file key and its
attribute path on a :class:`~designer.problem.Problem`).  Everything else reads
this table:

- the problem loader (schema keys and units, defaults, default bounds, the
  ranges it checks: ``designer.problem``),
- the model's ranges and variable order (``designer.model._caster``),
- the NLP and the GP parameter vectors and the names of their sensitivities
  (:func:`solver_values`, :func:`with_solver_values`),
- the sensitivity table, the report's problem table and ``docs/parameters.md``
  (:func:`markdown_table`; ``write_docs`` writes it).

To add a model constant, add one :class:`Parameter` below (with ``path`` if the
solvers should treat it as a parameter with a sensitivity), and use it in the
physics.  CONTRIBUTING.md walks through an example.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from designer.data.paper import BARE_FORK_DAMPING, DISTURBANCE_ANGLE, SLIP_COEFFICIENT
from designer.units import DIMENSIONS, INCH


@dataclass(frozen=True)
class Parameter:
    """One design variable or model constant.

    Attributes
    ----------
    name : identifier in code, solver parameter vectors and sensitivity tables
    symbol : the paper's symbol (T, d, K_s, θ0, ...)
    unit : SI unit as printed ("" for dimensionless)
    description : one line
    default : value used when the problem file does not give one [SI] (None: none / computed)
    range : allowed (low, high) [SI], inclusive, or None
    source : paper equation, table or figure, or "our estimate"
    key : problem-file key "section.key" (None: not in problem files)
    dimension : the dimension :func:`designer.units.parse_quantity` checks for ``key``
    hint : what a value outside ``range`` usually means; entries with a hint are
        checked by the loader (``designer.problem.check_range``)
    path : attribute path on a Problem for a fixed parameter of the NLP/GP (its
        sensitivity d log J / d log p is reported); ``a.b[c]`` reads ``a.b[<value of c>]``
        where ``c`` is a path of the conditions; ``conditions.inertia:x`` is the
        inertia model's parameter ``x`` (see ``InertiaModel.parameters``)
    when : (path, value): the solvers use the parameter only when the path has that value
    bounds : default (min, max) of a design variable [SI]
    store : attribute path on a Problem where the loader puts the value read from ``key`` when that is
        not ``path`` (``a["b"]`` is the literal dict key ``b``).  An entry with a ``key`` and neither
        ``store`` nor ``path`` is kept in ``Conditions.constants`` by name (:func:`location`), so a new
        constant needs no other code than the equation that reads it (``conditions.constant(name)``).
    scale : a design variable's least scale in the NLP [SI]: IPOPT sees x / max(upper bound, scale), numbers
        near 1 (``designer.solvers.nlp``)
    listed : a quantity of :data:`OUTPUT_TABLE` shown in the tables of one caster (the HTML of a
        :class:`~designer.model.Caster`, ``designer evaluate``); False: in its data only
    digits : display precision in the quantity's shown unit (:mod:`designer.display`: decimals, or significant
        digits where its dimension shows those); None: the dimension's default (a force to 0.01 N, a speed to
        1 mm/s, a length to 0.001 in or 0.01 mm).  The load is shown to 0.1 N, the turning effort to 1 mN.
    """

    name: str
    symbol: str
    unit: str
    description: str
    default: float | None
    range: tuple[float, float] | None
    source: str
    key: str | None = None
    dimension: str = "dimensionless"
    hint: str = ""
    path: str | None = None
    when: tuple[str, str] | None = None
    bounds: tuple[float, float] | None = None
    store: str | None = None
    scale: float | None = None
    listed: bool = True
    digits: int | None = None

    @property
    def shown_unit(self) -> str:
        """The unit for tables: "-" when dimensionless."""
        return self.unit or "-"

    @property
    def ascii_unit(self) -> str:
        """The SI unit in ASCII, as pint reads it ("N*m/rad", "kg*m**2"; "" when dimensionless): JSON records."""
        return DIMENSIONS[self.dimension][0]

    @property
    def label(self) -> str:
        """The description with the symbol, for a table's row ("critical shimmy speed V_c")."""
        return f"{self.description} {self.symbol}" if self.symbol else self.description

    @property
    def axis_label(self) -> str:
        """The label with the unit in brackets, for a plot's axis ("threshold force P [N]")."""
        return f"{self.label} [{self.unit}]" if self.unit else self.label

    def row(self, value: str, note: str = "") -> tuple[str, str, str]:
        """The (label, value, unit) row of a record's HTML table for ``value`` (already formatted): the label and
        the SI unit from the table, ``note`` in brackets after the label ("critical shimmy speed V_c (Eq. 7)")."""
        return (f"{self.label} ({note})" if note else self.label, value, self.unit)

    @property
    def column(self) -> str:
        """The name with its SI unit, for a CSV or DataFrame column ("trail_m", "damping_N_m_per_rad")."""
        suffix = self.unit.replace("·", "_").replace("/", "_per_").replace("²", "2").replace("³", "3")
        return f"{self.name}_{suffix}" if suffix else self.name


# --------------------------------------------------------------------------- design variables x = (T, d, B, c_f)

# a table, one parameter per line and read across: not reformatted
# fmt: off
VARIABLE_TABLE: tuple[Parameter, ...] = (
    Parameter("trail", "T", "m", "trail: spindle axis to tyre contact", None, (0.001, 0.25),
              "Eq. 7, Eq. 9", key="variables.trail", dimension="length", bounds=(1.0 * INCH, 2.5 * INCH),
              scale=0.01),
    Parameter("diameter", "d", "m", "wheel diameter", None, (0.01, 0.6),
              "Eq. 4A, Table 1", key="variables.diameter", dimension="length", bounds=(3.0 * INCH, 8.0 * INCH),
              scale=0.05),
    Parameter("groove", "B", "m", "groove width = tread separation of Eq. 7", None, (0.0, 0.1),
              "Eq. 7, Eq. 8", key="variables.groove", dimension="length", bounds=(0.0, 0.75 * INCH),
              scale=0.005),
    Parameter("damping", "c_f", "N·m/rad", "spindle friction damping M_f/θ0", None, (0.0, 100.0),
              "Eq. 11C", key="variables.damping", dimension="damping", bounds=(BARE_FORK_DAMPING, 6.0),
              scale=1.0),
)
# fmt: on
"""The design variables, in the order of x everywhere.  ``range`` is the model's range: beyond it the
paper's model does not apply, and a value there usually means inches were written as metres.  Its low
ends for trail (1 mm) and wheel diameter (10 mm) are physical floors: below them a caster has no trail or
no wheel to speak of, and the turning effort M/T (Eq. 9) or the sill force (Eq. 4A) overflow."""

# --------------------------------------------------------------------------- model constants
# The entries with a ``path`` are the solvers' fixed parameters, in the order of the NLP's parameter vector.

# a table, one parameter per line and read across: not reformatted
# fmt: off
CONSTANT_TABLE: tuple[Parameter, ...] = (
    Parameter("load", "L", "N", "caster load", 178.0, (1.0, 1e5), "Table 1 (test load), Appendix C",
              key="conditions.load", dimension="force",
              hint="a caster load of 0.1 kg to 10 t; was it given in another unit?", path="conditions.load",
              digits=1),
    Parameter("threshold_height", "h", "m", "door-sill height", 0.5 * INCH, (1e-4, 0.3), "Eq. 4A",
              key="conditions.threshold_height", dimension="length",
              hint="a sill of 0.1 mm to 30 cm; were inches written as metres?", path="conditions.threshold_height"),
    Parameter("target_speed", "V_target", "m/s", "speed without shimmy", None, (0.01, 100.0), "Eq. 7",
              key="shimmy.target_speed", dimension="speed",
              hint="plain numbers are m/s; was it given in km/h or mph?", path="target_speed"),
    Parameter("slip_coefficient", "K_s", "N", "tyre slip coefficient", SLIP_COEFFICIENT, (1.0, 1e6),
              "Appendix C, Eq. 12C, Fig. 3C", key="shimmy.slip_coefficient", dimension="force",
              hint="the paper's tyres have 1250 N", path="conditions.slip_coefficient"),
    Parameter("disturbance_angle", "θ0", "rad", "design disturbance angle", DISTURBANCE_ANGLE,
              (0.0, math.pi / 2), "Appendix C (rubber-hammer test)", key="shimmy.disturbance_angle",
              dimension="angle", path="conditions.disturbance_angle"),
    Parameter("tile_moment_per_load", "k_tile", "m", "sliding turning moment per load on tile", 0.005, (1e-6, 0.1),
              "Fig. 7A", key="turning.tile_moment_per_load", dimension="length",
              hint="the paper's tile gives 0.005 m", path="conditions.turning.tile_moment_per_load"),
    Parameter("groove_coefficient", "κ", "1/m", "groove penalty on turning moment", 0.10 / (9 / 16 * INCH),
              (0.0, 1e4), "Figs. 7–8 (+10 % for B = 9/16 in)", key="turning.groove_coefficient",
              dimension="per_length", hint="the paper's grooved tyre gives about 7 1/m",
              path="conditions.turning.groove_coefficient"),
    Parameter("bare_fork_damping", "c_0", "N·m/rad", "bare-fork damping", BARE_FORK_DAMPING, (1e-3, 100.0),
              "Appendix C, Eq. 11C", key="turning.bare_fork_damping", dimension="damping",
              hint="the paper's bare fork has 1.3 N·m/rad", path="conditions.turning.bare_fork_damping"),
    Parameter("carpet_factor", "k_carpet/k_tile", "", "carpet over tile", 2.0, (1e-3, 100.0),
              "Fig. 7 (\"approximately double\")", key="turning.carpet_factor", hint="the paper's carpet is about 2",
              path="conditions.turning.carpet_factor", when=("conditions.surface", "carpet")),
    Parameter("mode_factor", "m_mode", "", "turning-mode factor", None, None, "Figs. 10–12",
              path="conditions.turning.mode_factors[turning_mode]"),
    Parameter("chair_factor", "m_chair", "", "turning a wheelchair in place over the drill-press moment", 0.5,
              (1e-3, 100.0), "Figs. 10–12 (\"about 50 percent\")", key="turning.chair_factor",
              hint="the paper's chair mode is 0.5", store='conditions.turning.mode_factors["chair"]'),
    Parameter("pivot_factor", "m_pivot", "", "non-rolling wheel (drill press)", 1.0, (1e-3, 100.0), "Fig. 7A",
              key="turning.pivot_factor", hint="the paper's pivot mode is 1",
              store='conditions.turning.mode_factors["pivot"]'),
    Parameter("inertia_coefficient", "C", "", "inertia power-law coefficient (d in m, I_w in kg·m²)", None, None,
              "least squares on Table 1", key="inertia.coefficient", path="conditions.inertia:inertia_coefficient"),
    Parameter("inertia_exponent", "n", "", "inertia power-law exponent", None, (0.0, 10.0),
              "least squares on Table 1", key="inertia.exponent", path="conditions.inertia:inertia_exponent"),
    Parameter("tyre_width", "w", "m", "disc tyre width", 0.025, (0.0, 0.2), "our estimate",
              key="inertia.tyre_width", dimension="length", path="conditions.inertia:tyre_width"),
    Parameter("density", "ρ", "kg/m³", "disc density", 1200.0, (0.0, 20000.0), "our estimate (polyurethane)",
              key="inertia.density", dimension="density", path="conditions.inertia:density"),
    Parameter("wheel_inertia", "I_w", "kg·m²", "measured wheel inertia", 0.00127, (0.0, 0.1),
              "Eq. 8 (Invacare 7¾ in wheel)", key="inertia.inertia", dimension="inertia",
              path="conditions.inertia:wheel_inertia"),
    Parameter("swept_radius_max", "R_max", "m", "swept-radius limit", None, (1e-3, 10.0), "footrest clearance",
              key="constraints.swept_radius_max", dimension="length",
              hint="footrest clearances are a few inches", path="swept_radius_max"),
    Parameter("margin", "m_V", "", "relative safety margin on the target speed", 0.0, (0.0, 10.0),
              "Table 1 RMS scatter of Eq. 7 (10.3 %)", key="shimmy.margin", store="margin"),
    Parameter("frame_stiffness", "K", "N/m", "lateral frame stiffness at the bearing block", None, None,
              "Eq. 15B, calibrated to ω = 104.7 rad/s (Eq. 7C)", key="dynamics.frame_stiffness",
              dimension="stiffness", store="conditions.dynamics.frame_stiffness"),
    Parameter("fork_mass", "M_F", "kg", "fork mass", 0.3, None, "our estimate (steel fork)", key="dynamics.fork_mass",
              dimension="mass", store="conditions.dynamics.fork_mass"),
    Parameter("bearing_block_mass", "M_1", "kg", "apparent bearing-block mass", 0.2, None,
              "our estimate (housing)", key="dynamics.bearing_block_mass", dimension="mass",
              store="conditions.dynamics.bearing_block_mass"),
)
# fmt: on
"""The model constants: fixed quantities of a problem."""

SURFACES = ("tile", "carpet")
"""The floors of the turning model (Fig. 7): the choices of ``conditions.surface``."""

MODES = ("chair", "pivot")
"""The turning modes (the chair turned in place, a non-rolling wheel): the choices of ``conditions.turning_mode``."""

MASS_RANGE = (1.0, 2000.0)
"""Mass of the user plus the chair [kg] the problem file and the fleet table accept (0.1 kg to 2 t)."""

# --------------------------------------------------------------------------- quantities of an evaluated caster
# What :func:`designer.model.evaluate` gives for each caster besides its design (the fields of ``Casters`` and
# ``Caster``), in the order the tables show them.  A new quantity is one entry here and one line in the
# evaluator (``designer.model._candidates._evaluate``): it then appears in ``Caster.to_dict``, ``to_pandas``, the
# HTML repr and the table of ``designer evaluate`` (CONTRIBUTING.md).

# a table, one quantity per line and read across: not reformatted
# fmt: off
OUTPUT_TABLE: tuple[Parameter, ...] = (
    Parameter("inertia", "I_w", "kg·m²", "wheel inertia", None, None, "inertia model", dimension="inertia"),
    Parameter("measured", "", "", "wheel inertia measured", None, None, "risk law", listed=False),
    Parameter("extrapolated", "", "", "d outside Table 1's 4–8 in", None, None, "Table 1", listed=False),
    Parameter("effective_trail", "T_eff", "m", "effective trail e + (d/2) sin φ", None, None, "stem tilt",
              dimension="length", listed=False),
    Parameter("critical_speed", "V_c", "m/s", "critical shimmy speed", None, None, "Eq. 7", dimension="speed"),
    Parameter("confident_speed", "V_q", "m/s", "speed reached with probability 1 − α", None, None,
              "risk law (shimmy_speed_quantile)", dimension="speed", listed=False),
    Parameter("shimmy_amplitude", "θ_a", "rad", "shimmy amplitude at V_c", None, None,
              "Eq. 3's full amplitude at V_c: θ0/√(1 + (ω T/V_c)²) (Eq. 4's θ0 V_c/(ω T), behind Eq. 7, only when ω T/V_c ≫ 1)", dimension="angle"),
    Parameter("threshold_force_ratio", "P/L", "", "sill force ratio", None, None, "Eq. 4A"),
    Parameter("threshold_force", "P", "N", "sill force", None, None, "Eq. 4A", dimension="force"),
    Parameter("turning_moment", "M_turn + M_d", "N·m", "turning moment", None, None,
              "docs/model.md#turning-effort, Fig. 7", dimension="moment"),
    Parameter("turning_effort", "F_turn", "N", "turning effort", None, None, "Eq. 9", dimension="force",
              digits=3),
    Parameter("swept_radius", "T + d/2", "m", "swept radius", None, None, "", dimension="length"),
    Parameter("shimmy_frequency", "ω", "rad/s", "shimmy frequency", None, None, "Eq. 15B", dimension="angular_speed"),
    Parameter("shimmy_frequency_hz", "f = ω/2π", "Hz", "shimmy frequency in hertz", None, None, "Eq. 15B", dimension="frequency"),
    Parameter("g_risk", "", "", "risk constraint 1 − V_q/V_req", None, None, "risk bound", listed=False),
    Parameter("g_radius", "", "", "radius constraint R_s/R_max − 1", None, None, "footrest", listed=False),
    Parameter("risk_ok", "", "", "risk limit met", None, None, "risk bound", listed=False),
    Parameter("radius_ok", "", "", "radius limit met", None, None, "footrest", listed=False),
    Parameter("sill_ok", "", "", "climbs the sill (d > 2h)", None, None, "Eq. 4A", listed=False),
    Parameter("feasible", "", "", "every limit met", None, None, "", listed=False),
    Parameter("weighted", "J", "N", "weighted objective w_turn F_turn + w_threshold P", None, None, "",
              dimension="force", listed=False),
    Parameter(
        "growth_rate", "μ", "1/s", "growth rate of the oscillatory mode", None, None, "Eq. 16B", dimension="rate",
        listed=False,
    ),
    Parameter("shimmy_probability", "", "", "P(shimmy) under the risk law", None, None, "Monte Carlo",
              dimension="probability", listed=False),
    Parameter("shimmy_probability_se", "", "", "standard error of P(shimmy)", None, None, "Monte Carlo",
              dimension="probability", listed=False),
)
# fmt: on
"""The quantities of an evaluated caster [SI], by the names of ``Casters``' fields; ``listed`` ones are shown in
the tables of one caster (``designer evaluate``, ``Caster._repr_html_``)."""

OUTPUTS: dict[str, Parameter] = {p.name: p for p in OUTPUT_TABLE}
"""The quantities of an evaluated caster by name (not in :data:`PARAMETERS`: nothing reads them from a file)."""

PARAMETERS: dict[str, Parameter] = {p.name: p for p in VARIABLE_TABLE + CONSTANT_TABLE}
"""Every entry by name."""

VARIABLES: tuple[str, ...] = tuple(p.name for p in VARIABLE_TABLE)
"""The design variables x = (T, d, B, c_f), in this order everywhere."""

VARIABLE_INDEX: dict[str, int] = {name: k for k, name in enumerate(VARIABLES)}
"""Position of each design variable in a design vector x: the one table of indices (``x[VARIABLE_INDEX["groove"]]``)."""

DESIGN_UNITS: dict[str, str] = {f"design.{p.name}": p.unit for p in VARIABLE_TABLE}
"""The units of a record's ``design.*`` fields, from the table (a record's ``_units`` starts from these)."""


QUANTITY_PREFIXES = ("sku_",)
"""Prefixes of a column holding another caster's value of a quantity (a fleet's part number: ``sku_turning_effort``)."""


def _quantity(name: str) -> Parameter | None:
    """The table's entry of a quantity ``name`` (a :data:`QUANTITY_PREFIXES` name as its quantity), or None."""
    base = next((name[len(p) :] for p in QUANTITY_PREFIXES if name.startswith(p)), name)
    return PARAMETERS.get(base) or OUTPUTS.get(base)


def units_of(names: Iterable[str]) -> dict[str, str]:
    """The SI unit of each of ``names`` that is a quantity of the tables with a unit (``{"trail": "m"}``): a
    DataFrame's ``attrs["units"]``.  Other names are left out."""
    return {name: entry.unit for name in names if (entry := _quantity(name)) is not None and entry.unit}


def dimensions(names: Iterable[str]) -> dict[str, str]:
    """The dimension of each of ``names`` that is a quantity of the tables with a unit (:data:`PARAMETERS`,
    :data:`OUTPUTS`; a :data:`QUANTITY_PREFIXES` name as its quantity): the ``quantities`` of
    :func:`designer.textfiles.dict_rows`, so a CSV column names its unit from the one table.  Other names
    (flags, fractions, counts, text) are left out and keep their names."""
    return {name: entry.dimension for name in names if (entry := _quantity(name)) is not None and entry.unit}


def named(x: Any) -> dict[str, Any]:
    """The entries of a design vector ``x`` (a sequence, a NumPy or CasADi vector in :data:`VARIABLES` order) by
    name; for a 2-D NumPy array of designs (one per row), its columns by name."""
    if getattr(x, "ndim", 1) == 2:
        return {name: x[:, k] for name, k in VARIABLE_INDEX.items()}
    return {name: x[k] for name, k in VARIABLE_INDEX.items()}


SOLVER_PARAMETERS: tuple[Parameter, ...] = tuple(p for p in CONSTANT_TABLE if p.path)
"""The fixed parameters of the NLP and the GP, in parameter-vector order."""


def _pairs(attribute: str) -> dict[str, tuple[float, float]]:
    pairs: dict[str, tuple[float, float]] = {p.name: getattr(p, attribute) for p in VARIABLE_TABLE}
    assert None not in pairs.values(), attribute
    return pairs


MODEL_RANGE: dict[str, tuple[float, float]] = _pairs("range")
"""The model's range [SI] of each design variable (exclusive low for trail and diameter)."""

DEFAULT_BOUNDS: dict[str, tuple[float, float]] = _pairs("bounds")
"""The default (min, max) [SI] of each design variable."""

SCALES: tuple[float, ...] = tuple(float(p.scale or 1.0) for p in VARIABLE_TABLE)
"""The least NLP scale of each design variable [SI], in :data:`VARIABLES` order (``Parameter.scale``)."""


def default(name: str) -> Any:
    """The default value [SI] of entry ``name``."""
    return PARAMETERS[name].default


def by_key(section: str) -> dict[str, Parameter]:
    """The entries of one problem-file section, by key (``"turning"`` -> ``{"carpet_factor": ...}``)."""
    return {p.key.split(".", 1)[1]: p for p in PARAMETERS.values() if p.key and p.key.split(".", 1)[0] == section}


def checked_ranges() -> dict[str, tuple[float, float, str, str]]:
    """``{"section.key": (low, high, unit, hint)}`` of the entries the loader range-checks (those with a hint)."""
    return {p.key: (p.range[0], p.range[1], p.unit, p.hint) for p in CONSTANT_TABLE if p.key and p.range and p.hint}


# --------------------------------------------------------------------------- solver parameter vectors

_INDEX = re.compile(r'^(?P<attr>\w+)\[(?P<quote>"?)(?P<key>\w+)(?P=quote)\]$')
"""One step ``a[b]`` (dict ``a`` at the value of the conditions' ``b``) or ``a["b"]`` (at the key ``b``)."""


def location(p: Parameter) -> str | None:
    """Where the value of entry ``p`` lives on a Problem: ``store``, else ``path``, else (an entry of the
    problem file with no typed field) ``conditions.constants["<name>"]``; None for a key not in a file."""
    return p.store or p.path or (f'conditions.constants["{p.name}"]' if p.key else None)


def _dict_key(match: re.Match[str], conditions: Any) -> Any:
    return match["key"] if match["quote"] else getattr(conditions, match["key"])


def read_path(root: Any, path: str) -> Any:
    """Follow ``path`` from ``root`` (a Problem, or its Conditions for ``conditions.*`` paths given without
    the first step): attribute steps, ``a[b]`` / ``a["b"]`` dict steps, ``:x`` the inertia model's
    parameter ``x``.  A missing dict key reads as the entry's default (``constants`` of an older problem)."""
    conditions = getattr(root, "conditions", root)
    path, _, inertia_key = path.partition(":")
    value = root
    for step in path.split("."):
        match = _INDEX.match(step)
        if match:
            mapping = getattr(value, match["attr"])
            key = _dict_key(match, conditions)
            value = mapping[key] if key in mapping or key not in PARAMETERS else PARAMETERS[key].default
        else:
            value = getattr(value, step)
    if inertia_key:
        return value.parameters().get(inertia_key)
    return value


def _write(obj: Any, steps: list[str], value: Any, conditions: Any) -> Any:
    """A copy of dataclass ``obj`` with the attribute at ``steps`` replaced by ``value``."""
    step = steps[0]
    match = _INDEX.match(step)
    if match:
        mapping = dict(getattr(obj, match["attr"]))
        mapping[_dict_key(match, conditions)] = value
        return dataclasses.replace(obj, **{match["attr"]: mapping})
    if len(steps) == 1:
        return dataclasses.replace(obj, **{step: value})
    return dataclasses.replace(obj, **{step: _write(getattr(obj, step), steps[1:], value, conditions)})


def write_path(root: Any, path: str, value: Any) -> Any:
    """A copy of ``root`` (a dataclass: a Problem, or Conditions for a path without ``conditions.``) with
    the value at ``path`` (as :func:`read_path`, no ``:x`` step) replaced by ``value``."""
    return _write(root, path.split("."), value, getattr(root, "conditions", root))


def solver_values(problem: Any) -> dict[str, float]:
    """The fixed parameters of a continuous problem, by name, in :data:`SOLVER_PARAMETERS` order.

    An entry is left out when its ``when`` condition does not hold, when its
    value is None (no swept-radius limit), or when the inertia model does not
    have it.
    """
    out: dict[str, float] = {}
    for p in SOLVER_PARAMETERS:
        assert p.path is not None
        if p.when is not None and read_path(problem, p.when[0]) != p.when[1]:
            continue
        value = read_path(problem, p.path)
        if value is not None:
            out[p.name] = value
    return out


def with_solver_values(problem: Any, values: dict[str, Any]) -> Any:
    """The problem's conditions with the parameters ``values`` (floats or CasADi symbols) put in.

    Only ``conditions.*`` paths are written; the problem-level ones (target speed,
    swept-radius limit) are the caller's to use.  The inertia model is rebuilt from its
    parameters (a catalog wheel becomes a fixed inertia).
    """
    conditions = problem.conditions
    inertia: dict[str, Any] = {}
    for name, value in values.items():
        path = PARAMETERS[name].path
        if path is None or not path.startswith("conditions."):
            continue
        path, _, inertia_key = path.partition(":")
        if inertia_key:
            inertia[inertia_key] = value
        else:
            conditions = _write(conditions, path.split(".")[1:], value, problem.conditions)
    if inertia:
        conditions = dataclasses.replace(conditions, inertia=conditions.inertia.with_parameters(inertia))
    return conditions


# --------------------------------------------------------------------------- documentation


def _number(value: float | None) -> str:
    if value is None:
        return "–"
    return f"{value:.4g}"


def markdown_table() -> str:
    """The table as Markdown (``docs/parameters.md``; the report's and the docs' reference)."""
    lines = [
        "| name | symbol | unit | description | default | range | problem-file key | source |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for p in VARIABLE_TABLE + CONSTANT_TABLE:
        default_text = f"[{_number(p.bounds[0])}, {_number(p.bounds[1])}]" if p.bounds else _number(p.default)
        range_text = f"{_number(p.range[0])} to {_number(p.range[1])}" if p.range else "–"
        key = f"`{p.key}`" if p.key else "–"
        lines.append(
            f"| {p.name} | {p.symbol} | {p.shown_unit} | {p.description} | {default_text} | "
            f"{range_text} | {key} | {p.source} |"
        )
    return "\n".join(lines) + "\n"


DOC_HEADER = """# Parameters

Generated from `designer/parameters.py` by `python -c "import designer.parameters as p; p.write_docs()"`
(a test keeps the two equal).  Every value is in SI units; a problem file may write any of them
with units (`"2 in"`, `"20 deg"`).  For a design variable, *default* is the default `{min, max}`
and *range* the model's range.  The solvers report the sensitivity d log J / d log p of the
optimum to each constant that has a solver parameter (see `designer.parameters.SOLVER_PARAMETERS`).

"""


def outputs_markdown_table() -> str:
    """:data:`OUTPUT_TABLE` as Markdown: the quantities of an evaluated caster (``docs/parameters.md``)."""
    lines = [
        "| name | symbol | unit | description | source | in the tables of one caster |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for p in OUTPUT_TABLE:
        listed = "yes" if p.listed else "data only"
        lines.append(
            f"| {p.name} | {p.symbol or '–'} | {p.shown_unit} | {p.description} | {p.source or '–'} | {listed} |"
        )
    return "\n".join(lines) + "\n"


OUTPUTS_HEADER = """
## Quantities of an evaluated caster

What `designer.model.evaluate` gives for each caster besides its design (`designer.parameters.OUTPUT_TABLE`):
the fields and keys of `Casters` and `Caster`, their units in `to_pandas()`, the labels of a `Caster`'s HTML and
the rows of `designer evaluate`.

"""


def write_docs(path: str = "docs/parameters.md") -> None:
    """Write the tables to ``path`` (run from the repository root after changing an entry)."""
    with open(path, "w", encoding="utf-8") as out:
        out.write(DOC_HEADER + markdown_table() + OUTPUTS_HEADER + outputs_markdown_table())
