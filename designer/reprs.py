"""The result protocol (:class:`Record`) and the small HTML pieces of the notebook reprs.

Every result record of the package (a design, a problem, a solver's optimum, a front and its points, a
recommendation, a fix, a fleet, a simulation, an exploration, a calibration, a check, ...) is a dataclass built by
keyword with :class:`Record` as a base, so it answers the same four methods, spelled one way:

``to_dict()``      plain data (dicts, lists, str, numbers, None; NumPy turned into Python): ``json.dumps`` takes it
                   after :func:`designer.jsonsafe.finite`
``to_pandas()``    a pandas DataFrame (pandas: the ``notebook`` extra), units in ``df.attrs["units"]``
``_repr_html_()``  a compact HTML table with units (Jupyter), built from data already held: it computes nothing
                   expensive (no solver, no Monte Carlo)
``__repr__()``     at most three lines: what it is, its size, its headline numbers

A record declares its data in :attr:`Keyed._keys` (:class:`Key`: renamed, nested, read along a path, left out
when empty, given on request) and changes what the reprs show through hooks (:meth:`Record._repr_lines`,
:meth:`Record._html_rows`, ...); the four methods themselves are defined here only.  A record's small chart is
drawn by :mod:`designer.plots.svg` (:func:`~designer.plots.svg.svg_curve`, :func:`~designer.plots.svg.svg_sparkline`).  Ground layer: no designer import but the parameter table and its display, no solver, no matplotlib; every
text in the HTML is escaped.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Mapping
from html import escape
from typing import Any, ClassVar

import numpy as np

from designer.display import number, unit_text
from designer.parameters import OUTPUTS, PARAMETERS

STYLE = (
    "border-collapse:collapse;font-size:12px;font-family:sans-serif;margin:2px 0",
    "text-align:left;padding:1px 8px 1px 0;font-weight:normal;color:#555;white-space:nowrap",
    "text-align:right;padding:1px 4px;font-variant-numeric:tabular-nums;white-space:nowrap",
    "text-align:left;padding:1px 0 1px 4px;color:#555;white-space:nowrap",
)
"""Inline styles (table, label cell, value cell, unit cell): the repr must render without a stylesheet."""


class FrozenMapping(Mapping[Any, Any]):
    """A read-only mapping: the records' dict fields (a problem's bounds, choices, stock costs, the turning
    model's mode factors, the conditions' constants), so ``problem.bounds["trail"] = ...`` raises TypeError and
    a record stays what its constructor validated.

    Equal to a dict with the same items, printed like one, picklable (a problem goes to worker processes),
    hashable when its values are.  Build a changed copy with the record's ``replace`` (``problem.replace(
    bounds={**problem.bounds, "trail": Bound(0.03, 0.05)})``), which validates it again.
    """

    __slots__ = ("_data",)

    def __init__(self, data: Any = (), /) -> None:
        self._data = dict(data)

    def __getitem__(self, key: Any) -> Any:
        return self._data[key]

    def __iter__(self) -> Any:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def __repr__(self) -> str:
        return repr(self._data)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Mapping):
            return self._data == dict(other.items())
        return NotImplemented

    def __hash__(self) -> int:
        return hash(frozenset(self._data.items()))

    def __reduce__(self) -> tuple[Any, ...]:
        return (FrozenMapping, (self._data,))

    def __setitem__(self, key: Any, value: Any) -> None:
        raise TypeError(
            f"cannot set [{key!r}]: a record's mapping is read-only; build a changed copy with the record's "
            f"replace(), which checks it again"
        )

    def __delitem__(self, key: Any) -> None:
        self.__setitem__(key, None)


_AS_THEY_ARE = frozenset({type(None), str, int, float, bool, FrozenMapping, np.ndarray, np.float64, np.bool_})
"""Types :func:`deep_frozen` keeps as they are (as its tests below would), told by one set look-up first."""


def deep_frozen(value: Any) -> Any:
    """``value`` with its containers made read-only, all the way down: a list or a tuple as a tuple, a mapping as a
    :class:`FrozenMapping`, a set as a frozenset; records, strings, numbers, arrays and other objects as they are.
    What a record's fields are turned into when it is built (:meth:`Keyed.__post_init__`): a user's
    ``rec.alternatives.clear()`` or ``front.meta["x"] = 1`` raises instead of changing a result in place.  A list
    a user indexes still indexes (``rec.alternatives[0]``); ``to_dict`` and JSON give lists as before."""
    if type(value) in _AS_THEY_ARE or isinstance(value, (str, bytes, int, float, Keyed, FrozenMapping, frozenset)):
        return value
    if isinstance(value, Mapping):
        return FrozenMapping({k: deep_frozen(v) for k, v in value.items()})
    if isinstance(value, list) or type(value) is tuple:
        items = tuple(deep_frozen(v) for v in value)
        return value if type(value) is tuple and all(a is b for a, b in zip(items, value)) else items
    if isinstance(value, (set, bytearray)):
        return frozenset(value) if isinstance(value, set) else bytes(value)
    return value


def freeze_fields(record: Any) -> None:
    """Every dataclass field of ``record`` through :func:`deep_frozen` (in place, frozen dataclass or not), unless
    its class says why it stays open (:attr:`Keyed._open`)."""
    if getattr(type(record), "_open", ""):
        return
    for name in field_names(type(record)):
        value = getattr(record, name)
        kept = deep_frozen(value)
        if kept is not value:
            object.__setattr__(record, name, kept)


_FIELD_NAMES: dict[tuple[type, bool], tuple[str, ...]] = {}


def field_names(cls: type, shown: bool = False) -> tuple[str, ...]:
    """The names of the dataclass fields of ``cls`` (only those in its repr if ``shown``), read once a class."""
    if (cls, shown) not in _FIELD_NAMES:
        _FIELD_NAMES[cls, shown] = tuple(f.name for f in dataclasses.fields(cls) if f.repr or not shown)
    return _FIELD_NAMES[cls, shown]


def frozen(data: Any) -> FrozenMapping:
    """``data`` (a mapping) as a :class:`FrozenMapping`, nested mappings too (a stock's item costs)."""
    return data if isinstance(data, FrozenMapping) else deep_frozen(dict(data))


def dataframe(what: str, records: list[dict[str, Any]], columns: list[str], units: dict[str, str], **attrs: Any) -> Any:
    """A pandas DataFrame of ``records`` in ``columns`` order; ``df.attrs["units"]`` = ``units`` plus ``attrs``.

    ``what`` names the caller in the ImportError when pandas (an optional dependency: the ``notebook`` extra) is
    missing, with how to install it.
    """
    try:
        import pandas as pd  # optional dependency: only the to_pandas methods need it
    except ImportError:
        raise ImportError(f"{what} needs pandas: pip install 'caster-designer[notebook]'") from None
    df = pd.DataFrame.from_records(records, columns=columns)
    df.attrs.update(attrs)
    df.attrs["units"] = dict(units)
    return df


def si_frame(
    what: str, rows: list[dict[str, Any]], columns: list[str], units: Mapping[str, str] = {}, **attrs: Any
) -> Any:
    """A pandas DataFrame of ``rows`` (dicts keyed by ``columns``) whose quantities of the parameter table name
    their SI unit ("trail_m", "damping_N_m_per_rad", "critical_speed_m_s", "turning_effort_N"; other columns as
    they are, their units from ``units``): :func:`dataframe` with the units in ``df.attrs["units"]``."""
    renamed, all_units = {}, dict(units)
    for name in columns:
        unit = getattr(PARAMETERS.get(name) or OUTPUTS.get(name), "unit", "")
        suffix = unit.replace("·", "_").replace("/rad", "_per_rad").replace("/", "_")
        renamed[name] = f"{name}_{suffix}" if suffix else name
        if suffix:
            all_units[renamed[name]] = unit
    records = [{renamed[k]: v for k, v in row.items()} for row in rows]
    return dataframe(what, records, list(renamed.values()), all_units, **attrs)


# --------------------------------------------------------------------------- the result protocol

MAX_REPR_LINES = 3
"""A record's ``repr`` has at most this many lines (the full account is ``str()``, ``to_dict()`` or the HTML)."""

REPR_WIDTH = 118
"""Width at which the default ``repr`` wraps its fields."""


def plain(value: Any) -> Any:
    """``value`` as plain data: a record's :meth:`Record.to_dict`, other dataclasses field by field (fields hidden
    from their repr left out), mappings with string keys, sequences as lists, NumPy as Python; other objects
    with a ``to_dict`` through it, anything else as its ``str``.  Non-finite floats stay (``jsonsafe.finite``
    turns them into None)."""
    if isinstance(value, Keyed):
        return value.to_dict()
    if value is None or isinstance(value, (str, bool, int, float)):
        return value
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: plain(getattr(value, f.name)) for f in dataclasses.fields(value) if f.repr}
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, set, frozenset)):
        return [plain(v) for v in value]
    to_dict = getattr(value, "to_dict", None)
    if callable(to_dict):
        return plain(to_dict())
    return str(value)


