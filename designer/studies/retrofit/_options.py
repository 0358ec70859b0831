"""What a retrofit can change: the candidate values of each part and every combination of changed parts.

Part of :mod:`designer.studies.retrofit._retrofit`: the four parts and the
variable each sets, the candidate values from ``[stock]`` or a grid over the bounds (:func:`part_options`,
the one place that decides them), and the vectorised enumeration of one- to four-part changes.
"""

from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass

import numpy as np

from designer.data.paper import INCH
from designer.display import shown
from designer.model import Design
from designer.physics.inertia import Catalog, InertiaModel
from designer.problem import DEFAULT_PART_COSTS, PART_KINDS, Stock
from designer.units import written_size


PARTS = PART_KINDS
"""The four parts a retrofit can change, in the order they are listed (cheapest first)."""

PART_VARIABLE = {"washer": "damping", "tyre": "groove", "fork hole": "trail", "wheel": "diameter"}
"""The design variable each part sets (a catalogue wheel also sets groove and I_w)."""

GRID_STEP = {"trail": INCH / 16, "diameter": INCH / 16, "groove": INCH / 16, "damping": 0.1}
"""Step of the candidate grid [SI] for a variable that ``[stock]`` leaves continuous."""

_LENGTHS = ("trail", "diameter", "groove")


@dataclass(frozen=True)
class _Wheel:
    """A wheel on offer: diameter [m], groove [m] (NaN: takes any tyre), I_w [kg·m²], name, and whether its I_w
    was measured (else it is the inertia model's at d: a wheel known by its diameter)."""

    diameter: float
    groove: float
    inertia: float
    name: str | None
    measured: bool = True
    cost: float = DEFAULT_PART_COSTS["wheel"]


def part_options(problem, current: Design) -> tuple[dict, dict]:
    """What each part can be changed to: the one place that decides the candidate values.

    Returns ``(options, sources)``.  ``options``: {"washer": array of c_f,
    "tyre": array of B, "fork hole": array of T, "wheel": list of _Wheel},
    without the current value (no change is not an option).  ``sources`` says
    for each part where the values came from: ``[stock]`` (values that exist)
    or a grid over the problem's bounds (a key that ``[stock]`` leaves out
    leaves that variable continuous; the grid steps of :data:`GRID_STEP`
    stand in for it).

    A wheel from ``[stock] diameters`` takes I_w from the inertia model and
    keeps the current tyre profile only when that profile is on offer
    (``grooves``), otherwise it needs a tyre change too.  A catalogue wheel
    (``[stock] wheels``) brings its measured I_w (else the inertia model's)
    and its own groove when it lists one (then it is never combined with a
    tyre change); without one it takes a tyre like a ``diameters`` wheel.
    A tyre change keeps the current wheel and its I_w; when every catalogue
    wheel brings its own groove and no ``grooves`` are listed, tyres come
    only with wheels.  With ``[inertia] model = "catalog"`` the wheels are the
    problem's Table 1 wheels; a fixed inertia or diameter fixes the wheel.
    """
    keys = ("diameters", "grooves", "trails", "dampings", "wheels", "trail_step")  # a key left out: continuous
    stock = {key: value for key in keys if (value := getattr(problem.stock, key, None)) is not None}
    sources: dict[str, str] = {}
    dampings = _drop_current(_listed(stock, problem.bounds, sources, "dampings", "damping"), current.damping)
    if "trails" in stock:
        sources["trail"] = "[stock] (fork holes every trail_step from variables.trail.min)"
        trails = np.array(sorted(float(v) for v in stock["trails"]))
    else:
        trails = _listed(stock, problem.bounds, sources, "trails", "trail")
    trails = _drop_current(trails, current.trail)
    wheels, groove_values = _wheel_options(problem, stock, current, sources)
    if groove_values is None:
        groove_values = _listed(stock, problem.bounds, sources, "grooves", "groove")
    grooves = _drop_current(groove_values, current.groove)
    options = {"washer": dampings, "tyre": grooves, "fork hole": trails, "wheel": wheels}
    # a new wheel without its own groove keeps the current tyre profile only if that profile is on offer
    on_offer = "grooves" not in stock or bool(np.any(np.abs(groove_values - current.groove) <= 1e-9))
    sources = {part: sources.get(PART_VARIABLE[part], "") for part in PARTS} | {"_groove_on_offer": on_offer}
    priced = problem.stock if problem.stock is not None else Stock()
    costs = {part: np.array([priced.cost(part, float(v)) for v in options[part]]) for part in PARTS[:3]}
    costs["wheel"] = np.array([w.cost for w in wheels])
    return options | {"cost": costs}, sources


