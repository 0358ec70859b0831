"""The tool's own exceptions, one per kind of failure, each with an exit code.

The command line prints ``str(error)`` on one line and exits with
``error.exit_code``; the codes are documented in the README.  Also the signals:
SIGINT (Ctrl-C, exit 130) and SIGTERM (``kill``, logout, a service manager; exit 143)
raise :class:`KeyboardInterrupt` (:class:`Terminated` for SIGTERM) and set the flag
checked after every solver call (:func:`check_interrupt`).
"""

from __future__ import annotations

import os
import signal
import stat
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
    """The output cannot be written: the user's setup, not a bug (exit 7).

    A read-only folder, a path that is or lies under a regular file, a folder holding files of the user's
    that the command would replace, a full disk ("no space left on device"), a standard output that
    cannot take the output (``> /dev/full``).  The places are checked before any computing, so no work
    is lost; a later failure removes what was half-written (:mod:`designer.output`).
    """

    exit_code = 7


class ServerError(DesignerError):
    """``designer studio`` cannot listen: the port is in use or cannot be bound (exit 8)."""

    exit_code = 8


# --------------------------------------------------------------------------- Ctrl-C through the solvers

_INTERRUPTED = False


def read_input_text(
    path: str | os.PathLike[str], kind: str, suffix: str, encoding: str = "utf-8", limit: int | None = None
) -> str:
    """The text of an input file (a problem or fleet file), or ProblemError in one line naming the file.

    ``kind`` names the file in the messages ("problem file"), ``suffix`` the expected extension (".toml"):
    ``<path>: no such <kind>``, ``<path>: is a folder, expected a <suffix> <kind>``, or
    ``<path>: cannot read it (<error>)``.  With ``limit`` [bytes], at most ``limit`` + 1 bytes are read:
    a longer file (or an endless one, such as ``/dev/zero``) is ``<path>: larger than <limit> ...``.
    """
    source = str(path)
    if not os.path.exists(path):
        raise ProblemError(f"{source}: no such {kind}")
    if os.path.isdir(path):
        raise ProblemError(f"{source}: is a folder, expected a {suffix} {kind}")
    try:
        with open(path, "rb") as f:
            data = f.read() if limit is None else f.read(limit + 1)
        if limit is not None and len(data) > limit:
            size = _file_size(path)
            what = f"{size:,} bytes" if size > limit else "a device or a pipe that gave more"
            raise ProblemError(
                f"{source}: larger than the {_bytes(limit)} a {kind} may have ({what}); a {kind} is a few kB "
                f"of text: is this the right file?"
            )
        return data.decode(encoding).replace("\r\n", "\n").replace("\r", "\n")
    except (OSError, UnicodeDecodeError) as exc:
        raise ProblemError(f"{source}: cannot read it ({exc.__class__.__name__}: {exc})") from None


def _file_size(path) -> int:
    """The size of a regular file [bytes]; 0 for a device or a pipe (their size says nothing)."""
    try:
        st = os.stat(path)
    except OSError:
        return 0
    return st.st_size if stat.S_ISREG(st.st_mode) else 0


def _bytes(n: int) -> str:
    return f"{n // 2**20} MB" if n % 2**20 == 0 else f"{n:,} bytes"


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived (``kill``, logout, a service manager): handled as Ctrl-C, but the exit code is 143."""


_SIGNAL = 0  # the signal that set _INTERRUPTED


def interrupted() -> bool:
    """True once SIGINT or SIGTERM arrived while :func:`sigint_handler` was installed."""
    return _INTERRUPTED


def interrupt_exit_code(exc: BaseException | None = None) -> int:
    """The exit code of an interruption: 143 (128 + 15) for SIGTERM, 130 (128 + 2) for SIGINT (Ctrl-C)."""
    if isinstance(exc, Terminated) or _SIGNAL == signal.SIGTERM:
        return 128 + signal.SIGTERM
    return 128 + signal.SIGINT


def check_interrupt() -> None:
    """Raise KeyboardInterrupt (Terminated after SIGTERM) if a signal arrived; called after every solver call.

    CasADi (IPOPT), Clarabel and SLSQP run in C, C++ or Fortran: a KeyboardInterrupt raised by the
    default handler while they run is caught inside CasADi (it logs ``KeyboardInterruptException``
    and carries on with the next solve).  :func:`sigint_handler` records the signal in a flag as
    well, and this function turns the flag back into KeyboardInterrupt once the solver returns.
    """
    if _INTERRUPTED:
        raise Terminated if _SIGNAL == signal.SIGTERM else KeyboardInterrupt


def _on_signal(signum, frame):  # the flag survives a KeyboardInterrupt swallowed by a C extension
    global _INTERRUPTED, _SIGNAL
    _INTERRUPTED = True
    _SIGNAL = signum
    raise Terminated if signum == signal.SIGTERM else KeyboardInterrupt


_on_sigint = _on_signal  # its former name


class sigint_handler:
    """Context manager: install the flag-setting handler of SIGINT and SIGTERM (main thread only), restore on exit.

    Both signals raise in the main thread, so every ``finally`` and ``except BaseException`` cleans up (a
    report's temporary folder is removed, the previous report stays); the exit code tells them apart
    (:func:`interrupt_exit_code`).
    """

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __enter__(self):

        global _INTERRUPTED, _SIGNAL
        _INTERRUPTED, _SIGNAL = False, 0
        self._previous: dict = {}
        if threading.current_thread() is threading.main_thread():
            for signum in self.SIGNALS:
                self._previous[signum] = signal.signal(signum, _on_signal)
        return self

    def __exit__(self, *exc):

        global _INTERRUPTED, _SIGNAL
        for signum, previous in self._previous.items():
            signal.signal(signum, previous)
        _INTERRUPTED, _SIGNAL = False, 0
        return False


class QuietAfterInterrupt:
    """A logging filter (``logger.addFilter``) that drops every record once a signal arrived
    (:func:`interrupted`), and any record carrying a KeyboardInterrupt: a library's "trial failed"
    tracebacks are not the user's business after Ctrl-C; the command says "interrupted" in one line."""

    def filter(self, record) -> bool:
        info = record.exc_info
        return not (_INTERRUPTED or (info and isinstance(info[1], KeyboardInterrupt)))
