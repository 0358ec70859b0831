"""The studio in a real headless Chromium (Debian's chromium + chromedriver, driven by Selenium).

One session against `designer studio --port 0 --no-browser`, as a person would use it: load, move the
target speed, read the front and the recommendation and compare them with the API for the same problem,
click a point for its card, enter a shimmying caster for its risk and fixes, and enter min > max.
Skipped when Selenium, Dash or the system Chromium is missing (.ci/run installs them).
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

pytest.importorskip("dash")
webdriver = pytest.importorskip("selenium.webdriver")

from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402

from designer.studio import state, view  # noqa: E402

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
pytestmark = pytest.mark.skipif(not (CHROMIUM and CHROMEDRIVER), reason="needs Debian's chromium and chromium-driver")

PROBLEM = state.default_problem_path()
WAIT = 60  # s: the machine is shared; a redraw takes well under a second when it is not


def this_code() -> dict:
    """The environment of a child process that imports the ``designer`` these tests import (this checkout's, not
    an installed copy's: the child runs in another folder)."""
    import os

    import designer

    root = str(Path(designer.__file__).resolve().parents[1])
    return {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH")) if p)}


def start_studio(cwd: Path, problem: Path = PROBLEM):
    """`designer studio PROBLEM --port 0 --no-browser` in a subprocess; returns (process, url)."""
    cmd = [
        sys.executable,
        "-m",
        "designer.cli",
        "studio",
        str(problem),
        "--port",
        "0",
        "--no-browser",
        "--out",
        str(cwd / "out"),
    ]
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=this_code())
    line = proc.stdout.readline()
    match = re.search(r"(http://127\.0\.0\.1:\d+/)", line)
    if not match:
        proc.kill()
        raise AssertionError(f"no URL printed: {line!r} {proc.stderr.read()}")
    return proc, match.group(1)


def chrome():
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--disable-gpu",
        "--window-size=1500,1100",
    ):
        options.add_argument(arg)
    return webdriver.Chrome(options=options, service=webdriver.ChromeService(CHROMEDRIVER))


@pytest.fixture(scope="module")
def studio(tmp_path_factory):
    cwd = tmp_path_factory.mktemp("studio")
    proc, url = start_studio(cwd)
    driver = chrome()
    try:
        yield driver, url, cwd, proc
    finally:
        driver.quit()
        if proc.poll() is None:
            proc.kill()


def traces(driver) -> dict:
    """The plotted traces of the front chart by their meta key: {key: (x, y)}."""
    data = driver.execute_script(
        "const g = document.querySelector('#front .js-plotly-plot');"
        "return g && g.data ? g.data.map(t => [t.meta || '', Array.from(t.x), Array.from(t.y)]) : [];"
    )
    return {key: (x, y) for key, x, y in data}


def text(driver, element_id) -> str:
    """The element's text, "" while it is absent or being replaced by the page (a stale reference: read again)."""
    from selenium.common.exceptions import StaleElementReferenceException

    try:
        found = driver.find_elements(By.ID, element_id)
        return found[0].text if found else ""
    except StaleElementReferenceException:  # Dash replaced the element between finding and reading it
        return ""


def api_view(values: dict):
    """What the API gives for the same controls: the fronts and the recommendation's numbers."""
    data, _ = state.read_problem_data(PROBLEM)
    problem, _ = state.build_problem(data, values)
    fronts = view.compute_fronts(problem)
    rec = view.recommendation_record(fronts.recommendation)
    if rec is None:  # this version has no designer.recommend: the panel shows the weighted optimum
        best = (fronts.risk or fronts.continuous).weighted_best()
        rec = {"turning_effort": best.turning_effort, "threshold_force": best.threshold_force}
    return fronts, rec


