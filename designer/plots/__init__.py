"""Figure functions: arrays or plain records in, Axes (matplotlib's, or the SVG canvas of ``svg``) or SVG text out.

They never run a solver; the report, the notebook methods (``front.plot()``) and the studio all draw with
these same functions.  The Pareto report's figures (``figures``) draw on ``svg``, a small SVG canvas with
matplotlib's Axes calls; the notebook methods and the other reports on matplotlib.  Each module is public and
imported on its own (``from designer.plots.figures import ...``): some load matplotlib when imported, so this
package imports none of them."""

__all__ = ["calibration", "caster", "figures", "fleet", "fronts", "simulation", "stem", "svg"]
