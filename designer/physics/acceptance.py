"""Acceptance limits of a caster's parts and its risk at the worst corner of a tolerance box (exact law).

A factory builds each part with a spread; goods-in inspects each part against a limit.  For a caster
(T, I_w, B, c_f) and the risk law of :mod:`designer.physics.uncertainty`, the acceptance limit of a part
is the value at which, with every other part at its nominal value, the exact law gives
P(V_c,true < V_req) = α:

- trail T: the least (P falls as T grows, Eq. 7: V_c² = 4 c_f T²/(π I_w) + K_s B² T/(2 I_w));
- groove B: the least;
- bearing friction moment M_f = c_f θ0 [N·m]: the least (c_f = M_f/θ0, Eq. 7 with Eq. 11C's θ0);
- wheel inertia I_w: the largest measured one.

Each is a root of P(part) − α on the part's range (the parameter table's model range; the inertia in log I_w),
P by the exact law's Gauss–Hermite quadrature (:func:`~designer.physics.uncertainty.shimmy_probability_exact_many`).
When P stays at or below α over the whole side of the range the part has no limit there (None, with the reason).
:func:`acceptance_limits_many` finds every limit of many casters in one batch, row by row
(:func:`designer.physics.roots.bracketed_roots`); :func:`acceptance_limits` is the batch of one caster.

The worst corner (:func:`worst_corner`): each toleranced part at the edge of its tolerance where P is the
larger (others nominal), then all of them at once, the law's scatter on top: worst-case (arithmetic)
stacking, see docs/problem-file.md#tolerances.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from statistics import NormalDist
from dataclasses import dataclass
from typing import Any

import numpy as np

from designer.physics.roots import bracketed_roots
from designer.physics.scatter import InertiaPrediction
from designer.physics.shimmy import critical_shimmy_speed
from designer.physics.types import Array, Numeric
from designer.physics.uncertainty import (
    Uncertainty,
    _hermite_nodes,
    _linear_part,
    shimmy_probability_exact_many,
)

RISK_PARTS = ("trail", "groove", "damping")
"""The parts whose least acceptable value is a root of P = α (the inertia's largest is searched in log I_w)."""

EXACT_NODES = 16
"""Gauss–Hermite nodes per axis of :func:`measured_probabilities`' quadrature: P agrees with 32 nodes to 1e-15 on
the recommended casters of the shipped problems (tests/studies/test_spec.py), at a sixth of the work."""

LAW_NODES = 24
"""Gauss–Hermite nodes of the batched law's one quadrature axis (:func:`exact_probabilities`): P agrees with the
scalar 32 × 32 grid to about 3e-11 of itself on random casters (tests/physics/test_batched_law.py), where 16 nodes
leave 6e-11 and move a c_f limit by 3e-9, above :data:`LIMIT_RTOL`."""

LIMIT_RTOL = 1e-9
"""Relative tolerance of a limit's root [-]: far below any part's tolerance.  The root is sought on Φ⁻¹(P) −
Φ⁻¹(α), nearly straight in the part, so P at the limit is α to about 1e-10 (the shipped problems: 1e-10 at
worst) in about 13 quadratures a part (18 on P − α itself, whose step from 1 to 0 is steep)."""


@dataclass(frozen=True)
class LawCaster:
    """One caster as the risk law sees it (SI).

    Attributes
    ----------
    trail : T [m] (the trail the tyre sees)
    inertia : I_w [kg·m²]
    groove : B [m]
    damping : c_f [N·m/rad]
    slip_coefficient : K_s [N]
    diameter : d [m] of a wheel known by its diameter only (Table 1's prediction scatters I_w), None for a
        measured wheel (lognormal measurement scatter)
    """

    trail: float
    inertia: float
    groove: float
    damping: float
    slip_coefficient: float
    diameter: float | None = None

    def with_fields(self, changes: dict[str, float | None]) -> LawCaster:
        """The same caster with some fields set ({"trail": 0.05, "diameter": None, ...}) [SI]."""
        return dataclasses.replace(self, **changes)  # type: ignore[arg-type]

    def with_part(self, part: str, value: float) -> LawCaster:
        """The same caster with ``part`` ("trail", "groove", "damping") set to ``value`` [SI]."""
        return self.with_fields({part: value})


def exact_probability(
    caster: LawCaster, speed: float, uncertainty: Uncertainty, prediction: InertiaPrediction | None = None
) -> float:
    """P(V_c,true < speed) of ``caster`` under the exact law, by quadrature [-]: :func:`exact_probabilities` of one.

    The model error and the inertia's scatter by characteristic-function inversion, c_f and K_s through Eq. 7
    itself.  1 when Eq. 7's V_c is zero (no trail, or neither friction nor groove).
    """
    return float(exact_probabilities(law_columns([caster]), speed, uncertainty, prediction)[0])


@dataclass(frozen=True)
class PartLimit:
    """One part's acceptance limit (SI), or why it has none.

    Attributes
    ----------
    part : "trail", "groove", "damping" (c_f; the report states M_f = c_f θ0) or "inertia"
    side : "min" or "max"
    value : the limit [SI], or None when there is none inside the range
    probability : P(V_c,true < V_req) at the limit, others nominal [-] (α up to the root's tolerance);
        None for a geometric limit or no limit
    reason : what bounds it ("risk", "swept radius") or why there is no limit ("holds at the low end": P <= α
        over the whole range below nominal; "fails at the high end": no value in the range holds; "the problem
        has no swept-radius limit")
    """

    part: str
    side: str
    value: float | None
    probability: float | None
    reason: str


def least_part(
    caster: LawCaster,
    part: str,
    speed: float,
    uncertainty: Uncertainty,
    low: float,
    high: float,
    prediction: InertiaPrediction | None = None,
) -> PartLimit:
    """The least value of ``part`` (T [m], B [m] or c_f [N·m/rad]) at which P(V_c,true < speed) = α, the other
    parts at their nominal values; searched in the part's range [low, high] (P falls as the part grows: Eq. 7's
    V_c rises with T, B and c_f).

    None (with the reason) when P <= α already at ``low`` (no lower limit in the range) or P > α still at
    ``high`` (no value in the range holds).  :func:`acceptance_limits` with the other parts' ranges shut at their
    nominal values.
    """
    value = {name: getattr(caster, name) for name in RISK_PARTS}
    ranges = {name: (low, high) if name == part else (value[name], value[name]) for name in RISK_PARTS}
    limits = acceptance_limits(caster, speed, uncertainty, ranges, None, 0.0, prediction)
    return next(limit for limit in limits if (limit.part, limit.side) == (part, "min"))


def probit(probability: float) -> float:
    """Φ⁻¹(P) [-] of a probability, P held inside (1e-300, 1 − 1e-16) so that 0 and 1 keep their sign: the scale on
    which the limits' roots are sought (nearly straight in a part where P runs from 1 to 0 in a narrow step)."""
    return NormalDist().inv_cdf(min(max(probability, 1e-300), 1.0 - 1e-16))


def acceptance_limits(
    caster: LawCaster,
    speed: float,
    uncertainty: Uncertainty,
    ranges: dict[str, tuple[Numeric, Numeric]],
    swept_radius_max: float | None,
    wheel_diameter: float,
    prediction: InertiaPrediction | None = None,
) -> list[PartLimit]:
    """Every inspectable part's acceptance limit, each with the others at nominal [SI]: trail min, trail max,
    groove min, c_f min, I_w max (:func:`acceptance_limits_many` of one caster).

    Trail min, groove min and c_f min are the least values at which P = α (:func:`least_part`; ``ranges``: each
    part's model range); trail max = R_max − d/2 (the swept-radius limit T + d/2 <= R_max; none without it); I_w
    max the largest measured wheel inertia that holds (a measured wheel, measurement scatter about it).
    """
    return acceptance_limits_many([caster], speed, uncertainty, ranges, swept_radius_max, wheel_diameter, prediction)[0]


_LAW_FIELDS = ("trail", "inertia", "groove", "damping", "slip_coefficient")
"""The fields of :class:`LawCaster` that are numbers of every caster, in the law's order."""


def law_columns(casters: Sequence[LawCaster]) -> dict[str, Array]:
    """The casters' fields as arrays [SI], in the order of :class:`LawCaster` (a measured wheel's diameter nan)."""
    columns = {name: np.array([getattr(c, name) for c in casters], dtype=float) for name in _LAW_FIELDS}
    columns["diameter"] = np.array([np.nan if c.diameter is None else c.diameter for c in casters], dtype=float)
    return columns


def exact_probabilities(
    columns: dict[str, Array], speed: Numeric, uncertainty: Uncertainty, prediction: InertiaPrediction | None = None
) -> Array:
    """:func:`exact_probability` of many casters at once [-]: ``columns`` holds arrays of trail, inertia, groove,
    damping, slip_coefficient [SI] and diameter [m] (nan: a measured wheel), ``speed`` [m/s] broadcasts.

    :func:`designer.physics.uncertainty.shimmy_probability_exact_many` with :data:`LAW_NODES` nodes on its one
    quadrature axis.
    """
    c = columns
    return shimmy_probability_exact_many(
        c["trail"],
        c["inertia"],
        c["groove"],
        c["damping"],
        c["slip_coefficient"],
        speed,
        uncertainty,
        diameter=c["diameter"],
        prediction=prediction,
        nodes=LAW_NODES,
    )


def probits(probability: Array) -> Array:
    """:func:`probit` of each probability [-] (statistics.NormalDist: no scipy import)."""
    return np.array([probit(float(p)) for p in np.ravel(probability)]).reshape(np.shape(probability))


def _limit_search(
    columns: dict[str, Array],
    speed: Array,
    uncertainty: Uncertainty,
    ranges: dict[str, tuple[Numeric, Numeric]],
    prediction: InertiaPrediction | None = None,
) -> tuple[Array, Array, Array, Array]:
    """Every risk limit of many casters in one root search: the least T [m], B [m] and c_f [N·m/rad] at which
    P(V_c,true < speed) = α, the others nominal (:func:`least_part`), and the largest measured I_w, as one block
    of rows each.

    Each row is a root of Φ⁻¹(P) − Φ⁻¹(α) by :func:`bracketed_roots` (the scalar searches' Illinois steps, row
    by row) and every step's quadratures of all rows are one call of :func:`exact_probabilities`: T, B, c_f in
    their ``ranges`` ([low, high], numbers or one per caster) to :data:`LIMIT_RTOL`; I_w measured (lognormal
    scatter about it) in log I_w between the I_w at which Eq. 7's V_c equals the speed (V_c ∝ I_w^−1/2) and
    e^−12 of it, to 1e-11.

    Returns (values [SI], P at them [-], excess at the low end, excess at the high end), each parts × casters; a
    T, B or c_f row without a sign change in its range is nan (excess at the low end <= 0: it holds there;
    else it fails at the high end).
    """
    n = columns["trail"].size
    m = len(RISK_PARTS) + 1  # a block of rows per risk part, then the inertia's (in log I_w)
    kind = np.repeat(np.arange(m), n)
    cols = {key: np.tile(value, m) for key, value in columns.items()}
    is_inertia = kind == m - 1
    cols["inertia"] = np.where(is_inertia, 1.0, cols["inertia"])
    cols["diameter"] = np.where(is_inertia, np.nan, cols["diameter"])
    v = np.tile(speed, m)
    c = columns
    v_unit = critical_shimmy_speed(c["trail"], 1.0, c["groove"], c["damping"], c["slip_coefficient"])
    top = 2 * np.log(v_unit / speed)  # the log I_w whose V_c is the speed
    ends = [np.broadcast_to(np.asarray(x, dtype=float), (n,)) for part in RISK_PARTS for x in ranges[part]]
    low = np.concatenate([*ends[0::2], top - 12.0])
    high = np.concatenate([*ends[1::2], top])
    xtol = np.where(is_inertia, 1e-11, 1e-15 * np.maximum(np.abs(high), 1e-12))
    rtol = np.where(is_inertia, 0.0, LIMIT_RTOL)
    target = probit(float(uncertainty.probability))

    def probability(x: Array, rows: Any) -> Array:
        sub = {key: value[rows] for key, value in cols.items()}
        here = kind[rows]
        for k, part in enumerate(RISK_PARTS):
            sub[part] = np.where(here == k, x, sub[part])
        sub["inertia"] = np.where(here == m - 1, np.exp(np.where(here == m - 1, x, 0.0)), sub["inertia"])
        return exact_probabilities(sub, v[rows], uncertainty, prediction)

    def excess(x: Array, rows: Any) -> Array:
        return probits(probability(x, rows)) - target

    every = np.arange(m * n)
    at_low, at_high = excess(low, every), excess(high, every)
    found = ((at_low > 0) & (at_high <= 0)) | is_inertia
    rows = np.flatnonzero(found)
    values = np.full(m * n, np.nan)
    p = np.full(m * n, np.nan)

    def on_rows(x: Array, sub: Any) -> Array:
        return excess(x, rows[sub])

    roots = bracketed_roots(on_rows, low[rows], high[rows], xtol[rows], rtol[rows], fa=at_low[rows], fb=at_high[rows])
    values[rows] = roots
    p[rows] = probability(roots, rows)
    values[is_inertia] = np.exp(values[is_inertia])
    shape = (m, n)
    return values.reshape(shape), p.reshape(shape), at_low.reshape(shape), at_high.reshape(shape)


def acceptance_limits_many(
    casters: Sequence[LawCaster],
    speed: Numeric,
    uncertainty: Uncertainty,
    ranges: dict[str, tuple[Numeric, Numeric]],
    swept_radius_max: float | None | Sequence[float | None],
    wheel_diameter: Numeric,
    prediction: InertiaPrediction | None = None,
) -> list[list[PartLimit]]:
    """:func:`acceptance_limits` of many casters at once: one list of :class:`PartLimit` per caster, in the same
    order (trail min, trail max, groove min, c_f min, I_w max) [SI].

    ``speed`` [m/s], ``wheel_diameter`` d [m] (the swept-radius limit's) and each range's ends broadcast with the
    casters; ``swept_radius_max`` R_max [m] is one for all or one per caster (None: no limit).  Every part's
    root search of every caster runs in one batch (:func:`_limit_search`): the same limits as one caster at a
    time, to the root's tolerance.
    """
    n = len(casters)
    if not n:
        return []
    columns = law_columns(casters)
    v = np.broadcast_to(np.asarray(speed, dtype=float), (n,)).copy()
    d = np.broadcast_to(np.asarray(wheel_diameter, dtype=float), (n,))
    values, p, at_low, _ = _limit_search(columns, v, uncertainty, ranges, prediction)
    radius = list(swept_radius_max) if isinstance(swept_radius_max, Sequence) else [swept_radius_max] * n
    out = []
    for i in range(n):
        least = []
        for k, part in enumerate(RISK_PARTS):
            if np.isnan(values[k, i]):
                reason = "holds at the low end" if at_low[k, i] <= 0 else "fails at the high end"
                least.append(PartLimit(part, "min", None, None, reason))
            else:
                least.append(PartLimit(part, "min", float(values[k, i]), float(p[k, i]), "risk"))
        r_max = radius[i]
        if r_max is None:
            trail_max = PartLimit("trail", "max", None, None, "the problem has no swept-radius limit")
        else:
            trail_max = PartLimit("trail", "max", r_max - float(d[i]) / 2, None, "swept radius")
        inertia = PartLimit("inertia", "max", float(values[-1, i]), float(p[-1, i]), "risk")
        out.append([least[0], trail_max, least[1], least[2], inertia])
    return out


@dataclass(frozen=True)
class Corner:
    """The worst corner of a tolerance box.

    Attributes
    ----------
    edges : {part: the worst edge's value [SI]} (the parts given a tolerance)
    caster : the caster with every part at its worst edge at once
    probability : P(V_c,true < V_req) there, the law's scatter on top [-]
    nominal_probability : P at nominal [-]
    alpha : the bound α [-]
    """

    edges: dict[str, float]
    caster: LawCaster
    probability: float
    nominal_probability: float
    alpha: float

    @property
    def holds(self) -> bool:
        """P at the worst corner is at most α."""
        return self.probability <= self.alpha


Edge = tuple[float, dict[str, float | None]]
"""One edge of a part's tolerance: (the part's value there [SI], the LawCaster fields it sets)."""


def worst_corner(
    nominal: LawCaster,
    edges: dict[str, tuple[Edge, Edge]],
    speed: float,
    uncertainty: Uncertainty,
    prediction: InertiaPrediction | None = None,
) -> Corner:
    """P(V_c,true < speed) with every toleranced part at its worst edge at once (worst-case stacking) [-].

    ``edges``: {part: (low edge, high edge)}, each edge the part's value and the fields of the caster it sets
    (the diameter may move the wheel's inertia too; a measured wheel's limit sets I_w and makes it measured).
    The worst edge of a part is the one with the larger P, the others at nominal; the corner sets every worst
    edge together, and P there is the exact law's.
    """
    chosen: dict[str, float] = {}
    changes: dict[str, float | None] = {}
    for part, (low, high) in edges.items():
        p_low = exact_probability(nominal.with_fields(low[1]), speed, uncertainty, prediction)
        p_high = exact_probability(nominal.with_fields(high[1]), speed, uncertainty, prediction)
        value, fields = low if p_low >= p_high else high
        chosen[part] = value
        changes.update(fields)
    corner = nominal.with_fields(changes)
    return Corner(
        edges=chosen,
        caster=corner,
        probability=exact_probability(corner, speed, uncertainty, prediction),
        nominal_probability=exact_probability(nominal, speed, uncertainty, prediction),
        alpha=float(uncertainty.probability),
    )


def friction_moment(damping: float, disturbance_angle: float) -> float:
    """The bearing friction moment M_f = c_f θ0 [N·m] of a spindle damping c_f [N·m/rad] (Eq. 7, Eq. 11C)."""
    return damping * disturbance_angle


def exact_speed_quantiles(
    casters: list[LawCaster],
    uncertainty: Uncertainty,
    prediction: InertiaPrediction | None = None,
    guesses: list[float | None] | None = None,
) -> Array:
    """The speed reached with probability 1 − α of each caster: the V_q at which the exact law gives
    P(V_c,true < V_q) = α [m/s], all casters searched together.

    The exact law's α-quantile of V_c,true (:func:`~designer.physics.uncertainty.shimmy_probability_exact_many`,
    the batched quadrature, equal to the one-caster law to about 1e-12), found by
    :func:`designer.physics.roots.bracketed_roots` on Φ⁻¹(P) − Φ⁻¹(α) in log V (to 1e-10 in log V), each bracket
    grown from its ``guesses`` entry (the risk bound's V_q, which lies just below the quantile: 4–6 quadratures)
    or from Eq. 7's V_c until it holds the root.  Not the risk bound's V_q of
    :func:`~designer.physics.uncertainty.shimmy_speed_quantile`, which is a conservative bound (first order in c_f
    and K_s, its fit shifted up): the solvers constrain that one; this one is the number the tool prints as "speed
    reached with probability 1 − α".  0 where Eq. 7's V_c is zero.
    """
    n = len(casters)
    columns = law_columns(casters)
    live = np.flatnonzero((columns["trail"] > 0) & ((columns["damping"] > 0) | (columns["groove"] > 0)))
    out = np.zeros(n)
    if not live.size:
        return out
    target = probit(float(uncertainty.probability))

    def excess(log_v: Array, rows: Any) -> Array:
        sub = {key: value[live[rows]] for key, value in columns.items()}
        return probits(exact_probabilities(sub, np.exp(log_v), uncertainty, prediction)) - target

    every = np.arange(live.size)
    guess = np.array([np.nan if g is None or not g > 0 else g for g in (guesses or [None] * n)], dtype=float)[live]
    v_c = np.asarray(critical_shimmy_speed(*(columns[key][live] for key in _LAW_FIELDS)), dtype=float)
    given = np.isfinite(guess)
    lo = np.where(given, np.log(np.where(given, guess, 1.0)) - 0.002, np.log(v_c) - 1.0)
    hi = np.where(given, np.log(np.where(given, guess, 1.0)) + 0.01, np.log(v_c))
    step = np.where(given, 0.05, 1.0)
    f_lo, f_hi = excess(lo, every), excess(hi, every)
    # P rises with V: lower lo until P < α (the step doubling), then raise hi until P > α
    for end, f_end, sign in ((lo, f_lo, -1.0), (hi, f_hi, 1.0)):
        for _ in range(60):
            if not (bad := np.flatnonzero(sign * f_end <= 0)).size:
                break
            end[bad], step[bad] = end[bad] + sign * step[bad], 2 * step[bad]
            f_end[bad] = excess(end[bad], bad)
    out[live] = np.exp(bracketed_roots(excess, lo, hi, xtol=1e-10, rtol=0.0, fa=f_lo, fb=f_hi))
    return out


def exact_speed_quantile(
    caster: LawCaster,
    uncertainty: Uncertainty,
    prediction: InertiaPrediction | None = None,
    guess: float | None = None,
) -> float:
    """The speed reached with probability 1 − α of one caster [m/s]: :func:`exact_speed_quantiles` of one."""
    return float(exact_speed_quantiles([caster], uncertainty, prediction, [guess])[0])


def measured_probabilities(
    trail: Numeric,
    inertia: Numeric,
    groove: Numeric,
    damping: Numeric,
    slip_coefficient: float,
    speed: Numeric,
    uncertainty: Uncertainty,
) -> Array:
    """P(V_c,true < speed) of many casters with measured wheels by the exact law [-] (arrays, the speed [m/s]
    included, broadcast together).

    The same law as :func:`designer.physics.uncertainty.shimmy_probability_exact` with ``diameter=None`` and
    :data:`EXACT_NODES` Gauss–Hermite nodes a side, in one array call: the linear
    part (model error, σ_I/2 of the measured inertia) is the same distribution for every caster (log V_c's slope
    in log I_w is −1/2 whatever B, Eq. 7), so P = Σ w F(log v − log V_c(nodes)) over a (casters × nodes) grid.
    A caster without trail, or without both friction and groove (V_c = 0), gets 1.
    """
    t, i, b, c, s = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (trail, inertia, groove, damping, speed)))
    u = uncertainty
    zn, zw = _hermite_nodes(EXACT_NODES)
    a_, b_ = np.meshgrid(zn, zn, indexing="ij")
    zc, zk, w = a_.ravel(), b_.ravel(), np.outer(zw, zw).ravel()
    dead = (t <= 0) | ((c <= 0) & (b <= 0))
    safe = [np.where(dead, 1.0, x)[..., None] for x in (t, i, b, c)]
    v = critical_shimmy_speed(
        safe[0], safe[1], safe[2], safe[3] * np.exp(u.damping * zc), slip_coefficient * np.exp(u.slip_coefficient * zk)
    )
    gap = np.log(s[..., None]) - np.log(v)
    p = np.sum(w * measured_linear_cdf(gap, slip_coefficient, u), axis=-1)
    return np.where(dead, 1.0, p)


