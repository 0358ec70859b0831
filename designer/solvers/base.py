"""The solver protocol: one shape for every solver of a caster problem.

Every solver answers the same two questions about a :class:`~designer.problem.Problem`, and returns
records built by keyword:

``optimum(problem, weights, caps) -> Optimum``
    min J = w_turn F_turn + w_threshold P (Eq. 9, Eq. 4A) subject to V_c >= V_req (Eq. 7; its α-quantile
    with a risk bound), the bounds, the swept-radius limit R_s <= R_max and the optional ε caps
    P <= ε_P, F_turn <= ε_F (:class:`Caps`).  A catalog problem is solved per wheel and the best kept.
``front_designs(problem, eps) -> Designs``
    the ε-constraint optima min F_turn s.t. P <= ε at every ε of ``eps`` (a front's points).

The implementations (each in its solver's module, so that loading one does not load another's library):

=================  =====================================================================  ==============
name               how                                                                     tolerance on J
=================  =====================================================================  ==============
``closed-form``    the structure of the model (:mod:`designer.solvers.closed_form`)        1e-7
``casadi-ipopt``   the exact NLP from multiple starts (:mod:`designer.solvers.nlp`)       1e-8
``cvxpy-gp``       sequential geometric programming (:mod:`designer.solvers.gp`)          1e-4
``scipy-slsqp``    SLSQP on the NumPy model, finite differences (:mod:`designer.solvers.slsqp`)  1e-4
=================  =====================================================================  ==============

The tolerance is the relative gap in J to the exact optimum a solver is held to (``Solver.tolerance``;
tests/solvers/test_protocol.py runs one problem through all four).  Which solver runs where is decided in
one place, :mod:`designer.solvers` (:func:`~designer.solvers.solver`, :func:`~designer.solvers.front_solver`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol, TypeVar, runtime_checkable

import numpy as np

from designer.model import VARIABLES, Design
from designer.parameters import OUTPUTS
from designer.physics.inertia import Catalog
from designer.problem import Problem
from designer.reprs import Record, si_frame

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt


SOLVE_LOCK = threading.RLock()
"""One solve at a time per process.  CasADi's compiled functions and IPOPT instances, the compiled NLPs shared
between problems of one structure (:mod:`designer.solvers.nlp`) and the solvers' default instances hold
working memory: two threads solving on one of them at once crash the interpreter (a segmentation fault in
CasADi).  The public studies that solve (``designer.optimise``, ``pareto_front``, ``recommend``, ``fix``,
``fleet``, ``explore``) hold this lock (:func:`one_solve_at_a_time`); re-entrant, so one calling another is
fine.  Processes (``explore --workers``, fleet's Dask workers) each have their own."""

_F = TypeVar("_F", bound=Callable[..., Any])


def one_solve_at_a_time(func: _F) -> _F:
    """``func`` run under :data:`SOLVE_LOCK`: threads calling the API's studies at once are served in turn, each
    with the result a call alone gives."""

    @functools.wraps(func)
    def serialised(*args: Any, **kwargs: Any) -> Any:
        with SOLVE_LOCK:
            return func(*args, **kwargs)

    return serialised  # type: ignore[return-value]


@dataclass(frozen=True, kw_only=True)
class Caps:
    """Optional ε caps of an optimum: P <= ``threshold`` [N] and F_turn <= ``turning`` [N] (None: no cap)."""

    threshold: float | None = None
    turning: float | None = None


NO_CAPS = Caps()
"""No cap on either objective."""


@dataclass(frozen=True, kw_only=True)
class Optimum(Record):
    """The optimum one solver found for one problem (built by keyword).

    Attributes
    ----------
    solver : the solver's name ("closed-form", "casadi-ipopt", "cvxpy-gp", "scipy-slsqp")
    problem : the continuous problem solved (for a catalog problem: the chosen wheel's variant)
    weights : (w_turn, w_threshold) of the J minimised
    caps : the ε caps imposed
    design : the optimum (SI), or None when the solver found none
    objective : J = w_turn F_turn + w_threshold P [N] of ``design`` by the exact model (nan when none)
    success : a feasible optimum was found
    status : the solver's status ("optimal", "infeasible", IPOPT's return status, ...)
    wheel : the Table 1 wheel of a catalog problem, else None
    sensitivities : d log J / d log p [-] where the solver gives them (NLP multipliers, GP duals), else {}
    solves : number of solves (starts, GP solves, ε-points searched)
    seconds : wall time of the solves [s]
    build_seconds : wall time of building the solver's model (the compiled NLP) [s]
    result : the solver's own record (:class:`~designer.solvers.nlp.NLPResult`,
        :class:`~designer.solvers.gp.GPResult`) for what only it knows (multipliers, families), or None
    """

    solver: str
    problem: Problem = field(repr=False)
    weights: tuple[float, float]
    caps: Caps = NO_CAPS
    design: Design | None
    objective: float
    success: bool
    status: str
    wheel: str | None = None
    sensitivities: dict[str, float] = field(default_factory=dict, repr=False)
    solves: int = 0
    seconds: float = 0.0
    build_seconds: float = 0.0
    result: Any = field(default=None, repr=False)

    _units = {"objective": "N", "seconds": "s", "build_seconds": "s", "caps.threshold": "N", "caps.turning": "N"}


OBJECTIVES = ("turning_effort", "threshold_force", "critical_speed")
"""The columns of :attr:`Designs.objectives`: F_turn [N], P [N], V_c [m/s]."""


def _span(values: np.ndarray) -> str:
    """The range of ``values`` as text, "min – max" to 4 significant digits."""
    return f"{float(np.min(values)):.4g} – {float(np.max(values)):.4g}"


@dataclass(frozen=True, kw_only=True)
class Designs(Record):
    """The ε-constraint optima of one continuous problem (built by keyword): one row per ε.

    Attributes
    ----------
    solver : the solver's name
    epsilon : (N,) the caps ε on P [N]
    designs : (N, 4) the designs (SI, :data:`~designer.model.VARIABLES` order); a row that failed holds the
        solver's last iterate (or the box's upper corner when it has none)
    success : (N,) a feasible optimum was found at this ε
    objectives : (N, 3) F_turn [N], P [N] and V_c [m/s] of each row as the solver evaluates them
    status : per row, the solver's status
    multipliers : per row, {constraint: λ} (CasADi sign convention) where the solver has them, else {}
    solves : number of solves it took
    results : per row, the solver's own result (NLP rows: :class:`~designer.solvers.nlp.NLPResult`,
        which a later sweep starts warm from), or () when it has none
    """

    solver: str
    epsilon: np.ndarray
    designs: np.ndarray
    success: np.ndarray
    objectives: np.ndarray
    status: tuple[str, ...]
    multipliers: tuple[dict[str, float], ...] = ()
    solves: int = 0
    results: tuple[Any, ...] = field(default=(), repr=False)

    _units = {"epsilon": "N", "designs": "m, m, m, N·m/rad", "objectives": "N, N, m/s"}

    def __len__(self) -> int:
        return len(self.epsilon)

    def _repr_lines(self) -> list[str]:
        """One line: the solver, how many ε-optima of how many rows were found, the ε range and the solves."""
        eps = f", ε {_span(self.epsilon)} N" if len(self) else ""
        found = int(np.count_nonzero(self.success))
        return [f"Designs({self.solver}: {found} of {len(self)} ε-optima found{eps}, {self.solves} solves)"]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The solver, how many ε-optima were found, the ε range and the ranges of F_turn and P found."""
        ok = np.asarray(self.success, dtype=bool)
        rows: list[tuple[Any, Any, Any]] = [
            ("solver", self.solver, ""),
            ("ε-optima found", f"{int(ok.sum())} of {len(self)}", ""),
            ("solves", str(self.solves), ""),
        ]
        if len(self):
            rows.append(("ε", _span(self.epsilon), "N"))
        if ok.any():
            rows += [OUTPUTS[k].row(_span(self.objectives[ok, i])) for i, k in enumerate(OBJECTIVES[:2])]
        return rows

    def to_pandas(self) -> Any:
        """One row per ε: ``epsilon_N``, the design (``trail_m``, ``diameter_m``, ``groove_m``,
        ``damping_N_m_per_rad``), ``turning_effort_N``, ``threshold_force_N``, ``critical_speed_m_s``, ``success``
        and ``status``; units in ``df.attrs["units"]``."""
        rows = [
            {
                "epsilon_N": float(self.epsilon[i]),
                **dict(zip(VARIABLES, (float(v) for v in self.designs[i]))),
                **dict(zip(OBJECTIVES, (float(v) for v in self.objectives[i]))),
                "success": bool(self.success[i]),
                "status": self.status[i],
            }
            for i in range(len(self))
        ]
        columns = ["epsilon_N", *VARIABLES, *OBJECTIVES, "success", "status"]
        return si_frame("Designs.to_pandas", rows, columns, {"epsilon_N": "N"}, solver=self.solver)

    def design(self, i: int) -> Design:
        """Row ``i`` as a :class:`~designer.model.Design`."""
        return Design.from_array(self.designs[i])


@runtime_checkable
class Solver(Protocol):
    """What every solver implements (the module text); the four are listed in :data:`designer.solvers.SOLVERS`."""

    name: str
    """How results name it (``Solution.cross_check`` keys, ``Optimum.solver``)."""
    tolerance: float
    """Relative gap in J to the exact optimum this solver is held to."""

    def applicable(self, problem: Problem) -> bool:
        """Whether the solver can solve ``problem`` (e.g. the closed form needs its structure)."""
        ...

    def optimum(
        self,
        problem: Problem,
        weights: Sequence[float] | None = None,
        caps: Caps = NO_CAPS,
        *,
        starts: Sequence[Any] = (),
    ) -> Optimum:
        """The optimum of J (weights default: the problem's) under ``caps``; ``starts``: designs to start from
        (ignored by solvers that need none)."""
        ...

    def front_designs(self, problem: Problem, eps: npt.ArrayLike) -> Designs:
        """The ε-constraint optima min F_turn s.t. P <= ε of a continuous problem at every ε [N]."""
        ...


def weights_of(problem: Problem, weights: Sequence[float] | None) -> tuple[float, float]:
    """``weights`` as two floats, or the problem's."""
    w = problem.weights if weights is None else weights
    return float(w[0]), float(w[1])


def no_optimum(solver: str, problem: Problem, weights: tuple[float, float], caps: Caps, status: str) -> Optimum:
    """The :class:`Optimum` of a solver that found no feasible design."""
    return found_optimum(solver, problem, weights, caps, None, status=status)


def found_optimum(
    solver: str, problem: Problem, weights: tuple[float, float], caps: Caps, design: Design | None, **fields: Any
) -> Optimum:
    """The :class:`Optimum` a solver found: ``design`` (None: no feasible design), its ``objective`` J [N] (nan
    without a design) and the rest by keyword (``status`` "optimal" unless given)."""
    fields.setdefault("objective", math.nan)
    fields.setdefault("status", "optimal")
    return Optimum(
        solver=solver, problem=problem, weights=weights, caps=caps, design=design, success=design is not None, **fields
    )


def best_variant(problem: Problem, solve: Callable[[Problem], Optimum]) -> Optimum:
    """``solve`` on every continuous variant of ``problem`` (one per catalog wheel); the best successful one.

    Its ``wheel`` is set for a catalog problem; ties go to the first wheel (as ``min`` does); with no success,
    the first variant's failure.  ``solves`` and ``seconds`` are summed over the variants.
    """
    found = [solve(variant) for variant in problem.variants()]
    good = [o for o in found if o.success]
    chosen = min(good, key=lambda o: o.objective) if good else found[0]
    if problem.wheels:
        chosen = dataclasses.replace(chosen, wheel=wheel_of(chosen.problem))
    return dataclasses.replace(chosen, solves=sum(o.solves for o in found), seconds=sum(o.seconds for o in found))


def optima_designs(solver: str, problem: Problem, eps: np.ndarray, found: Sequence[Optimum], **fields: Any) -> Designs:
    """The :class:`Designs` of one :class:`Optimum` per ε (``fields``: the rest, by keyword): a row without a design
    holds the box's upper corner; the objectives by :func:`objectives_of`."""
    x = design_rows([problem.upper() if o.design is None else o.design for o in found])
    return Designs(
        solver=solver,
        epsilon=eps,
        designs=x,
        success=np.array([o.success for o in found], dtype=bool),
        objectives=objectives_of(problem, x),
        status=tuple(o.status for o in found),
        **fields,
    )


def design_rows(designs: Sequence[Design | npt.ArrayLike] | np.ndarray) -> np.ndarray:
    """Designs (:class:`~designer.model.Design` or SI sequences) as an (N, 4) SI array, VARIABLES order."""
    return np.array([np.asarray(d.as_array() if isinstance(d, Design) else d, float) for d in designs]).reshape(-1, 4)


def wheel_of(problem: Problem) -> str | None:
    """The Table 1 wheel of a catalog variant (its inertia model is that wheel's), else None."""
    inertia = problem.conditions.inertia
    return inertia.wheel.key if isinstance(inertia, Catalog) else None


def objectives_of(problem: Problem, x: np.ndarray) -> np.ndarray:
    """(N, 3) F_turn [N], P [N], V_c [m/s] of (N, 4) designs by the model's evaluator (:meth:`Problem.evaluate`;
    non-finite where the model fails): the solvers' numeric check of their own optima."""
    c = problem.evaluate(np.asarray(x, float).reshape(-1, 4))
    n = len(c)
    return np.column_stack([np.broadcast_to(np.asarray(getattr(c, k), float), (n,)) for k in OBJECTIVES])


__all__ = [
    "SOLVE_LOCK",
    "one_solve_at_a_time",
    "NO_CAPS",
    "Caps",
    "Designs",
    "Optimum",
    "Solver",
    "best_variant",
    "design_rows",
    "objectives_of",
    "found_optimum",
    "no_optimum",
    "optima_designs",
    "weights_of",
    "wheel_of",
]
