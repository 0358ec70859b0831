"""Goods-in inspection: a verdict on each caster a factory measured (docs/inspection.md).

An inspector measures each caster's parts (trail T, wheel diameter d, groove B, bearing friction moment M_f or
the damping c_f = M_f/θ0, the wheel's inertia I_w) and writes one row per caster (``measured.csv``; units in
the header, e.g. ``trail_mm``, ``friction_moment_N_m``, ``wheel_inertia_kg_m2``; a ``serial`` column kept).
:func:`inspect` grades every good row:

- P(shimmy): P(V_c,true < V_req) of that caster by the exact law (quadrature,
  :func:`designer.physics.acceptance.measured_probabilities`: the wheel is measured, so its I_w scatters by the
  measurement's σ_I only), at the problem's required speed V_req = (1 + margin) V_target under its risk law;
- pass: P <= α (the problem's bound); whether it fits the footrest (T + d/2 <= R_max) is said beside it;
- driver: the part that, put back to the nominal of the problem's recommended caster with the others as
  measured, lowers P the most (the part to fix first);
- whether it lies inside the recommendation's joint box and inside its one-at-a-time limits (so an inspector
  sees what the box would have decided).

The lot: how many pass, the worst caster, the fraction above α with its binomial standard error, and the mean
P(shimmy) (the expected share of casters in such a lot that shimmy at V_req).

Bad rows (a non-number, an empty or negative cell) are listed one per line (row, column, reason) and never
stop the good rows from being graded; the file is only read.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.errors import InputError
from designer.reprs import Key, Record
from designer.studies.recommend import recommend
from designer.studies.spec import MEASURE, risk_law
from designer.physics.acceptance import measured_probabilities
from designer.textfiles import csv_table, read_input_text
from designer.units import parse_quantity

if TYPE_CHECKING:
    from designer.problem import Problem
    from designer.studies.recommend import Recommendation

COLUMNS = {
    "trail": "length",
    "diameter": "length",
    "groove": "length",
    "friction_moment": "moment",
    "damping": "damping",
    "wheel_inertia": "inertia",
}
"""The measured parts and their dimension; the unit follows the name in the header (``trail_mm``)."""

UNIT_SPELLINGS = {
    "N_m": "N*m",
    "Nm": "N*m",
    "N_m_per_rad": "N*m/rad",
    "Nm_per_rad": "N*m/rad",
    "kg_m2": "kg*m**2",
    "kgm2": "kg*m**2",
    "kg_m^2": "kg*m**2",
}
"""Header unit spellings a CSV header can hold that pint reads otherwise."""

PARTS = ("trail", "groove", "friction_moment", "wheel_inertia")
"""The parts the risk depends on (the driver is one of them)."""

MAX_ROWS = 100_000
"""Most casters in one file (the exact law is evaluated for all of them at once, a few per millisecond)."""


@dataclass(frozen=True)
class BadRow:
    """One row that could not be graded: its line in the file, the column and why."""

    row: int
    column: str
    reason: str

    def line(self, source: str) -> str:
        """``measured.csv: row 7, column trail_mm: 'abc' is not a number``."""
        return f"{source}: row {self.row}, column {self.column}: {self.reason}"


@dataclass(frozen=True, kw_only=True)
class InspectedCaster(Record):
    """The verdict on one measured caster (SI).

    Attributes
    ----------
    serial : the row's serial (its line number when the file has no ``serial`` column)
    row : the line of the file
    parts : {trail, groove, friction_moment, wheel_inertia[, diameter]} as measured [SI]
    shimmy_probability : P(V_c,true < V_req) by the exact law, the wheel's I_w measured [-]
    passed : P <= α
    driver : the part that, back at nominal, lowers P the most
    fits_footrest : T + d/2 <= R_max (None: no diameter measured or no R_max)
    in_joint_box, in_one_at_a_time : inside the recommendation's joint box / each one-at-a-time limit
    """

    serial: str
    row: int
    parts: dict[str, float]
    shimmy_probability: float
    passed: bool
    driver: str
    fits_footrest: bool | None
    in_joint_box: bool
    in_one_at_a_time: bool

    _keys = (
        "serial",
        "row",
        "shimmy_probability",
        Key("pass", "passed"),
        "driver",
        "fits_footrest",
        "in_joint_box",
        "in_one_at_a_time",
        "parts",
    )


@dataclass(frozen=True, kw_only=True)
class Inspection(Record):
    """The verdicts on a lot of measured casters and the lot's summary.

    Attributes
    ----------
    casters : one :class:`InspectedCaster` per good row, in file order
    bad_rows : :class:`BadRow` of each row that could not be graded
    alpha : α [-]; speed : V_req [m/s]
    source : the file's name (messages)
    nominal : the recommended caster's parts [SI] the driver compares against
    """

    casters: list[InspectedCaster]
    bad_rows: list[BadRow]
    alpha: float
    speed: float
    source: str
    nominal: dict[str, float] = field(default_factory=dict)

    _keys = (
        "casters",
        Key("lot", lambda s: s.lot()),
        Key("bad_rows", lambda s: [{"row": b.row, "column": b.column, "reason": b.reason} for b in s.bad_rows]),
        "alpha",
        Key("speed", "speed"),
        "nominal",
    )

    def lot(self) -> dict[str, Any]:
        """{"graded", "passed", "failed", "worst": {"serial", "shimmy_probability"}, "fraction_above_alpha",
        "fraction_above_alpha_se" (binomial), "mean_shimmy_probability", "bad_rows"}."""
        n = len(self.casters)
        passed = sum(c.passed for c in self.casters)
        worst = max(self.casters, key=lambda c: c.shimmy_probability) if self.casters else None
        frac = (n - passed) / n if n else math.nan
        return {
            "graded": n,
            "passed": passed,
            "failed": n - passed,
            "worst": None
            if worst is None
            else {"serial": worst.serial, "shimmy_probability": worst.shimmy_probability, "driver": worst.driver},
            "fraction_above_alpha": frac,
            "fraction_above_alpha_se": math.sqrt(frac * (1 - frac) / n) if n else math.nan,
            "mean_shimmy_probability": float(np.mean([c.shimmy_probability for c in self.casters])) if n else math.nan,
            "inside_joint_box": sum(c.in_joint_box for c in self.casters),
            "bad_rows": len(self.bad_rows),
        }


def _header(raw: str, source: str) -> tuple[str, float]:
    """A header cell -> (part, factor to SI); ``serial`` -> ("serial", 1).  InputError for an unknown column."""
    text = raw.strip()
    if text == "serial":
        return "serial", 1.0
    for name in sorted(COLUMNS, key=len, reverse=True):
        if text == name:
            return name, 1.0
        if text.startswith(name + "_"):
            unit = text[len(name) + 1 :]
            unit = UNIT_SPELLINGS.get(unit, unit)
            return name, parse_quantity(f"1 {unit}", COLUMNS[name], f"{source}: column {text}")
    raise InputError(
        f"{source}: column {text!r}: unknown column; expected serial, trail_<unit>, diameter_<unit>, groove_<unit>, "
        "friction_moment_N_m (or damping_N_m_per_rad), wheel_inertia_kg_m2"
    )


def read_measured(path: Any, theta0: float) -> tuple[list[dict[str, Any]], list[BadRow], str]:
    """The rows of a measured-caster CSV in SI (``friction_moment`` from ``damping`` × θ0 when only c_f is given),
    the bad rows, and the file's name.  A header error (unknown or missing column, a unit of the wrong dimension)
    is one InputError line: nothing can be graded."""
    source = str(path)
    text = read_input_text(path, "measured-caster table", ".csv", limit=64 * 2**20, error=InputError)
    header, body, lines = csv_table(text, source)
    if not header:
        raise InputError(f"{source}: empty file; expected a header row (designer inspect PROBLEM --template FILE)")
    columns = [_header(h, source) for h in header]
    names = [c[0] for c in columns]
    missing = [n for n in ("trail", "groove", "wheel_inertia") if n not in names]
    if "friction_moment" not in names and "damping" not in names:
        missing.append("friction_moment")
    if missing:
        raise InputError(
            f"{source}: missing column {missing[0]!r} (with its unit, e.g. {missing[0]}_mm); found {', '.join(header)}"
        )
    if len(body) > MAX_ROWS:
        raise InputError(f"{source}: {len(body):,} rows; at most {MAX_ROWS:,} casters a file")
    rows, bad = [], []
    for cells, line in zip(body, lines):
        if len(cells) != len(header):
            bad.append(BadRow(line, "(row)", f"{len(cells)} cells, the header has {len(header)}"))
            continue
        out: dict[str, Any] = {"row": line, "serial": str(line)}
        fault = None
        for (name, factor), raw, cell in zip(columns, header, cells):
            if name == "serial":
                out["serial"] = cell.strip() or str(line)
                continue
            try:
                value = float(cell)
            except ValueError:
                fault = BadRow(line, raw.strip(), f"{cell.strip()!r} is not a number" if cell.strip() else "empty")
                break
            if not math.isfinite(value) or value < 0 or (value == 0 and name != "groove"):
                fault = BadRow(line, raw.strip(), f"{cell.strip()} must be a positive number")
                break
            out[name] = value * factor
        if fault is not None:
            bad.append(fault)
            continue
        if "friction_moment" not in out:
            out["friction_moment"] = out["damping"] * theta0
        rows.append(out)
    return rows, bad, source


def inspect(problem: Problem, table: Any, rec: Recommendation | None = None) -> Inspection:
    """Grade each measured caster of ``table`` (a CSV path) against ``problem`` (module text).

    ``rec``: the problem's recommendation (its nominal caster, joint box and one-at-a-time limits); computed when
    not given.  All casters' P, and each with one part back at nominal, in one array call of the exact law.
    """
    if rec is None:
        rec = recommend(problem)
    theta0 = float(problem.conditions.disturbance_angle)
    rows, bad, source = read_measured(table, theta0)
    law = risk_law(problem)
    alpha, speed, ks = float(law.probability), problem.required_speed, float(problem.conditions.slip_coefficient)
    spec = rec.spec
    nominal = {
        "trail": rec.design.trail,
        "groove": rec.design.groove,
        "friction_moment": rec.design.damping * theta0,
        "wheel_inertia": spec.inertia if spec is not None else float(problem.conditions.inertia(rec.design.diameter)),
    }
    casters: list[InspectedCaster] = []
    if rows:
        m = {p: np.array([r[p] for r in rows]) for p in PARTS}
        # row 0: as measured; row 1 + k: part k back at nominal
        grid = [m] + [{**m, p: np.full(len(rows), nominal[p])} for p in PARTS]
        stacked = {p: np.stack([g[p] for g in grid]) for p in PARTS}
        prob = measured_probabilities(
            stacked["trail"],
            stacked["wheel_inertia"],
            stacked["groove"],
            stacked["friction_moment"] / theta0,
            ks,
            speed,
            law,
        )
        r_max = problem.swept_radius_max
        for i, r in enumerate(rows):
            p = float(prob[0, i])
            parts = {k: r[k] for k in (*PARTS, "diameter") if k in r}
            fits = (
                None
                if r_max is None or "diameter" not in r
                else bool(r["trail"] + r["diameter"] / 2 <= r_max * (1 + 1e-9))
            )
            one = spec is not None and all(_inside(lim, parts) for lim in spec.limits)
            box = spec is not None and spec.joint is not None and spec.joint.contains(parts)
            casters.append(
                InspectedCaster(
                    serial=r["serial"],
                    row=r["row"],
                    parts=parts,
                    shimmy_probability=p,
                    passed=p <= alpha,
                    driver=PARTS[int(np.argmax(p - prob[1:, i]))],  # the part whose nominal lowers P most
                    fits_footrest=fits,
                    in_joint_box=bool(box),
                    in_one_at_a_time=bool(one),
                )
            )
    return Inspection(casters=casters, bad_rows=bad, alpha=alpha, speed=speed, source=source, nominal=nominal)


def _inside(lim: Any, parts: dict[str, float]) -> bool:
    """A measured caster within one one-at-a-time :class:`~designer.studies.spec.Limit` (no limit: within)."""
    if lim.value is None or lim.part not in parts:
        return True
    if lim.side == "min":
        return parts[lim.part] >= lim.value * (1 - 1e-9)  # 1e-9: a value written in mm against one in inches
    return parts[lim.part] <= lim.value * (1 + 1e-9)


TEMPLATE_HEAD = "# goods-in inspection form written by caster-designer's designer inspect"
"""The template's first line (a comment the reader skips)."""


def template_text(problem: Problem) -> str:
    """The empty form an inspector fills in: a comment naming the problem and how to measure, then the header in
    the problem's units (lengths in inches or millimetres; M_f in N·m, I_w in kg·m²)."""
    unit = "in" if getattr(problem, "units", "in") == "in" else "mm"
    header = ["serial", *(f"{part}_{unit}" for part in ("trail", "diameter", "groove"))]
    header += ["friction_moment_N_m", "wheel_inertia_kg_m2"]
    lines = [
        f"{TEMPLATE_HEAD} for problem {problem.name!r}: one row per caster; lines starting with # are skipped",
        *(f"# {part}: {how}" for part, how in MEASURE.items()),
        ",".join(header),
    ]
    return "\n".join(lines) + "\n"
