"""The one evaluator of candidate casters: a batch of designs and their conditions in, every number out.

:func:`evaluate` is where the studies get the performance and the risk of their candidates:
the stock screen and the records of ``designer.recommend``, the fixes of ``designer.fix``, the chairs ×
stock casters of ``designer fleet``, the studio's card.  It composes :func:`designer.model.performance`
(I_w, Eq. 7, the quantile of the risk law, Eq. 4A, Eq. 9) for arrays of candidates and adds what a
screen needs: the sill (d > 2h, else P = +inf), the swept radius of the fork as built (T + d/2), the
feasibility with one tolerance, and on request the Monte Carlo P(shimmy) with its standard error
(:func:`shimmy_probability`, the one batched Monte Carlo of the package).  The risk law itself (its
scatter, the quantile, the sampling) is :mod:`designer.physics.uncertainty`'s; it is called here and
nowhere else in the studies.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any, Self

import numpy as np

from designer.parameters import OUTPUT_TABLE, OUTPUTS, PARAMETERS, VARIABLE_TABLE, VARIABLES
from designer.boundary import SEED, Count, Instance, Quantity, Values, checked, one_line
from designer.units import real_number
from designer.reprs import Key, Record, dataframe, field_names, frozen
from designer.physics.geometry import effective_trail, swept_radius
from designer.physics.scatter import inertia_prediction
from designer.errors import InputError
from designer.physics.shimmy import (
    friction_damping_at_speed,
    growth_rate,
    shimmy_frequency,
    full_shimmy_amplitude,
    third_order_coefficients,
)
from designer.physics.uncertainty import (
    MC_TARGET_SE,
    Uncertainty,
    dominant_sentence,
    law_sources,
    shimmy_probability_exact_many,
    shimmy_probability_mc_many,
)
from designer.model._caster import Conditions, Design, check_design, performance, weighted

FEASIBILITY_TOLERANCE = 1e-9
"""Relative tolerance of the two limits a candidate must meet: V_q >= V_req (1 − tol) and R_s <= R_max (1 + tol).

