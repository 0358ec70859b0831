"""Pareto reports: pictures first, then tables (DESIGN §4.4).

:func:`write_report` writes ``results/<problem>/`` with ``index.html`` (one
self-contained file), ``report.md`` + ``figures/``, ``front.csv``,
``front.json`` and ``checks.json``.  :mod:`designer.report.regenerate`
rebuilds the reports of every shipped problem in one command.

Modules
-------
writer      gather the report's data, format tables, render, write safely
figures     the figures (front, variables, Fig. 14, Fig. 15, Fig. 2A, groove vs damper)
tradeoff    least turning effort to stop shimmy by groove, damper or both
regenerate  ``python -m designer.report.regenerate``: every shipped problem
"""
from designer.report.writer import ReportData, build_context, write_report

__all__ = ["ReportData", "build_context", "write_report"]