def _listed(stock: dict, bounds: dict, sources: dict, key: str, variable: str) -> np.ndarray:
    """The values of ``[stock] key`` within ``variable``'s bounds, else a grid over them; notes the source."""
    b = bounds[variable]
    values = stock.get(key)
    if values is not None:
        sources[variable] = "[stock]"
        values = np.array(sorted({float(v) for v in values}))
        return values[(values >= b.low * (1 - 1e-12)) & (values <= b.high * (1 + 1e-12))]  # within the bounds
    step = written_size(GRID_STEP[variable], "in") if variable in _LENGTHS else shown(GRID_STEP[variable], variable)
    sources[variable] = f"continuous (no [stock] {key}): grid over the bounds every {step}"
    if b.high <= b.low:
        return np.array([b.low])
    values = b.low + GRID_STEP[variable] * np.arange(int(math.floor((b.high - b.low) / GRID_STEP[variable] + 1e-9)) + 1)
    return np.append(values, b.high) if b.high - values[-1] > 1e-12 else values


def _drop_current(values: np.ndarray, value: float) -> np.ndarray:
    """``values`` without the current one (no change is not an option)."""
    values = np.asarray(values, dtype=float)
    return values[np.abs(values - value) > 1e-9 * max(1.0, abs(value))]


def _wheel_options(problem, stock: dict, current: Design, sources: dict) -> tuple[list[_Wheel], np.ndarray | None]:
    """The wheels on offer (catalogue, Table 1, none, or the stock diameters with the inertia model's I_w), and
    the groove values when the catalogue's wheels bring every tyre (else None: the tyres are listed apart)."""
    model: InertiaModel = problem.conditions.inertia
    bounds = problem.bounds
    wheels: list[_Wheel] = []
    catalogue = stock.get("wheels")
    groove_values = None
    if catalogue is not None:
        sources["diameter"] = "[stock] wheels (catalogue)"

        for entry in catalogue:
            d = float(entry.diameter)
            measured = entry.inertia is not None or bool(getattr(model, "measured", False))
            with warnings.catch_warnings(action="ignore"):  # extrapolation of the inertia fit: docs/retrofit.md
                i = float(model(d) if entry.inertia is None else entry.inertia)
            groove = math.nan if entry.groove is None else float(entry.groove)
            cost = problem.stock.cost("wheel") if entry.cost is None else float(entry.cost)
            wheels.append(_Wheel(d, groove, i, entry.name, measured, cost))
        if "grooves" not in stock and all(w.groove is not None for w in catalogue):
            sources["groove"] = "none on the current wheel (the catalogue's tyres come with its wheels)"
            groove_values = np.array([])
    elif problem.wheels:  # [inertia] model = "catalog": the Table 1 wheels of the problem
        sources["diameter"] = "the problem's Table 1 wheels ([inertia] wheels)"
        cost = problem.stock.cost("wheel") if problem.stock is not None else DEFAULT_PART_COSTS["wheel"]
        for key in problem.wheels:
            w = Catalog.from_key(key).wheel
            wheels.append(_Wheel(w.diameter, math.nan, w.inertia, f"Table 1 {w.key}", True, cost))
    elif model.fixed_diameter is not None or getattr(model, "name", "") == "fixed" or bounds["diameter"].fixed:
        sources["diameter"] = "none (the problem fixes the wheel: a fixed inertia or diameter)"
    else:
        diameters = _listed(stock, bounds, sources, "diameters", "diameter")

        with warnings.catch_warnings(action="ignore"):  # extrapolation of the inertia fit is stated in docs/retrofit.md
            inertias = np.asarray(model(diameters), dtype=float) * np.ones_like(diameters)
        measured = bool(getattr(model, "measured", False))
        priced = problem.stock if problem.stock is not None else Stock()
        wheels = [
            _Wheel(float(d), math.nan, float(i), None, measured, priced.cost("wheel", float(d)))
            for d, i in zip(diameters, inertias)
            if abs(d - current.diameter) > 1e-9
        ]
    return wheels, groove_values


