"""Output at the terminal's width, for every command: one width and one wrap rule.

The width is the terminal's (``COLUMNS`` when set; 80 when standard output is not a terminal), at least
:data:`NARROWEST`.  :func:`fit` is the rule: a line is stripped of trailing spaces, and a line wider than the
width is wrapped at word boundaries with a hanging indent (a ``#`` comment's continuation stays a comment),
never between a number and its unit.
The command line (:func:`designer.cli.main`) sends every text a command prints to standard output through
:class:`Fitted`, so no command can print past the width; tables are drawn at the width by rich
(:func:`console`), their columns giving way (``--wide`` where a command has it).
"""

from __future__ import annotations

import re
import shutil
import sys
import textwrap
from typing import TextIO

NARROWEST = 40
"""Least width [columns] text is wrapped to, however narrow the terminal says it is."""

WIDE = 150
"""The width of ``--wide`` [columns] (at least; a wider terminal keeps its own)."""

_ANSI = re.compile(r"\x1b\[[0-9;]*m")
_NUMBER_UNIT = re.compile(
    r"(?<=\d) (?=(?:%|°|×|m/s\b|mm\b|in\b|N·m/rad|N·m\b|N\b|kg·m²|kg\b|rad/s\b|rad\b|ms\b|s\b|pp\b))"
    r"|(?<=\bEq\.) (?=\d)|(?<=\bFig\.) (?=\d)|(?<=\bTable) (?=\d)"
)
"""The space between a number and its unit (``4.9 %``, ``2.392 m/s``, ``7 in``) or a reference and its number
(``Eq. 7``, ``Table 1``): never a line break."""
_JOIN = "\ue000"
"""Stands for such a space while a line is wrapped (a private-use character: not whitespace to textwrap)."""
_TRAILING = re.compile(r"[ \t]+((?:\x1b\[[0-9;]*m)*)$")


def width(wide: bool = False) -> int:
    """The output width [columns]: ``COLUMNS``, else the terminal's, else 80; at least :data:`NARROWEST`
    (:data:`WIDE` at least with ``wide``)."""
    columns = max(NARROWEST, shutil.get_terminal_size((80, 24)).columns)
    return max(columns, WIDE) if wide else columns


def fit_line(line: str, columns: int) -> str:
    """One line fitted to ``columns``: trailing spaces removed (also before a closing colour code); wider lines
    wrapped at word boundaries, continued with the line's indent plus two spaces (plus ``# `` for a comment,
    so a TOML or shell comment stays one).  A word longer than the width is left whole, and a number is never
    parted from its unit (:data:`_NUMBER_UNIT`)."""
    line = _TRAILING.sub(r"\1", line)
    if len(_ANSI.sub("", line)) <= columns or "\x1b" in line:  # coloured lines are rich's, drawn at the width
        return line
    body = line.lstrip(" ")
    indent = line[: len(line) - len(body)]
    more = indent + ("# " if body.startswith("#") else "  ")
    return textwrap.fill(
        joined(body),
        columns,
        initial_indent=indent,
        subsequent_indent=more,
        break_on_hyphens=False,
        break_long_words=False,
    ).replace(_JOIN, " ")


def fit(text: str, columns: int | None = None) -> str:
    """``text`` with every line fitted by :func:`fit_line` to ``columns`` (default :func:`width`)."""
    columns = width() if columns is None else columns
    return "\n".join(fit_line(line, columns) for line in text.split("\n"))


class Fitted:
    """A text stream that fits every whole line written to it (:func:`fit_line`) before passing it on.

    A line is held until its newline; :meth:`flush` passes on a partial line as it is (a prompt).  Everything
    else (``isatty``, ``fileno``, ``encoding``) is the wrapped stream's, so rich and ``input`` see a terminal
    where there is one.
    """

    def __init__(self, stream: TextIO, columns: int | None = None) -> None:
        self._stream = stream
        self._columns = width() if columns is None else columns
        self._pending = ""

    def write(self, text: str) -> int:
        """Hold ``text``; pass on each whole line fitted."""
        self._pending += text
        if "\n" in self._pending:
            whole, self._pending = self._pending.rsplit("\n", 1)
            self._stream.write(fit(whole, self._columns) + "\n")
        return len(text)

    def flush(self) -> None:
        """Pass on what is held (a partial line as it is) and flush the stream."""
        if self._pending:
            self._stream.write(self._pending)
            self._pending = ""
        self._stream.flush()

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def joined(text: str) -> str:
    """``text`` with the space between each number and its unit made unbreakable for a wrapper that splits at
    whitespace (rich's): :data:`_JOIN`, written back as a space by :class:`_Stdout`."""
    return _NUMBER_UNIT.sub(_JOIN, text)


class _Stdout:
    """``sys.stdout`` as it is at each write (:class:`Fitted` under the command line), with :data:`_JOIN` written
    as the space it stands for."""

    def write(self, text: str) -> int:
        sys.stdout.write(text.replace(_JOIN, " "))
        return len(text)

    def __getattr__(self, name: str):
        return getattr(sys.stdout, name)


def console(wide: bool = False):
    """A rich console drawing at :func:`width` (``wide``: :data:`WIDE` at least), no highlighting of numbers;
    the prose it prints (a string) never wraps between a number and its unit, as :func:`fit_line`.

    It writes to ``sys.stdout`` as it is when it prints, so its lines pass through :class:`Fitted`."""
    from rich.console import Console

    class _Console(Console):
        def print(self, *objects, **kwargs) -> None:
            super().print(*(joined(o) if isinstance(o, str) else o for o in objects), **kwargs)

    return _Console(width=width(wide), highlight=False, file=_Stdout())


def table(title: str, columns, rows=(), **options):
    """A rich table titled ``title`` (left): each column a name or (name, its options: ``justify``, ...), each
    row its cells; every text escaped (rich would read "[in]" as markup and drop it)."""
    from rich.markup import escape
    from rich.table import Table

    out = Table(title=escape(title), title_justify="left", **options)
    for column in columns:
        name, kwargs = (column, {}) if isinstance(column, str) else column
        out.add_column(escape(name), **kwargs)
    for row in rows:
        out.add_row(*(escape(str(cell)) for cell in row))
    return out


__all__ = ["NARROWEST", "WIDE", "Fitted", "console", "fit", "fit_line", "table", "width"]
