"""Issue 28.5: the report's first screen read at a glance (one caster, plain words, sizes as the user writes them,
the drawing's labels and captions, Figure 1's caption against its legend, the card at 1400 px in Chromium)."""

from __future__ import annotations

import dataclasses
import re
import shutil

import pytest

from designer.data.paper import INCH
from designer.errors import ProblemError
from designer.plots.caster import caster_svg
from designer.problem import problem_from_toml
from designer.report import write_report
from designer.report.formatting import size

from conftest import ROOT

TOML = '[shimmy]\ntarget_speed = "2.5 m/s"\n'


@pytest.mark.parametrize(
    "metres, units, text",
    [
        (7 * INCH, "in", "7 in"),
        (0.5 * INCH, "in", "1/2 in"),
        (2.5 * INCH, "in", "2 1/2 in"),
        (0.5625 * INCH, "in", "9/16 in"),
        (7.75 * INCH, "in", "7 3/4 in"),
        (0.0, "in", "0 in"),
        (2.139 * INCH, "in", "≈ 2 1/8 in"),  # 2.139 in is 0.2 sixteenths from 2 2/16: marked as rounded
        (0.013, "mm", "13 mm"),
        (7 * INCH, "mm", "177.8 mm"),
        (0.0127, "mm", "12.7 mm"),
    ],
)
def test_sizes_as_the_user_writes_them(metres, units, text):
    """Inches to the nearest 1/16 in lowest terms, millimetres to 0.1 without a trailing zero (hand values)."""
    assert size(metres, units) == text


@pytest.mark.parametrize(
    "extra, units",
    [
        ("", "in"),
        ('[conditions]\nthreshold_height = "13 mm"\n', "mm"),
        ('[conditions]\nthreshold_height = "0.5 in"\n', "in"),
        ('[conditions]\nthreshold_height = "13 mm"\n[variables]\ntrail = { min = "1 in", max = "2 in" }\n', "mm"),
        ('[conditions]\nthreshold_height = "0.5 in"\n[variables]\ntrail = { min = "25 mm", max = "50 mm" }\n', "in"),
        ('[conditions]\nthreshold_height = "13 mm"\n[report]\nunits = "in"\n', "in"),
        ('[report]\nunits = "mm"\n', "mm"),
    ],
)
def test_report_units_from_the_file(extra, units):
    """[report] units wins; without it the file's lengths decide, and the sill's unit when they mix."""
    assert problem_from_toml(TOML + extra).units == units


def test_report_units_rejects_other_units():
    """report.units = "cm" is one line naming the key, the value and the choices."""
    with pytest.raises(ProblemError, match=r"^p.toml: report.units = 'cm': expected one of 'in', 'mm'$"):
        problem_from_toml(TOML + '[report]\nunits = "cm"\n', source="p.toml")


@pytest.fixture(scope="module")
def stub():
    """indoor-manual's report data with its recommendation (as pareto computes it), without the slow parts."""
    from designer.pipeline import report_data
    from designer.problem import load_problem

    return report_data(load_problem(ROOT / "problems" / "indoor-manual.toml"), points=9, with_tighter=False)


def test_sill_in_mm_is_shown_in_mm(stub, tmp_path):
    """A problem whose sill is written as 13 mm (units "mm") gets a first screen in millimetres: the sill as
    "13 mm" (not 0.512 in), every size of the caster to 0.1 mm, the drawing labelled in mm."""
    problem = stub.problem.replace(conditions=stub.problem.conditions.replace(threshold_height=0.013), units="mm")
    folder = write_report(dataclasses.replace(stub, problem=problem), tmp_path / "mm")
    html = (folder / "index.html").read_text()
    card = html[html.index('id="build"') : html.index("</section>")]
    d = stub.recommendation.design
    assert "climbs the 13 mm sill" in card and "sill h = 13 mm" in card and "0.512 in" not in card
    assert f"a {size(d.diameter, 'mm')} wheel" in card and f"{size(d.trail, 'mm')} trail" in card
    assert not re.search(r"\d in\b", card), re.search(r".{40}\d in\b.{20}", card)  # no size in inches


def test_one_caster_in_plain_words_first(stub, tmp_path):
    """The card holds one caster: its headline, a plain-words lead (indoor-manual's buildable front has three
    points and no knee, so "the lowest combined force among the parts you can buy (turning effort plus sill force,
    a newton of each counted alike)"; a knee would read "the best balance ..."), its drawing and a one-row table with "P(shimmy): exact (Monte Carlo ± SE)" and the parameter table's names
    ("threshold force P", "swept radius T + d/2"); the terms (knee, risk-bounded
    front, α + 2 SE) are in the glossary under it; the continuous knee and the weighted optimum only further
    down."""
    folder = write_report(stub, tmp_path / "r")
    html = (folder / "index.html").read_text()
    card = html[html.index('id="build"') : html.index("</section>")]
    lead = re.search(r'<p class="lead">(.*?)</p>', card).group(1)
    assert stub.recommendation.rule.startswith("least J = 1 F_turn + 1 P: the buildable front has no knee")
    assert lead.startswith(
        "The lowest combined force among the parts you can buy (turning effort plus sill force, a newton of each "
        "counted alike): "
    )
    assert "knee" not in lead and "front" not in lead
    table = card[card.index('<table class="card">') : card.index("</table>")]
    assert (
        table.count("<tr") == 2
        and "<th>P(shimmy): exact (Monte Carlo ± SE)</th>" in table
        and "<th>swept radius T + d/2</th>" in table  # the table's name of the quantity, with its symbol
        and "<th>sill force P</th>" in table
    )
    assert "weighted optimum" not in card and "easiest" not in card and "continuous front" not in card
    terms = html[html.index('id="panel-terms"') :]
    terms = terms[: terms.index("</table>")]
    for term in ("best balance (knee)", "risk-bounded front", "α + 2 SE"):
        assert f"<td>{term}</td>" in terms
    assert html.index('id="panel-terms"') < html.index("Weighted optimum of J")


