"""What the studio shows, computed through the package's API (no web framework here).

The studio is a thin view of the records the studies return: the fronts come from :func:`designer.pareto_front`,
the recommendation, its alternatives and the buildable front from :func:`designer.recommend`, my caster and
its fixes (and the risk of a front point, which its record does not hold) from :func:`designer.fix`, the card's
sweeps from :func:`designer.studies.sweep.speed_sweeps`, θ(t) from :func:`designer.simulate`.  Nothing here
evaluates the model or re-states an equation: a number shown is a record's.
"""

from __future__ import annotations

import math
import threading
import time
import warnings
from collections import OrderedDict
from dataclasses import dataclass, field, fields, replace
from typing import TYPE_CHECKING

import numpy as np

from designer import display
from designer.errors import DesignerError
import designer.studio.helper as helper
from designer.model import Design
from designer.parameters import OUTPUT_TABLE
from designer.plots.caster import caster_svg
from designer.solvers.base import OBJECTIVES
from designer.studies.dynamics import simulate
from designer.studies.dynamics.limit_cycles import knock_safe_speeds
from designer.studies.recommend import recommend, with_spec
from designer.studies.retrofit import fix
from designer.studies.sweep import speed_sweeps

if TYPE_CHECKING:  # record types for the checker only: designer.studies.front loads casadi
    from designer.problem import Problem
    from designer.studies.front import Front
    from designer.studies.recommend import Recommendation

FIX_LIMIT = 100
"""Fixes listed for "my caster": the whole ranking within the limits up to this many (designer.fix evaluates
each listed fix by Monte Carlo, within the limits and beyond them, so the cost grows with this cap; how many
the default problem finds for a 1 in trail, 8 in wheel: docs/studio.md).  A longer ranking says it is the
top FIX_LIMIT of N and names ``designer fix`` for the rest."""

KNOCK_ANGLE = math.radians(20.0)
"""Size of the knock of the card's θ(t) [rad] (20°, the paper's design disturbance, Appendix C)."""


@dataclass
class Fronts:
    """Everything the chart and the recommendation panel draw for one problem.

    Attributes
    ----------
    problem : the validated problem
    continuous : nominal continuous front (Eq. 7 without scatter)
    risk : continuous risk-bounded front (P(V_c,true < V_req) <= α), or None without risk
    buildable : the buildable front (stock combinations), or None
    recommendation : designer.recommend's result, or None where this version has no recommend
    seconds : wall time of the computation [s]
    cpu_seconds : CPU time of the computing thread and of the helper process's job [s]
    notes : what could not be computed and why (one line each)
    """

    problem: Problem
    continuous: Front
    risk: Front | None = None
    buildable: Front | None = None
    recommendation: Recommendation | None = None
    seconds: float = 0.0
    cpu_seconds: float = 0.0
    notes: list[str] = field(default_factory=list)


LOCK = threading.RLock()
"""One computation at a time: the web server answers requests in threads, and CasADi's solvers are not
thread-safe (two fronts at once crash the process)."""


def _quiet(func, *args, **kwargs):
    with LOCK, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the page states the model's range; warnings would go to the console
        with np.errstate(all="ignore"):
            return func(*args, **kwargs)


_CACHE: OrderedDict = OrderedDict()
_CACHE_SIZE = 32

_FRONTS: OrderedDict = OrderedDict()
"""The fronts computed so far by :func:`front_key` (the last :data:`_CACHE_SIZE`): a change the front does not
depend on (α or σ for the nominal front, the stock for both) reuses it."""

FRONT_INDEPENDENT = (
    "name",
    "title",
    "description",
    "source",
    "stock",
    "weights",
    "max_threshold_force",
    "max_turning_effort",
    "choices",
)
"""Fields of a :class:`~designer.problem.Problem` that :func:`designer.pareto_front` does not read: the names, the
``[stock]`` (the buildable front's), the ``[objective]`` weights and caps (the recommendation's) and the
exploration's choices."""


IF_MEASURED = False
"""Whether the studio's recommendation finds its "if measured" variant (:func:`designer.recommend`'s
``if_measured``): nothing of the studio shows it, and it is a second pass over the stock (about 12 of a key
press's 35 ms of CPU of the recommendation); "Write report" computes its own as ``designer pareto`` does."""


