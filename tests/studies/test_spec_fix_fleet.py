"""The spec of every retrofit fix and every fleet part number: P(shimmy) exact with the Monte Carlo beside it,
the acceptance limits where the exact law crosses α, the JSON keys with their units; and the inspection sheet's
sentence on ``[tolerances] enforce``."""

from __future__ import annotations

import dataclasses
import json
import math
import warnings

import numpy as np
import pytest

from conftest import ROOT
from designer.cli import main
from designer.jsonsafe import finite
from designer.model import Design, evaluate
from designer.parameters import PARAMETERS
from designer.physics.acceptance import LIMIT_RTOL
from designer.problem import load_problem
from designer.studies.fleet import example_fleet, fleet_data, fleet_recommendations
from designer.studies.retrofit import fix

DEFAULT = ROOT / "problems" / "indoor-manual.toml"
EXAMPLE = "T=1.5in,d=7.75in,B=0.5625in,c=1.3"
"""The shipped retrofit example (docs/retrofit.md): indoor-manual's caster with a measured 0.00127 kg·m² wheel."""

MC_DRAWS = 200_000
"""Draws of this test's own Monte Carlo per caster (SE 0.05 percentage point at P = 5 %)."""

MC_SEED = 424_242
"""This test's own seed (not the reported Monte Carlo's 20111)."""


def null_se(p: float, n: int) -> float:
    """The standard error of a Monte Carlo of ``n`` draws if the exact P ``p`` is the truth: sqrt(p (1 − p)/n)
    (the estimate's own SE, from its p̂, understates it when only a few draws shimmy)."""
    return math.sqrt(p * (1 - p) / n)


KEYS = {"trail_min", "trail_max", "groove_min", "friction_moment_min", "wheel_inertia_max"}
"""The limits' keys: the part and the side."""


@pytest.fixture(scope="module")
def problem():
    return load_problem(DEFAULT)


@pytest.fixture(scope="module")
def example(problem):
    """Every fix of the shipped example, within the limits and beyond them (all found)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return fix(problem, EXAMPLE, inertia=0.00127)


@pytest.fixture(scope="module")
def fleet_example(problem):
    """The shipped fleet example (``designer fleet --example 500``) with its suggested part numbers."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return fleet_recommendations(example_fleet(500), problem, skus="auto")


def test_every_fix_exact_and_an_independent_monte_carlo_agree(problem, example):
    """Every fix of the shipped retrofit example (and the caster as it is): the exact P(shimmy) it reports agrees
    within 3 SE with a Monte Carlo of its own seed and 200 000 draws (the model's evaluator, every fix at once),
    and with the Monte Carlo the record carries beside it (its draws and seed said); the SE is the Monte Carlo's
    at the exact P (:func:`null_se`)."""
    states = [example.current, *example.fixes, *example.beyond]
    assert len(example.fixes) == example.found and len(example.beyond) == example.found_beyond > 0
    designs = {k: np.array([getattr(s.design, k) for s in states]) for k in ("trail", "diameter", "groove", "damping")}
    mc = evaluate(
        designs,
        problem.conditions,
        inertia=np.array([s.inertia for s in states]),
        measured=np.array([s.measured for s in states]),
        risk=problem.target_speed,
        samples=MC_DRAWS,
        seed=MC_SEED,
        target_se=None,
    )
    for k, s in enumerate(states):
        p = float(mc.shimmy_probability[k])
        assert abs(s.shimmy_probability - p) <= 3 * null_se(s.shimmy_probability, MC_DRAWS), (k, s, p)
        assert s.mc_seed == 20111 and s.mc_samples >= 50_000
        assert abs(s.shimmy_probability - s.shimmy_probability_mc) <= 3 * null_se(s.shimmy_probability, s.mc_samples)
        assert s.shimmy_probability_se == pytest.approx(
            math.sqrt(s.shimmy_probability_mc * (1 - s.shimmy_probability_mc) / s.mc_samples), rel=1e-9
        )
    assert example.current.spec is None
    spec = example.fixes[0].spec
    assert spec.probability == example.fixes[0].shimmy_probability
    assert (spec.mc_probability, spec.mc_se, spec.mc_seed) == (
        example.fixes[0].shimmy_probability_mc,
        example.fixes[0].shimmy_probability_se,
        20111,
    )


