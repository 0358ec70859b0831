"""Build this caster: one safe, buildable recommendation, by a stated rule, with the front behind it.

1. **The stock** (:func:`stock_candidates`): every combination of the parts of ``[stock]`` (fork holes,
   wheels or diameters, groove profiles, friction washers); a variable the stock leaves out stays
   continuous within its bounds, a fixed variable (or a catalogue wheel) is one part.
2. **Deterministic screening** (:func:`designer.model.evaluate`): the risk bound
   V_q(x) >= (1 + margin) V_target, V_q the speed reached with probability 1 − α (V_c of Eq. 7 itself with
   ``[robust] enabled = false``), the swept radius T + d/2 <= R_max and the sill (d > 2h, Eq. 4A).  No random
   numbers: a tighter α can never make a caster look better.
3. **The buildable front**: all-discrete stock is evaluated exactly (vectorised); with continuous
   variables left, each stock combination's continuous rest is solved exactly (the NLP of
   :mod:`designer.studies.front._pareto`: one point when the diameter is stock, since then P is fixed; its
   sub-front otherwise).  The non-dominated set in (F_turn, P) is kept.
4. **The rule** (:func:`select_rows`, vectorised so ``designer fleet`` uses the same code): the knee of
   the buildable front (the point farthest from the chord between its ends, objectives normalised to
   the front's range, on the ideal side; with no knee (fewer than three points, or none bulging toward the
   ideal): the end with the least J = w_turn F + w_threshold P), or with
   ``[objective] max_threshold_force`` / ``max_turning_effort`` the best on the other objective within
   the cap.  Alternatives: every other caster of the buildable front, each with its role (the easiest to
   turn, the easiest over the sill, or between the ends).
5. **Reported risk**: P(shimmy at V_target) by a separate Monte Carlo of the same distribution with its
   own seed and SE <= 0.1 percentage point (the evaluator's, :func:`designer.model.shimmy_probability`).

Steps 1 and 2 live in :mod:`designer.studies.recommend._stock`, step 4 in
:mod:`designer.studies.recommend._rule` and the :class:`Recommendation` record in
:mod:`designer.studies.recommend._record` (re-exported here); this module holds step 3 (the buildable
candidates), the messages when nothing is buildable, and :func:`recommend`, which runs the five steps.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass

import numpy as np

from designer.boundary import SEED, Count, checked
from designer.units import percent
from designer.display import quantity, shown
from designer.errors import InfeasibleError, InputError
from designer.model import VARIABLES, Casters, Design, evaluate, scatter_of
from designer.physics.inertia import Fixed, PowerLaw
from designer.physics.uncertainty import Uncertainty, dominant_sentence, law_sources
from designer.problem import MAX_SAMPLES, Bound, problem_argument
from designer.solvers import one_solve_at_a_time
from designer.studies.recommend._record import Recommendation, _parts
from designer.physics.acceptance import exact_probabilities, exact_speed_quantile, exact_speed_quantiles, law_columns
from designer.studies.spec import (
    caster_specs,
    corner_probabilities,
    law_caster,
    mc_draws,
    risk_law,
)
from designer.studies.recommend._rule import front_roles, rule_text, select_rows, weights_meaning
from designer.studies.recommend._stock import ScreenedTable, candidate_table, stock_candidates

__all__ = ["SPECS", "Recommendation", "recommend", "with_spec"]


@dataclass
class _Buildable:
    """The buildable candidates before the rule (all feasible): the model's numbers of each and its wheel."""

    values: Casters
    wheel: np.ndarray

    def __len__(self) -> int:
        return len(self.values.turning_effort)

    def design(self, i: int) -> Design:
        """Candidate ``i`` as a :class:`Design`."""
        v = self.values
        return Design(float(v.trail[i]), float(v.diameter[i]), float(v.groove[i]), float(v.damping[i]))

    def brief(self, i: int, corner: float) -> dict:
        """Candidate ``i`` as plain data: its design [SI], wheel, F_turn and P [N], and its worst-corner P."""
        v = self.values
        return {
            "design": self.design(i).to_dict(),
            "wheel": str(self.wheel[i]) or None,
            "turning_effort": float(v.turning_effort[i]),
            "threshold_force": float(v.threshold_force[i]),
            "worst_corner_probability": corner,
        }

    def corners(self, problem, rows) -> list[float]:
        """The worst-corner P of candidates ``rows`` under ``problem``'s ``[tolerances]``
        (:func:`designer.studies.spec.corner_probabilities`)."""
        v = self.values
        rows = [int(i) for i in rows]
        return corner_probabilities(
            problem,
            [self.design(i) for i in rows],
            [float(v.inertia[i]) for i in rows],
            [bool(v.measured[i]) for i in rows],
        )


