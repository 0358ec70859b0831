"""The tool's text files in one place: the rules every reader shares, and the one CSV writer.

Readers (the TOML problem file, the CSV data of ``designer calibrate`` and ``designer fleet``, a front's
``front.csv``) read through :func:`read_input_text` and :func:`csv_table`, so they refuse the same things with
the same one-line messages: a path that is neither a regular file nor a pipe (a folder, a character device such
as ``/dev/zero``, a socket; a pipe such as ``<(cat f)`` is read once, under the same size limit), a symbolic link loop or any other system error by its true reason
(:func:`designer.errors.os_reason`), a UTF-16/UTF-32 file (a byte-order mark: text, but not UTF-8), bytes that
are not UTF-8, a file over its size limit, a CSV cell over :data:`MAX_CELL` characters, a column named twice.

Every CSV the tool writes (fleet.csv, front.csv, explore.csv, the calibration's and the simulations' tables, a
fleet written by ``--example``) goes through :func:`csv_text`: a text cell that a spreadsheet would run as a
formula (starting with ``=``, ``+``, ``-``, ``@``, a tab or a carriage return) gets a leading ``'`` (OWASP's
advice against CSV injection); numbers, negative ones included, stay numbers.  The readers drop that ``'``
again (:func:`restore_cell`), so what the tool writes it reads back as it was.
"""

from __future__ import annotations

import csv
import io
import itertools
import math
import os
import re
import select
import stat
import threading
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from designer.errors import InputError, ProblemError, os_reason
from designer.units import csv_column

FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")
"""First characters that make a spreadsheet read a cell as a formula (OWASP, CSV injection)."""

MAX_CELL = 10_000
"""Longest CSV cell a reader accepts [characters]: a name or a number is a few dozen; a longer cell is
another file's content (the csv module's own limit, 131 072, would end in its own error instead)."""

PIPE_LIMIT = 64 * 2**20
"""Most bytes read from a pipe when the reader has no limit of its own [bytes]."""

PIPE_WAIT_SECONDS = 5.0
"""How long a reader waits for a process to write into a named FIFO before it gives up [s]."""

_NUMBER = re.compile(r"^[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?$")

_WIDE_MARKS = (
    (b"\xff\xfe\x00\x00", "UTF-32"),
    (b"\x00\x00\xfe\xff", "UTF-32"),
    (b"\xff\xfe", "UTF-16"),
    (b"\xfe\xff", "UTF-16"),
)
"""Byte-order marks of the wide Unicode encodings, longest first (UTF-32 LE starts as UTF-16 LE does)."""


# --------------------------------------------------------------------------- reading


def not_a_file(path: str | os.PathLike[str]) -> str | None:
    """What ``path`` is when it exists and is not a regular file ("a folder", "a character device", "a pipe
    (FIFO)", ...), following links; None for a regular file, a path that does not exist yet, or a link loop (the
    reader's own open says so)."""
    try:
        return _kind_of_file(os.stat(path).st_mode)
    except OSError:
        return None


def _kind_of_file(mode: int) -> str | None:
    """What a path that is not a regular file is ("a folder", "a character device", ...); None for a file."""
    if stat.S_ISREG(mode):
        return None
    kinds = (
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISFIFO, "a pipe (FIFO)"),
        (stat.S_ISSOCK, "a socket"),
    )
    return next((name for test, name in kinds if test(mode)), "not a regular file")


