"""Retrofit: the cheapest safe change to the caster you have.

A clinician or wheelchair user does not design a caster from scratch; they ask
what to change on the one that shimmies.  :func:`fix` answers with numbers:

1. **Diagnosis** of the current caster: V_c (Eq. 7, on the effective trail of a
   tilted stem, :func:`designer.physics.geometry.effective_trail`), the speed
   it reaches with probability 1 − α, P(shimmy at V_target) by Monte Carlo
   with its standard error, turning effort and sill force.
2. **Calibration** (optional): an observed shimmy onset V_obs on this caster
   replaces the population model error.  The caster's own factor
   k = V_obs / V_c,Eq.7(current) multiplies Eq. 7 for every modified caster;
   the remaining scatter is the onset's own uncertainty (σ of its log,
   default 5 %, normal) together with the scatter of M_f/θ0, K_s and I_w of
   the risk bound (kept in full: conservative for the parts you keep, whose
   deviation is already inside V_obs).
3. **Fixes** ranked by the rule of :data:`RULE`: every candidate changes one or
   more of the four parts (washer = damping c_f, tyre = groove B, fork hole =
   trail T, wheel = diameter d with I_w from the inertia model, or a
   catalogue wheel) to values that exist (:func:`part_options`), meets the
   risk bound and the swept-radius limit.  Those that keep the sill force
   within ``[retrofit] max_threshold_increase`` and the turning effort within
   ``[retrofit] max_turning_increase`` of the current caster's are ranked
   cheapest first (the ``[stock]`` costs of the parts changed), then by the
   smallest loss in J; the others are listed apart, the smallest overshoot of
   either limit first.

Everything is deterministic except the reported P(shimmy), a Monte Carlo
estimate with its own seed (feasibility and ranking use the quantile).
``docs/retrofit.md`` has the derivations and the worked Eq. 8 example.

Modules: :mod:`designer.studies.retrofit._input` reads and checks the current caster;
:mod:`designer.studies.retrofit._diagnosis` computes the numbers of a caster and of every candidate (V_c,
the quantile, F_turn, P, the Monte Carlo, the calibration); :mod:`designer.studies.retrofit._options`
decides what each part can become and enumerates the combinations; :mod:`designer.studies.retrofit._records`
holds the records and the rule; this module ranks (:func:`fix`).
"""

from __future__ import annotations

import warnings
import dataclasses
from dataclasses import dataclass

from typing import Any

import numpy as np

from designer.boundary import SEED, Count, Instance, Quantity, checked
from designer.model import VARIABLES, Casters, Design, scatter_of
from designer.physics.uncertainty import Uncertainty
from designer.problem import MAX_SAMPLES, problem_argument
from designer.solvers import one_solve_at_a_time
from designer.studies.retrofit._diagnosis import _calibrated, _current_inertia, _evaluate
from designer.studies.retrofit._input import _check_inputs, parse_current
from designer.studies.retrofit._options import (
    PART_VARIABLE,
    PARTS,
    _enumerate,
    combinations,
    part_options,
)
from designer.studies.spec import caster_specs, mc_draws, tolerance_corners
from designer.studies.retrofit._records import (
    Calibration,
    CasterState,
    Change,
    FixResult,
)
from designer.display import quantity
from designer.units import written_size
from designer.model import weighted

ONSET_SCATTER = 0.05
"""σ of log V_obs [-]: a shimmy onset seen on a push or a ramp is known to about ±5 % (our estimate)."""

REPORT_SAMPLES = 50_000
"""Monte Carlo draws of the reported P(shimmy): SE <= 0.1 percentage point at 5 %."""

MAX_CANDIDATES = 200_000
"""Every combination of the four parts is searched when there are at most this many (a stock of a few values
per part gives about a thousand; 200 000 take about 0.5 s of CPU); beyond it (a continuous variable's grid)
one- and two-part fixes are searched, and three- and four-part ones only when none of those is within the
sill-force limit."""


