"""Calibration of k_surface (Fig. 7), c_f (Eq. 7, Fig. 2C) and K_s (Eq. 12C, Fig. 3C) from CSV data."""

from __future__ import annotations

import json
import tomllib

import numpy as np
import pytest

from designer.studies.calibrate import EXAMPLES_DIR, calibrate_file, fit_damping, read_columns, write_examples
from designer.cli import main
from designer.report.agreement import compare_text
from designer.errors import InputError
from designer.problem import SCHEMA


def test_examples_regenerate_identically(tmp_path):
    """write_examples(seed 7) reproduces the shipped example CSVs: the same header, rows and text, every number at
    its printed precision (6 significant digits: one unit of the last digit, as another CPU may round it;
    designer.report.agreement.compare_text), and a shipped value changed in its 4th digit is caught."""
    paths = write_examples(tmp_path)
    for path in paths.values():
        shipped = (EXAMPLES_DIR / path.name).read_text()
        assert compare_text(shipped, path.read_text(), path.name, markup=False) == [], path.name
    shipped = (EXAMPLES_DIR / "slip.csv").read_text()
    assert compare_text(shipped.replace("16.4727", "16.4827"), paths["slip"].read_text(), markup=False)


def test_turning_recovers_k_tile():
    """Drill-press example (k_tile = 0.005 m, σ = 0.03 N·m): the 95 % interval contains 0.005 m and
    is narrower than ±5 %."""
    r = calibrate_file("turning", EXAMPLES_DIR / "turning_tile.csv")
    lo, hi = r.interval
    assert lo < 0.005 < hi
    assert (hi - lo) / 2 < 0.05 * 0.005


def test_slip_recovers_ks():
    """Treadmill example (K_s = 1250 N, σ = 4 N): the 95 % interval contains 1250 N."""
    r = calibrate_file("slip", EXAMPLES_DIR / "slip.csv")
    assert r.interval[0] < 1250 < r.interval[1]
    assert r.value == pytest.approx(1250, rel=0.05)


def test_damping_example_within_three_standard_errors():
    """Shipped Fig. 2C-like example (c_f = 1.3, 5 % speed noise, seed 7): this draw is low, 1.222 with
    95 % interval 1.156–1.287 (1.3 lies 2.5 standard errors away); assert |c_f − 1.3| < 3 SE and 8 %."""
    r = calibrate_file("damping", EXAMPLES_DIR / "damping.csv")
    assert abs(r.value - 1.3) < 3 * r.stderr
    assert r.value == pytest.approx(1.3, rel=0.08)


def test_damping_interval_coverage(tmp_path):
    """Over 30 seeds of the damping example the 95 % interval contains c_f = 1.3 in at least 80 % of
    fits (binomial: 95 % nominal gives ≥ 80 % with probability > 0.99)."""
    hits = 0
    for seed in range(30):
        paths = write_examples(tmp_path / str(seed), seed=seed)
        r = calibrate_file("damping", paths["damping"])
        hits += r.interval[0] <= 1.3 <= r.interval[1]
    assert hits >= 24


def test_damping_noise_free_exact():
    """Noise-free Eq. 7 speeds (with grooves and K_s = 1000 N) give back c_f = 2.0 to 1e-6."""
    from designer.physics.shimmy import critical_shimmy_speed

    T = np.array([0.04, 0.05, 0.06, 0.05])
    inertia = np.array([1e-3, 2e-3, 1.5e-3, 1e-3])
    B = np.array([0.0, 0.0, 0.01, 0.014])
    v = critical_shimmy_speed(T, inertia, B, 2.0, 1000.0)
    assert fit_damping(T, inertia, v, B, slip_coefficient=1000.0).value == pytest.approx(2.0, rel=1e-6)


