"""Issue 12.5, mutation testing: tests written against mutants that survived the first run
(benchmarks/mutation.md): what each check reports, the closed-form ends, the swept-radius trail."""

from __future__ import annotations


import numpy as np
import pytest

import designer.analysis.checks as ck
from designer.data.paper import INCH
from designer.problem import load_problem, problem_from_toml
from designer.solvers import structured
from designer.solvers.nlp import CasterNLP, evaluate_many

from conftest import ROOT
from test_trust_structured import HEAVY

PINNED = {
    # name: (kind, expected, got) as the report and validate show them
    "1 Eq. 8": ("paper", 2.91, 2.9113),
    "2 Table 1": ("paper", "RMS error within the paper's ±15% scatter; A, B > 2 m/s", "RMS 10.3%, worst 16.4%"),
    "3 groove +10 %": ("identity", "+10 % (chair and pivot)", "chair +10.0%, pivot +10.0%"),
    "4 carpet ×2": ("identity", 2.0, 2.0),
    "5 trail ×2": ("identity", 0.5, 0.5),
    "6 monotonicity": (
        "paper",
        "V_c ↑ with T, c_f, B; ↓ with I_w, d",
        "trail ok, damping ok, groove ok, inertia ok, diameter ok",
    ),
    "7 P/L vs d": (
        "paper",
        "decreasing, convex; slope at 4 in >= 2 × slope at 8 in; P/L(3 in) >= 1.5 × P/L(6 in)",
        "P/L 3 in 1.118, 4 in 0.882, 6 in 0.663, 8 in 0.553; slope ratio 4 in / 8 in 3.98",
    ),
    "9 Routh–Hurwitz": ("paper", "relative difference < 1e-09", None),
    "10 Quadra": ("paper", "> 3.8 m/s", 6.089),
    "fit I_w(d)": ("paper", "n 3.50, 1.873e-3", None),
}


def test_paper_check_records_pinned():
    """Each paper check's name, kind, expected and got, as validate and the report print them; claim and
    detail are non-empty sentences; to_dict carries every field (the numbers are the model's today, to the
    digits printed)."""
    checks = ck.paper_checks()
    assert [c.name for c in checks] == list(PINNED)
    for c in checks:
        kind, expected, got = PINNED[c.name]
        assert (c.kind, c.expected) == (kind, expected), c.name
        if got is not None:
            assert c.got == got, c.name
        assert isinstance(c.claim, str) and len(c.claim) > 30, c.name
        assert isinstance(c.detail, str) and len(c.detail) > 30, c.name
        d = c.to_dict()
        assert d == {
            "name": c.name,
            "claim": c.claim,
            "expected": c.expected,
            "got": c.got,
            "passed": True,
            "detail": c.detail,
            "kind": kind,
            "outcome": c.outcome,
            "disagreements": c.disagreements,
        }
    eq8, table1 = checks[0], checks[1]
    assert "error +0.04% (tolerance ±0.5%" in eq8.detail and "6.51 mph" in eq8.detail
    assert table1.detail.startswith("A: predicted 4.87 m/s, measured stable to 3.8; B: predicted 3.60 m/s")
    assert "C: predicted 2.00 vs measured 2.39 m/s (-16.4%)" in table1.detail
    assert "Tolerance: RMS <= 15% (the scatter of Fig. 2C), each wheel <= 25%" in table1.detail
    routh = checks[7]
    assert float(routh.got) < 1e-12 and "4 parameter sets" in routh.detail
    fit = checks[9]
    n = float(fit.got.split()[1].rstrip(","))
    assert n == pytest.approx(3.50, abs=0.01) and float(fit.got.split()[2]) == pytest.approx(1.873e-3, rel=5e-3)


def test_table1_disagreement_lines_pinned():
    """The six disagreement lines of check 2, word for word (size, direction, band)."""
    assert ck.check_table1().disagreements == [
        "B: predicted to shimmy at 3.60 m/s, below the 3.80 m/s up to which it was measured stable: disagrees "
        "by at least 5.3 %, within the paper's ±15 % scatter",
        "C: predicted 2.00 m/s against 2.39 m/s measured: disagrees by 16.4 % (predicted lower), outside the "
        "paper's ±15 % scatter, within the ±25 % allowed for one wheel",
        "D: predicted 1.85 m/s against 1.77 m/s measured: disagrees by 4.4 % (predicted higher), within the "
        "paper's ±15 % scatter",
        "E: predicted 1.63 m/s against 1.46 m/s measured: disagrees by 11.9 % (predicted higher), within the "
        "paper's ±15 % scatter",
        "F: predicted 1.46 m/s against 1.58 m/s measured: disagrees by 7.5 % (predicted lower), within the "
        "paper's ±15 % scatter",
        "G: predicted 1.12 m/s against 1.20 m/s measured: disagrees by 6.9 % (predicted lower), within the "
        "paper's ±15 % scatter",
    ]
    assert ck._disagreement("X", 1.0, 2.0, 0.15, 0.25).endswith("outside the ±25 % allowed for one wheel")


@pytest.mark.parametrize("factor, outcome", [(1.149, ck.WITHIN_SCATTER), (1.151, ck.FAILS)])
def test_table1_rms_limit_edge(factor, outcome):
    """All five measured wheels off by the same factor: RMS just inside ±15 % disagrees within the scatter,
    just outside fails (the limit is the stated scatter, not more)."""
    from test_trust_checks import _table1_model

    assert ck.check_table1(_table1_model(factor=factor)).outcome == outcome


