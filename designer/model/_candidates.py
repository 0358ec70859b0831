"""The one evaluator of candidate casters: a batch of designs and their conditions in, every number out.

:func:`evaluate_candidates` is where the studies get the performance and the risk of their candidates:
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
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from designer.parameters import VARIABLES
from designer.reprs import Record, dataframe, plain
from designer.physics.geometry import effective_trail, swept_radius
from designer.physics.scatter import inertia_prediction
from designer.physics.uncertainty import MC_TARGET_SE, Uncertainty, shimmy_probability_mc_many
from designer.model._caster import Conditions, Design, performance

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
    parameter table's order.
    """
    if isinstance(designs, Design):
        return {name: np.array([getattr(designs, name)], dtype=float) for name in VARIABLES}
    if isinstance(designs, Mapping):
        return {name: np.asarray(designs[name], dtype=float) for name in VARIABLES}
    if isinstance(designs, np.ndarray) and designs.dtype.names:
        return {name: np.asarray(designs[name], dtype=float) for name in VARIABLES}
    if isinstance(designs, Sequence) and designs and isinstance(designs[0], Design):
        return {name: np.array([getattr(d, name) for d in designs], dtype=float) for name in VARIABLES}
    array = np.asarray(designs, dtype=float).reshape(-1, len(VARIABLES))
    return {name: array[:, k] for k, name in enumerate(VARIABLES)}


@dataclass(frozen=True, kw_only=True)
class CandidateValues(Record):
    """Every number of a batch of candidate casters (arrays in the broadcast shape of the inputs), SI.

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
    threshold_force : P [N] (Eq. 4A); +inf where the wheel cannot climb the sill (d <= 2h)
    swept_radius : T + d/2 of the fork as built [m]
    risk_ok, radius_ok, sill_ok : each limit met (V_q >= V_req, R_s <= R_max within
        :data:`FEASIBILITY_TOLERANCE`; d > 2h); True where no limit was given
    feasible : all three
    shimmy_probability, shimmy_probability_se : Monte Carlo P(V_c,true < speed) and its standard error [-]
        (None unless asked for)
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
    threshold_force: np.ndarray
    swept_radius: np.ndarray
    risk_ok: np.ndarray
    radius_ok: np.ndarray
    sill_ok: np.ndarray
    feasible: np.ndarray
    shimmy_probability: np.ndarray | None = None
    shimmy_probability_se: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.feasible.shape[0]) if self.feasible.ndim else 1

    _units = {
        "trail": "m",
        "diameter": "m",
        "groove": "m",
        "damping": "N·m/rad",
        "inertia": "kg·m²",
        "effective_trail": "m",
        "critical_speed": "m/s",
        "confident_speed": "m/s",
        "turning_effort": "N",
        "threshold_force": "N",
        "swept_radius": "m",
    }

    def to_dict(self) -> dict[str, Any]:
        """``{field: list}`` per candidate (the Monte Carlo fields only when computed), plain data."""
        return {
            f.name: plain(np.asarray(getattr(self, f.name))) for f in fields(self) if getattr(self, f.name) is not None
        }

    def to_pandas(self) -> Any:
        """One row per candidate, one column per field (the Monte Carlo ones only when computed); units in
        ``df.attrs["units"]``."""
        columns = [f.name for f in fields(self) if getattr(self, f.name) is not None]
        n = len(self)
        arrays = {c: np.broadcast_to(np.asarray(getattr(self, c)), (n,)) for c in columns}
        rows = [{c: arrays[c][i].item() for c in columns} for i in range(n)]
        return dataframe(
            "CandidateValues.to_pandas", rows, columns, {c: u for c, u in self._units.items() if c in columns}
        )

    def _repr_lines(self) -> list[str]:
        """One line: how many candidates, how many feasible, and the ranges of F_turn and P."""
        f, p = np.atleast_1d(self.turning_effort), np.atleast_1d(self.threshold_force)
        return [
            f"CandidateValues({len(self)} candidates, {int(np.count_nonzero(self.feasible))} feasible; "
            f"F_turn {float(np.min(f)):.4g}–{float(np.max(f)):.4g} N, P {float(np.min(p)):.4g}–{float(np.max(p)):.4g} N)"
        ]

    def _html_title(self) -> str:
        return "Candidate casters"

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The count and the range of every field over the candidates (no Monte Carlo runs)."""
        rows: list[tuple[Any, Any, Any]] = [
            ("candidates (feasible)", f"{len(self)} ({int(np.count_nonzero(self.feasible))})", "")
        ]
        for f in fields(self):
            value = getattr(self, f.name)
            if value is None or np.asarray(value).dtype == bool:
                continue
            a = np.asarray(value, float)
            rows.append((f.name, f"{float(np.min(a)):.4g} – {float(np.max(a)):.4g}", self._units.get(f.name, "")))
        return rows

    def take(self, index: Any) -> "CandidateValues":
        """The candidates at ``index`` (a boolean mask or integer indices along the first axis)."""
        taken: dict[str, Any] = {
            f.name: None if getattr(self, f.name) is None else np.asarray(getattr(self, f.name))[index]
            for f in fields(self)
        }
        return CandidateValues(**taken)


