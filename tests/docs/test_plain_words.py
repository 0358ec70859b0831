"""Plain words where a person reads: no internal issue numbers or workshop names in any shipped text (the docs,
the README, the templates, the package's strings, the shipped problems), and no solver vocabulary ("J =",
"knee", "risk-bounded") on a first screen before the plain sentence that says what it means."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from designer.cli import main

from conftest import ROOT

INTERNAL = re.compile(
    r"\bissues?\s+#?\d+(?:\.\d+)?\b"  # "issue 11", "Issue 28.5"
    r"|\bthe\s+[\w-]+\s+issue\b"  # "the product-line issue"
    r"|\"[\w -]+\"\s+issue\b"  # '(the "Retrofit" issue)'
    r"|\b(?:this|last|next) round\b|\bround\s+\d+(?![.\d])\b",  # "round 3", "last round"
    re.IGNORECASE,
)
"""How the workshop names its own tasks; a reader of the tool has none of them."""

JARGON = re.compile(r"\bJ =|\bknee\b|risk-bounded", re.IGNORECASE)
"""The terms a first screen explains before it uses them."""


def shipped_texts() -> list[Path]:
    """Every text the project ships to a user: the docs and README, the report and sheet templates, the package's
    modules (their strings and help texts), the shipped problems and the changelog."""
    files = [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "CONTRIBUTING.md", ROOT / "mkdocs.yml"]
    files += sorted((ROOT / "docs").rglob("*.md"))
    files += sorted((ROOT / "designer").rglob("*.py")) + sorted((ROOT / "designer").rglob("*.j2"))
    files += sorted((ROOT / "designer").rglob("*.js")) + sorted((ROOT / "designer").rglob("*.css"))
    files += sorted((ROOT / "problems").glob("*.toml"))
    return [f for f in files if f.exists()]


def internal_references(text: str) -> list[str]:
    """The internal issue references in ``text``, each with a little context."""
    return [text[max(0, m.start() - 30) : m.end() + 10] for m in INTERNAL.finditer(text)]


def test_the_grep_catches_what_it_looks_for():
    """Planted: each way the workshop named an issue is found; plain uses of the word are not."""
    for planted in (
        "the cap (issue 11)",
        "Issue 28.5: the first screen",
        "assumption: the spread the product-line issue asks for",
        'fixes of designer.fix (the "Retrofit" issue) within',
        "added in round 3",
    ):
        assert internal_references(planted), planted
    for plain in ("a known issue with carpets", "rounded toward the safe side", "round 2.5 to 2"):
        assert not internal_references(plain), plain


def test_no_shipped_text_names_an_internal_issue():
    """No docs page, template, module string, problem file or README line names an internal issue."""
    found = {str(f.relative_to(ROOT)): refs for f in shipped_texts() if (refs := internal_references(f.read_text()))}
    assert found == {}


def _first_jargon(text: str) -> int | None:
    """Where the first of "J =", "knee" or "risk-bounded" stands in ``text`` (None: nowhere)."""
    m = JARGON.search(text)
    return None if m is None else m.start()


@pytest.mark.parametrize("name", ["indoor-manual", "sports-court", "catalog-retrofit", "powered-chair"])
def test_the_sheet_speaks_plainly(name, tmp_path, capsys):
    """The inspection sheet of each kind of rule (no knee, knee, two-point front) says how its caster was chosen
    in plain words and never "J =", "knee" or "risk-bounded"."""
    out = tmp_path / "sheet.html"
    assert main(["spec", name, "--out", str(out)]) == 0
    capsys.readouterr()
    html = out.read_text()
    text = re.sub(r"<[^>]+>", " ", re.sub(r"<style.*?</style>", "", html, flags=re.S))
    assert "Chosen as the " in text
    assert _first_jargon(text) is None, text[_first_jargon(text) - 60 : _first_jargon(text) + 40]


@pytest.fixture(scope="module")
def report_html(tmp_path_factory):
    """indoor-manual's report (nine points), as pareto writes it."""
    from designer.pipeline import report_data
    from designer.problem import load_problem
    from designer.report import write_report

    data = report_data(load_problem(ROOT / "problems" / "indoor-manual.toml"), points=9, with_tighter=False)
    return (write_report(data, tmp_path_factory.mktemp("r")) / "index.html").read_text()


def test_the_reports_first_screen_says_it_plainly_first(report_html):
    """The report's first screen (the "Build this" card): its headline and plain lead come first; a term ("knee",
    "J =", "risk-bounded") appears only after them, in the rule's name and in the glossary that links the terms."""
    card = report_html[report_html.index('id="build"') : report_html.index("</section>")]
    lead = re.search(r'<p class="lead">(.*?)</p>', card)
    assert lead is not None and _first_jargon(lead.group(1)) is None
    head = card[: lead.end()]
    assert _first_jargon(head) is None
    bullets = card[lead.end() : card.index("</ul>")]
    first = _first_jargon(bullets)
    assert first is None or bullets[first - 200 : first].count("The rule by its name") == 1
