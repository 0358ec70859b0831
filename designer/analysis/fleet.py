"""Product lines: a caster for every chair of a fleet, and the fewest part numbers for all of them.

A fleet is a table of chair configurations (``FLEET.csv``, one row per chair: load, sill height, target
speed, swept-radius limit, surface, turning mode, units sold).  The base problem gives everything else:
bounds, stock, risk bound, weights.  For each chair this module computes the recommendation of
``designer.recommend`` (issue "Build this caster") vectorised over chairs × stock casters:

1. every stock caster is screened against the chair's own constraints, deterministically:
   the risk bound ``shimmy_speed_quantile >= (1 + margin) V_target`` (V_c of Eq. 7 lowered by the
   scatter of the model, ``docs/fleet.md``), the swept radius T + d/2 <= R_max, and d/h > 2 (Eq. 4A);
2. turning effort F_turn (Eq. 9 with the turning model) and sill force P (Eq. 4A) of every caster for
   every chair, as (chairs × casters) arrays;
3. the buildable front of each chair (non-dominated feasible casters) and the rule of the base problem
   (the knee by default, or a cap on one objective), plus the two alternatives (easiest to turn,
   easiest over the sill).

V_c, its quantile and the swept radius depend on the caster only, so they are computed once per stock
caster; load, sill and speed enter per chair.  The reported P(shimmy) of each chair's caster is a
separate Monte Carlo estimate (:func:`monte_carlo`), timed on its own: that is the part worth a cluster.
With ``scheduler`` (a Dask address or ``"local"``) both run on Dask workers in chunks of chairs; the
client keeps reading, validation, the stock table, the K-median program and the report.
"""
from __future__ import annotations

import csv
import difflib
import io
import math
import re
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from designer.data.paper import INCH
from designer.errors import InputError, ProblemError
from designer.physics.geometry import swept_radius
from designer.physics.shimmy import critical_shimmy_speed
from designer.physics.threshold import threshold_force_ratio
from designer.physics.turning import MODES, SURFACES, added_damper_moment, sliding_turning_moment
from designer.units import parse_quantity

from designer.analysis.recommend import risk_screen, select_rows
from designer.analysis.recommend import confident_speed, stock_candidates
from designer.problem import Stock
from designer.analysis.kmedian import prune_candidates, solve_kmedian
from designer.problem import load_problem

GRAVITY = 9.80665
"""Standard gravity g [m/s²] for load = m g front_fraction / 2."""

COLUMNS = {
    "name": "text",
    "load": "force",
    "mass": "mass",
    "front_fraction": "dimensionless",
    "threshold_height": "length",
    "target_speed": "speed",
    "swept_radius_max": "length",
    "surface": "surface",
    "turning_mode": "mode",
    "count": "count",
}
"""Columns of FLEET.csv and their dimension; a unit may follow the name in the header (``load_N``)."""

REQUIRED = ("name", "threshold_height", "target_speed", "swept_radius_max", "surface", "turning_mode")
"""Columns every fleet needs; plus ``load`` or both ``mass`` and ``front_fraction``."""

UNIT_ALIASES = {"mps": "m/s", "m_s": "m/s", "kmh": "km/h", "kph": "km/h", "pct": "percent", "%": "percent",
                "lb": "lbf", "lbs": "lbf"}
"""Header unit spellings that pint does not read (``target_speed_mps``)."""

RANGES = {
    "load": (1.0, 1e5, "N", "a caster load of 0.1 kg to 10 t; was it given in another unit?"),
    "mass": (1.0, 2000.0, "kg", "user plus chair; was it given in another unit?"),
    "front_fraction": (0.0, 1.0, "", "the share of the weight on the two front casters, e.g. 0.4 or '40 %'"),
    "threshold_height": (1e-4, 0.3, "m", "a sill of 0.1 mm to 30 cm; were inches written as metres?"),
    "target_speed": (0.01, 100.0, "m/s", "plain numbers are m/s; was it given in km/h or mph?"),
    "swept_radius_max": (1e-3, 10.0, "m", "footrest clearances are a few inches; were inches written as metres?"),
}
"""Model range per column [SI] (same limits as the problem file's): outside it a row is an input error."""

MAX_CHAIRS = 10_000_000
"""Largest fleet read (rows)."""

CHUNK = 5000
"""Chairs per chunk of vectorised work (bounds memory: chunk × casters × 8 bytes per array)."""


# --------------------------------------------------------------------------- the fleet table


@dataclass
class Fleet:
    """Chair configurations, one entry per chair, SI units.

    Attributes
    ----------
    names : chair names (unique)
    load : caster load L [N] (given, or m g front_fraction / 2)
    threshold_height : sill height h [m]
    target_speed : V_target [m/s]
    swept_radius_max : R_max, footrest clearance [m]
    surface : "tile" | "carpet" per chair
    turning_mode : "chair" | "pivot" per chair
    count : units sold (weight of the chair in the part-number choice) [-]
    rows : line of each chair in the file (for messages)
    source : the file it was read from
    """

    names: list
    load: np.ndarray
    threshold_height: np.ndarray
    target_speed: np.ndarray
    swept_radius_max: np.ndarray
    surface: np.ndarray
    turning_mode: np.ndarray
    count: np.ndarray
    rows: np.ndarray | None = None
    source: str = "fleet"

    def __len__(self) -> int:
        return len(self.names)

    def subset(self, index) -> "Fleet":
        """The chairs at ``index`` (array of positions or a boolean mask)."""
        index = np.asarray(index)
        if index.dtype == bool:
            index = np.flatnonzero(index)
        return Fleet(names=[self.names[i] for i in index], load=self.load[index],
                     threshold_height=self.threshold_height[index], target_speed=self.target_speed[index],
                     swept_radius_max=self.swept_radius_max[index], surface=self.surface[index],
                     turning_mode=self.turning_mode[index], count=self.count[index],
                     rows=None if self.rows is None else self.rows[index], source=self.source)

    def arrays(self) -> dict:
        """The per-chair numbers as plain arrays (what a worker needs; no names)."""
        return {"load": self.load, "threshold_height": self.threshold_height, "target_speed": self.target_speed,
                "swept_radius_max": self.swept_radius_max, "surface": self.surface,
                "turning_mode": self.turning_mode}

    def problem(self, base, i: int):
        """The base problem with chair ``i``'s conditions: what ``designer.recommend`` takes for one chair."""
        conditions = base.conditions.replace(load=float(self.load[i]),
                                             threshold_height=float(self.threshold_height[i]),
                                             surface=str(self.surface[i]), turning_mode=str(self.turning_mode[i]))
        name = re.sub(r"[^A-Za-z0-9_.-]", "-", str(self.names[i]))[:64].lstrip("-_.") or "chair"
        return base.replace(name=name, conditions=conditions, target_speed=float(self.target_speed[i]),
                            swept_radius_max=float(self.swept_radius_max[i]), source=None)


