"""Analyses built on the model and the solvers: optimum, Pareto fronts, recommendation, risk, checks,
simulation, calibration, exploration.  Each module takes a :class:`designer.problem.Problem` (or a design)
and returns plain data; nothing here renders a report."""
