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

ROOT = Path(__file__).resolve().parents[1]
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
