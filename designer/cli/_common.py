"""Helpers shared by the sub-commands: option parsing with units, JSON output."""

from __future__ import annotations

import contextlib
import json
import os
import sys

from designer import Fixed, PowerLaw
from designer.cli._terminal import fit
from designer.jsonsafe import finite, resolved_numbers, stamped
from designer.errors import InputError
from designer.parameters import PARAMETERS
from designer.problem import INERTIA_RANGE
from designer.display import quantity, shown
from designer.units import outside_range, parse_quantity_text, written_size


PROBLEM_HELP = (
    "problem file (TOML), or the name of a shipped problem, e.g. problems/indoor-manual.toml or indoor-manual"
)
"""The help of every PROBLEM argument: a shipped problem is found by its name from any folder."""


quantity_option = parse_quantity_text
"""Parse a command-line quantity ("2in", "2 in", "50.8 mm", plain SI number):
:func:`designer.units.parse_quantity_text`."""


@contextlib.contextmanager
def api_named(names: dict[str, str]):
    """An InputError of the API inside the block named by the option its value came from: a message starting
    with a key of ``names`` (the API's name of an argument, "load ") starts with its value ("--load ") instead."""
    try:
        yield
    except InputError as exc:
        text = str(exc)
        prefix = next((p for p in names if text.startswith(p)), "")
        raise InputError(names.get(prefix, "") + text[len(prefix) :]) from None


def print_json(data, kind: str | None = None) -> None:
    """Print ``data`` as JSON; NaN and infinities become null; a dict gets its ``schema`` first
    (:func:`designer.jsonsafe.stamped`; ``kind``: default the running command's, ``"run --json"``)."""
    if isinstance(data, dict):
        data = stamped(kind or f"{RUNNING['command'] or 'designer'} --json", data)
    print(json.dumps(resolved_numbers(finite(data)), indent=2, sort_keys=False))  # 0.1524, not 0.15239999999999998


RUNNING = {"command": ""}
"""The command :func:`designer.cli.main` is running (``run`` for ``designer run ...``): the kind of its --json."""


def eprint(*args) -> None:
    """Print to stderr (progress and notes that must not pollute --json output), fitted to the terminal's width
    (:func:`designer.cli._terminal.fit`); a progress line left open (:func:`progress_line`) is ended first."""
    end_progress_line()
    print(fit(" ".join(str(a) for a in args)), file=sys.stderr)


_PROGRESS = {"open": False}
"""Whether stderr's last line is a progress line written with ``\r`` and not yet ended."""


def progress_line(text: str) -> None:
    """Write ``text`` over the current line of stderr (``\r``, no newline), at a terminal only: a counter that
    updates in place.  The next message (:func:`eprint`, an error, "interrupted") starts on a line of its own."""
    try:
        if not sys.stderr.isatty():  # a log file or a pipe: a counter rewritten in place is noise there
            return
    except (AttributeError, ValueError):
        return
    print(f"\r{text}", end="", file=sys.stderr, flush=True)
    _PROGRESS["open"] = True


def end_progress_line() -> None:
    """End a progress line left open by :func:`progress_line` (a newline), so the next message is one line."""
    if _PROGRESS["open"]:
        _PROGRESS["open"] = False
        try:
            print(file=sys.stderr, flush=True)
        except (OSError, ValueError):  # stderr closed: nothing to end
            pass


def say(path):
    """``print`` for the notes of a command that wrote ``path``, or :func:`eprint` when ``path`` is this process's
    standard output (``/dev/stdout``, ``/dev/fd/1``, or the very file stdout is redirected to), so the stream holds
    the file alone (``designer fleet --example 5 --out /dev/stdout | cat``)."""
    try:
        to_stdout = os.path.samestat(os.stat(path), os.fstat(sys.stdout.fileno()))
    except (OSError, ValueError, AttributeError):  # no such path, or stdout is not a real file (captured)
        to_stdout = str(path) in ("/dev/stdout", "/dev/fd/1", "/proc/self/fd/1")
    return eprint if to_stdout else print


def part_text(value: float, name: str, units: str) -> str:
    """One part of a caster by its symbol, a size as the problem writes it: "T 1 1/4 in", "c_f 1.30 N·m/rad"."""
    return f"{quantity(name).symbol} {shown(value, name) if name == 'damping' else written_size(value, units)}"


def parts_text(design, units: str) -> str:
    """A caster's four parts by :func:`part_text`: "T 1 1/4 in, d 8 in, B 0 in, c_f 1.30 N·m/rad" (``design``: a
    Design, or its dict)."""
    values = design if isinstance(design, dict) else design.to_dict()
    return ", ".join(part_text(values[n], n, units) for n in ("trail", "diameter", "groove", "damping"))


def ranged_option(value: str | None, entry: str, option: str):
    """Parse a quantity option and check it against the parameter table's range of ``entry``
    (:mod:`designer.parameters`), as a problem file's value is checked: InputError (exit 2) naming the option.
    ``None`` (not given) gives None."""
    p = PARAMETERS[entry]
    number = quantity_option(value, p.dimension, option)
    assert p.range is not None, entry
    if value is not None and not p.range[0] <= number <= p.range[1]:
        raise InputError(
            outside_range(option, value, number, *p.range, p.dimension) + (f" ({p.hint})" if p.hint else "")
        )
    return number


def inertia_option(text: str | None):
    """The wheel's inertia model of ``--inertia`` [kg·m²]: a measured wheel (:class:`designer.Fixed`) within the
    problem file's INERTIA_RANGE (as designer fix takes it), or Table 1's power law of d when not given."""
    if text is None:
        return PowerLaw()
    value = quantity_option(text, "inertia", "--inertia")
    if not INERTIA_RANGE[0] <= value <= INERTIA_RANGE[1]:
        raise InputError(
            f"--inertia {text}: must be between {INERTIA_RANGE[0]:g} and {INERTIA_RANGE[1]:g} kg·m² "
            "(Table 1: 0.00026 to 0.0046)"
        )
    return Fixed(value)


SEED_MAX = 2**32 - 1
"""Largest random seed (numpy's SeedSequence takes 0 to 2**32 - 1 as one word; the problem file's robust.seed)."""


def count_option(value: int | None, option: str, low: int, high: int, note: str = ""):
    """Check a whole-number option lies in [low, high]; InputError (exit 2) naming the option. ``None`` passes."""
    if value is not None and not low <= value <= high:
        raise InputError(f"{option} {value}: expected a whole number from {low} to {high}{note}")
    return value
