"""The studio's state: control values <-> problem-file data <-> URL query <-> TOML.

The studio never builds a :class:`~designer.problem.Problem` by hand.  Every
control edits one key of the *problem-file data* (the dict that a TOML problem
file parses to), and the result goes through
:func:`designer.problem.problem_from_dict`, the loader ``designer run`` uses.
So a bad value gives the CLI's one-line message, and "Save problem" writes
that same dict as TOML, which ``designer run`` reads back to the same problem.

No web framework is imported here: the module is tested on its own.
"""

from __future__ import annotations

import copy
import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import parse_qsl, urlencode

from designer import display
from designer.errors import DesignerError, ProblemError
from designer.physics.uncertainty import Uncertainty
from designer.parameters import VARIABLE_TABLE
from designer.units import DIMENSIONS, example, parse_quantity
from designer.problem import load_problem, problem_path
from designer.problem import DEFAULT_BOUNDS
from designer.problem import problem_from_dict

DEFAULT_PROBLEM = "indoor-manual.toml"
"""Problem the studio opens when none is given (the shipped default problem)."""


@dataclass(frozen=True)
class Control:
    """One live control of the studio.

    Attributes
    ----------
    key : short name, used in the URL and in element ids
    label : what the page shows beside it
    path : keys into the problem-file data, e.g. ("conditions", "load")
    kind : "quantity" (text with units), "number", "choice", "slider", "list"
    dimension : unit dimension of a quantity (designer.units.DIMENSIONS)
    group : the panel it sits in
    """

    key: str
    label: str
    path: tuple[str, ...]
    kind: str = "quantity"
    dimension: str = ""
    group: str = "use"
    options: tuple = ()
    optional: bool = False

    @property
    def dotted(self) -> str:
        """The problem-file key, as the loader's messages name it ("conditions.load")."""
        return ".".join(self.path)


def _bounds_controls() -> list[Control]:
    """A min and a max box per design variable, with its dimension from the parameter table."""
    return [
        Control(f"{p.name}_{end}", f"{p.name} {end}", ("variables", p.name, end), "quantity", p.dimension, "bounds")
        for p in VARIABLE_TABLE
        for end in ("min", "max")
    ]


CONTROLS: list[Control] = [
    Control("load", "load per caster", ("conditions", "load"), "quantity", "force"),
    Control("sill", "sill height", ("conditions", "threshold_height"), "quantity", "length"),
    Control("surface", "surface", ("conditions", "surface"), "choice", options=("tile", "carpet")),
    Control("target", "target speed [m/s]", ("shimmy", "target_speed"), "slider", "speed"),
    Control("alpha", "allowed chance of shimmy α", ("robust", "probability"), "number", group="risk"),
    Control("mode", "turning mode", ("conditions", "turning_mode"), "choice", options=("chair", "pivot")),
    Control("s_model", "σ model error (log)", ("robust", "model_error"), "number", group="risk"),
    Control("s_damping", "σ damping (log)", ("robust", "damping"), "number", group="risk"),
    Control("s_slip", "σ slip coefficient (log)", ("robust", "slip_coefficient"), "number", group="risk"),
    Control("s_inertia", "σ wheel inertia (log)", ("robust", "inertia"), "number", group="risk"),
    *_bounds_controls(),
    Control(
        "swept",
        "swept radius max (empty: none)",
        ("constraints", "swept_radius_max"),
        "quantity",
        "length",
        "bounds",
        optional=True,
    ),
]
"""Every control, in page order (:mod:`designer.studio.layout`: the first five on top, the others folded by
group; the callbacks read the controls in this order)."""

STOCK_CONTROLS = {
    "diameters": ("stock diameters", "length"),
    "grooves": ("stock grooves", "length"),
    "dampings": ("stock dampings", "damping"),
    "trail_step": ("trail step", "length"),
    "wheels": ("stock wheels (Table 1 letters)", ""),
}
"""[stock] keys the studio offers (keys of the problem file's [stock] section)."""


