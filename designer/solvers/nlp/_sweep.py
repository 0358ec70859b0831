"""How the NLP solves the ε-points of a front: two sweep strategies behind one interface.

A strategy is made for one continuous problem and its NLP (``strategy = Kind(nlp, problem)``) and answers
two questions, both with results of the NLP (:class:`designer.solvers.nlp.NLPResult`), which is the
authority on every point:

- :meth:`NLPSweep.ends`: the two lexicographic ends (min F_turn then min P; min P then min F_turn);
- :meth:`NLPSweep.sweep`: the optimum min F_turn s.t. P <= ε at every interior ε of a grid.

:class:`NLPSweep` solves from starts: the best designs of a Sobol sample of the box, then family restarts
(grooved, damped) and warm propagation between neighbours until no start improves (:class:`_Sweep`).

:class:`StructuredSweep` starts from the closed-form ε-optima of :mod:`designer.solvers.closed_form`
(nominal and risk-bounded problems alike, wherever :func:`~designer.solvers.closed_form.applicable` holds)
and confirms them with one warm batched NLP solve; a point the closed form has no optimum for, whose solve
fails, or whose NLP optimum is worse than the closed form's by more than 1e-9 (relative) goes through the
:class:`NLPSweep` machinery.  The family restarts are not needed otherwise: the closed form compares every
end of the constraint curve at every ε.

Nothing here changes the NLP object it is given (the problem's values are the NLP's own).  The solver protocol's
``front_designs`` of :class:`~designer.solvers.nlp.NLPSolver` runs these sweeps.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

from designer.model import Design, turning_effort
from designer.problem import Problem, family_of
from designer.solvers.base import design_rows
from designer.solvers.closed_form import structured_ends, structured_front_designs
from designer.solvers.nlp._casadi import BIG, CasterNLP, NLPResult, best_starts, sample_designs

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

CACHE_SIZE = 32
"""How many problems' samples are kept (the compiled NLPs: :data:`designer.solvers.nlp._cache.SHARED_SIZE`)."""


@dataclass
class Ends:
    """The lexicographic ends of one problem's front (None: not found) and what finding them cost."""

    a: NLPResult | None
    b: NLPResult | None
    solves: int
    statuses: tuple[str, ...] = ()
    """IPOPT statuses of the failed end solves when no end was found (for the error message)."""


def _found(ends: Ends) -> tuple[NLPResult, NLPResult]:
    """Both ends of a sweep; ValueError when they were not found (the caller sweeps only a front with ends)."""
    if ends.a is None or ends.b is None:
        raise ValueError(f"no sweep without the front's ends ({', '.join(ends.statuses) or 'not found'})")
    return ends.a, ends.b


def _family_starts(problem: Problem, design: Design) -> list[np.ndarray]:
    """The previous design moved to each competing family (grooved / damped)."""
    lo, hi = problem.lower(), problem.upper()
    grooved = dataclasses.replace(design, groove=hi.groove, damping=lo.damping)
    damped = dataclasses.replace(design, groove=lo.groove, damping=hi.damping)
    return [grooved.as_array(), damped.as_array()]


Sample: TypeAlias = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[np.ndarray], list[np.ndarray]]
"""A box sample: designs (N, 4), their F_turn, P and violation, and the two ends' best starts."""

Guide: TypeAlias = "tuple[npt.ArrayLike, Sequence[NLPResult]]"
"""An earlier pass of a sweep: its ε and its results."""

_SAMPLE_CACHE: dict[str, Sample] = {}


def box_sample(problem: Problem, n: int = 1024) -> Sample:
    """A vectorised look at the box: Sobol designs, their F_turn, P and constraint violation (one model call).

    Also the starts of the two lexicographic ends (:func:`best_starts` on the same designs).  Kept per
    problem data (bounds, conditions, V_req, R_max; the last :data:`CACHE_SIZE`): it is the same every
    call.  The arrays are read-only.
    """
    key = repr((n, problem.bounds, problem.conditions, problem.required_speed, problem.swept_radius_max))
    entry = _SAMPLE_CACHE.pop(key, None)
    if entry is None:
        x = sample_designs(problem, n, seed=0)
        values = problem.evaluate(x)
        entry = (
            x,
            values.turning_effort,
            values.threshold_force,
            values.violation(),
            best_starts(problem, (1.0, 0.0), samples=x),
            best_starts(problem, (0.0, 1.0), samples=x),
        )
        for a in (*entry[:4], *entry[4], *entry[5]):
            a.setflags(write=False)
    _SAMPLE_CACHE[key] = entry
    while len(_SAMPLE_CACHE) > CACHE_SIZE:
        _SAMPLE_CACHE.pop(next(iter(_SAMPLE_CACHE)))
    return entry


