"""The Pareto front as data: :class:`FrontPoint`, :class:`Front` and its indicators, tables and reprs.

A front is computed by :func:`designer.studies.front._pareto.pareto_front`; this module only holds it: the
points (SI units), the failed points, the run metadata, and what is read off them (hypervolume, knee,
weighted best, gaps, comparison with another front, CSV/JSON/pandas, notebook reprs).  No solver runs here.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.textfiles import csv_table, csv_text, dict_rows, read_input_text
from designer.studies.front._indicators import hypervolume_2d, igd_plus, nondominated, normalise
from designer.data.paper import INCH
from designer.errors import InputError
from designer.output import FileKind, write_file
from designer.model import VARIABLES, Caster, Design, check_design
from designer.parameters import DESIGN_UNITS, OUTPUTS, PARAMETERS, dimensions
from designer.units import csv_quantity
from designer.problem import example_names, example_problem
from designer.problem import Problem, family_of, load_problem
from designer.reprs import Key, Record, si_frame
from designer.solvers.base import OBJECTIVES
from designer.plots.svg import svg_curve
from designer.plots import fronts as front_plots

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

FRONT_CSV = FileKind("a front CSV")
"""What :meth:`Front.to_csv` may replace: a front CSV it wrote, unedited (the manifest of its folder proves it),
never another file of the user's."""

REFERENCE_OFFSET = 0.1
"""Hypervolume reference point: 10 % beyond the nadir in normalised objectives, i.e. (1.1, 1.1)."""


HYPERVOLUME_NORMALISATION = "(f - ideal) / (nadir - ideal), ideal and nadir of this front"
"""How front.json's hypervolume normalises the objectives (``hypervolume_reference.normalisation``)."""


@dataclass(frozen=True, kw_only=True)
class FrontPoint(Record):
    """One point of the front.

    Attributes
    ----------
    design : the design (SI)
    turning_effort : F_turn [N]
    threshold_force : P [N]
    critical_speed : V_c [m/s]
    margins : constraint margins (>= 0 feasible) by name
    epsilon : the cap on P used [N]
    status : IPOPT return status
    success : IPOPT succeeded and the point is feasible
    multipliers : {"shimmy": λ, "threshold_cap": λ, ...} (CasADi sign convention)
    family : "bare fork" | "groove" | "damper" | "groove+damper"
    wheel : Table 1 wheel for catalog problems
    caster : the evaluator's row of the point (:class:`designer.model.Caster`, under the problem's conditions),
        which ``turning_effort``, ``threshold_force`` and ``critical_speed`` were taken from; None for a failed
        point (the solver's own numbers) and for a point read back by :meth:`Front.from_csv` or
        :meth:`Front.from_pandas` (the file's numbers; nothing is evaluated again)
    """

    design: Design
    turning_effort: float
    threshold_force: float
    critical_speed: float
    margins: dict[str, float]
    epsilon: float
    status: str
    success: bool
    multipliers: dict[str, float] = field(default_factory=dict)
    family: str = ""
    wheel: str | None = None
    caster: Caster | None = field(default=None, repr=False, compare=False)

    _units = {
        **DESIGN_UNITS,
        **{n: OUTPUTS[n].unit for n in ("turning_effort", "threshold_force", "critical_speed")},
        "epsilon": OUTPUTS["threshold_force"].unit,
    }

    def row(self) -> dict[str, Any]:
        """The point as one flat row of ``front.csv`` and ``front.json`` (SI units; the margins are in
        :meth:`to_dict`, not here)."""
        out: dict[str, Any] = self.design.to_dict()
        out.update({n: getattr(self, n) for n in (*OBJECTIVES, "epsilon", "family", "status")})
        if self.wheel:
            out["wheel"] = self.wheel
        for name, value in self.multipliers.items():
            out[f"lambda_{name}"] = at_tolerance(value)
        return out