def _continuous_buildable(problem) -> _Buildable:
    """Each stock combination's continuous rest solved exactly (NLP), then pooled and evaluated by the model."""
    from designer.studies.front import pareto_front

    cand = stock_candidates(problem)
    rows = []
    for j in range(len(cand)):
        row = cand.design(j)
        # the problem with this combination's parts fixed (the rest continuous), a measured wheel's I_w fixed
        bounds = dict(problem.bounds) | {name: Bound(value, value) for name, value in row.items() if value is not None}
        conditions = problem.conditions
        if row["diameter"] is not None and cand.inertia is not None and cand.measured is not None and cand.measured[j]:
            conditions = conditions.replace(inertia=Fixed(float(cand.inertia[j])))
        sub = dataclasses.replace(problem, bounds=bounds, conditions=conditions, wheels=(), stock=None, source=None)
        points = 2 if row["diameter"] is not None else min(21, problem.pareto_points)
        try:
            with warnings.catch_warnings(action="ignore", category=UserWarning):
                front = pareto_front(sub, points=points)
        except InfeasibleError:
            continue
        measured = bool(getattr(sub.conditions.inertia, "measured", False))
        for pt in front:
            rows.append((pt.design, float(sub.conditions.inertia(pt.design.diameter)), cand.wheel[j], measured))
    values = evaluate(
        {name: np.array([getattr(r[0], name) for r in rows], float) for name in VARIABLES},
        problem.conditions,
        inertia=np.array([r[1] for r in rows], float),
        measured=np.array([r[3] for r in rows], bool),
    )
    return _Buildable(values, np.array([r[2] for r in rows], dtype=object))


def _infeasible_message(problem, table: ScreenedTable | None) -> str:
    """Exit-4 text: the closest stock combination and what to relax."""
    risk = problem.risk
    bound = (
        f"P(shimmy below {problem.required_speed:.3g} m/s) <= {risk.probability:g}"
        if risk is not None
        else f"V_c >= {problem.required_speed:.3g} m/s"
    )
    if table is None or not len(table.candidates):
        return (
            f"{problem.name}: no stock combination meets the risk bound {bound}; relax the stock "
            f"(more groove, stronger friction washers, longer fork holes), robust.probability or "
            f"shimmy.target_speed"
        )
    cand = table.candidates
    ratio = table.values.confident_speed / problem.required_speed
    pool = np.flatnonzero(table.values.radius_ok & np.isfinite(table.values.threshold_force))
    if not len(pool):
        j = int(np.argmin(table.values.swept_radius))
        return (
            f"{problem.name}: no stock combination fits the swept radius "
            f"{shown(problem.swept_radius_max, 'swept_radius', 'in')}; the smallest is "
            f"{shown(table.values.swept_radius[j], 'swept_radius', 'in')} (T + d/2); relax "
            f"constraints.swept_radius_max or stock smaller wheels or shorter fork holes"
        )
    j = int(pool[np.argmax(ratio[pool])])
    d = cand.design(j)
    relax = []
    if d["groove"] >= cand.groove.max() * (1 - 1e-12) and problem.bounds["groove"].high > 0:
        relax.append("a wider groove (stock.grooves)")
    if d["damping"] >= cand.damping.max() * (1 - 1e-12):
        relax.append("a stronger friction washer (stock.dampings)")
    if d["trail"] >= cand.trail.max() * (1 - 1e-12):
        relax.append(
            "a longer fork (variables.trail.max)"
            if problem.swept_radius_max is None or table.values.swept_radius[j] < problem.swept_radius_max * (1 - 1e-9)
            else "a larger swept radius (constraints.swept_radius_max)"
        )
    relax.append(
        "a smaller wheel (lighter: less inertia)" if d["diameter"] > cand.diameter.min() else "a lighter wheel"
    )
    relax.append(f"robust.probability (now {risk.probability:g})" if risk is not None else "shimmy.margin")
    relax.append("shimmy.target_speed")
    wheel = f" (wheel {cand.wheel[j]})" if cand.wheel[j] else ""
    return (
        f"{problem.name}: no stock combination meets the risk bound {bound}; the closest is "
        f"{_parts(d)}{wheel}, reaching {shown(table.values.confident_speed[j], 'confident_speed')} with probability "
        f"{percent(1 - (risk.probability if risk is not None else 0))} (needs {problem.required_speed:.3f}); relax: "
        + ", ".join(relax)
    )


