"""Product lines (`designer fleet`): the fleet table, the vectorised per-chair recommendation, the exact
K-median of part numbers, and the Dask path on a 2-worker LocalCluster."""

from __future__ import annotations

import html
import itertools
import csv
import json
import math
import pickle
import re

import numpy as np

from designer.physics.acceptance import LawCaster, exact_probability
import pytest

import designer
from designer.studies.fleet import _fleet, _rule, _table
from designer.units import written_size
from designer.studies.fleet import _kmedian
from designer.studies.fleet._kmedian import kmedian_curve, solve_kmedian
from designer.cli import main
from designer.data.paper import INCH
from designer.model import performance, scatter_of


def brute_force_kmedian(cost: np.ndarray, weights: np.ndarray, k: int) -> tuple[float, tuple[int, ...]]:
    """Enumerate every k-subset of columns; (least weighted regret, its columns) with every row served.

    The tests' exact reference: C(n, k) subsets, so only for small n (12 candidates and k = 3 is 220 subsets).
    """
    cost = np.asarray(cost, float)
    best: tuple[float, tuple[int, ...]] = (math.inf, ())
    for subset in itertools.combinations(range(cost.shape[1]), k):
        values = cost[:, list(subset)].min(axis=1)
        if np.all(np.isfinite(values)):
            total = float(np.dot(weights, values))
            if total < best[0] - 1e-12:
                best = (total, subset)
    return best


GOOD = """name,load_N,threshold_height_in,target_speed_m/s,swept_radius_max_in,surface,turning_mode,count
a,178,0.5,2.5,6,tile,chair,10
b,200,0.25,2.0,7,carpet,pivot,3
"""


@pytest.fixture(scope="module")
def base(root):
    return designer.load_problem(root / "problems" / "indoor-manual.toml")


@pytest.fixture(scope="module")
def fleet1000():
    return _table.example_fleet(1000, seed=3)


def test_units_in_header_and_cells_agree():
    """The same chairs with units in the header, in the cells, and in SI read to the same SI numbers."""
    header = _table.fleet_from_text(GOOD)
    cells = _table.fleet_from_text(
        "name,load,threshold_height,target_speed,swept_radius_max,surface,turning_mode,count\n"
        "a,178 N,0.5 in,2.5 m/s,6 in,tile,chair,10\n"
        "b,200 N,6.35 mm,7.2 km/h,7 in,carpet,pivot,3\n"
    )
    brackets = _table.fleet_from_text(
        "name,load [lbf],threshold_height (mm),target_speed_mps,swept_radius_max [in],surface,turning_mode\n"
        "a,40.0158,12.7,2.5,6,tile,chair\nb,44.9616,6.35,2.0,7,carpet,pivot\n"
    )
    for other in (cells, brackets):
        np.testing.assert_allclose(other.load, header.load, rtol=1e-5)
        np.testing.assert_allclose(other.threshold_height, [0.5 * INCH, 0.25 * INCH], rtol=1e-12)
        np.testing.assert_allclose(other.target_speed, [2.5, 2.0], rtol=1e-12)
        np.testing.assert_allclose(other.swept_radius_max, [6 * INCH, 7 * INCH], rtol=1e-12)
    assert list(header.count) == [10, 3]
    assert list(brackets.count) == [1, 1]  # no count column: every chair weighs 1


def test_mass_and_front_fraction_give_the_load_per_caster():
    """A row may give mass and front_fraction instead of load: L = m g f / 2 (another row keeps its load)."""
    f = _table.fleet_from_text(
        "name,load_N,mass_kg,front_fraction,threshold_height_in,target_speed,swept_radius_max_in,surface,turning_mode\n"
        "a,,100,0.4,0.5,2.5,6,tile,chair\nb,150,,,0.5,2.5,6,tile,chair\nc,,90,35 %,0.5,2.5,6,tile,chair\n"
    )
    assert f.load[0] == pytest.approx(100 * 9.80665 * 0.4 / 2, rel=1e-12)
    assert f.load[1] == 150
    assert f.load[2] == pytest.approx(90 * 9.80665 * 0.35 / 2, rel=1e-12)


BAD = [
    (
        "name,load_N,threshold_heigth_in,target_speed,swept_radius_max_in,surface,turning_mode\n"
        "a,178,0.5,2.5,6,tile,chair\n",
        ["column 'threshold_heigth_in'", "did you mean 'threshold_height'"],
    ),
    (
        "name,load_N,target_speed,swept_radius_max_in,surface,turning_mode\na,178,2.5,6,tile,chair\n",
        ["missing column 'threshold_height'"],
    ),
    (
        "name,lod_N,threshold_height_in,target_speed,swept_radius_max_in,surface,turning_mode\n"
        "a,178,0.5,2.5,6,tile,chair\n",
        ["did you mean 'load'"],
    ),
    (
        "name,load_in,threshold_height_in,target_speed,swept_radius_max_in,surface,turning_mode\n"
        "a,178,0.5,2.5,6,tile,chair\n",
        ["column load", "wrong dimension", "force"],
    ),
    (GOOD.replace("a,178,0.5", "a,178 kg,0.5"), ["row 2, column load", "wrong dimension"]),
    (GOOD.replace("b,200", "a,200"), ["row 3, column name = 'a'", "duplicate", "first at row 2"]),
    (
        GOOD.replace("a,178,0.5,2.5,6", "a,178,0.5,2.5,600"),
        ["row 2, column swept_radius_max", "outside the model's range"],
    ),
    (GOOD.replace("a,178,0.5", "a,,0.5"), ["row 2, column load", "empty"]),
    (GOOD.replace("carpet,pivot", "carpt,pivot"), ["row 3, column surface = 'carpt'", "did you mean 'carpet'"]),
    (GOOD.replace(",10\n", ",2.5\n"), ["row 2, column count"]),
    (GOOD.replace("name,load_N", "name,mass_kg"), ["missing column 'front_fraction'"]),
]