MULTIPLIER_ZERO = 1e-8
"""A constraint multiplier smaller than this in magnitude is zero: IPOPT's acceptable tolerance (the NLP's
``ipopt.acceptable_tol``); below it the solver cannot tell the multiplier from 0 (-9.96e-17 is written 0)."""


def at_tolerance(multiplier: float) -> float:
    """``multiplier``, or 0.0 if it is within :data:`MULTIPLIER_ZERO` of zero (the solver's resolution)."""
    return 0.0 if abs(multiplier) < MULTIPLIER_ZERO else multiplier


_COLUMNS = {v: PARAMETERS[v].column for v in VARIABLES}
"""DataFrame column of each design variable, its SI unit in the name (``trail_m``, ``damping_N_m_per_rad``)."""

CSV_QUANTITIES = {
    **dimensions([*VARIABLES, *OBJECTIVES]),
    "epsilon": "force",  # the cap on P
}
"""The quantities of front.csv and their dimensions: each column carries its unit in its name
(:func:`designer.units.csv_column`: ``trail_in`` or ``trail_mm`` as the problem writes lengths,
``turning_effort_N``, ``critical_speed_m_per_s``); flags (family, status, buildable) and the multipliers
keep their names."""


def _csv_point(r: dict[str, str], where: str) -> "FrontPoint":
    """A front.csv row as a :class:`FrontPoint` (SI); a missing column, a cell that is not a number or a design
    outside the model's range (an old bare-SI file holding inches: a 2 m trail) is an InputError naming ``where``
    (the file and line) and the column."""
    try:
        numbers: dict[str, Any] = {n: _csv_value(r, n) for n in (*OBJECTIVES, "epsilon")}
        point = FrontPoint(
            design=Design(*(_csv_value(r, v) for v in VARIABLES)),
            **numbers,
            margins={},
            status=r["status"],
            success=True,
            family=r["family"],
            multipliers={k[7:]: float(v) for k, v in r.items() if k.startswith("lambda_") and v not in ("", None)},
            wheel=r.get("wheel") or None,
        )
    except KeyError as missing:
        raise InputError(f"{where}: no column {missing} (a front.csv written by designer pareto)") from None
    except ValueError as error:
        raise InputError(f"{where}: {error}") from None
    check_design(point.design, f"{where}: ", error=InputError)
    return point


def _csv_value(r: dict[str, str], key: str) -> float:
    """The SI value of ``key`` in a front.csv row: from its unit-named column (``trail_in``, ``trail_mm``,
    ``turning_effort_N``: :func:`designer.units.csv_quantity`), or from a file written before the columns named
    their units (bare names, SI)."""
    for column, value in r.items():
        name, factor = csv_quantity(column)
        if name == key and column != key:
            return _cell_number(column, value) / factor
    return _cell_number(key, r[key])


def _cell_number(column: str, value: str) -> float:
    """A number cell of front.csv; ValueError naming the column for any other text (an empty cell included)."""
    try:
        return float(value)
    except ValueError:
        raise ValueError(f"column {column} = {value!r}: not a number") from None


