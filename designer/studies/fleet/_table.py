"""The fleet table: FLEET.csv -> per-chair arrays (:class:`Fleet`), one-line errors, example fleets.

Part of :mod:`designer.studies.fleet._fleet`: the columns and their units, the
model ranges per column, the reader and the writer of the example fleets.
"""

from __future__ import annotations

import difflib
import math
import re
import dataclasses
from dataclasses import dataclass
import os
from pathlib import Path

import numpy as np

from designer.data.paper import INCH
from designer.errors import InputError, ProblemError
from designer.textfiles import csv_table, csv_text, read_input_text
from designer.model import MASS_RANGE, caster_load
from designer.output import FileKind, write_file
from designer.physics.turning import MODES, SURFACES
from designer.units import parse_quantity


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

UNIT_ALIASES = {
    "mps": "m/s",
    "m_s": "m/s",
    "kmh": "km/h",
    "kph": "km/h",
    "pct": "percent",
    "%": "percent",
    "lb": "lbf",
    "lbs": "lbf",
}
"""Header unit spellings that pint does not read (``target_speed_mps``)."""

RANGES = {
    "load": (1.0, 1e5, "N", "a caster load of 0.1 kg to 10 t; was it given in another unit?"),
    "mass": (*MASS_RANGE, "kg", "user plus chair; was it given in another unit?"),
    "front_fraction": (0.0, 1.0, "", "the share of the weight on the two front casters, e.g. 0.4 or '40 %'"),
    "threshold_height": (1e-4, 0.3, "m", "a sill of 0.1 mm to 30 cm; were inches written as metres?"),
    "target_speed": (0.01, 100.0, "m/s", "plain numbers are m/s; was it given in km/h or mph?"),
    "swept_radius_max": (1e-3, 10.0, "m", "footrest clearances are a few inches; were inches written as metres?"),
}
"""Model range per column [SI] (same limits as the problem file's): outside it a row is an input error."""

CHAIR_ARRAYS = ("load", "threshold_height", "target_speed", "swept_radius_max", "surface", "turning_mode")
"""The per-chair columns a worker needs (:meth:`Fleet.arrays`)."""

MAX_CHAIRS = 100_000
"""Largest fleet (rows of FLEET.csv, chairs of --example): what one machine carries in bounded time and
memory (docs/fleet.md, "Size"; the recorded times: benchmarks/fleet.md); a larger product line is split into
files of at most this many chairs."""

MAX_FLEET_BYTES = 640 * MAX_CHAIRS
"""Largest fleet file read [bytes]: :data:`MAX_CHAIRS` rows of 640 characters (a row is about 60)."""


# --------------------------------------------------------------------------- the fleet table


@dataclass(frozen=True)
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

    def __post_init__(self) -> None:
        object.__setattr__(self, "names", tuple(self.names))  # read-only, as the records that hold it

    def __len__(self) -> int:
        return len(self.names)

    def subset(self, index) -> "Fleet":
        """The chairs at ``index`` (array of positions or a boolean mask)."""
        index = np.asarray(index)
        if index.dtype == bool:
            index = np.flatnonzero(index)
        return dataclasses.replace(
            self,
            names=[self.names[i] for i in index],
            **{key: value[index] for key, value in self.arrays().items()},
            count=self.count[index],
            rows=None if self.rows is None else self.rows[index],
        )

    def arrays(self) -> dict:
        """The per-chair numbers as plain arrays (what a worker needs; no names)."""
        return {key: getattr(self, key) for key in CHAIR_ARRAYS}

    def problem(self, base, i: int):
        """The base problem with chair ``i``'s conditions: what ``designer.recommend`` takes for one chair."""
        conditions = base.conditions.replace(
            load=float(self.load[i]),
            threshold_height=float(self.threshold_height[i]),
            surface=str(self.surface[i]),
            turning_mode=str(self.turning_mode[i]),
        )
        name = re.sub(r"[^A-Za-z0-9_.-]", "-", str(self.names[i]))[:64].lstrip("-_.") or "chair"
        return base.replace(
            name=name,
            conditions=conditions,
            target_speed=float(self.target_speed[i]),
            swept_radius_max=float(self.swept_radius_max[i]),
            source=None,
        )


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
            return name, text[len(name) + 1 :]
    known = ", ".join(COLUMNS)
    raise ProblemError(
        f"{source}: column {header!r}: unknown column{_suggest(text, list(COLUMNS))}; "
        f"expected {known} (a unit may follow: load_N, threshold_height_in)"
    )