def test_every_part_number_exact_and_an_independent_monte_carlo_agree(problem, fleet_example):
    """Every part number of the shipped fleet example: its spec's exact P(shimmy) (at the fastest V_target of the
    chairs it serves) agrees within 3 SE with a Monte Carlo of this test's own seed and 200 000 draws, and with
    the Monte Carlo it carries (its draws and seed said; the SE: the Monte Carlo's at the exact P); its trail's
    largest is the smallest swept-radius limit of those chairs."""
    result = fleet_example
    assert len(result.specs) == len(result.skus.chosen) >= 2
    feasible = np.flatnonzero(result.feasible)
    for spec, j in zip(result.specs, result.skus.chosen):
        mine = feasible[result.skus.assignment == j]
        assert spec.target_speed == pytest.approx(float(result.fleet.target_speed[mine].max()), rel=1e-12)
        assert spec.limit("trail", "max").value == pytest.approx(
            float(result.fleet.swept_radius_max[mine].min()) - spec.diameter / 2, rel=1e-12
        )
        mc = evaluate(
            Design(spec.trail, spec.diameter, spec.groove, spec.damping),
            problem.conditions,
            inertia=spec.inertia,
            measured=spec.measured,
            risk=spec.target_speed,
            samples=MC_DRAWS,
            seed=MC_SEED,
            target_se=None,
        )
        assert abs(spec.probability - mc.shimmy_probability) <= 3 * null_se(spec.probability, MC_DRAWS)
        assert spec.mc_seed == 20111 and spec.mc_samples >= 50_000
        assert abs(spec.probability - spec.mc_probability) <= 3 * null_se(spec.probability, spec.mc_samples)


def _probability(problem, fix_state, law, stem_angle, factor, **changes):
    """P(V_c,true < V_req) of a fix with some parts changed, by the model's evaluator (exact law, 32 nodes)."""
    inertia = changes.pop("inertia", fix_state.inertia)
    measured = changes.pop("measured", fix_state.measured)
    design = dataclasses.replace(fix_state.design, **changes)
    caster = evaluate(
        [design],
        problem.conditions.replace(uncertainty=law),
        inertia=[inertia],
        measured=[measured],
        stem_angle=stem_angle,
        calibration=factor,
        risk=problem.required_speed,
        exact=True,
    )
    return float(caster.shimmy_probability[0])