def _records(
    problem, b: _Buildable, items: list[tuple[int, str]], rule: str, samples=None, seed=None, quantiles=None
) -> list[Recommendation]:
    """Candidates ``items`` ((row, role) each) as :class:`Recommendation` records, with their reported risk:
    P(shimmy at V_target) by the exact law (quadrature) under the problem's risk law (the default scatter when
    the bound is off, whose V_q it then reports too), the Monte Carlo beside it as an independent check (each
    estimate the caster's own alone: :func:`designer.physics.uncertainty.shimmy_probability_mc_many`), both
    for all rows in one batch; no spec (:func:`_with_specs` adds it).  ``quantiles``: each one's speed reached
    w.p. 1 − α when the caller found them in a batch (:func:`_quantiles`; None: found here, row by row)."""
    u = scatter_of(problem.conditions)
    v = b.values
    rows = [i for i, _ in items]
    designs = [b.design(i) for i in rows]
    risk = evaluate(
        designs,
        problem.conditions.replace(uncertainty=u),
        inertia=v.inertia[rows],
        measured=v.measured[rows],
        risk=problem.target_speed,
        samples=samples,
        seed=seed,
    )
    law = risk_law(problem)
    casters = [law_caster(problem, d, float(v.inertia[i]), bool(v.measured[i])) for d, i in zip(designs, rows)]
    exact = exact_probabilities(law_columns(casters), problem.target_speed, law)
    out = []
    for k, ((i, role), q) in enumerate(zip(items, quantiles or [None] * len(items))):
        p, p_mc, se = float(exact[k]), float(risk.shimmy_probability[k]), float(risk.shimmy_probability_se[k])
        extra = _risk(problem, v, i, u, p, (p_mc, se)) if role == "recommended" else {}
        # the speed reached with probability 1 − α: the exact law's quantile (the solvers' V_q is a conservative
        # bound, v.confident_speed under the problem's bound, risk.confident_speed under the default scatter)
        bound = float(v.confident_speed[i] if problem.risk is not None else risk.confident_speed[k])
        out.append(
            Recommendation(
                caster=v.row(i),
                confident_speed=float(q if q is not None else exact_speed_quantile(casters[k], law, guess=bound)),
                shimmy_probability=p,
                shimmy_probability_mc=p_mc,
                shimmy_probability_se=se,
                rule=rule,
                wheel=str(b.wheel[i]) or None,
                role=role,
                mc_samples=mc_draws(p_mc, se),  # the draws behind the estimate, as fixes and fleet rows state theirs
                mc_seed=int(u.seed if seed is None else seed),
                problem=problem,
                **extra,
            )
        )
    return out