def _suggest(word: str, options) -> str:
    base = re.split(r"[\s\[(]", word.strip())[0]
    for candidate in (word, base, base.rsplit("_", 1)[0]):
        match = difflib.get_close_matches(candidate, list(options), n=1, cutoff=0.75)
        if match:
            return f" (did you mean {match[0]!r}?)"
    return ""


def read_fleet(path, base=None) -> Fleet:
    """Read and validate FLEET.csv.

    Columns: ``name, load, threshold_height, target_speed, swept_radius_max, surface, turning_mode`` and an
    optional ``count``; ``mass`` [kg] and ``front_fraction`` [-] may replace ``load`` per row (load =
    m g front_fraction / 2).  Units go in the header (``load_N``, ``threshold_height_in``,
    ``threshold_height [in]``) or in the cells (``"0.5 in"``); plain numbers without either are SI.

    Raises
    ------
    ProblemError (exit 3)
        One line naming the row and the column: a missing column (by its expected name), an unknown column
        (with "did you mean" for a near miss), a unit of the wrong dimension, a duplicate name, an
        empty cell, a value outside the model's range, an unknown surface or turning mode.
    """
    path = Path(path)
    if os.path.isfile(path) and path.stat().st_size > MAX_FLEET_BYTES:  # a name too long: read_input_text says so
        raise ProblemError(
            f"{path}: {path.stat().st_size:,} bytes; a fleet file is at most {MAX_FLEET_BYTES:,} bytes "
            f"({MAX_CHAIRS:,} chairs): split the fleet into files of at most {MAX_CHAIRS:,} chairs"
        )
    text = read_input_text(path, "fleet file", ".csv", limit=MAX_FLEET_BYTES)
    return fleet_from_text(text, source=str(path))


def fleet_from_text(text: str, source: str = "fleet") -> Fleet:
    """Parse CSV text into a validated :class:`Fleet` (see :func:`read_fleet`).

    Checked in this order, the first failure raised as one line: the header (columns, units, required
    columns), the row lengths, the names, the loads (or mass and front fraction), the sill, speed and
    radius columns, the surface and turning mode, the counts.
    """
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ProblemError(f"{source}: empty file; expected a header line (name, load_N, threshold_height_in, ...)")
    if len(lines) - 1 > MAX_CHAIRS:  # counted on the lines, before the CSV is parsed (a quoted cell may hold one)
        raise ProblemError(
            f"{source}: {len(lines) - 1:,} rows; a fleet has at most {MAX_CHAIRS:,} chairs: split it into files "
            f"of at most {MAX_CHAIRS:,} chairs (docs/fleet.md)"
        )
    header, body, lines_of_rows = csv_table(text, source, error=ProblemError)  # the readers' shared rules
    columns = _header_columns(header, source)
    if not body:
        raise ProblemError(f"{source}: no chairs (only a header)")

    n = len(body)
    width = len(header)
    row_numbers = np.array(lines_of_rows)  # physical line numbers (comments and blank lines skipped)
    for r, cells in enumerate(body):
        if len(cells) != width:
            raise ProblemError(f"{source}: row {row_numbers[r]}: {len(cells)} cells, the header has {width}")

    t = _Table(source, columns, body, row_numbers)
    names = t.names()
    load = t.loads()
    values = {name: t.numbers(name) for name in ("threshold_height", "target_speed", "swept_radius_max")}
    for name, v in values.items():
        t.check(name, v)
    labels = {name: t.labels(name, allowed) for name, allowed in (("surface", SURFACES), ("turning_mode", MODES))}
    count = t.counts() if "count" in columns else np.ones(n)
    return Fleet(names=names, load=load, **values, **labels, count=count, rows=row_numbers, source=source)


