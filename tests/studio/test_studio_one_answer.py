"""One caster, one answer, in headless Chromium: what the studio shows is what `designer run --json` gives.

Issue 41: the panel said P(shimmy) 2.98 % for the recommended caster and its card 0.26 % (the card evaluated the
caster again with its power-law I_w taken as measured).  Issue 42: after quick key presses the panel could show
the answer to an in-between speed, and after load 178 -> 250 -> 178 N the chart's axes stayed where the fronts
were not.  Each test drives `designer studio --port 0 --no-browser` (tests/studio/test_studio_browser.py's helpers)
and compares every number shown with `designer run PROBLEM --json` at display precision
(:mod:`designer.display`, in the problem's unit system).  Skipped without Selenium, Dash or Debian's Chromium.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("dash")
pytest.importorskip("selenium.webdriver")

from selenium.common.exceptions import TimeoutException  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402
from test_studio_browser import (  # noqa: E402
    CHROMEDRIVER,
    CHROMIUM,
    PROBLEM,
    WAIT,
    chrome,
    start_studio,
    text,
    this_code,
    traces,
)

from designer import display  # noqa: E402

pytestmark = pytest.mark.skipif(not (CHROMIUM and CHROMEDRIVER), reason="needs Debian's chromium and chromium-driver")

SHOWN = {"probability": "shimmy_probability", "vc": "critical_speed", "confident": "confident_speed"}
"""The numbers compared, by the suffix of their element id (rec-…, card-…): P(shimmy) at the target, V_c and the
speed reached with probability 1 − α."""


def run_json(problem: Path, cwd: Path) -> dict:
    """`designer run PROBLEM --json` (this checkout's code) as a dict."""
    out = subprocess.run(
        [sys.executable, "-m", "designer", "run", str(problem), "--json"],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=600,
        env=this_code(),
    )
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout)


def shown_numbers(driver, prefix: str) -> dict:
    """The texts of ``<prefix>-probability``, ``-vc`` and ``-confident`` on the page."""
    return {key: text(driver, f"{prefix}-{key}") for key in SHOWN}


def settled_numbers(wait, prefix: str) -> dict:
    """:func:`shown_numbers` once each of them reads (a span Dash is replacing at the moment of reading reads "",
    :func:`text`; a wrong number still reads, and fails the comparison that follows)."""

    def read(driver) -> dict | bool:
        numbers = shown_numbers(driver, prefix)
        return numbers if all(numbers.values()) else False

    return wait.until(read)


def expected(record: dict, units: str) -> dict:
    """What the page must show for ``record`` (a caster of `designer run --json`) at display precision."""
    return {key: display.shown(record[name], name, units) for key, name in SHOWN.items()}


def ready(driver) -> bool:
    """The page shows the answer to the controls it shows (the browser's comparison, app._request_callbacks)."""
    boxes = driver.find_elements(By.ID, "answer-box")
    return bool(boxes) and boxes[0].get_attribute("class") == "answered" and "computed" in text(driver, "status")


def open_card(driver, wait, button, title: str) -> None:
    """Click ``button`` and wait for the card titled ``title`` with its numbers."""
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", button)
    button.click()
    wait.until(lambda d: text(d, "card-title") == f"Card: {title}" and text(d, "card-probability"))


@pytest.fixture
def millimetre_problem(tmp_path) -> Path:
    """A problem written by `designer init --defaults --units mm` (the default problem, sizes in mm)."""
    path = tmp_path / "mm-chair.toml"
    out = subprocess.run(
        [sys.executable, "-m", "designer", "init", str(path), "--defaults", "--units", "mm"],
        capture_output=True,
        text=True,
        timeout=120,
        env=this_code(),
    )
    assert out.returncode == 0, out.stderr
    return path


@pytest.fixture
def page(tmp_path):
    """(the studio's URL, a headless Chromium, its wait, the studio's working folder): a studio of the default
    problem started in ``tmp_path / "run"``, both ended after the test."""
    cwd = tmp_path / "run"
    cwd.mkdir()
    proc, url = start_studio(cwd)
    driver = chrome()
    try:
        yield url, driver, WebDriverWait(driver, WAIT, poll_frequency=0.1), cwd
    finally:
        driver.quit()
        proc.kill()
        proc.wait(30)