def front_key(problem) -> str:
    """What a front of ``problem`` depends on: every field of the problem but :data:`FRONT_INDEPENDENT` (the
    conditions with the risk bound, the target speed and margin, the bounds, the swept-radius limit, the number
    of points, the catalogue wheels)."""
    return repr({f.name: getattr(problem, f.name) for f in fields(problem) if f.name not in FRONT_INDEPENDENT})


def compute_fronts(problem, key: str | None = None) -> Fronts:
    """The continuous, risk-bounded and buildable fronts and the recommendation of ``problem``.

    ``key`` (e.g. the canonical problem data) caches the result, so going back to a state is instant; the two
    continuous fronts are also kept by :func:`front_key`, so a control that one of them does not depend on
    recomputes only the other (and the recommendation).
    Raises the package's DesignerError (e.g. InfeasibleError naming the target to relax).
    """
    with LOCK:
        return _compute_fronts(problem, key)


def compute_spec(problem, key: str | None = None) -> Fronts:
    """:func:`compute_fronts` of ``problem`` with the recommended caster's spec (acceptance limits, worst corner:
    :func:`designer.studies.recommend.with_spec`, the spec :func:`designer.recommend` gives).

    The fronts are computed without it (about 0.1 s of CPU: the chart is drawn first); this adds it to the
    fronts cached for ``key``, so going back to a state shows its limits at once.
    """
    with LOCK:
        fronts = _compute_fronts(problem, key)
        rec = fronts.recommendation
        if rec is not None and rec.spec is None:
            fronts.recommendation = _quiet(with_spec, rec)
        return fronts


def cached(key: str):
    """The fronts computed earlier for ``key``, or None."""
    with LOCK:
        return _CACHE.get(key)


def _front(problem, computed=None):
    """:func:`designer.pareto_front` of ``problem``, kept by :func:`front_key` (the front of an equal key is
    returned as the front of ``problem``); ``computed``: that front, computed elsewhere (the helper process)."""
    from designer.studies.front import pareto_front  # casadi: loaded with the studio, not with `import designer`

    key = front_key(problem)
    front = _FRONTS.pop(key, None)
    if front is None:
        front = computed if computed is not None else _quiet(pareto_front, problem, knee=helper.KNEE)
    _FRONTS[key] = front
    while len(_FRONTS) > _CACHE_SIZE:
        _FRONTS.popitem(last=False)
    return front if front.problem is problem else replace(front, problem=problem)


def _compute_fronts(problem, key):
    if key is not None and key in _CACHE:
        _CACHE.move_to_end(key)
        return _CACHE[key]
    t0, c0 = time.perf_counter(), time.thread_time()
    out = Fronts(problem=problem, continuous=None)

    nominal = problem.nominal()
    # the risk-bounded front (else the nominal one) in the helper process, which designer studio starts, while
    # this one computes the recommendation and the other front
    wanted = [p for p in (problem if problem.risk is not None else None, nominal) if p is not None]
    missing = [p for p in wanted if front_key(p) not in _FRONTS]
    away = missing[0] if missing else None
    job = helper.submit(away) if away is not None else None
    # no spec: the chart first; the recommended caster's limits come a moment later (compute_spec)
    rec = _quiet(recommend, problem, specs="none", if_measured=IF_MEASURED)
    out.recommendation = rec
    out.buildable = getattr(rec, "buildable", None)
    fronts = {id(p): _front(p) for p in wanted if p is not away}  # here, while the helper computes its front
    done = helper.result(job)
    if away is not None:
        fronts[id(away)] = _front(away, done[0] if done else None)
    out.continuous = fronts[id(nominal)]
    out.risk = fronts[id(problem)] if problem.risk is not None else None
    out.seconds = time.perf_counter() - t0
    out.cpu_seconds = time.thread_time() - c0 + (done[1] if done else 0.0)
    if key is not None:
        _CACHE[key] = out
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    return out


def _points(front) -> list:
    """The points of ``front`` the chart draws (those with a design), in order; [] for None."""
    if front is None:
        return []
    return [p for p in getattr(front, "points", front) if getattr(p, "design", None) is not None]


def front_points(front) -> list[dict]:
    """Plain records of a front's points for the chart: the design, F_turn, P, V_c (each read from the point's
    record, :class:`designer.FrontPoint`) and its wheel's name; [] for None."""
    return [
        {
            "design": p.design.to_dict(),
            **{n: float(getattr(p, n)) for n in OBJECTIVES},
            "label": getattr(p, "wheel", None) or "",
        }
        for p in _points(front)
    ]