One number for every study.  A candidate that sits *on* a limit comes either from values converted from
inches (stock fork holes, wheel sizes, a footrest clearance: rounding of about 1e-16) or from the NLP,
which meets its constraints to IPOPT's ``constr_viol_tol`` of 1e-10 (scaled): 1e-9 accepts both, and it
is far below anything physical (2.5 nm/s on 2.5 m/s, a nanometre on a swept radius), so no caster that
misses a limit in earnest passes.  The sill (d > 2h, Eq. 4A) has no tolerance: there P is infinite."""


def scatter_of(conditions: Conditions) -> Uncertainty:
    """The risk law a reported P(shimmy) uses: the risk bound of the conditions (a problem's ``[robust]``),
    or the default :class:`~designer.physics.uncertainty.Uncertainty` when the bound is off
    (``[robust] enabled = false``: the design is nominal, its risk is still reported)."""
    return conditions.uncertainty if conditions.uncertainty is not None else Uncertainty()


def design_columns(designs: Any) -> dict[str, np.ndarray]:
    """Candidate designs as ``{name: array}`` in SI, by the names of :data:`designer.parameters.VARIABLES`.

    Accepts a mapping with those keys (arrays that broadcast together), a :class:`Design`, a sequence of
    Designs, a NumPy record array with those fields, or an (N, 4) array whose columns are in the
    parameter table's order; anything else (a string, a dict without the four names, an (N, 3) array) is an
    InputError in one line naming it.
    """
    batch = [designs] if isinstance(designs, Design) else designs
    try:
        if isinstance(batch, Mapping) or (isinstance(batch, np.ndarray) and batch.dtype.names):
            return {name: np.asarray(batch[name], dtype=float) for name in VARIABLES}
        if isinstance(batch, Sequence) and batch and isinstance(batch[0], Design):
            return {name: np.array([getattr(d, name) for d in batch], dtype=float) for name in VARIABLES}
        array = np.asarray(batch, dtype=float)
        if array.ndim == 0 or array.shape[-1] != len(VARIABLES):  # an (N, 3) array is not N casters of 4 numbers
            raise ValueError(f"an array of shape {array.shape}: expected (N, {len(VARIABLES)}), columns {VARIABLES}")
    except (AttributeError, KeyError, TypeError, ValueError) as error:
        raise InputError(
            f"design = {one_line(designs)}: expected a designer.Design (e.g. Design(trail='2 in', diameter='6 in', "
            f"groove=0, damping=1.3)) or a batch with the columns {', '.join(VARIABLES)} ({error})"
        ) from None
    array = array.reshape(-1, len(VARIABLES))
    return {name: array[:, k] for k, name in enumerate(VARIABLES)}


@dataclass(frozen=True, kw_only=True)
class Casters(Record):
    """Every number of a batch of evaluated casters (arrays in the broadcast shape of the inputs), SI: what
    :func:`evaluate` returns; ``.row(i)`` is one :class:`Caster`.

    Attributes
    ----------
    trail, diameter, groove, damping : the designs [m, m, m, N·m/rad]
    inertia : I_w [kg·m²] (given per candidate, or the inertia model at d)
    measured : whether each wheel's I_w was measured (the risk law's measurement scatter) or is known from its
        diameter only (Table 1's prediction interval)
    extrapolated : d outside Table 1's 4–8 in, where the power law and Eq. 7's check are extrapolations
    effective_trail : the trail the tyre sees, e + (d/2) sin φ for a stem tilted by φ [m] (= trail when upright)
    critical_speed : V_c of Eq. 7 on the effective trail [m/s] (not calibrated)
    confident_speed : the speed the risk bound compares with V_req [m/s]: the speed reached with probability
        1 − α under the risk law (``shimmy_speed_quantile``), or V_c itself without a risk bound; times the
        calibration factor k of an observed onset
    turning_effort : F_turn [N] (Eq. 9 with the turning model, on the effective trail)
    turning_moment : M_turn + M_d [N·m], the moment F_turn overcomes at the trail
    threshold_force : P [N] (Eq. 4A); +inf where the wheel cannot climb the sill (d <= 2h)
    threshold_force_ratio : P/L [-] (Eq. 4A); +inf where the wheel cannot climb the sill
    swept_radius : T + d/2 of the fork as built [m]
    shimmy_frequency : ω of the third-order model [rad/s] (Eq. 15B)
    g_risk, g_radius : the constraint values, g <= 0 feasible within :data:`FEASIBILITY_TOLERANCE`:
        1 − V_q/V_req and R_s/R_max − 1 [-] (−inf where no limit was given)
    risk_ok, radius_ok, sill_ok : each limit met (g_risk, g_radius <= :data:`FEASIBILITY_TOLERANCE`; d > 2h)
    feasible : all three
    weighted : J = w_turn F_turn + w_threshold P [N] for the weights given to :func:`evaluate` (else None)
    growth_rate : μ of the oscillatory mode at the speed given to :func:`evaluate` [1/s] (Eq. 16B; else None)
    shimmy_probability, shimmy_probability_se : P(V_c,true < speed) [-] (``risk``) by Monte Carlo with its
        standard error, or by quadrature of the exact law (``exact=True``: SE 0); None unless asked for
    """

    trail: np.ndarray
    diameter: np.ndarray
    groove: np.ndarray
    damping: np.ndarray
    inertia: np.ndarray
    measured: np.ndarray
    extrapolated: np.ndarray
    effective_trail: np.ndarray
    critical_speed: np.ndarray
    confident_speed: np.ndarray
    turning_effort: np.ndarray
    turning_moment: np.ndarray
    threshold_force: np.ndarray
    threshold_force_ratio: np.ndarray
    swept_radius: np.ndarray
    shimmy_frequency: np.ndarray
    g_risk: np.ndarray
    g_radius: np.ndarray
    risk_ok: np.ndarray
    radius_ok: np.ndarray
    sill_ok: np.ndarray
    feasible: np.ndarray
    weighted: np.ndarray | None = None
    growth_rate: np.ndarray | None = None
    shimmy_probability: np.ndarray | None = None
    shimmy_probability_se: np.ndarray | None = None
    quantities: Mapping[str, Any] = field(default_factory=dict, repr=False)
    """The quantities of :data:`designer.parameters.OUTPUT_TABLE` that have no field of their own, by name (read
    as attributes and keys like the fields): a new quantity needs no field here."""

    _keys = (Key("*", omit="none"), Key("**", "quantities"))
    """``{quantity: values}``, the optional ones only when computed (a list per candidate; a number for one)."""

    _units = {p.name: p.unit for p in VARIABLE_TABLE + OUTPUT_TABLE if p.unit}
    """The units of the parameter table (:data:`designer.parameters.OUTPUT_TABLE`)."""

    @classmethod
    def of(cls, **columns: Any) -> Self:
        """The record of ``columns`` by name: the fields, and the other quantities of
        :data:`designer.parameters.OUTPUT_TABLE` in :attr:`quantities` (TypeError for a name in neither)."""
        names = field_names(cls)
        unknown = [k for k in columns if k not in names and k not in OUTPUTS]
        if unknown:
            raise TypeError(f"{cls.__name__}.of: {unknown[0]!r} is neither a field nor in parameters.OUTPUT_TABLE")
        quantities = {k: v for k, v in columns.items() if k not in names}
        return cls(**{k: v for k, v in columns.items() if k in names}, quantities=frozen(quantities))

    def __getattr__(self, name: str) -> Any:
        quantities = self.__dict__.get("quantities") or {}
        if name in quantities:
            return quantities[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __len__(self) -> int:
        return int(self.feasible.shape[0]) if self.feasible.ndim else 1

    def J(self, weights: Sequence[float]) -> np.ndarray:
        """J = w_turn F_turn + w_threshold P [N] for ``weights`` (w_turn, w_threshold): the weighted objective,
        written once."""
        return np.asarray(weighted(np.asarray(self.turning_effort), np.asarray(self.threshold_force), weights))

    def g(self) -> np.ndarray:
        """The constraint values (N, 2): g_risk, g_radius; g <= :data:`FEASIBILITY_TOLERANCE` is feasible."""
        return np.column_stack([self._column("g_risk"), self._column("g_radius")])

    def violation(self) -> np.ndarray:
        """Total constraint violation [-]: the sum of the positive g (0 for a caster that meets both limits)."""
        out: np.ndarray = np.maximum(0.0, self.g()).sum(axis=1)
        return out

    def keys(self) -> list[str]:
        """The names of the quantities that hold a value (the optional ones only when computed): the columns, read
        by key as by attribute (``casters["threshold_force"]``)."""
        own = [name for name in field_names(type(self), shown=True) if getattr(self, name) is not None]
        return own + list(self.quantities)

    def __getitem__(self, key: str) -> Any:
        if key not in self.keys():
            raise KeyError(key)
        return getattr(self, key)

    def __contains__(self, key: object) -> bool:
        return key in self.keys()

    def get(self, key: str, default: Any = None) -> Any:
        """The field ``key``, or ``default`` when it holds no value."""
        return self[key] if key in self else default

    def _column(self, name: str) -> np.ndarray:
        """Quantity ``name`` broadcast to one value per candidate (a column of that shape as a read-only view: a slice
        of :meth:`take` cannot write into the record)."""
        a = np.asarray(getattr(self, name))
        if a.shape != (len(self),):
            return np.broadcast_to(a, (len(self),))
        view = a.view()
        view.flags.writeable = False
        return view

    def row(self, i: int) -> "Caster":
        """Caster ``i`` (the quantities as Python scalars)."""
        return self.take([i]).rows()[0]

    def _records(self) -> list[dict[str, Any]]:
        """One {quantity: value} per candidate (Python scalars), each column read once."""
        columns = self.keys()
        return [dict(zip(columns, values)) for values in zip(*(self._column(c).tolist() for c in columns))]

    def rows(self) -> list["Caster"]:
        """Every caster, as :meth:`row` gives it, each column read once (a front's points: a tenth of the time of
        one :meth:`row` a point)."""
        empty: dict[str, Any] = {f.name: None for f in fields(self) if f.name != "quantities"}
        return [Caster.of(**{**empty, **record}) for record in self._records()]

    def to_pandas(self) -> Any:
        """One row per candidate, one column per quantity (the Monte Carlo ones only when computed); units in
        ``df.attrs["units"]``."""
        units = {c: u for c, u in self._units.items() if c in self.keys()}
        return dataframe(f"{type(self).__name__}.to_pandas", self._records(), self.keys(), units)

    def _repr_lines(self) -> list[str]:
        """One line: how many candidates, how many feasible, and the ranges of F_turn and P."""
        f, p = np.atleast_1d(self.turning_effort), np.atleast_1d(self.threshold_force)
        return [
            f"{type(self).__name__}({len(self)} casters, {int(np.count_nonzero(self.feasible))} feasible; "
            f"F_turn {float(np.min(f)):.4g}–{float(np.max(f)):.4g} N, P {float(np.min(p)):.4g}–{float(np.max(p)):.4g} N)"
        ]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The count and the range of every quantity over the candidates (no Monte Carlo runs)."""
        rows: list[tuple[Any, Any, Any]] = [
            ("candidates (feasible)", f"{len(self)} ({int(np.count_nonzero(self.feasible))})", "")
        ]
        for name in self.keys():
            a = np.asarray(getattr(self, name))
            if a.dtype != bool:
                rows.append((name, f"{float(np.min(a)):.4g} – {float(np.max(a)):.4g}", self._units.get(name, "")))
        return rows

    def take(self, index: Any) -> "Casters":
        """The candidates at ``index`` (a boolean mask or integer indices along the first axis)."""
        taken: dict[str, Any] = {
            name: None if getattr(self, name) is None else np.asarray(self._column(name))[index]
            for name in [f.name for f in fields(self) if f.repr] + list(self.quantities)
        }
        return Casters.of(**taken)


@dataclass(frozen=True, kw_only=True)
class Caster(Casters):
    """One evaluated caster (:meth:`Casters.row`, or :func:`evaluate` of one :class:`Design`): the fields of
    :class:`Casters` as Python scalars, also read by key (``caster["threshold_force"]``, ``dict(caster)``), as
    the dict that ``designer.evaluate`` returned before.

    ``risk_law`` (not a column: not in ``keys()``): where the risk comes from, for one :class:`Design` evaluated
    with ``risk``: ``{"sources": [...], "dominant": sentence}``, each source of the law with its share of the
    variance of log V_c (:func:`designer.physics.uncertainty.law_sources`); None otherwise."""

    risk_law: Mapping[str, Any] | None = field(default=None, repr=False)

    def __len__(self) -> int:
        return 1

    @property
    def design(self) -> Design:
        """The caster's design (T, d, B, c_f), the same numbers as its fields."""
        return Design(float(self.trail), float(self.diameter), float(self.groove), float(self.damping))

    # one caster shows its values (the protocol's defaults, labels and units from the table), not their ranges
    _repr_lines = Record._repr_lines
    _html_rows = Record._html_rows


class OfCaster:
    """An attribute of a study's record read from the :class:`Caster` it holds (``record.caster.<name>``): the
    caster's numbers live once, in the evaluator's row, and the record's documented attribute (``rec.turning_effort``)
    reads it without computing anything.  A class attribute of the record, not a dataclass field::

        caster: Caster
        turning_effort = OfCaster()  # rec.turning_effort is rec.caster.turning_effort
    """

    name: str = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, record: Any, owner: type | None = None) -> Any:
        if record is None:
            return self
        return getattr(record.caster, self.name)


