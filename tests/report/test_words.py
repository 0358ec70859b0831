"""Issue 34.4: the words around the numbers are made from the data they state, and checked against it: the count
of buildable casters and of alternatives shown against ``front.csv``, the "no knee" claim against the front's
geometry, and no Markdown syntax showing as text in the HTML report."""

from __future__ import annotations

import csv
import html as htmllib
import json
import re
from pathlib import Path

import numpy as np
import pytest

from designer.units import csv_quantity

from designer.report.text import front_count_sentence
from designer.report.writer import _inline_code

from conftest import ROOT

RESULTS = ROOT / "results"
REPORTS = sorted(p.parent for p in RESULTS.glob("*/front.csv") if (p.parent / "front.json").is_file())


def _buildable_rows(folder: Path) -> list[dict]:
    """The buildable rows of a committed ``front.csv``, each quantity in SI under its bare name (the columns name
    their units: ``trail_in`` is ``trail`` [m], designer.units.csv_quantity)."""
    with open(folder / "front.csv", newline="", encoding="utf-8") as f:
        rows = [row for row in csv.DictReader(f) if row["buildable"] == "true"]
    return [
        {**r, **{csv_quantity(k)[0]: float(v) / csv_quantity(k)[1] for k, v in r.items() if k != csv_quantity(k)[0]}}
        for r in rows
    ]


def _panel(html: str, name: str) -> str:
    """The HTML of the report panel ``name`` (up to its closing table or paragraph)."""
    start = html.index(f'id="panel-{name}"')
    return html[start : html.index("</div>", start)]


@pytest.mark.parametrize("folder", REPORTS, ids=lambda p: p.name)
def test_alternatives_are_every_other_buildable_caster(folder):
    """front.json's alternatives are every buildable row of front.csv but the recommendation (none missing, none
    twice), and the alternatives panel has one row per buildable caster and says how many there are."""
    rows = _buildable_rows(folder)
    data = json.loads((folder / "front.json").read_text(encoding="utf-8"))
    rec = data.get("recommendation")
    if rec is None:
        pytest.skip(f"{folder.name} has no recommendation")  # nothing to show: no buildable caster
    key = lambda d: tuple(round(float(d[k]), 9) for k in ("trail", "diameter", "groove", "damping"))  # noqa: E731
    shown = [key(rec["design"])] + [key(a["design"]) for a in data["alternatives"]]
    assert sorted(shown) == sorted(key(r) for r in rows)
    html = (folder / "index.html").read_text(encoding="utf-8")
    if len(rows) > 1:
        panel = _panel(html, "alternatives")
        assert panel.count("<tr") == 1 + len(rows)
        assert f"The buildable front has {len(rows)} caster{'s' if len(rows) != 1 else ''}:" in panel
        roles = [a["role"] for a in data["alternatives"]]
        assert set(roles) <= {"easiest to turn", "between the ends", "easiest over the sill"}
        assert roles.count("easiest to turn") <= 1 and roles.count("easiest over the sill") <= 1


