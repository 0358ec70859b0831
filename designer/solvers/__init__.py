"""Solvers for caster design problems: one model, several tools.

nlp          CasADi/IPOPT exact NLP, built once per problem, multi-start (primary)
shared       one compiled NLP per problem structure (fronts, optimum and check 8c share it)
gp           cvxpy geometric programming: global certificate and duals
scipy_check  SLSQP cross-check from the NLP optimum and random starts
"""

from designer.physics._checks import enable_casadi

enable_casadi()  # the solvers build CasADi symbols from the physics functions
