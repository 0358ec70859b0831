"""The studio renders records: no module of ``designer/studio`` imports or calls an evaluation function of the model
or the physics, nor an inertia model it could put in the problem's place (issue 41: the card's
``Fixed(inertia)`` turned a wheel known by its diameter into a measured one, 0.26 % beside 2.98 %).

Read from the source (AST), late imports included; a planted module shows that each kind of violation is caught.
"""

from __future__ import annotations

import ast
from pathlib import Path

import designer

STUDIO = Path(designer.__file__).resolve().parent / "studio"

EVALUATORS = {
    "evaluate",
    "evaluate_candidates",
    "performance",
    "critical_speed",
    "critical_shimmy_speed",
    "turning_effort",
    "threshold_force",
    "threshold_force_ratio",
    "shimmy_probability",
    "shimmy_probability_exact",
    "shimmy_probability_mc_many",
    "shimmy_speed_quantile",
    "exact_shimmy_probability",
    "risk_record",
    "law_draws",
    "law_quantile",
    "inertia_prediction",
    "growth_rate",
}
"""Functions that compute a caster's numbers (the model's evaluator, Eq. 7, Eq. 4A, Eq. 9, the risk law)."""

INERTIA_MODELS = {"Fixed", "PowerLaw", "Catalog", "Disc"}
"""Inertia models: the studio takes a wheel's I_w from its record, never puts a model in the problem's place."""

SOURCES = ("designer.model", "designer.physics")
"""Where they live."""


def violations(source: str) -> list[str]:
    """Each import of an evaluation function or an inertia model from the model or the physics in ``source``, and
    each call of ``<designer module>.evaluate(...)`` (``designer.evaluate``, ``model.evaluate``)."""
    tree = ast.parse(source)
    found = []
    aliases = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                forbidden = alias.name in EVALUATORS or alias.name in INERTIA_MODELS
                if node.module.startswith(SOURCES) and forbidden:
                    found.append(f"line {node.lineno}: from {node.module} import {alias.name}")
                if node.module == "designer" and alias.name in EVALUATORS:
                    found.append(f"line {node.lineno}: from designer import {alias.name}")
                if node.module in ("designer", *SOURCES) or node.module.startswith(SOURCES):
                    aliases.add(alias.asname or alias.name)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "designer" or alias.name.startswith(SOURCES):
                    aliases.add(alias.asname or alias.name.split(".")[0])
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in EVALUATORS:
            owner = ast.unparse(node.func.value)
            if owner.split(".")[0] in aliases:
                found.append(f"line {node.lineno}: calls {ast.unparse(node.func)}")
    return found


def test_no_studio_module_evaluates_a_caster():
    """Every module of designer/studio: no evaluation function of the model or the physics imported or called,
    no inertia model imported (its numbers come from the records of recommend, pareto_front, fix and the
    sweep study)."""
    modules = sorted(STUDIO.glob("*.py"))
    assert len(modules) >= 8
    found = {path.name: violations(path.read_text(encoding="utf-8")) for path in modules}
    assert {name: v for name, v in found.items() if v} == {}


def test_the_rule_catches_a_planted_evaluation():
    """The rule is not vacuous: the card as it was (model.evaluate, Fixed), a late import of the risk law, a call
    of designer.evaluate and an aliased physics module's Eq. 7 are each reported; a study call is not."""
    planted = """
from designer.model import Design, evaluate
from designer.physics.inertia import Catalog, Fixed
import designer
import designer.physics.shimmy as shimmy

def card(problem, design):
    from designer.physics.uncertainty import shimmy_probability_exact
    values = evaluate(design, problem.conditions)
    again = designer.evaluate(design, problem.conditions, risk=2.5)
    return shimmy.critical_shimmy_speed(1, 2, 3)

def fine(problem):
    from designer.studies.recommend import recommend
    return recommend(problem)
"""
    found = violations(planted)
    assert any("import evaluate" in v for v in found)
    assert any("import Fixed" in v for v in found) and any("import Catalog" in v for v in found)
    assert any("shimmy_probability_exact" in v for v in found)
    assert any("calls designer.evaluate" in v for v in found)
    assert any("calls shimmy.critical_shimmy_speed" in v for v in found)
    assert not any("recommend" in v for v in found)
    assert len(found) == 6
