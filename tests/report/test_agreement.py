"""When two result files agree (designer.report.agreement, docs/checks.md#when-two-result-files-agree): the check
that keeps results/ current by number catches a real change (planted here in copies of the committed files) and
lets the last digit of a multiplier or a contour vertex move as another CPU moves it."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import pytest

from designer.cli import main
from designer.report.agreement import (
    DRAWING_PX,
    MONTE_CARLO_K,
    RULES,
    compare_csv,
    compare_files,
    compare_folders,
    compare_json,
    compare_text,
    keep_agreeing,
    rule_for,
    variable_scale,
)
from designer.output import MANIFEST, RUN_MANIFEST
from designer.units import csv_quantity

ROOT = Path(__file__).resolve().parents[2]
COMMITTED = ROOT / "results" / "indoor-manual"


@pytest.fixture()
def copy(tmp_path) -> Path:
    """A copy of the committed indoor-manual report (run.json aside), to plant changes in."""
    out = tmp_path / "indoor-manual"
    shutil.copytree(COMMITTED, out, ignore=shutil.ignore_patterns("run.json"))
    return out


def _edit_json(path: Path, edit) -> None:
    data = json.loads(path.read_text(encoding="utf-8"))
    edit(data)
    path.write_text(json.dumps(data, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")


def test_the_committed_report_agrees_with_itself(copy):
    """A copy of a committed report agrees with it: nothing is reported (the planted tests below start from it)."""
    assert compare_folders(COMMITTED, copy) == {}


@pytest.mark.parametrize("variable", ["trail", "diameter", "groove", "damping"])
def test_a_design_variable_moved_by_1e_4_relative_fails(copy, variable):
    """Moving one committed design variable of one front point by 1e-4 of its value (in front.json, then in
    front.csv) is reported, with the file, the field, both values and the tolerance (1e-7 of the variable's scale)."""
    front = json.loads((COMMITTED / "front.json").read_text())
    index = next(i for i, p in enumerate(front["points"]) if p[variable] != 0)
    _edit_json(
        copy / "front.json", lambda d: d["points"][index].update({variable: d["points"][index][variable] * 1.0001})
    )
    moved = compare_folders(COMMITTED, copy)
    assert list(moved) == ["front.json"]
    (m,) = moved["front.json"]
    assert m.where == f"front.json.points[{index}].{variable}" and m.rule == "design"
    assert m.new == pytest.approx(m.old * 1.0001, rel=1e-12) and m.tolerance < 1e-4 * abs(m.old)

    rows = (COMMITTED / "front.csv").read_text().splitlines()
    header = rows[0].split(",")
    name = next(h for h in header if csv_quantity(h)[0] == variable)  # trail_in, damping_N_m_per_rad
    column = header.index(name)
    row = next(i for i in range(1, len(rows)) if float(rows[i].split(",")[column]) != 0)
    cells = rows[row].split(",")
    cells[column] = repr(float(cells[column]) * 1.0001)
    rows[row] = ",".join(cells)
    (copy / "front.csv").write_text("\n".join(rows) + "\n")
    (m,) = compare_files(COMMITTED / "front.csv", copy / "front.csv")
    assert m.where == f"front.csv row {row} {name}" and m.rule == "design"
    assert m.tolerance < 1e-4 * abs(m.old)


def test_a_column_that_names_its_unit_is_on_its_variables_scale():
    """A front.csv column in inches or mm (``trail_in``, ``trail_mm``) is a design variable on its scale in that
    unit: 2.5 in is 63.5 mm is 0.0635 m; a move of 1e-8 of the scale agrees, 1e-6 does not; a renamed column
    (a front.csv of the bare SI names against one that names its units) is structural."""
    assert rule_for("trail_in") == rule_for("trail_mm") == rule_for("trail") == "design"
    assert variable_scale("trail_in") == pytest.approx(2.5) and variable_scale("trail_mm") == pytest.approx(63.5)
    assert rule_for("turning_effort_N") == "number" and variable_scale("status") == 0.0
    for name, value in (("trail_in", 2.0), ("trail_mm", 50.8)):
        old = f"{name},status\n{value!r},Solve_Succeeded\n"
        scale = variable_scale(name)
        assert compare_csv(old, old.replace(repr(value), repr(value + 1e-8 * scale))) == []
        (m,) = compare_csv(old, old.replace(repr(value), repr(value + 1e-6 * scale)))
        assert m.rule == "design" and m.where == f" row 1 {name}"
    assert compare_csv("trail,status\n0.0508,x\n", "trail_in,status\n2,x\n")[0].where == " (columns)"


def test_a_changed_status_fails(copy):
    """A front point's solver status changed (front.csv and front.json) is reported as an exact difference."""
    text = (copy / "front.csv").read_text()
    (copy / "front.csv").write_text(text.replace("Solve_Succeeded", "Maximum_Iterations_Exceeded", 1))
    _edit_json(copy / "front.json", lambda d: d["points"][2].update(status="Infeasible_Problem_Detected"))
    moved = compare_folders(COMMITTED, copy)
    assert sorted(moved) == ["front.csv", "front.json"]
    assert moved["front.csv"][0].where == "front.csv row 1 status"
    assert moved["front.json"][0].old == "Solve_Succeeded" and moved["front.json"][0].rule == "exact"


def test_a_changed_label_fails(copy):
    """A figure's axis label changed by one word, in the SVG file and in index.html, is reported (the text around
    the numbers must be identical), and so is a check's name in checks.json."""
    for name in ("figures/front.svg", "index.html"):
        text = (copy / name).read_text(encoding="utf-8")
        assert "turning effort F_turn [N]" in text, name
        (copy / name).write_text(text.replace("turning effort F_turn [N]", "turning force F_turn [N]", 1), "utf-8")
    _edit_json(copy / "checks.json", lambda d: d[0].update(name=d[0]["name"] + " (renamed)"))
    moved = compare_folders(COMMITTED, copy)
    assert sorted(moved) == ["checks.json", "figures/front.svg", "index.html"]
    assert "turning force" in moved["figures/front.svg"][0].new


def test_the_last_digit_of_a_multiplier_may_move():
    """The differences another CPU makes (issue 32: -0.6964 -> -0.6965, 2.21 -> 2.211 in powered-chair's front) agree:
    a multiplier is written to 4 significant digits; a move of 1 % of it does not agree."""
    old = {"points": [{"lambda_shimmy": -0.6964, "lambda_turning_cap": 2.21, "lambda_swept_radius": 0.0}]}
    new = {"points": [{"lambda_shimmy": -0.6965, "lambda_turning_cap": 2.211, "lambda_swept_radius": 3e-7}]}
    assert compare_json(old, new) == []
    moved = compare_json(old, {"points": [{**new["points"][0], "lambda_turning_cap": 2.21 * 1.01}]})
    assert [m.where for m in moved] == ["points[0].lambda_turning_cap"] and moved[0].rule == "multiplier"
    assert RULES["multiplier"].rtol == pytest.approx(2e-3)


def test_csv_cells_follow_the_same_rules():
    """front.csv is compared by column name and row with the JSON rules: a multiplier's last digit agrees, an
    objective moved by 1e-6 relative does not, and a renamed column or a missing row is structural."""
    old = "turning_effort,lambda_shimmy,status\n13.3317322,-0.6964,Solve_Succeeded\n"
    assert compare_csv(old, old.replace("-0.6964", "-0.6965")) == []
    (m,) = compare_csv(old, old.replace("13.3317322", "13.3317455"))
    assert m.where == " row 1 turning_effort" and m.rule == "number"
    assert compare_csv(old, old.replace("status", "state"))[0].rule == "exact"
    assert compare_csv(old, old.splitlines()[0] + "\n")[0].where == " (rows)"


def test_drawing_coordinates_agree_within_half_a_pixel():
    """An SVG coordinate moved by 0.1 px (the contour vertex of issue 32) agrees, by 0.6 px it does not; a number in
    text agrees at its printed precision (one unit of its last digit) and not beyond; a new element is structural."""
    svg = '<svg><path d="M886.3 299L887.6 299.7L889.4 300.8"/><text x="10" y="20">3.5 m/s</text></svg>'
    assert compare_text(svg, svg.replace("299.7", "299.8")) == []
    (m,) = compare_text(svg, svg.replace("299.7", f"{299.7 + DRAWING_PX + 0.1:.1f}"))
    assert m.rule == "drawing" and m.tolerance == DRAWING_PX
    assert compare_text(svg, svg.replace("3.5 m/s", "3.6 m/s")) == []  # one unit of the last printed digit
    assert [m.rule for m in compare_text(svg, svg.replace("3.5 m/s", "3.7 m/s"))] == ["printed"]
    assert compare_text(svg, svg.replace("</svg>", "<circle/></svg>"))[0].rule == "exact"


def test_a_monte_carlo_estimate_agrees_within_its_standard_errors():
    """P(shimmy) from the Monte Carlo agrees within 4 standard errors of the difference (its ``_se`` field), and
    not beyond: 0.02906 ± 0.00075 against 0.0331 (3.8 SE) agrees, against 0.0335 (4.2 SE) it does not."""
    old = {"shimmy_probability": 0.02906, "shimmy_probability_se": 0.00075}
    assert compare_json(old, {**old, "shimmy_probability": 0.0331}) == []
    (m,) = compare_json(old, {**old, "shimmy_probability": 0.0335})
    assert m.rule == "monte carlo" and m.tolerance == pytest.approx(4 * 0.00075 * 2**0.5)
    risk = {"risk": {"probability": 0.02906, "se": 0.00075}}
    assert compare_json(risk, {"risk": {"probability": 0.0331, "se": 0.00075}}) == []


def test_keep_agreeing_keeps_the_old_bytes_and_names_what_moved(copy, tmp_path):
    """The writer's step: a staged file that agrees with the existing one gets the existing bytes (the commit leaves
    it as it was); one that does not is kept new and named in one line with the value that moved."""
    stage = tmp_path / "stage"
    shutil.copytree(copy, stage)
    svg = (stage / "figures" / "groove_damper.svg").read_text(encoding="utf-8")
    (stage / "figures" / "groove_damper.svg").write_text(svg.replace('.5"', '.6"', 1), encoding="utf-8")
    _edit_json(
        stage / "front.json", lambda d: d["points"][0].update(turning_effort=d["points"][0]["turning_effort"] * 1.001)
    )
    before = (stage / "front.json").read_bytes()
    changed = keep_agreeing(stage, copy)
    assert (stage / "figures" / "groove_damper.svg").read_bytes() == (
        copy / "figures" / "groove_damper.svg"
    ).read_bytes()
    assert list(changed) == ["front.json"] and (stage / "front.json").read_bytes() == before
    assert changed["front.json"].startswith("front.json: 1 value moved: front.json.points[0].turning_effort: ")


def test_pareto_prints_the_rewritten_file(copy, monkeypatch, capsys):
    """`designer pareto` into a report whose front.json has one multiplier changed by 10 % (as an earlier run of
    the tool wrote it: its manifest holds the digest of those bytes) rewrites front.json whole and prints one line
    naming it and the value; every other file keeps its bytes."""
    _edit_json(
        copy / "front.json", lambda d: d["points"][0].update(lambda_shimmy=d["points"][0]["lambda_shimmy"] * 1.1)
    )
    manifest = json.loads((copy / MANIFEST).read_text(encoding="utf-8"))
    manifest["files"]["front.json"]["sha256"] = hashlib.sha256((copy / "front.json").read_bytes()).hexdigest()
    (copy / MANIFEST).write_text(json.dumps(manifest), encoding="utf-8")
    others = {  # the manifests record the new front.json's digest
        p: p.read_bytes()
        for p in copy.rglob("*")
        if p.is_file() and p.name not in ("front.json", MANIFEST, RUN_MANIFEST)
    }
    monkeypatch.chdir(ROOT)
    assert main(["pareto", "problems/indoor-manual.toml", "--out", str(copy)]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if "rewritten" in line]
    assert len(lines) == 1 and "front.json: 1 value moved: front.json.points[0].lambda_shimmy" in lines[0]
    assert all(p.read_bytes() == data for p, data in others.items())
    run = json.loads((copy / "run.json").read_text())
    assert list(run["moved"]) == ["front.json"]
    assert compare_files(COMMITTED / "front.json", copy / "front.json") == []


def test_p_at_a_limit_is_held_to_the_roots_precision():
    """P(shimmy) at an acceptance limit is α to the root's tolerance: the two sides of α a root on another CPU may
    land on (0.0499999992, 0.0500000002: 2e-8 apart, beyond the 'number' rule) agree; the limit itself stays on
    the 'number' rule, so a limit moved by 1e-7 of itself does not agree, nor does a P at the limit 1e-4 off."""
    spec = {"limits": {"trail_min": 0.0357395948}, "limit_probability": {"trail_min": 0.0499999992}}
    other = {"limits": {"trail_min": 0.0357395948}, "limit_probability": {"trail_min": 0.0500000002}}
    assert compare_json(spec, other) == []
    moved = compare_json(spec, {**other, "limits": {"trail_min": 0.0357395948 * (1 + 1e-7)}})
    assert [(m.where, m.rule) for m in moved] == [("limits.trail_min", "number")]
    off = compare_json(spec, {**other, "limit_probability": {"trail_min": 0.05 * (1 + 1e-4)}})
    assert [(m.where, m.rule) for m in off] == [("limit_probability.trail_min", "root")]


def test_the_docs_state_the_declared_tolerances():
    """docs/checks.md#when-two-result-files-agree states each tolerance of RULES as declared (words are data)."""
    text = (ROOT / "docs" / "checks.md").read_text(encoding="utf-8")
    section = text[text.index("## When two result files agree") :]

    def g(x: float) -> str:
        return f"{x:.2g}".replace("e-0", "e-")

    assert f"{g(RULES['design'].rtol)} of the variable's scale" in section
    assert f"{g(RULES['number'].rtol)} of its magnitude" in section
    assert f"{g(RULES['multiplier'].rtol)} of its magnitude, plus {g(RULES['multiplier'].atol)}" in section
    assert f"{g(RULES['root'].rtol)} of its magnitude | it is α by construction" in section
    assert f"{MONTE_CARLO_K:g} standard errors of the difference" in section
    assert f"| {DRAWING_PX:g} px |" in section


def test_a_standard_error_moves_with_its_estimate():
    """An SE field sqrt(p(1−p)/n) agrees within 4 of its own standard errors, |1−2p| SE²/(2p(1−p)) carried from p's:
    one sample of 50 000 more below the speed (p 0.02906 -> 0.02908) agrees, an SE 10 % larger does not."""
    n = 50_000

    def at(p):
        return {"shimmy_probability": p, "shimmy_probability_se": (p * (1 - p) / n) ** 0.5}

    assert compare_json(at(0.02906), at(0.02908)) == []
    wider = {**at(0.02906), "shimmy_probability_se": at(0.02906)["shimmy_probability_se"] * 1.1}
    assert [m.where for m in compare_json(at(0.02906), wider)] == ["shimmy_probability_se"]


def test_the_exact_risk_beside_its_monte_carlo_is_held_to_the_quadrature():
    """Where a record carries the exact P(shimmy) (quadrature) and its Monte Carlo check beside it: the Monte Carlo
    estimate agrees within 4 SE (one draw of 50 000 more below the speed moves it by 2e-5), while the exact value
    is a computed number: the same 2e-5 move of it is a change the check reports."""
    old = {"shimmy_probability": 0.02983, "shimmy_probability_mc": 0.02906, "shimmy_probability_se": 0.00075}
    assert compare_json(old, {**old, "shimmy_probability_mc": 0.02908}) == []
    (m,) = compare_json(old, {**old, "shimmy_probability": 0.02985})
    assert m.where == "shimmy_probability" and m.rule != "monte carlo"
    (m,) = compare_json(old, {**old, "shimmy_probability_mc": 0.0335})
    assert m.where == "shimmy_probability_mc" and m.rule == "monte carlo"
