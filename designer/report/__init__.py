"""Pareto reports: pictures first, then tables (docs/commands.md#reports).

:func:`write_report` writes ``results/<problem>/`` with ``index.html`` (one
self-contained file, figures as inline SVG), ``report.md`` + ``figures/*.svg``, ``front.csv``,
``front.json`` and ``checks.json``.  :mod:`designer.cli.regenerate`
rebuilds the reports of every shipped problem in one command.

Modules
-------
writer      render a :class:`designer.reportdata.ReportData` (templates, figures, data files) and write it safely
context     the Pareto page's tables as display strings (``build_context``), shared by both templates
formatting  numbers as table cells (through designer.display), for every report kind
files       safe report folders: refuse a foreign folder, replace atomically, keep files not owned
text        the sentences of the report, each generated from the data it states
figures     which plots/ function draws each figure of the Pareto report (as SVG), with which data and hover text
robust      the price-of-safety report (``designer robust``) from a :class:`designer.reportdata.RobustData`
calibration, fleet, limit_cycles   the reports of ``designer calibrate``, ``designer fleet`` and ``designer simulate --report``
(the data are computed by :mod:`designer.pipeline`, and :mod:`designer.jobs` runs the pipeline then the report;
figures are drawn by :mod:`designer.plots`; nothing here imports a study or the pipeline)
"""

from designer.report.context import build_context
from designer.report.writer import write_report
from designer.reportdata import ReportData

__all__ = ["ReportData", "build_context", "write_report"]