@checked(
    current=Instance((Design, str), 'a designer.Design or "T=1.5in,d=7.75in,B=0.5625in,c=1.3"'),
    inertia=Quantity("inertia", optional=True),
    shimmied_at=Quantity("speed", optional=True),
    stem_angle=Quantity("angle"),
    onset_scatter=Quantity("dimensionless"),
    limit=Count(0, optional=True, what="fixes (None: every one)"),
    samples=Count(100, MAX_SAMPLES, optional=True, what="Monte Carlo draws"),
    seed=SEED,
    specs=Count(0, optional=True, what="fixes given a spec (None: every one)"),
)
@one_solve_at_a_time
def fix(  # long: its docstring documents every argument and the ranking rule
    problem,
    current,
    inertia: float | None = None,
    shimmied_at: float | None = None,
    stem_angle: float = 0.0,
    *,
    onset_scatter: float = ONSET_SCATTER,
    limit: int | None = None,
    samples: int | None = None,
    seed: int | None = None,
    specs: int | None = 10,
) -> FixResult:
    """Diagnose a caster that shimmies and rank the safe changes to it, cheapest first.

    Parameters
    ----------
    problem : Problem (or a path to a problem file): load, sill, V_target, the
        risk bound, bounds, the swept-radius limit and ``[stock]``
    current : Design (or ``"T=1.5in,d=7.75in,B=0.5625in,c=1.3"``) of the caster
        as it is; T is the fork offset (the trail with the stem vertical) [m]
    inertia : the current wheel's measured I_w [kg·m²]; default the problem's inertia model (then the wheel is
        known by its diameter, and ``if_measured`` gives the retrofit for the wheel measured at that value)
    shimmied_at : observed shimmy onset V_obs [m/s] of this caster; calibrates
        the model error (see :class:`Calibration`)
    stem_angle : stem tilt φ from vertical [rad], positive when its top leans
        back; the effective trail is e + (d/2) sin φ (:func:`effective_trail`)
    onset_scatter : σ of log V_obs [-] (default 0.05)
    limit : keep the first ``limit`` fixes (None: all found)
    specs : give the first ``specs`` fixes (and the first ``specs`` beyond the limits) their spec, the acceptance
        limits from the exact law (:func:`designer.studies.spec.caster_spec`: about 0.1 s of CPU a fix); None:
        every fix kept; 0: none (the studio's list)
    samples, seed : Monte Carlo of the reported P(shimmy) (default: the risk bound's, at least 50 000 draws
        and more until the SE is 0.1 percentage point; its own seed, never one that ranks)

    Returns
    -------
    FixResult with ``.current`` and the ranked ``.fixes`` (rule :data:`RULE`).

    Every combination of the parts on offer is searched (up to :data:`MAX_CANDIDATES`).  Feasibility is
    deterministic: the speed reached with probability 1 − α (the quantile of the risk bound, times k when
    calibrated) >= (1 + margin) V_target, and T + d/2 <= the swept-radius limit.  The fixes that raise the sill
    force by at most ``problem.max_threshold_increase`` and the turning effort by at most
    ``problem.max_turning_increase`` are ranked cheapest first, then by the smallest loss
    (``fixes``); the others are listed apart (``beyond``).  Equations: Eq. 7 (V_c), Eq. 4A (P), Eq. 9 (F_turn).
    """
    problem = problem_argument(problem)
    if isinstance(current, str):
        current = parse_current(current, "current")
    _check_inputs(problem, current, inertia, shimmied_at, stem_angle, onset_scatter)
    measured = True  # a given I_w is the current wheel's measurement
    if inertia is None:
        inertia, measured = _current_inertia(problem, current)
    inertia = float(inertia)
    # steps 1 and 2: the risk model every caster is judged with (the bound's law, None: nominal; the report's),
    # calibrated by an observed onset V_obs (factor k = V_obs / V_c,Eq.7), and the current caster's numbers under it
    bound, report_u = problem.risk, scatter_of(problem.conditions)
    base = current.to_dict() | {"inertia": inertia, "measured": bool(measured)}
    arrays = {k: np.array([v]) for k, v in base.items()}
    calibration, factor = None, 1.0
    if shimmied_at is not None:
        predicted = float(_evaluate(arrays, problem.conditions, stem_angle, 1.0, bound).critical_speed[0])
        factor = float(shimmied_at) / predicted
        calibration = Calibration(
            observed_onset=float(shimmied_at), predicted_onset=predicted, factor=factor, scatter=float(onset_scatter)
        )
        bound = None if bound is None else _calibrated(bound, onset_scatter)
        report_u = _calibrated(report_u, onset_scatter)
    draws = int(samples or max(REPORT_SAMPLES, report_u.samples))
    setting = _Setting(
        problem, stem_angle, factor, bound, report_u, draws, int(report_u.seed if seed is None else seed)
    )
    now = _evaluate(arrays, problem.conditions, stem_angle, factor, bound, setting.limits, setting.monte_carlo)
    current_state = setting.state(now, 0, current, inertia, exact=setting.exact(base))
    options, sources = part_options(problem, current)
    result = FixResult(  # the diagnosis, its fixes still empty: assumptions, scatter, what is on offer
        problem=problem.name,
        target_speed=problem.target_speed,
        required_speed=problem.required_speed,
        probability=None if bound is None else bound.probability,
        stem_angle=stem_angle,
        calibration=calibration,
        current=current_state,
        fixes=[],
        found=0,
        stock=stock_offer(problem, options, sources),
        scatter={
            "bound": None if bound is None else dataclasses.asdict(bound),
            "reported": dataclasses.asdict(report_u) | {"samples": setting.samples, "seed": setting.seed},
        },
        max_threshold_increase=problem.max_threshold_increase,
        max_turning_increase=problem.max_turning_increase,
        units=problem.units,
    )
    if not measured:  # what measuring the current wheel (accepted at its power-law value) would change
        result = dataclasses.replace(
            result,
            if_measured=_if_measured(problem, current, inertia, shimmied_at, stem_angle, onset_scatter, samples, seed),
        )
    if current_state.meets_risk_bound:
        return result
    cands, within, beyond, searched = _ranked(options, sources, base, setting, current_state)
    keep = slice(None) if limit is None else slice(limit)
    n_within, n_beyond = len(within[keep]), len(beyond[keep])
    wanted = np.concatenate([np.arange(n_within), np.arange(n_beyond)]) < (np.inf if specs is None else specs)
    # step 3: the kept fixes as records in rank order: their changes, their cost against the current caster,
    # P(shimmy) (the evaluator's batched Monte Carlo beside the exact law) and, where wanted, their spec
    chosen = np.concatenate([within[keep], beyond[keep]]).astype(int)
    picked = {key: value[chosen] for key, value in cands.items()}
    values = _evaluate(picked, problem.conditions, stem_angle, factor, bound, setting.limits, setting.monte_carlo)
    exact = setting.exact(picked)
    designs = [Design(*(float(cands[name][j]) for name in VARIABLES)) for j in chosen]
    found = setting.specs(values, designs, [float(cands["inertia"][j]) for j in chosen], exact, wanted)
    states = [
        setting.state(
            values,
            n,
            designs[n],
            float(cands["inertia"][j]),
            _changes(current, inertia, cands, j, options["wheel"]),
            price=float(cands["price"][j]),
            current=current_state,
            exact=exact[n : n + 1],
            spec=found[n],
        )
        for n, j in enumerate(chosen)
    ]
    return dataclasses.replace(  # records do not change: the ranked fixes make a new one
        result,
        searched=searched,
        found=len(within),
        found_beyond=len(beyond),
        fixes=states[: len(within[keep])],
        beyond=states[len(within[keep]) :],
    )


