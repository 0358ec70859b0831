"""One boundary rule for the API's numbers (issue 42, class 3): every numeric argument of every public function and
record of ``designer.__all__`` takes a Python int or float, a NumPy scalar and a 0-d array alike, refuses a
boolean, NaN and infinity with that reason, and reads a string with its unit; a count takes whole numbers only.

The table is built from the API itself (the rules each public function declares with
:func:`designer.boundary.checked`, the number fields of the records), so a numeric argument added without a rule
fails :func:`test_every_numeric_parameter_of_a_public_function_has_a_rule`.  Refused rows call the public function
itself (the rule runs before any work); accepted rows run the same checks without the body
(``function.arguments``), and the issue's own cases run for real."""

from __future__ import annotations

import inspect
import math
import re
from pathlib import Path

import numpy as np
import pytest

import designer
from designer.boundary import Count, Instance, Quantities, Quantity, Values
from designer.errors import InputError
from designer.model import Conditions, Design

ROOT = Path(__file__).resolve().parents[1]
DESIGN = Design(trail="1.5 in", diameter="6 in", groove=0.0, damping=1.3)
CURRENT = "T=1.5in,d=7.75in,B=0.5625in,c=1.3"

SAMPLE = {  # dimension -> (a number [SI], the same with a unit, the unit string's value in SI)
    "length": (0.05, "5 cm", 0.05),
    "force": (178, "40 lbf", 40 * 4.4482216152605),
    "speed": (2.5, "9 km/h", 2.5),
    "angle": (0.3, "20 deg", math.radians(20)),
    "inertia": (0.0012, "0.0012 kg*m**2", 0.0012),
    "angular_speed": (0.7, "0.7 rad/s", 0.7),
    "time": (2, "2 s", 2.0),
    "dimensionless": (0.05, "5 %", 0.05),
    "mass": (0.444, "444 g", 0.444),
    "damping": (1.3, "1.3 N*m/rad", 1.3),
}


def _problem():
    return designer.example_problem("indoor-manual")


BASE = {  # a public function -> the other arguments a call needs
    "optimise": lambda: ((_problem(),), {}),
    "pareto_front": lambda: ((_problem(),), {}),
    "explore": lambda: ((_problem(),), {}),
    "fleet": lambda: ((ROOT / "no-such-fleet.csv",), {}),
    "recommend": lambda: ((_problem(),), {}),
    "fix": lambda: ((_problem(), CURRENT), {}),
    "simulate": lambda: ((DESIGN,), {}),
    "knock_safe_speed": lambda: ((DESIGN,), {}),
    "bifurcation_diagram": lambda: ((DESIGN,), {}),
    "evaluate": lambda: ((DESIGN,), {}),
}

KINDS = ["int", "float", "np.float32", "np.int64", "0-d array", "bool", "NaN", "inf", "str with unit", "str"]
"""The columns of the table: how a user may write a number."""


def _given(kind: str, number: float, unit_text: str, whole: int) -> object:
    """The value of column ``kind`` for a quantity ``number`` (or the count ``whole``)."""
    return {
        "int": whole,
        "float": float(number) + (0.5 if float(number).is_integer() else 0.0),
        "np.float32": np.float32(number),
        "np.int64": np.int64(whole),
        "0-d array": np.array(whole),
        "bool": True,
        "NaN": math.nan,
        "inf": math.inf,
        "str with unit": unit_text,
        "str": str(number),
    }[kind]


def _quantity_outcome(kind: str) -> str:
    """Expected outcome of a quantity: accepted (as SI) or the reason of the refusal."""
    return {"bool": "got a boolean", "NaN": "must be a finite number", "inf": "must be a finite number"}.get(
        kind, "accepted"
    )


def _count_outcome(kind: str) -> str:
    """Expected outcome of a count: whole numbers only (ints, NumPy's integers, a 0-d integer array)."""
    if kind in ("int", "np.int64", "0-d array"):
        return "accepted"
    return "got a boolean" if kind == "bool" else "expected"


def _public_functions() -> dict[str, object]:
    return {
        name: getattr(designer, name)
        for name in designer.__all__
        if inspect.isfunction(getattr(designer, name)) and hasattr(getattr(designer, name), "rules")
    }


