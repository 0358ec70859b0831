"""The problem file's [stock] section: the diameters, grooves, trails, dampings and named wheels a
maker can build from (the "Build this caster" recommendation snaps to them).

Read by :func:`designer.problem._loader.problem_from_dict`; each error names the key, the value and the
reason, as the rest of the loader.
"""

from __future__ import annotations

import math
from typing import Any, Callable, NoReturn

from designer.data.paper import INCH
from designer.display import number, shown, unit_text
from designer.physics.inertia import Fixed, InertiaModel
from designer.problem._core import (
    DEFAULT_PART_COSTS,
    INERTIA_RANGE,
    PART_KINDS,
    Bound,
    Stock,
    StockWheel,
    inches,
    parsed,
    show_key,
)


def _cost(raw: object, key: str, fail: Callable[[str], NoReturn]) -> float:
    """A part's cost: a finite number >= 0 (relative units, any currency)."""
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw) or not 0 <= raw <= 1e9:
        fail(f"{key} = {raw!r}: expected a cost, a number from 0 to 1e9 (relative units, any currency)")
    return float(raw)


def _priced(table: dict[str, Any], key: str, fail: Callable[[str], NoReturn]) -> tuple[list[object], dict[int, float]]:
    """The raw entries of a [stock] list and the costs of those written ``{ value = ..., cost = ... }``, by
    position."""
    entries, costs = [], {}
    for i, raw in enumerate(table[key]):
        if isinstance(raw, dict):
            extra = sorted(set(raw) - {"value", "cost"})
            if extra or "value" not in raw or "cost" not in raw:
                fail(
                    f"stock.{key}[{i}] = {raw!r}: expected a value, or a table {{ value = ..., cost = ... }}"
                    + (f" (unknown key {extra[0]!r})" if extra else "")
                )
            costs[i] = _cost(raw["cost"], f"stock.{key}[{i}].cost", fail)
            raw = raw["value"]
        entries.append(raw)
    return entries, costs


def _stock_values(
    table: dict[str, Any],
    key: str,
    dimension: str,
    variable: str,
    bounds: dict[str, Bound],
    fail: Callable[[str], NoReturn],
    item_costs: dict[str, dict[float, float]] | None = None,
) -> tuple[float, ...]:
    """A [stock] list in SI, each value inside ``variable``'s bounds (deduplicated, sorted).  An entry may be a
    table ``{ value = "7 in", cost = 6 }``: its cost goes into ``item_costs[variable]``."""
    values = table[key]
    if isinstance(values, (str, int, float)) or not isinstance(values, list):
        fail(f'stock.{key} = {values!r}: expected a list, e.g. ["4 in", "5 in"]')
    if not values:
        fail(f"stock.{key} = []: empty; list at least one value, or leave the key out to keep {variable} continuous")
    values, costs = _priced(table, key, fail)
    out = []
    b = bounds[variable]
    for i, raw in enumerate(values):
        v = parsed(raw, dimension, f"stock.{key}[{i}]", fail)
        if not b.low * (1 - 1e-9) - 1e-12 <= v <= b.high * (1 + 1e-9) + 1e-12:
            span = f"[{number(b.low, variable, 'in')}, {number(b.high, variable, 'in')}] {unit_text(variable, 'in')}"
            where = f"{shown(v, variable, 'in')} outside variables.{variable} = {span}"
            fail(f"stock.{key}[{i}] = {raw!r}: {where}; widen the bounds or drop the part")
        out.append(min(max(v, b.low), b.high))
        if i in costs and item_costs is not None:
            item_costs.setdefault(variable, {})[out[-1]] = costs[i]
    return tuple(sorted(set(out)))


def _kind_costs(raw: object, fail: Callable[[str], NoReturn]) -> dict[str, float]:
    """``stock.costs``: the cost of one part of each kind (washer, tyre, fork_hole, wheel); the others keep their
    defaults (:data:`DEFAULT_PART_COSTS`)."""
    if not isinstance(raw, dict):
        fail(f"stock.costs = {raw!r}: expected a table, e.g. {{ washer = 1, tyre = 2, fork_hole = 3, wheel = 4 }}")
    costs = dict(DEFAULT_PART_COSTS)
    for key, value in raw.items():
        kind = key.replace("_", " ")
        if kind not in PART_KINDS:
            fail(f"stock.costs.{show_key(key)}: unknown part; expected washer, tyre, fork_hole, wheel")
        costs[kind] = _cost(value, f"stock.costs.{key}", fail)
    return costs


STOCK_LISTS = (("diameters", "length", "diameter"), ("grooves", "length", "groove"), ("dampings", "damping", "damping"))
"""The [stock] lists of values: key, dimension, design variable."""


