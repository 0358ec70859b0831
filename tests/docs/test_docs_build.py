"""The documentation site builds with `mkdocs build --strict` (README, CONTRIBUTING): a broken link, a
reference to a name that no longer exists, or a docstring the API reference cannot parse fails the suite."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("mkdocs", reason="the docs extra (mkdocs, mkdocstrings[python]) is not installed")
pytest.importorskip("mkdocstrings_handlers.python", reason="mkdocstrings[python] is not installed")

ROOT = Path(__file__).resolve().parents[2]


def test_mkdocs_build_strict(tmp_path):
    """`mkdocs build --strict` exits 0 without a warning, and the API pages hold the public names' docstrings."""
    site = tmp_path / "site"
    run = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(site)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, f"mkdocs build --strict failed:\n{run.stdout}\n{run.stderr}"
    assert "WARNING" not in run.stderr, run.stderr
    front = (site / "api" / "front" / "index.html").read_text(encoding="utf-8")
    assert "pareto_front" in front and "Minimise J" in front  # optimise's docstring, rendered
    problems = (site / "api" / "problem" / "index.html").read_text(encoding="utf-8")
    assert "example_problem" in problems and "ProblemError" in problems
    assert (site / "how-to" / "run-a-problem" / "index.html").exists()
    assert (site / "examples" / "design-a-caster.ipynb").exists()


def test_api_reference_covers_the_public_names():
    """Every name of ``designer.__all__`` has a `::: designer.NAME` line (or `::: <defining module>.NAME`) in
    docs/api/, so a new public name does not go undocumented."""
    import designer

    lines = {
        line.strip()
        for p in (ROOT / "docs" / "api").glob("*.md")
        for line in p.read_text(encoding="utf-8").splitlines()
    }
    lazy = designer._LAZY
    missing = [
        name
        for name in designer.__all__
        if f"::: designer.{name}" not in lines and f"::: {lazy.get(name)}.{name}" not in lines
    ]
    assert missing == [], f"add `::: designer.NAME` for {missing} to a page of docs/api/"


def test_mkdocs_is_the_documented_command():
    """README and CONTRIBUTING give the one build command, and mkdocs.yml is strict."""
    for doc in ("README.md", "CONTRIBUTING.md"):
        assert "mkdocs build --strict" in (ROOT / doc).read_text(encoding="utf-8"), doc
    assert "strict: true" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
