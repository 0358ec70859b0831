"""The API's boundary: one rule for the numbers, counts and records a public function is given.

Every public function of :data:`designer.__all__` that takes a number, a count or a record declares its
arguments here, with :func:`checked`, and every value passes one of three rules before the function's body
runs:

``Quantity(dimension)``  a number [SI] or a string with units: :func:`designer.units.parse_quantity`, whose
                         numbers are :func:`designer.units.real_number`'s (``numbers.Real``, NumPy scalars and
                         0-d arrays included; booleans, NaN and infinities refused with that reason)
``Count(low, high)``     a whole number in a range: :func:`designer.units.whole_number` (``numbers.Integral``,
                         NumPy's integers included; booleans, floats and strings refused)
``Instance(kinds)``      a record of the package (a ``Design``, ``Conditions``): anything else is one InputError
                         line naming the argument and what it expects, never an AttributeError deep inside

(``Quantities`` is a fixed number of quantities, a speed range; ``Values`` a quantity given once or once per
caster, ``evaluate``'s loads and limits.)

The records (``Design``, ``Conditions``, ``Problem``, ``Uncertainty``, ``TyreParameters``) read their fields
with the same two functions of :mod:`designer.units`, and the problem file and the command line too, so a value
is refused alike wherever it enters.  The function's own range checks (an inertia within Table 1's span, a
front of 2 to 2001 points) then work on plain floats and ints.  Ground layer: imports nothing heavy (NumPy).
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from designer.errors import InputError
from designer.units import parse_quantity, whole_number

_F = TypeVar("_F", bound=Callable[..., Any])


@dataclass(frozen=True)
class Quantity:
    """A physical quantity [SI]: a number or a string with units of ``dimension``
    (:data:`designer.units.DIMENSIONS`); None passes when ``optional``."""

    dimension: str
    optional: bool = False

    def __call__(self, value: Any, key: str) -> Any:
        if value is None and self.optional:
            return None
        return parse_quantity(value, self.dimension, key)


@dataclass(frozen=True)
class Quantities:
    """A fixed number of quantities of one dimension (a speed range): a sequence of ``length`` values, each by
    :class:`Quantity`; given back as a tuple."""

    dimension: str
    length: int

    def __call__(self, value: Any, key: str) -> tuple[float, ...]:
        if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != self.length:
            raise InputError(f"{key} = {value!r}: expected {self.length} values ({self.dimension}), e.g. (0.3, 4.0)")
        return tuple(parse_quantity(v, self.dimension, f"{key}[{i}]") for i, v in enumerate(value))


@dataclass(frozen=True)
class Values:
    """A quantity given once or once per caster (``evaluate(..., load=...)``): one value by :class:`Quantity`, or
    an array (a list, a tuple, a NumPy array of one dimension or more) of numbers [SI], given back as a float
    array (booleans and strings refused); None passes when ``optional``."""

    dimension: str
    optional: bool = True

    def __call__(self, value: Any, key: str) -> Any:
        if value is None and self.optional:
            return None
        if not isinstance(value, (list, tuple)) and not (hasattr(value, "shape") and getattr(value, "ndim", 0) > 0):
            return parse_quantity(value, self.dimension, key)
        array = np.asarray(value)
        if array.dtype.kind not in "iuf":
            kind = "booleans" if array.dtype.kind == "b" else f"{array.dtype} values"
            raise InputError(f"{key}: expected numbers [SI] (one per caster), got {kind}")
        return array.astype(float)  # per caster, an infinity is "no limit" (a fleet's chairs without a radius)


@dataclass(frozen=True)
class Count:
    """A whole number from ``low`` to ``high`` (None: open); None passes when ``optional``.  ``what`` names the
    thing counted in the message."""

    low: int | None = None
    high: int | None = None
    optional: bool = False
    what: str = ""
    words: tuple[str, ...] = ()
    """Words that stand for a count chosen by the function (``skus="auto"``), passed as they are."""

    def __call__(self, value: Any, key: str) -> Any:
        if (value is None and self.optional) or (isinstance(value, str) and value in self.words):
            return value
        return whole_number(value, key, self.low, self.high, self.what, self.optional)


@dataclass(frozen=True)
class Instance:
    """An instance of one of ``kinds`` (a record of the package), named in the message by ``expected``."""

    kinds: tuple[type, ...]
    expected: str
    optional: bool = False

    def __call__(self, value: Any, key: str) -> Any:
        if (value is None and self.optional) or isinstance(value, self.kinds):
            return value
        raise InputError(f"{key} = {one_line(value)}: expected {self.expected}")


def one_line(value: Any, width: int = 80) -> str:
    """``repr(value)`` on one line, at most ``width`` characters (a batch or a record's repr runs to several)."""
    text = " ".join(repr(value).split())
    return text if len(text) <= width else text[: width - 1] + "…"


SEED = Count(0, 2**32 - 1, optional=True)
"""A random seed of the API (``seed=``): None (the default's) or 0 to 2³² − 1, as numpy and the command line take."""

Rule = Quantity | Quantities | Values | Count | Instance


def checked(**rules: Rule | Callable[[], Rule]) -> Callable[[_F], _F]:
    """Decorator of a public function: each argument named in ``rules`` passes its rule before the body runs,
    which gets the values the rules give back (floats [SI], ints, the records as they are).

    A rule may be given as a function returning it (``current=lambda: Instance((Design, str), ...)``): it is
    built on the first call, so a module need not import a record's module to declare it.  The wrapper keeps
    the function's signature and offers ``wrapper.arguments(*args, **kwargs)``, the same checks without the
    body (``inspect.BoundArguments`` of the checked values), and ``wrapper.rules``.
    """

    def decorate(function: _F) -> _F:
        signature = inspect.signature(function)
        unknown = set(rules) - set(signature.parameters)
        if unknown:
            raise TypeError(f"{function.__qualname__}: checked() names no parameter {sorted(unknown)[0]!r}")
        built: dict[str, Rule] = {}

        def rule(name: str) -> Rule:
            if name not in built:
                given = rules[name]
                built[name] = given if isinstance(given, Rule) else given()
            return built[name]

        def arguments(*args: Any, **kwargs: Any) -> inspect.BoundArguments:
            bound = signature.bind(*args, **kwargs)
            for name in rules:
                if name in bound.arguments:
                    bound.arguments[name] = rule(name)(bound.arguments[name], name)
            return bound

        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            bound = arguments(*args, **kwargs)
            return function(*bound.args, **bound.kwargs)

        wrapper.arguments = arguments  # type: ignore[attr-defined]
        wrapper.rules = tuple(rules)  # type: ignore[attr-defined]
        wrapper.rule = rule  # type: ignore[attr-defined]
        return wrapper  # type: ignore[return-value]

    return decorate


__all__ = ["SEED", "Count", "Instance", "Quantities", "Quantity", "Rule", "Values", "checked", "one_line"]