CHUNK = 8192
"""Points of :func:`measured_linear_cdf` per block (× its nodes, about 0.7 MB of doubles a temporary; an eighth
of it where the law takes the inversion, whose 512 nodes make 4 MB): memory does not grow with the batch."""

LINEAR_NODES = 10
"""Gauss–Hermite nodes over the measured inertia's normal part in :func:`measured_linear_cdf` (10 agree
with the characteristic-function inversion to its own precision, 7e-13, on the data law)."""


def measured_linear_cdf(x: Array, slip_coefficient: float, uncertainty: Uncertainty) -> Array:
    """CDF of the exact law's linear part for a measured wheel, X = σ_m t_ν + (σ_I/2) Z, at ``x`` [-].

    For an odd ν (the data law's 5) by Gauss–Hermite over Z with the Student-t CDF in closed form
    (F = 1/2 + (θ + sin θ Σ_k a_k cos^{2k+1} θ)/π, θ = atan(r), r = t/√ν, written with q = cos²θ = 1/(1 + r²) and
    sin θ cos^{2k+1} θ = r q^{k+1} so that atan is the one transcendental call): the same distribution as
    :class:`~designer.physics._sums.SumDistribution`'s inversion (which it matches to 7e-13, that inversion's own
    precision) at a twentieth of the work; any other law falls back to the inversion."""
    u = uncertainty
    a, dof, c = float(u.model_error), int(u.model_error_dof), 0.5 * float(u.inertia)
    flat, out = np.ravel(x), np.empty(np.size(x))
    if not (a > 0 and dof % 2 == 1):  # the inversion, a (points × its nodes) array a block
        dist = _linear_part(1.0, 1.0, 0.0, 1.0, slip_coefficient, u, None, None)
        for start in range(0, flat.size, CHUNK // 8):
            out[start : start + CHUNK // 8] = np.asarray(dist.cdf(flat[None, start : start + CHUNK // 8]))[0]
        return out.reshape(np.shape(x))
    nodes = LINEAR_NODES if dof >= 3 else 2 * LINEAR_NODES  # a Cauchy's (ν = 1) heavy tails take more
    zn, zw = _hermite_nodes(nodes) if c > 0 else (np.zeros(1), np.ones(1))
    for start in range(0, flat.size, CHUNK):  # blocks that stay in cache: no page faults for a fleet's corners
        # r held finite (±1e150: F is 0 or 1 to the last bit there) so that r q is not ∞ · 0 at x = ±∞
        r = np.clip((flat[start : start + CHUNK, None] - c * zn) / (a * math.sqrt(dof)), -1e150, 1e150)
        q = 1.0 / (1.0 + r * r)
        term, total = q, q
        for k in range(1, (dof - 1) // 2):
            term = term * q * ((2 * k) / (2 * k + 1))
            total = total + term
        cdf = 0.5 + (np.arctan(r) + (r * total if dof > 1 else 0.0)) / math.pi
        out[start : start + CHUNK] = np.sum(zw * cdf, axis=-1)
    return out.reshape(np.shape(x))
