"""Figure functions: arrays or plain records in, matplotlib Axes (or SVG text) out.

They never run a solver; the report, the notebook methods (``front.plot()``) and the studio all draw with
these same functions.  Each module is public and imported on its own (``from designer.plots.figures import
...``): some load matplotlib when imported, so this package imports none of them."""

__all__ = ["calibration", "caster", "figures", "fleet", "fronts", "simulation", "stem"]