def _quantiles(problem, b: _Buildable, rows: list[int]) -> list[float | None]:
    """The speed reached w.p. 1 − α of candidates ``rows`` under the problem's risk bound, all found together
    (:func:`designer.physics.acceptance.exact_speed_quantiles`, each from the solvers' V_q); None each when the
    problem has no bound (:func:`_records` then finds it under the default scatter, from that law's V_q)."""
    if problem.risk is None:
        return [None] * len(rows)
    v = b.values
    casters = [law_caster(problem, b.design(i), float(v.inertia[i]), bool(v.measured[i])) for i in rows]
    found = exact_speed_quantiles(casters, problem.risk, guesses=[float(v.confident_speed[i]) for i in rows])
    return [float(x) for x in found]


def with_spec(rec: Recommendation) -> Recommendation:
    """``rec`` with its spec (acceptance limits, worst corner), as :func:`recommend` gives it with ``specs="all"``
    or ``"recommended"``: for a recommendation computed with ``specs="none"`` (the studio draws the chart first
    and fills in the limits after).  Its alternatives are left as they are; ``rec`` itself when it has its spec
    already or is the "if measured" variant (which has none)."""
    if not isinstance(rec, Recommendation):
        raise InputError(f"rec = {rec!r:.80}: expected a designer.Recommendation (from designer.recommend)")
    return _with_specs([rec], [True])[0]


def _with_specs(records: list[Recommendation], wanted: list[bool]) -> list[Recommendation]:
    """The records, those ``wanted`` with their specs (as :func:`with_spec` gives each), the acceptance limits of
    all of them searched in one batch (:func:`designer.studies.spec.caster_specs`)."""
    todo = [r for r, w in zip(records, wanted) if w and r.spec is None and r.role != "if measured" and r.problem]
    if not todo:
        return records
    specs = caster_specs(
        [r.problem for r in todo],
        [r.design for r in todo],
        [r.inertia for r in todo],
        [r.measured for r in todo],
        [(r.shimmy_probability_mc, r.shimmy_probability_se, r.mc_samples, r.mc_seed) for r in todo],
        probability=[r.shimmy_probability for r in todo],
    )
    done = {id(r): spec for r, spec in zip(todo, specs)}
    return [dataclasses.replace(r, spec=done[id(r)]) if id(r) in done else r for r in records]


def _risk(problem, v: Casters, i: int, u: Uncertainty, p: float, mc: tuple[float, float]) -> dict:
    """The recommended caster's risk record: its exact P, the Monte Carlo P ± SE beside it, and the law's
    sources, each with its share of the variance of log V_c."""
    c = problem.conditions
    args = (float(v.trail[i]), float(v.inertia[i]), float(v.groove[i]), float(v.damping[i]), float(c.slip_coefficient))
    wheel = None if bool(v.measured[i]) else float(v.diameter[i])
    sources = law_sources(*args, u, diameter=wheel)
    return {
        "risk": {
            "probability": p,
            "monte_carlo": mc[0],
            "se": mc[1],
            "sources": sources,
            "dominant": dominant_sentence(sources),
        }
    }


def _buildable_front(problem, b: _Buildable, member: np.ndarray):
    """The buildable front as a :class:`designer.studies.front._pareto.Front` (decreasing P)."""
    from designer.studies.front import Front, FrontPoint, family_of

    idx = np.flatnonzero(member)
    idx = idx[np.argsort(-b.values.threshold_force[idx], kind="stable")]
    points = [
        FrontPoint(
            design=c.design,
            turning_effort=c.turning_effort,
            threshold_force=c.threshold_force,
            critical_speed=c.critical_speed,
            margins={"shimmy": c.confident_speed - problem.required_speed},
            epsilon=c.threshold_force,
            status="stock",
            success=True,
            family=family_of(problem, c.design),
            wheel=str(b.wheel[i]) or None,
            caster=c,
        )
        for i, c in zip(idx, (b.values.row(i) for i in idx))
    ]
    return Front(
        problem=problem,
        points=points,
        failed=[],
        meta={"method": "exhaustive over the stock; continuous rest solved exactly", "buildable": True},
    )