def _enumerate(options: dict, sources: dict, base: dict, max_parts: int, min_parts: int = 1) -> dict:
    """Every combination of changed parts with min_parts..max_parts parts, as arrays (vectorised).

    Keys: trail, diameter, groove, damping, inertia (SI), measured (the wheel's I_w measured), parts (count), order
    (a stable index for ties), mask_<part> (bool: changed), wheel (index into
    options["wheel"], −1: kept), price (the sum of the changed parts' costs, ``options["cost"]``).
    """
    costs = options.get("cost", {})
    chunks = []
    counter = 0
    for k in range(min_parts, max_parts + 1):
        for parts in itertools.combinations(PARTS, k):
            sizes = [len(options[p]) for p in parts]
            if 0 in sizes:
                continue
            grids = np.meshgrid(*[np.arange(s) for s in sizes], indexing="ij")
            n = int(np.prod(sizes))
            out = _unchanged(n, base, parts)
            out["order"] = counter + np.arange(n)
            valid = np.ones(n, dtype=bool)
            for part, grid in zip(parts, grids):
                index = grid.ravel()
                if part in costs:
                    out["price"] = out["price"] + costs[part][index]
                if part != "wheel":
                    out[PART_VARIABLE[part]] = options[part][index]
                else:
                    wheels = options["wheel"]
                    out["wheel"] = index
                    out["diameter"] = np.array([wheels[i].diameter for i in index])
                    out["inertia"] = np.array([wheels[i].inertia for i in index])
                    out["measured"] = np.array([wheels[i].measured for i in index], dtype=bool)
                    own = np.array([wheels[i].groove for i in index])
                    has_own = np.isfinite(own)
                    if "tyre" in parts:
                        valid &= ~has_own  # a catalogue wheel comes with its own tyre
                    else:
                        out["groove"] = np.where(has_own, own, out["groove"])
                        if not sources["_groove_on_offer"]:
                            valid &= has_own  # a stock wheel needs a stock tyre: the current profile is not on offer
            counter += n
            chunks.append({key: value[valid] for key, value in out.items()})
    if not chunks:
        return _unchanged(0, base, ())
    return {key: np.concatenate([c[key] for c in chunks]) for key in chunks[0]}


def _unchanged(n: int, base: dict, parts: tuple) -> dict:
    """The columns of ``n`` candidates that change ``parts``, each still the current caster ``base`` (its
    variables, I_w, no wheel, no price, order 0 …): what :func:`_enumerate` fills in."""
    out = {key: np.full(n, float(base[key])) for key in ("trail", "diameter", "groove", "damping", "inertia")}
    return out | {
        "measured": np.full(n, bool(base.get("measured", True))),
        "wheel": np.full(n, -1),
        "price": np.zeros(n),
        "parts": np.full(n, len(parts)),
        "order": np.arange(n),
        **{f"mask_{part}": np.full(n, part in parts) for part in PARTS},
    }


def combinations(options: dict, max_parts: int = 4) -> int:
    """How many candidates of 1..``max_parts`` changed parts ``options`` give (before a wheel's tyre rules)."""
    sizes = [len(options[p]) for p in PARTS]
    return sum(
        int(np.prod([sizes[i] for i in c]))
        for k in range(1, max_parts + 1)
        for c in itertools.combinations(range(4), k)
    )
