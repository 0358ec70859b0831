"""The tool's own exceptions, one per kind of failure, each with an exit code.

The command line prints ``str(error)`` on one line and exits with
``error.exit_code``; the codes are documented in the README.
"""
from __future__ import annotations


class DesignerError(Exception):
    """Base class: a failure the user can act on; the message says how."""

    exit_code = 1


class InputError(DesignerError, ValueError):
    """A value given on the command line or to the API is invalid (exit 2)."""

    exit_code = 2


class ProblemError(InputError):
    """A problem file is invalid: syntax, keys, units or ranges (exit 3)."""

    exit_code = 3


class InfeasibleError(DesignerError):
    """No design inside the bounds meets the constraints (exit 4).

    Attributes
    ----------
    best : dict | None
        The design that comes closest (e.g. the highest reachable V_c).
    """

    exit_code = 4

    def __init__(self, message: str, best: dict | None = None):
        super().__init__(message)
        self.best = best


class SolverError(DesignerError):
    """A numerical solver failed after every retry (exit 5)."""

    exit_code = 5


class StorageError(DesignerError):
    """An optuna storage URL is malformed or unreachable (exit 6)."""

    exit_code = 6