def _sample_starts(sample: Sample, eps_values: np.ndarray) -> np.ndarray:
    """For each ε: the sample design of least F_turn with P <= ε among the feasible (else the least violating)."""
    x, f, p, viol = sample[:4]
    eps = np.asarray(eps_values, float)[:, None]
    ok = (viol[None, :] <= 0) & (p[None, :] <= eps)
    score = np.where(ok, f[None, :], np.inf)
    best = np.argmin(score, axis=1)
    fallback = np.argmin(viol[None, :] + np.maximum(0.0, p[None, :] / eps - 1), axis=1)
    starts: np.ndarray = x[np.where(np.isfinite(score[np.arange(len(eps)), best]), best, fallback)]
    return starts


def _warm(results: Sequence[NLPResult]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The warm starts NLP results give: their designs (N, 4) [SI] and multipliers (lam_g, lam_x)."""
    lam_g, lam_x = np.array([r.lam_g for r in results]), np.array([r.lam_x for r in results])
    return design_rows([r.design for r in results]), lam_g, lam_x


def _rank(nlp: CasterNLP, result: NLPResult | None) -> float:
    return nlp.objectives(result.design)[0] if result is not None and result.success else np.inf


def lexicographic_ends(nlp: CasterNLP, problem: Problem, sample: Sample | None = None) -> Ends:
    """Lexicographic ends from sample starts: (min F, then min P) and (min P, then min F), each stage one batch."""
    if sample is not None:
        starts_f, starts_p = sample[4], sample[5]
    else:
        starts_f, starts_p = best_starts(problem, (1.0, 0.0)), best_starts(problem, (0.0, 1.0))
    weights = np.array([(1.0, 0.0)] * len(starts_f) + [(0.0, 1.0)] * len(starts_p))
    results = nlp.solve_many(starts_f + starts_p, weights)
    good_f = [r for r in results[: len(starts_f)] if r.success]
    good_p = [r for r in results[len(starts_f) :] if r.success]
    if not good_f or not good_p:
        return Ends(None, None, 16, tuple(sorted({r.status for r in results if not r.success})))
    obj_f = nlp.objectives_many([r.design for r in good_f])
    obj_p = nlp.objectives_many([r.design for r in good_p])
    best_f = good_f[int(np.argmin(obj_f[:, 0]))]  # the first of equal minima, as min() would
    best_p = good_p[int(np.argmin(obj_p[:, 1]))]
    f_min = float(obj_f[:, 0].min())
    p_min = float(obj_p[:, 1].min())
    # second stage: the other objective, the first capped at its optimum
    starts = [best_f.design.as_array(), best_p.design.as_array()] + _family_starts(problem, best_p.design)
    weights = np.array([(0.0, 1.0)] + [(1.0, 0.0)] * 3)
    caps_p = np.array([BIG] + [p_min * (1 + 1e-9)] * 3)
    caps_f = np.array([f_min * (1 + 1e-9)] + [BIG] * 3)
    second = nlp.solve_many(starts, weights, caps_p, caps_f)
    end_a = second[0] if second[0].success else best_f
    good_b = [r for r in second[1:] if r.success]
    end_b = good_b[int(np.argmin(nlp.objectives_many([r.design for r in good_b])[:, 0]))] if good_b else best_p
    return Ends(end_a, end_b, 16)


class NLPSweep:
    """The NLP sweep: ε-optima from sample starts, family restarts and warm propagation (see the module text)."""

    name = "nlp"
    method = (
        "ε-constraint on the CasADi/IPOPT NLP (min F_turn s.t. P <= ε), batched block-diagonal solves, "
        "warm-started from the neighbouring optimum, arc-length re-spaced, family restarts on a coarse "
        "subset and at family switches, propagated until no start improves"
    )

    def __init__(self, nlp: CasterNLP, problem: Problem):
        self.nlp, self.problem = nlp, problem
        self._sample: Sample | None = None

    @property
    def sample(self) -> Sample:
        """:func:`box_sample` of the problem, drawn when first needed."""
        if self._sample is None:
            self._sample = box_sample(self.problem)
        return self._sample

    def ends(self) -> Ends:
        """The two lexicographic ends (:func:`lexicographic_ends` from the sample's best starts)."""
        return lexicographic_ends(self.nlp, self.problem, self.sample)

    def sweep(self, eps_values: npt.ArrayLike, ends: Ends, guide: Guide | None = None) -> tuple[list[NLPResult], int]:
        """Results at every ε (the first and last are the ends) and the number of solves.

        ``guide`` = (ε, results) of an earlier pass: each point starts warm from the earlier pass's point
        just before it in sweep order (and from the one after when their families differ).
        """
        eps = np.asarray(eps_values, float)
        end_a, end_b = _found(ends)
        inner = eps[1:-1]
        sweep = _Sweep(self.nlp, self.problem, inner)
        if len(inner):
            if guide is None:
                sweep.run(_sample_starts(self.sample, inner))
            else:
                self._run_guided(sweep, inner, ends, guide)
            sweep.rescue()
        results = [end_a] + sweep.results() + [end_b]
        return results[: len(eps)] if len(eps) >= 2 else [end_a], sweep.solves

    def _run_guided(self, sweep: "_Sweep", inner: np.ndarray, ends: Ends, guide: Guide) -> None:
        """Run ``sweep`` warm from the earlier pass ``guide`` = (ε, results)."""
        g_eps, g_res = np.asarray(guide[0], float), guide[1]
        end_a, end_b = _found(ends)
        # the earlier pass's point just before in sweep order (ε decreasing), warm with its multipliers
        pos = np.clip(np.searchsorted(-g_eps, -inner, side="right") - 1, 0, len(g_eps) - 1)
        src: list[NLPResult] = []
        other: list[NLPResult | None] = []
        fam: dict[int, str] = {}

        def family(r: NLPResult) -> str:
            return fam.setdefault(id(r), family_of(self.problem, r.design))

        for j in pos.tolist():
            before = j
            while before > 0 and not g_res[before].success:
                before -= 1
            after = min(j + 1, len(g_res) - 1)
            while after < len(g_res) - 1 and not g_res[after].success:
                after += 1
            a = g_res[before] if g_res[before].success else end_a
            b = g_res[after] if g_res[after].success else end_b
            if before == 0 and 0 < after < len(g_res) - 1 and b.success:
                # the end's multipliers belong to its lexicographic solve (another objective): a warm
                # start from them takes ~25 iterations and would hold up the whole first batch, so the
                # next ε-point (~3 iterations) is the first start and the end, if needed, the second
                a, b = b, a
            src.append(a)
            other.append(b if family(a) != family(b) else None)
        pairs = [(i, r) for i, r in enumerate(other) if r is not None]
        sweep.run(*_warm(src), families=False, extra=([i for i, _ in pairs], *_warm([r for _, r in pairs])))

    def sweep_from_sample(self, eps: np.ndarray) -> tuple[list[NLPResult], int]:
        """Best results at ``eps`` (all interior) from the sample starts, with family restarts and rescue."""
        sweep = _Sweep(self.nlp, self.problem, eps)
        sweep.run(_sample_starts(self.sample, eps))
        sweep.rescue()
        return sweep.results(), sweep.solves


class StructuredSweep(NLPSweep):
    """Closed-form ε-optima (:mod:`designer.solvers.closed_form`) confirmed by one warm batched NLP solve.

    Use where :func:`designer.solvers.closed_form.applicable` holds and the diameter is free.  Falls back
    to :class:`NLPSweep` point by point (see the module text).
    """

    name = "structured"
    method = (
        "ε-constraint: closed-form ε-optima (designer.solvers.closed_form) confirmed by one warm batched "
        "solve of the CasADi/IPOPT NLP (min F_turn s.t. P <= ε), arc-length re-spaced; the NLP sweep "
        "(sample starts, family restarts) where the closed form has no optimum or the NLP disagrees"
    )

    def ends(self) -> Ends:
        """The ends from their closed form, confirmed by one warm batched NLP solve.

        Falls back to :func:`lexicographic_ends` (16 more solves) when the closed form finds no end, a
        solve fails or the NLP end is worse than the closed form's by more than 1e-9 (relative).
        """
        nlp = self.nlp
        ends = structured_ends(self.problem)
        if ends is not None:
            (f_a, p_a, _, _), (f_b, p_b, _, _) = nlp.objectives_many(ends)
            weights = np.array([(0.0, 1.0), (1.0, 0.0)])
            caps_p = np.array([BIG, p_b])
            caps_f = np.array([f_a, BIG])
            lam_g, lam_x = nlp.multipliers_many(ends, weights, caps_p, caps_f, tol=1e-8)
            a, b = nlp.solve_many(ends, weights, caps_p, caps_f, lam_g0=lam_g, lam_x0=lam_x)
            if a.success and b.success:
                (fa, pa, _, _), (fb, pb, _, _) = nlp.objectives_many([a.design, b.design])
                rel = 1 + 1e-9
                if fa <= f_a * rel and pa <= p_a * rel and fb <= f_b * rel and pb <= p_b * rel:
                    return Ends(a, b, 2)
        found = super().ends()
        found.solves += 2
        return found

    def sweep(self, eps_values: npt.ArrayLike, ends: Ends, guide: Guide | None = None) -> tuple[list[NLPResult], int]:
        """Results at every ε from the closed form, confirmed by the NLP (``guide`` is not needed)."""
        nlp, problem = self.nlp, self.problem
        eps = np.asarray(eps_values, float)
        end_a, end_b = _found(ends)
        inner = eps[1:-1]
        results: list[NLPResult | None] = [end_a] + [None] * len(inner) + [end_b]
        solves = 0
        if len(inner):
            x, ok = structured_front_designs(problem, inner)
            idx = np.flatnonzero(ok)
            if len(idx):
                lam_g, lam_x = nlp.multipliers_many(x[idx], (1.0, 0.0), inner[idx])
                solved = nlp.solve_many(x[idx], (1.0, 0.0), inner[idx], lam_g0=lam_g, lam_x0=lam_x)
                solves += len(idx)
                y = design_rows([r.design for r in solved])  # F_turn (Eq. 9) of both, as the model's evaluator
                f_cf, f_nlp = (
                    np.asarray(turning_effort(z[:, 0], z[:, 2], z[:, 3], problem.conditions)) for z in (x[idx], y)
                )
                for j, r, a, b in zip(idx, solved, f_nlp, f_cf):
                    if r.success and a <= b * (1 + 1e-9):
                        results[j + 1] = r
            bad = [j for j in range(len(inner)) if results[j + 1] is None]
            if bad:
                rescued, done = self.sweep_from_sample(inner[bad])
                solves += done
                for k, r in zip(bad, rescued):
                    results[k + 1] = r
        solved = [r for r in results if r is not None]
        return solved[: len(eps)] if len(eps) >= 2 else [end_a], solves


class _Sweep:
    """The interior ε-points of one pass, improved in batches until no start finds a better optimum.

    ``best[i]`` is the best successful result at ``eps[i]`` so far (None: none yet).  Rounds:

    1. the given starts (warm with multipliers when given): all points in one batched solve;
    2. with ``families``: family restarts (:func:`_family_starts` of the point's optimum, cold) on a
       coarse subset (every ``stride``-th point) and at every point whose family differs from a
       neighbour's; from a point they improve, the points up to the next coarse point on each side
       are re-solved warm from its new optimum;
    3. switches: wherever neighbours belong to different families (a discontinuity of the front is
       where the other family can win), each is re-solved warm from the other's optimum, and every
       improvement is passed on to its neighbours, until a round improves nothing.
    """

    def __init__(self, nlp: CasterNLP, problem: Problem, eps: np.ndarray):
        self.nlp, self.problem, self.eps = nlp, problem, np.asarray(eps, float)
        self.k = len(self.eps)
        self.best: list[NLPResult | None] = [None] * self.k
        self.first: list[NLPResult | None] = [None] * self.k  # first result (kept to report a failure)
        self.f = np.full(self.k, np.inf)
        self.solves = 0
        self.stride = max(1, self.k // 10)
        self._tried: set[tuple[int, int]] = set()

    def results(self) -> list[NLPResult]:
        """Per point the best successful result, else the first one (a failure, kept for its status)."""
        out = []
        for best, first in zip(self.best, self.first):
            result = best if best is not None else first
            if result is None:  # every point is tried in run's first round
                raise ValueError("a sweep point was never solved")
            out.append(result)
        return out

    def run(
        self,
        starts: npt.ArrayLike,
        lam_g: np.ndarray | None = None,
        lam_x: np.ndarray | None = None,
        families: bool = True,
        extra: tuple[list[int], np.ndarray, np.ndarray, np.ndarray] | None = None,
    ) -> None:
        self._try(list(range(self.k)), starts, lam_g, lam_x)
        if extra is not None:  # optional second start per point: (indices, starts, lam_g, lam_x)
            self._try(*extra)
        if families:
            switch = self._switches()
            coarse = sorted(set(range(0, self.k, self.stride)) | {self.k - 1} | switch)
            restarts = [
                (i, s)
                for i in coarse
                if (point := self.best[i]) is not None
                for s in _family_starts(self.problem, point.design)
            ]
            improved = self._try([i for i, _ in restarts], [s for _, s in restarts])
            self._propagate(improved, self.stride)
        for _ in range(self.k):
            pairs = [(i, j) for i in self._switches() for j in (i - 1, i + 1) if 0 <= j < self.k]
            if not self._propagate_pairs(pairs):
                break

    def _family(self, i: int) -> str:
        r = self.best[i]
        return family_of(self.problem, r.design) if r is not None else ""

    def _switches(self) -> set[int]:
        fam = [self._family(i) for i in range(self.k)]
        out: set[int] = set()
        for i in range(self.k - 1):
            if fam[i] != fam[i + 1]:
                out |= {i, i + 1}
        return out

    def _propagate(self, sources: set[int], width: int) -> None:
        pairs = [
            (i, j) for i in sorted(sources) for j in range(max(0, i - width), min(self.k, i + width + 1)) if j != i
        ]
        while pairs:
            improved = self._propagate_pairs(pairs)
            pairs = [(i, j) for i in sorted(improved) for j in (i - 1, i + 1) if 0 <= j < self.k]

    def _propagate_pairs(self, pairs: list[tuple[int, int]]) -> set[int]:
        """Re-solve point j warm from point i's optimum for each new (i, j) pair; the improved points."""
        chosen: list[tuple[int, NLPResult]] = []
        for i, j in pairs:
            source = self.best[i]
            key = (j, id(source))
            if source is None or key in self._tried or source is self.best[j]:
                continue
            self._tried.add(key)
            chosen.append((j, source))
        return self._try([j for j, _ in chosen], *_warm([r for _, r in chosen])) if chosen else set()

    def _try(
        self, idx: list[int], starts: npt.ArrayLike, lam_g: np.ndarray | None = None, lam_x: np.ndarray | None = None
    ) -> set[int]:
        if not len(idx):
            return set()
        warm = lam_g is not None and len(lam_g)
        results = self.nlp.solve_many(
            np.asarray(starts, float),
            (1.0, 0.0),
            self.eps[idx],
            lam_g0=lam_g if warm else None,
            lam_x0=lam_x if warm else None,
        )
        self.solves += len(idx)
        ok = np.array([r.success for r in results])
        f_all = np.full(len(results), np.inf)
        if np.any(ok):
            values = self.problem.evaluate(np.array([r.design.as_array() for r in results]))
            f_all[ok] = values.turning_effort[ok]
        improved: set[int] = set()
        for i, r, f in zip(idx, results, f_all):
            if self.first[i] is None:
                self.first[i] = r
            if np.isfinite(f) and f < self.f[i] - 1e-12 * max(1.0, abs(f)):  # a failed solve (inf) never improves
                if self.best[i] is not None and f < self.f[i] * (1 - 1e-9):
                    improved.add(i)
                self.best[i], self.f[i] = r, f
        return improved

    def rescue(self) -> None:
        """Points without a successful result: retry from a fresh sample of the box (as before)."""
        for i in range(self.k):
            if self.best[i] is not None:
                continue
            for s in best_starts(self.problem, (1.0, 0.0), k=4, threshold_cap=float(self.eps[i]), seed=3):
                r = self.nlp.solve(s, (1.0, 0.0), float(self.eps[i]))
                self.solves += 1
                if r.success and (self.best[i] is None or _rank(self.nlp, r) < self.f[i]):
                    self.best[i], self.f[i] = r, _rank(self.nlp, r)
