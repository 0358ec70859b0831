"""The tool's own exceptions, one per kind of failure, each with an exit code.

The command line prints ``str(error)`` on one line and exits with
``error.exit_code``; the codes are documented in the README.  Also the SIGINT
flag checked after every solver call (:func:`check_interrupt`).
"""

from __future__ import annotations
import os
import signal
import threading


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


class OutputError(DesignerError):
    """The output folder cannot be written: read-only, or a path under a regular file (exit 7).

    Checked before any computing, so no work is lost.
    """

    exit_code = 7


class ServerError(DesignerError):
    """``designer studio`` cannot listen: the port is in use or cannot be bound (exit 8)."""

    exit_code = 8


# --------------------------------------------------------------------------- Ctrl-C through the solvers

_INTERRUPTED = False


def read_input_text(path: str | os.PathLike[str], kind: str, suffix: str, encoding: str = "utf-8") -> str:
    """The text of an input file (a problem or fleet file), or ProblemError in one line naming the file.

    ``kind`` names the file in the messages ("problem file"), ``suffix`` the expected extension (".toml"):
    ``<path>: no such <kind>``, ``<path>: is a folder, expected a <suffix> <kind>``, or
    ``<path>: cannot read it (<error>)``.
    """
    source = str(path)
    if not os.path.exists(path):
        raise ProblemError(f"{source}: no such {kind}")
    if os.path.isdir(path):
        raise ProblemError(f"{source}: is a folder, expected a {suffix} {kind}")
    try:
        with open(path, encoding=encoding) as f:
            return f.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise ProblemError(f"{source}: cannot read it ({exc.__class__.__name__}: {exc})") from None


def interrupted() -> bool:
    """True once SIGINT arrived while :func:`sigint_handler` was installed."""
    return _INTERRUPTED


def check_interrupt() -> None:
    """Raise KeyboardInterrupt if SIGINT arrived; called after every solver call.

    CasADi (IPOPT), Clarabel and SLSQP run in C, C++ or Fortran: a KeyboardInterrupt raised by the
    default handler while they run is caught inside CasADi (it logs ``KeyboardInterruptException``
    and carries on with the next solve).  :func:`sigint_handler` records the signal in a flag as
    well, and this function turns the flag back into KeyboardInterrupt once the solver returns.
    """
    if _INTERRUPTED:
        raise KeyboardInterrupt


def _on_sigint(signum, frame):  # the flag survives a KeyboardInterrupt swallowed by a C extension
    global _INTERRUPTED
    _INTERRUPTED = True
    raise KeyboardInterrupt


class sigint_handler:
    """Context manager: install the flag-setting SIGINT handler (main thread only), restore on exit."""

    def __enter__(self):

        global _INTERRUPTED
        _INTERRUPTED = False
        self._previous = None
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, _on_sigint)
        return self

    def __exit__(self, *exc):

        global _INTERRUPTED
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
        _INTERRUPTED = False
        return False
