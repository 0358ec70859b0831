"""The ``designer`` command: one sub-command per module of this package (``designer.cli.<name>``).

Errors are printed as one line on stderr with a non-zero exit code per kind
(see :mod:`designer.errors` and docs/commands.md); ``--debug`` shows the traceback.
Ctrl-C (SIGINT) and SIGTERM print one line and exit 130 and 143, from start-up on
(:mod:`designer.entry` covers the imports before this module); a standard output
closed early (``designer validate --json | head -c5``) ends quietly with exit 141, as a
Unix tool killed by SIGPIPE; a standard output that cannot be written (``> /dev/full``)
is exit 7.
"""

from __future__ import annotations

import argparse
import codecs
import contextlib
import errno
import importlib
import os
import platform
import sys
import warnings
from collections.abc import Iterator

import designer
from designer.cli._common import RUNNING, end_progress_line
from designer.cli._parser import Parser
from designer.cli._terminal import Fitted, fit, width
from designer.errors import (
    DesignerError,
    OutputError,
    interrupt_exit_code,
    interrupted,
    mask_secrets,
    sigint_handler,
    system_error,
)

BROKEN_PIPE = 141
"""Exit code when the reader of standard output went away (``| head``): 128 + SIGPIPE, what a shell reports
for a Unix tool that SIGPIPE ended; quietly, without a message."""

COMMANDS = ["init", "evaluate", "validate", "run", "pareto", "explore", "robust", "simulate", "calibrate", "fleet"]
"""Sub-command modules in designer.cli; each defines ``register(subparsers)``."""
COMMANDS += ["studio", "fix", "spec", "inspect", "completion"]  # spec: the inspection sheet; inspect: goods-in


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every available sub-command."""
    parser = Parser(prog="designer", description="Optimal wheelchair caster design (shimmy, turning, door sills).")
    parser.add_argument("--debug", action="store_true", help="show the full traceback on errors")
    parser.add_argument("--version", action="version", version=_version(), help="print the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for name in COMMANDS:
        importlib.import_module(f"designer.cli.{name}").register(sub)
    return parser


def _version() -> str:
    """``designer 0.1.0 (Python 3.11.9)``: the package's version and the interpreter's."""
    return f"designer {designer.__version__} (Python {platform.python_version()})"


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``designer`` command (via :func:`designer.entry.main`); returns the exit code."""
    _ascii_fallback()  # a terminal that cannot print "·" or "²" gets "*" and "^2", not a UnicodeEncodeError
    with sigint_handler():  # SIGINT and SIGTERM raise (and set a flag checked after every solver call)
        try:
            return _main(argv)
        except KeyboardInterrupt as exc:  # Terminated (SIGTERM) too
            return _interrupted(exc)
        except BrokenPipeError:  # the reader of stdout went away (`| head`): stop quietly
            _silence_stdout()
            return BROKEN_PIPE
        except Exception:
            if interrupted():  # a C extension turned the KeyboardInterrupt into its own error (numpy: ImportError)
                return _interrupted(KeyboardInterrupt())
            raise


def _main(argv: list[str] | None) -> int:
    parser = build_parser()  # imports the sub-commands
    args = parser.parse_args(sys.argv[1:] if argv is None else list(argv))
    if not getattr(args, "command", None):
        parser.print_help()
        return 2
    RUNNING["command"] = args.command
    with warnings.catch_warnings(), _fitted(args):
        warnings.simplefilter("default")
        warnings.showwarning = _one_line_warning
        try:
            code = int(args.func(args) or 0)
            sys.stdout.flush()  # a full or closed stdout fails here, not in the interpreter's last flush
            return code
        except (KeyboardInterrupt, BrokenPipeError):
            raise
        except Exception as exc:
            if interrupted():  # a solver turned the KeyboardInterrupt into its own error (CasADi: RuntimeError)
                raise KeyboardInterrupt from None
            if isinstance(exc, OSError) and (full := _stdout_full(exc)) is not None:
                exc = full
                _silence_stdout()
            # the one place a system error becomes a line and an exit code (OSError by errno, RecursionError, ...)
            return _error(exc if args.debug else (system_error(exc) or exc), args.debug)


@contextlib.contextmanager
def _fitted(args) -> Iterator[None]:
    """Standard output at the terminal's width while the command runs (:class:`designer.cli._terminal.Fitted`:
    every line fitted, trailing spaces removed; ``--wide`` widens it); ``--json`` and what a program reads (a
    command that sets ``fit=False``: the shell's completion script) are left as they are."""
    if getattr(args, "json", False) or not getattr(args, "fit", True):
        yield
        return
    real = sys.stdout
    sys.stdout = Fitted(real, width(bool(getattr(args, "wide", False))))  # type: ignore[assignment]
    try:
        yield
    finally:
        try:
            sys.stdout.flush()
        finally:
            sys.stdout = real