def test_snippets_use_problem_keys(tmp_path):
    """Each snippet is valid TOML whose sections/keys are accepted by designer.problem."""
    for kind, name in (("turning", "turning_tile"), ("slip", "slip"), ("damping", "damping")):
        data = tomllib.loads(calibrate_file(kind, EXAMPLES_DIR / f"{name}.csv").snippet())
        for section, values in data.items():
            assert set(values) <= set(SCHEMA[section])
    turning = tomllib.loads(calibrate_file("turning", EXAMPLES_DIR / "turning_tile.csv").snippet())
    assert turning["turning"]["tile_moment_per_load"].endswith(" m")


@pytest.mark.parametrize(
    "text, message",
    [
        ("load_N,moment\n1,2\n2,3\n3,4\n", "missing column 'moment_Nm'"),
        ("load_N,moment_Nm\n1,2\n2,abc\n3,4\n", "row 3, column 'moment_Nm': 'abc' is not a number"),
        ("load_N,moment_Nm\n1,2\n2,nan\n3,4\n", "row 3, column 'moment_Nm': 'nan' is not finite"),
        ("load_N,moment_Nm\n1,2\n2,3\n", "2 data rows; the fit needs at least 3"),
        ("load_N,moment_Nm\n1,2\n2,\n3,4\n", "row 3, column 'moment_Nm': empty cell"),
        ("", "empty file"),
    ],
)
def test_bad_csv_one_line_error(tmp_path, text, message):
    """Bad CSVs raise one-line InputErrors naming the file, the column/row and the reason."""
    path = tmp_path / "data.csv"
    path.write_text(text)
    with pytest.raises(InputError) as info:
        read_columns(path, ("load_N", "moment_Nm"))
    assert message in str(info.value) and str(path) in str(info.value) and "\n" not in str(info.value)