def recommendation_record(rec) -> dict | None:
    """The recommendation's headline numbers as plain data, each read from the record :func:`designer.recommend`
    returned (None without a recommendation): the caster to build, then every alternative with its role."""
    if rec is None:
        return None
    out = numbers_of(rec)
    out["rule"] = getattr(rec, "rule", None)
    spec = getattr(rec, "spec", None)
    out["limits"] = None if spec is None else list(spec.limits)  # None: not computed yet (compute_spec)
    out["joint"] = None if spec is None else spec.joint
    corner = None if spec is None else spec.corner
    out["corner"] = None if corner is None else (corner["probability"], corner["holds"])
    out["alternatives"] = [numbers_of(alt) for alt in getattr(rec, "alternatives", None) or []]
    return out


NUMBERS = (*OBJECTIVES, "confident_speed", "shimmy_probability", "swept_radius", "inertia")
"""The numbers of a caster the studio shows: F_turn, P, V_c, the speed reached w.p. 1 − α, P(shimmy) at the
target speed (the exact law), the swept radius and I_w."""


def numbers_of(record, risk=None) -> dict:
    """A caster's numbers as plain data, each read from ``record`` (a :class:`designer.Recommendation` or one
    of its alternatives, a :class:`designer.FrontPoint`, the ``current`` caster of :func:`designer.fix`) or from
    the :class:`~designer.model.Caster` it holds; ``risk``: the record of the same caster under the problem's
    risk law (:func:`designer.fix`'s diagnosis) for the speed reached and P(shimmy), which a front point does
    not hold.  A number no record has is None (shown as :data:`designer.display.MISSING`); ``more``: every other
    listed quantity of :data:`designer.parameters.OUTPUT_TABLE` the record's caster holds, by name."""
    caster = getattr(record, "caster", None)
    out: dict = {"design": record.design.to_dict()}
    for key in NUMBERS:
        source = risk if risk is not None and key in ("confident_speed", "shimmy_probability") else record
        value = getattr(source, key, None)
        if value is None and caster is not None and source is record:
            value = caster.get(key)
        out[key] = None if value is None or not math.isfinite(float(value)) else float(value)
    # every other quantity of the table the caster holds (θ_a, ω, ...): a quantity added to the table appears here
    out["more"] = {
        p.name: float(caster[p.name])
        for p in OUTPUT_TABLE
        if caster is not None and p.listed and p.name not in NUMBERS and caster.get(p.name) is not None
    }
    measured = getattr(record, "measured", None)
    out["measured"] = bool(caster.get("measured") if measured is None and caster is not None else measured)
    out["role"] = getattr(record, "role", None)
    out["wheel"] = getattr(record, "wheel", None)
    return out


# --------------------------------------------------------------------------- one caster: the card

CARD_PARTS = ("recommendation", "alternative", "continuous", "risk", "buildable")
"""What a card can show: the caster to build, one of its alternatives (by index), a point of a front."""


def card_record(fronts: Fronts, part: str, index: int = 0):
    """The record a card shows: the recommendation itself (``part`` "recommendation"), its alternative
    ``index``, or point ``index`` of the ``part`` front.  A point of the buildable front is the recommendation or
    the alternative it is (the same caster: their records hold its P(shimmy)).  KeyError, IndexError for a
    part or index the fronts do not have."""
    rec = fronts.recommendation
    if part == "recommendation":
        if rec is None:
            raise KeyError(part)
        return rec
    if part == "alternative":
        return (rec.alternatives if rec is not None else [])[index]
    if part not in CARD_PARTS:
        raise KeyError(part)
    point = _points({"continuous": fronts.continuous, "risk": fronts.risk, "buildable": fronts.buildable}[part])[index]
    if part == "buildable" and rec is not None:
        for candidate in (rec, *rec.alternatives):
            if candidate.design == point.design:
                return candidate
    return point


