"""Build this caster: on every shipped problem the recommendation is stock, non-dominated among all stock
combinations that meet the risk bound (brute force), and its Monte Carlo P(shimmy) is at most α + 2 SE; the rule's
monotonicity in α and V_target; caps; exit 4; the JSON of `designer run`."""

from __future__ import annotations

import dataclasses
import itertools
import json
import math

import numpy as np
import pytest

import designer
from designer.studies.recommend import recommend
from designer.cli import main
from designer.data.paper import INCH
from designer.errors import InfeasibleError
from designer.model import performance
from designer.physics.inertia import Catalog, Fixed
from designer.physics.uncertainty import Uncertainty
from designer.problem import load_problem

from conftest import PROBLEMS, ROOT

NAMES = [p.stem for p in PROBLEMS]
TEST_SEED = 97531
"""The tests' own Monte Carlo seed (the report uses Uncertainty.seed)."""
TEST_SAMPLES = 120_000


@pytest.fixture(scope="module")
def recs():
    return {p.stem: (load_problem(p), recommend(load_problem(p))) for p in PROBLEMS}


def _brute(problem) -> list[tuple[float, float, tuple, bool]]:
    """Every stock combination (from the problem file's lists and fixed bounds, not from recommend's
    enumeration) with (F_turn, P, design, meets the bound) by model.performance one at a time."""
    s = problem.stock
    b = problem.bounds

    def listed(values, name):
        return list(values) if values is not None else [b[name].low]

    if problem.wheels:
        wheels = [
            (Catalog.from_key(k).fixed_diameter, problem.conditions.replace(inertia=Catalog.from_key(k)))
            for k in problem.wheels
        ]
    elif s.wheels is not None:
        wheels = [
            (
                w.diameter,
                problem.conditions if w.inertia is None else problem.conditions.replace(inertia=Fixed(w.inertia)),
            )
            for w in s.wheels
        ]
    else:
        wheels = [(d, problem.conditions) for d in listed(s.diameters, "diameter")]
    out = []
    for (d, cond), t, g, c in itertools.product(
        wheels, listed(s.trails, "trail"), listed(s.grooves, "groove"), listed(s.dampings, "damping")
    ):
        v = performance(t, d, g, c, cond)
        ok = float(v["confident_speed"]) >= problem.required_speed and d > 2 * cond.threshold_height
        if problem.swept_radius_max is not None:
            ok &= float(v["swept_radius"]) <= problem.swept_radius_max * (1 + 1e-9)
        out.append((float(v["turning_effort"]), float(v["threshold_force"]), (t, d, g, c), bool(ok)))
    return out


def test_every_shipped_problem_has_stock():
    """Every shipped problem declares [stock], and its recommendation's risk bound is on (α = 0.05)."""
    for path in PROBLEMS:
        p = load_problem(path)
        assert p.stock is not None, path.name
        assert p.risk is not None and p.risk.probability == 0.05


@pytest.mark.parametrize("name", NAMES)
def test_recommendation_is_stock_and_nondominated(recs, name):
    """The recommended caster and both alternatives are stock combinations that meet the risk bound, and no
    stock combination that meets it is at least as good on both objectives and better on one; with
    ``[tolerances] enforce = true`` (indoor-manual-tolerances) every combination that would dominate one of them
    fails the bound at its worst corner (the exact law's P there is above α)."""
    from designer.model import Design
    from designer.studies.spec import corner_probabilities

    problem, rec = recs[name]
    enforce = problem.tolerances is not None and problem.tolerances.enforce
    combos = _brute(problem)
    feasible = [c for c in combos if c[3]]
    assert feasible
    for r in [rec, *rec.alternatives]:
        x = r.design.as_array()
        match = [c for c in feasible if np.allclose(c[2], x, rtol=1e-12, atol=1e-15)]
        assert match, (name, r.design)
        f, p = match[0][0], match[0][1]
        assert r.turning_effort == pytest.approx(f, rel=1e-9) and r.threshold_force == pytest.approx(p, rel=1e-9)
        for g, q, y, _ in feasible:
            dominates = (g <= f * (1 - 1e-12) and q <= p * (1 + 1e-12)) or (
                g <= f * (1 + 1e-12) and q < p * (1 - 1e-12)
            )
            if dominates and enforce:
                d = Design(*(float(v) for v in y))
                at = corner_probabilities(problem, [d], [float(problem.conditions.inertia(d.diameter))], [False])[0]
                assert at > problem.risk.probability, (name, r.role, d)
            else:
                assert not dominates, (name, r.role, (g, q), (f, p))
    if enforce:
        return  # the buildable front is that of the casters holding at their worst corner
    # the buildable front is exactly the non-dominated feasible combinations
    pts = sorted({(round(c[0], 9), round(c[1], 9)) for c in feasible}, key=lambda t: (t[1], t[0]))
    front, best = [], math.inf
    for f, p in pts:
        if f < best:
            front.append((f, p))
            best = f
    assert len(rec.buildable) == len(front)