def read_stock(
    table: dict[str, Any],
    bounds: dict[str, Bound],
    inertia: InertiaModel,
    catalog: tuple[str, ...],
    fail: Callable[[str], NoReturn],
) -> Stock:
    """Parse [stock] against the bounds [SI] and the inertia model I_w(d) [kg·m²] (one-line errors, exit 3).

    ``catalog`` are the problem's catalogue wheels; ``fail`` raises the loader's ProblemError.  Lengths in the file may carry
    units ("5 in"); the result is in SI.
    """
    if not table:
        fail("[stock] is empty; list diameters, grooves, trail_step or dampings (a key left out stays continuous)")
    model = getattr(inertia, "name", "")
    if "diameters" in table or "wheels" in table:
        key = "diameters" if "diameters" in table else "wheels"
        if catalog:
            fail(
                f'stock.{key}: not allowed with [inertia] model = "catalog"; the wheel stock is '
                f"[inertia].wheels ({', '.join(catalog)})"
            )
        if model == "fixed" or isinstance(inertia, Fixed):
            fail(
                f'stock.{key}: not allowed with [inertia] model = "fixed"; a fixed inertia is one measured '
                f"wheel, so the diameter is fixed (set variables.diameter to it)"
            )
    if "diameters" in table and "wheels" in table:
        fail("stock: give diameters (and grooves) or wheels, not both")
    items: dict[str, dict[float, float]] = {}
    diameters, grooves, dampings = (
        _stock_values(table, key, dimension, variable, bounds, fail, items) if key in table else None
        for key, dimension, variable in STOCK_LISTS
    )
    trails = step = None
    if "trail_step" in table:
        step, trails = _stock_trails(table, bounds["trail"], fail)
    wheels = _stock_wheels(table["wheels"], bounds, grooves, fail) if "wheels" in table else None
    costs = _kind_costs(table["costs"], fail) if "costs" in table else dict(DEFAULT_PART_COSTS)
    if set(table) == {"costs"}:
        fail("[stock] lists only costs; list the parts too (diameters, grooves, trail_step, dampings or wheels)")
    return Stock(
        diameters=diameters,
        grooves=grooves,
        trail_step=step,
        trails=trails,
        dampings=dampings,
        wheels=wheels,
        costs=costs,
        item_costs=items,
    )


def _stock_trails(table: dict[str, Any], b: Bound, fail: Callable[[str], NoReturn]) -> tuple[float, tuple[float, ...]]:
    """``stock.trail_step``: the step [m] and the fork holes from ``variables.trail.min`` every step up to max."""
    step = parsed(table["trail_step"], "length", "stock.trail_step", fail)
    span = max(b.high - b.low, 0.0)  # inverted bounds are validate()'s one-line error, not the step's
    if not step > 0 or not math.isfinite(step):
        fail(f'stock.trail_step = {table["trail_step"]!r}: must be a positive length, e.g. "0.25 in"')
    if b.low <= b.high and span <= 0:  # inverted trail bounds: validate() names variables.trail (min > max)
        fail(
            f"stock.trail_step = {table['trail_step']!r}: variables.trail is fixed at {inches(b.low)}; "
            f"leave trail_step out"
        )
    if b.low <= b.high and step > span * (1 + 1e-9):
        fail(
            f"stock.trail_step = {inches(step)}: larger than the trail range "
            f"{inches(b.low)} to {inches(b.high)} ({inches(span)}); use a smaller step"
        )
    count = int(math.floor(span / step + 1e-9)) + 1
    if count > 10_000:
        fail(
            f"stock.trail_step = {inches(step)}: {count} fork holes; use a step of at least "
            f"{span / 10_000 / INCH:.3g} in"
        )
    return step, tuple(min(b.low + k * step, b.high) for k in range(count))


def _stock_wheels(
    raw: object, bounds: dict[str, Bound], grooves: tuple[float, ...] | None, fail: Callable[[str], NoReturn]
) -> tuple[StockWheel, ...]:
    """``stock.wheels``: named wheels, each with a diameter and optionally a groove and a measured I_w."""
    if not isinstance(raw, list):
        fail(f"stock.wheels = {raw!r}: expected a list of {{name, diameter, groove, inertia}} tables")
    if not raw:
        fail("stock.wheels = []: empty; list at least one wheel, or leave the key out")
    names: set[str] = set()  # filled by each wheel read
    out = [_stock_wheel(i, w, names, bounds, fail) for i, w in enumerate(raw)]
    given = [w.groove is not None for w in out]
    if any(given) and not all(given):
        fail("stock.wheels: give a groove for every wheel or for none (then [stock].grooves or continuous)")
    if all(given) and grooves is not None:
        fail("stock: the wheels give their grooves; leave stock.grooves out")
    return tuple(out)


def _stock_wheel(
    i: int, w: object, names: set[str], bounds: dict[str, Bound], fail: Callable[[str], NoReturn]
) -> StockWheel:
    """``stock.wheels[i]``: a table {name, diameter, groove, inertia} whose name is not in ``names`` (added)."""
    if not isinstance(w, dict):
        fail(
            f"stock.wheels[{i}] = {w!r}: expected a table such as "
            f'{{ name = "Frog 5", diameter = "5 in", groove = "0.25 in" }}'
        )
    extra = sorted(set(w) - {"name", "diameter", "groove", "inertia", "cost"})
    if extra:
        fail(f"stock.wheels[{i}].{show_key(extra[0])}: unknown key; expected name, diameter, groove, inertia, cost")
    for need in ("name", "diameter"):
        if need not in w:
            fail(f"stock.wheels[{i}].{need}: missing")
    name = w["name"]
    if not isinstance(name, str) or not name.strip():
        fail(f"stock.wheels[{i}].name = {name!r}: expected a non-empty string")
    if name in names:
        fail(f"stock.wheels[{i}].name = {name!r}: listed twice")
    names.add(name)
    d = _stock_values({"diameter": [w["diameter"]]}, "diameter", "length", "diameter", bounds, fail)[0]
    g = (
        _stock_values({"groove": [w["groove"]]}, "groove", "length", "groove", bounds, fail)[0]
        if "groove" in w
        else None
    )
    inertia_w = None
    if "inertia" in w:
        inertia_w = parsed(w["inertia"], "inertia", f"stock.wheels[{i}].inertia", fail)
        if not INERTIA_RANGE[0] <= inertia_w <= INERTIA_RANGE[1]:
            fail(
                f"stock.wheels[{i}].inertia = {inertia_w:g} kg·m²: outside {INERTIA_RANGE[0]:g} to "
                f"{INERTIA_RANGE[1]:g} kg·m²"
            )
    cost = _cost(w["cost"], f"stock.wheels[{i}].cost", fail) if "cost" in w else None
    return StockWheel(name.strip(), d, g, inertia_w, cost)