def test_at_each_limit_of_a_calibrated_tilted_fix_the_exact_law_gives_alpha(problem):
    """The top fix of the 8 in caster on a stem tilted 4° that shimmied at 1.2 m/s (calibrated law, effective
    trail): at each risk limit, the other parts at nominal, the model's evaluator (exact law, 32 nodes, computed
    on its own effective trail and calibration) gives P = α within what the root's precision allows: the change
    of P over the root's tolerance 2 (xtol + rtol |x|) (bracketed_root; xtol = LIMIT_RTOL × the range's top),
    or over I_w e^±1e−10 (the inertia's Newton step), plus 1e-12 for 16 against 32 quadrature nodes; and P 1 %
    beyond each limit is above α, 1 % inside below."""
    angle = math.radians(4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        result = fix(problem, "T=1.25in,d=8in,B=0,c=1.3", stem_angle=angle, shimmied_at=1.2, limit=1)
    best, k = result.fixes[0], result.calibration.factor
    spec = best.spec
    law = dataclasses.replace(problem.risk, model_error=result.calibration.scatter, model_error_dof=0)
    alpha = law.probability
    assert spec.stem_angle == angle and spec.calibration == k and spec.alpha == alpha
    theta0 = problem.conditions.disturbance_angle

    def p_at(part: str, value: float) -> float:
        if part == "inertia":
            return _probability(problem, best, law, angle, k, inertia=value, measured=True)
        return _probability(problem, best, law, angle, k, **{part: value})

    for part, name, side, scale in (
        ("trail", "trail", "min", 1.0),
        ("groove", "groove", "min", 1.0),
        ("damping", "friction_moment", "min", theta0),
        ("inertia", "wheel_inertia", "max", 1.0),
    ):
        x = spec.limit(name, side).value / scale
        if part == "inertia":
            lo, hi = x * math.exp(-1e-10), x * math.exp(1e-10)
        else:
            delta = 2 * (LIMIT_RTOL * PARAMETERS[part].range[1] + LIMIT_RTOL * abs(x))
            lo, hi = x - delta, x + delta
        allowed = abs(p_at(part, hi) - p_at(part, lo)) / 2 + 1e-12
        assert abs(p_at(part, x) - alpha) <= allowed, (name, p_at(part, x), allowed)
        worse, better = (0.99 * x, 1.01 * x) if side == "min" else (1.01 * x, 0.99 * x)
        assert p_at(part, worse) > alpha > p_at(part, better), name
    assert spec.limit("trail", "max").value == pytest.approx(problem.swept_radius_max - best.design.diameter / 2)


def test_fix_json_carries_exact_p_the_monte_carlo_and_the_limits_with_units(capsys):
    """``designer fix --json``: every fix has P(shimmy) (exact), the Monte Carlo beside it (P, SE, draws, seed)
    and its spec: limits by part and side in SI with a ``units`` entry beside them; the keys of before are kept."""
    assert main(["fix", str(DEFAULT), "--current", EXAMPLE, "--inertia", "0.00127", "--top", "3", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for f in data["fixes"] + data["fixes_beyond_limit"]:
        for key in ("shimmy_probability", "shimmy_probability_mc", "shimmy_probability_se", "mc_samples", "mc_seed"):
            assert isinstance(f[key], (int, float)), key
        for key in ("design", "objectives", "changes", "cost", "parts_cost", "within_limit", "confident_speed"):
            assert key in f
        spec = f["spec"]
        assert set(spec["limits"]) == KEYS and {spec["units"][k] for k in KEYS} == {"m", "N·m", "kg·m²"}
        assert spec["units"]["trail_min"] == "m" and spec["units"]["wheel_inertia_max"] == "kg·m²"
        assert spec["shimmy_probability"]["exact"] == f["shimmy_probability"]
        assert spec["limits"]["trail_min"] < f["design"]["trail"] <= spec["limits"]["trail_max"] + 1e-12
    assert "shimmy_probability_mc" in data["current"] and "spec" not in data["current"]


def test_fleet_json_carries_each_part_numbers_limits_with_units(fleet_example):
    """fleet.json: each part number's ``spec`` (limits by part and side in SI, ``units`` beside them, P exact with
    the Monte Carlo, its draws and seed); each row the part number's P exact with its Monte Carlo and SE."""
    data = json.loads(json.dumps(finite(fleet_data(fleet_example))))
    for sku in data["skus"]:
        spec = sku["spec"]
        assert set(spec["limits"]) == KEYS and all(spec["units"][k] for k in KEYS)
        assert spec["units"]["friction_moment_min"] == "N·m"
        assert set(spec["shimmy_probability"]) >= {"exact", "monte_carlo", "monte_carlo_se", "monte_carlo_samples"}
    row = next(r for r in data["rows"] if r["status"] == "ok")
    assert {"sku_shimmy_probability", "sku_shimmy_probability_mc", "sku_shimmy_probability_se"} <= set(row)


def test_the_sheet_says_how_the_caster_was_chosen_against_its_tolerances():
    """The inspection sheet states ``[tolerances] enforce`` in a sentence: chosen among the casters that hold at
    their worst corner (the tolerances problem, enforce = true), or at nominal when no tolerances are given."""
    from designer.report.sheet import enforce_sentence
    from designer.studies.recommend import recommend

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        plain = recommend(load_problem(DEFAULT))
        toleranced = recommend(load_problem(ROOT / "problems" / "indoor-manual-tolerances.toml"))
        relaxed = recommend(
            load_problem(ROOT / "problems" / "indoor-manual-tolerances.toml").replace(
                tolerances=dataclasses.replace(toleranced.problem.tolerances, enforce=False)
            )
        )
    assert enforce_sentence(plain).startswith("Chosen at nominal: the problem gives no [tolerances]")
    assert enforce_sentence(toleranced).startswith("Chosen among the casters that hold the bound at their worst")
    assert enforce_sentence(relaxed).startswith("[tolerances] enforce = false: the caster was chosen at nominal")


def test_the_enforce_sentence_states_the_problems_own_bound(tmp_path):
    """The sentence on [tolerances] enforce compares the worst corner with the problem's α, whether or not the
    recommendation carries its spec (the studio asks for none at first): with [robust] probability = 0.03 it
    says "above 3%", never the default 5%, and the same words with and without the spec."""
    from designer.problem import load_problem
    from designer.studies.recommend import recommend

    text = (ROOT / "problems" / "indoor-manual-tolerances.toml").read_text(encoding="utf-8")
    path = tmp_path / "alpha-3.toml"
    path.write_text(text + "\n[robust]\nprobability = 0.03\n", encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        problem = load_problem(path)
        full, bare = recommend(problem), recommend(problem, specs="none")
    assert full.alpha == 0.03 and bare.spec is None
    assert "above 3%" in full.enforced_sentence() and "5%" not in full.enforced_sentence()
    assert bare.enforced_sentence() == full.enforced_sentence()