@pytest.mark.parametrize("name", NAMES)
def test_monte_carlo_shimmy_probability_within_alpha(recs, name):
    """P(V_c,true < (1 + margin) V_target) of the recommended caster, by the tests' own Monte Carlo (120 000
    samples at least, seed 97531, SE <= 0.1 pp), is at most α + 2 SE; the reported one has SE <= 0.1 pp."""
    problem, rec = recs[name]
    u = problem.risk
    d = rec.design
    p, se = _mc(
        d.trail,
        rec.inertia,
        d.groove,
        d.damping,
        problem.conditions.slip_coefficient,
        problem.required_speed,
        u,
        samples=TEST_SAMPLES,
        seed=TEST_SEED,
    )
    assert p <= u.probability + 2 * se, (name, p, se)
    assert rec.shimmy_probability_se <= 0.001 + 1e-12 and rec.mc_seed != TEST_SEED
    assert rec.confident_speed >= problem.required_speed


def _indoor(**changes):
    p = load_problem(ROOT / "problems" / "indoor-manual.toml")
    return p.replace(**changes)


@pytest.mark.parametrize(
    "alphas, speeds", [((0.10, 0.05, 0.02, 0.01), (2.5,)), ((0.05,), (2.0, 2.5, 3.0, 3.5)), ((0.2, 0.05), (2.2, 2.8))]
)
def test_tighter_alpha_or_higher_target_never_better_on_both(alphas, speeds):
    """Property: a tighter α or a higher V_target never gives a recommendation that is easier to turn and
    easier over the sill at once (the feasible stock only shrinks and the choice is on the front)."""
    base = _indoor()
    results = {}
    for a in alphas:
        for v in speeds:
            problem = base.replace(
                target_speed=v, conditions=base.conditions.replace(uncertainty=Uncertainty(probability=a))
            )
            try:
                results[(a, v)] = recommend(problem, samples=1000)
            except InfeasibleError:
                results[(a, v)] = None
    for (a1, v1), loose in results.items():
        for (a2, v2), tight in results.items():
            if (a2, v2) == (a1, v1) or a2 > a1 or v2 < v1 or loose is None or tight is None:
                continue
            assert not (tight.turning_effort < loose.turning_effort and tight.threshold_force < loose.threshold_force)


def test_caps_pick_the_best_on_the_other_objective():
    """max_threshold_force = 110 N: least F_turn among buildable casters with P <= 110 N; max_turning_effort
    = 9 N: least P among those with F_turn <= 9 N (brute force)."""
    feasible = [c for c in _brute(_indoor()) if c[3]]
    capped = recommend(_indoor(max_threshold_force=110.0), samples=1000)
    assert capped.threshold_force <= 110.0
    assert capped.turning_effort == pytest.approx(min(c[0] for c in feasible if c[1] <= 110.0), rel=1e-12)
    assert "sill force <= 110.0 N" in capped.rule
    capped = recommend(_indoor(max_turning_effort=9.0), samples=1000)
    assert capped.turning_effort <= 9.0
    assert capped.threshold_force == pytest.approx(min(c[1] for c in feasible if c[0] <= 9.0), rel=1e-12)


def test_no_stock_meets_the_bound_is_exit_4(tmp_path, capsys):
    """A 14 m/s target on indoor-manual (the stock reaches 12.3 m/s at 95 %, the continuous box 15.1 m/s): exit 4,
    one line naming the closest combination and what to relax."""
    from designer.solvers.nlp import max_critical_speed
    from designer.studies.recommend._stock import candidate_table

    path = ROOT / "problems" / "indoor-manual.toml"
    problem = load_problem(path)
    assert candidate_table(problem).values.confident_speed.max() < 14.0 < max_critical_speed(problem)[0]
    assert main(["run", str(path), "--target-speed", "14 m/s", "--no-cross-check"]) == 4
    errors = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("designer: error")]
    assert len(errors) == 1
    assert "closest is T " in errors[0] and "relax" in errors[0] and "robust.probability" in errors[0]


