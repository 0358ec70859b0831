"""Regenerate every image in docs/ and the record of the data each is drawn from (docs/img/sources.json).

Run from the repository root (needs matplotlib, Dash, Selenium and Debian's ``chromium`` + ``chromium-driver``;
takes about two minutes)::

    python docs/img/render.py            # every image, then sources.json
    python docs/img/render.py studio     # the images whose name contains "studio" (sources.json updated for them)

Each image has a *source*: the text of the data it is drawn from (a repr's HTML, a plot's arrays, a command's
output at 80 columns, the committed report page it photographs, the studio's fronts and page layout), numbers
rounded to 6 significant digits.  ``sources.json`` keeps a digest of each; tests/docs/test_images.py
recomputes the sources (no browser, no pixels) and fails when one differs: the image is then stale, and this
command redraws it.

The images: the notebook reprs (``_repr_html_``) and plot methods; the report's first screen at 1400 and
390 px and its figures (results/indoor-manual/index.html); ``designer fix`` and ``designer fleet`` at
``COLUMNS=80`` (docs/img/terminal.py); a fleet report's first screen; the tilted-stem figure
(:mod:`designer.plots.stem`); the inspection sheet of ``designer spec`` (A4 and a 390 px phone); the studio at 1400 and 390 px and with a bad value.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
OUT = DOCS / "img"
SOURCES = OUT / "sources.json"
REPORT = ROOT / "results" / "indoor-manual" / "index.html"
FIX = ["designer", "fix", "problems/indoor-manual.toml", "--current", "T=1.25in,d=8in,B=0,c=1.3"]
FLEET = ["designer", "fleet", "fleet-example-500.csv", "--skus", "4"]
PAGE = (
    '<!doctype html><html><head><meta charset="utf-8"><title>{title}</title></head>'
    '<body style="margin:12px;background:white">{body}</body></html>'
)
WINDOWS = {"front": "680,190", "recommendation": "920,275", "simulation": "700,230"}
"""Chromium window size [px] per repr (the repr's own size plus a margin)."""
sys.path.insert(0, str(OUT))  # terminal.py beside this file


# --------------------------------------------------------------------------- what the images show


@functools.cache
def _notebook():
    """(front, recommendation, simulation) of the default problem, as the example notebook makes them."""
    import designer

    problem = designer.example_problem("indoor-manual")
    front = designer.pareto_front(problem, points=41)
    rec = designer.recommend(problem)
    # 10 % above Eq. 7's V_c the knock grows: the plot shows shimmy building up
    sim = designer.simulate(rec.design, problem.conditions, speed=1.1 * rec.critical_speed, cycles=12)
    return front, rec, sim


@functools.cache
def _plots() -> dict:
    """The notebook's figures by image name (matplotlib, Agg)."""
    import matplotlib

    matplotlib.use("Agg")
    front, rec, sim = _notebook()
    return {
        "img/plot-front.png": front.plot().figure,
        "img/plot-variables.png": front.plot_variables().flat[0].figure,
        "img/recommendation-draw.png": rec.draw()[0].figure,
        "img/simulation-plot.png": sim.plot().figure,
    }


@functools.cache
def _terminal(command: tuple[str, ...], folder: str | None = None) -> str:
    """What ``command`` prints at ``COLUMNS=80`` (``designer`` run as ``python -m designer``)."""
    run = [sys.executable, "-m", "designer", *command[1:]]
    env = os.environ | {"COLUMNS": "80", "LINES": "200", "TERM": "dumb"}
    return subprocess.run(run, env=env, capture_output=True, text=True, check=True, cwd=folder or ROOT).stdout


@functools.cache
def _fleet_folder() -> str:
    """A folder holding the example fleet of 500 chairs and its report (results/fleet/fleet-example-500/)."""
    folder = tempfile.mkdtemp(prefix="docs-fleet-")
    _terminal(("designer", "fleet", "--example", "500"), folder)
    _terminal(tuple(FLEET), folder)
    return folder


@functools.cache
def _spec_page() -> Path:
    """The default problem's inspection sheet (``designer spec``), written into a temporary folder."""
    page = Path(tempfile.mkdtemp(prefix="docs-spec-")) / "spec.html"
    _terminal(("designer", "spec", "problems/indoor-manual.toml", "--out", str(page)))
    return page


def _fleet_page() -> Path:
    return Path(_fleet_folder()) / "results" / "fleet" / "fleet-example-500" / "index.html"


@functools.cache
def _studio_data() -> str:
    """The studio's default view: its fronts and recommendation (numbers) and its page layout (components)."""
    from designer.studio import state, view
    from designer.studio.layout import build_layout

    data, name = state.read_problem_data(state.default_problem_path())
    values = state.control_values(data)
    problem, _ = state.build_problem(data, values)
    fronts = view.compute_spec(problem)  # the card as shown once its limits are filled in
    numbers = {
        part: None if f is None else f.objectives().tolist()
        for part, f in (("continuous", fronts.continuous), ("risk", fronts.risk), ("buildable", fronts.buildable))
    }
    numbers["recommendation"] = view.recommendation_record(fronts.recommendation)
    layout = build_layout(name, values).to_plotly_json()
    return _text({"numbers": numbers, "layout": layout})


def _figure_data(fig) -> str:
    """The data a matplotlib figure draws: every line's and collection's points, every text."""
    out = []
    for ax in fig.axes:
        out.append([line.get_xydata().tolist() for line in ax.get_lines()])
        out.append([np.asarray(c.get_offsets()).tolist() for c in ax.collections])
        out.append([t.get_text() for t in ax.texts] + [ax.get_xlabel(), ax.get_ylabel(), ax.get_title()])
    return _text(out)


def _text(obj) -> str:
    """``obj`` as JSON with numbers at 6 significant digits (the last digits of a solve vary by machine)."""

    def rounded(x):
        if isinstance(x, float):
            return float(f"{x:.6g}")
        if isinstance(x, dict):
            return {str(k): rounded(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [rounded(v) for v in x]
        if hasattr(x, "to_plotly_json"):
            return rounded(x.to_plotly_json())
        if isinstance(x, np.generic):
            return rounded(x.item())
        return x if isinstance(x, (str, int, bool, type(None))) else str(x)

    return json.dumps(rounded(obj), sort_keys=True, ensure_ascii=False)


def _untimed(text: str) -> str:
    """A command's output without its run times (``time [s]: ...`` and its wrapped lines): they vary by run."""
    return re.sub(r"time \[s\]:[^\n]*(\n    [^\n]*)*", "time [s]: ...", text)


def _page_text(path: Path) -> str:
    """A report page's text as Chromium draws it (the run's own folder names removed)."""
    return re.sub(r"/tmp/docs-(fleet|spec)-\w+", "FOLDER", path.read_text(encoding="utf-8"))


# --------------------------------------------------------------------------- drawing them


def _chromium(page: str | Path, png: Path, window: str) -> None:
    subprocess.run(
        [
            "chromium",
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            f"--screenshot={png}",
            f"--window-size={window}",
            Path(page).as_uri() if isinstance(page, Path) else page,
        ],
        check=True,
        capture_output=True,
    )


def _driver(width: int, height: int):
    """Selenium's headless Chromium with a ``width`` x ``height`` CSS px viewport (a phone below 500 px)."""
    from selenium import webdriver

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium") or "chromium"
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"):
        options.add_argument(arg)
    options.add_argument(f"--window-size={max(width, 500)},{height}")
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(shutil.which("chromedriver")))
    driver.execute_cdp_cmd(
        "Emulation.setDeviceMetricsOverride",
        {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": width < 500},
    )
    return driver


def _repr(name: str) -> Callable[[Path], None]:
    def render(png: Path) -> None:
        obj = dict(zip(("front", "recommendation", "simulation"), _notebook()))[name]
        with tempfile.TemporaryDirectory() as tmp:
            page = Path(tmp) / f"{name}.html"
            page.write_text(PAGE.format(title=name, body=obj._repr_html_()), encoding="utf-8")
            _chromium(page, png, WINDOWS[name])

    return render


def _plot(png: Path) -> None:
    _plots()[png.relative_to(DOCS).as_posix()].savefig(png, dpi=90)


def _page_shot(page: Callable[[], Path], width: int, height: int, clip: tuple[str, str] | None = None):
    """Screenshot of ``page`` in a ``width`` px window: the first ``height`` px, or (``clip``) the part from the
    top of one element to the bottom of another (CSS selectors), at half scale."""

    def render(png: Path) -> None:
        import base64

        driver = _driver(width, height)
        try:
            driver.get(page().as_uri())
            if clip is None:
                driver.save_screenshot(str(png))
                return
            top, bottom = (
                driver.execute_script(f"return document.querySelector('{sel}').getBoundingClientRect().toJSON()")
                for sel in clip
            )
            box = {"x": 0, "y": top["top"], "width": width, "height": bottom["bottom"] - top["top"], "scale": 0.5}
            shot = driver.execute_cdp_cmd("Page.captureScreenshot", {"clip": box, "captureBeyondViewport": True})
            png.write_bytes(base64.b64decode(shot["data"]))
        finally:
            driver.quit()

    return render


def _terminal_png(command: list[str], folder: Callable[[], str] | None = None):
    def render(png: Path) -> None:
        import terminal

        cwd = os.getcwd()
        os.chdir(folder() if folder else ROOT)
        try:
            terminal.main([png.name, "--", *command])
        finally:
            os.chdir(cwd)

    return render


def _stem(png: Path) -> None:
    from designer.plots.stem import stem_angle_figure
    from designer.studies.curves import stem_curves

    stem_angle_figure(png, stem_curves())


def _stem_source() -> str:
    from designer.plots.stem import stem_figure
    from designer.studies.curves import stem_curves

    return _figure_data(stem_figure(stem_curves()))


def _limits_shown(text: str) -> bool:
    """The studio card's ``rec-limits`` shows the limits (not the placeholder of the second callback)."""
    from designer.studio.panels import LIMITS_PENDING

    return text.startswith("acceptance limits") and text != LIMITS_PENDING


def _studio(width: int, height: int, bad: bool = False):
    """Screenshot of ``designer studio`` (its own process) at ``width`` px; ``bad``: trail min 3 in > max."""

    def render(png: Path) -> None:
        from selenium.webdriver.common.by import By
        from selenium.webdriver.common.keys import Keys
        from selenium.webdriver.support.ui import WebDriverWait

        with tempfile.TemporaryDirectory() as tmp:
            cmd = [sys.executable, "-m", "designer", "studio", "--port", "0", "--no-browser", "--out", tmp]
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
            driver = None
            try:
                url = re.search(r"(http://127\.0\.0\.1:\d+/)", proc.stdout.readline()).group(1)
                driver = _driver(width, height)
                driver.get(url)
                wait = WebDriverWait(driver, 120)
                wait.until(lambda d: any("computed" in e.text for e in d.find_elements(By.ID, "status")))
                # the card's acceptance limits come a moment after the chart (the studio's second callback)
                wait.until(lambda d: any(_limits_shown(e.text) for e in d.find_elements(By.ID, "rec-limits")))
                if bad:
                    box = driver.find_element(By.CSS_SELECTOR, '[data-key="trail_min"] input')
                    box.find_element(By.XPATH, "ancestor::details/summary").click()
                    box.clear()
                    box.send_keys("3 in", Keys.ENTER)
                    error = '[data-key="trail_min"] .control-error'
                    wait.until(lambda d: "greater" in d.find_element(By.CSS_SELECTOR, error).text)
                    driver.execute_script("document.querySelector('[data-key=\"trail_min\"]').scrollIntoView()")
                driver.execute_script("document.querySelector('#status').textContent = ''")  # its times vary
                driver.save_screenshot(str(png))
            finally:
                if driver is not None:
                    driver.quit()
                proc.kill()

    return render


# --------------------------------------------------------------------------- the list


IMAGES: dict[str, tuple[Callable[[], str], Callable[[Path], None]]] = {
    "img/repr-front.png": (lambda: _notebook()[0]._repr_html_(), _repr("front")),
    "img/repr-recommendation.png": (lambda: _notebook()[1]._repr_html_(), _repr("recommendation")),
    "img/repr-simulation.png": (lambda: _notebook()[2]._repr_html_(), _repr("simulation")),
    "img/plot-front.png": (lambda: _figure_data(_plots()["img/plot-front.png"]), _plot),
    "img/plot-variables.png": (lambda: _figure_data(_plots()["img/plot-variables.png"]), _plot),
    "img/recommendation-draw.png": (lambda: _figure_data(_plots()["img/recommendation-draw.png"]), _plot),
    "img/simulation-plot.png": (lambda: _figure_data(_plots()["img/simulation-plot.png"]), _plot),
    "img/first-screen.png": (lambda: _page_text(REPORT), _page_shot(lambda: REPORT, 1400, 1000)),
    "img/report-390.png": (lambda: _page_text(REPORT), _page_shot(lambda: REPORT, 390, 1500)),
    "img/report-figures.png": (
        lambda: _page_text(REPORT),
        _page_shot(lambda: REPORT, 1400, 1000, ("#figures", "#fig-groove_damper")),
    ),
    "img/fix-80-columns.png": (lambda: _terminal(tuple(FIX)), _terminal_png(FIX)),
    "img/fleet-80-columns.png": (
        lambda: _untimed(_terminal(tuple(FLEET), _fleet_folder())),
        _terminal_png(FLEET, _fleet_folder),
    ),
    "img/fleet-first-screen.png": (lambda: _page_text(_fleet_page()), _page_shot(_fleet_page, 1400, 1000)),
    "img/spec-sheet.png": (lambda: _page_text(_spec_page()), _page_shot(_spec_page, 765, 990)),
    "img/sheet-390.png": (lambda: _page_text(_spec_page()), _page_shot(_spec_page, 390, 1400)),
    "retrofit-stem.png": (_stem_source, _stem),
    "img/studio-1400.png": (_studio_data, _studio(1400, 1000)),
    "img/studio-390.png": (_studio_data, _studio(390, 1500)),
    "studio-bad-input.png": (_studio_data, _studio(1400, 900, bad=True)),
}
"""Every image in docs/ (path under docs/): (its source's text, how to draw it)."""


def digest(text: str) -> str:
    """The digest sources.json keeps of a source's text."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def sources(names=None) -> dict[str, str]:
    """{image: digest of its source} for ``names`` (default: every image)."""
    return {name: digest(IMAGES[name][0]()) for name in (names or IMAGES)}


def main(argv: list[str] | None = None) -> int:
    wanted = (argv if argv is not None else sys.argv[1:]) or [""]
    names = [n for n in IMAGES if any(w in n for w in wanted)]
    os.chdir(ROOT)
    recorded = json.loads(SOURCES.read_text()) if SOURCES.exists() else {}
    for name in names:
        IMAGES[name][1](DOCS / name)
        recorded[name] = digest(IMAGES[name][0]())
        print(f"docs/{name}")
    SOURCES.write_text(json.dumps(dict(sorted(recorded.items())), indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
