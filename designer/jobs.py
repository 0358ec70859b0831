"""The main job in one call: what ``designer pareto`` and the studio's "Write report" run.

:func:`compute_and_write` computes the report's data once (:func:`designer.pipeline.report_data`), hands them
to :func:`designer.report.write_report`, which only renders, and returns a JSON-ready summary.  It lives above
the pipeline and the report (the report layer calls neither the pipeline nor a study) and below the entry
layer, so that the CLI and the studio share it without one entry point importing another.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

from designer.errors import InertiaExtrapolationWarning, ModelRangeWarning
from designer.pipeline import report_data
from designer.report.writer import write_report


def compute_and_write(problem, points=None, out=None, progress=None, force=False, cross_check=False) -> dict:
    """Front, optimum, tighter front, checks and report of ``problem``; returns a summary dict.

    Parameters
    ----------
    problem : designer.problem.Problem
    points : number of front points (default the problem's)
    out : report folder (default ``results/<problem.name>``)
    force : write the report's files into ``out`` even over files of their names not proved the tool's
    cross_check : also run the GP/SLSQP cross-check of the weighted optimum
    progress : optional rich Progress to show the sweeps on

    Returns
    -------
    dict with the report folder, index.html path, counts, optimum and check results, and ``moved``: one line per
    file of an existing report that was rewritten because a value moved beyond its tolerance
    (:func:`designer.report.agreement.keep_agreeing`; a file that agrees keeps its bytes)
    """
    t0 = time.perf_counter()

    def tracker(label):
        if progress is None:
            return None
        task = progress.add_task(label, total=None)
        return lambda done, total: progress.update(task, completed=done, total=total)

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run_meta = {"command": "designer pareto", "points_option": points, "wall_seconds": None}
        data = report_data(problem, points, cross_check=cross_check, progress=tracker, run_meta=run_meta)
        folder = write_report(data, out, force=force)
    seen = set()
    for w in caught:
        text = str(w.message)
        if issubclass(w.category, (InertiaExtrapolationWarning, ModelRangeWarning)) or text in seen:
            continue
        seen.add(text)
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    # once for the problem, and only if a design the report shows (front point, optimum) is extrapolated
    reported = [p.design.diameter for p in data.front.points]
    reported += [data.solution.design.diameter] if data.solution is not None else []
    for message in problem.model_warnings(reported, front=True):
        warnings.warn(message + " (the report says so in its model section)", ModelRangeWarning, stacklevel=2)
    checks = data.checks
    failing = [c.name for c in checks if not c.passed]
    rec = data.recommendation
    return {
        "problem": problem.name,
        "report": str(folder),
        "index_html": str(Path(folder) / "index.html"),
        "points": len(data.front.points),
        "failed_points": len(data.front.failed),
        "recommendation": {**rec.to_dict(), **(data.knock_safe[0] if data.knock_safe else {})}
        if rec is not None
        else None,
        "optimum": data.solution.to_dict() if data.solution is not None else None,
        "checks_passed": len(checks) - len(failing),
        "checks_total": len(checks),
        "failing_checks": failing,
        "failing_front_checks": [name for name in failing if name.startswith("8")],
        "moved": dict(data.run.get("moved") or {}),
        "seconds": time.perf_counter() - t0,
    }