def _bulges(f: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Whether each point of a front lies strictly on the ideal side of the chord between its ends, both forces
    scaled to the front's range (the knee's definition, written here independently of the rule's code)."""
    fn = (f - f.min()) / (f.max() - f.min())
    pn = (p - p.min()) / (p.max() - p.min())
    a, b = np.argmin(fn), np.argmax(fn)  # the easiest-to-turn end (largest P) and the easiest-over-the-sill end
    # the chord from a to b; ideal side is toward (0, 0): a negative cross product with the chord's direction
    cross = (fn[b] - fn[a]) * (pn - pn[a]) - (pn[b] - pn[a]) * (fn - fn[a])
    return cross < -1e-9


@pytest.mark.parametrize("folder", REPORTS, ids=lambda p: p.name)
def test_no_knee_claim_matches_the_geometry(folder):
    """The rule says "no knee" exactly when the buildable front has fewer than three casters or none of its
    casters between the ends lies on the ideal side of the chord; it says "knee" only when one does."""
    rows = _buildable_rows(folder)
    data = json.loads((folder / "front.json").read_text(encoding="utf-8"))
    rec = data.get("recommendation")
    if rec is None or "<=" in rec["rule"]:
        pytest.skip("no recommendation, or a capped rule (no knee claim)")
    f = np.array([float(r["turning_effort"]) for r in rows])
    p = np.array([float(r["threshold_force"]) for r in rows])
    knee = len(rows) >= 3 and bool(_bulges(f, p).any())
    assert rec["rule"].startswith("knee") == knee, rec["rule"]
    assert ("no knee" in rec["rule"]) == (not knee), rec["rule"]


def test_bulge_geometry_catches_a_knee():
    """The geometric check above is not vacuous: a front whose middle point bulges toward the ideal has a knee,
    a straight or outward-bowed one has none."""
    assert _bulges(np.array([7.0, 7.5, 8.0]), np.array([133.0, 110.0, 107.0]))[1]
    assert not _bulges(np.array([7.0, 7.63, 7.94]), np.array([133.5, 118.07, 106.96])).any()


class _Rec:
    """The fields front_count_sentence reads."""

    def __init__(self, alternatives: int, front: int | None):
        self.alternatives = [object()] * alternatives
        self.buildable = None if front is None else type("F", (), {"points": [object()] * front})()


@pytest.mark.parametrize(
    "alternatives, front, words",
    [
        (
            2,
            3,
            "The buildable front has 3 casters: the caster to build (first row) and the 2 others, by turning effort.",
        ),
        (1, 2, "The buildable front has 2 casters: the caster to build (first row) and the other."),
        (0, 1, "The buildable front has 1 caster: the caster to build."),
        (4, None, "The buildable front has 5 casters: the caster to build (first row) and the 4 others"),
    ],
)
def test_front_count_sentence_counts(alternatives, front, words):
    """The sentence's counts are those of the record (its buildable front's points and its alternatives)."""
    assert front_count_sentence(_Rec(alternatives, front)).startswith(words)


def _visible_text(html: str) -> str:
    """The page's text as a reader sees it: no SVG, style or script, tags removed, entities decoded."""
    html = re.sub(r"<(svg|style|script)\b.*?</\1>", " ", html, flags=re.S)
    html = re.sub(r"<code>.*?</code>", " ", html, flags=re.S)
    return htmllib.unescape(re.sub(r"<[^>]+>", " ", html))


MARKDOWN = re.compile(r"`|\*\*|(?<![\w*])\*\w[^*\n]*?\*(?![\w*])|\]\(|^#+ |__\w", re.M)
"""Markdown syntax that must not show as text: inline code, bold, *emphasis*, links, headings, underscore
emphasis (a product such as N*m is not emphasis)."""


@pytest.mark.parametrize("page", sorted(RESULTS.glob("**/*.html")), ids=lambda p: str(p.relative_to(RESULTS)))
def test_no_markdown_shows_in_html(page):
    """No committed HTML page (the reports, the limit-cycle page) shows Markdown syntax as text (its inline code is
    rendered as <code>, *emphasis* as <em>)."""
    text = _visible_text(page.read_text(encoding="utf-8"))
    assert not MARKDOWN.search(text), MARKDOWN.search(text)


def test_inline_code_is_rendered():
    """The HTML finalizer turns Markdown inline code into <code>, escapes the rest, and leaves numbers and markup
    alone; the check above fails on the raw text (planted)."""
    raw = "run `designer pareto a<b.toml --cross-check` for it"
    out = str(_inline_code(raw))
    assert out == "run <code>designer pareto a&lt;b.toml --cross-check</code> for it"
    assert MARKDOWN.search(_visible_text(htmllib.escape(raw)))
    assert not MARKDOWN.search(_visible_text(out))
    assert _inline_code(3.5) == 3.5
