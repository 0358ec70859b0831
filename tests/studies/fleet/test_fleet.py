"""Product lines (`designer fleet`): the fleet table, the vectorised per-chair recommendation, the exact
K-median of part numbers, and the Dask path on a 2-worker LocalCluster."""

from __future__ import annotations

import json
import math
import pickle

import numpy as np
import pytest

import designer
from designer.studies.fleet import _fleet, _rule, _table
from designer.studies.fleet._kmedian import brute_force_kmedian, solve_kmedian
from designer.cli import main
from designer.data.paper import INCH
from designer.model import performance, scatter_of

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
    if len(front) < 3:  # no knee: the end with the least J = w F + w P (the easiest-to-turn end on a tie)
        w = problem.weights
        a, b = front[0], front[-1]
        return (b if w[0] * b[0] + w[1] * b[1] < w[0] * a[0] + w[1] * a[1] else a)[2], len(front)
    o = np.array([[f, p] for f, p, _ in front])
    ideal, nadir = o.min(axis=0), o.max(axis=0)
    n = (o - ideal) / np.where(nadir > ideal, nadir - ideal, 1.0)
    a, b = n[0], n[-1]
    chord = b - a
    dist = np.abs(chord[0] * (n[:, 1] - a[1]) - chord[1] * (n[:, 0] - a[0])) / np.hypot(*chord)
    below = (n[:, 0] - a[0]) * chord[1] - (n[:, 1] - a[1]) * chord[0]
    dist = np.where(below >= 0, dist, -dist)
    return front[int(np.argmax(dist))][2], len(front)


def test_vectorised_recommendation_equals_a_scalar_loop(base, fleet1000):
    """On 40 random chairs of a 1000-chair fleet the vectorised choice, front size and objectives equal a
    scalar loop over the stock (model.performance per caster, non-dominated sort, knee of Front.knee)."""
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
    recommendation is the design, turning effort, sill force, front size and Monte Carlo P(shimmy) ± SE of
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
        assert stock.design(j) == pytest.approx(r.design.as_dict(), rel=1e-12)
        assert ch["turning_effort"][k] == pytest.approx(r.turning_effort, rel=1e-12)
        assert ch["threshold_force"][k] == pytest.approx(r.threshold_force, rel=1e-12)
        assert (ch["shimmy_probability"][k], ch["shimmy_probability_se"][k]) == (
            r.shimmy_probability,
            r.shimmy_probability_se,
        )
        assert ch["front_size"][k] == len(r.buildable)
        ends = {a.role: a.design.as_dict() for a in r.alternatives}
        for role, key in (("easiest to turn", "easiest_turn"), ("easiest over the sill", "easiest_sill")):
            # recommend() leaves out an alternative that repeats the recommendation
            want = ends.get(role, r.design.as_dict())
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
    """K = 1…4: the MIP's least count-weighted regret and chosen casters equal enumeration of all K-subsets."""
    cost, weights = _small_instance(base)
    assert cost.shape == (60, 12) and np.isinf(cost).any()  # some casters break some chairs' bounds
    values = []
    for k in (1, 2, 3, 4):
        best, subset = brute_force_kmedian(cost, weights, k)
        sol = solve_kmedian(cost, weights, k)
        if math.isinf(best):
            assert sol.status == "infeasible"
            continue
        assert sol.status == "optimal"
        assert sol.regret == pytest.approx(best, rel=1e-9, abs=1e-9)
        # the chosen casters achieve the optimum (the brute-force subset, or a tie with it)
        achieved = float(np.dot(weights, cost[:, sol.chosen].min(axis=1)))
        assert achieved == pytest.approx(best, rel=1e-9, abs=1e-9)
        assert tuple(sol.chosen) == subset or achieved == pytest.approx(best, rel=1e-12)
        values.append(sol.regret)
    assert len(values) >= 2 and all(a >= b for a, b in zip(values, values[1:]))  # more SKUs never cost more