def evaluate_candidates(  # long: the docstring documents every argument; the body is about 45 lines
    designs: Any,
    conditions: Conditions,
    *,
    inertia: Any = None,
    measured: Any = None,
    load: Any = None,
    threshold_height: Any = None,
    required_speed: Any = None,
    swept_radius_max: Any = None,
    stem_angle: float = 0.0,
    calibration: float = 1.0,
    probability_at: Any = None,
    scatter: Uncertainty | None = None,
    samples: int | None = None,
    seed: int | None = None,
    target_se: float | None = MC_TARGET_SE,
) -> CandidateValues:
    """Evaluate a batch of candidate casters: performance, risk bound, feasibility, and the risk on request.

    Parameters
    ----------
    designs : the candidates, by name (:func:`design_columns`): T, d, B [m], c_f [N·m/rad]
    conditions : the chair and the model (load L [N], sill h [m], surface, turning mode, θ0, K_s, the inertia
        model, the risk law ``uncertainty``: the bound when set, else the nominal V_c >= V_req)
    inertia : I_w per candidate [kg·m²] (a measured or catalogue wheel); None: ``conditions.inertia(d)``
    measured : whether each candidate's I_w was measured (True, False or one flag per candidate); default: the
        inertia model's own when ``inertia`` is None (catalogue and fixed wheels measured, the power law not),
        else True.  A wheel not measured is known by its diameter: the risk law then scatters its I_w by Table
        1's prediction interval at d (bound and Monte Carlo alike)
    load, threshold_height : per-candidate (broadcasting) load [N] and sill height [m] instead of the
        conditions' (a fleet's chairs)
    required_speed : V_req = (1 + margin) V_target [m/s] of the risk limit (None: no limit)
    swept_radius_max : R_max [m] (None: no limit)
    stem_angle : stem tilt φ [rad] from vertical; T is then the fork offset e and the tyre sees e + (d/2) sin φ
    calibration : factor k = V_obs / V_c,Eq.7 of a caster whose onset was observed (multiplies V_c in the bound
        and in the Monte Carlo)
    probability_at : speed [m/s] (one, or one per candidate) at which to estimate P(V_c,true < speed) by Monte
        Carlo (None: no Monte Carlo)
    scatter : the risk law of that estimate (default :func:`scatter_of` the conditions)
    samples, seed, target_se : the Monte Carlo's least sample, seed and target standard error
        (:func:`shimmy_probability`)

    Returns
    -------
    CandidateValues.  Equations: I_w (inertia model), Eq. 7 (V_c), ``shimmy_speed_quantile`` (V_q, the risk
    law), Eq. 4A (P), Eq. 9 (F_turn), T + d/2 (R_s); :func:`designer.model.performance` composes them.
    """
    columns = design_columns(designs)
    t, d, b, c = (columns[name] for name in VARIABLES)
    cond = conditions
    if load is not None:
        cond = cond.replace(load=np.asarray(load, dtype=float))
    if threshold_height is not None:
        cond = cond.replace(threshold_height=np.asarray(threshold_height, dtype=float))
    i_w = np.asarray(cond.inertia(d) if inertia is None else inertia, dtype=float) + 0 * d
    if measured is None:
        measured = bool(getattr(cond.inertia, "measured", False)) if inertia is None else True
    flags = np.broadcast_to(np.asarray(measured, dtype=bool), np.broadcast_shapes(np.shape(measured), i_w.shape))
    t_eff = t if stem_angle == 0 else np.asarray(effective_trail(t, d / 2, stem_angle), dtype=float)
    h = np.asarray(cond.threshold_height, dtype=float)
    sill_ok = d > 2 * h
    climbing = np.where(sill_ok, d, 3 * h)  # a wheel that cannot climb gets P = inf below, not Eq. 4A's error
    values = performance(t_eff, climbing, b, c, cond, inertia=i_w, measured=flags, wheel_diameter=d)
    confident = np.asarray(values["confident_speed"], dtype=float)
    if calibration != 1.0:
        confident = calibration * confident
    force = np.where(sill_ok, np.asarray(values["threshold_force"], dtype=float), np.inf)
    radius = np.asarray(swept_radius(t, d), dtype=float)
    risk_ok, radius_ok = _limits(confident, radius, required_speed, swept_radius_max)
    turning = np.asarray(values["turning_effort"], dtype=float)
    shape = np.broadcast_shapes(turning.shape, force.shape, risk_ok.shape, radius_ok.shape, sill_ok.shape)
    out = CandidateValues(
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
        threshold_force=force,
        swept_radius=radius,
        risk_ok=risk_ok,
        radius_ok=radius_ok,
        sill_ok=sill_ok,
        feasible=np.broadcast_to(risk_ok & radius_ok & sill_ok, shape),
    )
    if probability_at is None:
        return out
    p, se = shimmy_probability(
        t_eff,
        i_w,
        b,
        c,
        float(cond.slip_coefficient),
        np.asarray(probability_at, dtype=float) / calibration,
        scatter_of(cond) if scatter is None else scatter,
        samples=samples,
        seed=seed,
        target_se=target_se,
        diameter=d,
        measured=flags,
    )
    return replace(out, shimmy_probability=p, shimmy_probability_se=se)


