"""caster-designer: optimal wheelchair caster design.

Chooses trail T, wheel diameter d, groove width B and spindle friction
damping c_f to minimise turning effort and threshold (door-sill) force with
no shimmy below a target speed (Eq. 7 of the reference paper).

``import designer`` loads nothing: the error classes, the model (NumPy),
the solvers (CasADi, cvxpy), optuna, matplotlib and the rest load when a name
that needs them is first used (the names below are resolved lazily).  So the
``designer`` command installs its Ctrl-C handler before any heavy import
(:mod:`designer.entry`).
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

# name -> module that defines it; imported on first use (keeps `import designer` light).
_LAZY = {
    "DesignerError": "designer.errors",
    "InfeasibleError": "designer.errors",
    "InputError": "designer.errors",
    "ProblemError": "designer.errors",
    "SolverError": "designer.errors",
    "Caster": "designer.model",
    "Casters": "designer.model",
    "Conditions": "designer.model",
    "Design": "designer.model",
    "evaluate": "designer.model",
    "performance": "designer.model",
    "Uncertainty": "designer.physics.uncertainty",
    "PowerLaw": "designer.physics.inertia",
    "Fixed": "designer.physics.inertia",
    "Problem": "designer.problem",
    "load_problem": "designer.problem",
    "problem_from_dict": "designer.problem",
    "problem_from_toml": "designer.problem",
    "example_problem": "designer.problem",
    "example_names": "designer.problem",
    "Solution": "designer.studies.optimum",
    "optimise": "designer.studies.optimum",
    "Front": "designer.studies.front",
    "FrontPoint": "designer.studies.front",
    "pareto_front": "designer.studies.front",
    "explore": "designer.studies.explore",
    "write_report": "designer.report",
    "report_data": "designer.pipeline",
    "fleet": "designer.studies.fleet",
    "knock_safe_speed": "designer.studies.dynamics.limit_cycles",
    "bifurcation_diagram": "designer.studies.dynamics.limit_cycles",
    "TyreParameters": "designer.physics.tyre",
    "recommend": "designer.studies.recommend",
    "Recommendation": "designer.studies.recommend",
    "simulate": "designer.studies.dynamics",
    "fix": "designer.studies.retrofit",
}


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


__all__ = list(_LAZY)
