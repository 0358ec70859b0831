"""The how-to pages' Python runs as written (docs/how-to/*.md and docs/index.md; examples in the docs are tests).

Each page's ```python blocks run in order in one namespace, in an empty temporary folder (as a reader would
paste them into a fresh session), and must not raise; a few printed facts are checked per page.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HOWTO = ROOT / "docs" / "how-to"
PAGES = sorted(HOWTO.glob("*.md")) + [ROOT / "docs" / "index.md"]

EXPECTED = {
    "index.md": [r"trail T\s+\d\.\d{3} in"],
    "run-a-problem.md": [r"Problem\('indoor-manual'", r"trail T\s+\d\.\d{3} in", r"index\.html"],
    "compare-fronts.md": [r"hypervolume \d\.\d{3} \(2\.5 m/s\) vs \d\.\d{3} \(3 m/s\)", r"3\.0 m/s: knee"],
    "calibrate.md": [r"K_s = \d+ N \(95 % CI", r"slip_coefficient = \"", r"c_f = \d\.\d{3} N·m/rad"],
    "retrofit.md": [r"now: V_c \d\.\d\d m/s", r"^1\. .*->"],
    "share-a-study.md": [r"14 trials \(4 new\)", r"^14 trials;"],
}
"""Facts each page's output must show (regular expressions, multiline)."""

FILES = {
    "run-a-problem.md": ["caster.png", "front.png", "my-report/index.html"],
    "compare-fronts.md": ["fronts.png"],
    "calibrate.md": ["treadmill.csv"],
    "share-a-study.md": ["study.db"],
}
"""Files each page writes into its folder."""


def python_blocks(page: Path) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", page.read_text(encoding="utf-8"), flags=re.S | re.M)


def test_every_howto_page_is_listed_and_has_code():
    """The five tasks of issue 17 each have a page with Python in it (the home page too), and the test knows
    every page."""
    names = {p.name for p in PAGES}
    assert names == set(EXPECTED)
    assert all(python_blocks(p) for p in PAGES)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.stem)
def test_howto_page_runs(page, tmp_path, monkeypatch):
    """Every ```python block of the page runs in a fresh folder without error, prints the page's facts and
    writes its files (figures, report, study)."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")  # a figure window would block; the pages save their figures to files
    namespace: dict = {"__name__": "__howto__"}
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        for number, block in enumerate(python_blocks(page), 1):
            exec(compile(block, f"{page.name} block {number}", "exec"), namespace)
    text = out.getvalue()
    for pattern in EXPECTED[page.name]:
        assert re.search(pattern, text, flags=re.M), f"{page.name}: no {pattern!r} in its output:\n{text[-2000:]}"
    for name in FILES.get(page.name, []):
        assert (tmp_path / name).stat().st_size > 0, f"{page.name} did not write {name}"


# ----------------------------------------------------------------------------------------------------
# Issue 12.6: the docs ship with the package's source; every problem-file key the loader accepts is
# documented, and code and report templates cite docs/, not an internal spec.

from designer.problem import SCHEMA

from conftest import ROOT


def test_every_loader_key_is_in_the_problem_file_reference():
    """Each key of designer.problem.SCHEMA appears in docs/problem-file.md as `section.key`
    (top-level keys as `key`); a key added to the loader without its documentation fails here."""
    text = (ROOT / "docs" / "problem-file.md").read_text(encoding="utf-8")
    missing = [
        f"{section}.{key}" if section else key
        for section, keys in SCHEMA.items()
        for key in keys
        if f"`{section + '.' if section else ''}{key}`" not in text
    ]
    assert not missing, f"undocumented problem-file keys: {missing}"
    for section in SCHEMA:
        if section:
            assert f"## [{section}]" in text, section


def test_no_internal_spec_citations():
    """No "DESIGN §" citation in the package or its report templates: they point to docs/ instead, and
    every docs/ file they cite exists."""
    offenders, cited = [], set()
    for path in (ROOT / "designer").rglob("*"):
        if path.suffix in (".py", ".j2", ".md", ".toml") and path.is_file():
            text = path.read_text(encoding="utf-8")
            if re.search(r"DESIGN(\.md)?`? ?§", text):
                offenders.append(str(path.relative_to(ROOT)))
            cited.update(re.findall(r"docs/([a-z0-9_-]+\.md)", text))
    assert not offenders
    assert cited and all((ROOT / "docs" / name).is_file() for name in cited), cited


def test_docs_cover_the_model_equations_and_checks():
    """docs/model.md names every equation the physics modules cite; docs/checks.md every check of validate."""
    model = (ROOT / "docs" / "model.md").read_text(encoding="utf-8")
    cited = set()
    for path in (ROOT / "designer" / "physics").glob("*.py"):
        cited.update(re.findall(r"Eq\. (\d+[A-C]?)", path.read_text(encoding="utf-8")))
    missing = sorted(e for e in cited if not re.search(rf"Eq\. {e}\b", model))
    assert not missing, f"equations cited in designer/physics but not in docs/model.md: {missing}"
    from designer.studies.checks import paper_checks

    checks = (ROOT / "docs" / "checks.md").read_text(encoding="utf-8")
    for c in paper_checks():
        assert f"### {c.name}" in checks, c.name
