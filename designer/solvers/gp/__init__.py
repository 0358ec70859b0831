"""Geometric programming (cvxpy): the shimmy problem as a sequential GP, a global certificate and duals.

All variables are positive; with the added damping c_d = c_f − c_0 as the variable, F_turn (Eq. 9) is a
posynomial, P/L (Eq. 4A) a truncated posynomial series, I_w a monomial, and the shimmy constraint (Eq. 7)
a signomial condensed to a monomial at the current point (docs/model.md#solvers).  cvxpy is imported here:
load this package only when a GP runs.

Modules
-------
_solve   :func:`solve_gp`, :func:`polish`, :class:`GPResult`; :class:`GPSolver`, the GP as a solver
         of the protocol (:mod:`designer.solvers.base`)
_family  one design family (groove, damper, both, neither) as a GP
_terms   the posynomial terms of the objectives and constraints
"""

from __future__ import annotations

from designer.solvers.gp._solve import GP, GPResult, GPSolver, polish, solve_gp

__all__ = ["GP", "GPResult", "GPSolver", "polish", "solve_gp"]