def _if_measured(
    problem, current: Design, inertia: float, shimmied_at, stem_angle: float, onset_scatter, samples, seed
) -> dict[str, object]:
    """The same retrofit for the current wheel measured at ``inertia`` [kg·m²] (its power-law value: the worst
    wheel of that size a measurement would accept), the measurement's scatter about it: {"inertia", "needs_fix",
    "current_shimmy_probability" (exact law), "current_shimmy_probability_mc" and "_se" (the Monte Carlo beside
    it), "fix" (the top fix or None), "summary"}."""
    alt = fix(
        problem,
        current,
        inertia,
        shimmied_at,
        stem_angle,
        onset_scatter=onset_scatter,
        limit=1,
        samples=samples,
        seed=seed,
    )
    return {
        "inertia": inertia,
        "needs_fix": alt.needs_fix,
        "current_shimmy_probability": alt.current.shimmy_probability,
        "current_shimmy_probability_mc": alt.current.shimmy_probability_mc,
        "current_shimmy_probability_se": alt.current.shimmy_probability_se,
        "fix": alt.fixes[0].to_dict() if alt.fixes else None,
        "summary": alt.summary(),
    }


def stock_offer(problem, options: dict, sources: dict) -> dict[str, str]:
    """What each part can become, in words: its values (sizes as the problem writes them), where they come from
    and what one costs ("c_f 2, 3 N·m/rad ([stock] dampings; 1 each)"); "none" for a part that cannot change."""
    units = problem.units
    out = {}
    for part in PARTS:
        values = options[part]
        costs = options["cost"][part]
        if len(values) == 0:
            out[part] = "none" + (f" ({sources[part]})" if sources[part].startswith("none") else "")
            continue
        if part == "wheel" and any(w.name for w in values):
            text = ", ".join(f"{w.name} ({written_size(w.diameter, units)})" for w in values)
        elif part == "washer":
            text = "c_f " + ", ".join(f"{v:g}" for v in values) + " N·m/rad"
        else:
            sizes = [written_size(float(getattr(v, "diameter", v)), units).rsplit(" ", 1) for v in values]
            text = f"{quantity(PART_VARIABLE[part]).symbol} " + ", ".join(x[0] for x in sizes) + f" {sizes[0][1]}"
        where = sources[part] if sources[part].startswith("continuous") else ""
        price = f"{costs[0]:g} each" if np.all(costs == costs[0]) else "costs " + ", ".join(f"{c:g}" for c in costs)
        out[part] = f"{text} ({where + '; ' if where else ''}{price})"
    return out