def test_missing_file_cli(capsys, tmp_path):
    """`designer calibrate turning missing.csv` exits 2 with one line 'no such CSV file' (the readers' shared
    words, designer.textfiles.read_input_text)."""
    code = main(["calibrate", "turning", str(tmp_path / "missing.csv")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.endswith("missing.csv: no such CSV file") and "\n" not in err


def test_cli_json_plot_snippet(capsys, tmp_path):
    """`designer calibrate slip --json --plot --snippet` gives value and a 2-element interval, writes a
    PNG and a snippet with [shimmy] slip_coefficient."""
    plot, snippet = tmp_path / "res.png", tmp_path / "ks.toml"
    code = main(
        ["calibrate", "slip", str(EXAMPLES_DIR / "slip.csv"), "--json", "--plot", str(plot), "--snippet", str(snippet)]
    )
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert out["interval"][0] < out["value"] < out["interval"][1]
    assert plot.stat().st_size > 5000
    assert "slip_coefficient" in tomllib.loads(snippet.read_text())["shimmy"]


def test_cli_report_folder(capsys, tmp_path):
    """`designer calibrate turning --report DIR` writes index.html (figure inline), report.md and calibration.json
    whose summary states the fitted value and interval of the JSON."""
    out = tmp_path / "cal"
    code = main(["calibrate", "turning", str(EXAMPLES_DIR / "turning_tile.csv"), "--report", str(out), "--json"])
    assert code == 0
    data = json.loads((out / "calibration.json").read_text())
    html = (out / "index.html").read_text()
    lo, hi = data["interval"]
    assert f"{data['value']:.5g}" in html and f"{lo:.5g} to {hi:.5g}" in html
    assert "data:image/png;base64," in html and (out / "figures" / "fit.png").stat().st_size > 5000
    assert (out / "report.md").read_text().startswith("# Calibration of ")
    assert json.loads(capsys.readouterr().out)["report"] == str(out)


@pytest.mark.parametrize(
    "kind, text, column",
    [
        ("slip", "slip_ratio,force_N\n0,0\n0,0\n0,0\n", "'slip_ratio'"),
        ("slip", "slip_ratio,force_N\n0.01,-12\n0.02,-25\n0.03,-37\n", "'force_N' against 'slip_ratio'"),
        ("slip", "slip_ratio,force_N\n1e-200,12\n2e-200,25\n3e-200,37\n", "'force_N' against 'slip_ratio'"),
        ("slip", "slip_ratio,force_N\n5,12\n10,25\n15,37\n", "'slip_ratio'"),
        ("turning", "load_N,moment_Nm\n100,0\n200,0\n300,0\n", "'moment_Nm' against 'load_N'"),
        ("turning", "load_N,moment_Nm\n1e300,1\n2e300,2\n3e300,3\n", "'load_N'"),
        (
            "damping",
            "trail_m,inertia_kgm2,critical_speed_mps\n1e-9,0.001,2\n2e-9,0.001,2.1\n1e-9,0.001,2.2\n",
            "'trail_m'",
        ),
        ("damping", "trail_m,inertia_kgm2,critical_speed_mps\n1e300,1e300,1e300\n1,1,1\n1,1,1\n", "'trail_m'"),
        (
            "damping",
            "trail_m,inertia_kgm2,critical_speed_mps\n0.05,1e-320,2\n0.05,1e-320,2\n0.05,1e-320,2\n",
            "'inertia_kgm2'",
        ),
        (
            "damping",
            "trail_m,inertia_kgm2,critical_speed_mps\n0.05,0.001,0.02\n0.06,0.001,0.02\n0.05,0.002,0.02\n",
            "'trail_m'",
        ),
    ],
)
def test_result_outside_the_model_is_an_error_naming_the_column(tmp_path, capsys, kind, text, column):
    """Issue 24.4: data whose fit is not finite or outside the parameter table's range of the constant (zero
    slip ratios gave "nan N", negative forces -1235.71 N, a tiny trail 2e15 N·m/rad, huge values overflow
    warnings and exit 70) end with exit 2 and one line naming the data column, no warning line, and no
    snippet written."""
    data, snippet = tmp_path / "data.csv", tmp_path / "snippet.toml"
    data.write_text(text)
    code = main(["calibrate", kind, str(data), "--snippet", str(snippet)])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and err.startswith("designer: error:") and column in err, err
    assert not snippet.exists()


def test_every_snippet_written_loads(tmp_path):
    """Issue 24.4, the rule itself: over 60 seeded slip and turning data sets of any sign and scale (1e-8 to
    1e8), a fit either fails with an InputError naming the file, or gives a snippet that the problem loader
    accepts on top of a shipped problem (never one it refuses)."""
    from designer.problem import problem_from_dict

    base = tomllib.loads((EXAMPLES_DIR.parents[2] / "problems" / "indoor-manual.toml").read_text())
    rng = np.random.default_rng(3)
    written = refused = 0
    for i in range(60):
        kind = ("slip", "turning")[i % 2]
        x = rng.uniform(0.005, 0.08, 5) if kind == "slip" else rng.uniform(50, 250, 5)
        y = x * 10.0 ** rng.uniform(-8, 8) * rng.choice([-1.0, 1.0]) * (1 + rng.normal(0, 0.05, 5))
        header = "slip_ratio,force_N" if kind == "slip" else "load_N,moment_Nm"
        y = np.abs(y) if kind == "turning" else y  # moments are non-negative (a row check of its own)
        path = tmp_path / f"{i}.csv"
        path.write_text(header + "\n" + "\n".join(f"{float(a)!r},{float(b)!r}" for a, b in zip(x, y)) + "\n")
        try:
            snippet = calibrate_file(kind, path).snippet()
        except InputError as exc:
            assert str(path) in str(exc) and "\n" not in str(exc)
            refused += 1
            continue
        merged = {**base, **{k: {**base.get(k, {}), **v} for k, v in tomllib.loads(snippet).items()}}
        problem_from_dict(merged, source=str(path))
        written += 1
    assert written >= 5 and refused >= 5