@checked(
    conditions=Instance((Conditions,), "a designer.Conditions, e.g. Conditions(load=178)"),
    speed=Values("speed"),
    risk=Values("speed"),
    inertia=Values("inertia"),
    load=Values("force"),
    threshold_height=Values("length"),
    required_speed=Values("speed"),
    swept_radius_max=Values("length"),
    stem_angle=Quantity("angle"),
    calibration=Quantity("dimensionless"),
    samples=Count(1, optional=True, what="Monte Carlo draws"),
    seed=SEED,
    target_se=Quantity("dimensionless", optional=True),
)
def evaluate(  # long: the docstring documents every argument
    designs: Any,
    conditions: Conditions = Conditions(),
    speed: Any = None,
    *,
    weights: Sequence[float] | None = None,
    risk: Any = None,
    exact: bool = False,
    inertia: Any = None,
    measured: Any = None,
    load: Any = None,
    threshold_height: Any = None,
    required_speed: Any = None,
    swept_radius_max: Any = None,
    stem_angle: float = 0.0,
    calibration: float = 1.0,
    scatter: Uncertainty | None = None,
    samples: int | None = None,
    seed: int | None = None,
    target_se: float | None = MC_TARGET_SE,
) -> Any:
    """The one door to the model for numbers: evaluate one caster or a batch.

    Parameters
    ----------
    designs : one :class:`Design` (then a :class:`Caster` is returned, after the model-range check of
        :func:`check_design`: InputError), or a batch by name (:func:`design_columns`): T, d, B [m],
        c_f [N·m/rad] (then :class:`Casters`)
    conditions : the chair and the model (load L [N], sill h [m], surface, turning mode, θ0, K_s, the inertia
        model, the risk law ``uncertainty``: the bound when set, else the nominal V_c >= V_req)
    speed : a speed [m/s] at which to give the growth rate μ of the oscillatory mode (Eq. 16B; Eq. 6 with
        Eq. 4 for the friction damping)
    weights : (w_turn, w_threshold): give ``weighted`` = J = w_turn F_turn + w_threshold P [N]
    risk : a speed [m/s] (one, or one per caster) at which to give P(V_c,true < speed) under the risk law
        (``scatter``, default :func:`scatter_of` the conditions): by Monte Carlo with its SE, or by quadrature
        of the exact law with ``exact=True`` (one caster at a time; SE 0); for one Design also ``risk_law``
    inertia : I_w per caster [kg·m²] (a measured or catalogue wheel); None: ``conditions.inertia(d)``
    measured : whether each caster's I_w was measured (True, False or one flag per caster); default: the
        inertia model's own when ``inertia`` is None (catalogue and fixed wheels measured, the power law not),
        else True.  A wheel not measured is known by its diameter: the risk law then scatters its I_w by Table
        1's prediction interval at d (bound and Monte Carlo alike)
    load, threshold_height : per-caster (broadcasting) load [N] and sill height [m] instead of the
        conditions' (a fleet's chairs)
    required_speed : V_req = (1 + margin) V_target [m/s] of the risk limit (None: no limit)
    swept_radius_max : R_max [m] (None: no limit)
    stem_angle : stem tilt φ [rad] from vertical; T is then the fork offset e and the tyre sees e + (d/2) sin φ
    calibration : factor k = V_obs / V_c,Eq.7 of a caster whose onset was observed (multiplies V_c in the bound
        and in the risk)
    samples, seed, target_se : the Monte Carlo's least sample, seed and target standard error
        (:func:`shimmy_probability`)

    Returns
    -------
    Casters (a Caster for one Design).  Equations: I_w (inertia model), Eq. 7 (V_c), ``shimmy_speed_quantile``
    (V_q, the risk law), Eq. 4A (P), Eq. 9 (F_turn), T + d/2 (R_s), Eq. 15B (ω), Eq. 16B (μ):
    :func:`designer.model.performance` composes them.
    """
    single = isinstance(designs, Design)
    if single:
        check_design(designs, error=InputError)  # an 8 m wheel is inches written as metres, not a caster
    speed, risk = _speed(speed), _speed(risk, "risk")
    weights = None if weights is None else _weights(weights)
    if not isinstance(exact, (bool, np.bool_)):
        raise InputError(f"exact = {exact!r}: expected True (the exact law by quadrature) or False (Monte Carlo)")
    given = {"load": load, "threshold_height": threshold_height}  # per caster [N], [m]: instead of the conditions'
    per_caster = {name: np.asarray(value, dtype=float) for name, value in given.items() if value is not None}
    cond = conditions.replace(**per_caster) if per_caster else conditions
    out = _evaluate(
        design_columns(designs), cond, inertia, measured, required_speed, swept_radius_max, stem_angle, calibration
    )
    extra: dict[str, Any] = {}
    if weights is not None:
        extra["weighted"] = out.J(weights)
    if speed is not None:
        extra["growth_rate"] = _growth_rate(out, conditions, speed)
    if risk is not None:
        law = scatter_of(cond) if scatter is None else scatter
        p, se = _risk(out, conditions, risk, law, exact, calibration, samples, seed, target_se)
        known = np.isfinite(np.asarray(out.critical_speed, dtype=float))  # a NaN caster has no risk, not P = 0
        known = known.reshape(known.shape + (1,) * (np.ndim(p) - known.ndim))
        extra["shimmy_probability"] = np.where(known, p, np.nan)
        extra["shimmy_probability_se"] = np.where(known, se, np.nan)
    if extra:
        out = replace(out, **extra)
    if not single:
        return out
    one = out.row(0)
    if risk is None:
        return one
    wheel = None if one.measured else float(one.diameter)  # where one caster's risk comes from
    t, i_w, b, c = (float(one[name]) for name in ("effective_trail", "inertia", "groove", "damping"))
    sources = law_sources(t, i_w, b, c, conditions.slip_coefficient, law, wheel)
    return replace(one, risk_law={"sources": sources, "dominant": dominant_sentence(sources)})


