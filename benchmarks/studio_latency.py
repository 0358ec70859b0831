"""Change-to-redraw latency of `designer studio` in a scripted headless-Chromium session (issues 14, 29.2).

    python -m benchmarks.studio_latency [--steps 20] [--rounds 1] [--problem PATH] [--out DIR]
                                        [--before CHECKOUT] [--write]
    python -m benchmarks.studio_latency --show     # the medians of the last run saved in --out

Starts ``designer studio --port 0 --no-browser``, opens it in Debian's headless Chromium (Selenium) at a target
speed of :data:`START` m/s (through the URL), and moves the target-speed slider one step (0.1 m/s) at a time
with the keyboard, each step to a target not computed before in that session (no cache hit).  For each step,
in the browser's clock:

- key press -> redraw: from the ``keydown`` event to the chart's first ``plotly_afterplot`` after the answer
  to the callback's request (the redraw with the new fronts);
- the same from just before the WebDriver call that presses the key (the measure of issue 14's runs, which
  also counts the driver's round trip);
- its parts: key press -> request sent, the request (server and network), answer -> redraw (the browser);
- the page's main-thread busy time per step (Chrome DevTools' ``TaskDuration``, from the key press to the
  redraw): the browser's CPU-bound work, which the load hardly changes;

and the server's compute time and CPU time from the status line.  The load average is printed at the start
and the end and written with the results.  The script waits for each answer in the page (:data:`ANSWERED`),
not by polling through WebDriver, so measuring takes next to no CPU from the studio's processes.

``--before CHECKOUT`` (e.g. ``git worktree add --detach /tmp/before <commit>``) runs the studio of that checkout
too, in sessions interleaved with this checkout's (``--rounds`` of each), so both see the same load; the
tables then have a before and an after column.  The studio children run without ``PYTHONDONTWRITEBYTECODE``
(else each start compiles the package).  Writes ``studio_latency.json`` and ``studio_latency.md`` into
``--out``; ``--write`` also puts the table into ``benchmarks/results.md`` between the studio markers.
Needs the ``studio`` extra and the system chromium + chromium-driver.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results.md"
BEGIN, END = "<!-- studio latency: begin -->", "<!-- studio latency: end -->"
AIM_MS = 150.0
"""Issue 44: key press to redraw <= 150 ms at the median (issues 14 and 29.2 asked for 300 ms)."""
START = 2.6
"""Target speed [m/s] the session opens at (through the URL); the steps go up from there, so none reaches the
default 2.5 m/s that the studio computes while it starts."""

HOOK = """
const gd = document.querySelector('#front .js-plotly-plot');
if (!gd) return false;  // the chart's code still loading
if (!window.__hooked) {
    window.__keys = []; window.__redraws = []; window.__requests = [];
    document.addEventListener('keydown', e => window.__keys.push(e.timeStamp), true);
    gd.on('plotly_afterplot', () => window.__redraws.push(performance.now()));
    new PerformanceObserver(list => list.getEntries().forEach(e => {
        if (e.name.includes('_dash-update-component')) window.__requests.push([e.startTime, e.responseEnd]);
    })).observe({type: 'resource'});
    window.__hooked = true;
}
return true;
"""
ANSWERED = """
const [before, target, done] = arguments;
(function check() {
    const key = window.__keys.find(k => k > before);
    const request = key === undefined ? undefined : window.__requests.find(r => r[0] > key);
    const redraw = request === undefined ? undefined : window.__redraws.find(t => t > request[1]);
    if (redraw !== undefined && Math.abs(parseFloat(new URLSearchParams(location.search).get('target')) - target) < 1e-9) {
        done([key, request, redraw]);
    } else {
        setTimeout(check, 5);
    }
})();
"""
"""Waits in the page for the redraw that answers the key press after ``before`` (its URL at ``target``) and returns
(key press, [request sent, answer], redraw) in the page's clock.  The wait is the page's own timer: a few µs of
the browser's time every 5 ms, where polling through WebDriver (two round trips every 10 ms: this script, the
driver and the page) took CPU from the studio's two processes on a 2-core machine."""

PARTS = {
    "redraw_ms": "key press -> chart redrawn [ms]",
    "driver_redraw_ms": "the same, from the WebDriver call (issue 14's measure) [ms]",
    "to_request_ms": "key press -> request sent [ms]",
    "request_ms": "request: server and network [ms]",
    "browser_ms": "answer -> chart redrawn (browser) [ms]",
    "browser_busy_ms": "browser: main-thread busy time per step [ms]",
    "compute_ms": "server: fronts + recommendation [ms]",
    "compute_cpu_ms": "server: CPU time of that computation [ms]",
}


def _load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"{one:.2f}, {five:.2f}, {fifteen:.2f}"


def _chrome():
    from selenium import webdriver

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium")
    for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu", "--window-size=1500,1100"):
        options.add_argument(a)
    return webdriver.Chrome(options=options, service=webdriver.ChromeService(shutil.which("chromedriver")))


