"""The exact law in batches (designer.physics.uncertainty.shimmy_probability_exact_many) and the acceptance limits
found for many casters together (designer.physics.acceptance.acceptance_limits_many) against the one-caster
functions they replace in the hot paths."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from designer.parameters import PARAMETERS
from designer.physics import acceptance as A
from designer.physics import uncertainty as U
from designer.physics.inertia import power_law_inertia
from designer.physics.shimmy import critical_shimmy_speed

SLIP = float(PARAMETERS["slip_coefficient"].default)
RANGES = {name: PARAMETERS[name].range for name in ("trail", "groove", "damping")}


def random_casters(seed: int, n: int = 50) -> dict[str, np.ndarray]:
    """n casters over the model's range: a fifth without groove, about 40 % with a measured wheel, speeds from 0.4
    to 1.2 of Eq. 7's V_c (P from about 1e-4 to 0.9, where a relative comparison means something)."""
    rng = np.random.default_rng(seed)
    d = rng.uniform(0.1, 0.2, n)
    cols = {
        "trail": rng.uniform(0.02, 0.08, n),
        "diameter": d,
        "inertia": np.asarray(power_law_inertia(d), dtype=float),
        "groove": np.where(np.arange(n) < n // 5, 0.0, rng.uniform(0.002, 0.03, n)),
        "damping": rng.uniform(0.2, 3.0, n),
        "measured": rng.random(n) < 0.4,
    }
    v_c = critical_shimmy_speed(cols["trail"], cols["inertia"], cols["groove"], cols["damping"], SLIP)
    cols["speed"] = v_c * rng.uniform(0.4, 1.2, n)
    return cols


def scalar_probabilities(c: dict[str, np.ndarray], law: U.Uncertainty, nodes: int = 32) -> np.ndarray:
    """The one-caster quadrature on a grid of nodes × nodes over (ξc, ξK) for each caster: Eq. 7 at the scattered
    c_f and K_s, the linear part (model error, inertia) by inversion; an independent check of the batch's one
    quadrature axis."""
    zn, zw = U._hermite_nodes(nodes)
    zc, zk = (z.ravel() for z in np.meshgrid(zn, zn, indexing="ij"))
    out = []
    for i in range(c["trail"].size):
        t, i_w, b, f = (float(c[k][i]) for k in ("trail", "inertia", "groove", "damping"))
        dist = U._linear_part(t, i_w, b, f, SLIP, law, None if c["measured"][i] else c["diameter"][i], None)
        v = critical_shimmy_speed(t, i_w, b, f * np.exp(law.damping * zc), SLIP * np.exp(law.slip_coefficient * zk))
        out.append(np.sum(np.outer(zw, zw).ravel() * dist.cdf((np.log(c["speed"][i]) - np.log(v))[None, :])[0]))
    return np.array(out)


def batched(c: dict[str, np.ndarray], law: U.Uncertainty) -> np.ndarray:
    return U.shimmy_probability_exact_many(
        c["trail"],
        c["inertia"],
        c["groove"],
        c["damping"],
        SLIP,
        c["speed"],
        law,
        diameter=c["diameter"],
        measured=c["measured"],
        nodes=A.LAW_NODES,
    )


@pytest.mark.parametrize("seed", [1, 2])
def test_batched_exact_law_equals_the_scalar_quadrature_on_50_random_casters(seed):
    """P of 50 random casters (grooved and not, measured and predicted wheels) in one call equals the one-caster
    quadrature's to 1e-10 of itself (the scalar's 32 × 32 grid; the inversion's own accuracy is about 1e-13)."""
    c = random_casters(seed)
    law = U.data_law()
    ours, theirs = batched(c, law), scalar_probabilities(c, law)
    assert theirs.min() > 1e-5 and theirs.max() < 0.999  # the speeds put P where a relative error means something
    assert np.max(np.abs(ours - theirs) / theirs) <= 1e-10


def test_the_comparison_catches_a_wrong_law():
    """The same comparison fails for a law one step off: the scatter of K_s 0.21 instead of 0.20 in the batch
    moves P of the grooved casters by far more than 1e-10 (the test above could fail)."""
    c = random_casters(1)
    law = U.data_law()
    wrong = batched(c, U.data_law(slip_coefficient=0.21))
    theirs = scalar_probabilities(c, law)
    assert np.max(np.abs(wrong - theirs) / theirs) > 1e-4


def test_batched_law_broadcasts_and_says_one_without_critical_speed():
    """A scalar speed broadcasts over the casters (the shape of the casters comes back) and a caster without trail
    has V_c = 0: P = 1, as for one caster (designer.physics.acceptance.exact_probability)."""
    law = U.data_law()
    trail = np.array([[0.05, 0.0], [0.03, 0.06]])
    p = U.shimmy_probability_exact_many(trail, 2e-3, 0.01, 1.3, SLIP, 2.5, law)
    assert p.shape == (2, 2) and p[0, 1] == 1.0
    one = U.shimmy_probability_exact(0.03, 2e-3, 0.01, 1.3, SLIP, 2.5, law, nodes=32)
    assert p[1, 0] == pytest.approx(one, rel=1e-10)


def test_batched_limits_equal_one_at_a_time_on_50_random_casters():
    """Every acceptance limit of 50 random casters found together equals the one-caster search to the root's
    tolerance: trail, groove and c_f mins (each part alone, least_part) within 2 × 2 (xtol + LIMIT_RTOL |x|)
    (two searches, each within 2 (xtol + rtol |x|) of the root), the measured I_w max (the scalar search,
    max_measured_inertia) within 1e-10 in log I plus the batch's 1e-11; the same parts without a limit, for the
    same reason."""
    c = random_casters(3)
    law = U.data_law()
    casters = [
        A.LawCaster(
            float(c["trail"][i]),
            float(c["inertia"][i]),
            float(c["groove"][i]),
            float(c["damping"][i]),
            SLIP,
            None if c["measured"][i] else float(c["diameter"][i]),
        )
        for i in range(c["trail"].size)
    ]
    speed = c["speed"] * 0.8
    many = A.acceptance_limits_many(casters, speed, law, RANGES, 0.2, c["diameter"])
    found = {"risk": 0, "none": 0}
    for i, caster in enumerate(casters):
        one = A.acceptance_limits(caster, float(speed[i]), law, RANGES, 0.2, float(c["diameter"][i]))
        one = [
            A.least_part(caster, x.part, float(speed[i]), law, *RANGES[x.part]) if x.side == "min" else x for x in one
        ]
        top = U.max_measured_inertia(caster.trail, caster.groove, caster.damping, SLIP, float(speed[i]), law)
        one[-1] = dataclasses.replace(one[-1], value=top)
        for ours, theirs in zip(many[i], one):
            assert (ours.part, ours.side, ours.reason) == (theirs.part, theirs.side, theirs.reason)
            if theirs.value is None:
                assert ours.value is None
                found["none"] += 1
                continue
            if ours.part == "inertia":
                assert abs(np.log(ours.value / theirs.value)) <= 1e-10 + 2e-11
            elif ours.reason == "risk":
                xtol = 1e-15 * max(abs(RANGES[ours.part][1]), 1e-12)
                assert abs(ours.value - theirs.value) <= 4 * (xtol + A.LIMIT_RTOL * abs(theirs.value))
                found["risk"] += 1
            else:
                assert ours.value == theirs.value
            if theirs.probability is not None:
                assert ours.probability == pytest.approx(theirs.probability, abs=1e-8)
    assert found["risk"] >= 60 and found["none"] >= 1  # most parts have a risk limit; some none in the range


def test_casters_sharing_a_wheel_size_share_a_tabulated_cdf_and_the_same_p():
    """60 casters on three wheel sizes (and measured wheels) bring many points per linear law: the batch tabulates
    each law's CDF (designer.physics._sums.CdfTable) and P still equals the one-caster quadrature to 1e-10."""
    from designer.physics import _sums

    c = random_casters(4, n=60)
    c["diameter"] = np.choose(np.arange(60) % 3, [0.127, 0.1524, 0.2032])
    c["inertia"] = np.asarray(power_law_inertia(c["diameter"]), dtype=float)
    v_c = critical_shimmy_speed(c["trail"], c["inertia"], c["groove"], c["damping"], SLIP)
    c["speed"] = v_c * np.random.default_rng(5).uniform(0.4, 1.2, 60)
    _sums._TABLES.clear()
    law = U.data_law()
    ours = batched(c, law)
    assert len(_sums._TABLES) >= 3  # the table path ran
    theirs = scalar_probabilities(c, law)
    assert np.max(np.abs(ours - theirs) / theirs) <= 1e-10


@pytest.mark.parametrize(
    "terms, normal",
    [
        ([(0.10751, 5), (0.5 * 0.36, 5)], 0.5 * 0.0894),  # model error, a 5 in wheel's prediction, E's half
        ([(0.10751, 5)], 0.5 * np.hypot(0.05, 0.0894)),  # a measured grooved wheel
        ([(0.10751, 5)], 0.05),  # a measured wheel without groove
    ],
)
def test_cdf_table_is_the_inversion_to_1e15(terms, normal):
    """The quintic Hermite table equals the characteristic-function inversion within 1e-15 (absolute) over its
    reach |x| <= 20 λ, tails included, and is symmetric: F(−x) = 1 − F(x)."""
    from designer.physics._sums import TABLE_REACH, CdfTable, SumDistribution

    dist = SumDistribution(terms, normal)
    table = CdfTable(dist)
    lam = float(dist.total_scale)
    rng = np.random.default_rng(6)
    x = np.concatenate([rng.standard_t(3, 4000) * lam, rng.uniform(-TABLE_REACH, TABLE_REACH, 2000) * lam])
    x = x[np.abs(x) <= TABLE_REACH * table.scale]
    assert np.max(np.abs(table(x) - dist.cdf(x[:, None]).ravel())) <= 1e-15
    assert np.max(np.abs(table(-x) - (1 - table(x)))) <= 1e-15


def test_gauss_legendre_matches_numpy_and_integrates_better():
    """The Newton Gauss–Legendre rule gives numpy's nodes to 1e-15 and integrates x^200 and cos(100 x) on [−1, 1]
    to 1e-15 (numpy's eigenvalue weights: 1e-14)."""
    from designer.physics._sums import gauss_legendre

    x, w = gauss_legendre(512)
    ref_x, ref_w = np.polynomial.legendre.leggauss(512)
    assert np.max(np.abs(x - ref_x)) <= 1e-15 and np.max(np.abs(w - ref_w)) <= 1e-14
    assert abs(np.sum(w * x**200) - 2 / 201) <= 1e-15
    assert abs(np.sum(w * np.cos(100 * x)) - 2 * np.sin(100) / 100) <= 1e-15


def test_monte_carlo_counts_are_eq7_on_the_stream_draws():
    """The Monte Carlo (Eq. 7 squared, shared exponentials) counts the same draws below V as Eq. 7 evaluated draw
    by draw on the seeded stream (designer.physics.uncertainty.law_draws): the same P to the last draw."""
    law = U.data_law(samples=10_000)
    c = random_casters(7, n=6)
    p, _ = U.shimmy_probability_mc_many(
        c["trail"], c["inertia"], c["groove"], c["damping"], SLIP, c["speed"], law,
        diameter=c["diameter"], measured=c["measured"], target_se=None,
    )  # fmt: skip
    f = U.law_draws(law, np.random.default_rng(law.seed), U.inertia_prediction().dof)
    for i in range(6):
        scale = law.inertia if c["measured"][i] else float(U.inertia_prediction().scale(c["diameter"][i]))
        iota = scale * (f["inertia_z"] if c["measured"][i] else f["inertia_t"])
        v = critical_shimmy_speed(
            c["trail"][i],
            c["inertia"][i] * np.exp(iota),
            c["groove"][i],
            c["damping"][i] * np.exp(law.damping * f["damping"]),
            SLIP * np.exp(law.slip_coefficient * f["slip"]),
        ) * np.exp(law.model_error * f["model"])
        assert p[i] == np.count_nonzero(v < c["speed"][i]) / 10_000
    assert 0 < p.min() and p.max() < 1
