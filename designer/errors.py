"""The tool's own exceptions, one per kind of failure, each with an exit code.

The command line prints ``str(error)`` on one line and exits with
``error.exit_code``; the codes are documented in docs/commands.md (errors and exit codes).  Also the signals:
SIGINT (Ctrl-C, exit 130) and SIGTERM (``kill``, logout, a service manager; exit 143)
raise :class:`KeyboardInterrupt` (:class:`Terminated` for SIGTERM) and set the flag
checked after every solver call (:func:`check_interrupt`).
"""

from __future__ import annotations

import errno
import logging
import re
import signal
import sys
import threading


class InertiaExtrapolationWarning(UserWarning):
    """The Table 1 inertia power law evaluated outside its data (4–8 in), at each evaluation: the studies silence
    this class and state the extrapolation once, for the designs they report (:class:`ModelRangeWarning`)."""


class ModelRangeWarning(UserWarning):
    """A design a study reports (a front point, an optimum) lies outside the data its model rests on
    (``Problem.model_warnings``): said once per study; the report states it in its model section."""


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


OS_REASONS: dict[int, str] = {
    errno.ENOENT: "no such file or folder",
    errno.ELOOP: "a symbolic link loop (a link that leads back to itself)",
    errno.EISDIR: "is a folder, expected a file",
    errno.ENOTDIR: "a part of the path is a file, not a folder",
    errno.EACCES: "permission denied",
    errno.EPERM: "operation not permitted",
    errno.EROFS: "read-only file system",
    errno.ENOSPC: "no space left on device",
    errno.EDQUOT: "no space left (disk quota exceeded)",
    errno.EFBIG: "file too large for the file system",
    errno.ENAMETOOLONG: "a name longer than the file system allows",
    errno.EMFILE: "too many open files",
    errno.EIO: "input/output error (a failing disk or a lost network share)",
    errno.ENXIO: "no such device (nothing reads or writes the other end)",
    errno.ENODEV: "no such device",
    errno.ETXTBSY: "the file is busy (a running program)",
    errno.EEXIST: "already exists",
    errno.EXDEV: "on another file system",
    errno.EBUSY: "busy (in use by the system)",
    errno.EINVAL: "not allowed here (an invalid name or operation on this file system)",
}
"""The true reason of each operating-system error a user's setup can cause, by errno: the one table every
message about a file or a folder uses (:func:`os_reason`)."""

WRITE_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EFBIG})
"""The errors that can only mean an output cannot be written (exit 7, :class:`OutputError`); a name too long can
be an input's too (every output is checked for it before any work, :mod:`designer.output`)."""


def os_reason(exc: OSError) -> str:
    """One short line: why ``exc`` happened, by its errno (:data:`OS_REASONS`), else the system's own words."""
    return OS_REASONS.get(exc.errno or 0) or exc.strerror or type(exc).__name__


def system_error(exc: BaseException) -> DesignerError | None:
    """A system error that reached the command's edge, as the tool's own error (one line, its exit code), or None
    for a bug.  An :class:`OSError` names its path and its true reason (:func:`os_reason`): exit 7 when only an
    output can cause it (:data:`WRITE_ERRNOS`), else exit 2; a :class:`RecursionError` is input nested too deeply
    (exit 2); a :class:`UnicodeEncodeError` is an output whose encoding cannot take a character (exit 7)."""
    if isinstance(exc, DesignerError):
        return exc
    if isinstance(exc, OSError) and exc.errno is not None:
        where = " -> ".join(str(f) for f in (exc.filename, exc.filename2) if f is not None) or "a file"
        kind = OutputError if exc.errno in WRITE_ERRNOS else InputError
        return kind(f"{where}: {os_reason(exc)}")
    if isinstance(exc, RecursionError):
        return InputError("the input is nested too deeply to read (thousands of levels of brackets or tables)")
    if isinstance(exc, UnicodeEncodeError):
        return OutputError(
            f"the output's encoding ({exc.encoding}) cannot write {exc.object[exc.start : exc.end]!r}; "
            f"set PYTHONIOENCODING=utf-8 or a UTF-8 locale"
        )
    return None


SECRET_KEYS = r"(?:[A-Za-z0-9_]*(?:password|passwd|pwd|secret|token)|pass|sslkey|odbc_connect)"
"""Keys whose value is a secret, a regular expression matched case-insensitively: a URL's query (``?password=``,
``?sslpassword=``, pymysql's ``passwd``, any ``*_token`` or ``*secret``, an ODBC connection string
``odbc_connect``), libpq's ``key=value`` form (``host=db password=x``) and ODBC's ``PWD=x;``."""

