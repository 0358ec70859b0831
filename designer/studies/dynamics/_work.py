"""A bound on the work of one shimmy study: evaluations of the equations of motion, and its speeds.

Every time integration of the room counts the evaluations of its right-hand side (and the closed-form
integration its grid points) against one budget; the outermost public study (:func:`simulate`,
:func:`onset_speed`, a knock onset or knock-safe speed, a bifurcation diagram) opens it with
:func:`bounded`, and every simulation it runs shares it.  When the budget is spent the study ends with
:class:`WorkLimitError`: one line saying what was being computed, with how many evaluations, and why
such a case is costly.  The count is deterministic (no clock), so a case ends the same way everywhere.

The searches in speed (onset, knock onset) stay inside :data:`SPEED_RANGE`, the model's speeds (the
problem file's ``shimmy.target_speed`` range): an onset beyond it is said, not searched for.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import inspect
import math
from collections.abc import Iterator
from typing import Any, Callable, TypeVar

from designer.boundary import Instance
from designer.errors import DesignerError, SolverError
from designer.model import Conditions, Design
from designer.parameters import PARAMETERS
from designer.physics.tyre import TyreParameters

MAX_EVALUATIONS = 2_000_000
"""Evaluations of the equations of motion one study may spend (about 20 s of CPU here at 9-10 µs each).
The cases measured need less: a simulation 2 000-15 000, an onset search 40 000-110 000 (500 000 for
T = 0.25 m, d = 0.6 m at a crawl), a knock-safe speed with the brush tyre 460 000, the default bifurcation
diagram (24 orbits, both tyres) about 800 000, the slowest single simulation of the model's range
(T = 0.25 m at 0.01 m/s: a 75 s aligning transient) about 740 000.  Work that grows with a requested count
(a bifurcation diagram's ``points``) gets a budget grown in proportion (:func:`scaled_budget`): 200 orbits
took 4.3 million."""

SPEED_RANGE: tuple[float, float] = PARAMETERS["target_speed"].range or (0.01, 100.0)
"""The model's speeds [m/s] (the problem file's range of ``shimmy.target_speed``)."""

_F = TypeVar("_F", bound=Callable[..., Any])

ARGUMENTS = {
    "design": Instance(
        (Design,), "a designer.Design, e.g. Design(trail='1.5 in', diameter='6 in', groove=0, damping=1.3)"
    ),
    "conditions": Instance((Conditions,), "a designer.Conditions, e.g. Conditions(load=178)"),
    "tyre": Instance((TyreParameters,), "None (the rolling tyre) or a designer.TyreParameters", optional=True),
}
"""The checks (:func:`designer.boundary.checked`) of the studies' common arguments: the caster, its conditions
and the tyre."""


class WorkLimitError(DesignerError):
    """A shimmy study spent :data:`MAX_EVALUATIONS` evaluations without an answer (exit 5, as a solver that
    fails).  Not a :class:`SolverError`: the searches that step over a failed orbit or bracket do not step
    over it, the study ends."""

    exit_code = SolverError.exit_code


class _Budget:
    def __init__(self, what: str, evaluations: int):
        self.what = what
        self.limit = evaluations
        self.left = evaluations

    def spend(self, n: int) -> None:
        self.left -= n
        if self.left < 0:
            raise WorkLimitError(
                f"{self.what}: stopped after {self.limit:,} evaluations of the equations of motion, the work "
                "limit of one study; such a case has time scales far apart (a short trail or a light wheel at "
                "a high speed, a long transient at a crawl): choose values nearer the paper's casters"
            )


_ACTIVE: contextvars.ContextVar[_Budget | None] = contextvars.ContextVar("designer_dynamics_budget", default=None)


@contextlib.contextmanager
def work_limit(what: str, evaluations: int | None = None) -> Iterator[None]:
    """Open one budget of ``evaluations`` (default :data:`MAX_EVALUATIONS`) for everything run inside, e.g. a
    command that runs several studies; ``what`` names it in the message.  Inside an open budget it opens
    none (the outer one bounds the whole)."""
    if _ACTIVE.get() is not None:
        yield
        return
    token = _ACTIVE.set(_Budget(what, MAX_EVALUATIONS if evaluations is None else int(evaluations)))
    try:
        yield
    finally:
        _ACTIVE.reset(token)


def bounded(what: str, scale: str | None = None) -> Callable[[_F], _F]:
    """Decorator of a public study: it runs inside :func:`work_limit` (``what`` names it), so a study that
    calls it shares the caller's budget.  ``scale`` names a count argument that the work grows with (the
    orbits of a bifurcation diagram): the budget is :data:`MAX_EVALUATIONS` times the count over its default,
    at least once."""

    def decorate(function: _F) -> _F:
        signature = inspect.signature(function)

        @functools.wraps(function)
        def wrapper(*args, **kwargs):
            evaluations = None
            if scale is not None:
                count = signature.bind(*args, **kwargs).arguments.get(scale, signature.parameters[scale].default)
                evaluations = scaled_budget(count, signature.parameters[scale].default)
            with work_limit(what, evaluations):
                return function(*args, **kwargs)

        return wrapper  # type: ignore[return-value]

    return decorate


def scaled_budget(count: float, reference: float) -> int:
    """:data:`MAX_EVALUATIONS` times ``count / reference``, at least :data:`MAX_EVALUATIONS` (work that grows
    with a requested count, e.g. --points orbits against the default 24)."""
    return int(MAX_EVALUATIONS * max(1.0, float(count) / float(reference)))


def spend(n: int = 1) -> None:
    """Count ``n`` evaluations against the open budget (none open: nothing counted)."""
    budget = _ACTIVE.get()
    if budget is not None:
        budget.spend(n)


def counted(rhs: Callable[..., Any]) -> Callable[..., Any]:
    """``rhs`` (a right-hand side for ``solve_ivp``) counting each call against the open budget."""
    budget = _ACTIVE.get()
    if budget is None:
        return rhs

    def f(t, y):
        budget.spend(1)
        return rhs(t, y)

    return f


def bracket_speed(
    grows: Callable[[float], bool], low: float, high: float, widen: float, tries: int, v7: float, what: str
) -> tuple[float, float]:
    """Widen (low, high) [m/s] × ``widen`` outward, inside :data:`SPEED_RANGE`, until ``grows`` is false at low and
    true at high (the onset searches, before :func:`bisect_speed`); SolverError naming ``what`` (the onset) and
    Eq. 7's ``v7`` [m/s] when that takes more than ``tries`` widenings or would leave the model's speeds."""
    v_min, v_max = SPEED_RANGE
    low, high = min(max(low, v_min), v_max), min(max(high, v_min), v_max)
    for _ in range(tries):
        if grows(low):
            if low <= v_min:
                raise SolverError(
                    f"{what} below {v_min:g} m/s, the model's lowest speed: the knock grows there already "
                    f"(Eq. 7 gives {v7:.3g} m/s)"
                )
            high, low = low, max(low / widen, v_min)
        elif not grows(high):
            if high >= v_max:
                raise SolverError(
                    f"no {what} up to {v_max:g} m/s, the model's highest speed: the knock decays there "
                    f"(Eq. 7 gives {v7:.3g} m/s); the caster does not shimmy at any speed the model covers"
                )
            low, high = high, min(high * widen, v_max)
        else:
            return low, high  # decays at low, grows at high
    raise SolverError(
        f"{what} not bracketed after {tries} widenings ×{widen:g} (last bracket {low:.3g}–{high:.3g} m/s, "
        f"Eq. 7 gives {v7:.3g} m/s)"
    )


def bisect_speed(grows: Callable[[float], bool], low: float, high: float, rtol: float) -> tuple[float, float]:
    """Bisect the bracket (low, high) [m/s], ``grows`` false at low and true at high, in log V until
    high/low − 1 <= ``rtol`` (the onset searches)."""
    while high / low - 1 > rtol:
        mid = math.sqrt(low * high)
        if grows(mid):
            high = mid
        else:
            low = mid
    return low, high