def _speed(speed: Any, name: str = "speed") -> Any:
    """A speed argument [m/s] (``speed`` of the growth rate, ``risk`` of P(shimmy)) as the boundary gave it (one, or
    one per caster: :class:`designer.boundary.Values`), finite and within the target speed's range of the parameter
    table; None stays None."""
    if speed is None:
        return None
    values = np.asarray(speed, dtype=float)
    low, high = PARAMETERS["target_speed"].range or (0.0, np.inf)
    bad = ~((values >= low) & (values <= high))
    if np.any(bad):
        shown = float(values.ravel()[np.argmax(bad.ravel())])
        raise InputError(f"{name} = {shown:g} m/s: outside the model's range {low:g} to {high:g} m/s")
    return values if values.ndim else float(values)


def _weights(weights: Any) -> tuple[float, float]:
    """(w_turn, w_threshold) [-]: exactly two finite numbers, not both zero."""
    try:  # each weight by the API's one rule for numbers (a boolean is not a weight)
        w = tuple(real_number(x, "weights") for x in weights)
    except (TypeError, InputError):
        w = ()
    if len(w) != 2 or not all(np.isfinite(w)) or min(w) < 0 or max(w) == 0:
        raise InputError(f"weights = {weights!r}: expected two finite weights >= 0, not both 0 (w_turn, w_threshold)")
    return w[0], w[1]