def test_enabled_false_states_the_risk(tmp_path):
    """[robust] enabled = false: the nominal problem; the recommendation says what risk it carries, as a number."""
    text = (ROOT / "problems" / "indoor-manual.toml").read_text() + "\n[robust]\nenabled = false\n"
    path = tmp_path / "nominal.toml"
    path.write_text(text)
    rec = recommend(load_problem(path), samples=20_000)
    assert rec.alpha is None
    assert f"{rec.shimmy_probability:.1%}" in rec.note and "no risk bound" in rec.note
    assert rec.critical_speed >= 2.5


def test_continuous_rest_is_solved_exactly():
    """Trail left out of [stock]: each (d, B, c_f) part gets its best trail (NLP); no trail on a fine grid
    does better with the same parts."""
    base = _indoor()
    stock = base.stock.__class__(diameters=(5 * INCH, 7 * INCH), grooves=(0.0, 0.5 * INCH), dampings=(1.3,))
    problem = base.replace(stock=stock)
    rec = recommend(problem, samples=1000)
    trails = np.linspace(problem.bounds["trail"].low, problem.bounds["trail"].high, 3001)
    for r in [rec, *rec.alternatives]:
        d = r.design
        v = performance(trails, d.diameter, d.groove, d.damping, problem.conditions)
        ok = (v["confident_speed"] >= problem.required_speed) & (v["swept_radius"] <= problem.swept_radius_max)
        assert r.turning_effort <= v["turning_effort"][ok].min() * (1 + 1e-7)