def read_input_text(
    path: str | os.PathLike[str],
    kind: str,
    suffix: str,
    limit: int | None = None,
    error: type[InputError] = ProblemError,
) -> str:
    """The text of an input file (a problem, a fleet, a calibration's data), or ``error`` in one line naming it.

    ``kind`` names the file in the messages ("problem file"), ``suffix`` the expected extension (".toml"):
    ``<path>: no such <kind>``, ``<path>: is a folder, expected a <suffix> <kind>`` (a character device, a
    FIFO, a socket likewise), ``<path>: a symbolic link loop``, ``<path>: permission denied`` (every system
    error by its errno, :func:`designer.errors.os_reason`), ``<path>: UTF-16 text, not UTF-8 ...``.  With
    ``limit`` [bytes], at most ``limit`` + 1 bytes are read: a longer file is ``<path>: larger than <limit>``.
    A UTF-8 byte-order mark is dropped; line ends become ``\\n``.
    """
    source = str(path)
    try:
        st = os.stat(path)
    except OSError as exc:
        reason = f"no such {kind}" if isinstance(exc, FileNotFoundError) else os_reason(exc)
        raise error(f"{source}: {reason}") from None
    other = _kind_of_file(st.st_mode)
    if other is not None and not stat.S_ISFIFO(st.st_mode):  # a pipe (<(cat f), a named FIFO) is read once
        raise error(f"{source}: is {other}, expected a {suffix} {kind}")
    try:
        if stat.S_ISFIFO(st.st_mode):  # read once, never without end, never waiting for ever for a writer
            data = _read_pipe(path, source, PIPE_LIMIT if limit is None else limit, error)
        else:
            with open(path, "rb") as f:
                data = f.read() if limit is None else f.read(limit + 1)
    except OSError as exc:
        raise error(f"{source}: cannot read it ({os_reason(exc)})") from None
    if limit is not None and len(data) > limit:
        size = f"{st.st_size:,} bytes" if stat.S_ISREG(st.st_mode) else f"more than {limit:,} bytes from a pipe"
        most = f"{limit // 2**20} MB" if limit % 2**20 == 0 else f"{limit:,} bytes"
        raise error(
            f"{source}: larger than the {most} a {kind} may have ({size}); a {kind} is a "
            f"few kB of text: is this the right file?"
        )
    for mark, name in _WIDE_MARKS:
        if data.startswith(mark):
            raise error(f"{source}: {name} text (it starts with a {name} byte-order mark); save the {kind} as UTF-8")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise error(f"{source}: line {line}: not UTF-8 text (byte 0x{data[exc.start]:02x}); save it as UTF-8") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _read_pipe(path, source: str, limit: int, error: type[InputError]) -> bytes:
    """At most ``limit`` + 1 bytes of a pipe (``<(cat f)``, a named FIFO), read once.  A FIFO that no process
    writes to within :data:`PIPE_WAIT_SECONDS` is ``error`` (its plain open would wait for ever)."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)  # returns at once, a writer or not
    try:
        poll = select.poll()
        poll.register(fd, select.POLLIN | select.POLLHUP)
        if not poll.poll(int(PIPE_WAIT_SECONDS * 1000)):
            raise error(
                f"{source}: a pipe (FIFO) that nothing writes to (waited {PIPE_WAIT_SECONDS:g} s); start its writer "
                f"first, or give the file itself"
            )
        os.set_blocking(fd, True)
        chunks, size = [], 0
        while size <= limit and (chunk := os.read(fd, min(1 << 16, limit + 1 - size))):
            chunks.append(chunk)
            size += len(chunk)
        return b"".join(chunks)
    finally:
        os.close(fd)


_FIELD_LIMIT = threading.Lock()


def csv_table(
    text: str, source: str, error: type[InputError] = InputError, max_cell: int = MAX_CELL
) -> tuple[list[str], list[list[str]], list[int]]:
    """The header, the rows and each row's line number of CSV ``text`` (comment lines ``#`` and blank lines
    skipped), by the readers' shared rules; ``error`` (one line naming ``source``) when:

    - the csv module cannot parse it (an unclosed quote): ``<source>: line N: not CSV (...)``;
    - a cell is longer than ``max_cell`` characters: ``<source>: row N, column C: a cell of K characters ...``;
    - a column is named twice: ``<source>: column 'x': x appears twice in the header``.

    A cell the CSV writer protected from spreadsheets (``'=x``) is read as it was written (:func:`restore_cell`).
    """
    numbered = [(i + 1, ln) for i, ln in enumerate(text.split("\n")) if ln.strip() and not ln.lstrip().startswith("#")]
    if not numbered:
        return [], [], []
    rows: list[list[str]] = []
    with _FIELD_LIMIT:  # the csv module's limit is process-wide: raised for this parse, cells checked below
        previous = csv.field_size_limit(max(len(text) + 1, csv.field_size_limit()))
        try:
            reader = csv.reader(io.StringIO("\n".join(ln for _, ln in numbered), newline="\n"), strict=True)
            try:
                rows = list(reader)
            except csv.Error as exc:
                line = numbered[min(reader.line_num, len(numbered)) - 1][0]
                raise error(f"{source}: line {line}: not CSV ({exc})") from None
        finally:
            csv.field_size_limit(previous)
    # the first line of each row (a quoted cell may span lines)
    starts = itertools.accumulate((1 + sum(cell.count("\n") for cell in row) for row in rows), initial=0)
    lines = [numbered[min(k, len(numbered) - 1)][0] for k, _ in zip(starts, rows)]
    header = [restore_cell(h) for h in rows[0]]
    for r, row in enumerate(rows):
        for c, cell in enumerate(row):
            if len(cell) > max_cell:
                column = header[c] if c < len(header) else f"#{c + 1}"
                raise error(
                    f"{source}: row {lines[r]}, column {column[:40]!r}: a cell of {len(cell):,} characters; a cell "
                    f"holds at most {max_cell:,} (is this the right file?)"
                )
    seen: set[str] = set()
    for h in header:
        if h.strip() in seen:
            raise error(f"{source}: column {h!r}: {h.strip()} appears twice in the header")
        seen.add(h.strip())
    body = [[restore_cell(cell) for cell in row] for row in rows[1:]]
    return header, body, lines[1:]


# --------------------------------------------------------------------------- writing


def safe_cell(value: Any) -> Any:
    """A CSV cell as the tool writes it: a number as it is (a negative one included: ``-3.2`` stays a number), a
    text starting with ``=``, ``+``, ``-``, ``@``, a tab or a carriage return with a leading ``'`` (a spreadsheet
    shows it as text instead of running it as a formula), any other text as it is."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value)).lower()
    if isinstance(value, (int, float, np.integer, np.floating)):
        return value
    text = "" if value is None else str(value)
    if text.startswith(FORMULA_STARTS) and not _NUMBER.match(text):
        return "'" + text
    return text


