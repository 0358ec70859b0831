"""Tolerances in every answer (issue 43): the price of the tolerances is stated from the least-J casters with and
without them, not from the rule's two picks."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from designer.problem import load_problem

ROOT = Path(__file__).resolve().parents[2]


def test_price_of_tolerances_compares_the_least_j_casters_with_and_without_them():
    """indoor-manual-tolerances (enforce = true): the price is J of the least-J buildable caster that holds at its
    worst corner (7 in, B 3/4 in, c_f 2.0 N·m/rad: the issue's 118.76 N) minus J of the least-J buildable caster
    (114.91 N, which fails there at 5.39 %); every buildable caster of lower J than the holding one fails at its
    worst corner (computed here caster by caster); the sentence says so and no longer gives the difference of the
    rule's picks (11.11 N more sill force) as the price."""
    from designer.studies.recommend import recommend
    from designer.studies.recommend._recommend import _buildable
    from designer.studies.spec import caster_corner

    problem = load_problem(ROOT / "problems" / "indoor-manual-tolerances.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        rec = recommend(problem, specs="none")
        b = _buildable(problem)
    price = rec.enforced["price"]
    hold, free = price["least_objective_holding"], price["least_objective_without_tolerances"]
    v = b.values
    j = v.turning_effort + v.threshold_force  # weights (1, 1)
    assert free["objective"] == pytest.approx(float(j.min()), rel=1e-12)
    assert hold["design"]["damping"] == pytest.approx(2.0) and hold["design"]["diameter"] == pytest.approx(7 * 0.0254)
    assert hold["objective"] == pytest.approx(118.76, abs=0.02)
    assert price["objective_price"] == pytest.approx(hold["objective"] - free["objective"], rel=1e-12)
    alpha = float(problem.risk.probability)
    below = np.flatnonzero(j < hold["objective"] - 1e-9)
    assert len(below) >= 1
    for i in below:
        corner = caster_corner(problem, b.design(int(i)), float(v.inertia[i]), bool(v.measured[i]))
        assert corner.probability > alpha
    text = rec.enforced_sentence()
    assert "Price of the tolerances: the least-J caster that holds" in text and "3.85 N of J" in text
    assert "rule's choice" in text


def _fleet_with_and_without(chairs: int):
    """(the tolerances example problem, designer.fleet's part numbers of the ``chairs``-chair example fleet of seed 0
    on it, the same without its [tolerances]): no Monte Carlo."""
    from designer.studies.fleet import example_fleet, fleet_recommendations

    problem = load_problem(ROOT / "problems" / "indoor-manual-tolerances.toml")
    fleet = example_fleet(chairs, seed=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        result = fleet_recommendations(fleet, problem, skus="auto", monte_carlo=False)
        bare = fleet_recommendations(fleet, problem.replace(tolerances=None), skus="auto", monte_carlo=False)
    return problem, result, bare


def test_fleet_part_numbers_hold_at_their_worst_corner_with_windows_at_least_the_tolerances():
    """designer.fleet on the 200-chair example with the shipped tolerances example as base problem (trail ±1.5 mm,
    groove ±0.4 mm, d ±1 mm, friction −30 %): every part number's spec holds P <= α at the worst corner of the
    tolerances (exact law), its joint box is at least the stated tolerances (scale >= 1 on every risk part) and its
    footrest trail maximum leaves at least the trail's ±1.5 mm above nominal (with d at +1 mm).  Without the
    tolerances the same fleet's part numbers fail there (the issue's 4.6–4.9 % part numbers): the check can fail.
    The price of the tolerances in part numbers is the separate run's suggested count against this one's: 9 and 9,
    so they cost no part number on this fleet."""
    problem, result, bare = _fleet_with_and_without(200)
    tol = problem.tolerances
    assert bare.tolerance_price is None and bare.suggested["count"] == 9 == result.suggested["count"]
    assert result.tolerance_price == {
        "part_numbers": 0,
        "with_tolerances": 9,
        "without_tolerances": 9,
        "sentence": "The tolerances cost no part number: 9 with them, 9 without.",
    }
    assert result.specs
    for spec in result.specs:
        assert spec.corner is not None and spec.corner["holds"]
        joint = spec.joint
        assert joint.shape == "tolerances" and joint.scale >= 1
        assert joint.trail_max - spec.trail >= tol.trail - 1e-12
        assert spec.trail - joint.trail_min >= tol.trail - 1e-12
        assert spec.groove - joint.groove_min >= tol.groove - 1e-12
    from designer.studies.spec import caster_corner

    failing = [
        spec
        for spec in bare.specs
        if not caster_corner(
            problem.replace(target_speed=spec.target_speed), _design(spec), spec.inertia, spec.measured
        ).holds
    ]
    assert failing, "without tolerances some part number should fail at the worst corner"


def test_fleet_report_states_what_the_tolerances_cost_in_part_numbers(tmp_path, capsys):
    """designer fleet on the 200-chair example of seed 1 with the tolerances example: 9 part numbers with them, 7
    without (a separate run of the same fleet with [tolerances] removed), stated once in --json, fleet.json, the
    report's first screen (report.md, index.html) and the screen's answer."""
    import json

    from designer.cli import main
    from designer.studies.fleet import example_fleet, fleet_recommendations, write_fleet_csv

    problem = ROOT / "problems" / "indoor-manual-tolerances.toml"
    chairs = example_fleet(200, seed=1)
    csv = write_fleet_csv(chairs, tmp_path / "fleet.csv")
    argv = ["fleet", str(csv), "--problem", str(problem), "--out", str(tmp_path / "r"), "--no-monte-carlo"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        bare = fleet_recommendations(
            chairs, load_problem(problem).replace(tolerances=None), skus="auto", monte_carlo=False
        )
        assert main([*argv, "--json"]) == 0
        price = json.loads(capsys.readouterr().out)["tolerance_price"]
        assert main(argv) == 0
    assert bare.suggested["count"] == price["without_tolerances"] == 7 < price["with_tolerances"] == 9
    sentence = "The tolerances cost 2 part numbers: 9 with them, 7 without."
    assert price == {"part_numbers": 2, "with_tolerances": 9, "without_tolerances": 7, "sentence": sentence}
    assert json.loads((tmp_path / "r" / "fleet.json").read_text(encoding="utf-8"))["tolerance_price"] == price
    for name in ("report.md", "index.html"):
        assert (tmp_path / "r" / name).read_text(encoding="utf-8").count(sentence) == 1
    assert sentence in " ".join(capsys.readouterr().out.split())


def _design(spec):
    from designer.model import Design

    return Design(trail=spec.trail, diameter=spec.diameter, groove=spec.groove, damping=spec.damping)


def test_fix_ranks_only_fixes_that_hold_at_the_worst_corner_when_tolerances_are_stated():
    """designer.fix on indoor-manual-tolerances (current caster T 1.25 in, d 8 in, plain tyre, bare bearing): every
    ranked fix holds P <= α at the worst corner of [tolerances] (its spec's exact corner, computed for all of them),
    and the same retrofit without [tolerances] ranks first a fix that fails there (the screen changes the answer)."""
    import designer
    from designer.studies.spec import caster_corner

    problem = load_problem(ROOT / "problems" / "indoor-manual-tolerances.toml")
    current = "T=1.25in,d=8in,B=0,c=1.3"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        held = designer.fix(problem, current, specs=100)
        bare = designer.fix(problem.replace(tolerances=None), current, specs=1)
    assert held.fixes
    for f in held.fixes:
        assert f.spec is not None and f.spec.corner["holds"]
    first = bare.fixes[0]
    corner = caster_corner(problem, first.design, float(first.caster.inertia), bool(first.caster.measured))
    assert not corner.holds


def test_fewer_part_numbers_with_the_tolerances_is_said_so_and_the_docs_quote_the_runs():
    """On the 100-chair example (seed 0) the tolerances need one part number fewer (6 against 7: regret counts from
    each chair's best caster that holds), said as such, with the separate run without them giving the 7; the
    sentences docs/inspection.md quotes for this fleet and for the 200-chair example of seed 1 are the program's."""
    problem, result, bare = _fleet_with_and_without(100)
    sentence = "The tolerances need 1 part number fewer: 6 with them, 7 without"
    assert bare.suggested["count"] == result.tolerance_price["without_tolerances"] == 7
    assert result.tolerance_price["part_numbers"] == -1 and result.tolerance_price["sentence"].startswith(sentence)
    docs = " ".join((ROOT / "docs" / "inspection.md").read_text(encoding="utf-8").split())
    assert f'"{sentence}", on `--example 100`' in docs
    assert '"The tolerances cost 2 part numbers: 9 with them, 7 without." on `--example 200 --seed 1`' in docs
    assert "seed-0 example: none, 9 and 9" in docs
