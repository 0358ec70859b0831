"""The records of the limit-cycle room: what one knock does and a knock's onset bracket, a periodic orbit and a
branch of them, a bifurcation diagram, a μ sensitivity point, the Table 1 comparison, the (K, N) map, a scanned
onset, a design's knock-safe speeds and the whole results/simulation limit-cycle study.  Built by
:mod:`~designer.studies.dynamics.limit_cycles._system`, :mod:`~designer.studies.dynamics.limit_cycles._orbits`,
:mod:`~designer.studies.dynamics.limit_cycles._studies` and :mod:`~designer.studies.dynamics.limit_cycles._knock`;
rendered by :mod:`designer.report.limit_cycles`, which reads their attributes.  Their ``to_dict()`` is the dict the functions returned before (the keys of
results/simulation/bifurcation.json and of ``designer simulate --bifurcation --json``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from designer.display import number, shown
from designer.model import Design
from designer.physics.tyre import TyreParameters
from designer.reprs import Key, Keyed, Record, dataframe


@dataclass(frozen=True, kw_only=True)
class KnockResult(Record):
    """What a knock does: the trace, the amplitudes and the verdict.

    Attributes
    ----------
    t, theta : time [s] and caster angle θ [rad] (empty unless ``record``)
    extrema : (t [s], θ [rad]) at the reversals
    early_amplitude : mean half peak-to-peak over two periods after the aligning transient [rad]
    late_amplitude : the same over the last two periods (0 if the motion stopped) [rad]
    shimmy : True if the knock ends in sustained shimmy: |θ| reached the limit, or the caster still
        reverses at least 3 times in the last two periods with late ≥ 0.5 early (a decaying
        Coulomb-damped motion stops in finite time; a slow creep of a sliding tyre is not shimmy)
    reason : "end", "limit" (|θ| reached ``angle_limit``) or "rest" (the caster stopped)
    """

    t: np.ndarray
    theta: np.ndarray
    extrema: np.ndarray
    early_amplitude: float
    late_amplitude: float
    shimmy: bool
    reason: str
    speed: float = 0.0
    angle: float = 0.0

    _units = {**dict.fromkeys(("theta", "early_amplitude", "late_amplitude", "angle"), "rad"), "t": "s", "speed": "m/s"}


@dataclass(frozen=True, kw_only=True)
class OnsetBracket(Record):
    """Knock onset by bisection: the knock decays at ``low`` and is sustained at ``high`` [m/s]."""

    low: float
    high: float
    evaluations: int

    _units = {"low": "m/s", "high": "m/s", "speed": "m/s"}
    _keys = ("low", "high", "speed", "evaluations")
    """The bracket, its geometric mean and the number of knock simulations."""

    @property
    def speed(self) -> float:
        """Geometric mean of the bracket [m/s]."""
        return math.sqrt(self.low * self.high)


@dataclass(frozen=True, kw_only=True)
class PeriodicOrbit(Record):
    """A symmetric periodic orbit (shimmy at constant amplitude) and its stability.

    Attributes
    ----------
    amplitude : θ_max = A [rad]
    speed : V [m/s]
    state : state at the maximum of θ (θ' = 0) [SI]
    period : full period [s]
    multipliers : nontrivial Floquet multipliers of the full period (complex) [-]
    stable : all |multiplier| < 1
    closure : largest change of the section state over one full period, in rad
        (X/T, X'/(ωT), θ) [rad]
    residual : half-period fixed-point residual at convergence [rad]
    iterations : Newton iterations
    """

    amplitude: float
    speed: float
    state: np.ndarray
    period: float
    multipliers: np.ndarray
    stable: bool
    closure: float
    residual: float
    iterations: int

    _keys = (
        *("amplitude", "speed", "period", "frequency", "stable", "closure", "residual", "iterations"),
        Key("multipliers", lambda o: [[float(m.real), float(m.imag)] for m in o.multipliers]),
        "max_abs_multiplier",
    )
    """Plain floats, the complex multipliers as [re, im] pairs (not the section ``state``)."""

    @property
    def frequency(self) -> float:
        """2π / period [rad/s]."""
        return 2 * math.pi / self.period

    @property
    def max_abs_multiplier(self) -> float:
        """Largest |Floquet multiplier| [-] (below 1: stable)."""
        return float(np.max(np.abs(self.multipliers)))

    _units = {
        **dict.fromkeys(("amplitude", "closure", "residual"), "rad"),
        "speed": "m/s",
        "period": "s",
        "frequency": "rad/s",
    }


@dataclass(frozen=True)
class Branch(Record):
    """Periodic orbits along amplitude, split into stable and unstable pieces for the diagram."""

    orbits: list[PeriodicOrbit] = field(default_factory=list)
    failed: list[float] = field(default_factory=list)  # amplitudes where no orbit was found [rad]

    _units = {"failed": "rad"}

    def _repr_lines(self) -> list[str]:
        """One line: the HTML rows (how many orbits and stable ones, over which amplitudes and speeds, failures)."""
        return [f"Branch({', '.join(f'{label} {value} {unit}'.rstrip() for label, value, unit in self._html_rows())})"]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The orbits (stable ones), their ranges of amplitude and speed (the table's precision; none: missing), the
        failed amplitudes."""
        a, v = ([getattr(o, k) for o in self.orbits] or [math.nan] for k in ("amplitude", "speed"))
        return [
            ("orbits (stable)", f"{len(self.orbits)} ({sum(bool(o.stable) for o in self.orbits)})", ""),
            ("amplitude A", f"{number(min(a), dimension='angle')} – {number(max(a), dimension='angle')}", "rad"),
            ("speed V", f"{number(min(v), dimension='speed')} – {number(max(v), dimension='speed')}", "m/s"),
            ("failed amplitudes", str(len(self.failed)), ""),
        ]

    def pieces(self) -> list[dict[str, Any]]:
        """Consecutive runs of equal stability: [{"kind", "speed", "amplitude"}] (SI, rad)."""
        out: list[dict[str, Any]] = []
        for orb in self.orbits:
            kind = "stable" if orb.stable else "unstable"
            if not out or out[-1]["kind"] != kind:
                out.append({"kind": kind, "speed": [], "amplitude": []})
            out[-1]["speed"].append(float(orb.speed))
            out[-1]["amplitude"].append(float(orb.amplitude))
        return out


def _rows_frame(record: Any, units: dict[str, str]) -> Any:
    """A study's ``rows`` as a pandas DataFrame, one row each (their ``to_dict()``), with ``units`` and the knock angle."""
    rows = [r.to_dict() for r in record.rows]
    return dataframe(f"{type(record).__name__}.to_pandas", rows, list(rows[0]), units, angle=record.angle)


@dataclass(frozen=True, kw_only=True)
class BifurcationDiagram(Record):
    """Periodic orbits of one caster against speed (:func:`bifurcation_diagram`).

    Attributes
    ----------
    design : the caster (T, d, B [m], c_f [N·m/rad])
    model : "brush tyre" or "rolling" (the paper's tyre, ``tyre`` None)
    tyre : the brush tyre's parameters, None for the rolling tyre
    inertia : I_w [kg·m²]
    friction_moment : M_f = c_f θ0 [N·m]
    frequency : ω of Eq. 15B [rad/s]
    eq7_critical_speed : Eq. 7's V_c [m/s]
    disturbance_angle : θ0 [rad]
    branches : consecutive runs of equal stability, [{"kind": "stable" | "unstable", "speed": [m/s],
        "amplitude": [rad]}] (plain data for the plot)
    orbits : every periodic orbit of the diagram (unstable part, then the stable part by amplitude)
    fold_speed : lowest speed of a periodic orbit [m/s] (below it every knock decays); NaN without a stable orbit
    reference_speed : where the stable branch was first looked for [m/s]
    stable_at_reference : the stable orbit at ``reference_speed``, or None
    max_closure : largest closure error of the orbits over one full period [rad]
    failed_amplitudes : amplitudes of the unstable branch where no orbit was found [rad]
    """

    design: Design
    model: str
    tyre: TyreParameters | None
    inertia: float
    friction_moment: float
    frequency: float
    eq7_critical_speed: float
    disturbance_angle: float
    branches: list[dict[str, Any]]
    orbits: list[PeriodicOrbit]
    fold_speed: float
    reference_speed: float
    stable_at_reference: PeriodicOrbit | None
    max_closure: float
    failed_amplitudes: list[float]

    _keys = ("*", Key("tyre", lambda b: None if b.tyre is None else dataclasses.asdict(b.tyre)))
    """Every field; the tyre as its five parameters (SI; None for the rolling tyre)."""

    _units = {
        **dict.fromkeys(("eq7_critical_speed", "fold_speed", "reference_speed"), "m/s"),
        **{"disturbance_angle": "rad", "max_closure": "rad", "inertia": "kg·m²", "friction_moment": "N·m"},
        "frequency": "rad/s",
    }

    def _repr_lines(self) -> list[str]:
        """One line: the tyre, the orbits, the fold and Eq. 7's V_c."""
        stable = sum(bool(o.stable) for o in self.orbits)
        return [
            f"BifurcationDiagram({self.model}: {len(self.orbits)} orbits ({stable} stable), fold "
            f"{shown(self.fold_speed, dimension='speed')}, Eq. 7 V_c {shown(self.eq7_critical_speed, 'critical_speed')}, "
            "max closure "
            f"{self.max_closure:.1e} rad)"
        ]


@dataclass(frozen=True, kw_only=True)
class FrictionPoint(Record):
    """The orbit branch of one tyre friction coefficient μ (:func:`friction_sensitivity`).

    Attributes
    ----------
    friction_coefficient : μ [-]
    fold_speed, fold_amplitude : the fold of the branch: lowest speed of any orbit [m/s] and its amplitude [rad]
        (the smallest sustained shimmy); NaN without a stable orbit
    stable_amplitude : amplitude of the stable orbit at the study's speed [rad] (NaN: none found)
    max_abs_multiplier : its largest |Floquet multiplier| [-]
    closure : its closure error over one full period [rad]
    """

    friction_coefficient: float
    fold_speed: float
    fold_amplitude: float
    stable_amplitude: float
    max_abs_multiplier: float
    closure: float

    _units = {"fold_speed": "m/s", "fold_amplitude": "rad", "stable_amplitude": "rad", "closure": "rad"}


@dataclass(frozen=True, kw_only=True)
class Table1Row(Keyed):
    """One wheel of Table 1: measured and predicted critical speeds [m/s].

    Attributes
    ----------
    wheel, name : Table 1's key and name of the wheel
    inertia : I_w [kg·m²]; mass : M_W [kg]
    measured : measured V_c [m/s], None for the wheels stable up to 3.8 m/s
    eq7, rolling_sim, tyre_sim : Eq. 7, the rolling simulation and the brush-tyre simulation [m/s]
    rolling_sim_bracket, tyre_sim_bracket : the simulations' bisection brackets [m/s]
    flagged : the predictions below 3.8 m/s of a wheel measured stable up to there (``flagged_below_3.8``)
    """

    wheel: str
    name: str
    inertia: float
    mass: float
    measured: float | None
    eq7: float
    rolling_sim: float
    tyre_sim: float
    rolling_sim_bracket: list[float]
    tyre_sim_bracket: list[float]
    flagged: list[str]

    _keys = (
        *("wheel", "name", "inertia", "mass", "measured", "eq7", "rolling_sim", "tyre_sim"),
        *("rolling_sim_bracket", "tyre_sim_bracket"),
        Key("**", lambda r: {"flagged_below_3.8": list(r.flagged)}),  # a dot in the key: spread, not nested
    )

    def prediction(self, key: str) -> float:
        """The prediction named ``key`` ("eq7", "rolling_sim" or "tyre_sim") [m/s]."""
        return float({"eq7": self.eq7, "rolling_sim": self.rolling_sim, "tyre_sim": self.tyre_sim}[key])


@dataclass(frozen=True, kw_only=True)
class ErrorStats(Keyed):
    """Errors prediction/measured − 1 over the measured wheels: RMS, mean (bias), largest |error| [-], count."""

    rms: float
    bias: float
    max_abs: float
    n: int


@dataclass(frozen=True, kw_only=True)
class Table1Comparison(Record):
    """Table 1 against Eq. 7 and the two simulations (:func:`table1_comparison`).

    Attributes
    ----------
    rows : one :class:`Table1Row` per wheel
    stats : {"eq7", "rolling_sim", "tyre_sim": :class:`ErrorStats`} over the measured wheels (C–G)
    angle : knock θ_i [rad]
    trail : T [m]
    tyre : the brush tyre (load L [N], cornering stiffness C [N/rad], μ [-]); each wheel its own mass
    stable_up_to : speed up to which wheels A and B were measured stable [m/s]
    """

    rows: list[Table1Row]
    stats: dict[str, ErrorStats]
    angle: float
    trail: float
    tyre: TyreParameters
    stable_up_to: float

    _keys = (
        *("rows", "stats", "angle", "trail", Key("load", "tyre.load")),
        Key(
            "tyre",
            lambda t: {
                "cornering_stiffness": t.tyre.cornering_stiffness,
                "friction_coefficient": t.tyre.friction_coefficient,
            },
        ),
        "stable_up_to",
    )
    _units = {"angle": "rad", "trail": "m", "load": "N", "stable_up_to": "m/s"}

    def to_pandas(self) -> Any:
        """One row per wheel (the columns of :class:`Table1Row`), speeds in m/s."""
        units = {"inertia": "kg·m²", "mass": "kg"} | {k: "m/s" for k in ("measured", "eq7", "rolling_sim", "tyre_sim")}
        return _rows_frame(self, units)


@dataclass(frozen=True, kw_only=True)
class MapCell(Keyed):
    """One caster at one (K, N) of the map.

    Attributes
    ----------
    caster : its name
    stiffness, lateral_mass : K [N/m] and N [kg] (``K``, ``N``); stiffness_factor, mass_factor : K/K0, N/N0 [-]
    frequency : ω of Eq. 15B with the brush tyre [rad/s]
    eq7 : Eq. 7's V_c [m/s]; measured : the caster's measured V_c [m/s]
    rolling_onset : knock onset with the rolling tyre [m/s] (NaN: not bracketed)
    tyre_onset : knock onset with the brush tyre [m/s] (NaN: sustained nowhere in the scan)
    tyre_onset_monotone : sustained at every scanned speed above the onset; tyre_onset_below_scan : sustained
        already at the lowest scanned speed
    stable_amplitude : stable shimmy amplitude at the measured speed [rad] (NaN: none found)
    stable_max_multiplier : its largest |Floquet multiplier| [-]
    """

    caster: str
    stiffness: float
    lateral_mass: float
    stiffness_factor: float
    mass_factor: float
    frequency: float
    eq7: float
    measured: float
    rolling_onset: float
    tyre_onset: float
    tyre_onset_monotone: bool
    tyre_onset_below_scan: bool
    stable_amplitude: float
    stable_max_multiplier: float

    _keys = (
        *("caster", Key("K", "stiffness"), Key("N", "lateral_mass")),
        *(Key("K_factor", "stiffness_factor"), Key("N_factor", "mass_factor"), "frequency", "eq7", "measured"),
        *("rolling_onset", "tyre_onset", "tyre_onset_monotone", "tyre_onset_below_scan", "stable_amplitude"),
        "stable_max_multiplier",
    )
    """The columns of stiffness_mass_map.csv."""


@dataclass(frozen=True, kw_only=True)
class StiffnessMassMap(Record):
    """Onsets and the stable amplitude over a grid of frame stiffness K and lateral mass N
    (:func:`stiffness_mass_map`).

    Attributes
    ----------
    rows : one :class:`MapCell` per caster and (K, N)
    stiffness, lateral_mass : the defaults K0 [N/m] and N0 [kg] (``K0``, ``N0``)
    factors : the grid factors on K0 and N0 [-]
    angle : knock θ_i [rad]
    """

    rows: list[MapCell]
    stiffness: float
    lateral_mass: float
    factors: list[float]
    angle: float

    _keys = ("rows", Key("K0", "stiffness"), Key("N0", "lateral_mass"), "factors", "angle")
    _units = {"K0": "N/m", "N0": "kg", "angle": "rad"}

    def casters(self) -> list[tuple[str, list[MapCell], MapCell]]:
        """The casters of the map, in order: (name, its cells, its cell at the defaults K0, N0)."""
        out = []
        for name in dict.fromkeys(r.caster for r in self.rows):
            cells = [r for r in self.rows if r.caster == name]
            out.append((name, cells, next(r for r in cells if r.stiffness_factor == 1.0 and r.mass_factor == 1.0)))
        return out

    def to_pandas(self) -> Any:
        """One row per cell (the columns of stiffness_mass_map.csv)."""
        units = {"K": "N/m", "N": "kg", "frequency": "rad/s", "stable_amplitude": "rad"}
        return _rows_frame(self, units | {k: "m/s" for k in ("eq7", "measured", "rolling_onset", "tyre_onset")})


@dataclass(frozen=True, kw_only=True)
class OnsetScan(Record):
    """The lowest speed at which a knock is sustained, from a scan then bisection (:func:`scanned_onset_speed`).

    Attributes
    ----------
    speed : the onset [m/s] (NaN if sustained nowhere in the scan)
    monotone : sustained at every scanned speed above the first
    below_scan : sustained already at the lowest scanned speed
    evaluations : knock simulations
    """

    speed: float
    monotone: bool
    below_scan: bool
    evaluations: int

    _units = {"speed": "m/s"}


@dataclass(frozen=True, kw_only=True)
class KnockSafe(Record):
    """One design's knock-safe speeds (:func:`knock_safe_speeds`, the recommendation card).

    Attributes
    ----------
    knock_angle : θ0 [rad]
    knock_safe_rtol : relative width of the onset bracket [-]
    knock_safe_speed : for a θ0 knock [m/s] (None: not bracketed, see ``knock_safe_error``)
    knock_safe_speed_double : for a 2 θ0 knock [m/s] (None when 2 θ0 ≥ 90° or not bracketed)
    knock_safe_error : why an onset could not be bracketed (None when both were)
    """

    knock_angle: float
    knock_safe_rtol: float
    knock_safe_speed: float | None
    knock_safe_speed_double: float | None
    knock_safe_error: str | None = None

    _keys = (
        *("knock_angle", "knock_safe_rtol", "knock_safe_speed", "knock_safe_speed_double"),
        Key("knock_safe_error", omit="none"),
    )
    _units = {"knock_angle": "rad", "knock_safe_speed": "m/s", "knock_safe_speed_double": "m/s"}


@dataclass(frozen=True, kw_only=True)
class RollingLimitCheck(Keyed):
    """The brush tyre's rolling limit against today's rolling model: the onset of a θ0 knock on the same caster.

    Attributes
    ----------
    factor : the cornering stiffness × this, saturation off [-]
    today : onset by :mod:`designer.studies.dynamics._simulate` [m/s]
    tyre_limit : onset of the brush tyre in that limit [m/s]
    today_bracket, tyre_limit_bracket : their bisection brackets [m/s]
    """

    factor: float
    today: float
    tyre_limit: float
    today_bracket: list[float]
    tyre_limit_bracket: list[float]


@dataclass(frozen=True, kw_only=True)
class LimitCycleStudy(Record):
    """Everything the results/simulation limit-cycle report shows (:func:`limit_cycle_study`), Appendix C caster.

    Attributes
    ----------
    bifurcation, rolling : bifurcation diagrams with the brush tyre and with the rolling tyre
    friction : the brush tyre's branch for each friction coefficient μ
    knock_safe : knock-safe speeds [m/s] by ``"<rolling|brush>_<1|2>theta0"`` (knocks of θ0 and 2 θ0)
    table1 : Table 1 comparison
    rolling_limit : the brush tyre's rolling limit against today's model
    stiffness_mass_map : the (K, N) map (``map``)
    measured_speed, measured_amplitude : the Appendix C caster's measured V_c [m/s] and shimmy amplitude [rad]
        (``measured.speed``, ``measured.amplitude``)
    seconds : wall time of the study [s]
    quick : the quick version (fewer orbits; for checking the pipeline, not for results)
    """

    bifurcation: BifurcationDiagram
    rolling: BifurcationDiagram
    friction: list[FrictionPoint]
    knock_safe: dict[str, float]
    table1: Table1Comparison
    rolling_limit: RollingLimitCheck
    stiffness_mass_map: StiffnessMassMap
    measured_speed: float
    measured_amplitude: float
    seconds: float
    quick: bool

    _keys = (
        *("bifurcation", "rolling", "friction", "knock_safe", "table1", "rolling_limit"),
        Key("map", "stiffness_mass_map"),
        *(Key("measured.speed", "measured_speed"), Key("measured.amplitude", "measured_amplitude"), "seconds", "quick"),
    )
    _units = {"measured.speed": "m/s", "measured.amplitude": "rad", "seconds": "s"}

    def _repr_lines(self) -> list[str]:
        """Two lines: the orbits' headline (fold, stable amplitude against the measured) and the other parts."""
        ref = self.bifurcation.stable_at_reference
        amplitude = "none" if ref is None else f"{ref.amplitude:.3g} rad"
        return [
            f"LimitCycleStudy({'quick' if self.quick else 'full'}): "
            f"fold {shown(self.bifurcation.fold_speed, dimension='speed')}, "
            f"stable amplitude at {self.measured_speed:.4g} m/s {amplitude} (measured {self.measured_amplitude:.3g} rad)",
            f"  {len(self.friction)} friction coefficients, {len(self.table1.rows)} Table 1 wheels, "
            f"{len(self.stiffness_mass_map.rows)} map cells, {self.seconds:.0f} s",
        ]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        ref = self.bifurcation.stable_at_reference
        rows: list[tuple[Any, Any, Any]] = [
            ("fold speed (brush tyre)", number(self.bifurcation.fold_speed, dimension="speed"), "m/s"),
            ("stable amplitude at the measured V_c", "none" if ref is None else f"{ref.amplitude:.4g}", "rad"),
            ("measured V_c", f"{self.measured_speed:.4g}", "m/s"),
            ("measured amplitude", f"{self.measured_amplitude:.4g}", "rad"),
        ]
        rows += [(f"knock-safe speed {k}", number(v, dimension="speed"), "m/s") for k, v in self.knock_safe.items()]
        rows += [(f"Table 1 RMS error {k}", f"{100 * s.rms:.1f}", "%") for k, s in self.table1.stats.items()]
        return rows