@dataclass(frozen=True)
class _Setting:
    """What every caster of one retrofit is judged with: the problem (its conditions, limits and the rule's numbers)
    and the risk model."""

    problem: Any
    stem_angle: float
    factor: float
    bound: Uncertainty | None
    report_u: Uncertainty
    samples: int
    seed: int

    def overshoot(self, turning_effort: Any, threshold_force: Any, current: CasterState) -> Any:
        """How far a caster's rises exceed the limits [-]: max(ΔP/P − the sill limit, ΔF/F − the turning limit),
        each relative to the current caster's force; <= 0 is within both limits (floats or arrays)."""
        rise_p = (threshold_force - current.threshold_force) / current.threshold_force
        rise_f = (turning_effort - current.turning_effort) / current.turning_effort
        return np.maximum(rise_p - self.problem.max_threshold_increase, rise_f - self.problem.max_turning_increase)

    @property
    def limits(self) -> tuple[float, float | None]:
        """(V_req [m/s], R_max [m] or None): the limits every caster must meet."""
        return self.problem.required_speed, self.problem.swept_radius_max

    @property
    def monte_carlo(self) -> tuple[float, Uncertainty, int, int]:
        """(V_target [m/s], scatter, samples, seed) of the reported P(shimmy)'s Monte Carlo."""
        return self.problem.target_speed, self.report_u, self.samples, self.seed

    def exact(self, arrays: dict) -> np.ndarray:
        """The reported P(shimmy at V_target) of candidates (arrays) by the exact law (quadrature) under the
        scatter of the report, on the effective trail, calibrated: the evaluator's ``exact=True``."""
        arrays = {k: np.atleast_1d(np.asarray(v)) for k, v in arrays.items()}
        values = _evaluate(
            arrays, self.problem.conditions, self.stem_angle, self.factor, self.bound, None, self.monte_carlo, True
        )
        return np.asarray(values.shimmy_probability, dtype=float)

    def specs(self, values: Casters, designs: list[Design], inertia: list[float], exact: Any, wanted: Any) -> list:
        """The specs of the fixes ``wanted`` (None for the others), their acceptance limits searched in one batch
        (:func:`designer.studies.spec.caster_specs`): caster k of ``values`` is ``designs[k]`` with wheel
        inertia ``inertia[k]`` [kg·m²] and exact P(shimmy) ``exact[k]``."""
        rows = [k for k in range(len(designs)) if wanted[k]]
        out: list = [None] * len(designs)
        p_mc, se = (np.asarray(values[key], float) for key in ("shimmy_probability", "shimmy_probability_se"))
        mc = [(float(p_mc[k]), float(se[k]), mc_draws(float(p_mc[k]), float(se[k])), self.seed) for k in rows]
        found = caster_specs(
            self.problem,
            [designs[k] for k in rows],
            [float(inertia[k]) for k in rows],
            [bool(values.measured[k]) for k in rows],
            mc,
            law=self.report_u,
            stem_angle=self.stem_angle,
            calibration=self.factor,
            probability=[float(np.asarray(exact).ravel()[k]) for k in rows],
        )
        for k, spec in zip(rows, found):
            out[k] = spec
        return out

    def state(
        self,
        values: Casters,
        j,
        design: Design,
        inertia: float,
        changes=(),
        price: float = 0.0,
        current: CasterState | None = None,
        exact: Any = None,
        spec: Any = None,
    ) -> CasterState:
        """Caster ``j`` of the evaluated ``values`` (with their Monte Carlo) as a :class:`CasterState`; ``price``
        the cost of its parts; ``current`` the caster as it is, which its changes, rises and limits are taken
        against (None: this is the current caster); ``exact`` its P(shimmy) by the exact law (an array of one).
        ``spec``: the fix's spec when it has one (:meth:`specs`)."""
        f, p = float(values.turning_effort[j]), float(values.threshold_force[j])
        base_f, base_p = (f, p) if current is None else (current.turning_effort, current.threshold_force)
        cost_turn, cost_threshold = f - base_f, p - base_p  # 0 for the current caster itself
        within = current is None or bool(self.overshoot(f, p, current) <= 1e-12)
        p_mc, se = float(values.shimmy_probability[j]), float(values.shimmy_probability_se[j])
        draws = mc_draws(p_mc, se)
        p_exact = float(np.asarray(exact).ravel()[0]) if exact is not None else p_mc
        return CasterState(
            caster=values.row(j),
            calibrated_critical_speed=float(self.factor * values.critical_speed[j]),
            shimmy_probability=p_exact,
            shimmy_probability_mc=p_mc,
            shimmy_probability_se=se,
            mc_samples=draws,
            mc_seed=self.seed,
            spec=spec,
            changes=tuple(changes),
            cost_turning_effort=cost_turn,
            cost_threshold_force=cost_threshold,
            loss=float(weighted(cost_turn, cost_threshold, self.problem.weights)),
            parts_cost=float(price),
            threshold_increase=cost_threshold / base_p,
            turning_increase=cost_turn / base_f,
            within_limit=within,
        )