def test_drawing_shows_the_limit_the_treads_and_its_captions():
    """The top view draws the footrest limit even where it equals the swept radius (its own dashed ring, drawn
    under the swept circle's line), labels both treads and the groove (one tread when B = 0), and each view's
    caption sits under its own drawing (below its bottom, centred on it)."""
    t, d, b, h = 2.5 * INCH, 7 * INCH, 0.5 * INCH, 0.5 * INCH
    svg = caster_svg(t, d, b, h, t + d / 2, scale=25.0, units="in")
    limit = re.search(r'<circle class="footrest-limit" cx="([0-9.]+)" cy="([0-9.]+)" r="([0-9.]+)"', svg)
    swept = re.search(r'<circle class="swept" cx="([0-9.]+)" cy="([0-9.]+)" r="([0-9.]+)"', svg)
    assert limit and swept and float(limit.group(3)) == float(swept.group(3)) == pytest.approx(6 * 25.0, abs=0.06)
    assert svg.index('class="footrest-limit"') < svg.index('class="swept"')  # the line of the swept circle on top
    assert "stroke-dasharray" in svg[svg.index('class="footrest-limit"') :].split("/>")[0]
    assert svg.count(">tread</text>") == 2 and "groove B = 1/2 in" in svg and "(at the limit)" in svg
    side, *top = re.findall(r'<text class="caption" x="([0-9.]+)" y="([0-9.]+)"[^>]*>([^<]*)</text>', svg)
    ground = float(re.search(r'<line x1="0" y1="([0-9.]+)"', svg).group(1))
    assert side[2] == "side view, rolling to the right" and float(side[1]) > ground
    assert float(side[0]) < float(swept.group(1)) - float(swept.group(3))  # under the side view, left of the top
    assert all(float(x) == pytest.approx(float(swept.group(1))) for x, _, _ in top)  # centred on the top view
    assert all(float(y) > float(swept.group(2)) + float(swept.group(3)) for _, y, _ in top)  # under it
    assert "one tread (no groove)" in caster_svg(t, d, 0.0, h, None, units="mm")


def test_front_caption_matches_its_legend(stub):
    """Figure 1's caption names each marked design as its legend does: the star is the caster to build ("build
    this" in the legend), the cross the weighted optimum (it said the star was the weighted optimum)."""
    from designer.report import figures
    from designer.report.context import front_caption

    marks = figures.arguments("front", stub)["marks"]
    legend = {m["kind"]: m["label"] for m in marks}
    caption = front_caption(stub)
    assert legend["recommended"].startswith("build this")
    assert "the caster to build (gold star, 'build this')" in caption
    # the weighted optimum has its own legend entry, or shares the knee's where the two coincide (indoor-manual's
    # continuous knee is the front's corner, where J = F_turn + P is least too)
    weighted = legend["weighted"] or legend["knee"]
    assert weighted.startswith(("weighted optimum", "knee of the continuous front = weighted optimum"))
    assert "the weighted optimum, not the recommendation" in caption
    assert "(star)" not in caption and "line of constant J" not in caption
    from designer.plots.fronts import MARK_STYLE

    assert MARK_STYLE["recommended"]["marker"] == "*" and MARK_STYLE["weighted"]["marker"] == "X"


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")


@pytest.mark.skipif(not (CHROMIUM and CHROMEDRIVER), reason="needs Debian's chromium and chromium-driver")
def test_card_fits_at_1400_px_in_chromium():
    """The committed results/indoor-manual/index.html in Chromium at 1400 px: the card's table needs no sideways
    scroll (its width within its box, the page no wider than the window) and its "P(shimmy): exact (Monte Carlo ± SE)" and
    "swept radius T + d/2" headers lie inside the window."""
    webdriver = pytest.importorskip("selenium.webdriver")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--disable-gpu",
        "--window-size=1400,1000",
    ):
        options.add_argument(arg)
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(CHROMEDRIVER))
    try:
        driver.get((ROOT / "results" / "indoor-manual" / "index.html").as_uri())
        m = driver.execute_script(
            "const t = document.querySelector('#build table.card'), box = t.parentElement;"
            "const th = [...t.querySelectorAll('th')].map(h => [h.textContent, h.getBoundingClientRect().right]);"
            "return {table: t.scrollWidth, box: box.clientWidth, page: document.documentElement.scrollWidth,"
            " window: window.innerWidth, th: th};"
        )
    finally:
        driver.quit()
    assert m["table"] <= m["box"] and m["page"] <= m["window"], m
    right = dict(m["th"])
    assert (
        right["P(shimmy): exact (Monte Carlo ± SE)"] <= m["window"] and right["swept radius T + d/2"] <= m["window"]
    ), m
