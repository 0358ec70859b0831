"""The benchmark suite runs (issue 23.4): ``python -m benchmarks.run --quick`` on the current code, as a smoke test.

Nothing here times anything: the test checks that the quick run exits 0 and writes its tables with every method
row and every column, so the benchmark cannot rot unnoticed again (it once exec'd a module from git history).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PROBLEMS = ("indoor-manual", "sports-court", "powered-chair")
COLUMNS = "| method | time | model evaluations / NLP solves | HV / HV_exact101 | IGD+ | points |"


def _methods(quick: dict) -> list[str]:
    """The rows every problem's table must have, from the run's own configuration."""
    grid = "×".join(str(n) for n in quick["grid"])
    return (
        [f"exact front N={n}" for n in quick["points"]]
        + [f"pymoo NSGA-II {g} gen" for g in quick["pymoo_generations"]]
        + [
            f"optuna NSGA-II {label} {trials}"
            for trials in quick["optuna_trials"]
            for label in ("defaults", "best operators")
        ]
        + ["scipy SLSQP ε-loop (101 ε)", f"dense grid {grid}"]
    )


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    """``python -m benchmarks.run --quick --out <tmp>`` from the repository root, on this checkout's package."""
    out = tmp_path_factory.mktemp("bench")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks.run", "--quick", "--out", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    return proc, out