def _rows() -> list[tuple[str, str, str, object, object]]:
    """(function, argument, kind, given value, expected: 'accepted', the SI value, or a reason)."""
    rows = []
    for fname, function in sorted(_public_functions().items()):
        for arg in function.rules:
            rule = function.rule(arg)
            if isinstance(rule, (Quantity, Values)):
                number, unit_text, si = SAMPLE[rule.dimension]
                for kind in KINDS:
                    given = _given(kind, number, unit_text, int(number) if float(number).is_integer() else 1)
                    if kind == "str" and rule.dimension not in ("dimensionless", "angle"):
                        rows.append((fname, arg, kind, given, "a number without its unit"))  # a plain "2.5" has no unit
                        continue
                    outcome = _quantity_outcome(kind)
                    rows.append((fname, arg, kind, given, outcome if outcome != "accepted" else si))
            elif isinstance(rule, Count):
                whole = rule.low if rule.low is not None and rule.low > 0 else 5
                for kind in KINDS:
                    outcome = _count_outcome(kind)
                    given = _given(kind, whole, f"{whole} s", whole)
                    rows.append((fname, arg, kind, given, whole if outcome == "accepted" else outcome))
    return rows


ROWS = _rows()


def _expected_number(kind: str, si: float, given: object) -> float:
    """What an accepted value must become [SI]: the unit string's SI value, else the number written."""
    return si if kind == "str with unit" else float(given)  # type: ignore[arg-type]


@pytest.mark.parametrize("fname, arg, kind, given, expected", ROWS, ids=[f"{r[0]}-{r[1]}-{r[2]}" for r in ROWS])
def test_every_numeric_argument_of_every_public_function(fname, arg, kind, given, expected):
    """One row per public function × numeric argument × way of writing a number: accepted values reach the body as
    a float [SI] (or an int for a count) equal to what was written; refused ones are one InputError line naming
    the argument and the reason, before any work."""
    function = getattr(designer, fname)
    args, kwargs = BASE[fname]()
    kwargs[arg] = given
    if isinstance(expected, str):
        with pytest.raises(InputError) as caught:
            function(*args, **kwargs)
        text = str(caught.value)
        assert text.startswith(f"{arg} = ") or text.startswith(f"{arg}["), text
        assert expected in text and "\n" not in text
        return
    got = function.arguments(*args, **kwargs).arguments[arg]
    assert got == pytest.approx(_expected_number(kind, expected, given), rel=1e-12)
    assert type(got) is (int if isinstance(function.rule(arg), Count) else float)


RECORD_NUMBERS = [
    (Design, ("trail", "diameter", "groove", "damping"), lambda **kw: Design(**{**DESIGN.to_dict(), **kw})),
    (Conditions, ("load", "threshold_height", "disturbance_angle", "slip_coefficient"), lambda **kw: Conditions(**kw)),
    (
        designer.TyreParameters,
        ("cornering_stiffness", "friction_coefficient", "load", "wheel_mass"),
        lambda **kw: designer.TyreParameters(**kw),
    ),
    (
        designer.Uncertainty,
        ("probability", "model_error", "damping", "slip_coefficient", "inertia"),
        lambda **kw: designer.Uncertainty(**kw),
    ),
]

RECORD_VALUES = {  # field -> (a valid number [SI], written with a unit, its SI value, dimension, reason a whole
    # number is refused by the field's range or "")
    "trail": (0.05, "5 cm", 0.05, "length", ""),
    "diameter": (0.15, "6 in", 0.1524, "length", ""),
    "groove": (0.01, "1 cm", 0.01, "length", ""),
    "damping": (1.3, "1.3 N*m/rad", 1.3, "damping", ""),
    "load": (178, "40 lbf", 40 * 4.4482216152605, "force", ""),
    "threshold_height": (0.0127, "0.5 in", 0.0127, "length", "outside the model's range"),
    "disturbance_angle": (0.3, "20 deg", math.radians(20), "angle", ""),
    "slip_coefficient": (1250, "1250 N", 1250.0, "force", ""),
    "cornering_stiffness": (1250, "1250 N", 1250.0, "force", ""),
    "friction_coefficient": (0.7, "70 %", 0.7, "dimensionless", ""),
    "wheel_mass": (0.444, "444 g", 0.444, "mass", ""),
    "Uncertainty.probability": (0.05, "5 %", 0.05, "dimensionless", "between 0 and 1"),
    "Uncertainty.model_error": (0.1, "10 %", 0.1, "dimensionless", ""),
    "Uncertainty.damping": (0.1, "10 %", 0.1, "dimensionless", ""),
    "Uncertainty.slip_coefficient": (0.2, "20 %", 0.2, "dimensionless", ""),
    "Uncertainty.inertia": (0.05, "5 %", 0.05, "dimensionless", ""),
}


