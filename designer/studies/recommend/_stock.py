"""The stock and its deterministic screening: steps 1 and 2 of :mod:`designer.studies.recommend._recommend`.

Every combination of the parts of ``[stock]`` as arrays (:func:`stock_candidates`, the single owner of
the enumeration; ``designer fleet`` uses it too) and the screened table (:func:`candidate_table`): the risk
bound, the swept radius and the sill as a deterministic screen, with the objectives, all from the model's
evaluator (:func:`designer.model.evaluate`).  Re-exported by
:mod:`designer.studies.recommend._recommend`.
"""

from __future__ import annotations

import itertools
import warnings
from dataclasses import dataclass

import numpy as np

from designer.errors import InertiaExtrapolationWarning
from designer.model import VARIABLES, Casters, evaluate
from designer.physics.inertia import Catalog


@dataclass
class CandidateTable:
    """Every stock combination as arrays (one entry per combination), SI; ``None`` = continuous.

    Attributes
    ----------
    trail, diameter, groove, damping : the parts [m, m, m, N·m/rad], or None where the variable is continuous
    inertia : I_w per combination [kg·m²] (None when the diameter is continuous)
    measured : whether that I_w was measured (a catalogue wheel, a stock wheel listed with its inertia) or comes
        from the inertia model at d (a wheel known by its diameter only); None when the diameter is continuous
    wheel : wheel name per combination ("" for a plain diameter)
    note : where the stock comes from
    """

    trail: np.ndarray | None
    diameter: np.ndarray | None
    groove: np.ndarray | None
    damping: np.ndarray | None
    inertia: np.ndarray | None
    wheel: np.ndarray
    note: str = ""
    measured: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.wheel)

    @property
    def discrete(self) -> bool:
        """Every variable is a part (nothing left to solve continuously)."""
        return all(getattr(self, k) is not None for k in VARIABLES)

    def design(self, j: int) -> dict:
        """Combination ``j`` as {trail, diameter, groove, damping} [SI] (None where continuous)."""
        return {k: (None if getattr(self, k) is None else float(getattr(self, k)[j])) for k in VARIABLES}


def _wheel_rows(problem, stock):
    """Wheel choices: (diameter, inertia or None, groove or None, name) tuples, or None if d is continuous."""

    c = problem.conditions
    if problem.wheels:  # [inertia] model = "catalog": the wheels are Table 1's, with measured I_w
        return [
            (Catalog.from_key(k).fixed_diameter, float(Catalog.from_key(k).wheel.inertia), None, k)
            for k in problem.wheels
        ]
    if stock is not None and stock.wheels is not None:
        return [(w.diameter, w.inertia, w.groove, w.name) for w in stock.wheels]
    values = _values(problem, "diameter", None if stock is None else stock.diameters)
    if values is None:
        return None
    if getattr(c.inertia, "measured", False):  # measured wheels: a fixed I_w, or the power law's value at d
        with warnings.catch_warnings(action="ignore", category=InertiaExtrapolationWarning):
            return [(d, float(c.inertia(d)), None, "") for d in values]
    return [(d, None, None, "") for d in values]  # I_w from the inertia model (stock_candidates fills it in)


def _values(problem, name: str, listed):
    """A variable's stock values: those listed, else the fixed value, else None (continuous)."""
    b = problem.bounds[name]
    return tuple(listed) if listed is not None else (b.low,) if b.fixed else None


def stock_candidates(problem, stock=None) -> CandidateTable:
    """All stock combinations of ``problem`` (its ``[stock]``, or ``stock`` if given) as arrays.

    Parameters
    ----------
    problem : the problem (bounds, inertia model, catalogue wheels)
    stock : a :class:`designer.problem.Stock` to use instead of ``problem.stock``

    Returns
    -------
    CandidateTable; a variable neither listed nor fixed is ``None`` (continuous within its bounds).
    """
    stock = problem.stock if stock is None else stock
    wheels = _wheel_rows(problem, stock)
    trails = _values(problem, "trail", None if stock is None else stock.trails)
    grooves = _values(problem, "groove", None if stock is None else stock.grooves)
    dampings = _values(problem, "damping", None if stock is None else stock.dampings)
    wheel_axis = wheels if wheels is not None else [(None, None, None, "")]
    rows = []
    for (d, inertia, g_w, name), t, g, c in itertools.product(
        wheel_axis, trails or (None,), grooves or (None,), dampings or (None,)
    ):
        groove = g_w if g_w is not None else g  # a catalogue wheel's own groove (then stock.grooves is absent)
        rows.append((t, d, groove, c, inertia, name))
    rows = list(dict.fromkeys(rows))  # a wheel's own groove repeats once per listed groove

    def column(i, continuous):
        return None if continuous else np.array([r[i] for r in rows], float)

    grooves_continuous = grooves is None and (wheels is None or any(w[2] is None for w in wheel_axis))
    inertia = measured = None
    if wheels is not None:
        inertia = np.array([r[4] if r[4] is not None else np.nan for r in rows], float)
        missing = np.isnan(inertia)
        measured = ~missing | bool(getattr(problem.conditions.inertia, "measured", False))
        if missing.any():
            with warnings.catch_warnings(action="ignore", category=InertiaExtrapolationWarning):
                d = np.array([r[1] for r in rows], float)
                inertia[missing] = np.asarray(problem.conditions.inertia(d[missing]), float) + 0 * d[missing]
    note = (
        "the problem's [stock]"
        if problem.stock is not None and stock is problem.stock
        else "the given stock"
        if stock is not None
        else "no [stock]: every variable that is not fixed is continuous"
    )
    return CandidateTable(
        trail=column(0, trails is None),
        diameter=column(1, wheels is None),
        groove=column(2, grooves_continuous),
        damping=column(3, dampings is None),
        inertia=inertia,
        wheel=np.array([r[5] for r in rows], dtype=object),
        note=note,
        measured=measured,
    )


@dataclass
class ScreenedTable:
    """:class:`CandidateTable` (all discrete) and every number of its screening, per combination
    (:func:`designer.model.evaluate`: V_c, V_q, R_s, F_turn, P, the limits met)."""

    candidates: CandidateTable
    values: Casters


def candidate_table(problem, stock=None) -> ScreenedTable:
    """All-discrete stock of ``problem`` evaluated and screened by the model's evaluator.

    Raises ValueError if a variable is continuous (use :func:`recommend`, which solves the rest).
    """
    cand = stock_candidates(problem, stock)
    if not cand.discrete:
        raise ValueError("candidate_table needs every variable in the stock; a continuous one is solved by recommend()")
    values = evaluate(
        {name: getattr(cand, name) for name in VARIABLES},
        problem.conditions,
        inertia=cand.inertia,
        measured=cand.measured,
        required_speed=problem.required_speed,
        swept_radius_max=problem.swept_radius_max,
    )
    return ScreenedTable(cand, values)
