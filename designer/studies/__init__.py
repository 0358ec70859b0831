"""Studies: one package per use case, built on the model and the solvers.

Each takes a :class:`designer.problem.Problem` (or a design) and returns result records; nothing here renders
a report.  Each study is a room of its own, used through its ``__init__``; a new analysis becomes a new
package here (CONTRIBUTING.md).

front      exact Pareto fronts, indicators, the groove-damper trade-off
optimum    the scalarised optimum and its cross-checks
recommend  the stock caster to build
retrofit   fixes for a caster that shimmies (``designer fix``)
fleet      per-chair recommendations and part numbers (``designer fleet``)
dynamics   shimmy in time: simulation, onset, limit cycles, knock-safe speeds
explore    optuna exploration and shared studies
robust     the price of safety (nominal against risk-bounded fronts)
sweep      V_c against one part of a caster (the studio's card)
calibrate  the model's constants from the user's rig
checks     the paper's checks and the checks of a front
curves     the arrays the report's paper figures and the docs' stem figure draw

The packages are not imported here: ``import designer.studies.front`` loads only what a front needs.
"""

__all__ = [
    "calibrate",
    "checks",
    "curves",
    "dynamics",
    "explore",
    "fleet",
    "front",
    "optimum",
    "recommend",
    "retrofit",
    "robust",
    "sweep",
]