_USERINFO = re.compile(
    r"(?P<lead>(?:[A-Za-z][A-Za-z0-9+.-]*:/{0,3}|/{2,3})?)"  # a scheme with none to three slashes, or bare '//'
    r"(?P<user>[^\s:/@'\"]*):(?!/)(?P<secret>[^\s'\"]*)@"  # user:secret@, up to the last '@' of the host's word
    r"(?=[^\s@'\"/]*(?:[\s/'\"?#]|$))"
)
"""``user:secret@host`` wherever it stands: after ``scheme://``, ``scheme:/``, ``scheme//`` or with no scheme at
all (``caster:S3cretPW@db.example.com/studies``), a raw ``@`` or ``:`` inside the secret included."""

_KEY_VALUE = re.compile(
    rf"(?<![A-Za-z0-9_])(?P<key>{SECRET_KEYS})(?P<eq>\s*(?:=|%3D)\s*)"
    r"(?P<value>'(?:[^'\\]|\\.)*'|\"[^\"]*\"|\{[^}]*\}|[^\s&;#'\"]+)",
    re.IGNORECASE,
)
"""``password=secret`` (a URL's query, libpq's ``password='se cret'``, ODBC's ``PWD={x};``, percent-encoded
``PWD%3Dsecret`` inside an ``odbc_connect``)."""


def mask_secrets(text: str) -> str:
    """``text`` with every secret that looks like a connection string's replaced by ``***``: ``user:secret@host``
    in any URL form (with a scheme and ``://``, ``:/`` or ``//``, or without a scheme) and every secret key's
    value (:data:`SECRET_KEYS`).  Applied to every message the command line prints (one place, so no message
    can show a password), and by :func:`designer.studies.explore._storage.redact_url`."""
    text = _USERINFO.sub(lambda m: f"{m['lead']}{m['user']}:***@", str(text))
    return _KEY_VALUE.sub(lambda m: f"{m['key']}{m['eq']}***", text)


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


def _silent(*_args) -> None:
    """A hook that prints nothing (an unraisable exception or a thread's, after a signal)."""


def quiet_after_signal() -> None:
    """Once SIGINT or SIGTERM arrived the command prints one line, "interrupted", and nothing else: every logger
    is silenced (Dask's ``distributed.*``, optuna's, asyncio's "Task exception was never retrieved"), and so are
    the exceptions of threads and the "Exception ignored in ..." of shutting-down libraries (Dask's atexit
    ``close_clusters``).  :class:`sigint_handler` restores them when its block ends (a caller in the same
    process goes on); the command line then ends the process at once (:func:`designer.entry.main`)."""
    logging.disable(logging.CRITICAL)
    sys.unraisablehook = _silent
    threading.excepthook = _silent


def _on_signal(signum, frame):  # the flag survives a KeyboardInterrupt swallowed by a C extension
    global _INTERRUPTED, _SIGNAL
    _INTERRUPTED = True
    _SIGNAL = signum
    quiet_after_signal()
    raise Terminated if signum == signal.SIGTERM else KeyboardInterrupt


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
        self._quiet = (logging.root.manager.disable, sys.unraisablehook, threading.excepthook)
        self._previous: dict = {}
        if threading.current_thread() is threading.main_thread():
            for signum in self.SIGNALS:
                self._previous[signum] = signal.signal(signum, _on_signal)
        return self

    def __exit__(self, *exc):
        global _INTERRUPTED, _SIGNAL
        for signum, previous in self._previous.items():
            signal.signal(signum, previous)
        if _INTERRUPTED:  # the loggers and hooks as they were before the signal (quiet_after_signal)
            logging.disable(self._quiet[0])
            sys.unraisablehook, threading.excepthook = self._quiet[1], self._quiet[2]
        _INTERRUPTED, _SIGNAL = False, 0
        return False


class QuietAfterInterrupt:
    """A logging filter (``logger.addFilter``) that drops every record once a signal arrived
    (:func:`interrupted`), and any record carrying a KeyboardInterrupt: a library's "trial failed"
    tracebacks are not the user's business after Ctrl-C; the command says "interrupted" in one line."""

    def filter(self, record) -> bool:
        info = record.exc_info
        return not (_INTERRUPTED or (info and isinstance(info[1], KeyboardInterrupt)))