def critical_speed(
    trail: Any, inertia: Any, groove: Any, damping: Any, slip_coefficient: float = Conditions().slip_coefficient
) -> Any:
    """V_c of Eq. 7 [m/s] of casters whose wheel inertia I_w [kg·m²] is given (a simulated knock's effective
    c_f = M_f/θ_i, a paper figure's Table 1 wheel, a paper check), by :func:`evaluate` without a risk law; T, B [m],
    c_f [N·m/rad] broadcast, K_s [N]; a float for scalar inputs.  The wheel's diameter plays no part in V_c once
    I_w is given.  The signature of :func:`designer.physics.shimmy.critical_shimmy_speed`, so a check can take
    either."""
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (trail, inertia, groove, damping)))
    t, i_w, b, c = (a.ravel() for a in arrays)
    design = {"trail": t, "diameter": np.full(t.shape, 0.2), "groove": b, "damping": c}  # d: any, I_w is given
    conditions = Conditions(slip_coefficient=float(slip_coefficient), uncertainty=None)
    v = evaluate(design, conditions, inertia=i_w).critical_speed.reshape(arrays[0].shape)
    return float(v) if v.ndim == 0 else v


def _evaluate(
    columns: dict[str, np.ndarray],
    cond: Conditions,
    inertia: Any,
    measured: Any,
    required_speed: Any,
    swept_radius_max: Any,
    stem_angle: float,
    calibration: float,
) -> Casters:
    """The deterministic columns of :func:`evaluate` (performance, limits, feasibility) under ``cond``, the conditions
    with any per-caster load and sill height."""
    t, d, b, c = (columns[name] for name in VARIABLES)
    i_w = np.asarray(cond.inertia(d) if inertia is None else inertia, dtype=float) + 0 * d
    if measured is None:
        measured = bool(getattr(cond.inertia, "measured", False)) if inertia is None else True
    flags = np.broadcast_to(np.asarray(measured, dtype=bool), np.broadcast_shapes(np.shape(measured), i_w.shape))
    t_eff = t if stem_angle == 0 else np.asarray(effective_trail(t, d / 2, stem_angle), dtype=float)
    h = np.asarray(cond.threshold_height, dtype=float)
    sill_ok = d > 2 * h
    climbing = np.where(sill_ok, d, 3 * h)  # a wheel that cannot climb gets P = inf below, not Eq. 4A's error
    values = performance(t_eff, climbing, b, c, cond, inertia=i_w, measured=flags, wheel_diameter=d)
    confident = calibration * np.asarray(values["confident_speed"], dtype=float)  # k V_q (x 1.0 is exact)
    force = np.where(sill_ok, np.asarray(values["threshold_force"], dtype=float), np.inf)
    ratio = np.where(sill_ok, np.asarray(values["threshold_force_ratio"], dtype=float), np.inf)
    radius = np.asarray(swept_radius(t, d), dtype=float)
    g_risk, g_radius = _constraints(confident, radius, required_speed, swept_radius_max)
    risk_ok, radius_ok = g_risk <= FEASIBILITY_TOLERANCE, g_radius <= FEASIBILITY_TOLERANCE
    turning = np.asarray(values["turning_effort"], dtype=float)
    shape = np.broadcast_shapes(turning.shape, force.shape, risk_ok.shape, radius_ok.shape, sill_ok.shape)
    omega = np.asarray(shimmy_frequency(t_eff, i_w, cond.dynamics), dtype=float)
    return Casters.of(  # the quantities of parameters.OUTPUT_TABLE: a new one is one line here
        trail=t,
        diameter=d,
        groove=b,
        damping=c,
        inertia=i_w,
        measured=flags,
        extrapolated=np.asarray(inertia_prediction().extrapolated(d), dtype=bool),
        effective_trail=np.asarray(t_eff, dtype=float),
        critical_speed=np.asarray(values["critical_speed"], dtype=float),
        confident_speed=confident,
        turning_effort=turning,
        turning_moment=np.asarray(values["turning_moment"], dtype=float) + 0 * turning,
        threshold_force=force,
        threshold_force_ratio=ratio,
        swept_radius=radius,
        shimmy_frequency=omega,
        shimmy_frequency_hz=omega / (2 * np.pi),
        shimmy_amplitude=full_shimmy_amplitude(values["critical_speed"], t_eff, omega, cond.disturbance_angle),
        g_risk=g_risk,
        g_radius=g_radius,
        risk_ok=risk_ok,
        radius_ok=radius_ok,
        sill_ok=sill_ok,
        feasible=np.broadcast_to(risk_ok & radius_ok & sill_ok, shape),
    )


