"""The studio on a 390 px phone (Chromium's phone emulation): text a person reads, targets a finger hits, a
message that moves nothing, and a first screen in plain words.

Skipped without Selenium, Dash or Debian's Chromium.
"""

from __future__ import annotations

import base64
import re

import pytest

pytest.importorskip("dash")
pytest.importorskip("selenium.webdriver")

from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402
from test_studio_browser import CHROMEDRIVER, CHROMIUM, WAIT, start_studio, text  # noqa: E402
from test_studio_one_answer import open_card, ready  # noqa: E402

pytestmark = pytest.mark.skipif(not (CHROMIUM and CHROMEDRIVER), reason="needs Debian's chromium and chromium-driver")

PHONE = 390
"""A phone's CSS width [px]."""

SMALLEST_TEXT = 11.0
"""The smallest text a person reads on a phone [px] (issue "one screen": 11 px)."""

SMALLEST_TARGET = 44.0
"""The smallest touch target [px] (Apple's and WCAG 2.5.5's 44 px)."""

TEXTS = """
const out = [];
for (const el of document.querySelectorAll('body *')) {
  const own = Array.from(el.childNodes).some(n => n.nodeType === 3 && n.textContent.trim());
  if (!own) continue;
  const r = el.getBoundingClientRect();
  if (r.width === 0 || r.height === 0 || getComputedStyle(el).visibility === 'hidden') continue;
  out.push([parseFloat(getComputedStyle(el).fontSize), el.tagName, el.textContent.trim().slice(0, 40)]);
}
return out;
"""
"""Every visible element holding text of its own (HTML and the charts' SVG text): [font size px, tag, text]."""

TARGETS = """
const out = [];
for (const el of document.querySelectorAll('button, summary, [role=slider], input[type=text], .dash-dropdown')) {
  const r = el.getBoundingClientRect();
  if (r.width === 0 || r.height === 0) continue;
  out.push([Math.min(r.width, r.height), el.tagName, el.id || el.className.toString().slice(0, 40)]);
}
return out;
"""
"""Every visible touch target (buttons, folded sections' headings, the slider's handle, text boxes, menus):
[its smaller side px, tag, id or class]."""

PLACES = """
return Array.from(document.querySelectorAll('.control')).map(el => {
  const r = el.getBoundingClientRect(); return [el.dataset.key || el.textContent.slice(0, 20), r.left + scrollX, r.top + scrollY, r.width];
});
"""
"""Where every control sits: [key, left, top, width]."""

JARGON = ("J =", "knee", "risk-bounded", "Pareto", "epsilon", "ε")
"""Words of the tool's own trade that the first screen does not use."""


def test_the_studio_reads_on_a_phone(tmp_path, browser):
    """At 390 px: the smallest text on the page, the charts and the card of the caster to build included, is at
    least 11 px (the card's drawing, an SVG image, shown at its own size with 11 px text: it scrolls sideways in
    its box rather than shrink) and the smallest touch target at least 44 px (buttons were about 21 px, issue "one screen");
    a red message beside a control moves no other control (it showed in the flow and pushed them); the panel
    names "the caster to build" and its first screen has none of the tool's jargon.  Planted, a 9 px label and a
    20 px button are caught."""
    cwd = tmp_path / "run"
    cwd.mkdir()
    proc, url = start_studio(cwd)
    try:
        phone = browser(PHONE, 1800)
        wait = WebDriverWait(phone, WAIT, poll_frequency=0.1)
        phone.get(url)
        wait.until(ready)
        first = phone.find_element(By.ID, "answer-box").text
        assert "The caster to build" in first
        assert [word for word in JARGON if word in first] == []
        open_card(phone, wait, phone.find_element(By.ID, "rec-card"), "the caster to build")
        wait.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#card-sweeps .main-svg"))

        drawing = phone.find_element(By.ID, "card-drawing")  # an image: its text is the SVG's, shown unscaled
        svg = base64.b64decode(drawing.get_attribute("src").split(",", 1)[1]).decode()
        sizes = [float(x) for x in re.findall(r'font-size="([0-9.]+)"', svg)]
        assert sizes and min(sizes) >= SMALLEST_TEXT
        natural, shown = phone.execute_script(
            "const i = document.getElementById('card-drawing'); return [i.naturalWidth, i.getBoundingClientRect().width]"
        )
        assert shown == natural
        texts = phone.execute_script(TEXTS)
        assert len(texts) > 100 and any(tag == "text" for _, tag, _ in texts)  # the charts' text is measured
        smallest = min(texts)
        assert smallest[0] >= SMALLEST_TEXT, smallest
        targets = phone.execute_script(TARGETS)
        assert len(targets) >= 8
        smallest = min(targets)
        assert smallest[0] >= SMALLEST_TARGET, smallest

        before = phone.execute_script(PLACES)
        box = phone.find_element(By.CSS_SELECTOR, '[data-key="load"] input')
        box.send_keys(Keys.CONTROL, "a")
        box.send_keys("heavy", Keys.ENTER)
        wait.until(
            lambda d: text(d, "answer-box") and d.find_element(By.CSS_SELECTOR, '[data-key="load"] .control-error').text
        )
        message = phone.find_element(By.CSS_SELECTOR, '[data-key="load"] .control-error')
        assert message.is_displayed() and "conditions.load" in message.text
        assert phone.execute_script(PLACES) == before
        assert phone.execute_script("return [document.documentElement.scrollWidth, window.innerWidth]") == [
            PHONE,
            PHONE,
        ]

        phone.execute_script(  # planted: the measures catch a small label and a small button
            "const s = document.createElement('span'); s.textContent = 'tiny'; s.style.fontSize = '9px';"
            "const b = document.createElement('button'); b.textContent = 'x'; b.style.cssText = 'height:20px;min-height:0';"
            "document.body.prepend(s, b);"
        )
        assert min(phone.execute_script(TEXTS))[0] == 9
        assert min(phone.execute_script(TARGETS))[0] < 21
    finally:
        proc.kill()
        proc.wait(30)