def stock_controls() -> list[Control]:
    """Controls of the [stock] lists."""
    return [
        Control(
            f"stock_{key}",
            label + (" (comma separated)" if key.endswith("s") else ""),
            ("stock", key),
            "list" if key.endswith("s") else "quantity",
            dim,
            "stock",
            optional=True,
        )
        for key, (label, dim) in STOCK_CONTROLS.items()
    ]


def all_controls() -> list[Control]:
    """:data:`CONTROLS` plus the stock controls of this version."""
    return CONTROLS + stock_controls()


SLIDER = {"min": 0.5, "max": 6.0, "step": 0.1}
"""Range of the target-speed slider [m/s] (the text box beside it takes any value)."""


# --------------------------------------------------------------------------- reading a problem file


def read_problem_data(path=None) -> tuple[dict, str]:
    """The problem-file data of ``path`` (default: the shipped indoor-manual problem) and its name.

    Raises ProblemError (the loader's one line) for a missing or broken file.
    """

    if path is None:
        path = default_problem_path()
    problem = load_problem(path)  # the CLI's checks and messages, before the page opens
    data = tomllib.loads(problem_path(path).read_text(encoding="utf-8"))  # a path, or a shipped problem's name
    data.setdefault("name", problem.name)
    return data, problem.name


def default_problem_path() -> Path:
    """problems/indoor-manual.toml of this checkout, else of the current folder."""
    here = Path(__file__).resolve().parents[2] / "problems" / DEFAULT_PROBLEM
    return here if here.exists() else Path("problems") / DEFAULT_PROBLEM


def _show(value, dimension: str, units: str = "in") -> str:
    """A value of the problem file as the text box shows it: strings as written, SI numbers with their unit (a
    length in the problem's ``units``, "in" or "mm", :func:`designer.display.unit`)."""
    if isinstance(value, str):
        return value
    if dimension == "length":
        length = display.unit("length", units)
        return f"{value * length.factor:.6g} {length.text}"
    unit = DIMENSIONS[dimension][0] if dimension else ""
    return f"{value:.6g} {unit}".strip()


def _as_list(value) -> list:
    return list(value) if isinstance(value, (list, tuple)) else [value]


_COST = re.compile(r"^(?P<value>.*?)\s*\(cost\s+(?P<cost>[-+0-9.eE]+)\)$")
"""A stock item shown with its own cost: ``7 in (cost 6)``."""


def _show_item(item, dimension: str, units: str = "in") -> str:
    """One item of a [stock] list as its text box shows it: a value (``7 in``), a value with its own cost
    (``{ value = "7 in", cost = 6 }`` -> ``7 in (cost 6)``), a named wheel by its name."""
    if isinstance(item, dict):
        if "name" in item:
            return str(item["name"])
        shown = _show(item.get("value", ""), dimension, units)
        return f"{shown} (cost {item['cost']:g})" if isinstance(item.get("cost"), (int, float)) else shown
    return _show(item, dimension, units)


def _list_items(text: str, before) -> list:
    """The items of a [stock] list's text box: ``7 in (cost 6)`` -> ``{value = "7 in", cost = 6.0}``, a name of
    a named wheel of ``before`` (the list as the file had it) -> that wheel's table, else the text."""
    named = {str(v["name"]): v for v in _as_list(before or []) if isinstance(v, dict) and "name" in v}
    out: list = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        match = _COST.match(part)
        if part in named:
            out.append(named[part])
        elif match:
            try:
                out.append({"value": match["value"], "cost": float(match["cost"])})
            except ValueError:
                out.append(part)
        else:
            out.append(part)
    return out


def get(data: dict, path: tuple[str, ...]):
    """The value at ``path`` of nested dicts, or None."""
    for key in path:
        if not isinstance(data, dict) or key not in data:
            return None
        data = data[key]
    return data


NUMBER_DIGITS = 4
"""Significant digits a number box shows (α, the σ of the scatter: the Table 1 fit's σ is known to about 20 %;
four digits tell it from a rounded value).  A box left as shown leaves the problem's own value untouched
(:func:`apply`)."""


