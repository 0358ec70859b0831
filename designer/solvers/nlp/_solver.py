"""The CasADi/IPOPT NLP as a solver of the protocol (:class:`designer.solvers.base.Solver`).

``optimum``: every start (the best points of the Sobol sample of the box for the weights, the two families'
corners and any given starts) solved on the problem's compiled NLP (:func:`~designer.solvers.nlp.shared_nlp`),
the best successful one kept, with its sensitivities d log J / d log p from the multipliers.

``front_designs``: the ε-sweep of :mod:`designer.solvers.nlp._sweep`.  With ``structured=True`` (the front's
choice where the closed form applies: :func:`designer.solvers.front_solver`) the sweep starts from the closed
form's ε-optima and confirms them; otherwise it starts from the sample with family restarts.  A front
(:func:`designer.studies.front.pareto_front`) also asks for the two lexicographic ends (:meth:`front_ends`) and
passes them, and its first pass as a warm ``guide`` to its second, to ``front_designs``.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.problem import Problem
from designer.solvers.closed_form import CLOSED_FORM, applicable as closed_form_applicable
from designer.solvers.base import NO_CAPS, Caps, Designs, Optimum, best_variant, design_rows, found_optimum, weights_of
from designer.solvers.nlp._cache import shared_nlp
from designer.solvers.nlp._casadi import BIG, CasterNLP, NLPResult, best_starts, solve_best
from designer.solvers.nlp._sweep import Ends, NLPSweep, StructuredSweep

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt


def nlp_designs(nlp: CasterNLP, solver: str, eps: npt.ArrayLike, results: Sequence[NLPResult], solves: int) -> Designs:
    """:class:`~designer.solvers.base.Designs` of NLP results at ``eps``: objectives through the NLP's own graph
    (:meth:`CasterNLP.objectives_many`), multipliers by constraint name, the results kept (warm starts)."""
    x = np.array([r.design.as_array() for r in results], float).reshape(-1, 4)
    return Designs(
        solver=solver,
        epsilon=np.asarray(eps, float).ravel(),
        designs=x,
        success=np.array([bool(r.success) for r in results], dtype=bool),
        objectives=nlp.objectives_many(x)[:, :3],
        status=tuple(str(r.status) for r in results),
        multipliers=tuple(dict(zip(nlp.constraint_names, np.asarray(r.lam_g, float).tolist())) for r in results),
        solves=solves,
        results=tuple(results),
    )


class NLPSolver:
    """The exact NLP from multiple starts (module text); ``structured``: its front sweep starts from the closed form."""

    name = "casadi-ipopt"
    tolerance = 1e-8

    def __init__(self, structured: bool = False, samples: int = 1024):
        self.sweep = StructuredSweep if structured else NLPSweep
        self.samples = samples
        self._front_nlp: tuple[Problem, CasterNLP] | None = None

    @property
    def strategy(self) -> str:
        """The front sweep's name ("nlp" or "structured"; a front's ``meta["strategy"]``)."""
        return self.sweep.name

    @property
    def method(self) -> str:
        """The front sweep in words (a front's ``meta["method"]``)."""
        return self.sweep.method

    def applicable(self, problem: Problem) -> bool:
        """The NLP solves every problem (a catalog per wheel); the structured sweep needs the closed form."""
        if self.sweep is StructuredSweep:
            return not problem.bounds["diameter"].fixed and closed_form_applicable(problem)
        return True

    # ----------------------------------------------------------------- the weighted optimum
    def optimum(
        self,
        problem: Problem,
        weights: Sequence[float] | None = None,
        caps: Caps = NO_CAPS,
        *,
        starts: Sequence[Any] = (),
    ) -> Optimum:
        """The best NLP optimum from the sample's best starts plus ``starts`` (module text); a catalog problem
        per wheel.  ``result`` is the :class:`NLPResult`, ``build_seconds`` the compiled NLP's build time."""
        w = weights_of(problem, weights)
        return best_variant(problem, lambda variant: self._optimum(variant, w, caps, starts))

    def _optimum(self, problem: Problem, w: tuple[float, float], caps: Caps, starts: Sequence[Any]) -> Optimum:
        nlp = shared_nlp(problem, same_scaling=True)  # the front's compiled NLP: the same solves as a new build
        cap_p = BIG if caps.threshold is None else float(caps.threshold)
        cap_f = BIG if caps.turning is None else float(caps.turning)
        all_starts = best_starts(problem, w, n=self.samples, threshold_cap=cap_p) + list(design_rows(starts))
        t0 = time.perf_counter()
        best, results = solve_best(nlp, all_starts, w, cap_p, cap_f)
        seconds = time.perf_counter() - t0
        if best is None:
            return found_optimum(
                self.name, problem, w, caps, None, status=", ".join(sorted({r.status for r in results})) or "unknown"
            )
        return found_optimum(
            self.name,
            problem,
            w,
            caps,
            best.design,
            objective=float(best.objective),
            sensitivities=nlp.sensitivities(best, w, cap_p, cap_f),
            solves=len(all_starts),
            seconds=seconds,
            build_seconds=nlp.build_seconds,
            result=best,
        )

    # ----------------------------------------------------------------- fronts
    def front_nlp(self, problem: Problem) -> CasterNLP:
        """The compiled NLP the front calls of ``problem`` share (:func:`shared_nlp`; one view per problem, so its
        ``build_seconds`` count the batch solvers built on the way)."""
        if self._front_nlp is None or self._front_nlp[0] is not problem:
            self._front_nlp = (problem, shared_nlp(problem, build=CasterNLP))
        return self._front_nlp[1]

    def _sweeper(self, problem: Problem) -> NLPSweep:
        return self.sweep(self.front_nlp(problem), problem)

    def front_ends(self, problem: Problem) -> Ends:
        """The two lexicographic ends (min F_turn then min P; min P then min F_turn) of a continuous problem
        (``a``, ``b`` None when not found, with the failed statuses)."""
        return self._sweeper(problem).ends()

    def ends_designs(self, problem: Problem, ends: Ends, eps: npt.ArrayLike | None = None) -> Designs:
        """The two ends found by :meth:`front_ends` as :class:`Designs` (rows a, b); ε: ``eps``, else their own P."""
        nlp = self.front_nlp(problem)
        if ends.a is None or ends.b is None:
            raise ValueError(f"{problem.name}: the front's ends were not found ({', '.join(ends.statuses)})")
        results = [ends.a, ends.b]
        if eps is None:
            eps = nlp.objectives_many([r.design for r in results])[:, 1]
        return nlp_designs(nlp, self.name, eps, results, ends.solves)

    def front_designs(
        self, problem: Problem, eps: npt.ArrayLike, *, ends: Ends | None = None, guide: Designs | None = None
    ) -> Designs:
        """ε-optima at every ε of a continuous problem.

        Without ``ends`` every ε is solved from the sample's starts (family restarts, rescue).  With ``ends``
        (:meth:`front_ends`) the first and last ε are the ends, not solved again; ``guide`` (an earlier pass at
        other ε, :class:`Designs` with NLP results) starts each point warm from its neighbour in that pass.
        """
        sweeper = self._sweeper(problem)
        e = np.asarray(eps, float).ravel()
        if ends is None:
            results, solves = sweeper.sweep_from_sample(e)
        else:
            warm = None if guide is None else (guide.epsilon, list(guide.results))
            results, solves = sweeper.sweep(e, ends, guide=warm)
        return nlp_designs(sweeper.nlp, self.name, e[: len(results)], results, solves)

    def first_pass(self, problem: Problem, eps: npt.ArrayLike, *, ends: Ends) -> Designs:
        """A front's first pass: ε-optima at ``eps`` whose objectives space its second pass by arc length.

        The structured sweep's are the closed form's ε-optima, not confirmed by the NLP (``results`` empty): the
        front keeps only the second pass's points, each confirmed there, so a confirming solve here would cost
        a batched solve per front (a third of a risk-bounded front's CPU time) and change nothing that is
        kept.  The NLP sweep's are :meth:`front_designs` (solved; its second pass starts warm from them).
        """
        if self.sweep is StructuredSweep:
            return CLOSED_FORM.front_designs(problem, eps)
        return self.front_designs(problem, eps, ends=ends)

    def build_seconds(self, problem: Problem) -> float:
        """Wall time spent building the compiled NLP used for ``problem``'s front [s]."""
        return float(self.front_nlp(problem).build_seconds)


NLP = NLPSolver()
"""The NLP's :class:`~designer.solvers.base.Solver` (its front sweeps from the sample)."""

__all__ = ["NLP", "NLPSolver", "nlp_designs"]