@pytest.mark.parametrize("units", ["in", "mm"])
def test_panel_and_cards_show_designer_runs_numbers(tmp_path, millimetre_problem, units):
    """On the default problem (inches) and on one written in millimetres: every P(shimmy), V_c and "speed
    reached" shown for the caster to build, in the panel and in its card, equals `designer run --json`'s
    recommendation at display precision; the same for the card of its first alternative.  The caster to build
    leads with the problem's unit (a mm problem: "T 63.50 mm"), and on the default problem both the panel and
    the card say P(shimmy) 2.98 % (the card said 0.26 % before)."""
    problem = PROBLEM if units == "in" else millimetre_problem
    cwd = tmp_path / "run"
    cwd.mkdir()
    proc, url = start_studio(cwd, problem)
    driver = chrome()
    try:
        reference = run_json(problem, cwd)
        rec, alternative = reference["recommendation"], reference["alternatives"][0]
        wait = WebDriverWait(driver, WAIT, poll_frequency=0.1)
        driver.get(url)
        wait.until(ready)
        design = text(driver, "rec-design")
        assert design.startswith(f"T {display.shown(rec['design']['trail'], 'trail', units)}")
        assert f" {units}," in design and (" in," not in design if units == "mm" else " mm," not in design)
        assert settled_numbers(wait, "rec") == expected(rec, units)

        open_card(driver, wait, driver.find_element(By.ID, "rec-card"), "the caster to build")
        assert settled_numbers(wait, "card") == expected(rec, units)
        if units == "in":
            assert text(driver, "rec-probability") == text(driver, "card-probability") == "2.98 %"

        button = driver.find_element(By.CSS_SELECTOR, ".alt-card")  # the first alternative's
        assert button.text.startswith(f"card: {alternative['role']}")
        open_card(driver, wait, button, alternative["role"])
        assert settled_numbers(wait, "card") == expected(alternative, units)
        assert display.shown(alternative["design"]["diameter"], "diameter", units) in text(driver, "card-design")
    finally:
        driver.quit()
        proc.kill()
        proc.wait(30)


def test_quick_keys_end_on_the_answer_to_the_controls_shown(page):
    """Issue 42: ten quick presses of the target-speed slider's arrow key and a load change and back (178 ->
    250 -> 178 N, Enter each), faster than the server answers; once the page says it shows the answer to its
    controls, the panel's numbers equal `designer run --json` of the problem those controls make (the file
    "Save problem" writes of them), and the chart's axes hold every point drawn."""
    url, driver, wait, cwd = page
    driver.get(url)
    wait.until(ready)
    driver.execute_script(  # every class the answer's box takes from here on
        "window.seen = []; new MutationObserver(() => window.seen.push(document.getElementById('answer-box')"
        ".className)).observe(document.getElementById('answer-box'), {attributes: true});"
    )
    handle = driver.find_element(By.CSS_SELECTOR, '[data-key="target"] [role="slider"]')
    handle.click()
    for _ in range(10):
        handle.send_keys(Keys.ARROW_RIGHT)
    load = driver.find_element(By.CSS_SELECTOR, '[data-key="load"] input')
    for value in ("250 N", "178 N"):
        load.send_keys(Keys.CONTROL, "a")
        load.send_keys(value, Keys.ENTER)
    try:
        wait.until(lambda d: "target=3.5" in d.current_url and ready(d))
    except TimeoutException:  # what the page shows then: the URL, the answer box, the status and its history
        box = driver.find_element(By.ID, "answer-box").get_attribute("class")
        seen = driver.execute_script("return window.seen")
        pytest.fail(f"never settled: {driver.current_url} box={box!r} status={text(driver, 'status')!r} seen={seen}")
    assert "waiting" in driver.execute_script("return window.seen")  # said so while it was computing
    shown = settled_numbers(wait, "rec")

    driver.find_element(By.ID, "save").click()
    wait.until(lambda d: "saved" in text(d, "save-result"))
    saved = cwd / "out" / "indoor-manual.toml"
    reference = run_json(saved, cwd)
    assert reference["required_speed"] == pytest.approx(3.5)
    assert shown == expected(reference["recommendation"], "in")

    ranges = driver.execute_script(
        "const g = document.querySelector('#front .js-plotly-plot');"
        "return [g._fullLayout.xaxis.range, g._fullLayout.yaxis.range];"
    )
    points = traces(driver)
    assert points and {"continuous", "risk", "buildable", "recommendation"} <= set(points)
    for key, (x, y) in points.items():
        assert all(ranges[0][0] <= v <= ranges[0][1] for v in x), (key, ranges[0], min(x), max(x))
        assert all(ranges[1][0] <= v <= ranges[1][1] for v in y), (key, ranges[1], min(y), max(y))


def test_back_and_forward_set_the_controls_and_their_answer(page):
    """The browser's Back and Forward after a change of the target speed (2.6 -> 2.7 m/s): the slider shows the
    URL's target again, and the page settles on the answer to it (the panel's P(shimmy) of each target is the one
    that target showed first). The URL's values reach the controls through the numbered ``url-values`` store."""
    url, driver, wait, _ = page

    def slider() -> str:
        return driver.find_element(By.CSS_SELECTOR, '[data-key="target"] [role="slider"]').get_attribute(
            "aria-valuenow"
        )

    def settled(target: str):
        return lambda d: f"target={target}" in d.current_url and slider() == target and ready(d)

    driver.get(url + "?target=2.6")
    wait.until(settled("2.6"))
    first = settled_numbers(wait, "rec")
    handle = driver.find_element(By.CSS_SELECTOR, '[data-key="target"] [role="slider"]')
    handle.click()
    handle.send_keys(Keys.ARROW_RIGHT)
    wait.until(settled("2.7"))
    second = settled_numbers(wait, "rec")
    assert first != second  # P(shimmy) at the target moves with it
    driver.back()
    wait.until(settled("2.6"))
    assert settled_numbers(wait, "rec") == first
    driver.forward()
    wait.until(settled("2.7"))
    assert settled_numbers(wait, "rec") == second