def test_designer_recommend_and_run_json(capsys):
    """designer.recommend is the package's name; `designer run --json` keeps design/objectives/sensitivities/
    cross_check and adds recommendation, alternatives and weights; the recommendation alone carries risk and spec,
    every design record its extrapolated flag (true exactly when d lies outside Table 1's 4–8 in)."""
    assert designer.recommend is recommend
    path = ROOT / "problems" / "sports-court.toml"
    assert main(["run", str(path), "--json", "--no-cross-check"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"design", "objectives", "sensitivities", "cross_check", "recommendation", "alternatives", "weights"} <= set(
        out
    )
    r = out["recommendation"]
    assert set(r["design"]) == {"trail", "diameter", "groove", "damping"}
    assert {
        "turning_effort",
        "threshold_force",
        "critical_speed",
        "shimmy_probability",
        "shimmy_probability_se",
        "rule",
    } <= set(r)
    assert out["weights"] == [1.0, 1.0]
    assert {"risk", "spec", "extrapolated", "measured"} <= set(r)
    only = {"role", "risk", "if_measured"}  # the recommendation's own records (alternatives carry a spec too)
    assert all(set(a) >= set(r) - only and not only - {"role"} & set(a) for a in out["alternatives"])
    for a in [r, *out["alternatives"]]:
        assert a["extrapolated"] is not (4 * INCH - 1e-9 <= a["design"]["diameter"] <= 8 * INCH + 1e-9)


def test_front_csv_gains_buildable_rows(recs, tmp_path):
    """front.csv with the buildable front: its rows are added with buildable = true, the front's are false."""
    import csv

    from designer.studies.front import Front

    problem, rec = recs["indoor-manual"]
    front = Front(problem, rec.buildable.points[:1], [], {})  # any front: the rows' origin is what is tested
    front.to_csv(tmp_path / "front.csv", buildable=rec.buildable)
    rows = list(csv.DictReader(open(tmp_path / "front.csv")))
    assert [r["buildable"] for r in rows] == ["false"] + ["true"] * len(rec.buildable)
    assert float(rows[1]["turning_effort_N"]) == pytest.approx(rec.buildable.points[0].turning_effort, rel=1e-9)


def _mc(*args, **kwargs) -> tuple[float, float]:
    """The model's Monte Carlo P(shimmy) and SE of one caster, as floats."""
    from designer.model import shimmy_probability

    p, se = shimmy_probability(*args, **kwargs)
    return float(p), float(se)


# --------------------------------------------------------------------------- the risk law's records


def test_recommendation_risk_spec_and_if_measured(recs):
    """indoor-manual: the recommendation carries its risk (the reported P ± SE, the law's sources with shares that
    add up to 1), confirmed by a Monte Carlo of the same law with a seed of this test's own (P <= α + 2 SE, the
    wheel known by its diameter); its spec (M_f = c_f θ0; at max_inertia the exact law with a measured wheel's
    scatter gives α to 0.5 pp, and P rises through α there); and what measuring the wheel allows (never worse
    in J, its own risk within α + 2 SE as a measured wheel at its power-law value; the headline names the force
    that rises as well as the one that falls, shown on sports-court where one does)."""
    from designer.model import design_columns, evaluate, shimmy_probability
    from designer.physics.uncertainty import shimmy_probability_exact

    problem, rec = recs["indoor-manual"]
    d = rec.design
    c = problem.conditions
    assert not rec.measured and not rec.extrapolated
    risk = rec.risk
    assert (risk["probability"], risk["monte_carlo"], risk["se"]) == (
        rec.shimmy_probability,
        rec.shimmy_probability_mc,
        rec.shimmy_probability_se,
    )
    assert sum(s["share"] for s in risk["sources"]) == pytest.approx(1.0, abs=1e-12)
    assert [s["kind"] for s in risk["sources"]] == ["data", "data", "assumed", "assumed"]
    p, se = shimmy_probability(
        d.trail,
        rec.inertia,
        d.groove,
        d.damping,
        c.slip_coefficient,
        problem.target_speed,
        problem.risk,
        samples=200_000,
        seed=31337,
        diameter=d.diameter,
    )
    assert float(p) <= problem.risk.probability + 2 * float(se)
    spec = rec.spec
    assert spec.friction_moment == pytest.approx(d.damping * math.radians(20), rel=1e-12)
    assert (spec.trail, spec.diameter, spec.groove) == (d.trail, d.diameter, d.groove)
    top = spec.limit("wheel_inertia", "max").value
    args = (d.trail, top, d.groove, d.damping, c.slip_coefficient, problem.required_speed, problem.risk)
    assert abs(shimmy_probability_exact(*args) - problem.risk.probability) <= 0.005
    below = shimmy_probability_exact(d.trail, 0.9 * top, *args[2:])
    above = shimmy_probability_exact(d.trail, 1.1 * top, *args[2:])
    assert below < problem.risk.probability < above
    m = rec.if_measured
    w = problem.weights
    assert w[0] * m["turning_effort"] + w[1] * m["threshold_force"] <= (
        w[0] * rec.turning_effort + w[1] * rec.threshold_force
    ) * (1 + 1e-12)
    assert m["saves_threshold_force"] == pytest.approx(rec.threshold_force - m["threshold_force"], abs=1e-12)
    md = designer.Design(**m["design"])
    v = evaluate(
        design_columns(md),
        c,
        inertia=m["inertia"],
        measured=True,
        required_speed=problem.required_speed,
        risk=problem.target_speed,
        seed=4711,
    )
    assert v.feasible[0] and float(v.inertia[0]) == pytest.approx(float(c.inertia(md.diameter)), rel=1e-12)
    assert float(v.shimmy_probability[0]) <= problem.risk.probability + 2 * float(v.shimmy_probability_se[0])
    assert "If you measure the wheel: a 7 in wheel measured at or under 0.00117 kg·m²" in rec.headline()
    # here the measured wheel keeps the 7 in diameter (the sill force) and saves turning effort with less groove
    assert m["saves_threshold_force"] == 0 < m["saves_turning_effort"]
    assert f"{m['saves_turning_effort']:.2g} N easier to turn" in rec.headline()
    # the sentence states a cost as plainly as a saving: for sports-court the sill force falls and the turning
    # effort rises
    _, court = recs["sports-court"]
    m = court.if_measured
    assert m["saves_threshold_force"] > 0 > m["saves_turning_effort"]
    assert f"{m['saves_threshold_force']:.2g} N easier over the sill" in court.headline()
    assert f"{-m['saves_turning_effort']:.2g} N harder to turn" in court.headline()


def test_stock_with_measured_inertias_gets_the_measured_scatter(tmp_path):
    """[stock] wheels listed with their inertia are measured wheels (the measurement's σ 0.05 in the bound), a
    wheel listed without one is known by its diameter (Table 1's prediction interval): the screen's speed
    reached with probability 95 % is the physics layer's bound of each kind."""
    from designer.physics.uncertainty import shimmy_speed_quantile
    from designer.studies.recommend._stock import candidate_table

    text = (ROOT / "problems" / "indoor-manual.toml").read_text()
    text = text.replace('diameters = ["3 in", "4 in", "5 in", "6 in", "7 in", "8 in"]\n', "")
    text = text.replace(
        'grooves = ["0 in",',
        'wheels = [{ name = "M7", diameter = "7 in", inertia = "0.0011 kg*m**2" }, { name = "U6", diameter = "6 in" }]\n'
        'grooves = ["0 in",',
    )
    path = tmp_path / "mixed.toml"
    path.write_text(text)
    problem = load_problem(path)
    table = candidate_table(problem)
    cand, v = table.candidates, table.values
    assert set(cand.wheel) == {"M7", "U6"}
    assert np.array_equal(cand.measured, cand.wheel == "M7")
    c = problem.conditions
    for j in (int(np.flatnonzero(cand.wheel == "M7")[3]), int(np.flatnonzero(cand.wheel == "U6")[3])):
        measured = bool(cand.measured[j])
        q = shimmy_speed_quantile(
            cand.trail[j],
            cand.inertia[j],
            cand.groove[j],
            cand.damping[j],
            c.slip_coefficient,
            problem.risk,
            diameter=None if measured else cand.diameter[j],
        )
        assert v.confident_speed[j] == pytest.approx(float(q), rel=1e-12)
    assert cand.inertia[cand.wheel == "M7"][0] == 0.0011


def test_mixed_catalogue_recommendation_is_non_dominated(tmp_path):
    """On a catalogue mixing a measured and an unmeasured wheel, the recommendation is non-dominated in (F_turn, P)
    among the stock combinations that meet the same risk law's bound (the screen's feasible rows)."""
    from designer.studies.recommend._stock import candidate_table

    text = (ROOT / "problems" / "indoor-manual.toml").read_text()
    text = text.replace('diameters = ["3 in", "4 in", "5 in", "6 in", "7 in", "8 in"]\n', "")
    text = text.replace(
        'grooves = ["0 in",',
        'wheels = [{ name = "M7", diameter = "7 in", inertia = "0.0011 kg*m**2" }, { name = "U6", diameter = "6 in" },'
        ' { name = "U8", diameter = "8 in" }]\ngrooves = ["0 in",',
    )
    path = tmp_path / "mixed.toml"
    path.write_text(text)
    problem = load_problem(path)
    rec = recommend(problem, samples=20_000)
    v = candidate_table(problem).values
    ok = v.feasible
    f, p = v.turning_effort[ok], v.threshold_force[ok]
    dominated = (
        (f <= rec.turning_effort)
        & (p <= rec.threshold_force)
        & ((f < rec.turning_effort * (1 - 1e-12)) | (p < rec.threshold_force * (1 - 1e-12)))
    )
    assert not dominated.any()
    assert rec.if_measured is not None


def test_rule_takes_the_least_j_end_when_no_point_bulges_toward_the_ideal(recs):
    """The knee is the point farthest from the ends' chord on the ideal side.  A three-point front whose middle
    point lies beyond the chord (indoor-manual's buildable front: 5 in plain 7.01 N / 133.5 N, 6 in 7.63 / 118.1,
    7 in 7.94 / 107.0) has no knee: the rule takes the end with the least J = F_turn + P (the 7 in wheel, J 114.9
    against 140.5), not the end a tie in distance happens to give; a middle point inside the chord is the knee."""
    from designer.studies.recommend import select_rows

    f = np.array([[7.008, 7.631, 7.942]])
    p = np.array([[133.5, 118.07, 106.96]])
    sel = select_rows(f, p, np.ones_like(f, bool))
    assert int(sel["choice"][0]) == 2 and not bool(sel["knee"][0])
    f_convex = np.array([[3.54, 3.86, 23.38]])  # sports-court's buildable front: its middle point is the knee
    p_convex = np.array([[59.7, 49.8, 43.6]])
    sel = select_rows(f_convex, p_convex, np.ones_like(f_convex, bool))
    assert int(sel["choice"][0]) == 1 and bool(sel["knee"][0])
    problem, rec = recs["indoor-manual"]
    # stated to 2 decimals: each within half a unit of the 2nd decimal (not a rounding of the solver's last digits)
    assert [x.turning_effort for x in rec.buildable.points] == pytest.approx([7.01, 7.63, 7.94], abs=5e-3)
    assert rec.design.diameter == pytest.approx(7 * INCH) and rec.rule.startswith("least J = 1 F_turn + 1 P")
    assert "no knee" in rec.rule and recs["sports-court"][1].rule == "knee of the buildable risk-bounded front"


def test_alternatives_without_their_specs_keep_every_number(recs):
    """recommend(..., specs="recommended") leaves the alternatives' spec None and changes nothing else: every key
    of each alternative's JSON record but ``spec`` equal (the casters, roles, forces, the exact P(shimmy) and the
    Monte Carlo beside it), and the recommended caster's spec as with every spec."""
    problem, full = recs["indoor-manual"]
    light = recommend(problem, specs="recommended")
    assert light.spec is not None and light.spec.to_dict() == full.spec.to_dict()
    assert len(light.alternatives) == len(full.alternatives) >= 2
    for a, b in zip(light.alternatives, full.alternatives):
        assert a.spec is None and b.spec is not None
        assert "spec" not in a.to_dict() and "spec" in b.to_dict()
        assert {k: v for k, v in b.to_dict().items() if k != "spec"} == a.to_dict()


@pytest.mark.parametrize("name", ["indoor-manual", "catalog-retrofit"])
def test_a_spec_added_afterwards_is_the_one_recommend_gives(recs, name):
    """recommend(..., specs="none") (the studio at each key press) then with_spec (the studio a moment later)
    give exactly the recommendation and spec of recommend(problem): every number of the JSON record equal, not
    just close; the alternatives keep no spec; a bad ``specs`` is refused."""
    from designer.errors import InputError
    from designer.studies.recommend import with_spec

    problem, full = recs[name]
    bare = recommend(problem, specs="none")
    assert bare.spec is None and all(a.spec is None for a in bare.alternatives)
    assert bare.shimmy_probability == full.shimmy_probability
    later = with_spec(bare)
    assert later.spec is not None and later.spec.to_dict() == full.spec.to_dict()
    assert later.to_dict() == full.to_dict()
    assert with_spec(later) is later
    with pytest.raises(InputError, match="specs='some'"):
        recommend(problem, specs="some")


@pytest.mark.parametrize("name", ["indoor-manual", "catalog-retrofit"])
def test_without_if_measured_only_that_variant_is_left_out(recs, name):
    """recommend(..., if_measured=False) (the studio, which does not show the variant) gives the same record,
    every number equal, with ``if_measured`` None."""
    problem, full = recs[name]
    bare = recommend(problem, specs="none", if_measured=False)
    assert bare.if_measured is None
    same = recommend(problem, specs="none")
    assert {k: v for k, v in bare.to_dict().items() if k != "if_measured"} == {
        k: v for k, v in same.to_dict().items() if k != "if_measured"
    }
    assert dataclasses.replace(bare, if_measured=same.if_measured).to_dict() == same.to_dict()


def test_each_records_risk_is_its_casters_alone(recs):
    """The records' exact P(shimmy) and Monte Carlo P ± SE, found for all of them in one batch, are each caster's
    own: the exact law of that caster alone (to 1e-12) and the Monte Carlo of evaluate() of that caster alone
    (the same number)."""
    from designer.model import evaluate, scatter_of
    from designer.studies.spec import exact_shimmy_probability

    problem, full = recs["indoor-manual"]
    conditions = problem.conditions.replace(uncertainty=scatter_of(problem.conditions))
    for r in [full, *full.alternatives]:
        alone = evaluate([r.design], conditions, inertia=[r.inertia], measured=[r.measured], risk=problem.target_speed)
        assert (r.shimmy_probability_mc, r.shimmy_probability_se) == (
            float(alone.shimmy_probability[0]),
            float(alone.shimmy_probability_se[0]),
        )
        p = exact_shimmy_probability(problem, r.design, r.inertia, r.measured, problem.target_speed)
        assert r.shimmy_probability == pytest.approx(p, rel=1e-12, abs=0) and 0 < p < 1
