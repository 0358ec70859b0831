"""Helpers shared by the sub-commands: option parsing with units, JSON output."""
from __future__ import annotations

import json
import math
import sys

from designer.jsonsafe import finite
from designer.errors import InputError
from designer.units import parse_quantity


def quantity_option(value: str | None, dimension: str, option: str, default=None):
    """Parse a command-line quantity ("2in", "2 in", "50.8 mm", plain SI number)."""
    if value is None:
        return default
    text = value.strip()
    try:
        number = float(text)
    except ValueError:
        number = None
    if number is not None:
        return parse_quantity(number, dimension, option)
    # allow "2in" without a space
    import re

    match = re.match(r"^([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*([A-Za-z].*)$", text)
    if match:
        text = f"{match.group(1)} {match.group(2)}"
    return parse_quantity(text, dimension, option)


def choice_option(value: str, allowed: tuple[str, ...], option: str) -> str:
    """Check a categorical option; InputError naming option, value and the choices."""
    if value not in allowed:
        raise InputError(f"{option} {value!r}: expected one of {', '.join(allowed)}")
    return value


def print_json(data) -> None:
    """Print ``data`` as JSON; NaN and infinities become null."""
    print(json.dumps(finite(data), indent=2, sort_keys=False))


def eprint(*args) -> None:
    """Print to stderr (progress and notes that must not pollute --json output)."""
    print(*args, file=sys.stderr)