def test_kmedian_heuristic_gap_bound_brackets_the_optimum(base):
    """Above the exact size limit: greedy + swap is never better than the MIP, its bound never above it."""
    cost, weights = _small_instance(base, seed=8)
    exact = solve_kmedian(cost, weights, 3)
    heur = solve_kmedian(cost, weights, 3, exact_limit=0)
    assert heur.status in ("heuristic", "optimal-by-bound") and exact.status == "optimal"
    assert heur.regret >= exact.regret * (1 - 1e-12)
    assert heur.lower_bound <= exact.regret * (1 + 1e-9)
    assert heur.gap == pytest.approx(heur.regret - heur.lower_bound)


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
    assert data["k"] == 2 and len(data["skus"]) == 2 and data["sku_status"] == "optimal"
    assert sum(s["chairs"] for s in data["skus"]) == data["feasible_chairs"]
    assert {"id", "design", "chairs", "count"} <= set(data["skus"][0])
    assert [c["k"] for c in data["regret_curve"]] == [1, 2, 3]
    regrets = [c["regret"] for c in data["regret_curve"] if c["regret"] is not None]
    assert regrets == sorted(regrets, reverse=True)
    assert data["weights"] == [1.0, 1.0] and "regret" in data
    header = (out / "fleet.csv").read_text().splitlines()[0].split(",")
    assert header == [
        "name",
        "trail",
        "diameter",
        "groove",
        "damping",
        "turning_effort",
        "threshold_force",
        "shimmy_probability",
        "shimmy_probability_se",
        "sku",
        "sku_turning_effort",
        "sku_threshold_force",
        "sku_shimmy_probability",
        "status",
    ]
    rows = data["rows"]
    assert len(rows) == 60
    for r in rows:
        if r["status"] == "ok":
            assert r["sku"] in (1, 2) and r["sku_turning_effort"] > 0 and r["sku_threshold_force"] > 0
            assert 0 <= r["shimmy_probability"] <= 1 and r["shimmy_probability_se"] > 0
    assert (out / "index.html").read_text().count("data:image/png;base64") == 2


def test_infeasible_chair_is_reported_not_dropped(base):
    """A chair no stock caster can serve (1 in footrest clearance) keeps its row with a reason, and the
    part-number choice leaves it out."""
    f = _table.fleet_from_text(GOOD + "tight,178,0.5,2.5,1,tile,chair,5\n")
    res = _fleet.fleet_recommendations(f, base, skus=1, k_max=1, monte_carlo=False)
    regret = res.regret_cost["regret"][np.arange(2), res.skus.assignment]
    assert np.all(regret >= 0) and np.all(np.isfinite(regret))  # never negative, never a broken bound
    rows = res.rows()
    assert [r["name"] for r in rows] == ["a", "b", "tight"]
    assert rows[2]["status"].startswith("infeasible") and "swept radius" in rows[2]["status"]
    assert rows[2]["trail"] is None and rows[2]["sku"] is None
    assert res.skus.assignment.shape == (2,)


def test_dask_local_cluster_gives_the_in_process_result(base):
    """The same code path on a 2-worker LocalCluster (separate processes) gives identical choices and
    Monte Carlo numbers as in-process; what is shipped to workers holds no CasADi object."""
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
    np.testing.assert_array_equal(remote.chairs["shimmy_probability"], local.chairs["shimmy_probability"])
    assert remote.scheduler and remote.scheduler.startswith("tcp://")


def test_batched_monte_carlo_gives_the_numbers_of_the_shared_function(base):
    """Chairs sharing a caster share one seeded draw; P(shimmy) and SE equal shimmy_probability_mc per chair
    exactly (speeds spread so that some estimates need the function's top-up for SE <= 0.1 pp)."""
    from designer.physics.uncertainty import shimmy_probability_mc

    stock = _rule.stock_table(base)
    u = scatter_of(base.conditions)
    j = int(np.argmin(np.abs(stock.confident_speed - 2.5)))
    speeds = np.sort(np.random.default_rng(3).uniform(0.5, 1.6, 12) * stock.critical_speed[j])
    designs = np.tile([stock.trail[j], stock.diameter[j], stock.groove[j], stock.damping[j]], (12, 1))
    got = _rule._mc_task(designs, np.full(12, stock.inertia[j]), speeds, base.conditions.slip_coefficient, u)
    for r in range(12):
        want = shimmy_probability_mc(
            stock.trail[j],
            stock.inertia[j],
            stock.groove[j],
            stock.damping[j],
            base.conditions.slip_coefficient,
            speeds[r],
            u,
        )
        assert tuple(got[r]) == want, r
    assert got[0, 0] < 0.05 < got[-1, 0]  # both paths (shared draw, top-up) are exercised
