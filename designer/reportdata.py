"""The data one report shows, computed by :mod:`designer.pipeline` and handed to :mod:`designer.report`, which
renders them and computes nothing.

:class:`ReportData` is what a Pareto report shows (``designer pareto``, the studio), :class:`RobustData` the
price-of-safety report (``designer robust``).  They live here, between the studies that make their parts and the
pipeline that fills them, so that the report layer reads them without importing a study or the pipeline.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from designer.display import number, shown
from designer.physics.uncertainty import Uncertainty
from designer.problem import Problem
from designer.reprs import Key, Record, dataframe

if TYPE_CHECKING:  # record types for the checker only: designer.studies.front and .optimum load casadi
    from designer.studies.checks import Check
    from designer.studies.front import Front, TradeoffRow
    from designer.studies.optimum import Solution
    from designer.studies.recommend import Recommendation

CROSS_CHECK_COMMAND = "designer pareto {problem} --cross-check"
"""How to run the GP and SLSQP cross-check of the weighted optimum (kept out of the main job for speed)."""


@dataclass(kw_only=True)
class ReportData(Record):
    """Everything one Pareto report shows, computed; SI units throughout.

    Attributes
    ----------
    problem : designer.problem.Problem
    front : the exact front the problem asks for (failed points in ``front.failed``)
    tighter : front for V_target × :data:`TIGHTER_FACTOR` (check 8c), or None
    recommendation : the Recommendation or None; ``recommendation_error`` says why not
    price_of_stock : :func:`price_of_stock` of the recommendation against ``front``, or None
    knock_safe : per caster of the "Build this" card (recommendation, then its alternatives), the dict of
        :func:`designer.studies.dynamics.limit_cycles.knock_safe_speeds` (``knock_safe_speed``,
        ``knock_safe_speed_double`` [m/s]); empty without a recommendation
    solution : the weighted optimum (:class:`designer.studies.optimum._optimise.Solution`) or None
    solution_error : why the optimum is missing, if it is
    cross_checked : whether the GP/SLSQP cross-check ran (``--cross-check``)
    paper_checks, front_checks : lists of :class:`designer.studies.checks.Check`
    checks_summary : the checks counted in one sentence (:func:`designer.studies.checks.summary_line`)
    knock_safe_band : the knock-safe speed's error against Table 1 at the problem's knock θ0
        (:func:`designer.studies.checks.knock_safe_table1_error`: ``angle`` [rad], ``log_rms``, ``bias``); None
        without knock-safe speeds
    tradeoff : rows of :func:`designer.studies.front._tradeoff.groove_damper_tradeoff`
    curves : the arrays of the paper figures and of the groove–damper plane
        (:func:`designer.studies.curves.report_curves`); not in :meth:`to_dict`
    gaps : ``front.gaps()``
    degenerate_reason, degenerate_reason_short : why a front has fewer than two points ("" otherwise)
    run : metadata (date, versions, digest, solver settings, seconds per step)
    """

    _open = "the report's working data: the writer adds its run record (timings, files moved) as it writes"

    problem: Problem
    front: Front
    tighter: Front | None = None
    recommendation: Recommendation | None = None
    recommendation_error: str = ""
    price_of_stock: dict[str, float | None] | None = None
    knock_safe: list[dict[str, float]] = field(default_factory=list)
    solution: Solution | None = None
    solution_error: str = ""
    cross_checked: bool = False
    paper_checks: list[Check] = field(default_factory=list)
    front_checks: list[Check] = field(default_factory=list)
    checks_summary: str = ""
    knock_safe_band: dict[str, float] | None = None
    tradeoff: list[TradeoffRow] = field(default_factory=list)
    curves: dict[str, Any] = field(default_factory=dict, repr=False)
    gaps: list[tuple[int, str]] = field(default_factory=list)
    degenerate_reason: str = ""
    degenerate_reason_short: str = ""
    run: dict[str, Any] = field(default_factory=dict)

    _keys = ("*", Key("recommendation", options={"alternatives": True}))
    """Plain data of everything the report shows: the problem, the fronts, the recommendation (with its
    alternatives), the optimum, the checks, the trade-off table, the gaps and the run metadata (SI)."""

    def to_pandas(self) -> Any:
        """The checks, one row per check: ``name``, ``kind``, ``outcome``, ``passed``, ``expected``, ``got``,
        ``claim`` and ``detail`` (the report's checks table)."""
        columns = ["name", "kind", "outcome", "passed", "expected", "got", "claim", "detail"]
        rows = [{k: c.to_dict()[k] for k in columns} for c in self.checks]
        return dataframe("ReportData.to_pandas", rows, columns, {}, problem=self.problem.name)

    def _repr_lines(self) -> list[str]:
        """One line: the problem, the front, the recommendation and the checks that failed."""
        rec = self.recommendation
        built = (
            f"build T {shown(rec.design.trail, 'trail', 'in')}, d {shown(rec.design.diameter, 'diameter', 'in')}"
            if rec
            else "no caster"
        )
        failed = [c.name for c in self.checks if not c.passed]
        return [
            f"ReportData({self.problem.name!r}: front of {len(self.front.points)} points, {built}, "
            f"{len(self.checks)} checks, {len(failed)} failed{': ' + ', '.join(failed) if failed else ''})"
        ]

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """The headline numbers of the report (no solver runs)."""
        rows: list[tuple[Any, Any, Any]] = [
            ("front points (failed)", f"{len(self.front.points)} ({len(self.front.failed)})", "")
        ]
        rec = self.recommendation
        if rec is not None:
            forces = number(rec.turning_effort, "turning_effort"), number(rec.threshold_force, "threshold_force")
            rows += [("recommendation", rec.design.describe(), ""), ("its F_turn / P", " / ".join(forces), "N")]
        else:
            rows.append(("recommendation", self.recommendation_error or "none", ""))
        if self.solution is not None:
            rows.append(("weighted optimum J", number(self.solution.objectives["weighted"], "weighted"), "N"))
        failed = [c.name for c in self.checks if not c.passed]
        rows.append(("checks (failed)", f"{len(self.checks)} ({', '.join(failed) or 'none'})", ""))
        return rows

    @property
    def checks(self) -> list[Check]:
        """Paper checks then front checks."""
        return self.paper_checks + self.front_checks

    @property
    def cross_check_command(self) -> str:
        """The command that runs the solver cross-check for this problem."""
        source = getattr(self.problem, "source", None) or f"problems/{self.problem.name}.toml"
        return CROSS_CHECK_COMMAND.format(problem=source)


@dataclass(kw_only=True)
class RobustData(Record):
    """The price-of-safety comparison of one problem: nominal against risk-bounded fronts (SI).

    Attributes
    ----------
    problem : the problem (with its risk bound)
    nominal, robust : the nominal (Eq. 7) and risk-bounded fronts
    rows : per risk-bounded point: P, F_turn robust and nominal (interpolated), extra, V_c, Monte Carlo P(shimmy)
    compare : hypervolumes of the two fronts (``Front.compare``)
    uncertainty : the :class:`~designer.physics.uncertainty.Uncertainty` of the bound
    run : metadata (date, versions, digest, CPU seconds)
    """

    _open = "the report's working data: the writer adds its run record (timings, files moved) as it writes"

    problem: Problem
    nominal: Front
    robust: Front
    rows: list[dict[str, float]]
    compare: dict[str, float]
    uncertainty: Uncertainty
    run: dict[str, Any] = field(default_factory=dict)

    def to_pandas(self) -> Any:
        """One row per risk-bounded point: P, F_turn risk-bounded and nominal, the extra effort [N], V_c [m/s] and
        the Monte Carlo P(shimmy) of both designs (the report's table)."""
        columns = list(self.rows[0]) if self.rows else ["threshold_force"]
        units = {c: "N" for c in columns if c.startswith(("threshold", "turning", "extra"))}
        units["critical_speed"] = "m/s"
        rows = [dict(r) for r in self.rows]
        return dataframe("RobustData.to_pandas", rows, columns, units, problem=self.problem.name)

    def _repr_lines(self) -> list[str]:
        """One line: the two fronts and the largest extra turning effort the risk bound costs."""
        extra = [r["extra_effort"] for r in self.rows if np.isfinite(r["extra_effort"])]
        most = f", extra F_turn up to {shown(max(extra), 'turning_effort')}" if extra else ""
        return [
            f"RobustData({self.problem.name!r}: nominal front {len(self.nominal.points)} points, risk-bounded "
            f"{len(self.robust.points)} points at α = {self.uncertainty.probability:g}{most})"
        ]


__all__ = ["CROSS_CHECK_COMMAND", "ReportData", "RobustData"]