def _split_header(header: str, source: str) -> tuple[str, str | None]:
    """``"load_N"`` -> ("load", "N"); ``"threshold_height [in]"`` -> ("threshold_height", "in")."""
    text = header.strip()
    match = re.fullmatch(r"(.+?)\s*[\[(]\s*(.+?)\s*[\])]", text)
    if match:
        base, unit = match.group(1).strip(), match.group(2)
        if base in COLUMNS:
            return base, unit
    if text in COLUMNS:
        return text, None
    for name in sorted(COLUMNS, key=len, reverse=True):
        if text.startswith(name + "_") and len(text) > len(name) + 1:
            return name, text[len(name) + 1:]
    known = ", ".join(COLUMNS)
    raise ProblemError(f"{source}: column {header!r}: unknown column{_suggest(text, list(COLUMNS))}; "
                       f"expected {known} (a unit may follow: load_N, threshold_height_in)")


def _suggest(word: str, options) -> str:
    base = re.split(r"[\s\[(]", word.strip())[0]
    for candidate in (word, base, base.rsplit("_", 1)[0]):
        match = difflib.get_close_matches(candidate, list(options), n=1, cutoff=0.75)
        if match:
            return f" (did you mean {match[0]!r}?)"
    return ""


def _header_factor(name: str, unit: str | None, source: str) -> float:
    """SI value of one header unit (1.0 when the header has none)."""
    dimension = COLUMNS[name]
    if unit is None:
        return 1.0
    if dimension in ("text", "surface", "mode", "count"):
        raise ProblemError(f"{source}: column {name}_{unit}: {name} takes no unit")
    unit = UNIT_ALIASES.get(unit, unit)
    try:
        return parse_quantity(f"1 {unit}", dimension, f"{source}: column {name} (unit {unit!r} in the header)")
    except InputError as exc:
        raise ProblemError(str(exc)) from None


def read_fleet(path, base=None) -> Fleet:
    """Read and validate FLEET.csv.

    Columns: ``name, load, threshold_height, target_speed, swept_radius_max, surface, turning_mode`` and an
    optional ``count``; ``mass`` [kg] and ``front_fraction`` [-] may replace ``load`` per row (load =
    m g front_fraction / 2).  Units go in the header (``load_N``, ``threshold_height_in``,
    ``threshold_height [in]``) or in the cells (``"0.5 in"``); plain numbers without either are SI.

    Raises
    ------
    ProblemError (exit 3)
        One line naming the row and the column: a missing column (by its expected name, with "did you
        mean" for a near miss), an unknown column, a unit of the wrong dimension, a duplicate name, an
        empty cell, a value outside the model's range, an unknown surface or turning mode.
    """
    path = Path(path)
    source = str(path)
    if not path.exists():
        raise ProblemError(f"{source}: no such fleet file")
    if path.is_dir():
        raise ProblemError(f"{source}: is a folder, expected a .csv fleet file")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ProblemError(f"{source}: cannot read it ({exc.__class__.__name__}: {exc})") from None
    return fleet_from_text(text, source=source)