def _limits(confident: np.ndarray, radius: np.ndarray, required: Any, r_max: Any) -> tuple[np.ndarray, np.ndarray]:
    """(V_q >= V_req, R_s <= R_max), each within :data:`FEASIBILITY_TOLERANCE`; all True for a limit not given."""
    risk_ok = np.ones(confident.shape, dtype=bool)
    if required is not None:
        risk_ok = confident >= np.asarray(required, dtype=float) * (1 - FEASIBILITY_TOLERANCE)
    radius_ok = np.ones(radius.shape, dtype=bool)
    if r_max is not None:
        radius_ok = radius <= np.asarray(r_max, dtype=float) * (1 + FEASIBILITY_TOLERANCE)
    return risk_ok, radius_ok


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
    columns = [trail, inertia, groove, damping, speed] + ([] if diameter is None else [diameter])
    if measured is not None:
        columns.append(measured)
    arrays = np.broadcast_arrays(*(np.asarray(x) for x in columns))
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    t, i_w, b, c, v_req = (np.asarray(a, dtype=float) for a in flat[:5])
    d = None if diameter is None else np.asarray(flat[5], dtype=float)
    flags = None if measured is None else np.asarray(flat[-1], dtype=bool)
    if not t.size:
        return np.zeros(shape), np.zeros(shape)
    p, se = shimmy_probability_mc_many(
        t,
        i_w,
        b,
        c,
        slip_coefficient,
        v_req,
        uncertainty,
        diameter=d,
        measured=flags,
        samples=samples,
        seed=seed,
        target_se=target_se,
    )
    return p.reshape(shape), se.reshape(shape)
