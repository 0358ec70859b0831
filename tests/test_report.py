"""Pareto reports (docs/commands.md#reports): the committed results/ are reproducible, the HTML is
self-contained and escaped, writes are atomic, and ``designer pareto`` writes every file."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest

from designer import load_problem
from designer.cli import main
from designer.plots import figures
from designer.pipeline import report_data
from designer.report import write_report

ROOT = Path(__file__).resolve().parents[1]
COMMITTED = ROOT / "results" / "indoor-manual"
FILES = ("index.html", "report.md", "front.csv", "front.json", "checks.json")
FIGURES = tuple(f"figures/{name}.png" for name in figures.FIGURES)
OBJECTIVES_RTOL = 1e-5
"""Regenerated front objectives must match the committed ones to this relative tolerance."""


@pytest.fixture(scope="module")
def regenerated(tmp_path_factory) -> tuple[Path, int]:
    """``designer pareto problems/indoor-manual.toml`` into a temporary folder (the committed report's command)."""
    out = tmp_path_factory.mktemp("pareto") / "indoor-manual"
    code = main(["pareto", str(ROOT / "problems" / "indoor-manual.toml"), "--out", str(out)])
    return out, code


@pytest.fixture(scope="module")
def invacare():
    """The report data of the paper's Invacare wheel (fixed diameter, single-point front): fast to compute."""
    problem = load_problem(ROOT / "problems" / "paper-invacare.toml")
    return problem, report_data(problem)


def _read_csv(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_cli_writes_every_file(regenerated, capsys):
    """`designer pareto` exits 0 (every check passes on indoor-manual) and writes the report files and figures."""
    out, code = regenerated
    assert code == 0
    for name in FILES + FIGURES:
        assert (out / name).is_file(), name
        assert (out / name).stat().st_size > 0, name
    data = json.loads((out / "front.json").read_text())
    for key in ("caster-designer", "numpy", "scipy", "casadi", "cvxpy", "optuna"):
        assert data["run"]["versions"][key], key
    assert data["run"]["problem_digest"] == load_problem(ROOT / "problems" / "indoor-manual.toml").digest()
    assert data["run"]["wall_seconds"] > 0 and data["run"]["date"]


def test_committed_results_are_current(regenerated):
    """results/indoor-manual matches a fresh run: front.csv objectives within 1e-5, the same check verdicts."""
    out, _ = regenerated
    assert COMMITTED.is_dir(), "results/indoor-manual is missing: run python -m designer.commands.regenerate"
    new, old = _read_csv(out / "front.csv"), _read_csv(COMMITTED / "front.csv")
    assert len(new) == len(old), "number of front points changed: regenerate results/"
    for column in ("turning_effort", "threshold_force"):
        a = np.array([float(r[column]) for r in new])
        b = np.array([float(r[column]) for r in old])
        np.testing.assert_allclose(a, b, rtol=OBJECTIVES_RTOL, err_msg=f"{column}: regenerate results/")
    verdict = lambda path: {c["name"]: c["passed"] for c in json.loads(path.read_text())}  # noqa: E731
    assert verdict(out / "checks.json") == verdict(COMMITTED / "checks.json")


def test_html_is_self_contained(regenerated):
    """index.html loads nothing from the network: no http(s) src/href, no external CSS/JS, all figures inline."""
    out, _ = regenerated
    html = (out / "index.html").read_text()
    assert not re.search(r"""(src|href)\s*=\s*["']?\s*(https?:)?//""", html, re.I)
    assert "<link" not in html.lower() and "<script" not in html.lower()
    images = re.findall(r"<img[^>]+src=\"([^\"]+)\"", html)
    assert len(images) == len(figures.FIGURES)
    assert all(src.startswith("data:image/png;base64,") for src in images)


def test_main_job_computes_the_knock_safe_speeds_of_the_card(regenerated):
    """`designer pareto` simulates the knock-safe speeds of the recommendation and its alternatives only
    (θ0 and 2 θ0 knocks, m/s in front.json, the 2 θ0 one lower), times the step, and the card shows them."""
    out, _ = regenerated
    data = json.loads((out / "front.json").read_text())
    rec = data["recommendation"]
    assert 0 < rec["knock_safe_speed_double"] < rec["knock_safe_speed"]
    assert rec["knock_safe_speed"] == pytest.approx(rec["critical_speed"], rel=0.05)
    assert all("knock_safe_speed" in a for a in data["alternatives"])
    assert "knock_safe_speed" not in data["points"][0]
    assert data["run"]["compute_cpu_seconds"]["knock_safe"] > 0
    assert (
        f"{rec['knock_safe_speed']:.2f} / {rec['knock_safe_speed_double']:.2f} m/s" in (out / "report.md").read_text()
    )


def test_no_nan_anywhere(regenerated):
    """No NaN in a report: tables, Markdown, CSV and JSON."""
    out, _ = regenerated
    for name in FILES:
        text = (out / name).read_text()
        assert not re.search(r"\bnan\b|\binf\b", text, re.I), name


def test_title_is_escaped(invacare, tmp_path):
    """User text is shown as text: a <script> title is escaped in index.html and report.md."""
    import dataclasses

    problem, data = invacare
    evil = problem.replace(title='<script>alert("x")</script> & co')
    folder = write_report(dataclasses.replace(data, problem=evil), tmp_path / "r")
    html = (folder / "index.html").read_text()
    assert "<script>" not in html
    assert "&lt;script&gt;" in html
    assert "<script>" not in (folder / "report.md").read_text()


def test_single_point_front_explained(invacare, tmp_path):
    """A fixed-diameter problem has a one-point front; the report says why and still has every figure."""
    problem, data = invacare
    assert len(data.front) == 1
    folder = write_report(data, tmp_path / "inv")
    html = (folder / "index.html").read_text()
    assert "Why the front is a single point" in html and "fixed at 7.750 in" in html
    assert all((folder / f).is_file() for f in FIGURES)


def test_failed_write_leaves_nothing(invacare, tmp_path, monkeypatch):
    """An exception while writing leaves no report folder and no temporary folder; an old report stays intact."""
    problem, data = invacare

    def broken(*args, **kwargs):
        raise RuntimeError("figure failed")

    monkeypatch.setattr(figures, "figure_threshold", broken)
    with pytest.raises(RuntimeError, match="figure failed"):
        write_report(data, tmp_path / "new")
    assert list(tmp_path.iterdir()) == []
    # an existing report is not touched by a failed rewrite
    old = tmp_path / "old"
    old.mkdir()
    (old / "index.html").write_text("previous report")
    (old / "front.json").write_text('{"problem": "old", "points": []}')  # a previous report of this tool
    with pytest.raises(RuntimeError):
        write_report(data, old)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old"]
    assert (old / "index.html").read_text() == "previous report"


def test_cli_exit_1_when_a_front_check_fails(tmp_path, monkeypatch, capsys):
    """A failing check 8 gives exit 1, after the report is written (docs/commands.md)."""
    import designer.analysis.checks as checks

    real = checks.front_checks

    def failing(front, tighter=None, **kw):
        out = real(front, tighter, **kw)
        out[0].passed = False
        return out

    monkeypatch.setattr(checks, "front_checks", failing)
    out = tmp_path / "inv"
    code = main(["pareto", str(ROOT / "problems" / "paper-invacare.toml"), "--out", str(out)])
    assert code == 1
    assert (out / "index.html").is_file()
    assert "check failed on the front" in capsys.readouterr().err
    verdicts = {c["name"]: c["passed"] for c in json.loads((out / "checks.json").read_text())}
    assert verdicts["8a trade-off"] is False