def fleet_from_text(text: str, source: str = "fleet") -> Fleet:  # noqa: C901 - one check per column and unit form, each with its own one-line error
    """Parse CSV text into a validated :class:`Fleet` (see :func:`read_fleet`)."""
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ProblemError(f"{source}: empty file; expected a header line (name, load_N, threshold_height_in, ...)")
    reader = csv.reader(io.StringIO("\n".join(lines)))
    try:
        table = list(reader)
    except csv.Error as exc:
        raise ProblemError(f"{source}: not a CSV file ({exc})") from None
    header, body = table[0], table[1:]
    if len(body) > MAX_CHAIRS:
        raise ProblemError(f"{source}: {len(body)} rows; at most {MAX_CHAIRS} chairs")
    columns: dict[str, tuple[int, float, str | None]] = {}
    for pos, raw in enumerate(header):
        name, unit = _split_header(raw, source)
        if name in columns:
            raise ProblemError(f"{source}: column {raw!r}: {name} appears twice in the header")
        columns[name] = (pos, _header_factor(name, unit, source), unit)
    heads = [h.strip() for h in header]
    for name in REQUIRED:
        if name not in columns:
            raise ProblemError(f"{source}: missing column {name!r}{_suggest_missing(name, heads)}")
    if "load" not in columns and not ("mass" in columns and "front_fraction" in columns):
        if "mass" in columns or "front_fraction" in columns:
            missing = "front_fraction" if "mass" in columns else "mass"
            raise ProblemError(f"{source}: missing column {missing!r}{_suggest_missing(missing, heads)} "
                               f"(load = mass g front_fraction / 2 needs both)")
        raise ProblemError(f"{source}: missing column 'load'{_suggest_missing('load', heads)} "
                           f"(or give mass and front_fraction)")
    if not body:
        raise ProblemError(f"{source}: no chairs (only a header)")

    n = len(body)
    width = len(header)
    # physical line numbers (comments and blank lines skipped above)
    physical = [i + 1 for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.lstrip().startswith("#")]
    row_numbers = np.array(physical[1:1 + n] if len(physical) > n else range(2, n + 2))
    for r, cells in enumerate(body):
        if len(cells) != width:
            raise ProblemError(f"{source}: row {row_numbers[r]}: {len(cells)} cells, the header has {width}")

    def column(name: str) -> list[str]:
        pos = columns[name][0]
        return [cells[pos].strip() for cells in body]

    def numbers(name: str, optional: bool = False) -> np.ndarray:
        pos, factor, _ = columns[name]
        dimension = COLUMNS[name]
        out = np.empty(n)
        for r, cells in enumerate(body):
            cell = cells[pos].strip()
            if cell == "":
                if optional:
                    out[r] = np.nan
                    continue
                raise ProblemError(f"{source}: row {row_numbers[r]}, column {name}: empty; give a number"
                                   + (f" in {columns[name][2]}" if columns[name][2] else " (SI) or one with units"))
            try:
                out[r] = float(cell) * factor
            except ValueError:
                out[r] = _cell_quantity(cell, dimension, f"{source}: row {row_numbers[r]}, column {name}")
            if not math.isfinite(out[r]):
                raise ProblemError(f"{source}: row {row_numbers[r]}, column {name} = {cell!r}: must be finite")
        return out

    def check(name: str, values: np.ndarray, skip=None) -> None:
        low, high, unit, hint = RANGES[name]
        bad = ~((values >= low) & (values <= high)) if name != "front_fraction" else ~((values > 0) & (values <= 1))
        if skip is not None:
            bad &= ~skip
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise ProblemError(f"{source}: row {row_numbers[r]}, column {name} = {values[r]:g} {unit}".rstrip()
                               + f": outside the model's range {low:g} to {high:g} {unit}".rstrip() + f" ({hint})")

    names = column("name")
    seen: dict[str, int] = {}
    for r, name in enumerate(names):
        if not name:
            raise ProblemError(f"{source}: row {row_numbers[r]}, column name: empty; every chair needs a name")
        if name in seen:
            raise ProblemError(f"{source}: row {row_numbers[r]}, column name = {name!r}: duplicate name "
                               f"(first at row {row_numbers[seen[name]]})")
        seen[name] = r

    load = numbers("load", optional=True) if "load" in columns else np.full(n, np.nan)
    if "mass" in columns and "front_fraction" in columns:
        mass = numbers("mass", optional=True)
        fraction = numbers("front_fraction", optional=True)
        for r in range(n):
            given = (not math.isnan(load[r]), not math.isnan(mass[r]), not math.isnan(fraction[r]))
            if given[0] and (given[1] or given[2]):
                raise ProblemError(f"{source}: row {row_numbers[r]}, column load: give load or mass and "
                                   f"front_fraction, not both")
            if not given[0] and not (given[1] and given[2]):
                col = "mass" if not given[1] else "front_fraction"
                raise ProblemError(f"{source}: row {row_numbers[r]}, column {col}: empty; give load, or mass "
                                   f"and front_fraction")
        by_mass = np.isnan(load)
        check("mass", mass, skip=~by_mass)
        check("front_fraction", fraction, skip=~by_mass)
        load = np.where(by_mass, mass * GRAVITY * fraction / 2, load)
    else:
        empty = np.flatnonzero(np.isnan(load))
        if len(empty):
            raise ProblemError(f"{source}: row {row_numbers[empty[0]]}, column load: empty; give a number"
                               + (f" in {columns['load'][2]}" if columns["load"][2] else " (SI) or one with units"))
    check("load", load)
    values = {name: numbers(name) for name in ("threshold_height", "target_speed", "swept_radius_max")}
    for name, v in values.items():
        check(name, v)
    labels = {}
    for name, allowed in (("surface", SURFACES), ("turning_mode", MODES)):
        cells = column(name)
        for r, cell in enumerate(cells):
            if cell not in allowed:
                raise ProblemError(f"{source}: row {row_numbers[r]}, column {name} = {cell!r}: expected one of "
                                   f"{', '.join(allowed)}{_suggest(cell, allowed)}")
        labels[name] = np.array(cells, dtype=object)
    if "count" in columns:
        count = np.empty(n)
        for r, cell in enumerate(column("count")):
            try:
                value = float(cell) if cell else 1.0
            except ValueError:
                value = math.nan
            if not math.isfinite(value) or value < 0 or value != int(value) or value > 1e12:
                raise ProblemError(f"{source}: row {row_numbers[r]}, column count = {cell!r}: expected a whole "
                                   f"number of units sold, 0 or more")
            count[r] = value
    else:
        count = np.ones(n)
    return Fleet(names=names, load=load, threshold_height=values["threshold_height"],
                 target_speed=values["target_speed"], swept_radius_max=values["swept_radius_max"],
                 surface=labels["surface"], turning_mode=labels["turning_mode"], count=count,
                 rows=row_numbers, source=source)


def _suggest_missing(name: str, heads: list[str]) -> str:
    """" (did you mean 'threshold_heigth_in'?)" when a header is a near miss of the expected ``name``."""
    scored = []
    for h in heads:
        stem = re.split(r"\s*[\[(]", h)[0]
        for candidate in {stem, stem.rsplit("_", 1)[0], stem.rsplit("_", 2)[0]}:
            score = difflib.SequenceMatcher(None, name, candidate).ratio()
            scored.append((score, h))
    scored = [s for s in scored if s[0] >= 0.75]
    return f" (did you mean {max(scored)[1]!r}?)" if scored else ""


_CELL_CACHE: dict = {}


def _cell_quantity(cell: str, dimension: str, key: str) -> float:
    """A cell with units ("0.5 in") in SI; parsed by pint once per distinct text."""
    hit = _CELL_CACHE.get((cell, dimension))
    if hit is not None:
        return hit
    try:
        value = parse_quantity(cell, dimension, key)
    except InputError as exc:
        raise ProblemError(str(exc)) from None
    if len(_CELL_CACHE) < 100_000:
        _CELL_CACHE[(cell, dimension)] = value
    return value


# --------------------------------------------------------------------------- example fleets


EXAMPLE_RANGES = {
    "load": ("120–300 N per caster", "assumption: the spread the product-line issue asks for; the paper's "
             "slip and turning tests used 178 N (40 lb) per caster (Appendix C, Fig. 7), near the middle"),
    "threshold_height": ("0.25–0.75 in", "0.5 in is the paper's case (Fig. 2A) and the US accessibility limit "
                         "for door thresholds (2010 ADA Standards 404.2.5: 1/2 in, 3/4 in for existing "
                         "sliding doors); 0.25 in is an assumption for floor transitions"),
    "swept_radius_max": ("5–8 in", "assumption: footrest clearances of common manual chairs; the default "
                         "problem uses 6 in"),
    "target_speed": ("1.5–3.5 m/s", "assumption: above the paper's 1 m/s walking speed (where its E&J wheels "
                     "were near their critical speed) up to a fast push or a ramp; the default problem uses "
                     "2.5 m/s"),
    "surface": ("70 % tile, 30 % carpet", "assumption"),
    "turning_mode": ("85 % chair, 15 % pivot", "assumption"),
    "count": ("10–2000 units sold, log-uniform", "assumption"),
}
"""Ranges of ``designer fleet --example N`` and where each comes from."""