def card(problem, record, with_simulation: bool = True) -> dict:
    """Everything a caster's card shows: its numbers (from ``record``, :func:`numbers_of`; a front point's speed
    reached and P(shimmy) from :func:`designer.fix`'s diagnosis of it, the same risk law as the recommendation's),
    the knock-safe speeds, V_c against trail and diameter (:func:`designer.studies.sweep.speed_sweeps`), θ(t)
    after a knock and the drawing.  Nothing is evaluated twice: a recommendation's numbers are its own."""
    risk = None
    if getattr(record, "shimmy_probability", None) is None:  # a front point: no risk numbers of its own
        risk = _quiet(fix, problem, record.design, limit=0, specs=0).current
    numbers = numbers_of(record, risk)
    design = record.design
    out = {
        "numbers": numbers,
        "sweeps": _quiet(speed_sweeps, problem, design, numbers["inertia"], numbers["measured"]),
        "knock": None,
    }
    if with_simulation:
        try:
            out["knock"] = knock_response(problem, design)
        except DesignerError as exc:
            out["knock_error"] = str(exc)
        try:
            own = numbers["inertia"] if numbers["measured"] else None
            out["numbers"].update(knock_safe(problem, design, own))
        except DesignerError as exc:
            out["numbers"]["knock_safe_error"] = str(exc)
    out["svg"] = drawing_svg(problem, design)
    return out


def knock_response(problem, design: Design, angle: float = KNOCK_ANGLE) -> dict:
    """θ(t) after a knock of ``angle`` [rad] at the target speed (:func:`designer.simulate`, the problem's
    conditions)."""

    result = _quiet(
        simulate, design, problem.conditions, speed=problem.target_speed, angle=angle, samples_per_period=24
    )
    return {
        "t": np.asarray(result.t),
        "theta": np.asarray(result.theta),
        "grows": bool(result.grows),
        "diverged": bool(result.diverged),
        "growth_ratio": float(result.growth_ratio),
    }


def knock_safe(problem, design: Design, inertia: float | None = None) -> dict:
    """The design's knock-safe speeds for knocks of θ0 and 2 θ0 [m/s] (simulated, rolling tyre,
    :func:`designer.studies.dynamics.limit_cycles.knock_safe_speeds`; ``inertia``: a measured wheel's own I_w);
    about 0.05–0.1 s of CPU, so on a click only."""

    return _quiet(knock_safe_speeds, [design], problem.conditions, inertias=[inertia])[0].to_dict()


def drawing_svg(problem, design: Design) -> str | None:
    """The caster drawn to scale as SVG text, its sizes in the problem's units (:func:`designer.plots.caster.caster_svg`)."""

    return _quiet(
        caster_svg,
        design.trail,
        design.diameter,
        design.groove,
        problem.conditions.threshold_height,
        problem.swept_radius_max,
        units=problem.units,
    )


# --------------------------------------------------------------------------- my caster


def fix_command(path, design: Design, units: str = "in") -> str:
    """The ``designer fix`` command line that lists every fix of ``design`` for the problem file ``path``, its
    sizes in ``units`` (the problem's)."""

    def size(name: str) -> str:
        value = getattr(design, name)
        return display.number(value, name, units).rstrip("0").rstrip(".") + display.unit_text(name, units)

    return (
        f'designer fix {path} --current "T={size("trail")},d={size("diameter")},B={size("groove")},'
        f'c={display.number(design.damping, "damping", units)}"'
    )


def mine_record(problem, design: Design):
    """The record of a caster the user has: :func:`designer.fix`'s diagnosis of it (``current``: its numbers and
    its risk under the problem's risk law, the exact P(shimmy))."""
    return _quiet(fix, problem, current=design, limit=0, specs=0).current


def my_caster(problem, design: Design) -> dict:
    """A caster the user has: its numbers and risk for ``problem`` and its ranked fixes, each read from the
    record :func:`designer.fix` returns (``current`` and ``fixes``)."""
    result = _quiet(fix, problem, current=design, limit=FIX_LIMIT, specs=0)  # the list shows no limits
    out = {"numbers": numbers_of(result.current), "fix_note": None}
    out["found"] = int(getattr(result, "found", 0) or 0)
    out["command"] = fix_command(getattr(problem, "source", None) or f"{problem.name}.toml", design, problem.units)
    out["summary"] = result.summary() if hasattr(result, "summary") else ""
    out["meets_risk_bound"] = bool(result.current.meets_risk_bound)
    rows = []
    for rank, item in enumerate(getattr(result, "fixes", None) or [], start=1):
        changes = getattr(item, "changes", ()) or ()
        row = numbers_of(item)
        row.update(
            rank=rank,
            description="; ".join(c.describe() for c in changes) if changes else str(item),
            parts_changed=getattr(item, "parts_changed", len(changes)),
        )
        rows.append(row)
    out["fixes"] = rows
    return out