def units_of(data: dict) -> str:
    """The unit system of problem-file ``data`` (``[report] units``: "in" or "mm"; "in" when it names none or
    another, which the loader refuses with its own message)."""
    units = (get(data, ("report", "units")) or "in") if isinstance(data, dict) else "in"
    return units if units in ("in", "mm") else "in"


def control_values(data: dict) -> dict:
    """The value every control shows for problem-file ``data`` (defaults filled in as the loader would)."""

    defaults = Uncertainty()
    units = units_of(data)
    out = {}
    for c in all_controls():
        value = get(data, c.path)
        if c.path[0] == "variables":
            spec = get(data, ("variables", c.path[1]))
            if spec is not None and not isinstance(spec, dict):
                value = spec  # a fixed variable: min = max
            if value is None:
                low, high = DEFAULT_BOUNDS[c.path[1]]
                value = low if c.path[2] == "min" else high
        if c.group == "risk" and value is None:
            value = getattr(defaults, c.path[1])
        if c.kind == "slider":
            value = parse_quantity(value, "speed", c.dotted) if value is not None else 2.5
            out[c.key] = round(float(value), 6)
        elif c.kind == "number":
            out[c.key] = float(f"{float(value):.{NUMBER_DIGITS}g}")  # σ 0.1075, not 0.10751150496617…
        elif c.kind == "choice":
            out[c.key] = value if value is not None else c.options[0]
        elif c.kind == "list":
            out[c.key] = "" if value is None else ", ".join(_show_item(v, c.dimension, units) for v in _as_list(value))
        else:
            out[c.key] = "" if value is None else _show(value, c.dimension, units)
    return out


# --------------------------------------------------------------------------- controls -> problem


class ControlError(DesignerError):
    """A control's value is invalid; ``key`` names the control, the message is the CLI's line."""

    exit_code = ProblemError.exit_code

    def __init__(self, message: str, key: str | None):
        super().__init__(message)
        self.key = key


def apply(data: dict, values: dict) -> dict:
    """A copy of problem-file ``data`` with the control ``values`` that differ from what ``data`` shows
    (:func:`control_values`) written into it.

    Raises ControlError (naming the control) for a value that is not even of the right type
    (a number box holding text); units and ranges are left to the loader.
    """
    out = copy.deepcopy(data)
    shown = control_values(data)
    for c in all_controls():
        if c.key not in values or values[c.key] == shown[c.key]:
            continue  # as the page shows the file: the file's own value stays (not its rounded display)
        value = values[c.key]
        if c.kind == "list" and str(value).strip() == shown.get(c.key):
            continue  # unchanged: the file's list as it was (items with their own costs, named wheels)
        if c.kind == "slider":
            value = f"{_number(value, c):g} m/s"
        elif c.kind == "number":
            value = _number(value, c)
        elif c.kind in ("list", "quantity"):
            text = "" if value is None else str(value).strip()
            if not text and (c.optional or c.kind == "list"):  # an empty box: the key left out
                _delete(out, c.path)
                continue
            if not text:
                raise ControlError(
                    f"{c.dotted}: empty; give a value with its unit, e.g. {example(c.dimension)!r}", c.key
                )
            value = _list_items(text, get(data, c.path)) if c.kind == "list" else text
        _set(out, c.path, value)
    return out


def _number(value, c: Control) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ControlError(f"{c.dotted} = {value!r}: expected a number", c.key) from None
    if not math.isfinite(number):
        raise ControlError(f"{c.dotted} = {value!r}: must be finite", c.key)
    return number


def _set(data: dict, path: tuple[str, ...], value) -> None:
    for key in path[:-1]:
        nxt = data.get(key)
        if not isinstance(nxt, dict):
            nxt = {} if not (key in data and path[0] == "variables") else {"min": data[key], "max": data[key]}
            data[key] = nxt
        data = nxt
    data[path[-1]] = value


def _delete(data: dict, path: tuple[str, ...]) -> None:
    parent = get(data, path[:-1]) if len(path) > 1 else data
    if isinstance(parent, dict):
        parent.pop(path[-1], None)


