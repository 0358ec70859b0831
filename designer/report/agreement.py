"""When two result files agree: value by value, each number within the tolerance of what produced it.

A committed report (``results/``) is checked, and kept, by its numbers, not by its bytes.  The last digit of a
number the solver resolves to 1e-8 can sit on a rounding boundary, and another CPU, BLAS kernel or library patch
release moves it across: a byte comparison then fails although nothing changed.  Here two versions of a file
*agree* when they have the same structure (the same keys, columns, rows, elements, labels and text) and every
number in them agrees within the tolerance of its field (docs/checks.md#when-two-result-files-agree):

- JSON is walked as a tree (the same keys and list lengths), CSV by column name and row;
- SVG, HTML and Markdown are compared as text with their numbers taken out: the text around the numbers must be
  identical (every element, attribute, label and word), a drawing coordinate (an SVG geometry attribute) agrees
  within :data:`DRAWING_PX`, and a number written in text agrees at its printed precision;
- any other file (a PNG) agrees only byte for byte: the writer keeps it when the data it is drawn from agree.

The tolerance of each kind of field is declared once, in :data:`RULES`, with where it comes from; :func:`rule_for`
says which rule a field follows.  :func:`compare_files` returns the values that moved beyond their tolerance
(empty: the files agree), :func:`compare_folders` does the same for every file of two report folders, and
:func:`keep_agreeing` is the writer's step that copies the old bytes over a new file that agrees with them, so a
rerun on another machine leaves a checkout clean.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

from designer.parameters import VARIABLES
from designer.units import csv_quantity
from designer.report.resolution import (
    AT_BOUND,
    DIFFERENCE_SCALE,
    MULTIPLIER_FLOOR,
    MULTIPLIER_GROUPS,
    MULTIPLIER_SIGNIFICANT,
    ROOT_GROUPS,
    ROOT_SIGNIFICANT,
    SIGNIFICANT,
    VARIABLE_SCALES,
)

IPOPT_ACCEPTABLE_TOL = 1e-8
"""IPOPT's acceptable tolerance on the scaled NLP (designer.solvers.nlp): the loosest optimality a solve returns."""
QUANTUM = 10.0 ** (1 - SIGNIFICANT)
"""One unit of the 9th significant digit, relative: what rounding to :data:`SIGNIFICANT` digits can add."""
DRAWING_PX = 0.5
"""Drawing tolerance [px] of an SVG coordinate: half a pixel, below what a screen shows (written to 0.1 px)."""
MONTE_CARLO_K = 4.0
"""A Monte Carlo estimate agrees within this many standard errors (of the difference of the two estimates)."""
TEXT_TYPES = frozenset({".svg", ".html", ".md", ".txt"})
"""Files compared as text with their numbers taken out."""
GEOMETRY = frozenset(
    {"x", "y", "x1", "x2", "y1", "y2", "cx", "cy", "r", "rx", "ry", "width", "height", "d", "points", "transform"}
)
"""SVG attributes that hold drawing coordinates [px] (or a rotation angle [°]): compared within DRAWING_PX."""
MONTE_CARLO_SE = {
    "shimmy_probability": "shimmy_probability_se",
    "shimmy_probability_mc": "shimmy_probability_se",
    "probability_mc": "probability_mc_se",
}
"""Monte Carlo estimates and the sibling key of their standard error (besides any ``X`` with an ``X_se``)."""
EXACT_BESIDE_MONTE_CARLO = {"shimmy_probability": "shimmy_probability_mc"}
"""A field that is exact (the risk law's quadrature) where its record carries the Monte Carlo estimate beside it
(the key named here): then it agrees as a computed number, and the estimate within its SE."""
MARGIN_SCALES = {**VARIABLE_SCALES, "shimmy": 1.0, "swept_radius": VARIABLE_SCALES["diameter"]}
"""Scale of an optimum's constraint margin [SI]: its variable's; 1 m/s for V_c - V_req (target speeds are 1 to 5
m/s); the diameter's for the swept radius [m].  A margin at the solver's tolerance is written 0, so it agrees on
this scale, not on its own magnitude."""