@pytest.mark.parametrize("text, expected", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_fleet_input_is_one_line_naming_row_and_column(tmp_path, capsys, text, expected):
    """Each bad fleet gives exit 3 and one line on stderr naming the row and column (or the missing column)."""
    path = tmp_path / "fleet.csv"
    path.write_text(text)
    code = main(["fleet", str(path), "--no-monte-carlo", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 3, err
    assert len(err.splitlines()) == 1
    for piece in expected:
        assert piece in err, err
    assert not (tmp_path / "out").exists()


def test_skus_larger_than_the_stock_is_exit_2(tmp_path, capsys, root):
    """--skus K above the number of stock casters: exit 2 naming the option and the stock size."""
    path = tmp_path / "fleet.csv"
    path.write_text(GOOD)
    code = main(
        [
            "fleet",
            str(path),
            "--skus",
            "10000",
            "--no-monte-carlo",
            "--problem",
            str(root / "problems" / "indoor-manual.toml"),
            "--out",
            str(tmp_path / "out"),
        ]
    )
    errors = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("designer: error")]
    assert code == 2 and len(errors) == 1 and "--skus 10000: larger than the stock (630 casters)" in errors[0]


def test_example_fleet_stays_in_its_stated_ranges_and_reads_back(tmp_path):
    """--example N: loads 120–300 N, sills 0.25–0.75 in, clearance 5–8 in, speeds 1.5–3.5 m/s; the CSV reads back."""
    f = _table.example_fleet(500, seed=1)
    assert 120 <= f.load.min() and f.load.max() <= 300 and f.load.max() - f.load.min() > 150
    assert 0.25 * INCH <= f.threshold_height.min() and f.threshold_height.max() <= 0.75 * INCH
    assert 5 * INCH <= f.swept_radius_max.min() and f.swept_radius_max.max() <= 8 * INCH
    assert 1.5 <= f.target_speed.min() and f.target_speed.max() <= 3.5
    assert set(f.surface) == {"tile", "carpet"} and set(f.turning_mode) == {"chair", "pivot"}
    back = _table.read_fleet(_table.write_fleet_csv(f, tmp_path / "f.csv"))
    assert back.names == f.names
    np.testing.assert_allclose(back.load, f.load, rtol=1e-12)
    np.testing.assert_allclose(back.threshold_height, f.threshold_height, rtol=1e-9)
    np.testing.assert_array_equal(back.count, f.count)
    assert set(_table.EXAMPLE_RANGES) >= {"load", "threshold_height", "swept_radius_max", "target_speed"}


def _reference_choice(problem, stock, chair: dict) -> tuple[int, int]:
    """Scalar reference for one chair: loop over the stock with model.performance, the front, the knee."""
    c = problem.conditions.replace(
        load=chair["load"],
        threshold_height=chair["threshold_height"],
        surface=chair["surface"],
        turning_mode=chair["turning_mode"],
    )
    pts = []
    for j in range(len(stock)):
        d = stock.design(j)
        if d["diameter"] <= 2 * chair["threshold_height"]:
            continue
        if d["trail"] + d["diameter"] / 2 > chair["swept_radius_max"] * (1 + 1e-9):
            continue
        v = performance(d["trail"], d["diameter"], d["groove"], d["damping"], c)
        if stock.confident_speed[j] < (1 + problem.margin) * chair["target_speed"]:
            continue
        pts.append((float(v["turning_effort"]), float(v["threshold_force"]), j))
    if not pts:
        return -1, 0
    front = []
    for f, p, j in sorted(pts, key=lambda t: (t[1], t[0])):
        if not front or f < front[-1][0]:
            front.append((f, p, j))
    front = front[::-1]  # decreasing threshold force, as Front

    def least_j_end():  # no knee: the end with the least J = w F + w P (the easiest-to-turn end on a tie)
        w = problem.weights
        a, b = front[0], front[-1]
        return (b if w[0] * b[0] + w[1] * b[1] < w[0] * a[0] + w[1] * a[1] else a)[2], len(front)

    if len(front) < 3:
        return least_j_end()
    o = np.array([[f, p] for f, p, _ in front])
    ideal, nadir = o.min(axis=0), o.max(axis=0)
    n = (o - ideal) / np.where(nadir > ideal, nadir - ideal, 1.0)
    a, b = n[0], n[-1]
    chord = b - a
    dist = np.abs(chord[0] * (n[:, 1] - a[1]) - chord[1] * (n[:, 0] - a[0])) / np.hypot(*chord)
    below = (n[:, 0] - a[0]) * chord[1] - (n[:, 1] - a[1]) * chord[0]
    dist = np.where(below >= 0, dist, -dist)
    if not dist.max() > 0:  # no point bulges toward the ideal: no knee either
        return least_j_end()
    return front[int(np.argmax(dist))][2], len(front)


def test_vectorised_recommendation_equals_a_scalar_loop(base, fleet1000):
    """On 40 random chairs of a 1000-chair fleet the vectorised choice, front size and objectives equal a
    scalar loop over the stock (model.performance per caster, non-dominated sort, knee of Front.knee, or the
    least-J end when no point bulges toward the ideal)."""
    stock = _rule.stock_table(base)
    rec = _rule.recommend_chairs(fleet1000.arrays(), stock, base)
    rng = np.random.default_rng(11)
    for i in rng.choice(len(fleet1000), 40, replace=False):
        chair = {k: (v[i] if isinstance(v[i], str) else float(v[i])) for k, v in fleet1000.arrays().items()}
        j, size = _reference_choice(base, stock, chair)
        assert rec["choice"][i] == j, (i, chair)
        assert rec["front_size"][i] == size
        if j >= 0:
            c = base.conditions.replace(
                load=chair["load"],
                threshold_height=chair["threshold_height"],
                surface=chair["surface"],
                turning_mode=chair["turning_mode"],
            )
            d = stock.design(j)
            v = performance(d["trail"], d["diameter"], d["groove"], d["damping"], c)
            assert rec["turning_effort"][i] == pytest.approx(float(v["turning_effort"]), rel=1e-12)
            assert rec["threshold_force"][i] == pytest.approx(float(v["threshold_force"]), rel=1e-12)
    assert (rec["front_size"] >= 2).mean() > 0.5  # the front is not trivially one point


STOCK = """
[stock]
diameters = ["3 in", "4 in", "5 in", "6 in", "8 in"]
grooves = ["0 in", "0.25 in", "0.5625 in"]
trail_step = "0.25 in"
dampings = ["1.3 N*m/rad", "2 N*m/rad", "3 N*m/rad"]
"""


@pytest.fixture(scope="module")
def stocked(root):
    """The default problem with its [stock] (or, if it has none, 5 wheels × 3 grooves × 7 fork holes × 3 washers)."""
    from designer.problem import problem_from_toml

    text = (root / "problems" / "indoor-manual.toml").read_text()
    return problem_from_toml(text if "[stock]" in text else text + STOCK, default_name="indoor-manual-stock")


def test_vectorised_recommendation_equals_designer_recommend(stocked, fleet1000):
    """The contract with issue 11: on 20 random chairs of a 1000-chair example fleet, the vectorised
    recommendation is the design, turning effort, sill force, front size and P(shimmy) (exact, and its Monte Carlo
    ± SE) of
    ``recommend`` on the chair's own problem (the base problem with the chair's load, sill, speed,
    clearance, surface and turning mode), and the alternatives are its two ends."""
    from designer.studies.recommend import recommend

    stock = _rule.stock_table(stocked)
    assert len(stock) >= 315 and "[stock]" in stock.note and "default" not in stock.note
    picks = np.random.default_rng(20).choice(len(fleet1000), 20, replace=False)
    sub = fleet1000.subset(picks)
    res = _fleet.fleet_recommendations(sub, stocked, monte_carlo=True)
    ch = res.chairs
    for k in range(20):
        r = recommend(sub.problem(stocked, k))
        j = ch["choice"][k]
        assert j >= 0
        assert stock.design(j) == pytest.approx(r.design.to_dict(), rel=1e-12)
        assert ch["turning_effort"][k] == pytest.approx(r.turning_effort, rel=1e-12)
        assert ch["threshold_force"][k] == pytest.approx(r.threshold_force, rel=1e-12)
        assert (ch["shimmy_probability"][k], ch["shimmy_probability_mc"][k], ch["shimmy_probability_se"][k]) == (
            r.shimmy_probability,
            r.shimmy_probability_mc,
            r.shimmy_probability_se,
        )
        assert ch["front_size"][k] == len(r.buildable)
        ends = {a.role: a.design.to_dict() for a in r.alternatives}
        for role, key in (("easiest to turn", "easiest_turn"), ("easiest over the sill", "easiest_sill")):
            # recommend() leaves out an alternative that repeats the recommendation
            want = ends.get(role, r.design.to_dict())
            assert stock.design(ch[key][k]) == pytest.approx(want, rel=1e-12), role
    assert len(set(ch["choice"].tolist())) >= 2  # the 20 chairs do not all get one caster


def _small_instance(base, chairs=60, candidates=12, seed=5):
    """Regret matrix of 60 chairs × 12 candidate casters (every chair served by at least one)."""
    f = _table.example_fleet(400, seed=seed)
    stock = _rule.stock_table(base)
    ev = _rule.evaluate_chairs(f.arrays(), stock, base)
    w = np.asarray(base.weights)
    j = np.where(ev["feasible"], w[0] * ev["turning_effort"] + w[1] * ev["threshold_force"], np.inf)
    rec = _rule.recommend_chairs(f.arrays(), stock, base)
    popular = np.argsort(-np.bincount(rec["choice"][rec["choice"] >= 0], minlength=len(stock)))
    cols = np.sort(popular[:candidates])
    sub = j[:, cols]
    served = np.flatnonzero(np.isfinite(sub).any(axis=1))[:chairs]
    sub = sub[served]
    regret = sub - sub.min(axis=1, keepdims=True)
    return regret, f.count[served]


def test_kmedian_equals_brute_force_on_60_chairs_12_candidates(base):
    """K = 1…4: the solver's least count-weighted regret and chosen casters equal enumeration of all
    K-subsets, each K proved optimal (lower bound within the stated tolerance of the value)."""
    cost, weights = _small_instance(base)
    assert cost.shape == (60, 12) and np.isinf(cost).any()  # some casters break some chairs' bounds
    values = []
    for k in (1, 2, 3, 4):
        best, subset = brute_force_kmedian(cost, weights, k)
        sol = solve_kmedian(cost, weights, k)
        if math.isinf(best):
            assert sol.status == "infeasible"
            continue
        assert sol.status in ("optimal", "optimal-by-bound")
        assert sol.regret == pytest.approx(best, rel=1e-9, abs=1e-9)
        assert sol.lower_bound <= best * (1 + 1e-12) and sol.gap <= _kmedian.TOLERANCE * best
        # the chosen casters achieve the optimum (the brute-force subset, or a tie with it)
        achieved = float(np.dot(weights, cost[:, sol.chosen].min(axis=1)))
        assert achieved == pytest.approx(best, rel=1e-9, abs=1e-9)
        assert tuple(sol.chosen) == subset or achieved == pytest.approx(best, rel=1e-12)
        values.append(sol.regret)
    assert len(values) >= 2 and all(a >= b for a, b in zip(values, values[1:]))  # more SKUs never cost more


def _random_instance(rng, kind):
    """A small random K-median instance: continuous costs, many ties, points in a square, or repeated rows;
    a share of the pairs not allowed (+inf); each row's least cost 0 (regrets), weights 1–19."""
    m, n = int(rng.integers(1, 40)), int(rng.integers(1, 11))
    if kind == 0:
        c = rng.uniform(0, 10, (m, n))
    elif kind == 1:
        c = rng.integers(0, 4, (m, n)).astype(float)
    elif kind == 2:
        c = np.linalg.norm(rng.uniform(0, 1, (m, 1, 2)) - rng.uniform(0, 1, (1, n, 2)), axis=2)
    else:
        c = np.repeat(rng.uniform(0, 10, (max(1, m // 3), n)), 3, axis=0)
    c = np.where(rng.uniform(size=c.shape) < rng.choice([0.0, 0.3, 0.6]), np.inf, c)
    least = np.where(np.isfinite(c).any(axis=1, keepdims=True), np.min(c, axis=1, keepdims=True), 0.0)
    return c - least, rng.integers(1, 20, c.shape[0]).astype(float)


def test_optimality_proof_against_exhaustive_kmedian():
    """On 240 random instances (ties, repeated rows, forbidden pairs) and every K: the value equals the
    exhaustive K-median, the status is a proof ("optimal" or "optimal-by-bound") with a lower bound that
    never exceeds the exhaustive optimum and lies within the tolerance of the value, the assignment gives
    each chair its cheapest chosen caster, and "infeasible" is said exactly when no K casters serve all."""
    rng = np.random.default_rng(2024)
    proofs = set()
    for trial in range(240):
        cost, weights = _random_instance(rng, trial % 4)
        for k, sol in kmedian_curve(cost, weights, range(1, cost.shape[1] + 1)).items():
            best, _ = brute_force_kmedian(cost, weights, k)
            if math.isinf(best):
                assert sol.status == "infeasible", (trial, k)
                continue
            assert sol.status in ("optimal", "optimal-by-bound"), (trial, k, sol.status)
            proofs.add(sol.method.split(" (")[0])
            tol = _kmedian.TOLERANCE * max(1.0, best)
            assert abs(sol.regret - best) <= tol and sol.lower_bound <= best + tol and sol.gap <= tol
            assert len(sol.chosen) == k or sol.method == "all useful casters"
            served = cost[np.arange(len(cost)), sol.assignment]
            assert np.allclose(served, cost[:, sol.chosen].min(axis=1)) and math.isclose(
                float(weights @ served), sol.regret, rel_tol=1e-12, abs_tol=1e-12
            )
    # both proofs are exercised: the Lagrangian bound alone, and elimination + HiGHS
    assert {"Lagrangian bound", "Lagrangian elimination"} <= proofs


def test_lagrangian_bound_never_exceeds_the_optimum():
    """L(λ) <= the exhaustive K-median optimum for arbitrary multipliers λ (the bound the proofs rest on)."""
    rng = np.random.default_rng(7)
    checked = 0
    for trial in range(60):
        cost, weights = _random_instance(rng, trial % 4)
        inst = _kmedian._Instance(cost, weights)  # the bound the solver computes: over the reduced problem
        for k in range(1, cost.shape[1] + 1):
            best, _ = brute_force_kmedian(cost, weights, k)
            if math.isinf(best):
                continue
            for scale in (0.0, 1.0, 5.0):
                lam = rng.uniform(0, scale * (1 + np.nanmax(np.where(np.isfinite(cost), cost, 0))), inst.m)
                lam = lam * inst.w
                assert inst.relaxation(lam, min(k, inst.n))[0] <= best * (1 + 1e-12) + 1e-9
                checked += 1
    assert checked > 300


def test_elimination_keeps_every_optimal_set_and_radius_mip_is_exact():
    """The Lagrangian elimination never removes a caster of any optimal K-set and never forces one that some
    optimal set omits; HiGHS on the radius form alone gives the exhaustive optimum."""
    rng = np.random.default_rng(3)
    for trial in range(40):
        cost, weights = _random_instance(rng, 2 if trial % 2 else 1)
        if not np.isfinite(cost).any(axis=1).all() or cost.shape[1] < 3:
            continue
        for k in range(1, cost.shape[1]):
            best, _ = brute_force_kmedian(cost, weights, k)
            if math.isinf(best):
                continue
            res, chosen, constant = _kmedian.radius_mip(cost, weights, k)
            assert res.status == 0 and math.isclose(res.fun + constant, best, rel_tol=1e-9, abs_tol=1e-9)
            assert math.isclose(float(weights @ cost[:, chosen].min(axis=1)), best, rel_tol=1e-9, abs_tol=1e-9)
            optimal = [
                set(s)
                for s in itertools.combinations(range(cost.shape[1]), k)
                if math.isclose(float(weights @ cost[:, list(s)].min(axis=1)), best, rel_tol=1e-12, abs_tol=1e-12)
            ]
            inst = _kmedian._Instance(cost, weights)
            lam = inst.w * inst.sub[:, inst.sub.argmin(axis=1)].min(axis=1) + rng.uniform(0, 1, inst.m)
            keep, forced = _kmedian._eliminate(inst, lam, min(k, inst.n - 1) or 1, best)
            if k >= inst.n:
                continue
            kept = {int(inst.cols[j]) for j in keep}
            must = {int(inst.cols[j]) for j in forced}
            # optimal sets over the pruned columns (pruning keeps at least one optimal set)
            pruned = [s for s in optimal if s <= set(inst.cols.tolist())]
            assert pruned and all(s <= kept for s in pruned) and all(must <= s for s in pruned)


def test_pruning_and_merging_keep_the_optimum():
    """Dropped columns are each dominated by a kept one, merged rows carry the summed weights, and the
    optimum over the kept columns equals the optimum over all columns."""
    rng = np.random.default_rng(9)
    for trial in range(40):
        cost, weights = _random_instance(rng, 3 if trial % 2 else 1)
        keep = _kmedian.prune_candidates(cost)
        for b in set(range(cost.shape[1])) - set(keep.tolist()):
            assert not np.isfinite(cost[:, b]).any() or any(np.all(cost[:, a] <= cost[:, b]) for a in keep)
        rows, w, inverse = _kmedian.aggregate_rows(cost, weights)
        assert np.array_equal(rows[inverse], cost) and math.isclose(w.sum(), weights.sum())
        assert len(np.unique(rows, axis=0)) == len(rows)
        for k in range(1, min(4, len(keep)) + 1):
            assert brute_force_kmedian(cost[:, keep], weights, k)[0] == pytest.approx(
                brute_force_kmedian(cost, weights, k)[0], rel=1e-12
            )


def test_column_dominance_over_blocks_drops_only_what_is_dominated_on_every_row():
    """Rows given in blocks: a column dominated by one column in the first block and by another in the second
    is kept (no single column dominates it on every row); one dominated on every row by one column is dropped;
    a column allowed for no row is dropped; the result is that of the whole matrix at once."""
    inf = np.inf
    good_first = [0.0] * 5 + [9.0] * 5
    good_last = [9.0] * 5 + [0.0] * 5
    middle = [1.0] * 10
    worse_than_middle = [2.0] * 10
    never = [inf] * 10
    cost = np.array([good_first, good_last, middle, worse_than_middle, never]).T
    assert list(_kmedian.prune_candidates(cost, block_rows=5)) == [0, 1, 2]
    assert list(_kmedian.prune_candidates(cost, block_rows=100)) == [0, 1, 2]
    rng = np.random.default_rng(4)
    for _ in range(20):
        c, _w = _random_instance(rng, 2)
        if len(c) > 3:
            assert np.array_equal(_kmedian.prune_candidates(c, block_rows=3), _kmedian.prune_candidates(c))


def test_suggested_count_is_the_smallest_k_within_max_regret_by_brute_force(base):
    """On a 30-chair fleet: the suggested count is the smallest K whose exhaustive least mean regret (over
    units sold) is <= --max-regret, for thresholds between the curve's values, at a value exactly, and
    below the whole curve (then K_max, flagged not within)."""
    f = _table.example_fleet(30, seed=12)
    res = _fleet.fleet_recommendations(f, base, skus="auto", k_max=4, monte_carlo=False)
    cost, columns = res.regret_cost["regret"], res.regret_cost["columns"]
    units = float(f.count[res.feasible].sum())
    keep = _kmedian.prune_candidates(cost)
    exhaustive = {k: brute_force_kmedian(cost[:, keep], f.count[res.feasible], k)[0] / units for k in range(1, 5)}
    assert all(a > b for a, b in zip(list(exhaustive.values()), list(exhaustive.values())[1:]))
    for k, value in exhaustive.items():
        assert res.curve[k].regret / units == pytest.approx(value, rel=1e-9)
    cases = [
        ((exhaustive[2] + exhaustive[3]) / 2, 3, True),
        (exhaustive[2], 2, True),
        (exhaustive[1] * 2, 1, True),
        (exhaustive[4] / 2, 4, False),
    ]
    for threshold, expected, within in cases:
        got = _fleet.suggest_skus(res.curve, units, threshold)
        assert (got["count"], got["within"]) == (expected, within), threshold
        assert got["mean_regret_N"] == pytest.approx(exhaustive[expected], rel=1e-9)
        assert f"{threshold:g} N" in got["rule"]
    assert res.suggested == _fleet.suggest_skus(res.curve, units, _fleet.DEFAULT_MAX_REGRET)
    assert res.skus is res.curve[res.suggested["count"]] and set(res.skus.chosen) <= set(columns.tolist())
    # without --k-max the curve goes on past 8 until the threshold is met (every K proved optimal)
    strict = _fleet.fleet_recommendations(f, base, skus="auto", monte_carlo=False, max_regret=0.02)
    count, ks = strict.suggested["count"], sorted(strict.curve)
    assert strict.suggested["within"] and ks == list(range(1, max(8, count) + 1)) and count > 8
    assert strict.curve[count].regret / units <= 0.02 < strict.curve[count - 1].regret / units
    assert {s.status for s in strict.curve.values()} <= {"optimal", "optimal-by-bound"}


def test_fleet_cli_writes_csv_json_and_report(tmp_path, capsys, root):
    """`designer fleet F --skus 2 --json`: exit 0, fleet.csv with the issue's columns, JSON skus/regret/rows."""
    path = _table.write_fleet_csv(_table.example_fleet(60, seed=2), tmp_path / "f.csv")
    out = tmp_path / "out"
    code = main(
        [
            "fleet",
            str(path),
            "--skus",
            "2",
            "--k-max",
            "3",
            "--problem",
            str(root / "problems" / "indoor-manual.toml"),
            "--out",
            str(out),
            "--json",
        ]
    )
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["k"] == 2 and len(data["skus"]) == 2 and data["sku_status"] in ("optimal", "optimal-by-bound")
    assert sum(s["chairs"] for s in data["skus"]) == data["feasible_chairs"]
    assert {"id", "design", "chairs", "count", "extrapolated"} <= set(data["skus"][0])
    for sku in data["skus"]:  # every design record says whether its wheel is outside Table 1's 4–8 in
        assert sku["extrapolated"] == (not 4 * INCH * 0.999 <= sku["design"]["diameter"] <= 8 * INCH * 1.001)
    assert [c["k"] for c in data["regret_curve"]] == [1, 2, 3]
    regrets = [c["total_regret_N"] for c in data["regret_curve"] if c["total_regret_N"] is not None]
    assert regrets == sorted(regrets, reverse=True)
    assert data["weights"] == [1.0, 1.0] and data["total_regret_N"] == data["regret_curve"][1]["total_regret_N"]
    header = (out / "fleet.csv").read_text().splitlines()[0].split(",")
    assert header == [
        "name",
        "trail_in",
        "diameter_in",
        "groove_in",
        "damping_N_m_per_rad",
        "turning_effort_N",
        "threshold_force_N",
        "shimmy_probability",
        "shimmy_probability_mc",
        "shimmy_probability_se",
        "sku",
        "sku_turning_effort_N",
        "sku_threshold_force_N",
        "sku_shimmy_probability",
        "sku_shimmy_probability_mc",
        "sku_shimmy_probability_se",
        "knee_regret_N",
        "sku_regret_N",
        "status",
    ]
    rows = list(csv.DictReader(open(out / "fleet.csv", encoding="utf-8")))
    sku = {s["id"]: s["design"] for s in data["skus"]}
    served = next(r for r in rows if r["sku"])
    ident = int(served["sku"].split(":")[0])  # a part number with its sizes: "3: T 2 1/2 in, d 7 in, ..."
    assert served["sku"] == f"{ident}: " + ", ".join(
        [f"T {written_size(sku[ident]['trail'])}", f"d {written_size(sku[ident]['diameter'])}",
         f"B {written_size(sku[ident]['groove'])}", f"c_f {sku[ident]['damping']:.3g} N·m/rad"]
    )  # fmt: skip
    chair = next(r for r in data["rows"] if r["name"] == served["name"])
    assert float(served["trail_in"]) == pytest.approx(chair["trail"] / INCH, rel=1e-5)
    text = (out / "fleet.json").read_text()
    # numbers as resolved, at most 12 significant digits: 0.1778, not 0.17779999999999999 (a limit's P may be
    # 0.0499999998898: α to the root's precision, a true 12th digit)
    digits = [len(m.group(1).replace(".", "").lstrip("0")) for m in re.finditer(r"(?<![\w.])-?(\d+\.\d+)", text)]
    assert digits and max(digits) <= 12, max(digits)
    rows = data["rows"]
    assert len(rows) == 60
    for r in rows:
        if r["status"] == "ok":
            assert r["sku"] in (1, 2) and r["sku_turning_effort"] > 0 and r["sku_threshold_force"] > 0
            assert 0 <= r["shimmy_probability"] <= 1 and r["shimmy_probability_se"] > 0
            assert abs(r["shimmy_probability"] - r["shimmy_probability_mc"]) <= 4 * r["shimmy_probability_se"]
    # the Pareto report's look: its stylesheet, the answer and the part numbers in the first-screen box with
    # the regret curve, SVG figures inline (each point's numbers on hover) and the same files for report.md
    page = (out / "index.html").read_text()
    assert ".build {" in page and "<img" not in page and "data:image" not in page
    box = page.split('<section class="build" id="build">', 1)[1].split("</section>", 1)[0]
    assert html.escape(data["answer"]) in box and "<td>2</td>" in box and 'id="fig-regret"' in box
    for name in ("regret", "distributions"):
        svg = (out / "figures" / f"{name}.svg").read_text()
        assert svg.startswith("<svg") and svg.strip() in page
    for c in data["regret_curve"]:
        assert f"K = {c['k']}: mean regret {c['mean_regret_N']:.3f} N" in box
    md = (out / "report.md").read_text()
    assert md.splitlines()[5] == f"## {data['answer']}" and "](figures/regret.svg)" in md


def test_infeasible_chair_is_reported_not_dropped(base):
    """A chair no stock caster can serve (1 in footrest clearance) keeps its row with a reason, and the
    part-number choice leaves it out."""
    f = _table.fleet_from_text(GOOD + "tight,178,0.5,2.5,1,tile,chair,5\n")
    res = _fleet.fleet_recommendations(f, base, skus=1, k_max=1, monte_carlo=False)
    col = np.searchsorted(res.regret_cost["columns"], res.skus.assignment)
    regret = res.regret_cost["regret"][np.arange(2), col]
    assert np.all(regret >= 0) and np.all(np.isfinite(regret))  # never negative, never a broken bound
    rows = res.rows()
    assert [r["name"] for r in rows] == ["a", "b", "tight"]
    assert rows[2]["status"].startswith("infeasible") and "swept radius" in rows[2]["status"]
    assert rows[2]["trail"] is None and rows[2]["sku"] is None
    assert res.skus.assignment.shape == (2,)


def test_dask_local_cluster_gives_the_in_process_result(base):
    """The same code path on a 2-worker LocalCluster (separate processes) gives identical choices and the same
    P(shimmy) as in-process (to 1e-12 relative); what is shipped to workers holds no CasADi object."""
    import distributed  # in the `test` extra: this test never skips

    f = _table.example_fleet(300, seed=4)
    stock = _rule.stock_table(base)
    payload = pickle.dumps((_rule._split(f, 100)[0][1], stock, base))
    assert b"casadi" not in payload
    local = _fleet.fleet_recommendations(f, base, monte_carlo=True, chunk=100)
    with (
        distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster,
        distributed.Client(cluster) as client,
    ):
        remote = _fleet.fleet_recommendations(f, base, scheduler=client, monte_carlo=True, chunk=100)
        assert len(client.scheduler_info()["workers"]) == 2
    np.testing.assert_array_equal(remote.chairs["choice"], local.chairs["choice"])
    # to the last bits: after the other tests of this file the in-process exact P differs from the fresh workers'
    # by up to 1e-14 relative (seen since one caster's law became the batched law of one; 1e-16 absolute)
    np.testing.assert_allclose(remote.chairs["shimmy_probability"], local.chairs["shimmy_probability"], rtol=1e-12)
    assert remote.scheduler and remote.scheduler.startswith("tcp://")


def test_batched_monte_carlo_gives_the_numbers_of_the_shared_function(base):
    """Chairs sharing a caster share one seeded draw; the Monte Carlo P(shimmy) and SE equal, per chair, the
    model's Monte Carlo of that caster alone (speeds spread so that some estimates need the top-up for SE <= 0.1
    pp); the exact P beside them is the exact law's of that caster (quadrature), within 3 SE of the draw."""
    stock = _rule.stock_table(base)
    u = scatter_of(base.conditions)
    j = int(np.argmin(np.abs(stock.confident_speed - 2.5)))
    assert not stock.measured[j]  # a stock diameter: the wheel is known by its diameter only
    speeds = np.sort(np.random.default_rng(3).uniform(0.5, 1.6, 12) * stock.critical_speed[j])
    designs = np.tile([stock.trail[j], stock.diameter[j], stock.groove[j], stock.damping[j]], (12, 1))
    got = _rule._mc_task(
        designs, np.full(12, stock.inertia[j]), speeds, base.conditions.slip_coefficient, u, np.full(12, False)
    )
    for r in range(12):
        want = _mc(
            stock.trail[j],
            stock.inertia[j],
            stock.groove[j],
            stock.damping[j],
            base.conditions.slip_coefficient,
            speeds[r],
            u,
            diameter=stock.diameter[j],
        )
        assert tuple(got[r, 1:]) == want, r
        caster = LawCaster(
            stock.trail[j],
            stock.inertia[j],
            stock.groove[j],
            stock.damping[j],
            base.conditions.slip_coefficient,
            stock.diameter[j],
        )
        assert got[r, 0] == exact_probability(caster, speeds[r], u)
        assert abs(got[r, 0] - got[r, 1]) <= 3 * got[r, 2] + 1e-12, r
    assert got[0, 1] < 0.05 < got[-1, 1]  # both paths (shared draw, top-up) are exercised


def _regret_keys(node, path=""):
    """Every (path, key) of a JSON tree whose key names a regret and holds a number."""
    out = []
    if isinstance(node, dict):
        for key, value in node.items():
            if "regret" in key and isinstance(value, (int, float)) and not isinstance(value, bool):
                out.append(f"{path}/{key}")
            out += _regret_keys(value, f"{path}/{key}")
    elif isinstance(node, list):
        for i, value in enumerate(node):
            out += _regret_keys(value, f"{path}[{i}]")
    return out


def test_fleet_cli_answer_first_from_another_folder_and_json_units(tmp_path, monkeypatch, capsys):
    """From a folder outside the repository, without --problem (the shipped indoor-manual problem):
    `designer fleet F --skus 2` prints the suggested count on its first line and the two part numbers asked in
    one screen (--verbose: the K asked on a later line), and writes the report under ./results/fleet/<name>/;
    `--json` has suggested_skus {count, rule, mean_regret_N}, "regret_unit": "N", and every number keyed by a
    regret ends in _N."""
    monkeypatch.chdir(tmp_path)
    path = _table.write_fleet_csv(_table.example_fleet(40, seed=6), tmp_path / "line.csv")
    assert main(["fleet", path.name, "--skus", "2", "--no-monte-carlo"]) == 0
    screen = capsys.readouterr().out.splitlines()
    assert len(screen) <= 24 and max(len(ln) for ln in screen) <= 80
    assert [ln.split(":")[0] for ln in screen if ln.startswith("  part ")] == ["  part 1", "  part 2"]
    assert main(["fleet", path.name, "--skus", "2", "--no-monte-carlo", "--verbose"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == screen[0]
    first = re.fullmatch(
        r"(\d+) part numbers? serve all 40 chairs within 2 N of their best caster on average", lines[0]
    )
    second = re.match(r"  mean regret (\d+\.\d\d) N per unit sold against each chair's least J = F_turn \+ P", lines[1])
    assert first and second, lines[:2]
    assert max(len(ln) for ln in lines) <= 80  # COLUMNS unset and not a terminal: 80 columns
    assert (tmp_path / "results" / "fleet" / "line" / "fleet.csv").exists()
    assert main(["fleet", path.name, "--skus", "2", "--no-monte-carlo", "--json", "--out", "o"]) == 0
    data = json.loads(capsys.readouterr().out)
    suggested = data["suggested_skus"]
    assert {"count", "rule", "mean_regret_N"} <= set(suggested) and data["regret_unit"] == "N"
    assert suggested["count"] == int(first.group(1)) and f"{suggested['mean_regret_N']:.2f}" == second.group(1)
    curve = {c["k"]: c["mean_regret_N"] for c in data["regret_curve"]}
    assert suggested["mean_regret_N"] <= 2.0 and all(curve[k] > 2.0 for k in curve if k < suggested["count"])
    if suggested["count"] != 2:
        assert any(ln.startswith("K = 2 (asked with --skus)") for ln in lines)
        assert "2 part numbers as asked (--skus)" in " ".join(" ".join(screen).split())
    keys = _regret_keys(data)
    assert keys and all(k.endswith("_N") for k in keys), [k for k in keys if not k.endswith("_N")]
    assert {"/total_regret_N", "/mean_regret_N", "/suggested_skus/mean_regret_N"} <= set(keys)


def test_max_regret_option_reads_units_and_refuses_nonsense(tmp_path, capsys):
    """--max-regret "1 lbf" is 4.448 N in the rule; a negative or unit-less nonsense value is one line, exit 2."""
    path = _table.write_fleet_csv(_table.example_fleet(20, seed=6), tmp_path / "f.csv")
    args = ["fleet", str(path), "--no-monte-carlo", "--json", "--out", str(tmp_path / "o")]
    assert main([*args, "--max-regret", "1 lbf"]) == 0
    assert "4.44822 N" in json.loads(capsys.readouterr().out)["suggested_skus"]["rule"]
    for bad in ("-1", "2 m"):
        code = main([*args, "--max-regret", bad])
        errors = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("designer: error")]
        assert code == 2 and len(errors) == 1 and "--max-regret" in errors[0], (bad, errors)


def test_regret_is_measured_against_the_least_j_not_the_recommendation(base):
    """Own recommendation = the knee of the chair's front, not its least J: per chair, knee_regret_N and
    sku_regret_N equal J − (least J over the chair's allowed stock, by a scalar loop); the count of chairs
    whose part number beats their recommendation on J is reported as such."""
    f = _table.example_fleet(50, seed=21)
    res = _fleet.fleet_recommendations(f, base, skus=2, k_max=2, monte_carlo=False)
    data = _fleet.fleet_data(res)
    stock = res.stock
    ev = _rule.evaluate_chairs(f.arrays(), stock, base)
    w = base.weights
    better = 0
    for i, row in enumerate(data["rows"]):
        if row["status"] != "ok":
            continue
        allowed = np.flatnonzero(ev["feasible"][i])
        least = min(w[0] * ev["turning_effort"][i, j] + w[1] * ev["threshold_force"][i, j] for j in allowed)
        knee = w[0] * row["turning_effort"] + w[1] * row["threshold_force"]
        sku = w[0] * row["sku_turning_effort"] + w[1] * row["sku_threshold_force"]
        assert row["knee_regret_N"] == pytest.approx(knee - least, abs=1e-9 * least)
        assert row["sku_regret_N"] == pytest.approx(sku - least, abs=1e-9 * least)
        assert row["knee_regret_N"] >= 0 and row["sku_regret_N"] >= 0
        better += sku < knee - 1e-9 * least
    own = data["own_recommendation"]
    assert own["part_number_better_on_J"] == better and "knee" in own["meaning"] and "least J" in own["meaning"]


def test_fleet_run_loads_no_matplotlib_and_json_reads_back(tmp_path):
    """The whole `designer fleet F --skus 2` process (report included) loads no matplotlib (its figures are
    SVG), and its --json output is valid JSON with one row per chair (written by the fast row writer)."""
    import subprocess
    import sys

    path = _table.write_fleet_csv(_table.example_fleet(15, seed=1), tmp_path / "f.csv")
    code = (
        "import sys, io, contextlib; from designer.cli import main; buf = io.StringIO()\n"
        f"with contextlib.redirect_stdout(buf): rc = main(['fleet', {str(path)!r}, '--skus', '2', '--json', "
        f"'--no-monte-carlo', '--out', {str(tmp_path / 'o')!r}])\n"
        "print(rc, 'matplotlib' in sys.modules); print(buf.getvalue())"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    first, rest = out.split("\n", 1)
    assert first == "0 False"
    data = json.loads(rest)
    run = data.pop("run")
    assert len(data["rows"]) == 15 and data == json.loads((tmp_path / "o" / "fleet.json").read_text())
    # the date, times and versions only in run.json (and --json's "run"): a rerun writes the same files
    assert run == json.loads((tmp_path / "o" / "run.json").read_text()) | {
        "date": run["date"],
        "timings": run["timings"],
        "curve_seconds": run["curve_seconds"],
    }
    assert {"date", "timings", "curve_seconds", "versions"} <= set(run)
    for name in ("fleet.json", "index.html", "report.md"):
        text = (tmp_path / "o" / name).read_text()
        assert run["date"][:10] not in text and "seconds" not in text, name


def _mc(*args, **kwargs) -> tuple[float, float]:
    """The model's Monte Carlo P(shimmy) and SE of one caster, as floats."""
    from designer.model import shimmy_probability

    p, se = shimmy_probability(*args, **kwargs)
    return float(p), float(se)


def test_fleet_rows_say_when_a_diameter_is_outside_table1(base):
    """Every chair's row with a caster says whether its wheel's diameter lies outside Table 1's 4–8 in (the
    inertia fit and Eq. 7's check extrapolate there); a chair without a caster has None; the stock table holds the
    same flag per caster."""
    res = _fleet.fleet_recommendations(_table.example_fleet(30, seed=12), base, monte_carlo=False)
    rows = res.rows()
    assert any(r["status"] == "ok" for r in rows)
    for r in rows:
        if r["status"] == "ok":
            assert r["extrapolated"] == (not 4 * INCH * 0.999 <= r["diameter"] <= 8 * INCH * 1.001)
        else:
            assert r["extrapolated"] is None
    stock = res.stock
    assert np.array_equal(stock.extrapolated, (stock.diameter < 4 * INCH * 0.999) | (stock.diameter > 8 * INCH * 1.001))


def test_fleet_cli_part_numbers_in_written_sizes_never_broken(tmp_path, monkeypatch, capsys):
    """Issue 28.5 on the fleet's terminal answer: each part number's sizes are written as the user writes them
    (inches to 1/16, "2 1/2 in", "3/4 in"; not "2.5 in" or "0.75 in"), at COLUMNS=50 no line but the first (the
    answer, kept whole for a script to read) is wider than 50, and no size is broken across two lines (each SKU's
    sizes all stand on its first line)."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("COLUMNS", "50")
    path = _table.write_fleet_csv(_table.example_fleet(40, seed=6), tmp_path / "line.csv")
    assert main(["fleet", path.name, "--skus", "3", "--no-monte-carlo", "--json", "--out", "j"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert main(["fleet", path.name, "--skus", "3", "--no-monte-carlo", "--out", "t"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert max(len(ln) for ln in lines[1:]) <= 50
    assert data["k"] == 3 and len(data["skus"]) == 3
    for s in data["skus"]:
        d = s["design"]
        line = next(ln for ln in lines if ln.startswith(f"  part {s['id']}: "))
        want = f"T {written_size(d['trail'])}, d {written_size(d['diameter'])}, B {written_size(d['groove'])}"
        assert want in line, (want, line)
        assert re.search(r"\d\.\d+ in", line) is None, line


def test_a_part_without_a_limit_reads_none_in_the_goods_in_table():
    """The fleet report's goods-in row of a part number: a part with no limit inside its range reads "none" (not
    "≥ none"), a trail limited on one side only shows that side, and a limit shows its side and value."""
    from designer.report.fleet import _sku_spec

    units = {"trail_min": "m", "trail_max": "m", "groove_min": "m", "friction_moment_min": "N·m"}
    p = {"at_speed": 2.5, "exact": 0.03, "monte_carlo": 0.031, "monte_carlo_se": 0.001}
    p |= {"monte_carlo_samples": 50000, "monte_carlo_seed": 1}
    limits = {"trail_min": None, "trail_max": 0.05, "groove_min": None, "friction_moment_min": 0.25}
    row = _sku_spec(
        {
            "limits": limits | {"wheel_inertia_max": 0.002},
            "units": units | {"wheel_inertia_max": "kg·m²"},
            "shimmy_probability": p,
        }
    )
    assert row["B_lim"] == "none" and row["T_lim"].startswith("≤ 50.00 mm") and "none" not in row["T_lim"]
    assert row["M_lim"] == "≥ 0.250 N·m" and row["I_lim"].startswith("≤ 0.002")
    assert not any("≥ none" in v or "≤ none" in v for v in row.values())


def test_a_bound_equal_to_the_value_up_to_the_sums_rounding_leaves_no_gap():
    """A MIP bound below the value by the rounding of a sum of one regret a chair (HiGHS sums in its own order:
    5.8e-11 N on a 593,420 N total, which moved with the BLAS kernel) is no gap: gap 0, bound = value; a bound
    below by more than that rounding keeps its gap."""
    import time

    from designer.studies.fleet._kmedian import KMedianSolution, _finish, _Instance

    rng = np.random.default_rng(7)
    cost, weights = rng.uniform(100.0, 2000.0, (500, 6)), np.ones(500)
    inst = _Instance(cost, weights)
    value = inst.value(range(inst.n))
    out = KMedianSolution(k=inst.n, candidates=inst.n)
    close = _finish(
        inst, out, range(inst.n), value * (1 - 1e-16) - 5.8e-11 * value / 593420, "optimal", "m", time.time()
    )
    assert close.gap == 0.0 and close.lower_bound == close.regret
    far = _finish(inst, out, range(inst.n), value * (1 - 1e-9), "optimal", "m", time.time())
    assert far.gap == pytest.approx(value * 1e-9, rel=1e-6)
