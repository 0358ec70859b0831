"""Pareto reports: pictures first, then tables (docs/commands.md#reports).

:func:`write_report` writes ``results/<problem>/`` with ``index.html`` (one
self-contained file), ``report.md`` + ``figures/``, ``front.csv``,
``front.json`` and ``checks.json``.  :mod:`designer.commands.regenerate`
rebuilds the reports of every shipped problem in one command.

Modules
-------
writer      gather the report's data, format tables, render, write safely
(figures are drawn by :mod:`designer.plots`; the groove/damper trade-off is computed in
:mod:`designer.analysis.tradeoff`)
"""
from designer.report.writer import ReportData, build_context, write_report

__all__ = ["ReportData", "build_context", "write_report"]