SPECS = ("all", "recommended", "none")
"""The values of :func:`recommend`'s ``specs``: which casters get their spec."""


# long: the docstring documents every argument and the result (the body is under 55 lines)
@checked(samples=Count(100, MAX_SAMPLES, optional=True, what="Monte Carlo draws"), seed=SEED)
@one_solve_at_a_time
def recommend(
    problem,
    samples: int | None = None,
    seed: int | None = None,
    *,
    front=None,
    specs: str = "all",
    if_measured: bool = True,
) -> Recommendation:
    """``designer.recommend``: the caster to build for ``problem``, by the problem's rule.

    Parameters
    ----------
    problem : a :class:`designer.problem.Problem` or a path to a problem file
    samples, seed : Monte Carlo sample (a minimum) and seed of the reported P(shimmy) (default the
        problem's ``[robust]`` ones: 50 000, seed 20111)
    front : the continuous risk-bounded front of ``problem`` when the caller has it (kept in
        ``Recommendation.front``; nothing here computes it)
    specs : which casters get their spec (acceptance limits and worst corner: about 0.1 s of CPU each, the
        quadratures of :func:`designer.physics.acceptance.acceptance_limits`): "all" (the default: the
        recommended caster and every alternative), "recommended" (the alternatives' ``spec`` None) or "none"
        (every ``spec`` None: the studio at each key press, which adds the recommended caster's afterwards with
        :func:`with_spec`, the same spec); every caster has its exact P(shimmy) whatever ``specs``
    if_measured : whether to find ``Recommendation.if_measured`` (the recommendation for wheels that will be
        measured: a second pass over the stock, about a third of the time at a key press); False leaves it None
        (the studio, which does not show it); nothing else changes

    Returns
    -------
    Recommendation (with every other caster of the buildable front as its alternatives, from the easiest to
    turn to the easiest over the sill, the buildable front and the continuous front it was given)

    Raises
    ------
    InfeasibleError (exit 4)
        No stock combination meets the risk bound (the message names the closest and what to relax),
        or none is within the cap of ``[objective]``.
    """

    if not isinstance(specs, str) or specs not in SPECS:
        raise InputError(f"specs={specs!r}: expected one of {', '.join(map(repr, SPECS))}")
    problem = problem_argument(problem)
    b = _buildable(problem)
    sel = _select(problem, b, np.ones(len(b), bool))
    enforced = None
    if problem.tolerances is not None and problem.tolerances.enforce:
        enforced = sel, _enforce(problem, b, int(sel["choice"][0]))
        sel = enforced[1]
    size = int(sel["front_size"][0])
    choice = int(sel["choice"][0])
    if choice < 0:
        if enforced is not None and int(enforced[0]["choice"][0]) >= 0:  # none holds at the worst corner
            corner = b.corners(problem, [int(enforced[0]["choice"][0])])[0]
            raise InfeasibleError(
                f"{problem.name}: no buildable caster holds P(shimmy) <= {risk_law(problem).probability:g} at the "
                f"worst corner of [tolerances] (the rule's pick without it reaches {corner:.2%} there); tighten "
                "tolerances, widen the stock or set tolerances.enforce = false"
            )
        # a buildable front exists but no point is within the cap of [objective]
        capped = "threshold_force" if problem.max_threshold_force is not None else "turning_effort"
        lo = int(sel["easiest_sill" if capped == "threshold_force" else "easiest_turn"][0])
        cap = f"objective.max_{capped} = {shown(getattr(problem, 'max_' + capped), capped)}"
        best = f"the least {quantity(capped).description} buildable is {shown(b.values[capped][lo], capped)}"
        raise InfeasibleError(
            f"{problem.name}: no buildable caster within the risk bound meets {cap}; {best}; "
            f"raise the cap or widen the stock"
        )
    rule = rule_text(problem, size, bool(sel["knee"][0]))
    items = [(choice, "recommended")] + [(i, r) for i, r in front_roles(b.values.turning_effort, sel) if i != choice]
    rec, *alts = _records(problem, b, items, rule, samples, seed, _quantiles(problem, b, [i for i, _ in items]))
    rec, *alts = _with_specs([rec, *alts], [specs != "none"] + [specs == "all"] * len(alts))
    return dataclasses.replace(
        rec,
        alternatives=alts,
        buildable=_buildable_front(problem, b, sel["front"][0]),
        front=front,
        note=_note(problem, rec, size),
        if_measured=_if_measured(problem, rec, samples, seed) if if_measured else None,
        enforced=None if enforced is None else _enforced(problem, b, rec, int(enforced[0]["choice"][0])),
    )


