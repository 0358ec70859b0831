"""The report and the inspection sheet on a 390 px phone (headless Chromium): the smallest text drawn in a drawing
or a figure is at least 11 px, every link or button of the page is a touch target of at least 44 px, and neither
page scrolls sideways (a drawing or a figure too wide for the phone scrolls in its own frame)."""

from __future__ import annotations

import pytest

from designer.cli import main

from conftest import ROOT

PHONE = 390
"""A phone's CSS width [px]."""
SMALLEST_TEXT = 11.0
"""The least size [px] of text in a drawing or a figure on a phone (the body text is 16 px)."""
TOUCH = 44.0
"""The least touch target [px] (Apple's Human Interface Guidelines; WCAG 2.5.5's 44 × 44 CSS px)."""

SMALLEST = """
const sizes = [];
for (const t of document.querySelectorAll('svg text')) {
  const r = t.getBoundingClientRect();
  if (!t.textContent.trim() || r.width === 0) continue;
  const m = t.getScreenCTM();
  sizes.push([parseFloat(getComputedStyle(t).fontSize) * Math.hypot(m.a, m.b), t.textContent.trim().slice(0, 40)]);
}
sizes.sort((a, b) => a[0] - b[0]);
const targets = [];
for (const b of document.querySelectorAll('a[href], button, input, select, summary')) {
  const r = b.getBoundingClientRect();
  if (r.width === 0) continue;
  targets.push([Math.min(r.width, r.height), (b.textContent || b.value || '').trim().slice(0, 30)]);
}
targets.sort((a, b) => a[0] - b[0]);
return [sizes[0] || null, targets[0] || null, sizes.length, document.documentElement.scrollWidth, window.innerWidth];
"""
"""The smallest drawn text [px, its words], the smallest touch target [px, its words], how many texts were
measured, and how wide the page is and the window shows [px]."""


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """indoor-manual's report (nine points) and its inspection sheet, as pareto and spec write them."""
    from designer.pipeline import report_data
    from designer.problem import load_problem
    from designer.report import write_report

    folder = tmp_path_factory.mktemp("phone")
    data = report_data(load_problem(ROOT / "problems" / "indoor-manual.toml"), points=9, with_tighter=False)
    report = write_report(data, folder / "report") / "index.html"
    sheet = folder / "spec.html"
    assert main(["spec", "indoor-manual", "--out", str(sheet)]) == 0
    return {"report": report, "sheet": sheet}


@pytest.mark.parametrize("name", ["report", "sheet"])
def test_text_and_targets_are_big_enough_on_a_phone(name, pages, browser, capsys):
    """At 390 px the smallest text of the drawings and figures is at least 11 px, the smallest link or button at
    least 44 px (the sheet has none), and the page is no wider than the phone."""
    capsys.readouterr()
    phone = browser(PHONE)
    phone.get(pages[name].as_uri())
    smallest, target, count, width, window = phone.execute_script(SMALLEST)
    assert count > 5 and smallest is not None
    assert smallest[0] >= SMALLEST_TEXT - 0.01, f"{name}: {smallest[1]!r} drawn at {smallest[0]:.1f} px"
    if name == "report":
        assert target is not None and target[0] >= TOUCH, f"{name}: {target[1]!r} is {target[0]:.0f} px"
    assert (width, window) == (PHONE, PHONE), f"{name}: {width} px wide on a {PHONE} px phone"


def test_the_measure_catches_small_text_and_a_small_button(pages, browser):
    """Planted: a 6 px label in the report's drawing and a 20 px button are what the measure reports."""
    phone = browser(PHONE)
    phone.get(pages["report"].as_uri())
    phone.execute_script(
        "const t = document.querySelector('.drawing svg text'); t.style.fontSize = '1px';"
        "const b = document.createElement('button'); b.textContent = 'x'; b.style.cssText = 'width:20px;height:20px;"
        "padding:0;min-height:0'; document.body.prepend(b)"
    )
    smallest, target, *_ = phone.execute_script(SMALLEST)
    assert smallest[0] < SMALLEST_TEXT and target[0] <= 20