def example_fleet(n: int, seed: int = 0) -> Fleet:
    """A plausible fleet of ``n`` chairs, drawn uniformly within :data:`EXAMPLE_RANGES` (seeded).

    Loads 120–300 N, sills 0.25–0.75 in, footrest clearance 5–8 in, speeds 1.5–3.5 m/s; see
    :data:`EXAMPLE_RANGES` for the source of each range (several are assumptions, said so there).
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= MAX_CHAIRS:
        raise InputError(f"--example {n!r}: expected a number of chairs from 1 to {MAX_CHAIRS}")
    rng = np.random.default_rng(seed)
    width = len(str(n))
    return Fleet(
        names=[f"chair-{i + 1:0{width}d}" for i in range(n)],
        load=np.round(rng.uniform(120.0, 300.0, n), 1),
        threshold_height=np.round(rng.uniform(0.25, 0.75, n), 3) * INCH,
        target_speed=np.round(rng.uniform(1.5, 3.5, n), 2),
        swept_radius_max=np.round(rng.uniform(5.0, 8.0, n), 2) * INCH,
        surface=np.where(rng.random(n) < 0.7, "tile", "carpet").astype(object),
        turning_mode=np.where(rng.random(n) < 0.85, "chair", "pivot").astype(object),
        count=np.round(np.exp(rng.uniform(np.log(10), np.log(2000), n))),
        rows=np.arange(2, n + 2), source=f"example-{n}")


def write_fleet_csv(fleet: Fleet, path) -> Path:
    """Write a fleet as FLEET.csv with units in the header (the format :func:`read_fleet` reads)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = ["# Example fleet written by `designer fleet --example`; ranges and their sources: docs/fleet.md",
             "name,load_N,threshold_height_in,target_speed_m/s,swept_radius_max_in,surface,turning_mode,count"]
    for i in range(len(fleet)):
        lines.append(f"{fleet.names[i]},{fleet.load[i]:.1f},{fleet.threshold_height[i] / INCH:.3f},"
                     f"{fleet.target_speed[i]:.2f},{fleet.swept_radius_max[i] / INCH:.2f},{fleet.surface[i]},"
                     f"{fleet.turning_mode[i]},{int(fleet.count[i])}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


# --------------------------------------------------------------------------- the stock


@dataclass
class StockTable:
    """Every stock caster of the base problem as arrays (one entry per combination), SI.

    Attributes
    ----------
    trail, diameter, groove, damping : the design [m, m, m, N·m/rad]
    inertia : I_w of the wheel [kg·m²]
    wheel : wheel name per caster (catalogue) or ""
    critical_speed : V_c, Eq. 7 [m/s]
    design_speed : what the risk bound compares with (1 + margin) V_target: the α-quantile of V_c
        (``shimmy_speed_quantile``) or V_c itself when the risk bound is off [m/s]
    confident_speed : the speed reached with probability 1 − α [m/s] (= design_speed)
    swept_radius : T + d/2 [m]
    note : where the stock comes from
    """

    trail: np.ndarray
    diameter: np.ndarray
    groove: np.ndarray
    damping: np.ndarray
    inertia: np.ndarray
    wheel: np.ndarray
    critical_speed: np.ndarray = field(default=None)
    design_speed: np.ndarray = field(default=None)
    swept_radius: np.ndarray = field(default=None)
    note: str = ""

    def __len__(self) -> int:
        return len(self.trail)

    def design(self, j: int) -> dict:
        """Stock caster ``j`` as {trail, diameter, groove, damping} [SI]."""
        return {"trail": float(self.trail[j]), "diameter": float(self.diameter[j]), "groove": float(self.groove[j]),
                "damping": float(self.damping[j])}


DEFAULT_STOCK = {
    "diameters": [3.0, 4.0, 5.0, 6.0, 8.0],
    "grooves": [0.0, 0.25, 0.5625],
    "trail_step": 0.25,
    "dampings": [1.3, 2.0, 3.0],
}
"""Stock used when the base problem declares none [in, in, in, N·m/rad]: common caster sizes, the
tyre profiles of the paper (plain, 1/4 in, 9/16 in groove), fork holes every 1/4 in, bare bearing and
two friction washers.  Values outside the problem's bounds are left out."""


def risk_of(problem):
    """The risk bound in force (``problem.risk`` when the problem has it, else its [robust] uncertainty)."""
    if hasattr(problem, "risk"):
        return problem.risk
    return problem.conditions.uncertainty


def _uncertainty_module():
    # the V_c quantile and the Monte Carlo live in physics/uncertainty.py (earlier: designer/robust.py)
    try:
        from designer.physics import uncertainty as module
    except ImportError:  # pragma: no cover - before the restructure
        from designer import robust as module
    return module


def stock_table(problem) -> StockTable:
    """All stock combinations of the base problem, with V_c, its quantile and the swept radius.

    The enumeration is :func:`designer.analysis.recommend.stock_candidates` (the single owner): the
    problem's ``[stock]`` when it declares one, otherwise :data:`DEFAULT_STOCK` within its bounds (the
    table's ``note`` says so).  Every variable must be discrete: a part number is a design tuple.
    """

    if getattr(problem, "stock", None) is not None:
        cand = stock_candidates(problem)
        note = "the base problem's [stock]"
    else:
        cand = stock_candidates(problem, _default_stock(problem))
        note = "the base problem has no [stock]; default stock within its bounds (docs/fleet.md)"
    stock_key = {"trail": "trail_step", "diameter": "diameters", "groove": "grooves", "damping": "dampings"}
    for key in ("trail", "diameter", "groove", "damping"):
        if cand.get(key) is None:
            raise ProblemError(f"{problem.source or problem.name}: stock.{stock_key[key]}: missing, so {key} stays "
                               f"continuous; a fleet's part numbers are stock casters, so list every variable in "
                               f"[stock] (docs/fleet.md)")
    table = StockTable(trail=cand.trail, diameter=cand.diameter, groove=cand.groove, damping=cand.damping,
                       inertia=np.asarray(cand.inertia, float), wheel=np.asarray(cand.wheel, dtype=object), note=note)
    c = problem.conditions
    table.critical_speed = critical_shimmy_speed(table.trail, table.inertia, table.groove, table.damping,
                                                 c.slip_coefficient)
    table.design_speed = np.asarray(confident_speed(table.trail, table.inertia, table.groove, table.damping,
                                                    c.slip_coefficient, risk_of(problem)), float)
    table.swept_radius = swept_radius(table.trail, table.diameter)
    return table


def _default_stock(problem):
    """:data:`DEFAULT_STOCK` within the problem's bounds, as a :class:`designer.problem.Stock`."""

    b = problem.bounds

    def within(values, name):
        lo, hi = b[name].low, b[name].high
        kept = [v for v in values if lo - 1e-12 <= v <= hi + 1e-12]
        return tuple(kept or [lo])

    step = DEFAULT_STOCK["trail_step"] * INCH
    lo, hi = b["trail"].low, b["trail"].high
    trails = tuple(lo + step * np.arange(int(math.floor((hi - lo) / step + 1e-9)) + 1))
    return Stock(diameters=None if problem.wheels or b["diameter"].fixed else
                 within([v * INCH for v in DEFAULT_STOCK["diameters"]], "diameter"),
                 grooves=within([v * INCH for v in DEFAULT_STOCK["grooves"]], "groove"), trail_step=step,
                 trails=trails, dampings=within(DEFAULT_STOCK["dampings"], "damping"))


# --------------------------------------------------------------------------- vectorised recommendation


RESULT_FIELDS = ("choice", "easiest_turn", "easiest_sill", "best_j", "front_size", "turning_effort",
                 "threshold_force", "objective", "reason")


def evaluate_chairs(chairs: dict, stock: StockTable, problem) -> dict:
    """Turning effort, sill force and feasibility of every stock caster for every chair (chairs × casters).

    Parameters
    ----------
    chairs : per-chair arrays ``load`` [N], ``threshold_height`` [m], ``target_speed`` [m/s],
        ``swept_radius_max`` [m], ``surface``, ``turning_mode`` (as :meth:`Fleet.arrays`)
    stock : the stock table (V_c and its quantile already per caster)
    problem : the base problem (margin, turning constants, disturbance angle)

    Returns
    -------
    dict of (chairs, casters) arrays: ``turning_effort`` F_turn [N] (Eq. 9 with the turning model),
    ``threshold_force`` P [N] (Eq. 4A; +inf where d/h <= 2), ``feasible`` (risk bound, swept radius,
    sill), and per-chair boolean (chairs,) ``any_risk``, ``any_radius``, ``any_sill`` for the reasons.
    """
    c = problem.conditions
    load = np.asarray(chairs["load"], float)
    height = np.asarray(chairs["threshold_height"], float)
    n, s = len(load), len(stock)
    effort = np.empty((n, s))
    damper = added_damper_moment(stock.damping, c.disturbance_angle, c.turning)
    for surface in SURFACES:
        for mode in MODES:
            rows = np.flatnonzero((chairs["surface"] == surface) & (chairs["turning_mode"] == mode))
            if len(rows):
                moment = sliding_turning_moment(load[rows, None], stock.groove[None, :], surface, mode, c.turning)
                effort[rows] = (moment + damper[None, :]) / stock.trail[None, :]
    diameters, inverse = np.unique(stock.diameter, return_inverse=True)
    climbs = diameters[None, :] > 2 * height[:, None]
    safe = np.where(climbs, diameters[None, :], 3 * height[:, None])
    ratio = np.where(climbs, threshold_force_ratio(safe, height[:, None]), np.inf)
    force = load[:, None] * ratio[:, inverse]
    required = (1 + problem.margin) * np.asarray(chairs["target_speed"], float)
    risk_ok = risk_screen(stock.design_speed[None, :], required[:, None])
    radius_ok = stock.swept_radius[None, :] <= np.asarray(chairs["swept_radius_max"], float)[:, None] * (1 + 1e-9)
    sill_ok = climbs[:, inverse]
    return {"turning_effort": effort, "threshold_force": force, "feasible": risk_ok & radius_ok & sill_ok,
            "any_risk": risk_ok.any(axis=1), "any_radius": radius_ok.any(axis=1), "any_sill": sill_ok.any(axis=1),
            "required": required}


# long: the vectorised rule is one pass over chairs x stock (screen, front, knee, alternatives)
def recommend_chairs(chairs: dict, stock: StockTable, problem) -> dict:
    """The recommendation of every chair, vectorised: buildable front, rule, alternatives.

    For each chair: the feasible stock casters (:func:`evaluate_chairs`), their non-dominated set in
    (F_turn, P) (the buildable front), and the stock index chosen by the base problem's rule: the knee of
    the front (the point farthest from the chord between its two ends, in objectives normalised to the
    front's range, toward the ideal point; with fewer than three points the end with the least J), or, with
    a cap on one objective, the best on the other within the cap.  Also the easiest-to-turn and
    easiest-over-the-sill ends and the least J = w_turn F_turn + w_threshold P (the regret baseline).

    Returns
    -------
    dict of (chairs,) arrays: ``choice``, ``easiest_turn``, ``easiest_sill``, ``best_j`` (stock indices,
    −1 if the chair has no feasible caster), ``front_size``, ``turning_effort`` [N], ``threshold_force`` [N]
    and ``objective`` J of the choice, ``reason`` (empty, or why the chair is infeasible).
    """
    ev = evaluate_chairs(chairs, stock, problem)
    f, p, ok = ev["turning_effort"], ev["threshold_force"], ev["feasible"]
    n, s = f.shape
    fm = np.where(ok, f, np.inf)
    rows = np.arange(n)
    # P depends on the wheel diameter only (Eq. 4A), so casters of one diameter share P and only the
    # least-F allowed one of each diameter can be on the front (ties: the lowest stock index).  Reduce
    # to one candidate per diameter first: (chairs × diameters) instead of (chairs × casters).
    _, group = np.unique(stock.diameter, return_inverse=True)
    perm = np.argsort(group, kind="stable")
    counts = np.bincount(group)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    fperm = fm[:, perm]
    gmin = np.minimum.reduceat(fperm, starts, axis=1)
    position = np.where(fperm == np.repeat(gmin, counts, axis=1), np.arange(s), s)
    gstock = perm[np.minimum(np.minimum.reduceat(position, starts, axis=1), s - 1)]
    gp = np.where(np.isfinite(gmin), np.take_along_axis(p, gstock, axis=1), np.inf)
    w = np.asarray(problem.weights, float)
    j = np.where(ok, w[0] * f + w[1] * p, np.inf)
    best_j = np.where(ok.any(axis=1), np.argmin(j, axis=1), -1)
    cap_p = getattr(problem, "max_threshold_force", None)
    cap_f = getattr(problem, "max_turning_effort", None)
    # the buildable front and the rule: designer.analysis.recommend.select_rows (the single owner of the rule)
    sel = select_rows(gmin, gp, np.isfinite(gmin), problem.weights, cap_p, cap_f)

    def stock_index(k):
        return np.where(k >= 0, np.take_along_axis(gstock, np.maximum(k, 0)[:, None], axis=1)[:, 0], -1)

    choice, easiest_turn, easiest_sill = (stock_index(sel[k]) for k in ("choice", "easiest_turn", "easiest_sill"))
    size, no_cap = sel["front_size"], sel["over_cap"]

    sel = np.maximum(choice, 0)
    reason = np.full(n, "", dtype=object)
    for i in np.flatnonzero(choice < 0):
        reason[i] = _reason(i, ev, stock, no_cap[i], cap_p, cap_f)
    return {"choice": choice, "easiest_turn": easiest_turn, "easiest_sill": easiest_sill, "best_j": best_j,
            "front_size": size, "turning_effort": np.where(choice >= 0, f[rows, sel], np.nan),
            "threshold_force": np.where(choice >= 0, p[rows, sel], np.nan),
            "objective": np.where(choice >= 0, j[rows, sel], np.nan), "reason": reason}


def _reason(i, ev, stock, over_cap, cap_p, cap_f) -> str:
    """Why chair ``i`` gets no caster, in one phrase."""
    if over_cap:
        cap = f"sill force <= {cap_p:.1f} N" if cap_p is not None else f"turning effort <= {cap_f:.2f} N"
        return f"infeasible: no buildable caster within the cap {cap}"
    missing = []
    if not ev["any_risk"][i]:
        missing.append(f"risk bound (best confident speed {stock.design_speed.max():.2f} m/s < required "
                       f"{ev['required'][i]:.2f} m/s)")
    if not ev["any_radius"][i]:
        missing.append(f"swept radius (smallest {stock.swept_radius.min() / INCH:.2f} in)")
    if not ev["any_sill"][i]:
        missing.append(f"sill (largest wheel {stock.diameter.max() / INCH:.2f} in <= twice the sill)")
    if missing:
        return "infeasible: no stock caster meets the " + "; ".join(missing)
    return "infeasible: no stock caster meets the risk bound, the swept radius and the sill at once"


def _chunk_task(chairs: dict, stock: StockTable, problem) -> dict:
    """One chunk of chairs on a worker: plain arrays in, plain arrays out (nothing else crosses the wire)."""
    return recommend_chairs(chairs, stock, problem)


def _split(fleet: Fleet, chunk: int) -> list[tuple[int, dict]]:
    arrays = fleet.arrays()
    return [(start, {k: v[start:start + chunk] for k, v in arrays.items()}) for start in range(0, len(fleet), chunk)]


# --------------------------------------------------------------------------- Monte Carlo of the choice


def _mc_task(designs: np.ndarray, inertia: np.ndarray, speeds: np.ndarray, slip: float, uncertainty) -> np.ndarray:
    """P(shimmy) and its SE for each (design, speed) row: the numbers of ``shimmy_probability_mc``.

    That estimate draws one seeded stream per call, so every speed asked of one caster sees the same
    first ``samples`` draws.  Rows of one caster therefore share one draw of V_c,true (the same stream,
    by the module's own ``sample_log_factors``), and each speed counts the draws below it; a row whose
    estimate would need more draws for SE <= 0.1 pp (P above about 5 %) calls the function itself.
    ``tests/test_fleet.py`` checks that both give identical numbers.
    """
    module = _uncertainty_module()
    mc = module.shimmy_probability_mc
    out = np.empty((len(speeds), 2))
    target = getattr(module, "MC_TARGET_SE", None)
    batch = hasattr(module, "sample_log_factors") and uncertainty.samples <= 1_000_000
    key = np.column_stack([designs, inertia])
    start = 0
    while start < len(speeds):
        stop = start + 1
        while stop < len(speeds) and np.array_equal(key[stop], key[start]):
            stop += 1
        t, _d, g, c = (float(x) for x in designs[start])
        i_w = float(inertia[start])
        rows = range(start, stop)
        if batch and stop - start > 1:
            n = int(uncertainty.samples)
            f = module.sample_log_factors(uncertainty, n, np.random.default_rng(uncertainty.seed))
            v = np.sort(critical_shimmy_speed(t, i_w * np.exp(f["inertia"]), g, c * np.exp(f["damping"]),
                                              slip * np.exp(f["slip"])) * np.exp(f["model"]))
            hits = np.searchsorted(v, speeds[start:stop], side="left")
            p = hits / n
            var = np.maximum(p * (1 - p), 1.0 / n)
            done = np.ones(len(p), bool) if target is None else np.ceil(var / target**2) <= n
            out[start:stop, 0] = p
            out[start:stop, 1] = np.sqrt(var / n)
            rows = [start + r for r in np.flatnonzero(~done)]
        for r in rows:
            out[r] = mc(t, i_w, g, c, slip, float(speeds[r]), uncertainty)
        start = stop
    return out


def mc_uncertainty(problem):
    """The uncertainty the reported P(shimmy) uses: the problem's risk, or the default scatter when it is off."""
    risk = risk_of(problem)
    if risk is None:
        risk = _uncertainty_module().Uncertainty()
    return risk


# --------------------------------------------------------------------------- the whole fleet


@dataclass
class FleetResult:
    """Per-chair recommendations of a fleet, and the part numbers when asked for.

    Attributes
    ----------
    fleet : the chairs
    stock : the stock table
    problem : the base problem
    chairs : per-chair arrays (:func:`recommend_chairs` fields, plus ``shimmy_probability`` and ``_se``)
    skus : the K-median solution for ``--skus K`` (or None), and ``curve`` K -> solution
    timings : wall times [s] per stage
    """

    fleet: Fleet
    stock: StockTable
    problem: object
    chairs: dict
    skus: object | None = None
    curve: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    scheduler: str | None = None
    regret_cost: object | None = None

    @property
    def feasible(self) -> np.ndarray:
        """Chairs with a recommendation (the others are reported with their reason)."""
        return self.chairs["choice"] >= 0

    def rows(self) -> list[dict]:
        """One dict per chair: the columns of fleet.csv (SI)."""
        ch = self.chairs
        out = []
        sku = None if self.skus is None or self.skus.assignment is None else self.skus
        sku_index = {} if sku is None else {j: i + 1 for i, j in enumerate(sku.chosen)}
        position = np.cumsum(self.feasible) - 1
        for i in range(len(self.fleet)):
            j = int(ch["choice"][i])
            row = {"name": self.fleet.names[i]}
            design = self.stock.design(j) if j >= 0 else dict.fromkeys(("trail", "diameter", "groove", "damping"))
            row.update(design)
            row["turning_effort"] = float(ch["turning_effort"][i]) if j >= 0 else None
            row["threshold_force"] = float(ch["threshold_force"][i]) if j >= 0 else None
            p = ch.get("shimmy_probability")
            row["shimmy_probability"] = None if p is None or j < 0 else float(p[i])
            row["shimmy_probability_se"] = None if p is None or j < 0 else float(ch["shimmy_probability_se"][i])
            if sku is not None:
                a = int(sku.assignment[position[i]]) if j >= 0 else -1
                row["sku"] = sku_index.get(a) if a >= 0 else None
                row["sku_turning_effort"] = float(self.regret_cost["turning_effort"][position[i], a]) if a >= 0 else None
                row["sku_threshold_force"] = float(self.regret_cost["threshold_force"][position[i], a]) if a >= 0 else None
                sp = ch.get("sku_shimmy_probability")
                row["sku_shimmy_probability"] = None if sp is None or a < 0 else float(sp[i])
            row["status"] = "ok" if j >= 0 else str(ch["reason"][i])
            out.append(row)
        return out

    def sku_records(self) -> list[dict]:
        """``[{"id", "design", "chairs", "count"}]`` of the chosen part numbers."""
        if self.skus is None or self.skus.assignment is None:
            return []
        feasible = np.flatnonzero(self.feasible)
        out = []
        for k, j in enumerate(self.skus.chosen):
            mine = feasible[self.skus.assignment == j]
            out.append({"id": k + 1, "design": self.stock.design(j), "wheel": str(self.stock.wheel[j]) or None,
                        "chairs": len(mine), "count": int(self.fleet.count[mine].sum())})
        return out


def fleet_recommendations(fleet: Fleet, problem, skus: int | None = None, k_max: int | None = None,
                          scheduler=None, monte_carlo: bool = True, chunk: int = CHUNK,
                          time_limit: float = 120.0) -> FleetResult:
    """Recommend a caster for every chair of ``fleet`` and, with ``skus``, choose K part numbers.

    Parameters
    ----------
    fleet : the chairs (:func:`read_fleet` or :func:`example_fleet`)
    problem : the base problem (bounds, stock, risk, weights)
    skus : K, the number of part numbers (None: per-chair recommendations only)
    k_max : regret curve for K = 1 … k_max (default max(K, 8), at most the number of useful casters)
    scheduler : None (in-process), a Dask scheduler address ``"tcp://host:8786"``, ``"local"`` (a
        2-worker LocalCluster), or a ``distributed.Client``
    monte_carlo : also estimate each chair's P(shimmy) (the reported number; the expensive part)
    chunk : chairs per task
    time_limit : per-K limit of the mixed-integer solve [s]

    Returns
    -------
    FleetResult
    """
    if skus is not None:
        if isinstance(skus, bool) or not isinstance(skus, (int, np.integer)) or skus < 1:
            raise InputError(f"--skus {skus!r}: expected a whole number of part numbers, 1 or more")
    timings = {}
    start = time.perf_counter()
    stock = stock_table(problem)
    if skus is not None and skus > len(stock):
        raise InputError(f"--skus {skus}: larger than the stock ({len(stock)} casters); choose at most {len(stock)}")
    timings["stock"] = time.perf_counter() - start

    client, own = _client(scheduler)
    try:
        start = time.perf_counter()
        parts = _split(fleet, chunk)
        if client is None:
            results = [recommend_chairs(arrays, stock, problem) for _, arrays in parts]
        else:
            stock_f = client.scatter(stock, broadcast=True, hash=False)
            problem_f = client.scatter(problem, broadcast=True, hash=False)
            futures = [client.submit(_chunk_task, arrays, stock_f, problem_f, pure=False) for _, arrays in parts]
            results = client.gather(futures)
        chairs = {k: np.concatenate([r[k] for r in results]) for k in results[0]}
        timings["recommend"] = time.perf_counter() - start
        result = FleetResult(fleet=fleet, stock=stock, problem=problem, chairs=chairs, timings=timings,
                             scheduler=None if client is None else str(getattr(client, "scheduler_info",
                                                                                lambda: {})().get("address", "")))
        if monte_carlo:
            start = time.perf_counter()
            chairs["shimmy_probability"], chairs["shimmy_probability_se"] = _monte_carlo(
                client, stock, problem, chairs["choice"], fleet.target_speed, chunk=max(50, chunk // 20))
            timings["monte_carlo"] = time.perf_counter() - start
        if skus is not None:
            start = time.perf_counter()
            choose_skus(result, skus, k_max=k_max, time_limit=time_limit)
            timings["skus"] = time.perf_counter() - start
            if monte_carlo and result.skus is not None and result.skus.assignment is not None:
                start = time.perf_counter()
                assigned = np.full(len(fleet), -1)
                assigned[result.feasible] = result.skus.assignment
                chairs["sku_shimmy_probability"], _ = _monte_carlo(client, stock, problem, assigned,
                                                                   fleet.target_speed, chunk=max(50, chunk // 20))
                timings["sku_monte_carlo"] = time.perf_counter() - start
    finally:
        if own:
            _close(client)
    return result


def _monte_carlo(client, stock, problem, choice, speeds, chunk):
    """Reported P(shimmy) at each chair's V_target for its caster; NaN where there is none."""
    u = mc_uncertainty(problem)
    slip = problem.conditions.slip_coefficient
    rows = np.flatnonzero(choice >= 0)
    p = np.full(len(choice), np.nan)
    se = np.full(len(choice), np.nan)
    if not len(rows):
        return p, se
    # The estimate is a deterministic function of (caster, speed) (its own fixed seed), so chairs that share
    # both share one estimate: each distinct pair is sampled once.
    pairs, inverse = np.unique(np.stack([choice[rows].astype(float), np.asarray(speeds, float)[rows]], axis=1),
                               axis=0, return_inverse=True)
    which = pairs[:, 0].astype(int)
    designs = np.stack([stock.trail, stock.diameter, stock.groove, stock.damping], axis=1)[which]
    inertia = stock.inertia[which]
    sp = pairs[:, 1]
    if client is not None:  # enough tasks to keep every worker busy
        chunk = max(1, min(chunk, -(-len(sp) // (8 * max(1, len(client.scheduler_info().get("workers", {})))))))
    pieces = [slice(a, a + chunk) for a in range(0, len(sp), chunk)]
    if client is None:
        outs = [_mc_task(designs[s], inertia[s], sp[s], slip, u) for s in pieces]
    else:
        futures = [client.submit(_mc_task, designs[s], inertia[s], sp[s], slip, u, pure=False) for s in pieces]
        outs = client.gather(futures)
    both = np.concatenate(outs)[np.ravel(inverse)]
    p[rows], se[rows] = both[:, 0], both[:, 1]
    return p, se


def choose_skus(result: FleetResult, k: int, k_max: int | None = None, time_limit: float = 120.0) -> None:
    """Solve the K-median over the stock for the feasible chairs; fill ``result.skus`` and the regret curve.

    Regret of chair i with caster j: J_ij − min_j' J_ij' over the chair's own feasible stock (never
    negative), J = w_turn F_turn + w_threshold P with the base problem's weights; +inf where caster j
    breaks the chair's own risk bound, swept-radius limit or sill.  Infeasible chairs are left out (and
    reported per row).  Exact MIP (:mod:`designer.analysis.kmedian`).
    """

    fleet, stock, problem = result.fleet, result.stock, result.problem
    rows = np.flatnonzero(result.feasible)
    if not len(rows):
        raise InputError("--skus: no chair of the fleet has a feasible stock caster, nothing to choose")
    parts = [rows[a:a + CHUNK] for a in range(0, len(rows), CHUNK)]
    f_parts, p_parts, cost_parts = [], [], []
    w = np.asarray(problem.weights, float)
    for part in parts:
        ev = evaluate_chairs({k2: v[part] for k2, v in fleet.arrays().items()}, stock, problem)
        j = np.where(ev["feasible"], w[0] * ev["turning_effort"] + w[1] * ev["threshold_force"], np.inf)
        cost_parts.append(j - j.min(axis=1, keepdims=True))
        f_parts.append(ev["turning_effort"])
        p_parts.append(ev["threshold_force"])
    cost = np.concatenate(cost_parts)
    result.regret_cost = {"turning_effort": np.concatenate(f_parts), "threshold_force": np.concatenate(p_parts),
                          "regret": cost}
    weights = fleet.count[rows]
    useful = len(prune_candidates(cost))
    k_max = max(k, 8) if k_max is None else max(k, k_max)
    k_max = min(k_max, max(useful, k))
    curve = {}
    for kk in range(1, k_max + 1):
        curve[kk] = solve_kmedian(cost, weights, kk, time_limit=time_limit)
    result.curve = curve
    result.skus = curve[k]
    result.candidates = useful


def _client(scheduler):
    """(client, owned) for a scheduler address, "local", a Client, or None (in-process)."""
    if scheduler is None:
        return None, False
    try:
        # dask is optional (the `fleet` extra): imported only when a scheduler is asked for
        from distributed import Client, LocalCluster
    except ImportError:
        raise InputError("--scheduler: needs dask[distributed]; install it with "
                         "pip install 'caster-designer[fleet]'") from None
    if isinstance(scheduler, Client):
        return scheduler, False
    if scheduler == "local":
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        return Client(cluster), True
    if not isinstance(scheduler, str) or not re.match(r"^(tcp|tls|inproc|ucx)://\S+$", scheduler):
        raise InputError(f"--scheduler {scheduler!r}: expected an address such as tcp://host:8786, or 'local'")
    try:
        return Client(scheduler, timeout="10s"), True
    except (OSError, TimeoutError) as exc:
        raise InputError(f"--scheduler {scheduler}: cannot reach the scheduler ({type(exc).__name__}: {exc}); "
                         f"start one with `dask scheduler` (docs/fleet.md)") from None


def _close(client) -> None:
    cluster = getattr(client, "cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()



def fleet_data(result: FleetResult) -> dict:
    """Plain data of a fleet run (what ``--json`` prints and the report renders): settings, part numbers,
    regret curve, per-chair rows, distributions, timings.  SI units; J uses the base problem's weights."""
    problem = result.problem
    risk = risk_of(problem)
    u = mc_uncertainty(problem)
    ch = result.chairs
    ok = result.feasible
    rows = result.rows()
    choice = ch["choice"][ok]
    dist = {"trail": result.stock.trail[choice], "diameter": result.stock.diameter[choice],
            "groove": result.stock.groove[choice], "damping": result.stock.damping[choice],
            "turning_effort": ch["turning_effort"][ok], "threshold_force": ch["threshold_force"][ok]}
    if "shimmy_probability" in ch:
        dist["shimmy_probability"] = ch["shimmy_probability"][ok]
    served_units = float(result.fleet.count[ok].sum()) or 1.0
    curve = [{"k": k, "regret": s.regret if s.status != "infeasible" else None,
              "mean_regret": s.regret / served_units if s.status != "infeasible" else None, "status": s.status,
              "lower_bound": s.lower_bound, "gap": s.gap, "seconds": s.seconds, "chosen": s.chosen}
             for k, s in sorted(result.curve.items())]
    w = tuple(float(x) for x in problem.weights)
    return {
        "fleet": result.fleet.source,
        "chairs": len(result.fleet),
        "feasible_chairs": int(ok.sum()),
        "units": int(result.fleet.count.sum()),
        "problem": problem.name,
        "weights": list(w),
        "objective": f"J = {w[0]:g} F_turn + {w[1]:g} P [N]: 1 N of sill force is worth "
                     f"{(w[1] / w[0]) if w[0] else math.inf:g} N of turning effort",
        "regret_definition": "regret of a chair = J with its assigned part number − the least J over the "
                             "chair's own feasible stock (never negative); the part numbers minimise the "
                             "count-weighted sum",
        "risk": None if risk is None else {"probability": risk.probability, "margin": problem.margin},
        "monte_carlo": {"samples": getattr(u, "samples", None), "seed": getattr(u, "seed", None)},
        "rule": ("cap on sill force" if getattr(problem, "max_threshold_force", None) is not None else
                 "cap on turning effort" if getattr(problem, "max_turning_effort", None) is not None else
                 "knee of the buildable front"),
        "stock": {"casters": len(result.stock), "note": result.stock.note,
                  "useful_for_skus": getattr(result, "candidates", None)},
        "skus": result.sku_records(),
        "k": None if result.skus is None else result.skus.k,
        "regret": None if result.skus is None or result.skus.status == "infeasible" else result.skus.regret,
        "mean_regret": None if result.skus is None or result.skus.status == "infeasible" else
        result.skus.regret / served_units,
        "sku_status": None if result.skus is None else result.skus.status,
        "regret_curve": curve,
        "rows": rows,
        "distributions": {k: np.asarray(v, float) for k, v in dist.items()},
        "alpha": None if risk is None else risk.probability,
        "timings": dict(result.timings),
        "scheduler": result.scheduler,
    }


def fleet(chairs, problem=None, skus: int | None = None, scheduler=None, monte_carlo: bool = True,
          k_max: int | None = None) -> FleetResult:
    """``designer.fleet``: per-chair recommendations of a fleet and, with ``skus``, K part numbers.

    Parameters
    ----------
    chairs : a FLEET.csv path or a :class:`Fleet` (e.g. ``example_fleet(1000)``)
    problem : the base problem (a :class:`designer.problem.Problem` or a TOML path; default
        ``problems/indoor-manual.toml``)
    skus, scheduler, monte_carlo, k_max : as :func:`fleet_recommendations`

    Returns
    -------
    FleetResult; ``fleet_data(result)`` gives the plain data of ``--json``.
    """

    if not isinstance(chairs, Fleet):
        chairs = read_fleet(chairs)
    if problem is None or isinstance(problem, (str, Path)):
        problem = load_problem(problem or "problems/indoor-manual.toml")
    return fleet_recommendations(chairs, problem, skus=skus, k_max=k_max, scheduler=scheduler,
                                 monte_carlo=monte_carlo)
