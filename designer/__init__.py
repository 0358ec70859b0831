"""caster-designer: optimal wheelchair caster design.

Chooses trail T, wheel diameter d, groove width B and spindle friction
damping c_f to minimise turning effort and threshold (door-sill) force with
no shimmy below a target speed (Eq. 7 of the reference paper).
"""
from designer.errors import DesignerError, InfeasibleError, InputError, ProblemError, SolverError
from designer.model import Conditions, Design, evaluate, performance
from designer.optimise import Solution, optimise
from designer.pareto import Front, FrontPoint, pareto_front
from designer.problem import Problem, load_problem, problem_from_dict, problem_from_toml
from designer.robust import Uncertainty

__version__ = "0.1.0"

_LAZY = {"write_report": ("designer.report", "write_report"), "explore": ("designer.exploration", "explore")}
_LAZY["fleet"] = ("designer.analysis.fleet", "fleet")


def __getattr__(name):
    """``designer.write_report`` and ``designer.explore`` import matplotlib / optuna only when first used."""
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module), attr)
    raise AttributeError(f"module 'designer' has no attribute {name!r}")

__all__ = [
    "Conditions",
    "Design",
    "Front",
    "FrontPoint",
    "Solution",
    "Uncertainty",
    "DesignerError",
    "InfeasibleError",
    "InputError",
    "Problem",
    "ProblemError",
    "SolverError",
    "evaluate",
    "explore",
    "load_problem",
    "optimise",
    "pareto_front",
    "performance",
    "problem_from_dict",
    "problem_from_toml",
    "write_report",
]
