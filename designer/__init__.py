"""caster-designer: optimal wheelchair caster design.

Chooses trail T, wheel diameter d, groove width B and spindle friction
damping c_f to minimise turning effort and threshold (door-sill) force with
no shimmy below a target speed (Eq. 7 of the reference paper).

``import designer`` loads NumPy and the physics only; the solvers (CasADi,
cvxpy), optuna, matplotlib and the rest load when a function that needs them
is first used (the names below are resolved lazily).
"""

from __future__ import annotations

import importlib

from designer.errors import DesignerError, InfeasibleError, InputError, ProblemError, SolverError
from designer.model import Conditions, Design, evaluate, performance
from designer.physics.uncertainty import Uncertainty

__version__ = "0.1.0"

# name -> module that defines it; imported on first use (keeps `import designer` light).
_LAZY = {
    "Problem": "designer.problem",
    "load_problem": "designer.problem",
    "problem_from_dict": "designer.problem",
    "problem_from_toml": "designer.problem",
    "Solution": "designer.analysis.optimise",
    "optimise": "designer.analysis.optimise",
    "Front": "designer.analysis.pareto",
    "FrontPoint": "designer.analysis.pareto",
    "pareto_front": "designer.analysis.pareto",
    "explore": "designer.analysis.exploration",
    "write_report": "designer.report",
    "report_data": "designer.pipeline",
    "fleet": "designer.analysis.fleet",
    "knock_safe_speed": "designer.analysis.limit_cycles",
    "bifurcation_diagram": "designer.analysis.limit_cycles",
    "TyreParameters": "designer.physics.tyre",
    "recommend": "designer.analysis.recommend",
    "Recommendation": "designer.analysis.recommend",
    "simulate": "designer.analysis.simulate",
}
_LAZY["fix"] = "designer.analysis.retrofit"  # issue 18: retrofit
_LAZY["example_problem"] = "designer.examples"  # issue 17: shipped example problems (package data)
_LAZY["example_names"] = "designer.examples"


def __getattr__(name: str):
    """Resolve the lazily imported public names of :data:`_LAZY`."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'designer' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "Conditions",
    "Design",
    "DesignerError",
    "InfeasibleError",
    "InputError",
    "ProblemError",
    "SolverError",
    "Uncertainty",
    "evaluate",
    "performance",
    *_LAZY,
]