def restore_cell(cell: str) -> str:
    """A cell as it was before :func:`safe_cell` protected it: ``'=x`` -> ``=x`` (only before a formula
    character; any other ``'`` is the user's)."""
    # a carriage return read from a file is a line feed by then (read_input_text): "'\n" was "'\r"
    if cell.startswith("'") and cell[1:].startswith((*FORMULA_STARTS, "\n")) and not _NUMBER.match(cell[1:]):
        return cell[1:]
    return cell


def csv_text(rows: Iterable[Sequence[Any]], comments: Sequence[str] = ()) -> str:
    """CSV text of ``rows`` (the header first), every cell through :func:`safe_cell`, lines ending in LF;
    ``comments`` are written first as ``# ...`` lines (the readers skip them).  Floats are written by ``str``
    (``repr``: exact) unless the caller formatted them; NaN and infinities as empty cells."""
    out = [f"# {line}\n" for line in comments]
    out += [",".join(_quoted(safe_cell(v)) for v in row) + "\n" for row in rows]
    return "".join(out)


def _quoted(value: Any) -> str:
    """One cell as RFC 4180 writes it: quoted (quotes doubled) when it holds a comma, a quote, a line feed or a
    carriage return (the csv module leaves a lone CR unquoted when lines end in LF); NaN and infinities empty."""
    text = "" if isinstance(value, (float, np.floating)) and not math.isfinite(value) else str(value)
    if any(ch in text for ch in ',"\n\r'):
        return '"' + text.replace('"', '""') + '"'
    return text


def dict_rows(
    rows: Iterable[dict[str, Any]],
    columns: Sequence[str],
    float_format: str = "{!r}",
    quantities: Mapping[str, str] | None = None,
    units: str = "in",
) -> list[list[Any]]:
    """The header and one list per dict of ``rows`` for :func:`csv_text`: a missing key or None as an empty cell,
    a float formatted by ``float_format`` (``"{:.6g}"``).

    ``quantities`` (key -> dimension: "length", "force", "speed", ...) is the one rule of the CSV files the tool
    writes: the column of a quantity carries its unit in its name and its values are in that unit
    (:func:`designer.units.csv_column`: ``trail_in`` or ``trail_mm`` as the problem writes lengths, ``units``;
    ``turning_effort_N``, ``critical_speed_m_per_s``); the other columns (flags such as ``family``, ``status``
    and ``buildable``, fractions, counts, names that already end in their unit) keep their names."""
    named = {c: csv_column(c, (quantities or {}).get(c, ""), units) for c in columns}
    out: list[list[Any]] = [[named[c][0] for c in columns]]
    for r in rows:
        cells: list[Any] = []
        for c in columns:
            value = r.get(c)
            whole = isinstance(value, (int, np.integer)) and not isinstance(value, bool)
            if value is None:
                cells.append("")
            elif isinstance(value, float) or (named[c][1] != 1.0 and whole):  # a quantity in its column's unit
                cells.append(float_format.format(float(value) * named[c][1]))
            else:
                cells.append(value)
        out.append(cells)
    return out


__all__ = [
    "FORMULA_STARTS",
    "MAX_CELL",
    "csv_table",
    "csv_text",
    "dict_rows",
    "not_a_file",
    "read_input_text",
    "restore_cell",
    "safe_cell",
]