@dataclass(frozen=True)
class Rule:
    """How a kind of field agrees: |a - b| <= rtol * max(|a|, |b|, scale) + atol (scale: the field's own)."""

    name: str
    rtol: float
    atol: float
    source: str


RULES = {
    "design": Rule(
        "design variable",
        AT_BOUND + QUANTUM,
        0.0,
        "of the variable's scale: IPOPT resolves a variable to AT_BOUND = 1e-7 of its scale (an active bound's gap "
        "is the barrier parameter over the bound's multiplier, designer.report.resolution), plus the 9th digit",
    ),
    "number": Rule(
        "objective or computed number",
        IPOPT_ACCEPTABLE_TOL + QUANTUM,
        0.0,
        "relative: IPOPT's acceptable tolerance 1e-8 on the scaled NLP (tol is 1e-10), plus the 9th digit",
    ),
    "multiplier": Rule(
        "Lagrange multiplier or sensitivity",
        2 * 10.0 ** (1 - MULTIPLIER_SIGNIFICANT),
        MULTIPLIER_FLOOR,
        "relative: written to 4 significant digits (a rounding boundary crossed is up to 1e-3 of the value); a "
        "multiplier is a derivative, resolved only to IPOPT's dual tolerance over the constraint's scaled gradient "
        "(no better than the primal's square root near a weakly active constraint), so one more unit; 0 below "
        "the floor 1e-6",
    ),
    "monte carlo": Rule(
        "Monte Carlo estimate",
        0.0,
        0.0,
        f"within {MONTE_CARLO_K:g} standard errors of the difference (sqrt(SE_a² + SE_b²), its SE field); its SE "
        "field, sqrt(p(1-p)/n), within as many of its own, |1-2p| SE²/(2p(1-p)), carried from p's",
    ),
    "root": Rule(
        "P(shimmy) at an acceptance limit",
        10.0 ** (1 - ROOT_SIGNIFICANT),
        0.0,
        "relative: alpha by construction, written to 6 significant digits (the limit's root is found to 1e-9 of the "
        "part, times P's elasticity in the part), one unit of the 6th digit",
    ),
    "exact": Rule("string, count, status, boolean", 0.0, 0.0, "equal"),
    "drawing": Rule("drawing coordinate", 0.0, DRAWING_PX, "half a pixel (SVG geometry attributes, written to 0.1 px)"),
    "printed": Rule(
        "number in text", IPOPT_ACCEPTABLE_TOL + QUANTUM, 0.0, "one unit of its last printed digit, or as a number"
    ),
}
"""The tolerance of each kind of field, declared once (docs/checks.md#when-two-result-files-agree)."""


@dataclass(frozen=True)
class Moved:
    """One value that moved beyond its tolerance (or a structural difference: ``rule`` 'exact')."""

    where: str
    old: object
    new: object
    rule: str
    tolerance: float = 0.0

    def line(self) -> str:
        """``where: old -> new (rule, tolerance)`` as one short line."""
        if isinstance(self.old, float | int) and isinstance(self.new, float | int) and self.rule != "exact":
            delta = abs(float(self.new) - float(self.old))
            return f"{self.where}: {self.old!r} -> {self.new!r} (moved {delta:.3g}, {self.rule} tolerance {self.tolerance:.3g})"
        return f"{self.where}: {_short(self.old)} -> {_short(self.new)} ({self.rule})"