def _record_rows():
    rows = []
    for cls, fields, build in RECORD_NUMBERS:
        for name in fields:
            number, unit_text, si, dimension, whole_refusal = (
                RECORD_VALUES.get(f"{cls.__name__}.{name}") or RECORD_VALUES[name]
            )
            for kind in KINDS:
                given = _given(kind, number, unit_text, int(number) if float(number).is_integer() else 1)
                if kind == "str" and dimension not in ("dimensionless", "angle"):
                    expected: object = "a number without its unit"
                elif kind in ("int", "np.int64", "0-d array") and whole_refusal:
                    expected = whole_refusal  # no whole number [SI] is in this field's range: refused by its range
                else:
                    outcome = _quantity_outcome(kind)
                    expected = outcome if outcome != "accepted" else si
                rows.append((cls.__name__, build, name, kind, given, expected))
    return rows


RECORD_ROWS = _record_rows()


@pytest.mark.parametrize(
    "cls, build, name, kind, given, expected",
    RECORD_ROWS,
    ids=[f"{r[0]}-{r[2]}-{r[3]}" for r in RECORD_ROWS],
)
def test_every_number_field_of_the_public_records(cls, build, name, kind, given, expected):
    """The records of the API (Design, Conditions, TyreParameters, Uncertainty) read their numbers by the same rule:
    ``Design(trail, diameter, 0.0, False)`` is refused like ``Conditions(load=True)`` (the issue), a NumPy scalar
    or 0-d array is a number, NaN and infinity are refused with that reason."""
    if isinstance(expected, str):
        with pytest.raises(InputError) as caught:
            build(**{name: given})
        text = str(caught.value)
        assert name in text and expected in text and "\n" not in text, text
        return
    got = getattr(build(**{name: given}), name)
    assert type(got) is float
    assert got == pytest.approx(_expected_number(kind, expected, given), rel=1e-12)


ISSUE_ROWS = [  # (label, call, expected: None when it must succeed, else text of the one-line refusal)
    ("Conditions(load=np.float32(900))", lambda: Conditions(load=np.float32(900)).load, None),
    ("Conditions(load=np.int64(900))", lambda: Conditions(load=np.int64(900)).load, None),
    ("Conditions(load=np.array(900.0))", lambda: Conditions(load=np.array(900.0)).load, None),
    ("Design(T, d, 0.0, False)", lambda: Design(0.05, 0.15, 0.0, False), "damping = False: expected a number"),
    ("Conditions(load=True)", lambda: Conditions(load=True), "load = True: expected a number"),
    ("optimise(p, samples=-5)", lambda: designer.optimise(_problem(), samples=-5), "samples = -5: expected"),
    ("recommend(p, seed=-1)", lambda: designer.recommend(_problem(), seed=-1), "seed = -1: expected"),
    ("fix(p, d, seed=-1)", lambda: designer.fix(_problem(), CURRENT, seed=-1), "seed = -1: expected"),
    ("fleet(..., k_max=0)", lambda: designer.fleet(ROOT / "x.csv", k_max=0), "k_max = 0: expected"),
    ("explore(..., population_size=0)", lambda: designer.explore(_problem(), population_size=0), "population_size"),
    ("fix(problem, None)", lambda: designer.fix(_problem(), None), "current = None: expected a designer.Design"),
    ("simulate('abc')", lambda: designer.simulate("abc"), "design = 'abc': expected a designer.Design"),
    ("knock_safe_speed(None)", lambda: designer.knock_safe_speed(None), "design = None: expected a designer.Design"),
    ("Front.from_csv(missing)", lambda: designer.Front.from_csv("nope/front.csv"), "nope/front.csv: no such"),
    ("evaluate(load=[True])", lambda: designer.evaluate(DESIGN, load=[True, False]), "load: expected numbers"),
    ("Problem pareto_points True", lambda: _problem().replace(pareto_points=True), "got a boolean"),
    ("Problem weights (True, 1)", lambda: _problem().replace(weights=(True, 1)), "weights[0] = True"),
    ("Problem pareto_points np.int64", lambda: _problem().replace(pareto_points=np.int64(9)).pareto_points, None),
    ("optimise samples 2.5", lambda: designer.optimise(_problem(), samples=2.5), "samples = 2.5: expected a whole"),
    ("pareto points np.bool_", lambda: designer.pareto_front(_problem(), points=np.bool_(True)), "got a boolean"),
    ("simulate speed np.float32 nan", lambda: designer.simulate(DESIGN, speed=np.float32("nan")), "finite"),
    ("knock tyre 'brush'", lambda: designer.knock_safe_speed(DESIGN, tyre="brush"), "tyre = 'brush': expected"),
    ("bifurcation range of one", lambda: designer.bifurcation_diagram(DESIGN, speed_range=(1.0,)), "speed_range"),
]


