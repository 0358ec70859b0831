"""The report on a phone (390 CSS px, headless Chromium): the page does not scroll sideways, the first screen's
numbers stack into one "name  value" line each, the drawing fits the width and a tapped figure shows its full
size in its own frame."""

from __future__ import annotations

from pathlib import Path

import pytest

PHONE = 390
"""A phone's CSS width [px] (an iPhone 12–15 held upright)."""
SIDEWAYS = "return [document.documentElement.scrollWidth, window.innerWidth]"
"""How wide the page is and the window shows [px].  A phone (Chromium's mobile emulation) zooms out to show a
page wider than the screen: the window then grows with the page, so both are compared with the phone's width."""
ROOT = Path(__file__).resolve().parents[2]
REPORTS = (
    sorted((ROOT / "results").glob("*/index.html"))
    + sorted((ROOT / "results").glob("robust/*/index.html"))
    + [ROOT / "results" / "simulation" / "limit_cycles.html"]
)


@pytest.fixture
def phone(browser):
    return browser(PHONE)


@pytest.mark.parametrize("page", REPORTS, ids=lambda p: p.parent.relative_to(ROOT / "results").as_posix())
def test_report_does_not_scroll_sideways_on_a_phone(phone, page):
    """Every committed report page is at most as wide as a 390 px window."""
    phone.get(page.as_uri())
    width, window = phone.execute_script(SIDEWAYS)
    assert (width, window) == (PHONE, PHONE), f"{page}: {width} px wide, shown {window} px wide on a {PHONE} px phone"


def test_the_sideways_check_catches_a_wide_element(phone):
    """Planted: a 900 px wide block in the default report makes the page scroll sideways, and the check sees it."""
    phone.get((ROOT / "results" / "indoor-manual" / "index.html").as_uri())
    phone.execute_script(
        "const d = document.createElement('div'); d.style.width = '900px'; d.style.height = '10px';"
        "document.body.append(d)"
    )
    width, window = phone.execute_script(SIDEWAYS)
    assert width > PHONE and window > PHONE


def test_first_screen_stacks_and_scales_on_a_phone(phone):
    """At 390 px: the 9-column "Build this" table shows one line per quantity (label left, value right, all
    inside the window); the drawing and a figure keep their own size (their labels readable) in frames inside
    the window that scroll sideways."""
    page = ROOT / "results" / "indoor-manual" / "index.html"
    phone.get(page.as_uri())
    cells = phone.execute_script(
        "return Array.from(document.querySelectorAll('table.card td')).map(td => {"
        "const r = td.getBoundingClientRect(); return [getComputedStyle(td, '::before').content, r.left, r.right,"
        " r.top]})"
    )
    assert len(cells) == 9
    assert [c[0].strip('"') for c in cells][:4] == ["trail T", "diameter d", "groove B", "damping c_f"]
    assert all(0 <= left and right <= PHONE for _, left, right, _ in cells)
    tops = [top for *_, top in cells]
    assert tops == sorted(tops) and len(set(tops)) == 9  # one under another, not side by side
    # the drawing keeps its own size (its labels readable) in a frame inside the window, which scrolls sideways
    frame = "document.querySelector('.build .drawing')"
    assert phone.execute_script(f"return {frame}.getBoundingClientRect().right") <= PHONE
    drawn = phone.execute_script(f"return {frame}.querySelector('svg').getBoundingClientRect().width")
    own = float(phone.execute_script(f"return {frame}.querySelector('svg').getAttribute('width')"))
    assert drawn == pytest.approx(own, abs=0.5)
    # a figure too: its full size (zoomed 1.03 so its smallest label is 11 px), scrolling in its frame, not the page
    plot = "document.querySelector('#fig-variables .plot')"
    assert phone.execute_script(f"return {plot}.getBoundingClientRect().right") <= PHONE
    full = phone.execute_script(f"return {plot}.querySelector('svg').getBoundingClientRect().width")
    own = float(phone.execute_script(f"return {plot}.querySelector('svg').getAttribute('width')"))
    assert full == pytest.approx(1.03 * (own + 2), abs=1.0)  # the figure's own width and its 1 px border each side
    assert phone.execute_script(f"return {plot}.scrollWidth > {plot}.clientWidth")
    assert phone.execute_script(SIDEWAYS) == [PHONE, PHONE]