def _growth_rate(out: Casters, conditions: Conditions, speed: Any) -> np.ndarray:
    """μ of the oscillatory mode at ``speed`` [1/s] (Eq. 16B of the Eq. 12B coefficients; c_f as the hydraulic
    damping of Eq. 6 at the amplitude of Eq. 4), per caster."""
    t = np.atleast_1d(out.effective_trail)
    i_w, b, c, v = (
        np.broadcast_to(np.asarray(x, dtype=float), t.shape) for x in (out.inertia, out.groove, out.damping, speed)
    )
    c_d = friction_damping_at_speed(c, t, v)
    k_s = conditions.slip_coefficient
    return np.atleast_1d(growth_rate(third_order_coefficients(t, i_w, b, c_d, v, k_s, conditions.dynamics)))


def _risk(
    out: Casters,
    conditions: Conditions,
    speed: Any,
    law: Uncertainty,
    exact: bool,
    calibration: float,
    samples: int | None,
    seed: int | None,
    target_se: float | None,
) -> tuple[np.ndarray, np.ndarray]:
    """P(V_c,true < speed) and its SE per caster: Monte Carlo, or the exact law by quadrature (SE 0)."""
    speed = np.asarray(speed, dtype=float) / calibration
    args = (out.effective_trail, out.inertia, out.groove, out.damping, float(conditions.slip_coefficient), speed, law)
    if exact:
        p = shimmy_probability_exact_many(*args, diameter=out.diameter, measured=out.measured)
        return p, np.zeros_like(p)
    return shimmy_probability(
        *args, samples=samples, seed=seed, target_se=target_se, diameter=out.diameter, measured=out.measured
    )