def _interrupted(exc: KeyboardInterrupt) -> int:
    """One line for an interruption (its message if it has one, e.g. how to resume) and its exit code."""
    code = interrupt_exit_code(exc)
    text = str(exc) or ("terminated (SIGTERM)" if code == 143 else "interrupted")
    end_progress_line()  # a "\rcase 3/12" counter: the message on a line of its own
    print(f"designer: {text}", file=sys.stderr, flush=True)
    return code


_FULL_ERRNOS = {errno.ENOSPC: "no space left on device", errno.EDQUOT: "no space left (disk quota exceeded)"}


def _stdout_full(exc: OSError) -> OutputError | None:
    """The OutputError if ``exc`` is a full standard output: a full disk without a file name (every file the tool
    writes goes through :mod:`designer.output`, whose errors name their file), e.g. ``designer validate --json >
    /dev/full``; None otherwise."""
    if exc.errno not in _FULL_ERRNOS or exc.filename is not None:
        return None
    where = ""
    try:  # what stdout is, where the system says (Linux): "/dev/full", "/tmp/out.json"
        where = f" ({os.readlink(f'/proc/self/fd/{sys.__stdout__.fileno()}')})"
    except (OSError, ValueError, AttributeError):
        pass
    return OutputError(f"standard output{where}: {_FULL_ERRNOS[exc.errno or errno.ENOSPC]}; the output is incomplete")


def _silence_stdout() -> None:
    """Point file descriptor 1 at /dev/null: what is still buffered goes nowhere, and the interpreter's last
    flush cannot fail again (it would print "Exception ignored ..." and exit 120)."""
    if sys.stdout is not sys.__stdout__:  # captured (tests): nothing to silence
        return
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass


def _error(exc: Exception, debug: bool) -> int:
    """Print ``exc`` on one line on stderr and return its exit code (re-raise it with --debug)."""
    if debug:
        raise exc
    end_progress_line()
    if isinstance(exc, DesignerError):
        print(f"designer: error: {mask_secrets(str(exc))}", file=sys.stderr)  # no message shows a password
        return exc.exit_code
    # a bug: still one line unless --debug
    print(
        f"designer: internal error: {type(exc).__name__}: {mask_secrets(str(exc))} (run with --debug for the traceback)",
        file=sys.stderr,
    )
    return 70


ASCII_GLYPHS = {
    "·": "*",
    "²": "^2",
    "³": "^3",
    "×": "x",
    "−": "-",
    "–": "-",
    "—": "--",
    "±": "+/-",
    "°": " deg",
    "≤": "<=",
    "≥": ">=",
    "≈": "~",
    "→": "->",
    "←": "<-",
    "…": "...",
    "µ": "u",
    "μ": "mu",
    "α": "alpha",
    "θ": "theta",
    "κ": "kappa",
    "ω": "omega",
    "ρ": "rho",
    "Δ": "Delta",
    "½": "1/2",
    "¼": "1/4",
    "¾": "3/4",
    "‘": "'",
    "’": "'",
    "“": '"',
    "”": '"',
    "✓": "ok",
    "✗": "x",
}
"""ASCII for the glyphs the tool prints, used where the terminal's encoding cannot take them (a C locale)."""


def _ascii_replace(exc: UnicodeError) -> tuple[str, int]:
    """The codec error handler "designer-ascii": a glyph of :data:`ASCII_GLYPHS` in ASCII, any other character as
    a backslash escape; the line is printed either way."""
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    text = exc.object[exc.start : exc.end]
    return "".join(ASCII_GLYPHS.get(ch, ch.encode("ascii", "backslashreplace").decode()) for ch in text), exc.end


def _ascii_fallback() -> None:
    """Standard output and error print what their encoding cannot take through "designer-ascii"
    (:func:`_ascii_replace`) instead of raising UnicodeEncodeError; nothing changes on a UTF-8 terminal."""
    codecs.register_error("designer-ascii", _ascii_replace)
    for stream in (sys.stdout, sys.stderr):
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None and getattr(stream, "errors", "strict") == "strict":
            try:
                reconfigure(errors="designer-ascii")
            except (ValueError, OSError):  # a stream that cannot change (closed, detached)
                pass


_SHOWN: set[str] = set()


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    text = str(message).splitlines()[0] if str(message) else ""
    if text in _SHOWN:  # each distinct warning once per command
        return
    _SHOWN.add(text)
    print(fit(f"designer: warning: {text}"), file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())


__all__ = ["COMMANDS", "build_parser", "main"]
