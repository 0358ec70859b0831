"""designer inspect: a verdict on each measured caster by the exact law, the lot's summary, bad rows named one per
line with exit 2 after the good rows are graded, the input file never written; the empty form (--template)."""

from __future__ import annotations

import hashlib
import json
import warnings
from pathlib import Path

import pytest

from designer.physics.uncertainty import shimmy_probability_exact
from designer.problem import load_problem

ROOT = Path(__file__).resolve().parents[2]
PROBLEM = ROOT / "problems" / "indoor-manual.toml"


@pytest.fixture(scope="module")
def indoor():
    """indoor-manual and its recommendation (nominal caster, joint box, one-at-a-time limits)."""
    from designer.studies.recommend import recommend

    problem = load_problem(PROBLEM)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return problem, recommend(problem)


def _lot(rec) -> tuple[list[list], list[str]]:
    """22 measured casters (mm, N·m, kg·m²) and 4 bad rows: inside the joint box, outside the box but inside the
    one-at-a-time limits, inside the box but outside one-at-a-time (the trail between the two minima), outside
    both, one part off at a time."""
    j, spec, d = rec.spec.joint, rec.spec, rec.design
    one = {lim.key: lim.value for lim in spec.limits}
    nom = [d.trail * 1e3, d.diameter * 1e3, d.groove * 1e3, spec.friction_moment, spec.inertia]
    low = [j.trail_min * 1e3, d.diameter * 1e3, j.groove_min * 1e3, j.friction_moment_min, j.wheel_inertia_max]
    rows = []
    for k, f in enumerate((0.0, 0.2, 0.5, 0.8, 0.95, 0.999)):  # inside the box: toward every limit at once
        rows.append([f"in{k}", *(n + f * (lo - n) for n, lo in zip(nom, low))])
    m_f = 0.5 * (j.friction_moment_min + one["friction_moment_min"])  # inside one-at-a-time, below the box
    rows.append(["oat-m", nom[0], nom[1], nom[2], m_f, nom[4]])
    rows.append(
        [
            "oat-all",
            one["trail_min"] * 1e3 + 0.01,
            nom[1],
            one["groove_min"] * 1e3 + 0.01,
            one["friction_moment_min"] + 1e-3,
            one["wheel_inertia_max"] * 0.999,
        ]
    )
    rows.append(["oat-mi", nom[0], nom[1], nom[2], m_f, j.wheel_inertia_max * 1.2])
    t_mid = 0.5 * (j.trail_min + one["trail_min"]) * 1e3  # inside the box, below the one-at-a-time trail min
    rows.append(["box-t", t_mid, nom[1], nom[2], nom[3], nom[4]])
    for k, f in enumerate((1.05, 1.2, 1.5)):  # beyond the box on every part at once
        rows.append([f"out{k}", *(n + f * (lo - n) for n, lo in zip(nom, low))])
    rows += [
        ["only-t", 40.0, nom[1], nom[2], nom[3], nom[4]],
        ["only-b", nom[0], nom[1], 5.0, nom[3], nom[4]],
        ["only-m", nom[0], nom[1], nom[2], 0.1, nom[4]],
        ["only-i", nom[0], nom[1], nom[2], nom[3], 0.004],
        ["big-d", nom[0], nom[1] + 5, nom[2], nom[3], nom[4]],
        ["plain", nom[0], nom[1], 0.0, nom[3], nom[4]],
        ["n1", 60.0, 177.8, 18.0, 0.42, 0.0012],
        ["n2", 58.0, 177.8, 17.0, 0.35, 0.0014],
        ["n3", 62.0, 177.8, 19.5, 0.5, 0.0011],
    ]
    text = ["serial,trail_mm,diameter_mm,groove_mm,friction_moment_N_m,wheel_inertia_kg_m2"]
    text += [",".join([r[0], *(f"{x:.6g}" for x in r[1:])]) for r in rows[:10]]
    text += ["bad1,abc,177.8,19,0.45,0.00117", "bad2,63.5,177.8,,0.45,0.00117"]
    text += [",".join([r[0], *(f"{x:.6g}" for x in r[1:])]) for r in rows[10:]]
    text += ["bad3,63.5,177.8,19,-0.45,0.00117", "bad4,63.5,177.8,19"]
    return rows, text


def _exact(problem, row) -> float:
    """P(V_c,true < V_req) of a measured caster (its values as the CSV writes them) by the exact law, 32 nodes a side."""
    row = [row[0], *(float(f"{x:.6g}") for x in row[1:])]
    theta0 = float(problem.conditions.disturbance_angle)
    return float(
        shimmy_probability_exact(
            row[1] / 1e3,
            row[5],
            row[3] / 1e3,
            row[4] / theta0,
            float(problem.conditions.slip_coefficient),
            problem.required_speed,
            problem.risk,
            None,
            None,
            32,
        )
    )