def _header_columns(header: list[str], source: str) -> dict[str, tuple[int, float, str | None]]:
    """{column: (position, factor to SI, unit)} of the header; ProblemError for a repeated or missing column."""
    columns: dict[str, tuple[int, float, str | None]] = {}
    for pos, raw in enumerate(header):
        name, unit = _split_header(raw, source)
        if name in columns:
            raise ProblemError(f"{source}: column {raw!r}: {name} appears twice in the header")
        factor = 1.0  # the SI value of the header's unit
        if unit is not None:
            if COLUMNS[name] in ("text", "surface", "mode", "count"):
                raise ProblemError(f"{source}: column {name}_{unit}: {name} takes no unit")
            si = UNIT_ALIASES.get(unit, unit)
            try:
                factor = parse_quantity(
                    f"1 {si}", COLUMNS[name], f"{source}: column {name} (unit {si!r} in the header)"
                )
            except InputError as exc:
                raise ProblemError(str(exc)) from None
        columns[name] = (pos, factor, unit)
    # a header that is no column's was refused above with its "did you mean": a missing column has no near miss
    for name in REQUIRED:
        if name not in columns:
            raise ProblemError(f"{source}: missing column {name!r}")
    if "load" not in columns and not ("mass" in columns and "front_fraction" in columns):
        if "mass" in columns or "front_fraction" in columns:
            missing = "front_fraction" if "mass" in columns else "mass"
            raise ProblemError(f"{source}: missing column {missing!r} (load = mass g front_fraction / 2 needs both)")
        raise ProblemError(f"{source}: missing column 'load' (or give mass and front_fraction)")
    return columns


@dataclass
class _Table:
    """The rows of a fleet file under its header: each reader checks one column, with one-line errors."""

    source: str
    columns: dict[str, tuple[int, float, str | None]]
    body: list[list[str]]
    row_numbers: np.ndarray

    @property
    def n(self) -> int:
        """The number of rows (chairs)."""
        return len(self.body)

    def column(self, name: str) -> list[str]:
        pos = self.columns[name][0]
        return [cells[pos].strip() for cells in self.body]

    def numbers(self, name: str, optional: bool = False) -> np.ndarray:
        source, row_numbers = self.source, self.row_numbers
        pos, factor, unit = self.columns[name]
        dimension = COLUMNS[name]
        out = np.empty(self.n)
        for r, cells in enumerate(self.body):
            cell = cells[pos].strip()
            if cell == "":
                if optional:
                    out[r] = np.nan
                    continue
                raise ProblemError(
                    f"{source}: row {row_numbers[r]}, column {name}: empty; give a number"
                    + (f" in {unit}" if unit else " (SI) or one with units")
                )
            try:
                out[r] = float(cell) * factor
            except ValueError:
                out[r] = _cell_quantity(cell, dimension, f"{source}: row {row_numbers[r]}, column {name}")
            if not math.isfinite(out[r]):
                raise ProblemError(f"{source}: row {row_numbers[r]}, column {name} = {cell!r}: must be finite")
        return out

    def check(self, name: str, values: np.ndarray, skip=None) -> None:
        low, high, unit, hint = RANGES[name]
        bad = ~((values >= low) & (values <= high)) if name != "front_fraction" else ~((values > 0) & (values <= 1))
        if skip is not None:
            bad &= ~skip
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise ProblemError(
                f"{self.source}: row {self.row_numbers[r]}, column {name} = {values[r]:g} {unit}".rstrip()
                + f": outside the model's range {low:g} to {high:g} {unit}".rstrip()
                + f" ({hint})"
            )

    def names(self) -> list[str]:
        """The chairs' names: each given, none repeated."""
        names = self.column("name")
        seen: dict[str, int] = {}
        for r, name in enumerate(names):
            if not name:
                raise ProblemError(
                    f"{self.source}: row {self.row_numbers[r]}, column name: empty; every chair needs a name"
                )
            if name in seen:
                raise ProblemError(
                    f"{self.source}: row {self.row_numbers[r]}, column name = {name!r}: duplicate "
                    f"name (first at row {self.row_numbers[seen[name]]})"
                )
            seen[name] = r
        return names

    def loads(self) -> np.ndarray:
        """Caster load L [N] per chair: the load column, or m g front_fraction / 2 where that is given."""
        source, row_numbers, columns, n = self.source, self.row_numbers, self.columns, self.n
        either = "mass" in columns and "front_fraction" in columns  # else an empty load cell is an error here
        load = self.numbers("load", optional=either) if "load" in columns else np.full(n, np.nan)
        if either:
            mass = self.numbers("mass", optional=True)
            fraction = self.numbers("front_fraction", optional=True)
            for r in range(n):
                given = (not math.isnan(load[r]), not math.isnan(mass[r]), not math.isnan(fraction[r]))
                if given[0] and (given[1] or given[2]):
                    raise ProblemError(
                        f"{source}: row {row_numbers[r]}, column load: give load or mass and front_fraction, not both"
                    )
                if not given[0] and not (given[1] and given[2]):
                    col = "mass" if not given[1] else "front_fraction"
                    raise ProblemError(
                        f"{source}: row {row_numbers[r]}, column {col}: empty; give load, or mass and front_fraction"
                    )
            by_mass = np.isnan(load)
            self.check("mass", mass, skip=~by_mass)
            self.check("front_fraction", fraction, skip=~by_mass)
            load = np.where(by_mass, caster_load(mass, fraction), load)
        self.check("load", load)
        return load

    def labels(self, name: str, allowed: tuple[str, ...]) -> np.ndarray:
        """A categorical column (surface, turning mode): every cell one of ``allowed``."""
        cells = self.column(name)
        for r, cell in enumerate(cells):
            if cell not in allowed:
                raise ProblemError(
                    f"{self.source}: row {self.row_numbers[r]}, column {name} = {cell!r}: expected "
                    f"one of {', '.join(allowed)}{_suggest(cell, allowed)}"
                )
        return np.array(cells, dtype=object)

    def counts(self) -> np.ndarray:
        """Units sold per chair: a whole number, 0 or more (an empty cell is 1)."""
        count = np.empty(self.n)
        for r, cell in enumerate(self.column("count")):
            try:
                value = float(cell) if cell else 1.0
            except ValueError:
                value = math.nan
            if not math.isfinite(value) or value < 0 or value != int(value) or value > 1e12:
                raise ProblemError(
                    f"{self.source}: row {self.row_numbers[r]}, column count = {cell!r}: expected a "
                    f"whole number of units sold, 0 or more"
                )
            count[r] = value
        return count


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
    "load": (
        "120–300 N per caster",
        "assumption: light to heavy users of one product line; the paper's "
        "slip and turning tests used 178 N (40 lb) per caster (Appendix C, Fig. 7), near the middle",
    ),
    "threshold_height": (
        "0.25–0.75 in",
        "0.5 in is the paper's case (Fig. 2A) and the US accessibility limit "
        "for door thresholds (2010 ADA Standards 404.2.5: 1/2 in, 3/4 in for existing "
        "sliding doors); 0.25 in is an assumption for floor transitions",
    ),
    "swept_radius_max": (
        "5–8 in",
        "assumption: footrest clearances of common manual chairs; the default problem uses 6 in",
    ),
    "target_speed": (
        "1.5–3.5 m/s",
        "assumption: above the paper's 1 m/s walking speed (where its E&J wheels "
        "were near their critical speed) up to a fast push or a ramp; the default problem uses "
        "2.5 m/s",
    ),
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
        rows=np.arange(2, n + 2),
        source=f"example-{n}",
    )