def build_problem(data: dict, values: dict):
    """Validate: control ``values`` over problem-file ``data`` -> (Problem, the data used).

    Raises ControlError whose ``key`` is the control the loader's message names (None if no
    single control is to blame), and whose text is the loader's one line.
    """

    merged = apply(data, values)
    try:
        return problem_from_dict(merged), merged
    except DesignerError as exc:
        raise ControlError(str(exc), blame(str(exc))) from None


def control_errors(data: dict, values: dict, defaults: dict) -> dict:
    """Every control's own message: each changed control tried alone over the defaults {key: one line}.

    So two bad boxes both show their message (the loader stops at the first); cheap, the loader takes
    about a millisecond.
    """
    out = {}
    for key, value in values.items():
        if key not in defaults or value == defaults[key]:
            continue
        try:
            build_problem(data, {**defaults, key: value})
        except ControlError as exc:
            out[exc.key if exc.key is not None else key] = str(exc)
    return out


def blame(message: str) -> str | None:
    """The control whose key the one-line ``message`` names (longest match), or None."""
    best, length = None, 0
    for c in all_controls():
        for candidate in (c.dotted, ".".join(c.path[:2])):
            if re.search(rf"(^|[\s:]){re.escape(candidate)}\b", message) and len(candidate) > length:
                if candidate == ".".join(c.path[:2]) and c.path[0] == "variables" and c.path[-1] != "min":
                    continue  # "variables.trail = [..]" (min > max) goes beside the min box
                best, length = c.key, len(candidate)
    if best is None and "target" in message:
        return "target"
    return best


# --------------------------------------------------------------------------- URL


def to_query(values: dict, defaults: dict) -> str:
    """The URL query ("?target=3&trail_min=1.5+in") of the controls that differ from ``defaults``."""
    changed = [
        (k, f"{v:g}" if isinstance(v, float) else str(v))
        for k, v in values.items()
        if k in defaults and v != defaults[k]
    ]
    return "?" + urlencode(changed) if changed else ""


def from_query(search: str | None, defaults: dict) -> dict:
    """Control values from a URL query: ``defaults`` with the keys the query names (unknown keys ignored)."""
    out = dict(defaults)
    kinds = {c.key: c.kind for c in all_controls()}
    for key, value in parse_qsl((search or "").lstrip("?"), keep_blank_values=True):
        if key not in kinds:
            continue
        if kinds[key] in ("slider", "number"):
            try:
                out[key] = float(value)
            except ValueError:
                out[key] = value  # shown back as typed; the loader's message says what is wrong
        else:
            out[key] = value
    return out


# --------------------------------------------------------------------------- TOML


def to_toml(data: dict) -> str:
    """Problem-file data as TOML text (what "Save problem" writes; :func:`tomllib.loads` gives ``data`` back)."""
    lines = [f"{_bare(key)} = {_toml_value(value)}" for key, value in data.items() if not isinstance(value, dict)]
    for key, value in data.items():
        if isinstance(value, dict):
            lines += ["", f"[{_bare(key)}]", *(f"{_bare(sub)} = {_toml_value(item)}" for sub, item in value.items())]
    return "\n".join(lines).lstrip("\n") + "\n"


def _bare(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else toml_string(key)


_TOML_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}


def toml_string(text: str) -> str:
    """``text`` as a TOML basic string: quotes, backslashes and every control character TOML forbids raw
    (U+0000 to U+001F and U+007F) escaped, the rest (non-ASCII included) as it is; ``tomllib`` reads it back to
    ``text``.  A lone surrogate (not a character) is a ValueError."""
    out = []
    for ch in text:
        code = ord(ch)
        if ch in _TOML_ESCAPES:
            out.append(_TOML_ESCAPES[ch])
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04X}")
        elif 0xD800 <= code <= 0xDFFF:
            raise ValueError(f"cannot write the lone surrogate U+{code:04X} to TOML")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"cannot write {value!r} to TOML")
        return repr(value)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{_bare(k)} = {_toml_value(v)}" for k, v in value.items()) + " }"
    raise ValueError(f"cannot write {type(value).__name__} to TOML")