def test_inspect_grades_each_caster_by_the_exact_law_and_names_bad_rows(indoor, tmp_path, capsys):
    """designer inspect --json on 22 measured casters and 4 bad rows: one entry per good row in file order; each P is
    the exact law's (32 nodes) to 1e-8 relative, pass is P <= α; every caster inside the joint box passes, while
    casters inside every one-at-a-time limit fail (the issue's finding); a caster with one part off nominal names
    that part as the driver; the lot counts and its worst caster agree with the entries; the 4 bad rows are named
    one per line (row, column, reason) on stderr; exit 2; the file's bytes are unchanged."""
    from designer.cli import main

    problem, rec = indoor
    rows, text = _lot(rec)
    path = tmp_path / "measured.csv"
    path.write_text("\n".join(text) + "\n", encoding="utf-8")
    before = hashlib.sha256(path.read_bytes()).hexdigest()
    assert main(["inspect", str(PROBLEM), str(path), "--json"]) == 2
    out, err = capsys.readouterr()
    assert hashlib.sha256(path.read_bytes()).hexdigest() == before
    data = json.loads(out)
    casters = data["casters"]
    assert [c["serial"] for c in casters] == [r[0] for r in rows] and len(casters) == 22
    alpha = float(problem.risk.probability)
    for c, r in zip(casters, rows):
        assert c["shimmy_probability"] == pytest.approx(_exact(problem, r), rel=1e-8, abs=1e-14)
        assert c["pass"] == (c["shimmy_probability"] <= alpha)
        if c["in_joint_box"]:
            assert c["pass"], c["serial"]
    by = {c["serial"]: c for c in casters}
    assert all(by[f"in{k}"]["in_joint_box"] for k in range(6))
    assert by["in5"]["shimmy_probability"] > 0.9 * alpha  # the box's corner is near α: not needlessly small
    assert by["box-t"]["in_joint_box"] and not by["box-t"]["in_one_at_a_time"] and by["box-t"]["pass"]
    assert by["oat-all"]["in_one_at_a_time"] and not by["oat-all"]["in_joint_box"] and not by["oat-all"]["pass"]
    assert by["oat-mi"]["in_one_at_a_time"] and not by["oat-mi"]["in_joint_box"]
    assert not any(by[f"out{k}"]["in_joint_box"] or by[f"out{k}"]["pass"] for k in range(3))
    assert [by[s]["driver"] for s in ("only-t", "only-b", "only-m", "only-i")] == [
        "trail",
        "groove",
        "friction_moment",
        "wheel_inertia",
    ]
    assert by["big-d"]["fits_footrest"] is False and by["in0"]["fits_footrest"] is True
    lot = data["lot"]
    assert lot["graded"] == 22 and lot["passed"] == sum(c["pass"] for c in casters) and lot["bad_rows"] == 4
    worst = max(casters, key=lambda c: c["shimmy_probability"])
    assert lot["worst"]["serial"] == worst["serial"]
    assert lot["fraction_above_alpha"] == pytest.approx(1 - lot["passed"] / 22)
    lines = err.strip().splitlines()
    assert lines == [
        f"{path}: row 12, column trail_mm: 'abc' is not a number",
        f"{path}: row 13, column groove_mm: empty",
        f"{path}: row 26, column friction_moment_N_m: -0.45 must be a positive number",
        f"{path}: row 27, column (row): 4 cells, the header has 6",
    ]


def test_inspect_text_and_exit_0_without_bad_rows(indoor, tmp_path, capsys):
    """Without bad rows the text verdict exits 0 and states the lot (passes, worst caster, fraction above α)."""
    from designer.cli import main

    problem, rec = indoor
    rows, text = _lot(rec)
    path = tmp_path / "good.csv"
    path.write_text("\n".join(t for t in text if not t.startswith("bad")) + "\n", encoding="utf-8")
    assert main(["inspect", str(PROBLEM), str(path)]) == 0
    out = " ".join(capsys.readouterr().out.split())  # the terminal's line breaks joined
    assert "Lot: " in out and " of 22 pass; worst " in out and "fraction above α" in out
    assert "FAIL" in out and "pass" in out


def test_template_is_the_empty_form_in_the_problems_units_and_never_overwrites(tmp_path, capsys):
    """--template writes the header in the problem's units (indoor-manual: inches), which designer inspect reads back
    (a form with no rows grades nothing, exit 0); a second --template over the same file is refused with exit 7 and
    leaves it byte for byte; a header with an unknown column is one line, exit 2."""
    from designer.cli import main

    form = tmp_path / "form.csv"
    assert main(["inspect", str(PROBLEM), "--template", str(form)]) == 0
    body = form.read_bytes()
    header = [ln for ln in body.decode().splitlines() if not ln.startswith("#")]
    assert header == ["serial,trail_in,diameter_in,groove_in,friction_moment_N_m,wheel_inertia_kg_m2"]
    assert main(["inspect", str(PROBLEM), "--template", str(form)]) == 7
    assert form.read_bytes() == body
    assert "already exists" in capsys.readouterr().err
    bad = tmp_path / "bad.csv"
    bad.write_text("serial,trial_mm,groove_mm,friction_moment_N_m,wheel_inertia_kg_m2\n", encoding="utf-8")
    assert main(["inspect", str(PROBLEM), str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "column 'trial_mm': unknown column" in err[0]