@pytest.mark.parametrize("call, expected", [r[1:] for r in ISSUE_ROWS], ids=[r[0] for r in ISSUE_ROWS])
def test_the_issues_cases_and_more(call, expected):
    """The cases the issue lists, and others of the same classes (a 0-d array, np.bool_, a count of 2.5, a boolean
    per caster, a tyre given by name), each accepted or refused in one line with the true reason."""
    if expected is None:
        assert call() in (900.0, 9)
        return
    with pytest.raises(InputError) as caught:
        call()
    assert expected in str(caught.value) and "\n" not in str(caught.value), str(caught.value)


def test_fix_takes_a_numpy_inertia_end_to_end():
    """``fix(..., inertia=np.float32(0.0012))`` (the issue: "must be between 1e-09 and 10 kg·m²") runs and uses the
    value given, as float(np.float32(0.0012))."""
    result = designer.fix(_problem(), CURRENT, inertia=np.float32(0.0012), specs=0, limit=1)
    assert result.current.inertia == pytest.approx(float(np.float32(0.0012)), rel=1e-12)


def test_every_numeric_parameter_of_a_public_function_has_a_rule():
    """A parameter of a public function annotated as a number (int or float) is declared with a rule of
    designer.boundary, so it is checked like every other; a new one without a rule fails here."""
    own_checks = {  # arguments checked by a function of their own, each tested in tests/test_api_boundary.py
        ("evaluate", "weights"),  # two weights: designer.model._candidates._weights (each by real_number)
        ("optimise", "weights"),  # designer.problem.check_weights (each by real_number)
        ("report_data", "points"),  # passed on to pareto_front, whose rule is in the table
    }
    missing = []
    for name in designer.__all__:
        function = getattr(designer, name)
        if not inspect.isfunction(function) or name in ("performance",):  # performance: floats, arrays, CasADi
            continue
        rules = getattr(function, "rules", ())
        for p in inspect.signature(function).parameters.values():
            note = str(p.annotation)
            numeric = re.search(r"\b(int|float)\b", note) and "Callable" not in note
            if numeric and p.name not in rules and (name, p.name) not in own_checks:
                missing.append(f"{name}({p.name}: {note})")
    assert missing == []


def test_a_rule_catches_a_missing_check():
    """The table's premise: without its rule, a boolean slips through as a number (what Design did before)."""
    assert float(True) == 1.0  # Python counts a boolean as a number ...
    with pytest.raises(InputError, match="got a boolean"):
        Quantity("damping")(False, "damping")  # ... the boundary does not
    with pytest.raises(InputError, match="expected a designer.Design"):
        Instance((Design,), "a designer.Design")("abc", "design")
    assert Quantities("speed", 2)((np.float32(0.5), "9 km/h"), "speed_range") == pytest.approx((0.5, 2.5))
