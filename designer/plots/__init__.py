"""Figure functions: arrays or plain records in, matplotlib Axes (or SVG text) out.

They never run a solver; the report, the notebook methods (``front.plot()``) and the studio all draw with
these same functions.  matplotlib is imported by the modules here, never by ``import designer``."""