def _step(driver, handle, target: float) -> dict:
    """Press → once; wait for the redraw that answers it; its times (module text)."""
    from selenium.webdriver.common.keys import Keys

    before = driver.execute_script("return performance.now()")
    handle.send_keys(Keys.ARROW_RIGHT)
    key, (sent, answer), redraw = driver.execute_async_script(ANSWERED, before, target)
    status = driver.find_element("id", "status").text
    compute = re.search(r"computed in (\d+) ms \((\d+) ms CPU\)", status)
    return {
        "target_speed": target,
        "redraw_ms": redraw - key,
        "driver_redraw_ms": redraw - before,
        "to_request_ms": sent - key,
        "request_ms": answer - sent,
        "browser_ms": redraw - answer,
        "compute_ms": float(compute.group(1)) if compute else None,
        "compute_cpu_ms": float(compute.group(2)) if compute else None,
    }


def _busy(driver) -> float:
    """The page's main-thread busy time so far [ms] (Chrome DevTools' TaskDuration: the CPU-bound part of the
    browser's work, about the same at any load)."""
    metrics = driver.execute_cdp_cmd("Performance.getMetrics", {})["metrics"]
    return 1000.0 * next(m["value"] for m in metrics if m["name"] == "TaskDuration")


def session(tree: Path, steps: int, problem: str | None) -> dict:
    """One studio of checkout ``tree`` in one browser: start-up, first view, ``steps`` slider steps."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    work = Path(tempfile.mkdtemp(prefix="studio-bench-"))
    env = {**os.environ, "PYTHONPATH": str(tree)}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    cmd = [sys.executable, "-m", "designer.cli", "studio", "--port", "0", "--no-browser", "--out", str(work)]
    if problem:
        cmd.insert(4, str(Path(problem).resolve()))
    t_start = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=tree, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    driver = None
    try:
        line = proc.stdout.readline()
        match = re.search(r"(http://\S+/)", line)
        if not match:
            raise RuntimeError(f"the studio printed no URL: {line!r} {proc.stderr.read()[-2000:]}")
        startup = time.perf_counter() - t_start
        driver = _chrome()
        wait = WebDriverWait(driver, 120, poll_frequency=0.01)
        t0 = time.perf_counter()
        driver.get(f"{match.group(1)}?target={START:g}")
        wait.until(lambda d: "computed" in d.find_element(By.ID, "status").text)
        first_view = time.perf_counter() - t0
        wait.until(lambda d: d.execute_script(HOOK))
        driver.set_script_timeout(120)  # s: one step's answer (ANSWERED)
        handle = driver.find_element(By.CSS_SELECTOR, '[data-key="target"] [role="slider"]')
        driver.execute_script("arguments[0].focus()", handle)
        time.sleep(0.5)
        driver.execute_cdp_cmd("Performance.enable", {})
        busy = _busy(driver)
        rows = []
        for i in range(1, steps + 1):
            rows.append(_step(driver, handle, round(START + 0.1 * i, 6)))
            rows[-1]["browser_busy_ms"] = _busy(driver) - busy
            time.sleep(0.3)
            busy = _busy(driver)
    finally:
        if driver is not None:
            driver.quit()
        proc.terminate()
        proc.wait(30)
        shutil.rmtree(work, ignore_errors=True)
    return {"startup_s": startup, "first_view_s": first_view, "rows": rows}


def _commit(tree: Path) -> str:
    out = subprocess.run(["git", "-C", str(tree), "log", "-1", "--format=%h %cs"], capture_output=True, text=True)
    return out.stdout.strip() or "?"


def summarise(sessions: list[dict]) -> dict:
    """Median, min, p90 and max of every part over all steps of ``sessions``."""
    rows = [r for s in sessions for r in s["rows"]]
    out = {"steps": len(rows)}
    for key in PARTS:
        values = sorted(r[key] for r in rows if r[key] is not None)
        out[key] = {
            "median": statistics.median(values),
            "min": values[0],
            "p90": values[int(0.9 * (len(values) - 1))],
            "max": values[-1],
        }
    out["startup_s"] = statistics.median(s["startup_s"] for s in sessions)
    out["first_view_s"] = statistics.median(s["first_view_s"] for s in sessions)
    return out


def markdown(summary: dict) -> list[str]:
    """The tables of a run: after (this checkout) and, when measured, before."""
    runs = summary["runs"]
    names = list(runs)
    lines = [
        f"## Studio: key press to redraw (`python -m benchmarks.studio_latency`, {summary['date']})",
        "",
        f"Machine: {summary['machine']}; load average (1, 5, 15 min) {summary['load_start']} at the start, "
        f"{summary['load_end']} at the end. Problem: {summary['problem']}. "
        f"{summary['rounds']} session(s) of {summary['steps']} slider steps of 0.1 m/s per checkout"
        + (", interleaved" if len(names) > 1 else "")
        + f", from {START:g} m/s up, each to a target not computed before (no cache hit). "
        + "; ".join(f"{name}: {runs[name]['commit']}" for name in names)
        + ".",
        "",
        "| median (min – p90 – max) | " + " | ".join(names) + " |",
        "|---|" + "---:|" * len(names),
    ]
    for key, label in PARTS.items():
        cells = []
        for name in names:
            s = runs[name]["summary"][key]
            cells.append(f"**{s['median']:.0f}** ({s['min']:.0f} – {s['p90']:.0f} – {s['max']:.0f})")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append(
        "| start-up (command to URL) / first view [s] | "
        + " | ".join(f"{runs[n]['summary']['startup_s']:.1f} / {runs[n]['summary']['first_view_s']:.1f}" for n in names)
        + " |"
    )
    after = runs[names[-1]]["summary"]["redraw_ms"]["median"]
    lines += [
        "",
        f"Aim (issue 44): key press to redraw <= {AIM_MS:.0f} ms at the median; this run: {after:.0f} ms "
        + ("(met)." if after <= AIM_MS else "(not met)."),
        "The server's times come from the studio's status line (the compute of the fronts and the recommendation, "
        "CPU time of both studio processes); on a shared machine the wall times include waiting for a core (see "
        "the load average), while the two CPU rows (server, browser main thread) are about what a change costs on "
        "an idle machine.",
        "",
    ]
    return lines


SHOWN = {
    "redraw_ms": "key press -> chart redrawn",
    "compute_ms": "server: fronts + recommendation",
    "compute_cpu_ms": "server: CPU time of that",
    "browser_ms": "browser: answer -> redraw",
}
"""The rows of :func:`show` (medians) and their labels."""


def show(summary: dict) -> list[str]:
    """The medians of a saved run in a few lines of text at most 80 wide (docs/studio.md shows them)."""
    runs = summary["runs"]
    names = list(runs)
    width = 34
    lines = [
        f"last run {summary['date'][:10]} ({summary['machine']}, load {summary['load_start'].split(',')[0]}),"
        f" {summary['rounds']} x {summary['steps']} steps each; medians:",
        " " * width + "".join(f"{name + ' ' + runs[name]['commit'][:7]:>16}" for name in names),
    ]
    for key, label in SHOWN.items():
        lines.append(f"{label:<{width}}" + "".join(f"{runs[n]['summary'][key]['median']:>13.0f} ms" for n in names))
    after = runs[names[-1]]["summary"]["redraw_ms"]["median"]
    lines.append(
        f"aim: key press -> redraw <= {AIM_MS:.0f} ms at the median: " + ("met" if after <= AIM_MS else "not met")
    )
    return lines


def write_results(lines: list[str]) -> None:
    """Put ``lines`` between the studio markers of benchmarks/results.md (appended the first time)."""
    text = RESULTS.read_text(encoding="utf-8")
    block = "\n".join([BEGIN, *lines, END])
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + block + rest.split(END, 1)[1]
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    RESULTS.write_text(text, encoding="utf-8")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=1, help="sessions per checkout (interleaved with --before)")
    parser.add_argument("--problem", default=None)
    parser.add_argument("--before", default=None, help="a checkout of the code to compare with (its studio runs too)")
    parser.add_argument("--out", default=str(Path(__file__).resolve().parent))
    parser.add_argument("--write", action="store_true", help="also write the table into benchmarks/results.md")
    parser.add_argument("--show", action="store_true", help="print the medians of the run saved in --out; run nothing")
    args = parser.parse_args(argv)
    if args.show:
        print("\n".join(show(json.loads((Path(args.out) / "studio_latency.json").read_text()))))
        return 0

    trees = {"after": ROOT}
    if args.before:
        trees = {"before": Path(args.before).resolve(), "after": ROOT}
    load_start = _load()
    print(f"load average at the start: {load_start}", flush=True)
    sessions: dict = {name: [] for name in trees}
    for r in range(args.rounds):
        for name, tree in trees.items():
            sessions[name].append(session(tree, args.steps, args.problem))
            redraw = statistics.median(row["redraw_ms"] for row in sessions[name][-1]["rows"])
            print(f"round {r + 1}, {name}: median key press -> redraw {redraw:.0f} ms (load {_load()})", flush=True)
    load_end = _load()
    print(f"load average at the end: {load_end}", flush=True)
    summary = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "machine": f"{platform.machine()}, {os.cpu_count()} cores",
        "load_start": load_start,
        "load_end": load_end,
        "problem": args.problem or "problems/indoor-manual.toml (default)",
        "steps": args.steps,
        "rounds": args.rounds,
        "runs": {
            name: {"commit": _commit(tree), "summary": summarise(sessions[name]), "sessions": sessions[name]}
            for name, tree in trees.items()
        },
    }
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "studio_latency.json").write_text(json.dumps(summary, indent=2))
    lines = markdown(summary)
    (out / "studio_latency.md").write_text("\n".join(lines))
    if args.write:
        write_results(lines)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