def flatten(data: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested dicts as one level with dotted keys (``{"design": {"trail": 0.05}}`` -> ``{"design.trail": 0.05}``);
    lists stay as values."""
    out: dict[str, Any] = {}
    for key, value in data.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping) and value:
            out.update(flatten(value, name + "."))
        else:
            out[name] = value
    return out


def shown(value: Any) -> str:
    """A value as a short text: numbers to 4 significant digits, long lists (and lists of records) by their
    length."""
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, (list, tuple)):
        if len(value) > 4 or any(isinstance(v, (Mapping, list, tuple)) for v in value):
            return f"[{len(value)} values]"
        return "[" + ", ".join(shown(v) for v in value) + "]"
    return str(value)


def _quantity(key: str) -> Any:
    """The parameter table's entry of a flattened key that names a quantity ("critical_speed", "design.trail"),
    or None (a key nested elsewhere, a solver's dual or a margin, is not the quantity of its name)."""
    name = key.removeprefix("design.")
    return None if "." in name else PARAMETERS.get(name) or OUTPUTS.get(name)


@dataclasses.dataclass(frozen=True)
class Key:
    """One key of a record's :meth:`Record.to_dict`, declared in the record's :attr:`Record._keys`.

    Attributes
    ----------
    name : the key; dots nest (``"turning.carpet_factor"`` -> ``{"turning": {"carpet_factor": ...}}``).  ``"*"``
        stands for every field shown in the dataclass repr, in order (a later Key of the same name takes that
        field's place); ``"**"`` spreads the mapping at ``source`` into the dict
    source : where the value comes from: an attribute path from the record (``"conditions.load"``; a step
        ``"digest()"`` is a method called without arguments), or a function of the record; None: ``name``
    omit : ``"none"``: left out when the value is None; ``"empty"``: also when it is an empty list, tuple or mapping
        (for ``"*"``: each field); ``""``: always there
    option : kept only when ``to_dict(**{option: True})`` is asked for (``to_dict(alternatives=True)``)
    options : passed to the value's own ``to_dict`` when the value is a record (a nested record with its option)
    """

    name: str
    source: str | Callable[[Any], Any] | None = None
    omit: str = ""
    option: str | None = None
    options: Mapping[str, bool] = dataclasses.field(default_factory=dict)

    def value(self, record: Any) -> Any:
        """The plain value of this key for ``record`` (:func:`plain`)."""
        source = self.name if self.source is None else self.source
        if callable(source):
            value = source(record)
        else:
            value = record
            for step in source.split("."):
                value = getattr(value, step[:-2])() if step.endswith("()") else getattr(value, step)
        if self.options and isinstance(value, Keyed):
            return value.to_dict(**self.options)
        return plain(value)

    def omitted(self, value: Any) -> bool:
        """Whether ``value`` (plain) is left out: by :attr:`omit`, when it is None (or empty)."""
        empty = self.omit == "empty" and isinstance(value, (list, tuple, Mapping)) and not value
        return bool(self.omit) and (value is None or empty)


class Keyed:
    """Plain data declared once: :meth:`to_dict` built from the class's :attr:`_keys` (by default every field shown
    in the dataclass repr).  :class:`Record` derives from it; so do the small dataclasses that are parts of a
    record without being shown on their own (a problem's stock and tolerances, a risk law's sources)."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        # a subclass's own __post_init__ (its checks) is followed by the freezing of its containers
        post = cls.__dict__.get("__post_init__")
        if post is not None and not getattr(post, "_freezes", False):

            @functools.wraps(post)
            def checked_then_frozen(self: Any, *args: Any, **kw: Any) -> None:
                post(self, *args, **kw)
                freeze_fields(self)

            checked_then_frozen._freezes = True  # type: ignore[attr-defined]
            cls.__post_init__ = checked_then_frozen  # type: ignore[method-assign]

    def __post_init__(self) -> None:
        """A record's containers made read-only once it is built (:func:`deep_frozen`); records are frozen
        dataclasses, so with this nothing of a result changes after it is returned."""
        if dataclasses.is_dataclass(self):
            freeze_fields(self)

    __post_init__._freezes = True  # type: ignore[attr-defined]

    _open: ClassVar[str] = ""
    """Why a record stays mutable (its containers too), or "" (the rule: frozen, its containers read-only).  Only
    the report's own working data says a reason; tests/test_records.py lists the classes that do."""

    _keys: ClassVar[tuple[str | Key, ...]] = ("*",)
    """The keys of :meth:`to_dict` (:class:`Key`, or a name for ``Key(name)``): every repr field by default.  A
    record whose data has another shape declares it here instead of writing its own ``to_dict``."""

    # ----------------------------------------------------------------- data
    def _layout(self) -> list[Key]:
        """The keys of :meth:`to_dict` in order: :attr:`_keys` with ``"*"`` expanded to the repr fields."""
        keys: dict[str, Key] = {}
        for entry in self._keys:
            key = Key(entry) if isinstance(entry, str) else entry
            if key.name == "*":
                fields: tuple[Any, ...] = dataclasses.fields(self) if dataclasses.is_dataclass(self) else ()  # type: ignore[arg-type]
                shown = [f.name for f in fields if f.repr]
                keys.update({name: Key(name, omit=key.omit) for name in shown})
            elif key.name == "**":
                keys[f"**{len(keys)}"] = key
            else:
                keys[key.name] = key
        return list(keys.values())

    def to_dict(self, **options: bool) -> dict[str, Any]:
        """The record as plain data, key by key of :attr:`_keys` (by default every repr field, :func:`plain`);
        ``options`` (``alternatives=True``) add the keys declared with that ``option``.  JSON after
        :func:`designer.jsonsafe.finite`."""
        unknown = set(options) - {k.option for k in self._layout() if k.option}
        if unknown:
            raise TypeError(f"{type(self).__name__}.to_dict() got an unexpected option {sorted(unknown)[0]!r}")
        out: dict[str, Any] = {}
        for key in self._layout():
            if key.option is not None and not options.get(key.option):
                continue
            value = key.value(self)
            if key.omitted(value):
                continue
            if key.name == "**":
                out.update(value)
            else:  # at the dotted key (nested dicts made as needed)
                *parents, last = key.name.split(".")
                place = out
                for part in parents:
                    place = place.setdefault(part, {})
                place[last] = value
        return out


class Record(Keyed):
    """The result protocol (module text): ``to_dict``, ``to_pandas``, ``_repr_html_`` and ``__repr__``.

    A record is a dataclass deriving from this class and built by keyword.  The defaults work from its fields
    (those shown in the dataclass repr; back references such as the problem are declared ``repr=False``):

    - :meth:`to_dict` gives every such field as plain data (:func:`plain`);
    - :meth:`to_pandas` one row of the flattened :meth:`to_dict`, units from :attr:`_units`;
    - :meth:`_repr_html_` a table of :meth:`_html_rows` under :meth:`_html_title`;
    - ``repr`` the :meth:`_repr_lines` (the class name and its fields), at most :data:`MAX_REPR_LINES`;

    both reprs show each key of :meth:`to_dict` with its unit (:attr:`_units`, else the parameter table's label,
    precision and unit: :meth:`_shown`), a list by its length, as GPkit's ``SolutionArray.table()`` prints any
    solution from its variables' own keys.

    A record declares the shape of its data in :attr:`_keys` (renamed keys, values read along a path, nested
    keys, keys left out when empty, keys given on request), overrides :meth:`to_pandas` when it has a better
    table (documented where it round-trips: ``from_pandas``), and the hooks ``_repr_lines``, ``_html_title``, ``_html_rows``,
    ``_html_caption``, ``_html_extra`` to change what the reprs show; it never defines ``__repr__`` or
    ``_repr_html_`` itself (a TypeError at class creation), so the protocol is spelled once.  No hook may run a
    solver or a Monte Carlo.
    """

    _units: ClassVar[Mapping[str, str]] = {}
    """SI unit of each field (dotted names of the flattened ``to_dict``), shown beside values and in pandas attrs."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name in ("__repr__", "_repr_html_"):
            if name in cls.__dict__ and cls.__dict__[name] is not getattr(Record, name):
                raise TypeError(
                    f"{cls.__name__} defines {name}: a Record shows itself through the _repr_lines and _html_* hooks"
                )
        # @dataclass writes its own __repr__ unless the class body has one: this one is the protocol's
        cls.__repr__ = Record.__repr__  # type: ignore[method-assign]

    def to_pandas(self) -> Any:
        """One row: the flattened :meth:`to_dict` (dotted column names), units in ``df.attrs["units"]``."""
        row = flatten(self.to_dict())
        units = {k: u for k, u in self._units.items() if k in row}
        return dataframe(f"{type(self).__name__}.to_pandas", [row], list(row), units, record=type(self).__name__)

    # ----------------------------------------------------------------- reprs
    def __repr__(self) -> str:
        lines = self._repr_lines()
        if len(lines) > MAX_REPR_LINES:
            lines = lines[: MAX_REPR_LINES - 1] + [lines[MAX_REPR_LINES - 1].rstrip() + " …"]
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """A compact HTML table: a bold title (:meth:`_html_title`), rows of (label, value, unit)
        (:meth:`_html_rows`), an optional caption (:meth:`_html_caption`) and extra HTML (:meth:`_html_extra`).

        A value is shown as given (the hooks format numbers); the extra (e.g. an SVG) is placed beside the table
        unescaped, so a hook returns only strings built by this package.
        """
        table, th, td, unit = STYLE
        body = "".join(
            f'<tr><th style="{th}">{escape(str(label))}</th><td style="{td}">{escape(str(value))}</td>'
            f'<td style="{unit}">{escape(str(u))}</td></tr>'
            for label, value, u in self._html_rows()
        )
        caption, extra = self._html_caption(), self._html_extra()
        cap = (
            f'<div style="font-size:11px;color:#555;font-family:sans-serif;max-width:420px">{escape(caption)}</div>'
            if caption
            else ""
        )
        inner = (
            f'<div><div style="font-weight:bold;font-family:sans-serif;font-size:13px">{escape(self._html_title())}'
            f'</div><table style="{table}">{body}</table>{cap}</div>'
        )
        if extra:
            return (
                f'<div style="display:flex;gap:16px;align-items:flex-start">'
                f'<div style="flex:none">{inner}</div><div style="flex:none">{extra}</div></div>'
            )
        return f"<div>{inner}</div>"

    def _shown(self) -> list[tuple[str, str, str, str]]:
        """(key, label, value, unit) of each item of the flattened :meth:`to_dict` but its nested lists of records
        (a list by its length): a quantity of the parameter table (:mod:`designer.parameters`) under its label,
        with its precision and SI unit (:mod:`designer.display`), unless :attr:`_units` gives its unit."""
        out = []
        for key, value in flatten(self.to_dict()).items():
            entry = _quantity(key)
            prefix = key.rsplit(".", 1)[0] + " " if "." in key else ""
            label = prefix + entry.label if entry is not None else key
            unit = self._units.get(key, unit_text(entry.name) if entry is not None else "")
            numeric = isinstance(value, (int, float)) and not isinstance(value, bool)
            own = entry is None or not numeric or key in self._units  # else the table's precision
            out.append((key, label, shown(value) if own else number(value, entry.name), unit))
        return out

    def _repr_lines(self) -> list[str]:
        """The repr's lines: ``Class(field=value unit, ...)`` of the fields, wrapped at :data:`REPR_WIDTH`."""
        parts = [f"{k}={v if len(v) <= 60 else v[:59] + '…'} {u}".rstrip() for k, _, v, u in self._shown()]
        lines, line = [], f"{type(self).__name__}("
        for i, part in enumerate(parts):
            piece = part + (", " if i < len(parts) - 1 else "")
            if len(line) + len(piece) > REPR_WIDTH and line.strip():
                lines.append(line.rstrip())
                line = "  "
            line += piece
        lines.append(line + ")")
        return lines

    def _html_title(self) -> str:
        """The class name, with the name of the record's problem (or its own) when it has one."""
        name = getattr(getattr(self, "problem", self), "name", None)
        return type(self).__name__ + (f" {name!r}" if isinstance(name, str) else "")

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """(label, value, unit) rows of the HTML table: every item of :meth:`_shown`."""
        return [(label, v, u) for _, label, v, u in self._shown()]

    def _html_caption(self) -> str:
        """The title of the record's problem (or its own), or ""."""
        title = getattr(getattr(self, "problem", self), "title", "")
        return title if isinstance(title, str) else ""

    def _html_extra(self) -> str:
        """HTML placed beside the table (e.g. an SVG curve built by :func:`svg_curve`), or ""."""
        return ""


__all__ = [
    "FrozenMapping",
    "deep_frozen",
    "freeze_fields",
    "Key",
    "Keyed",
    "MAX_REPR_LINES",
    "frozen",
    "Record",
    "dataframe",
    "flatten",
    "plain",
    "shown",
    "si_frame",
]