@dataclass(frozen=True)
class Front(Record):
    """An exact Pareto front (valid points sorted by decreasing threshold force).

    Iterating yields the valid points, from the cheapest-to-turn design to the
    lowest-threshold-force design.
    """

    problem: Problem
    points: list[FrontPoint]
    failed: list[FrontPoint] = field(default_factory=list)
    meta: dict[str, Any] = field(default_factory=dict)
    continuous_knee: FrontPoint | None = field(default=None, repr=False)
    """The knee of the continuous front, solved for (:func:`designer.studies.front._pareto._continuous_knee`);
    None: the samples' own (a front read from a file, a catalog front of one point per wheel)."""

    _keys = (
        Key("problem", "problem.name"),
        Key("points", "rows()"),
        Key("failed", lambda f: [p.row() for p in f.failed]),
        Key("hypervolume", lambda f: f.hypervolume() if f.points else None),
        Key("hypervolume_reference.normalisation", lambda f: HYPERVOLUME_NORMALISATION),
        Key("hypervolume_reference.ideal", lambda f: f.ideal_nadir()[0] if f.points else None),
        Key("hypervolume_reference.nadir", lambda f: f.ideal_nadir()[1] if f.points else None),
        Key("hypervolume_reference.reference_normalised", lambda f: [1 + REFERENCE_OFFSET] * 2),
        Key("knee", lambda f: f._index(f.knee())),
        Key("knee_point", lambda f: f.continuous_knee.row() if f.continuous_knee is not None else None),
        Key("weighted_best", lambda f: f._index(f.weighted_best())),
        Key("gaps", lambda f: [{"index": i, "what": what} for i, what in f.gaps()]),
        "meta",
    )
    """Plain data (front.json): the points, the failed points, the indicators (the hypervolume of the front
    normalised by its own ideal and nadir), the knee's and the weighted best's index, the gaps and run metadata."""

    def _index(self, point: FrontPoint | None) -> int | None:
        """The position of ``point`` among the points (the sample nearest in P for the continuous knee), or None."""
        if point is None or not self.points:
            return None
        if point in self.points:
            return self.points.index(point)
        return int(np.argmin([abs(p.threshold_force - point.threshold_force) for p in self.points]))

    def __iter__(self) -> Iterator[FrontPoint]:
        return iter(self.points)

    def __len__(self) -> int:
        return len(self.points)

    def objectives(self) -> np.ndarray:
        """(N, 2) array of (turning_effort, threshold_force) [N] of the valid points."""
        return np.array([[p.turning_effort, p.threshold_force] for p in self.points]).reshape(-1, 2)

    def designs(self) -> np.ndarray:
        """(N, 4) array of the designs (SI)."""
        return np.array([p.design.as_array() for p in self.points]).reshape(-1, 4)

    def ideal_nadir(self) -> tuple[np.ndarray, np.ndarray]:
        """Ideal (best of each objective) and nadir (worst on the front) [N]."""
        f = self.objectives()
        return f.min(axis=0), f.max(axis=0)

    def reference_point(self) -> np.ndarray:
        """Stated hypervolume reference: nadir + 10 % of the front's extent, in newtons."""
        ideal, nadir = self.ideal_nadir()
        return nadir + REFERENCE_OFFSET * np.where(nadir > ideal, nadir - ideal, 1.0)

    def hypervolume(
        self, ref: npt.ArrayLike | None = None, ideal: npt.ArrayLike | None = None, nadir: npt.ArrayLike | None = None
    ) -> float:
        """Normalised hypervolume of the front.

        Objectives are normalised by (f − ideal)/(nadir − ideal) with the
        front's own ideal and nadir unless given (give another front's to
        compare fronts); the reference point is (1.1, 1.1) in normalised
        units unless ``ref`` (normalised) is given.
        """
        own_ideal, own_nadir = self.ideal_nadir()
        ideal = own_ideal if ideal is None else np.asarray(ideal, float)
        nadir = own_nadir if nadir is None else np.asarray(nadir, float)
        ref = np.full(2, 1 + REFERENCE_OFFSET) if ref is None else np.asarray(ref, float)
        return hypervolume_2d(normalise(self.objectives(), ideal, nadir), ref)

    def knee(self) -> FrontPoint | None:
        """The knee: the point farthest from the chord between the two ends, in normalised objectives: the
        continuous front's, solved for, when :func:`~designer.studies.front.pareto_front` found one
        (``continuous_knee``), else the farthest of the points."""
        if self.continuous_knee is not None:
            return self.continuous_knee
        if len(self.points) < 3:
            return self.points[0] if self.points else None
        f = normalise(self.objectives(), *self.ideal_nadir())
        a, chord = f[0], f[-1] - f[0]
        if not np.any(chord):
            return self.points[0]
        # the distance from the chord times its length, signed: the knee bulges toward the ideal (> 0)
        return self.points[int(np.argmax((f[:, 0] - a[0]) * chord[1] - (f[:, 1] - a[1]) * chord[0]))]

    def weighted_best(self, weights: Sequence[float] | None = None) -> FrontPoint | None:
        """The front point minimising J = w_turn F_turn + w_threshold P (default weights: the problem's)."""
        if not self.points:
            return None
        w = np.asarray(self.problem.weights if weights is None else weights, float)
        return self.points[int(np.argmin(self.objectives() @ w))]

    def gaps(self, factor: float = 3.0) -> list[tuple[int, str]]:
        """Discontinuities: family switches and jumps larger than ``factor`` × the median spacing.

        Returns (index of the point after the gap, description) pairs.
        """
        out: list[tuple[int, str]] = []
        if len(self.points) < 3:
            return out
        f = normalise(self.objectives(), *self.ideal_nadir())
        steps = np.hypot(*np.diff(f, axis=0).T)
        median = np.median(steps) if np.any(steps > 0) else 0
        for i in range(1, len(self.points)):
            a, b = self.points[i - 1], self.points[i]
            if a.family != b.family:
                out.append((i, f"family switch {a.family} → {b.family} at P ≈ {b.threshold_force:.2f} N"))
            elif median > 0 and steps[i - 1] > factor * median:
                out.append((i, f"jump in the front between P = {a.threshold_force:.2f} and {b.threshold_force:.2f} N"))
        return out

    def compare(self, other: "Front") -> dict[str, float]:
        """Compare with another front on common normalisation (this front's ideal/nadir).

        Returns hypervolumes of both, IGD+ of ``other`` against this front, and
        ``dominated_fraction``: the share of ``other``'s points weakly dominated
        by one of this front's points (a discrete test: a point of ``other``
        that falls between two of this front's points can be dominated by the
        continuous front and still count as not dominated; see
        :func:`designer.studies.checks.front_checks` for the exact test).
        """
        ideal, nadir = self.ideal_nadir()
        mine = normalise(self.objectives(), ideal, nadir)
        theirs = normalise(other.objectives(), ideal, nadir)
        tol = 1e-6
        dominated = [bool(np.any(np.all(mine <= q + tol, axis=1))) for q in theirs]
        return {
            "hypervolume_self": self.hypervolume(ideal=ideal, nadir=nadir),
            "hypervolume_other": other.hypervolume(ideal=ideal, nadir=nadir),
            "igd_plus_other": igd_plus(theirs, mine),
            "dominated_fraction": float(np.mean(dominated)) if dominated else float("nan"),
        }

    def _repr_lines(self) -> list[str]:
        """Two lines within 80 columns: the problem, the number of points and the objective ranges; the knee and
        the hypervolume (no solver runs)."""
        name = getattr(self.problem, "name", "?")
        if not self.points:
            return [f"Front({name!r}: empty, {len(self.failed)} failed)"]
        (f0, p0), (f1, p1) = self.ideal_nadir()
        k = self.knee() or self.points[0]
        return [
            f"Front({name!r}: {len(self.points)} points, F_turn {f0:.3g}–{f1:.3g} N, P {p0:.3g}–{p1:.3g} N,",
            f"  knee F_turn {k.turning_effort:.3g} N / P {k.threshold_force:.3g} N, "
            f"hypervolume {self.hypervolume():.3f})",
        ]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """A compact table with units (notebooks; < 50 ms: benchmarks/notebook_reprs.py)."""
        if not self.points:
            return [("points", "0", ""), ("failed", f"{len(self.failed)}", "")]
        (f0, p0), (f1, p1) = self.ideal_nadir()
        k = self.knee() or self.points[0]
        d = k.design
        return [
            ("points (failed)", f"{len(self.points)} ({len(self.failed)})", ""),
            OUTPUTS["turning_effort"].row(f"{f0:.4g} – {f1:.4g}"),
            OUTPUTS["threshold_force"].row(f"{p0:.4g} – {p1:.4g}"),
            ("knee F_turn / P", f"{k.turning_effort:.4g} / {k.threshold_force:.4g}", "N"),
            ("knee T / d / B", f"{d.trail / INCH:.3f} / {d.diameter / INCH:.3f} / {d.groove / INCH:.3f}", "in"),
            ("knee c_f", f"{d.damping:.4g}", "N·m/rad"),
            ("knee V_c", f"{k.critical_speed:.4g}", "m/s"),
            ("families", ", ".join(dict.fromkeys(p.family for p in self.points if p.family)) or "–", ""),
            ("normalised hypervolume", f"{self.hypervolume():.4f}", ""),
        ]

    def _html_extra(self) -> str:
        """An inline SVG of the curve F_turn(P), the knee marked (axes as :meth:`plot`)."""
        if not self.points:
            return ""
        f = self.objectives()
        k = self.knee() or self.points[0]
        return svg_curve(
            f[:, 1],
            f[:, 0],
            OUTPUTS["threshold_force"].axis_label,
            OUTPUTS["turning_effort"].axis_label,
            marks=[(k.threshold_force, k.turning_effort, "knee")],
        )

    def plot(self, ax: Any = None, color_by: str | None = "family") -> Any:
        """Draw the front, turning effort F_turn [N] against sill force P [N], knee circled; returns the Axes.

        ``color_by``: "family" (the mechanism that stops shimmy), "trail", "diameter", "groove" [mm],
        "damping" [N·m/rad], "critical_speed" [m/s] or None.  The report's front figure draws with the same
        function (:func:`designer.plots.fronts.plot_front`).
        """

        f = self.objectives()
        ax = front_plots.plot_front(
            f[:, 0],
            f[:, 1],
            [p.family for p in self.points],
            ax=ax,
            color_by=color_by,
            designs=self.designs(),
            critical_speed=[p.critical_speed for p in self.points],
            legend=False,
            label="buildable front" if self.meta.get("buildable") else "continuous front",
        )
        knee = self.knee()
        if knee is not None and len(self) >= 3:
            label = f"knee: P {knee.threshold_force:.1f} N, F {knee.turning_effort:.2f} N"
            mark = {n: getattr(knee, n) for n in OBJECTIVES[:2]} | {"kind": "knee", "label": label}
            front_plots.draw_fronts(ax, [], [mark], legend=False)
        if len(self):
            ax.legend(fontsize=7.5, loc="upper right", framealpha=0.92)
        ax.set_title(f"Pareto front: {getattr(self.problem, 'name', '?')}", fontsize=10)
        return ax

    def plot_variables(self, axes: Any = None) -> Any:
        """The design variables T, d, B [mm, in] and c_f [N·m/rad] along the front against P [N].

        Returns the 2 × 2 array of Axes (``axes``: your own 2 × 2 array sharing x, or None for a new figure).
        The report's variables figure draws with the same function
        (:func:`designer.plots.fronts.plot_variables`).
        """

        return front_plots.plot_variables(
            [p.threshold_force for p in self.points],
            self.designs(),
            [p.family for p in self.points],
            [self.problem.bounds[v] for v in VARIABLES],
            self.gaps(),
            axes=axes,
        )

    def to_pandas(self, failed: bool = False) -> Any:
        """The points as a pandas DataFrame, one row per point, SI units in the column names.

        Columns: ``trail_m``, ``diameter_m``, ``groove_m``, ``damping_N_m_per_rad``, ``turning_effort_N``,
        ``threshold_force_N``, ``critical_speed_m_s``, ``epsilon_N``, ``family``, ``status``, ``success``,
        ``wheel``, ``margin_<constraint>`` (units in ``df.attrs["units"]``) and ``lambda_<constraint>``
        (multipliers).  ``failed=True`` adds the failed points with ``failed`` true.  Inverse:
        :meth:`from_pandas`.
        """
        points = [(p, False) for p in self.points] + ([(p, True) for p in self.failed] if failed else [])
        margins = list(dict.fromkeys(m for p, _ in points for m in p.margins))
        lambdas = list(dict.fromkeys(m for p, _ in points for m in p.multipliers))
        columns = [*VARIABLES, *OBJECTIVES, "epsilon_N", "family"]
        columns += ["status", "success", "wheel", *(f"margin_{m}" for m in margins)]
        columns += [f"lambda_{m}" for m in lambdas] + (["failed"] if failed else [])
        records = [
            {
                **p.design.to_dict(),
                **{n: getattr(p, n) for n in OBJECTIVES},
                **{"epsilon_N": p.epsilon, "family": p.family, "status": p.status, "success": bool(p.success)},
                "wheel": p.wheel,
                **{f"margin_{m}": p.margins.get(m, math.nan) for m in margins},
                **{f"lambda_{m}": at_tolerance(p.multipliers.get(m, math.nan)) for m in lambdas},
                **({"failed": bad} if failed else {}),
            }
            for p, bad in points
        ]
        units = {"epsilon_N": "N"}
        units |= {f"margin_{m}": "SI of the constraint (m/s shimmy, m lengths, N forces)" for m in margins}
        units |= {f"lambda_{m}": "CasADi multiplier" for m in lambdas}
        return si_frame("Front.to_pandas", records, columns, units, problem=getattr(self.problem, "name", None))

    @classmethod
    def from_pandas(cls, df: Any, problem: Problem) -> "Front":
        """Rebuild a front from :meth:`to_pandas` output (rows with ``failed`` true go to ``.failed``).

        NaN margins and multipliers are left out of the points' dicts (``to_pandas`` writes NaN where a point
        lacks one).  ``meta`` is ``{"source": "pandas"}``.
        """
        points: list[FrontPoint] = []
        failed: list[FrontPoint] = []
        margin_cols = [c for c in df.columns if c.startswith("margin_")]
        lambda_cols = [c for c in df.columns if c.startswith("lambda_")]
        for r in df.to_dict("records"):
            wheel = r.get("wheel")
            point = FrontPoint(
                design=Design(**{v: float(r[_COLUMNS[v]]) for v in VARIABLES}),
                turning_effort=float(r["turning_effort_N"]),
                threshold_force=float(r["threshold_force_N"]),
                critical_speed=float(r["critical_speed_m_s"]),
                epsilon=float(r["epsilon_N"]),
                margins={c[7:]: float(r[c]) for c in margin_cols if not math.isnan(float(r[c]))},
                multipliers={c[7:]: float(r[c]) for c in lambda_cols if not math.isnan(float(r[c]))},
                status=str(r["status"]),
                success=bool(r["success"]),
                family=str(r["family"]),
                wheel=wheel if isinstance(wheel, str) else None,
            )
            (failed if bool(r.get("failed", False)) else points).append(point)
        return cls(problem=problem, points=points, failed=failed, meta={"source": "pandas"})

    @classmethod
    def from_csv(
        cls, path: str | Path, problem: Problem | str | Path | None = None, buildable: bool = False
    ) -> "Front":
        """Read a front written by :meth:`to_csv`, e.g. a report's ``front.csv`` (SI columns; no pandas needed).

        Parameters
        ----------
        path : the CSV file
        problem : a :class:`~designer.problem.Problem`, the path of a problem file, the name of a shipped
            example (``designer.example_problem``), or None: the problem named in the ``front.json`` beside the
            CSV, when it is a shipped example with the same digest
        buildable : read the buildable front's rows (column ``buildable`` true) instead of the front's

        The margins are not in the CSV (empty dicts); the multipliers are (``lambda_*`` columns).  ``meta`` is
        ``{"source": path}``.
        """
        text = read_input_text(path, "front CSV file", ".csv", error=InputError)  # first: a missing CSV is the reason
        problem = _problem_for_csv(path, problem)
        header, body, lines = csv_table(text, str(path))
        points = []
        for row, line in zip(body, lines):
            r = dict(zip(header, row))
            if (r.get("buildable", "false") == "true") != buildable:
                continue
            points.append(_csv_point(r, f"{path}: line {line}"))
        return cls(problem=problem, points=points, meta={"source": str(path)})

    def rows(self) -> list[dict[str, Any]]:
        """One flat dict per valid point (SI units)."""
        return [p.row() for p in self.points]

    def to_csv(self, path: str | Path, buildable: "Front | None" = None) -> None:
        """Write the valid points: trail_in, diameter_in, groove_in, damping_N_m_per_rad, turning_effort_N,
        threshold_force_N, critical_speed_m_per_s, epsilon_N, family, status, … (:data:`CSV_QUANTITIES`: each
        quantity in the unit its column names, lengths as the problem writes them, ``in`` or ``mm``).

        ``buildable``: the buildable front (``Recommendation.buildable``, when the problem has ``[stock]``):
        its points are added as rows and a column ``buildable`` says true for them, false for this front's.
        The file is replaced atomically, and only if it is new, empty or a front CSV (its header starts with the
        design variables and the objectives): a file of the user's is an OutputError
        (:func:`designer.output.write_file`).
        """
        rows = self.rows()
        columns = [*CSV_QUANTITIES, "family", "status"]
        if buildable is not None:
            rows = [{**r, "buildable": "false"} for r in rows] + [{**r, "buildable": "true"} for r in buildable.rows()]
            columns.append("buildable")
        extra = sorted({k for r in rows for k in r} - set(columns))
        units = getattr(self.problem, "units", "in")
        # the one CSV writer (designer.textfiles): each quantity's column names its unit; names kept from formulas
        table = dict_rows(rows, columns + extra, "{:.10g}", quantities=CSV_QUANTITIES, units=units)
        write_file(path, csv_text(table), "to_csv", example="front.csv", kind=FRONT_CSV)