def test_quick_benchmark_exits_0_and_writes_its_files(quick_run):
    """The quick run exits 0 and writes results.md, results.json and scaling.png (non-empty)."""
    proc, out = quick_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    for name in ("results.md", "results.json", "scaling.png"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name


def test_quick_benchmark_table_has_every_method_and_column(quick_run):
    """Per problem, results.md has the table header and one row of 6 cells per method (exact fronts, pymoo,
    optuna, SLSQP, grid); results.json has the same methods, each with its HV ratio and IGD+; the exact
    101-point front is its own reference (HV ratio 1, IGD+ 0)."""
    proc, out = quick_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    text = (out / "results.md").read_text(encoding="utf-8")
    data = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert data["quick"] is True
    quick = data["config"]  # the budgets the run used (benchmarks.run.QUICK)
    sections = text.split("\n## ")
    for name in PROBLEMS:
        section = next(s for s in sections if s.startswith(name + "\n"))
        assert COLUMNS in section, name
        rows = {line.split(" | ")[0].lstrip("| "): line for line in section.splitlines() if line.startswith("| ")}
        for method in _methods(quick):
            assert method in rows, (name, method)
            assert rows[method].count("|") == 7, rows[method]  # 6 cells
        methods = data["problems"][name]["methods"]
        assert set(_methods(quick)) <= set(methods), name
        for method in _methods(quick):
            assert 0.0 <= methods[method]["hv_ratio"] and methods[method]["igd_plus"] >= 0.0, (name, method)
        reference = methods["exact front N=101"]  # its own reference: equal up to the rounding of the HV sums
        assert reference["hv_ratio"] == pytest.approx(1.0, abs=1e-12) and reference["igd_plus"] <= 1e-12


def test_quick_benchmark_quotes_the_before_numbers(quick_run):
    """The "before" speed of the old exact front is quoted from the committed benchmarks/results.json (the old
    code is not run): the quick run's before/after line carries the committed ms per point and commit."""
    proc, out = quick_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    committed = json.loads((ROOT / "benchmarks" / "results.json").read_text(encoding="utf-8"))
    data = json.loads((out / "results.json").read_text(encoding="utf-8"))
    text = (out / "results.md").read_text(encoding="utf-8")
    for name in PROBLEMS:
        before = committed["problems"][name]["legacy"]["ms_per_point_before"]
        quoted = data["problems"][name]["legacy"]
        assert quoted["ms_per_point_before"] == before and quoted["commit"] == "085d726"
        assert f"{before:.2f} ms per point before (commit 085d726" in text


def test_a_full_run_keeps_the_other_benchmarks_sections(tmp_path):
    """benchmarks.run writes its part of results.md between its own markers and keeps the sections the other
    benchmarks write (cold start, main job, fleet, studio latency) and the text between them: a first run over a
    file without its markers replaces only what comes before the first other section, a second run only its block."""
    from benchmarks.run import BEGIN, END, write_markdown

    path = tmp_path / "results.md"
    others = "<!-- coldstart: begin -->\nC\n<!-- coldstart: end -->\nnotes\n<!-- studio latency: begin -->\nS\n"
    others += "<!-- studio latency: end -->\n"
    path.write_text("# Benchmarks\nold tables\n\n" + others, encoding="utf-8")
    write_markdown(path, "# Benchmarks\nfirst")
    assert path.read_text(encoding="utf-8") == f"{BEGIN}\n# Benchmarks\nfirst\n{END}\n\n{others}"
    write_markdown(path, "# Benchmarks\nsecond")
    assert path.read_text(encoding="utf-8") == f"{BEGIN}\n# Benchmarks\nsecond\n{END}\n\n{others}"


def test_the_shown_summary_is_the_saved_runs_ratios():
    """benchmarks.run --show prints, from the committed results.json, each method's speed ratio against the exact
    101-point front and its hypervolume ratio as ranges over the problems (the numbers docs/benchmarks.md shows),
    each line at most 80 characters."""
    from benchmarks.run import show

    results = json.loads((ROOT / "benchmarks" / "results.json").read_text(encoding="utf-8"))
    lines = show(results)
    assert all(len(line) <= 80 for line in lines)
    problems = results["problems"]
    ratios = [
        p["methods"]["pymoo NSGA-II 300 gen"]["warm" if "warm" in p["methods"]["pymoo NSGA-II 300 gen"] else "time"][
            "median_s"
        ]
        / p["methods"]["exact front N=101"]["warm"]["median_s"]
        for p in problems.values()
    ]
    row = next(line for line in lines if "pymoo NSGA-II 300 gen" in line)
    assert f"{min(ratios):.0f}–{max(ratios):.0f}× faster" in row or f"{min(ratios):.0f}× faster" in row


def test_quick_benchmark_reports_the_speed_guards(quick_run):
    """The quick run measures the speed guards of issue 44 (benchmarks.speed): the numpy import, the main job and
    the spec batch, each with a positive CPU and its ratio to the numpy import, and prints them in its tables."""
    proc, out = quick_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    runs = json.loads((out / "results.json").read_text(encoding="utf-8"))["speed"]["runs"]
    assert set(runs) == {"numpy import", "after: main job", "after: spec batch"}
    numpy_cpu = runs["numpy import"]["cpu"]
    for r in runs.values():
        assert r["cpu"] > 0 and r["x_numpy"] == pytest.approx(r["cpu"] / numpy_cpu)
    text = (out / "results.md").read_text(encoding="utf-8")
    assert "main job (pareto)" in text and "spec batch (fix, 329)" in text


def _speed_run() -> dict:
    """A made-up benchmarks.speed result with a before checkout (numbers chosen to check the arithmetic)."""
    runs = {
        "numpy import": {"cpu": 0.2, "cpu_range": [0.19, 0.21], "wall": 0.3},
        "after: main job": {"cpu": 1.4, "cpu_range": [1.3, 1.5], "wall": 2.0},
        "after: spec batch": {"cpu": 1.2, "cpu_range": [1.1, 1.3], "wall": 1.5},
        "before: main job": {"cpu": 2.0, "cpu_range": [1.9, 2.1], "wall": 2.5},
        "before: spec batch": {"cpu": 20.0, "cpu_range": [19.0, 21.0], "wall": 22.0},
    }
    for name, r in runs.items():
        r["x_numpy"] = r["cpu"] / 0.2
        if name.startswith("after: "):
            r["x_before"] = r["cpu"] / runs["before: " + name[7:]]["cpu"]
    return {
        "date": "2026-12-07T14:00:00+00:00",
        "cpus": 2,
        "repeats": 3,
        "before": "/tmp/before",
        "load_start": [1.5, 1.0, 1.0],
        "load_end": [2.0, 1.0, 1.0],
        "runs": runs,
        "studio": {"date": "2026-12-05T12:01:11+00:00", "redraw_ms": {"before": 406.0, "after": 242.0}},
    }


def test_speed_summary_shows_each_figure_with_its_ratio():
    """benchmarks.speed's summary (docs/benchmarks.md's block) states the main job as 7.0 x the numpy import
    (1.4 s / 0.2 s), the spec batch's CPU, the after/before ratios 0.70 and 0.060, and the studio medians; every
    line at most 80 characters."""
    from benchmarks.speed import summary

    lines = summary(_speed_run())
    text = "\n".join(lines)
    assert all(len(line) <= 80 for line in lines)
    assert "1.40 =  7.0 x numpy" in text and "1.20" in text
    assert "after/before 0.70" in text and "after/before 0.060" in text
    assert "before 406 ms, after 242 ms" in text


def test_speed_section_replaces_only_its_block(tmp_path, monkeypatch):
    """benchmarks.speed --write puts its table between its markers in results.md (appended the first time,
    replaced after), keeping the other sections, and saves the run to speed.json."""
    from benchmarks import speed

    results, saved = tmp_path / "results.md", tmp_path / "speed.json"
    results.write_text("<!-- main job: begin -->\nM\n<!-- main job: end -->\n", encoding="utf-8")
    monkeypatch.setattr(speed, "RESULTS", results)
    monkeypatch.setattr(speed, "SAVED", saved)
    speed.write(_speed_run())
    speed.write(_speed_run())
    text = results.read_text(encoding="utf-8")
    assert text.startswith("<!-- main job: begin -->\nM\n<!-- main job: end -->\n")
    assert text.count(speed.BEGIN) == 1 and text.count(speed.END) == 1
    assert "| 1.40 [1.30–1.50] | 7.0 | 0.70 |" in text
    assert json.loads(saved.read_text(encoding="utf-8"))["runs"]["after: main job"]["cpu"] == 1.4
