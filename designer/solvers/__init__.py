"""Solvers for caster design problems: one model, several tools.

Modules (each imported on its own, so that loading one solver does not load another's library)
-------
nlp          CasADi/IPOPT exact NLP, built once per problem, multi-start (primary)
cache        one compiled NLP per problem structure (fronts, optimum and check 8c share it)
closed_form  closed-form ε-optima of the front where the structure allows (checked by the NLP)
gp           cvxpy geometric programming: global certificate and duals
slsqp        SciPy SLSQP cross-check from the NLP optimum and random starts
"""

from designer.physics import enable_casadi

enable_casadi()  # the solvers build CasADi symbols from the physics functions

__all__ = ["enable_casadi"]
