"""The outcome of an exploration (:class:`ExploreResult`, its files) and the comparison with the exact front."""

from __future__ import annotations

import json
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from designer.textfiles import csv_text, dict_rows
from designer.jsonsafe import finite, stamped
from designer.parameters import OUTPUTS, VARIABLE_TABLE, VARIABLES, dimensions, units_of
from designer.versions import versions
from designer.studies.front import hypervolume_2d, igd_plus, normalise
from designer.problem import Problem
from designer.reprs import Key, Record, dataframe
from designer.plots.svg import svg_curve
from designer.studies.explore._operators import Operators, category_problem, search_space
from designer.studies.explore._storage import _atomic_write_many, _one_line

UNITS = {
    **{p.name: p.ascii_unit for p in VARIABLE_TABLE},
    "turning_effort": "N",
    "threshold_force": "N",
    "critical_speed": "m/s",
    "hypervolume": "N^2",
}
"""The units of explore.json's numbers (``"units"``), ASCII as pint reads them."""


CATEGORICAL = ("wheel", "surface", "turning_mode")
"""Categorical dimensions, in this order in category labels and CSV columns."""

CSV_COLUMNS = (*VARIABLES, "turning_effort", "threshold_force", "critical_speed")
"""The quantities of explore.csv: T, d, B, c_f, F_turn, P, V_c; each column names its unit, its dimension from
the parameter table (:func:`designer.parameters.dimensions`, :func:`designer.textfiles.dict_rows`: ``trail_in`` or ``trail_mm`` as the problem writes lengths,
``damping_N_m_per_rad``, ``turning_effort_N``, ``critical_speed_m_per_s``)."""


# --------------------------------------------------------------------------- result


