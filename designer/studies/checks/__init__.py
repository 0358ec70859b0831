"""The paper's trade-offs as executable checks (docs/checks.md).

Each check records the paper's claim (its words or number), what we compute,
the error and pass/fail.  :func:`paper_checks` runs the checks that need no
optimisation (1–7, 9, 10); :func:`front_checks` runs check 8 on a computed
Pareto front; :func:`law_checks` the risk law's check (11).  ``designer validate`` prints them; the reports
embed them.

Modules, one kind of check each
-------------------------------
_record  :class:`Check`, its outcomes and kinds, the summary line
_paper   checks 1–7, 9, 10 and the inertia fit, against the paper's numbers
_front   check 8 on a computed front (and the exact dominance test of a tighter front)
_law     check 11: the risk law against the Table 1 wheels, leave one out
_knock   the knock-safe speed's error against Table 1 (the band beside a knock-safe speed)
"""

from __future__ import annotations

from designer.studies.checks._record import (
    FAILS,
    KINDS,
    NOT_APPLICABLE,
    REPRODUCED,
    WITHIN_SCATTER,
    Check,
    CheckValue,
    count_outcomes,
    summary_line,
)
from designer.studies.checks._paper import (
    CENTRAL_90_Z,
    TABLE1_MAX_TOLERANCE,
    TABLE1_RMS_TOLERANCE,
    check_carpet,
    check_eq8,
    check_groove_turning,
    check_inertia_fit,
    check_monotonic,
    check_quadra,
    check_routh_hurwitz,
    check_table1,
    check_threshold_curve,
    check_trail_halves,
    paper_checks,
)
from designer.studies.checks._front import dominated_by_problem, front_checks
from designer.studies.checks._law import (
    LOO_LEVEL,
    check_leave_one_out,
    law_checks,
    leave_one_out_rows,
    write_leave_one_out_table,
)
from designer.studies.checks._knock import knock_safe_table1_error

__all__ = [
    "CENTRAL_90_Z",
    "FAILS",
    "KINDS",
    "LOO_LEVEL",
    "NOT_APPLICABLE",
    "REPRODUCED",
    "TABLE1_MAX_TOLERANCE",
    "TABLE1_RMS_TOLERANCE",
    "WITHIN_SCATTER",
    "Check",
    "CheckValue",
    "check_carpet",
    "check_eq8",
    "check_groove_turning",
    "check_inertia_fit",
    "check_leave_one_out",
    "check_monotonic",
    "check_quadra",
    "check_routh_hurwitz",
    "check_table1",
    "check_threshold_curve",
    "check_trail_halves",
    "count_outcomes",
    "dominated_by_problem",
    "front_checks",
    "knock_safe_table1_error",
    "law_checks",
    "leave_one_out_rows",
    "paper_checks",
    "summary_line",
    "write_leave_one_out_table",
]
