"""Change-to-redraw latency of `designer studio` in a scripted headless-Chromium session (issue 14).

    python -m benchmarks.studio_latency [--steps 20] [--problem problems/indoor-manual.toml] [--out benchmarks]

Starts ``designer studio --port 0 --no-browser``, opens it in Debian's headless Chromium (Selenium), and
moves the target-speed slider one step (0.1 m/s) at a time with the keyboard, each step to a target not
seen before (no cache hit).  For each step it measures, in the browser's clock, the time from just before
the key press to the chart's next ``plotly_afterplot`` event (the redraw with the new fronts), and reads
the server's compute time from the status line.  Writes ``studio_latency.json`` and ``studio_latency.md``.
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

HOOK = """
const gd = document.querySelector('#front .js-plotly-plot');
window.__redraws = window.__redraws || [];
if (!gd.__hooked) { gd.on('plotly_afterplot', () => window.__redraws.push(performance.now())); gd.__hooked = true; }
return true;
"""


def main(argv=None) -> int:
    from selenium import webdriver
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import WebDriverWait

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--problem", default=None)
    parser.add_argument("--out", default=str(Path(__file__).resolve().parent))
    args = parser.parse_args(argv)

    work = Path(tempfile.mkdtemp(prefix="studio-bench-"))
    cmd = [sys.executable, "-m", "designer.cli", "studio", "--port", "0", "--no-browser", "--out", str(work)]
    if args.problem:
        cmd.insert(4, args.problem)
    t_start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    url = re.search(r"(http://\S+/)", line).group(1)
    startup = time.perf_counter() - t_start
    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium")
    for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu", "--window-size=1500,1100"):
        options.add_argument(a)
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(shutil.which("chromedriver")))
    rows = []
    try:
        wait = WebDriverWait(driver, 120, poll_frequency=0.01)
        t0 = time.perf_counter()
        driver.get(url)
        wait.until(lambda d: "computed" in d.find_element(By.ID, "status").text)
        first_view = time.perf_counter() - t0
        wait.until(lambda d: d.execute_script(HOOK))
        handle = driver.find_element(By.CSS_SELECTOR, '[data-key="target"] [role="slider"]')
        driver.execute_script("arguments[0].focus()", handle)
        for _ in range(args.steps // 2):  # start below the default so that every step is a new target
            handle.send_keys(Keys.ARROW_LEFT)
        wait.until(lambda d: f"target={2.5 - 0.1 * (args.steps // 2):g}" in d.current_url)
        time.sleep(0.5)
        for _ in range(args.steps):
            before = driver.execute_script("return performance.now()")
            handle.send_keys(Keys.ARROW_RIGHT)
            wait.until(lambda d: any(t > before for t in d.execute_script("return window.__redraws")))
            after = min(t for t in driver.execute_script("return window.__redraws") if t > before)
            status = driver.find_element(By.ID, "status").text
            compute = re.search(r"computed in (\d+) ms \((\d+) ms CPU\)", status)
            target = float(handle.get_attribute("aria-valuenow"))
            rows.append(
                {
                    "target_speed": target,
                    "redraw_ms": after - before,
                    "compute_ms": float(compute.group(1)) if compute else None,
                    "compute_cpu_ms": float(compute.group(2)) if compute else None,
                }
            )
            time.sleep(0.3)
    finally:
        driver.quit()
        proc.terminate()
        proc.wait(30)
    redraw = [r["redraw_ms"] for r in rows]
    compute = [r["compute_ms"] for r in rows if r["compute_ms"] is not None]
    cpu = [r["compute_cpu_ms"] for r in rows if r["compute_cpu_ms"] is not None]
    summary = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}",
        "problem": args.problem or "problems/indoor-manual.toml (default)",
        "steps": len(rows),
        "startup_s": startup,
        "first_view_s": first_view,
        "redraw_ms": {
            "median": statistics.median(redraw),
            "min": min(redraw),
            "max": max(redraw),
            "p90": sorted(redraw)[int(0.9 * (len(redraw) - 1))],
        },
        "compute_ms": {"median": statistics.median(compute), "min": min(compute), "max": max(compute)},
        "compute_cpu_ms": {"median": statistics.median(cpu), "min": min(cpu), "max": max(cpu)},
        "rows": rows,
    }
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "studio_latency.json").write_text(json.dumps(summary, indent=2))
    md = [
        f"# Studio change-to-redraw latency ({summary['date']})",
        "",
        f"Machine: {summary['machine']}. Problem: {summary['problem']}. "
        f"{len(rows)} slider steps of 0.1 m/s, each to a new target (no cache hit).",
        "",
        "| | median | min | p90 | max |",
        "|---|---:|---:|---:|---:|",
        "| key press -> chart redrawn [ms] | {median:.0f} | {min:.0f} | {p90:.0f} | {max:.0f} |".format(
            **summary["redraw_ms"]
        ),
        "| server: fronts + recommendation [ms] | {median:.0f} | {min:.0f} | | {max:.0f} |".format(
            **summary["compute_ms"]
        ),
        "| server: CPU time of that computation [ms] | {median:.0f} | {min:.0f} | | {max:.0f} |".format(
            **summary["compute_cpu_ms"]
        ),
        "",
        "On a shared machine the wall times include waiting for a core (see the load average); the CPU time "
        "is about what the computation takes on an idle machine. Browser and network add the difference "
        "between the first two rows.",
        "",
        f"Start-up (command to URL, solver warmed): {startup:.1f} s; first view in the browser: {first_view:.1f} s.",
        "",
    ]
    (out / "studio_latency.md").write_text("\n".join(md))
    print("\n".join(md))
    return 0


if __name__ == "__main__":
    sys.exit(main())