@dataclass(frozen=True, kw_only=True)
class ExploreResult(Record):
    """The outcome of :func:`explore`.

    Attributes
    ----------
    problem : the problem explored
    study_name, storage : optuna study name and storage (password redacted)
    seed : sampler seed (None: not seeded)
    trials : COMPLETE trials in the study
    front : overall front, list of dicts with the CSV columns [SI], categories, ``trial``, ``refined``
    category_fronts : {category label: front (same dict rows)}
    distinct : distinct parameter sets among the COMPLETE trials
    feasible : COMPLETE trials meeting every constraint
    hypervolume : HV of the front [N²] with ``reference_point``
    comparison : explored vs exact (HV, ratio, IGD+, reference, normalisation) or a note
    operators : the NSGA-II configuration
    refined : whether the fronts were polished by the NLP
    seconds : wall time of the study [s] (trials_per_second = trials run / seconds)
    """

    problem: Problem
    study_name: str
    storage: str
    seed: int | None
    trials: int
    front: list[dict[str, Any]]
    category_fronts: dict[str, list[dict[str, Any]]]
    distinct: int
    feasible: int
    hypervolume: float
    reference_point: tuple[float, ...]
    comparison: dict[str, Any]
    operators: Operators
    refined: bool
    seconds: float
    trials_run: int
    workers: int
    warnings: list[str] = field(default_factory=list)

    _keys = (
        Key("problem", "problem.name"),
        Key("problem_digest", "problem.digest()"),
        *(Key("study", "study_name"), "storage", "seed", "trials", "trials_run", "workers", "seconds"),
        *("trials_per_second", Key("distinct_parameter_sets", "distinct"), Key("feasible_trials", "feasible")),
        *("refined", "operators", Key("units", lambda r: UNITS), "hypervolume", "reference_point", "front"),
        *("category_fronts", "comparison", "warnings", Key("versions", lambda r: versions())),
    )
    """Plain data for explore.json (SI units)."""

    @property
    def trials_per_second(self) -> float:
        return self.trials_run / self.seconds if self.seconds > 0 else float("nan")

    def objectives(self) -> np.ndarray:
        """(n, 2) array of (F_turn, P) [N] of the overall front."""
        return np.array([[r["turning_effort"], r["threshold_force"]] for r in self.front], float).reshape(-1, 2)

    def _ranges(self) -> tuple[str, str]:
        f = self.objectives()
        if not len(f):
            return "–", "–"
        return f"{f[:, 0].min():.4g} – {f[:, 0].max():.4g}", f"{f[:, 1].min():.4g} – {f[:, 1].max():.4g}"

    def _repr_lines(self) -> list[str]:
        """Two lines: trials, front size and objective ranges [N]; hypervolume [N²] against the exact front's."""
        f_range, p_range = self._ranges()
        ratio = self.comparison.get("hypervolume_ratio")
        versus = f" ({ratio:.3f} of the exact front's)" if isinstance(ratio, float) else ""
        return [
            f"ExploreResult({self.problem.name!r}: {self.trials} trials, {self.feasible} feasible, "
            f"front of {len(self.front)} points, F_turn {f_range} N, P {p_range} N)",
            f"  hypervolume {self.hypervolume:.4g} N²{versus}, {self.seconds:.3g} s, seed {self.seed}",
        ]

    def _html_caption(self) -> str:
        return str(self.comparison.get("note", ""))

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """A compact table with units (notebooks; no trial runs)."""
        f_range, p_range = self._ranges()
        c = self.comparison
        rows = [
            ("study (storage)", f"{self.study_name} ({self.storage})", ""),
            ("trials: complete / run here", f"{self.trials} / {self.trials_run}", ""),
            ("feasible / distinct", f"{self.feasible} / {self.distinct}", ""),
            ("front points", f"{len(self.front)}", ""),
            OUTPUTS["turning_effort"].row(f_range),
            OUTPUTS["threshold_force"].row(p_range),
            ("hypervolume", f"{self.hypervolume:.5g}", "N²"),
        ]
        if "hypervolume_ratio" in c:
            rows += [
                ("hypervolume / exact front's", f"{c['hypervolume_ratio']:.4f}", ""),
                ("IGD+ to the exact front (normalised)", f"{c['igd_plus']:.4g}", ""),
            ]
        rows += [
            ("wall time (trials/s)", f"{self.seconds:.3g} ({self.trials_per_second:.3g})", "s"),
            ("seed, workers, NLP-refined", f"{self.seed}, {self.workers}, {'yes' if self.refined else 'no'}", ""),
        ]
        return rows

    def _html_extra(self) -> str:
        """An SVG of the explored front, F_turn against P."""
        f = self.objectives()
        if not len(f):
            return ""
        order = np.argsort(f[:, 1])
        return svg_curve(
            f[order, 1], f[order, 0], OUTPUTS["threshold_force"].axis_label, OUTPUTS["turning_effort"].axis_label
        )

    def to_pandas(self) -> Any:
        """The explored front as a DataFrame, one row per point: the quantities of ``explore.csv`` in SI (``trail``,
        ``diameter``, ``groove``, ``damping``, ``turning_effort``, ``threshold_force``, ``critical_speed``), the
        categories that were explored, ``trial`` and ``refined``; units in ``df.attrs["units"]``."""
        columns = list(dict.fromkeys(k for r in self.front for k in r)) or list(CSV_COLUMNS)
        return dataframe(
            "ExploreResult.to_pandas",
            [dict(r) for r in self.front],
            columns,
            units_of(columns),
            problem=self.problem.name,
            study=self.study_name,
        )

    def write(self, out_dir: str | Path) -> tuple[Path, Path]:
        """Write explore.csv (every per-category front point, ``overall_front`` flag) and explore.json.

        Both are written to temporary files in ``out_dir`` and renamed into
        place, so a reader never sees a half-written file; the folder is made if
        needed, and nothing else in it is touched (:func:`designer.output.output_folder`).
        """
        out = Path(out_dir)
        cats = [name for name in CATEGORICAL if any(name in r for rows in self.category_fronts.values() for r in rows)]
        overall = {(r["trial"], r["turning_effort"], r["threshold_force"]) for r in self.front}
        rows = [
            {
                **r,
                **{c: str(r[c]) for c in cats},
                "overall_front": str((r["trial"], r["turning_effort"], r["threshold_force"]) in overall).lower(),
                "refined": str(r["refined"]).lower(),
                "trial": str(r["trial"]),
            }
            for rows in self.category_fronts.values()
            for r in rows
        ]
        columns = [*CSV_COLUMNS, *cats, "overall_front", "refined", "trial"]
        # the one CSV writer (designer.textfiles): each quantity's column names its unit
        table = dict_rows(rows, columns, "{:.10g}", quantities=dimensions(CSV_COLUMNS), units=self.problem.units)
        csv_path, json_path = out / "explore.csv", out / "explore.json"
        _atomic_write_many(
            {
                csv_path: csv_text(table),
                json_path: json.dumps(stamped("explore.json", finite(self.to_dict())), indent=2) + "\n",
            }
        )
        return csv_path, json_path


# --------------------------------------------------------------------------- fronts


def _box_reference(problem: Problem) -> tuple[float, float]:
    """Fallback HV reference (F_turn, P) [N]: the worst corner of the box (min T, min d, max B, max c_f) of
    every category, +10 %; used only when the exact front (and its stated reference) is unavailable."""
    worst = []
    for cat in search_space(problem).categories():
        sub = category_problem(problem, cat)
        lo, hi = sub.lower(), sub.upper()
        values = sub.evaluate(np.array([[lo.trail, lo.diameter, hi.groove, hi.damping]])).row(0)
        worst.append((values.turning_effort, values.threshold_force))
    return (1.1 * max(w[0] for w in worst), 1.1 * max(w[1] for w in worst))