def _select(problem, b: _Buildable, ok: np.ndarray) -> dict:
    """The rule over the buildable candidates marked ``ok`` (:func:`select_rows`, one row)."""
    return select_rows(
        b.values.turning_effort[None, :],
        b.values.threshold_force[None, :],
        ok[None, :],
        problem.weights,
        problem.max_threshold_force,
        problem.max_turning_effort,
    )


def _enforce(problem, b: _Buildable, free: int) -> dict:
    """``[tolerances] enforce = true``: the rule among the casters that hold the bound at their worst corner.

    The rule's own pick ``free`` stays when it holds (enforcing a limit it meets changes nothing).  Else,
    lazily: the worst-corner P (exact law, :func:`designer.studies.spec.corner_probabilities`) of the current
    front's members only; the failing ones leave and the front is taken again, until every member holds.  A
    caster dominated by one that holds stays dominated, so the result is the front of all holding casters."""
    alpha = risk_law(problem).probability
    ok = np.ones(len(b), bool)
    if free >= 0 and b.corners(problem, [free])[0] <= alpha:
        return _select(problem, b, ok)
    corner = np.full(len(b), np.nan)
    while True:
        sel = _select(problem, b, ok)
        members = np.flatnonzero(sel["front"][0])
        todo = members[np.isnan(corner[members])]
        if not len(todo):
            return sel
        corner[todo] = b.corners(problem, todo)
        ok[todo] = corner[todo] <= alpha


def _enforced(problem, b: _Buildable, rec: Recommendation, free: int) -> dict:
    """What enforcing the worst corner changed: the caster the rule picks without it, its worst-corner P, and the
    cost of the enforced one in turning effort and sill force [N] (zero when the rule's pick already holds)."""
    v = b.values
    d = b.design(free)
    corner = b.corners(problem, [free])[0]
    return {
        "changed": bool(not np.allclose(d.as_array(), rec.design.as_array(), rtol=1e-12, atol=1e-15)),
        "unenforced": b.brief(free, corner),
        "costs_turning_effort": rec.turning_effort - float(v.turning_effort[free]),
        "costs_threshold_force": rec.threshold_force - float(v.threshold_force[free]),
        "price": _price(problem, b),
    }


PRICE_CHUNK = 8
"""Casters whose worst corner is computed at once while looking for the least-J one that holds."""


def _price(problem, b: _Buildable) -> dict:
    """The price of the tolerances apart from the rule's choice: the least-J buildable caster without them against
    the least-J one that holds the bound at its worst corner (J = w_turn F_turn + w_threshold P [N]); the casters
    are taken in order of J and their worst corners computed a few at a time until one holds."""
    v = b.values
    j = v.J(problem.weights)
    order = np.argsort(j, kind="stable")
    alpha = risk_law(problem).probability
    corner: dict[int, float] = {}
    hold = None
    for start in range(0, len(order), PRICE_CHUNK):
        chunk = [int(k) for k in order[start : start + PRICE_CHUNK]]
        corner.update(zip(chunk, b.corners(problem, chunk)))
        hold = next((k for k in chunk if corner[k] <= alpha), None)
        if hold is not None:
            break

    def brief(i: int | None) -> dict | None:
        return None if i is None else b.brief(i, corner[i]) | {"objective": float(j[i])}

    free = int(order[0])
    return {
        "least_objective_without_tolerances": brief(free),
        "least_objective_holding": brief(hold),
        "objective_price": None if hold is None else float(j[hold] - j[free]),
    }