def clean(points: list[FrontPoint]) -> list[FrontPoint]:
    """Remove dominated and duplicate points; sort by decreasing threshold force."""
    if not points:
        return []
    f = np.array([[p.turning_effort, p.threshold_force] for p in points])
    # tolerance: treat differences below 1e-9 relative as ties
    scale = np.maximum(np.abs(f).max(axis=0), 1e-12)
    rounded = np.round(f / scale, 9)
    keep = nondominated(rounded)
    kept = [p for p, k in zip(points, keep) if k]
    kept.sort(key=lambda p: -p.threshold_force)
    return kept


__all__ = ["REFERENCE_OFFSET", "Front", "FrontPoint", "clean", "family_of"]


def _problem_for_csv(path: str | Path, problem: Problem | str | Path | None) -> Problem:
    """The problem of :meth:`Front.from_csv`: as given, loaded from a file or example name, or found beside."""
    if isinstance(problem, Problem):
        return problem
    if problem is not None:
        text = str(problem)
        return example_problem(text) if text in example_names() else load_problem(text)
    beside = Path(path).with_name("front.json")
    try:
        info = json.loads(beside.read_text(encoding="utf-8"))
        name, digest = info["problem"], info.get("problem_digest")
    except (OSError, ValueError, KeyError):
        raise InputError(
            f"Front.from_csv: problem = None: no front.json beside {path} names the problem; pass "
            "problem= (a Problem, a problem file or an example name)"
        ) from None
    if name in example_names() and (digest is None or example_problem(name).digest() == digest):
        return example_problem(name)
    raise InputError(
        f"Front.from_csv: problem = None: {beside} names {name!r}, which is not a shipped example "
        "with the same digest; pass problem= (a Problem or its problem file)"
    )