def _short(value, width: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= width else text[: width - 3] + "..."


# --------------------------------------------------------------------------- numbers


def rule_for(key, parent=None) -> str:
    """The :data:`RULES` key of the number stored under ``key`` (its dict's ``parent`` key: multiplier groups); a
    CSV column that names its unit (``trail_in``, ``trail_mm``: :func:`designer.units.csv_quantity`) follows the
    rule of its quantity."""
    if parent in MULTIPLIER_GROUPS or isinstance(key, str) and key.startswith("lambda_"):
        return "multiplier"
    if parent in ROOT_GROUPS:
        return "root"
    if key in VARIABLES or isinstance(key, str) and csv_quantity(key)[0] in VARIABLES:
        return "design"
    return "number"


def variable_scale(key) -> float:
    """The scale of the design variable stored under ``key`` in the unit it is written in (:data:`VARIABLE_SCALES`
    [SI], times the factor of a column that names its unit: ``trail_in`` is on 2.5 in's scale), else 0."""
    if not isinstance(key, str):
        return 0.0
    if key in VARIABLE_SCALES:
        return VARIABLE_SCALES[key]
    name, factor = csv_quantity(key)
    return VARIABLE_SCALES.get(name, 0.0) * factor


def tolerance(rule: str, a: float, b: float, scale: float = 0.0) -> float:
    """The largest |a - b| rule ``rule`` accepts for the values ``a``, ``b`` (``scale``: the field's own)."""
    r = RULES[rule]
    return r.rtol * max(abs(a), abs(b), abs(scale)) + r.atol


def _number(a, b, where: str, rule: str, scale: float = 0.0, se: tuple = ()) -> Moved | None:
    """None if the numbers ``a`` and ``b`` agree under ``rule`` (nan agrees with nan; inf with the same inf)."""
    a, b = float(a), float(b)
    if math.isnan(a) or math.isnan(b) or math.isinf(a) or math.isinf(b):
        return None if (a == b or math.isnan(a) and math.isnan(b)) else Moved(where, a, b, rule)
    if se:
        tol = MONTE_CARLO_K * math.hypot(*se)
    else:
        tol = tolerance(rule, a, b, scale)
    return None if abs(a - b) <= tol else Moved(where, a, b, rule, tol)


def _is_number(value) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


# --------------------------------------------------------------------------- JSON


def compare_json(old, new, where: str = "") -> list[Moved]:
    """Every value of the JSON trees ``old`` and ``new`` that moved beyond its tolerance, or differs in kind."""
    out: list[Moved] = []
    _walk(old, new, where, None, None, None, out)
    return out


def _walk(old, new, where, key, parent, siblings, out) -> None:  # noqa: C901 - one branch per JSON kind
    if isinstance(old, dict) and isinstance(new, dict):
        if list(old) != list(new):
            out.append(Moved(where or "(top)", sorted(old), sorted(new), "exact"))
            return
        for k in old:
            _walk(old[k], new[k], f"{where}.{k}" if where else str(k), k, key, (old, new), out)
    elif isinstance(old, list) and isinstance(new, list):
        if len(old) != len(new):
            out.append(Moved(f"{where} (length)", len(old), len(new), "exact"))
            return
        for i, (a, b) in enumerate(zip(old, new)):
            _walk(a, b, f"{where}[{i}]", key, parent, siblings, out)
    elif _is_number(old) and _is_number(new) and not (isinstance(old, int) and isinstance(new, int)):
        moved = _field(old, new, where, key, parent, siblings)
        if moved is not None:
            out.append(moved)
    elif isinstance(old, str) and isinstance(new, str):
        out.extend(compare_text(old, new, where, markup=False))
    elif old != new or type(old) is not type(new):
        out.append(Moved(where, old, new, "exact"))


def _estimate_of(key, siblings):
    """The Monte Carlo estimate whose standard error is stored under ``key`` (``X`` for ``X_se``), or None."""
    if not (siblings and isinstance(key, str) and (key == "se" or key.endswith("_se"))):
        return None
    name = "probability" if key == "se" else key[:-3]
    value = siblings[0].get(EXACT_BESIDE_MONTE_CARLO.get(name, name), siblings[0].get(name))
    return value if _is_number(value) else None


def _field(old, new, where, key, parent, siblings) -> Moved | None:
    """One number of a JSON object (``siblings``: the old and new dicts holding it, for SEs and scales)."""
    se_key = MONTE_CARLO_SE.get(key) or (f"{key}_se" if isinstance(key, str) else None)
    if siblings and isinstance(key, str) and EXACT_BESIDE_MONTE_CARLO.get(key) in siblings[0]:
        se_key = None  # the exact value; its Monte Carlo check is the sibling
    if key == "probability" and siblings and "se" in siblings[0]:
        se_key = "se"
    if siblings and se_key and se_key in siblings[0] and _is_number(siblings[0].get(se_key)):
        se = (float(siblings[0][se_key]), float(siblings[1].get(se_key, 0.0) or 0.0))
        return _number(old, new, where, "monte carlo", se=se)
    estimate = _estimate_of(key, siblings)
    if estimate is not None:  # a binomial SE = sqrt(p(1-p)/n) moves with its estimate p
        p = float(estimate)
        if 0 < p < 1:
            spread = tuple(abs(1 - 2 * p) * float(x) ** 2 / (2 * p * (1 - p)) for x in (old, new))
            return _number(old, new, where, "monte carlo", se=spread)
    rule = rule_for(key, parent)
    scale = variable_scale(key) if rule == "design" else 0.0
    if parent == "constraints" and isinstance(key, str):  # an optimum's margin: on its constraint's scale
        rule, scale = "design", MARGIN_SCALES.get(key.split(".", 1)[0], MARGIN_SCALES["swept_radius"])
    elif key in DIFFERENCE_SCALE and siblings and _is_number(siblings[0].get(DIFFERENCE_SCALE[key])):
        scale = float(siblings[0][DIFFERENCE_SCALE[key]])  # a difference of objectives: on the objective's scale
    return _number(old, new, where, rule, scale)


# --------------------------------------------------------------------------- CSV


def compare_csv(old: str, new: str, where: str = "") -> list[Moved]:
    """Every cell of the CSV texts ``old`` and ``new`` (by column name and row) that moved beyond its tolerance;
    a different header or row count is one structural difference."""
    a, b = list(csv.reader(io.StringIO(old))), list(csv.reader(io.StringIO(new)))
    if not a or not b or a[0] != b[0]:
        return [Moved(f"{where} (columns)", a[0] if a else [], b[0] if b else [], "exact")]
    if len(a) != len(b):
        return [Moved(f"{where} (rows)", len(a) - 1, len(b) - 1, "exact")]
    header, out = a[0], []
    for row, (ra, rb) in enumerate(zip(a[1:], b[1:]), start=1):
        if len(ra) != len(rb):
            out.append(Moved(f"{where} row {row} (cells)", len(ra), len(rb), "exact"))
            continue
        old_row, new_row = dict(zip(header, map(_cell, ra))), dict(zip(header, map(_cell, rb)))
        for name in header:
            x, y = old_row.get(name), new_row.get(name)
            if _is_number(x) and _is_number(y):
                moved = _field(x, y, f"{where} row {row} {name}", name, None, (old_row, new_row))
                if moved is not None:
                    out.append(moved)
            elif x != y:
                out.append(Moved(f"{where} row {row} {name}", x, y, "exact"))
    return out


def _cell(text: str):
    """A CSV cell as a float when it is a decimal number, else the text itself."""
    try:
        return float(text) if _NUMBER_CELL.fullmatch(text) else text
    except ValueError:
        return text


_NUMBER_CELL = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?inf|nan")


# --------------------------------------------------------------------------- text: SVG, HTML, Markdown

_TOKEN = re.compile(r"[A-Za-z0-9+/=]{40,}|#[0-9a-fA-F]{3,8}\b|[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d{1,3})?")
"""A number as written; a hex colour and a long base64 run (an inlined PNG) are text, not numbers."""
_TAG = re.compile(r"<[^<>]*>")
_ATTRIBUTE = re.compile(r'([\w:-]+)\s*=\s*"([^"]*)"')


def _numbers(text: str) -> tuple[list[str], list[str]]:
    """(the text between the numbers, the numbers as written); hex colours stay text."""
    parts, numbers, last = [], [], 0
    for m in _TOKEN.finditer(text):
        if m.group().startswith("#") or len(m.group()) >= 40:
            continue
        parts.append(text[last : m.start()])
        numbers.append(m.group())
        last = m.end()
    parts.append(text[last:])
    return parts, numbers


def _unit(written: str) -> float:
    """One unit of the last digit of the number as ``written`` ("2.21" -> 0.01, "1.5e-05" -> 1e-06)."""
    mantissa, _, exponent = written.lower().partition("e")
    decimals = len(mantissa.split(".", 1)[1]) if "." in mantissa else 0
    return 10.0 ** (int(exponent or 0) - decimals)


def _segments(text: str, markup: bool) -> list[tuple[str, str]]:
    """``text`` cut into (kind, piece): 'drawing' for an SVG geometry attribute's value, 'printed' elsewhere."""
    if not markup:
        return [("printed", text)]
    out, last = [], 0
    for tag in _TAG.finditer(text):
        out.append(("printed", text[last : tag.start()]))
        inner, pos = tag.group(), 0
        for attribute in _ATTRIBUTE.finditer(inner):
            kind = "drawing" if attribute.group(1) in GEOMETRY else "printed"
            out.append(("printed", inner[pos : attribute.start(2)]))
            out.append((kind, attribute.group(2)))
            pos = attribute.end(2)
        out.append(("printed", inner[pos:]))
        last = tag.end()
    out.append(("printed", text[last:]))
    return out


def compare_text(old: str, new: str, where: str = "", markup: bool = True) -> list[Moved]:
    """The differences of two texts (SVG, HTML, Markdown, or a JSON string when not ``markup``): the text around
    the numbers must be identical; a drawing coordinate agrees within DRAWING_PX, any other number at its printed
    precision (one unit of its last digit, the larger of the two) or as a computed number, whichever is looser."""
    a, b = _segments(old, markup), _segments(new, markup)
    if [k for k, _ in a] != [k for k, _ in b]:
        return [Moved(f"{where} (structure)", _short(old), _short(new), "exact")]
    out: list[Moved] = []
    line = 1
    for (kind, x), (_, y) in zip(a, b):
        if x == y:  # the same text agrees: only its lines are counted
            line += x.count("\n")
            continue
        (px, nx), (py, ny) = _numbers(x), _numbers(y)
        if px != py:
            first = next(i for i, (p, q) in enumerate(zip(px + [""], py + [""])) if p != q)
            out.append(Moved(f"{where} line {line} (text)", _context(px, nx, first), _context(py, ny, first), "exact"))
            return out
        for p, u, v in zip(px, nx, ny):
            line += p.count("\n")
            a_, b_ = float(u), float(v)
            if kind == "drawing":
                tol = RULES["drawing"].atol
            else:
                tol = max(_unit(u), _unit(v)) + tolerance("printed", a_, b_)
            if abs(a_ - b_) > tol:
                out.append(Moved(f"{where} line {line}", a_, b_, kind, tol))
        line += px[-1].count("\n")
    return out


def _context(parts: list[str], numbers: list[str], i: int) -> str:
    """The text around the ``i``-th piece (what a reader would see differ)."""
    before = numbers[i - 1] if 0 < i <= len(numbers) else ""
    return before + parts[i][:60] if i < len(parts) else before


# --------------------------------------------------------------------------- files and folders


def compare_files(old: Path, new: Path) -> list[Moved]:
    """The values that moved between the files ``old`` and ``new`` (empty: they agree), by the file's type."""
    name, suffix = Path(new).name, Path(new).suffix.lower()
    if suffix not in {".json", ".csv"} | TEXT_TYPES:
        same = Path(old).read_bytes() == Path(new).read_bytes()
        return [] if same else [Moved(name, "(bytes)", "(other bytes)", "exact")]
    try:
        a, b = Path(old).read_text(encoding="utf-8"), Path(new).read_text(encoding="utf-8")
    except UnicodeDecodeError:
        return [Moved(name, "(bytes)", "(not UTF-8 text)", "exact")]
    if a == b:  # the same text agrees whatever its type (a rerun's usual case: no parsing needed)
        return []
    if suffix == ".json":
        try:
            return compare_json(json.loads(a), json.loads(b), name)
        except ValueError:
            return [] if a == b else [Moved(name, "(not JSON)", "(text)", "exact")]
    if suffix == ".csv":
        return compare_csv(a, b, name)
    return compare_text(a, b, name, markup=suffix in {".svg", ".html"})


def _files(folder: Path, skip: frozenset) -> dict[str, Path]:
    return {
        str(p.relative_to(folder)): p
        for p in sorted(Path(folder).rglob("*"))
        if p.is_file() and p.name not in skip and not any(part.startswith(".") for part in p.relative_to(folder).parts)
    }


def compare_folders(old: Path, new: Path, skip=frozenset({"run.json"})) -> dict[str, list[Moved]]:
    """``{relative path: moved values}`` of every file of the folders ``old`` and ``new`` that does not agree
    (a file in one folder only is one structural difference); ``skip``: names not compared (run.json)."""
    a, b = _files(Path(old), frozenset(skip)), _files(Path(new), frozenset(skip))
    out: dict[str, list[Moved]] = {}
    for name in sorted(set(a) | set(b)):
        if name not in a or name not in b:
            out[name] = [
                Moved(name, "(present)" if name in a else "(absent)", "(absent)" if name in a else "(new)", "exact")
            ]
            continue
        moved = compare_files(a[name], b[name])
        if moved:
            out[name] = moved
    return out


def summary(name: str, moved: list[Moved]) -> str:
    """One line for a rewritten file: how many values moved, the largest beyond its tolerance first."""
    worst = max(moved, key=_excess)
    more = f" (+{len(moved) - 1} more)" if len(moved) > 1 else ""
    return f"{name}: {len(moved)} value{'s' if len(moved) != 1 else ''} moved: {worst.line()}{more}"


def _excess(m: Moved) -> float:
    if m.rule == "exact" or not (_is_number(m.old) and _is_number(m.new)):
        return math.inf
    return abs(float(m.new) - float(m.old)) / (m.tolerance or 1.0)


def keep_agreeing(stage: Path, target: Path, skip=frozenset({"run.json"})) -> dict[str, str]:
    """Copy the bytes of every file of ``target`` over the staged file of the same name in ``stage`` when the two
    agree, so the commit leaves that file as it was; returns ``{relative path: one line}`` of the staged files that
    replace a file of ``target`` that does not agree (which values moved, and by how much)."""
    changed: dict[str, str] = {}
    if not Path(target).is_dir():
        return changed
    for name, new in _files(Path(stage), frozenset(skip)).items():
        old = Path(target) / name
        if not old.is_file() or old.is_symlink():
            continue
        moved = compare_files(old, new)
        if moved:
            changed[name] = summary(name, moved)
        elif old.read_bytes() != new.read_bytes():
            shutil.copyfile(old, new)
    return changed


__all__ = [
    "DRAWING_PX",
    "MONTE_CARLO_K",
    "RULES",
    "Moved",
    "Rule",
    "compare_csv",
    "compare_files",
    "compare_folders",
    "compare_json",
    "compare_text",
    "keep_agreeing",
    "rule_for",
    "summary",
    "tolerance",
]