def _exact_front(problem: Problem) -> dict[str, Any] | None:
    """The exact front of :func:`designer.studies.front._pareto.pareto_front`, or a note when it is unavailable."""
    from designer.studies.front import pareto_front

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            front = pareto_front(problem, points=problem.pareto_points)
            pts = np.asarray(front.objectives(), float).reshape(-1, 2)
            ref = tuple(float(v) for v in front.reference_point())
    except Exception as exc:  # noqa: BLE001 - the exploration is still valid without it
        return {"note": f"exact front failed ({type(exc).__name__}: {_one_line(exc)}); no comparison"}
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) == 0:
        return {"note": "the exact front has no valid points; no comparison"}
    return {"points": pts, "reference_point": ref}


NORMALISATION_NOTE = (
    "(f - ideal)/(nadir - ideal) with the exact front's ideal and nadir; HV in N² "
    "and normalised with the exact front's reference point (nadir + 10 % of its "
    "extent, i.e. (1.1, 1.1) normalised); IGD+ normalised"
)
"""How explore.json's comparison normalises (its ``normalisation.note``)."""


@dataclass(frozen=True, kw_only=True)
class FrontComparison(Record):
    """An explored front against the exact one (:func:`compare_fronts`): explore.json's ``comparison``.

    Attributes
    ----------
    hypervolume_explored, hypervolume_exact : HV of each front with the same reference point [N²]
    hypervolume_explored_normalised, hypervolume_exact_normalised : the same on normalised objectives [-]
    hypervolume_ratio : explored / exact [-] (NaN when the exact HV is 0)
    igd_plus : IGD+ of the explored front to the exact one, normalised [-]
    reference_point : HV reference (F_turn, P) [N]
    ideal, nadir : the exact front's ideal and nadir (F_turn, P) [N]; reference_normalised : the reference
        normalised by them [-] (``normalisation.ideal``, ``.nadir``, ``.reference_normalised``, with a note)
    exact_points : points of the exact front
    """

    hypervolume_explored: float
    hypervolume_exact: float
    hypervolume_explored_normalised: float
    hypervolume_exact_normalised: float
    hypervolume_ratio: float
    igd_plus: float
    reference_point: list[float]
    ideal: list[float]
    nadir: list[float]
    reference_normalised: list[float]
    exact_points: int

    _keys = (
        *("hypervolume_explored", "hypervolume_exact", "hypervolume_explored_normalised"),
        *("hypervolume_exact_normalised", "hypervolume_ratio", "igd_plus", "reference_point"),
        *(Key("normalisation.ideal", "ideal"), Key("normalisation.nadir", "nadir")),
        Key("normalisation.reference_normalised", "reference_normalised"),
        Key("normalisation.note", lambda c: NORMALISATION_NOTE),
        "exact_points",
    )
    """explore.json's ``comparison`` keys."""

    _units = {"hypervolume_explored": "N²", "hypervolume_exact": "N²"}

    def _repr_lines(self) -> list[str]:
        return [
            f"FrontComparison(HV ratio {self.hypervolume_ratio:.4g}, IGD+ {self.igd_plus:.3g} (normalised), "
            f"{self.exact_points} exact points)"
        ]


def compare_fronts(explored: np.ndarray, exact: np.ndarray, reference: Sequence[float]) -> FrontComparison:
    """Explored vs exact front: hypervolume with the same reference, ratio, IGD+ (normalised).

    Parameters
    ----------
    explored, exact : (n, 2) arrays of (F_turn, P) [N]
    reference : HV reference point (F_turn, P) [N] (the exact front's stated one)

    Returns
    -------
    FrontComparison with ``hypervolume_explored`` and ``hypervolume_exact`` [N²], their
    ``hypervolume_ratio``, ``igd_plus`` on objectives normalised by the exact
    front's ideal and nadir, ``reference_point`` and the normalisation; ``to_dict()`` is the dict this
    function returned before (explore.json's ``comparison``).
    """
    exact = np.asarray(exact, float).reshape(-1, 2)
    explored = np.asarray(explored, float).reshape(-1, 2)
    ideal, nadir = exact.min(axis=0), exact.max(axis=0)
    hv_exact = hypervolume_2d(exact, reference)
    hv = hypervolume_2d(explored, reference)
    ref_n = normalise(np.asarray(reference, float)[None, :], ideal, nadir)[0]
    return FrontComparison(
        hypervolume_explored=float(hv),
        hypervolume_exact=float(hv_exact),
        hypervolume_explored_normalised=float(hypervolume_2d(normalise(explored, ideal, nadir), ref_n)),
        hypervolume_exact_normalised=float(hypervolume_2d(normalise(exact, ideal, nadir), ref_n)),
        hypervolume_ratio=float(hv / hv_exact) if hv_exact > 0 else float("nan"),
        igd_plus=float(igd_plus(normalise(explored, ideal, nadir), normalise(exact, ideal, nadir))),
        reference_point=[float(v) for v in reference],
        ideal=ideal.tolist(),
        nadir=nadir.tolist(),
        reference_normalised=ref_n.tolist(),
        exact_points=len(exact),
    )