EXAMPLE_HEADER = "# Example fleet written by `designer fleet --example`; ranges and their sources: docs/fleet.md"
"""The first line of an example fleet CSV (a comment :func:`read_fleet` skips)."""

EXAMPLE_KIND = FileKind("an example fleet written by designer fleet --example")
"""What ``fleet --example --out FILE`` may replace: an example fleet it wrote, unedited (the manifest of its folder
proves it); never a fleet of the user's, nor an example the user edited."""


def write_fleet_csv(fleet: Fleet, path) -> Path:
    """Write a fleet as FLEET.csv with units in the header (the format :func:`read_fleet` reads), atomically
    (:func:`designer.output.write_file`: a folder or an unwritable place is an OutputError, exit 7)."""
    path = Path(path)
    rows: list[list[object]] = [
        ["name", "load_N", "threshold_height_in", "target_speed_m/s", "swept_radius_max_in", "surface"]
        + ["turning_mode", "count"]
    ]
    for i in range(len(fleet)):
        rows.append(
            [
                fleet.names[i],
                f"{fleet.load[i]:.1f}",
                f"{fleet.threshold_height[i] / INCH:.3f}",
                f"{fleet.target_speed[i]:.2f}",
                f"{fleet.swept_radius_max[i] / INCH:.2f}",
                fleet.surface[i],
                fleet.turning_mode[i],
                int(fleet.count[i]),
            ]
        )
    write_file(path, csv_text(rows, comments=[EXAMPLE_HEADER[2:]]), "--out", example="fleet.csv", kind=EXAMPLE_KIND)
    return path
