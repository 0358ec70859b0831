"""The ``designer`` command: one sub-command per module of this package (``designer.cli.<name>``).

Errors are printed as one line on stderr with a non-zero exit code per kind
(see :mod:`designer.errors` and the README); ``--debug`` shows the traceback.
"""

from __future__ import annotations

import argparse
import importlib
import re
import sys
import warnings

from designer.errors import DesignerError, interrupted, sigint_handler

COMMANDS = ["evaluate", "validate", "run", "pareto", "explore", "robust", "simulate", "calibrate", "fleet", "studio"]
"""Sub-command modules in designer.cli; each defines ``register(subparsers)``."""
COMMANDS.append("fix")  # issue 18: retrofit


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2, like every input error
        self.exit(2, f"designer: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every available sub-command."""
    parser = _Parser(prog="designer", description="Optimal wheelchair caster design (shimmy, turning, door sills).")
    parser.add_argument("--debug", action="store_true", help="show the full traceback on errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        try:
            module = importlib.import_module(f"designer.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"designer.cli.{name}":
                continue
            raise
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``designer`` console script; returns the exit code."""
    try:
        parser = build_parser()  # imports the sub-commands: Ctrl-C may arrive here too
    except KeyboardInterrupt:
        print("designer: interrupted", file=sys.stderr)
        return 130
    args = parser.parse_args(_join_negative_values(parser, sys.argv[1:] if argv is None else list(argv)))
    if not getattr(args, "command", None):
        parser.print_help()
        return 2
    with warnings.catch_warnings(), sigint_handler():  # Ctrl-C: a flag checked after every solver call
        warnings.simplefilter("default")
        warnings.showwarning = _one_line_warning
        try:
            return int(args.func(args) or 0)
        except KeyboardInterrupt:
            print("designer: interrupted", file=sys.stderr)
            return 130
        except Exception as exc:
            if interrupted():  # a solver turned the KeyboardInterrupt into its own error (CasADi: RuntimeError)
                print("designer: interrupted", file=sys.stderr)
                return 130
            return _error(exc, args.debug)


_NEGATIVE = re.compile(r"^-[0-9.]")


def _join_negative_values(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``--weights -1,1`` -> ``--weights=-1,1``: argparse would read ``-1,1`` as an option and complain
    that ``--weights`` lacks its value; joined, the option's own check names the value."""
    takes_value = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                takes_value |= {s for a in sub._actions if a.nargs != 0 for s in a.option_strings}
    out, i = [], 0
    while i < len(argv):
        if argv[i] in takes_value and i + 1 < len(argv) and _NEGATIVE.match(argv[i + 1]):
            out.append(f"{argv[i]}={argv[i + 1]}")
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out


def _error(exc: Exception, debug: bool) -> int:
    """Print ``exc`` on one line on stderr and return its exit code (re-raise it with --debug)."""
    if debug:
        raise exc
    if isinstance(exc, DesignerError):
        print(f"designer: error: {exc}", file=sys.stderr)
        return exc.exit_code
    # a bug: still one line unless --debug
    print(
        f"designer: internal error: {type(exc).__name__}: {exc} (run with --debug for the traceback)", file=sys.stderr
    )
    return 70


_SHOWN: set[str] = set()


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    text = str(message).splitlines()[0] if str(message) else ""
    if text in _SHOWN:  # each distinct warning once per command
        return
    _SHOWN.add(text)
    print(f"designer: warning: {text}", file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())


__all__ = ["COMMANDS", "build_parser", "main"]
