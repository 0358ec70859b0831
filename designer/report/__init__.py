"""Pareto reports: pictures first, then tables (docs/commands.md#reports).

:func:`write_report` writes ``results/<problem>/`` with ``index.html`` (one
self-contained file), ``report.md`` + ``figures/``, ``front.csv``,
``front.json`` and ``checks.json``.  :mod:`designer.commands.regenerate`
rebuilds the reports of every shipped problem in one command.

Modules
-------
writer      format the tables of a :class:`designer.pipeline.ReportData`, render, write safely
text        the sentences of the report, each generated from the data it states
build       compute_and_write: the pipeline's data, rendered, and a summary (``designer pareto``, the studio)
robust      the price-of-safety report (``designer robust``) from a :class:`designer.pipeline.RobustData`
(the data are computed by :mod:`designer.pipeline`; figures are drawn by :mod:`designer.plots`)
"""

from designer.report.writer import ReportData, build_context, write_report  # ReportData: from designer.pipeline

__all__ = ["ReportData", "build_context", "write_report"]
