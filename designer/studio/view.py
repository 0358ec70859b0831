"""What the studio shows, computed through the package's API (no web framework here).

The studio is a thin view: the fronts come from :func:`designer.pareto_front`, the recommendation and the
buildable front from :func:`designer.recommend`, the fixes of "my caster" from :func:`designer.fix`, a
design's numbers from :func:`designer.evaluate` and its risk from the model's evaluator
(:func:`designer.model.evaluate`), θ(t) from :func:`designer.simulate`.  Nothing here re-states an
equation.
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

from designer.errors import DesignerError
import designer.studio.helper as helper
from designer.model import Design, evaluate
from designer.physics.inertia import Catalog, Fixed
from designer.units import INCH
from designer.plots.caster import caster_svg
from designer.studies.dynamics import simulate
from designer.studies.dynamics.limit_cycles import knock_safe_speeds
from designer.studies.recommend import recommend, with_spec
from designer.studies.retrofit import fix

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
        front = computed
    if front is None:
        front = _quiet(pareto_front, problem)
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
    rec = _quiet(recommend, problem, specs="none")
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


def wheel_inertia(problem, wheel) -> float | None:
    """The measured I_w [kg·m²] of a named wheel of ``problem`` (a Table 1 catalogue wheel or a ``[stock]``
    wheel), None for an unnamed one (then the problem's inertia model at the diameter applies)."""
    if problem is None or not wheel:
        return None
    if wheel in (getattr(problem, "wheels", None) or ()):
        return float(Catalog.from_key(wheel).wheel.inertia)
    stock = getattr(problem, "stock", None)
    for w in getattr(stock, "wheels", None) or ():
        if getattr(w, "name", None) == wheel and getattr(w, "inertia", None) is not None:
            return float(w.inertia)
    return None


def front_points(front) -> list[dict]:
    """Plain records of a front's points (design SI, F_turn, P, V_c, the wheel's own I_w or None) for the
    chart; [] for None."""
    if front is None:
        return []
    points = getattr(front, "points", front)
    problem = getattr(front, "problem", None)
    out = []
    for p in points:
        design = getattr(p, "design", None)
        if design is None:
            continue
        out.append(
            {
                "design": design.to_dict(),
                "turning_effort": float(p.turning_effort),
                "threshold_force": float(p.threshold_force),
                "critical_speed": float(getattr(p, "critical_speed", float("nan"))),
                "family": getattr(p, "family", "") or "",
                "label": getattr(p, "label", None) or getattr(p, "wheel", None) or "",
                "inertia": wheel_inertia(problem, getattr(p, "wheel", None)),
            }
        )
    return out


def recommendation_record(rec) -> dict | None:
    """The recommendation's headline numbers as plain data (None without a recommendation)."""
    if rec is None:
        return None
    keys = (
        "turning_effort",
        "threshold_force",
        "critical_speed",
        "confident_speed",
        "shimmy_probability",
        "shimmy_probability_se",
        "swept_radius",
        "swept_radius_max",
        "rule",
    )
    out = {k: getattr(rec, k, None) for k in keys}
    out["design"] = rec.design.to_dict()
    inertia = getattr(rec, "inertia", None)
    out["inertia"] = float(inertia) if inertia is not None and math.isfinite(float(inertia)) else None
    spec = getattr(rec, "spec", None)
    out["limits"] = (  # None: not computed yet (compute_spec)
        None if spec is None else [f"{lim.side} {lim.part.replace('_', ' ')} {lim.shown}" for lim in spec.limits]
    )
    corner = None if spec is None else spec.corner
    out["corner"] = None if corner is None else (corner["probability"], corner["holds"])
    out["alternatives"] = []
    for alt in getattr(rec, "alternatives", None) or []:
        out["alternatives"].append(
            {
                "label": getattr(alt, "role", None) or getattr(alt, "rule", ""),
                "design": alt.design.to_dict(),
                "turning_effort": alt.turning_effort,
                "threshold_force": alt.threshold_force,
            }
        )
    return out


# --------------------------------------------------------------------------- one design: the card


def design_numbers(problem, design: Design) -> dict:
    """A design's numbers for ``problem``: objectives, V_c, ω, P(shimmy) at the target, the speed reached w.p. 1-α.

    ``shimmy_probability`` is the Monte Carlo estimate of P(V_c,true < V_target) with the problem's scatter;
    ``confident_speed`` is the α-quantile of V_c,true, the speed reached without shimmy with probability
    1 − α (both from the model's evaluator, :func:`designer.model.evaluate`).  Both are None when the
    problem has no risk.
    """

    conditions = problem.conditions
    risk = problem.risk
    values = _quiet(
        evaluate, design, conditions, speed=problem.target_speed, risk=None if risk is None else problem.target_speed
    )
    out = {
        k: float(values[k])
        for k in ("turning_effort", "threshold_force", "critical_speed", "swept_radius", "inertia", "shimmy_frequency")
        if k in values
    }
    out["design"] = design.to_dict()
    out["target_speed"] = problem.target_speed
    out["swept_radius_max"] = problem.swept_radius_max
    out["alpha"] = None if risk is None else risk.probability
    out["shimmy_probability"] = out["shimmy_probability_se"] = out["confident_speed"] = None
    if risk is not None:
        out["shimmy_probability"] = float(values.shimmy_probability)
        out["shimmy_probability_se"] = float(values.shimmy_probability_se)
        out["confident_speed"] = float(values.confident_speed)
    return out


def speed_sweeps(problem, design: Design, n: int = 61) -> dict:
    """V_c (and its α-quantile with risk) against trail and against diameter around ``design``.

    Each sweep spans the problem's bounds of that variable (and ±50 % of the design's value if the
    bounds are fixed), the other variables held at the design's values; evaluated vectorised by
    :func:`designer.model.evaluate`.  Returns {"trail": {...}, "diameter": {...}} of arrays [SI].
    """
    conditions = problem.conditions
    out = {}
    for name in ("trail", "diameter"):
        b = problem.bounds[name]
        value = getattr(design, name)
        lo, hi = (b.low, b.high) if b.high > b.low else (0.5 * value, 1.5 * value)
        lo, hi = min(lo, value), max(hi, value)
        if name == "diameter":
            lo = max(lo, 2.05 * conditions.threshold_height)
        x = np.linspace(lo, hi, n)
        args = {k: np.full(n, getattr(design, k)) for k in ("trail", "diameter", "groove", "damping")}
        args[name] = x
        values = _quiet(evaluate, args, conditions)
        out[name] = {
            "x": x,
            "critical_speed": np.asarray(values.critical_speed, float),
            "confident_speed": np.asarray(values.confident_speed, float),
            "value": value,
        }
    return out


def knock_response(problem, design: Design, angle: float = KNOCK_ANGLE) -> dict:
    """θ(t) after a knock of ``angle`` [rad] at the target speed (:func:`designer.studies.dynamics._simulate.simulate`)."""

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


def knock_safe(problem, design: Design) -> dict:
    """The design's knock-safe speeds for knocks of θ0 and 2 θ0 [m/s] (simulated, rolling tyre: the report's
    card, :func:`designer.studies.dynamics.limit_cycles.knock_safe_speeds`); about 0.05–0.1 s of CPU, so on a click only."""

    return _quiet(knock_safe_speeds, [design], problem.conditions)[0].to_dict()


def drawing_svg(problem, design: Design) -> str | None:
    """The caster drawn to scale as SVG text (:func:`designer.plots.caster.caster_svg`)."""

    return _quiet(
        caster_svg,
        design.trail,
        design.diameter,
        design.groove,
        problem.conditions.threshold_height,
        problem.swept_radius_max,
    )


def card(problem, design: Design, with_simulation: bool = True, inertia: float | None = None) -> dict:
    """Everything a point's card shows: numbers (with the knock-safe speeds), sweeps, θ(t) and the drawing.

    ``inertia`` [kg·m²]: the wheel's own I_w when it is known (a catalogue or stock wheel, e.g. the
    recommendation's), else the problem's inertia model at the design's diameter.
    """
    if inertia is not None and math.isfinite(float(inertia)):
        problem = problem.replace(conditions=problem.conditions.replace(inertia=Fixed(float(inertia))))
    out = {"numbers": design_numbers(problem, design), "sweeps": speed_sweeps(problem, design)}
    out["knock"] = None
    if with_simulation:
        try:
            out["knock"] = knock_response(problem, design)
        except DesignerError as exc:
            out["knock_error"] = str(exc)
        try:
            out["numbers"].update(knock_safe(problem, design))
        except DesignerError as exc:
            out["numbers"]["knock_safe_error"] = str(exc)
    out["svg"] = drawing_svg(problem, design)
    return out


# --------------------------------------------------------------------------- my caster


def fix_command(path, design: Design) -> str:
    """The ``designer fix`` command line that lists every fix of ``design`` for the problem file ``path``."""
    return (
        f'designer fix {path} --current "T={design.trail / INCH:.4g}in,d={design.diameter / INCH:.4g}in,'
        f'B={design.groove / INCH:.4g}in,c={design.damping:.4g}"'
    )


def my_caster(problem, design: Design) -> dict:
    """A caster the user has: its numbers and risk for ``problem`` and the ranked fixes of :func:`designer.fix`."""
    out = {"numbers": design_numbers(problem, design), "fixes": None, "fix_note": None}

    result = _quiet(fix, problem, current=design, limit=FIX_LIMIT, specs=0)  # the list shows no limits
    out["found"] = int(getattr(result, "found", 0) or 0)
    out["command"] = fix_command(getattr(problem, "source", None) or f"{problem.name}.toml", design)
    out["summary"] = result.summary() if hasattr(result, "summary") else ""
    current = getattr(result, "current", None)
    if current is not None:  # the retrofit's own diagnosis of the caster as it is (same model)
        out["meets_risk_bound"] = bool(getattr(current, "meets_risk_bound", False))
    rows = []
    for rank, item in enumerate(getattr(result, "fixes", None) or [], start=1):
        changes = getattr(item, "changes", ()) or ()
        row = {
            "rank": rank,
            "description": "; ".join(c.describe() for c in changes) if changes else str(item),
            "parts_changed": getattr(item, "parts_changed", len(changes)),
        }
        for attr in ("turning_effort", "threshold_force", "critical_speed", "confident_speed", "shimmy_probability"):
            value = getattr(item, attr, None)
            if value is not None and math.isfinite(float(value)):
                row[attr] = float(value)
        design_ = getattr(item, "design", None)
        if design_ is not None:
            row["design"] = design_.to_dict()
        rows.append(row)
    out["fixes"] = rows
    return out