def test_studio_in_chromium(studio):
    """Load, move the target speed, compare with the API, click a point, my caster, min > max."""
    driver, url, cwd, _ = studio
    wait = WebDriverWait(driver, WAIT, poll_frequency=0.1)
    driver.get(url)
    wait.until(lambda d: "computed" in text(d, "status") and "risk" in traces(d))
    # the browser's own parseInt, parseFloat and trims, not Dash's polyfill's (app.NATIVE): a fresh frame's
    # Function.prototype.toString shows a replacement's source
    assert (
        driver.execute_script(
            "const f = document.body.appendChild(document.createElement('iframe')), show = f.contentWindow.Function"
            ".prototype.toString, own = [parseInt, parseFloat, ''.trim, ''.trimStart, ''.trimEnd, Number.parseInt];"
            "const native = own.map(g => /\\[native code\\]/.test(show.call(g))); f.remove(); return native;"
        )
        == [True] * 6
    )
    before = traces(driver)["risk"]
    rec_before = (text(driver, "rec-turning"), text(driver, "rec-threshold"))

    # move the target-speed slider by keyboard: 2.5 -> 3.0 m/s (step 0.1)
    handle = driver.find_element(By.CSS_SELECTOR, '[data-key="target"] [role="slider"]')
    handle.click()
    for _ in range(5):
        handle.send_keys(Keys.ARROW_RIGHT)
    wait.until(lambda d: "target=3" in d.current_url)
    wait.until(lambda d: "risk" in traces(d) and traces(d)["risk"] != before)
    values = state.from_query(
        "?" + driver.current_url.split("?", 1)[1], state.control_values(state.read_problem_data(PROBLEM)[0])
    )
    assert values["target"] == pytest.approx(3.0)
    fronts, rec = api_view(values)
    x, y = traces(driver)["risk"]  # P across, F_turn up (as the report draws it)
    api = fronts.risk.objectives()
    assert len(x) == len(api)
    assert x == pytest.approx(list(api[:, 1]), rel=1e-9) and y == pytest.approx(list(api[:, 0]), rel=1e-9)
    _, yc = traces(driver)["continuous"]
    assert yc == pytest.approx(list(fronts.continuous.objectives()[:, 0]), rel=1e-9)
    # 3 m/s needs a smaller wheel (the turning effort may stay: it does not depend on d)
    wait.until(lambda d: (text(d, "rec-turning"), text(d, "rec-threshold")) != rec_before)
    assert float(text(driver, "rec-turning").split()[0]) == pytest.approx(rec["turning_effort"], rel=5e-4)
    assert float(text(driver, "rec-threshold").split()[0]) == pytest.approx(rec["threshold_force"], rel=5e-4)

    # click a point of the risk-bounded front: its card opens with the same numbers
    points = driver.find_elements(By.CSS_SELECTOR, "#front .scatterlayer .trace")[1].find_elements(
        By.CSS_SELECTOR, "path.point"
    )
    k = len(points) // 2
    ActionChains(driver).move_to_element(points[k]).pause(0.2).click().perform()
    wait.until(lambda d: text(d, "card-title").startswith("Card"))
    wait.until(lambda d: d.find_elements(By.ID, "card-knock") or d.find_elements(By.ID, "card-sweeps"))
    shown = float(text(driver, "card-turning").split()[0])
    assert min(abs(shown - v) / v for v in api[:, 0]) < 5e-4  # a point of that front
    assert "%" in text(driver, "card-probability")
    assert driver.find_elements(By.ID, "card-sweeps")
    drawing = driver.find_element(By.ID, "card-drawing")  # the drawing to scale
    assert drawing.tag_name == "img" and drawing.get_attribute("src").startswith("data:image/svg+xml")

    # my caster: 1 in trail, 8 in wheel, no groove, bare fork: V_c far below 3 m/s -> it shimmies
    for key, value in (("trail", "1 in"), ("diameter", "8 in"), ("groove", "0 in"), ("damping", "1.3")):
        box = driver.find_element(By.ID, f"mine-{key}")
        box.clear()
        box.send_keys(value)
    driver.find_element(By.ID, "mine-go").click()
    wait.until(lambda d: "chance of shimmy" in text(d, "mine-probability"))
    probability = float(re.search(r"([0-9.]+) %", text(driver, "mine-probability")).group(1))
    assert probability > 99.0
    wait.until(lambda d: "mine" in traces(d))
    wait.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#fixes li"))
    assert len(driver.find_elements(By.CSS_SELECTOR, "#fixes li")) >= 1

    # save the problem: the file the studio writes reads back to the problem shown
    driver.find_element(By.ID, "save").click()
    wait.until(lambda d: "saved" in text(d, "save-result"))
    saved = cwd / "out" / "indoor-manual.toml"
    assert tomllib.loads(saved.read_text())["shimmy"]["target_speed"] == "3 m/s"

    # min > max: the loader's message beside the control, the last valid front stays
    shown_front = traces(driver)["risk"]
    box = driver.find_element(By.CSS_SELECTOR, '[data-key="trail_min"] input')
    assert not box.is_displayed()  # the bounds are folded under "More controls"
    box.find_element(By.XPATH, "ancestor::details/summary").click()
    box.clear()
    box.send_keys("3 in", Keys.ENTER)
    wait.until(
        lambda d: (
            "min is greater than max" in d.find_element(By.CSS_SELECTOR, '[data-key="trail_min"] .control-error').text
        )
    )
    message = driver.find_element(By.CSS_SELECTOR, '[data-key="trail_min"] .control-error').text
    assert message.startswith("variables.trail") and "3.000 in > 2.500 in" in message
    assert traces(driver)["risk"] == shown_front
    assert not math.isnan(float(text(driver, "rec-turning").split()[0]))


PHONE = 390
"""A phone's CSS width [px] (an iPhone 12–15 held upright)."""


def test_studio_fits_a_phone(studio, browser):
    """At 390 px (Chromium's phone emulation) the studio does not scroll sideways: the page is 390 px wide and
    shown 390 px wide (a phone zooms out to show a wider page), and the chart, the recommendation and the first
    controls lie inside the window; planted, a 900 px wide block is seen."""
    _, url, _, _ = studio
    phone = browser(PHONE, 1800)
    phone.get(url)
    WebDriverWait(phone, WAIT, poll_frequency=0.1).until(lambda d: "computed" in text(d, "status"))
    sideways = "return [document.documentElement.scrollWidth, window.innerWidth]"
    assert phone.execute_script(sideways) == [PHONE, PHONE]
    for element in ("front", "recommendation", "first-controls"):
        box = phone.execute_script(f"return document.getElementById('{element}').getBoundingClientRect().toJSON()")
        assert 0 <= box["left"] and box["right"] <= PHONE and box["width"] > 0.8 * PHONE - 40, (element, box)
    phone.execute_script(
        "const d = document.createElement('div'); d.style.width = '900px'; d.style.height = '10px';"
        "document.body.append(d)"
    )
    assert min(phone.execute_script(sideways)) > PHONE


def test_ctrl_c_stops_cleanly(studio):
    """Ctrl-C (SIGINT) stops the server: exit code 0 and one line saying so."""
    import signal

    proc = studio[3]
    proc.send_signal(signal.SIGINT)
    assert proc.wait(30) == 0
    assert "stopped" in proc.stderr.read()