def test_summary_counts_front_checks():
    """The summary line counts front checks, including 'not applicable' ones."""
    a = ck.Check("8a x", "c", 1, 1, True, kind="front")
    b = ck.Check("8c x", "c", 1, 1, True, kind="front", outcome=ck.NOT_APPLICABLE)
    f = ck.Check("8b x", "c", 1, 2, False, kind="front")
    text = ck.summary_line([a, b, f])
    assert text.endswith("; front checks: 1 pass, 1 fail, 1 not applicable")
    assert ck.count_outcomes([a, b, f])["front"] == {
        ck.REPRODUCED: 1,
        ck.WITHIN_SCATTER: 0,
        ck.FAILS: 1,
        ck.NOT_APPLICABLE: 1,
    }
    with pytest.raises(ValueError):
        ck.Check("x", "c", 1, 1, True, outcome="maybe")


def test_front_checks_texts_and_single_point(tmp_path):
    """Check 8 on a one-point front: 8a has nothing to compare (passes), 8b counts the inactive points;
    names, kinds and the tighter-front wording are those documented in docs/checks.md."""
    from designer.analysis.pareto import Front
    from test_trust_checks import _optimal_points

    problem = load_problem(ROOT / "problems" / "indoor-manual.toml").nominal()
    (p,) = _optimal_points(problem, [110.0])
    a, b = ck.front_checks(Front(problem, [p]))
    assert (a.name, a.got, a.outcome, a.kind) == (
        "8a trade-off",
        "1 point(s): nothing to compare",
        ck.REPRODUCED,
        "front",
    )
    assert (b.name, b.got, b.kind) == (
        "8b shimmy active",
        "0 of 1 points inactive, 0 of them with groove or damper",
        "front",
    )
    looser = Front(problem, _optimal_points(problem, [105.0, 110.0, 120.0]))
    c8a = ck.front_checks(looser)[0]
    assert c8a.got == "0 diameter and 0 effort reversals in 3 points" and c8a.detail.startswith("d ")


@pytest.mark.parametrize("toml", ["indoor", "heavy"])
def test_structured_ends_match_nlp_ends(toml):
    """The closed-form lexicographic ends equal IPOPT's: end A has the least F_turn (to 1e-7) and, among
    designs with it, the least P; end B the least P (to 1e-7), then the least F_turn."""
    from designer.analysis.sweeps import lexicographic_ends

    problem = (
        load_problem(ROOT / "problems" / "indoor-manual.toml").nominal()
        if toml == "indoor"
        else problem_from_toml(HEAVY)
    )
    xa, xb = structured.structured_ends(problem)
    nlp = CasterNLP(problem)
    ends = lexicographic_ends(nlp, problem)
    ra, rb = ends.a, ends.b
    (fa, pa, _, _), (fb, pb, _, _) = nlp.objectives_many([xa, xb])
    (na_f, na_p, _, _), (nb_f, nb_p, _, _) = nlp.objectives_many([ra.design, rb.design])
    assert fa == pytest.approx(na_f, rel=1e-7) and pa == pytest.approx(na_p, rel=1e-6)
    assert pb == pytest.approx(nb_p, rel=1e-7) and fb == pytest.approx(nb_f, rel=1e-6)
    v = evaluate_many(problem, np.array([xa, xb]))["critical_speed"]
    assert np.all(v >= problem.required_speed * (1 - 1e-9))


def test_structured_front_designs_on_the_curve():
    """Closed-form ε-optima: P = ε where the diameter is free (Eq. 4A inverted), feasible, on V_c = V_req."""
    problem = load_problem(ROOT / "problems" / "indoor-manual.toml").nominal()
    eps = np.array([100.0, 110.0, 120.0])
    x, ok = structured.structured_front_designs(problem, eps)
    assert ok.all()
    values = evaluate_many(problem, x)
    assert values["threshold_force"] == pytest.approx(eps, rel=1e-9)
    assert structured.diameter_at(problem, eps) == pytest.approx(x[:, 1], rel=1e-12)
    assert np.isnan(structured.diameter_at(problem, [0.0])[0])
    assert structured.applicable(problem)
    assert not structured.applicable(problem.replace(wheels=("C", "D")))
    with pytest.raises(ValueError):
        structured.structured_front_designs(problem.replace(wheels=("C",)), eps)


def test_designs_at_diameter_infeasible_when_trail_cannot_fit():
    """The swept-radius limit sets the trail: R_max = 5.5 in with a 7 in wheel leaves T = 2 in (feasible);
    R_max = 4.4 in leaves 0.9 in, below the 1 in minimum: infeasible, the design clipped to T = 1 in."""
    base = load_problem(ROOT / "problems" / "indoor-manual.toml").nominal()
    d = np.array([7 * INCH])
    x, ok = structured.designs_at_diameter(base.replace(swept_radius_max=5.5 * INCH), d)
    assert ok.tolist() == [True] and x[0, 0] == pytest.approx(2 * INCH)
    x, ok = structured.designs_at_diameter(base.replace(swept_radius_max=4.4 * INCH), d)
    assert ok.tolist() == [False] and x[0, 0] == pytest.approx(1 * INCH)