def _constraints(confident: np.ndarray, radius: np.ndarray, required: Any, r_max: Any) -> tuple[np.ndarray, np.ndarray]:
    """g_risk = 1 − V_q/V_req and g_radius = R_s/R_max − 1 [-] (g <= 0 feasible); −inf for a limit not given."""
    g_risk = np.full(confident.shape, -np.inf) if required is None else 1 - confident / np.asarray(required, float)
    g_radius = np.full(radius.shape, -np.inf) if r_max is None else radius / np.asarray(r_max, dtype=float) - 1
    return np.asarray(g_risk, dtype=float), np.asarray(g_radius, dtype=float)


# --------------------------------------------------------------------------- the Monte Carlo risk


def shimmy_probability(
    trail: Any,
    inertia: Any,
    groove: Any,
    damping: Any,
    slip_coefficient: float,
    speed: Any,
    uncertainty: Uncertainty,
    samples: int | None = None,
    seed: int | None = None,
    target_se: float | None = MC_TARGET_SE,
    diameter: Any = None,
    measured: Any = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Monte Carlo P(V_c,true < speed) and its standard error for many casters at once [-].

    V_c,true is Eq. 7 with the constants drawn from the risk law
    (:func:`designer.physics.uncertainty.shimmy_probability_mc_many`: Student-t model error; the wheel's I_w
    scattered by Table 1's Student-t prediction at its ``diameter`` when it is not ``measured``, by the
    measurement's lognormal scatter when it is; lognormal c_f and K_s).  Each caster's estimate is the one of
    a single seeded stream (``seed``, default ``uncertainty.seed``): at least ``samples`` draws (default
    ``uncertainty.samples``, whole blocks of 10 000), more until the standard error is at most ``target_se``
    (None: never), so every estimate is the same number for a caster alone or in a batch.

    Parameters
    ----------
    trail, inertia, groove, damping : T [m], I_w [kg·m²], B [m], c_f [N·m/rad] of each caster (broadcast)
    slip_coefficient : K_s [N]
    speed : the speed [m/s] of each caster (broadcast)
    uncertainty : the risk law
    diameter : d [m] of each caster (broadcast); None: every wheel measured
    measured : whether each wheel was measured (broadcast; default: all measured without a diameter, none
        with one)

    Returns
    -------
    (p, se): arrays in the broadcast shape of the inputs.
    """
    given: dict[str, Any] = {k: v for k, v in (("diameter", diameter), ("measured", measured)) if v is not None}
    arrays = np.broadcast_arrays(*(np.asarray(x) for x in (trail, inertia, groove, damping, speed, *given.values())))
    shape = arrays[0].shape
    if not arrays[0].size:
        return np.zeros(shape), np.zeros(shape)
    t, i_w, b, c, v_req, *rest = (a.ravel() for a in arrays)
    law: dict[str, Any] = {"samples": samples, "seed": seed, "target_se": target_se, **dict(zip(given, rest))}
    p, se = shimmy_probability_mc_many(t, i_w, b, c, slip_coefficient, v_req, uncertainty, **law)
    return p.reshape(shape), se.reshape(shape)