def _ranked(options: dict, sources: dict, base: dict, setting: _Setting, current_state: CasterState):
    """The feasible fixes in the order of :data:`RULE`: (candidates, the ranked indices within the sill-force
    limit, the ranked indices beyond it, which combinations were searched)."""
    s = setting
    if combinations(options) <= MAX_CANDIDATES:
        cands = _enumerate(options, sources, base, max_parts=4)
        searched = "every combination of the four parts"
    else:
        cands = _enumerate(options, sources, base, max_parts=2)
        searched = (
            f"one- and two-part fixes ({combinations(options):,} combinations of all four parts exceed "
            f"{MAX_CANDIDATES:,}: a continuous part's grid)"
        )
    values = _evaluate(cands, s.problem.conditions, s.stem_angle, s.factor, s.bound, s.limits)
    over = s.overshoot(values.turning_effort, values.threshold_force, current_state)
    if searched.startswith("one-") and not np.any(values.feasible & (over <= 1e-12)):
        more = _enumerate(options, sources, base, max_parts=4, min_parts=3)
        if len(more["trail"]) <= MAX_CANDIDATES:
            more["order"] = more["order"] + len(cands["order"])
            cands = {key: np.concatenate([cands[key], more[key]]) for key in cands}
            values = _evaluate(cands, s.problem.conditions, s.stem_angle, s.factor, s.bound, s.limits)
            over = s.overshoot(values.turning_effort, values.threshold_force, current_state)
            searched = "one- and two-part fixes, then three- and four-part ones (none of the first within the limits)"
    d_turn = values.turning_effort - current_state.turning_effort
    d_force = values.threshold_force - current_state.threshold_force
    loss = np.round(weighted(d_turn, d_force, s.problem.weights), 9)
    price = np.round(cands["price"], 9)
    feasible = values.feasible
    if s.problem.tolerances is not None:  # only fixes that hold at the tolerances' worst corner
        # the bound's V_q at each corner against V_req, vectorised: a conservative bound of the exact law's
        # quantile, so a fix kept holds there by the exact law too; used to rank, never printed
        for corner in tolerance_corners(s.problem, cands):
            with warnings.catch_warnings(action="ignore", category=UserWarning):
                at = _evaluate(corner, s.problem.conditions, s.stem_angle, s.factor, s.bound, s.limits)
            feasible = feasible & np.asarray(at.risk_ok, bool)
    inside = np.flatnonzero(feasible & (over <= 1e-12))
    outside = np.flatnonzero(feasible & (over > 1e-12))
    keys = (cands["order"], -values.confident_speed, np.round(d_turn, 9), np.round(d_force, 9), loss, price)
    ranked = inside[np.lexsort([key[inside] for key in keys])]
    apart = outside[np.lexsort((cands["order"][outside], loss[outside], price[outside], np.round(over[outside], 9)))]
    return cands, ranked, apart, searched


def _changes(current: Design, inertia: float, cands: dict, j: int, wheels: list) -> tuple[Change, ...]:
    out = [
        Change(part=part, variable=name, before=getattr(current, name), after=float(cands[name][j]))
        for part, name in PART_VARIABLE.items()
        if part != "wheel" and cands[f"mask_{part}"][j]
    ]
    if cands["mask_wheel"][j]:
        name = wheels[int(cands["wheel"][j])].name
        out.append(
            Change(
                part="wheel", variable="diameter", before=current.diameter, after=float(cands["diameter"][j]), name=name
            )
        )
        if not cands["mask_tyre"][j] and abs(float(cands["groove"][j]) - current.groove) > 1e-12:
            out.append(Change(part="wheel", variable="groove", before=current.groove, after=float(cands["groove"][j])))
        if abs(float(cands["inertia"][j]) - inertia) > 1e-15:
            out.append(Change(part="wheel", variable="inertia", before=inertia, after=float(cands["inertia"][j])))
    return tuple(out)


__all__ = ["fix", "stock_offer", "MAX_CANDIDATES", "ONSET_SCATTER", "REPORT_SAMPLES"]