def _if_measured(problem, rec: Recommendation, samples, seed) -> dict | None:
    """The recommendation for wheels that will be measured and accepted only up to their power-law value: every
    candidate evaluated as a measured wheel at exactly that value (the worst wheel accepted, with the
    measurement's scatter about it), chosen by the problem's own rule and never worse in J = w_F F + w_P P than
    ``rec``.  None when the inertia model is not the power law or every wheel is measured already."""
    model = problem.conditions.inertia
    if not isinstance(model, PowerLaw) or model.measured or problem.wheels:
        return None
    measured = problem.replace(conditions=problem.conditions.replace(inertia=dataclasses.replace(model, measured=True)))
    try:
        b = _buildable(measured)
    except InfeasibleError:
        return None
    sel = _select(measured, b, np.ones(len(b), bool))
    if measured.tolerances is not None and measured.tolerances.enforce:  # the worst corner decides here too
        sel = _enforce(measured, b, int(sel["choice"][0]))
    cost = b.values.J(problem.weights)
    j_rec = float(rec.caster.J(problem.weights))
    choice = int(sel["choice"][0])
    designs = np.column_stack([getattr(b.values, name) for name in VARIABLES])
    same = np.flatnonzero(np.all(np.isclose(designs, rec.design.as_array()[None, :], rtol=1e-12, atol=1e-15), axis=1))
    if (choice < 0 or cost[choice] > j_rec * (1 + 1e-12)) and len(same):
        choice = int(same[0])  # the rule's pick would cost more than the recommendation: keep the recommendation
    if choice < 0:
        return None
    (r,) = _records(measured, b, [(choice, "if measured")], rec.rule, samples, seed)
    return {
        "design": r.design.to_dict(),
        **{key: getattr(r, key) for key in ("turning_effort", "threshold_force", "shimmy_probability")},
        **{key: getattr(r, key) for key in ("shimmy_probability_se", "inertia", "extrapolated")},
        "saves_turning_effort": rec.turning_effort - r.turning_effort,
        "saves_threshold_force": rec.threshold_force - r.threshold_force,
    }


def _buildable(problem) -> _Buildable:
    """Step 3: the buildable candidates (exact for all-discrete stock, NLP for a continuous rest); raises
    InfeasibleError (the box's own diagnosis, else the closest stock combination) when there is none."""
    table = None
    if stock_candidates(problem).discrete:
        table = candidate_table(problem)
        b = _Buildable(table.values.take(table.values.feasible), table.candidates.wheel[table.values.feasible])
    else:
        b = _continuous_buildable(problem)
    if not len(b):
        from designer.studies.optimum import diagnose_infeasible

        error = diagnose_infeasible(problem)  # out of reach of the whole box: that is the message, not the stock's
        if isinstance(error, InfeasibleError):
            raise error
        raise InfeasibleError(_infeasible_message(problem, table))
    return b


def _note(problem, rec: Recommendation, size: int) -> str:
    """What to know about the recommendation: a short buildable front, or no risk bound."""
    notes = []
    if size < 3:
        notes.append(
            f"the buildable front has {size} point{'s' if size != 1 else ''}: "
            + (
                "the recommendation is the one with the least J (weights: "
                + weights_meaning(problem.weights)
                + ") and the only alternative the other end"
                if size == 2
                else "one stock caster is best on both objectives, so there is no alternative"
            )
        )
    if problem.risk is None:
        notes.append(
            f"no risk bound ([robust] enabled = false): this caster shimmies at {problem.target_speed:.3g} m/s "
            f"with probability {rec.shimmy_probability:.1%} ± {rec.shimmy_probability_se:.1%} under the "
            f"default scatter"
        )
    return "; ".join(notes)
