"""The main job, cold: ``python -m benchmarks.main_job [PROBLEM] [--repeats N] [--before DIR] [--write]``.

Two measurements of ``designer pareto PROBLEM`` (default problems/indoor-manual.toml), each in fresh
interpreters, against ``python -c "import numpy"`` in the same run (interleaved, so all three see the same
load):

- the whole process, ``python -m designer pareto PROBLEM --out TMP``: wall seconds and CPU seconds
  (user + system of the child, ``resource.getrusage``), and their ratios to the numpy import's, against the
  aims of issue 29: wall <= 12 x, CPU <= 10 x;
- the split: a child that imports the package, reads the problem, runs ``report_data`` and ``write_report``
  and prints the CPU seconds of each step (``ReportData.run``'s ``compute_cpu_seconds`` and
  ``render_cpu_seconds``, measured with time.process_time).

``--before DIR``: a checkout of earlier code with its own ``DIR/.venv`` (e.g. ``git worktree add /tmp/before
main``, then the README's install there) is measured in the same run, interleaved with this one, so a change's
cost is read side by side under the same load.

Cold means a new interpreter with no warm state of this process; Python's bytecode caches are on, as for
any run after the first (an unmeasured run writes them first; ``PYTHONDONTWRITEBYTECODE`` is dropped from the
children's environment, else every run would compile the package from source).  ``--write`` puts the tables,
with the load average at start and end, into ``benchmarks/results.md`` between the main-job markers, with the
before column quoted from issue 29 (:data:`BEFORE`).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results.md"
BEGIN, END = "<!-- main job: begin -->", "<!-- main job: end -->"
AIM_WALL, AIM_CPU = 12.0, 10.0
"""Issue 29: the main job's wall time <= 12 x and CPU <= 10 x those of ``python -c "import numpy"``."""
BEFORE = {
    "source": "issue 29 (2-core machine, cold, median of 3; before the SVG figures, the knock events without "
    "scipy.optimize and the import trimming)",
    "numpy_cpu": 0.35,
    "steps": {
        "import": 1.52,
        "front": 0.44,
        "tighter": 0.21,
        "recommendation": 0.11,
        "knock_safe": 1.47,
        "optimum, checks, tradeoff": 0.21,
        "figures": 5.07,
        "writing": 0.25,
        "total": 9.50,
    },
    "process_cpu": 8.4,
    "process_wall": 8.1,
    "process_cpu_ratio": 22.6,
}
"""The before column, quoted from issue 29's table (CPU seconds) and its whole-process measurement."""

CHILD = r"""
import json, sys, time, warnings
c0 = time.process_time()
import designer
from designer.problem import load_problem
from designer.pipeline import report_data
from designer.report import write_report
imp = time.process_time() - c0
warnings.simplefilter("ignore")
c1 = time.process_time()
problem = load_problem(sys.argv[1])
load = time.process_time() - c1
data = report_data(problem)
write_report(data, sys.argv[2])
out = {"import": imp, "load problem": load, **data.run["compute_cpu_seconds"], **data.run["render_cpu_seconds"],
       "total": time.process_time()}
print(json.dumps(out))
"""


def child_env(tree: Path = ROOT) -> dict:
    """The children's environment: bytecode caches on (as a user's runs after the first), the package of ``tree``."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPATH"] = str(tree)
    return env


def run(command: list[str], tree: Path = ROOT) -> tuple[float, float, str]:
    """(wall [s], CPU [s] = user + system of the child, stdout) of one child process run in ``tree``; raises on
    failure."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(command, cwd=tree, capture_output=True, text=True, env=child_env(tree))
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 1):  # 1: a front check failed; the report is still written
        raise RuntimeError(f"{' '.join(command)} exited {done.returncode}: {done.stderr[-800:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stdout


def measure(problem: str, repeats: int, before: Path | None = None) -> dict:
    """Interleaved repeats of the numpy import, the whole process and the split (and, with ``before``, the same two
    of that checkout with its own interpreter); medians and ranges."""
    numpy_cmd = [sys.executable, "-c", "import numpy"]
    trees = {"": (ROOT, sys.executable)}
    if before is not None:
        trees["before "] = (before, str(before / ".venv" / "bin" / "python"))
    rows: dict[str, list] = {"numpy": []}
    with tempfile.TemporaryDirectory() as tmp:
        # each checkout writes its own folders: a report of one release is not the other's to replace (manifests)
        slot = {tag: f"{tmp}/{'before' if tag else 'after'}" for tag in trees}
        for tag, (tree, python) in trees.items():
            run([python, "-m", "designer", "pareto", problem, "--out", f"{slot[tag]}-w"], tree)  # unmeasured: caches
            rows[f"{tag}process"], rows[f"{tag}split"] = [], []
        for _ in range(repeats):
            rows["numpy"].append(run(numpy_cmd)[:2])
            for tag, (tree, python) in trees.items():
                rows[f"{tag}process"].append(
                    run([python, "-m", "designer", "pareto", problem, "--out", f"{slot[tag]}-p"], tree)[:2]
                )
                out = run([python, "-c", CHILD, problem, f"{slot[tag]}-s"], tree)[2]
                rows[f"{tag}split"].append(json.loads(out.strip().splitlines()[-1]))
    med = statistics.median
    result: dict = {
        name: {
            "wall": med(w for w, _ in rows[name]),
            "cpu": med(c for _, c in rows[name]),
            "wall_range": [min(w for w, _ in rows[name]), max(w for w, _ in rows[name])],
            "cpu_range": [min(c for _, c in rows[name]), max(c for _, c in rows[name])],
        }
        for name in rows
        if not name.endswith("split")
    }
    for tag in trees:
        split = rows[f"{tag}split"]
        result[f"{tag}split"] = {
            k: {
                "cpu": med(r.get(k, 0.0) for r in split),
                "range": [min(r.get(k, 0.0) for r in split), max(r.get(k, 0.0) for r in split)],
            }
            for k in split[0]
        }
    return result


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.main_job")
    parser.add_argument("problem", nargs="?", default="problems/indoor-manual.toml")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--write", action="store_true", help="write the tables into benchmarks/results.md")
    parser.add_argument("--before", type=Path, help="a checkout of earlier code with its own .venv, measured beside")
    args = parser.parse_args(argv)
    load_start = [round(x, 2) for x in os.getloadavg()]
    print(f"load average at start: {load_start}", flush=True)
    r = measure(args.problem, args.repeats, args.before)
    load_end = [round(x, 2) for x in os.getloadavg()]
    n, p = r["numpy"], r["process"]
    print(f"main job {args.problem}, {args.repeats} cold runs each, median [min-max]:")
    print(f"  python -c 'import numpy':  wall {n['wall']:.2f} s, CPU {n['cpu']:.2f} s")
    print(
        f"  designer pareto (process):  wall {p['wall']:.2f} s = {p['wall'] / n['wall']:.1f} x (aim <= {AIM_WALL:g} x), "
        f"CPU {p['cpu']:.2f} s = {p['cpu'] / n['cpu']:.1f} x (aim <= {AIM_CPU:g} x)"
    )
    print("  CPU seconds per step (report_data + write_report in one child):")
    for k, v in r["split"].items():
        print(f"    {k:15s} {v['cpu']:.2f}  [{v['range'][0]:.2f}-{v['range'][1]:.2f}]")
    if args.before is not None:
        b = r["before process"]
        print(
            f"  before ({args.before}), same run: wall {b['wall']:.2f} s, CPU {b['cpu']:.2f} s "
            f"[{b['cpu_range'][0]:.2f}-{b['cpu_range'][1]:.2f}]; after/before CPU {p['cpu'] / b['cpu']:.3f}"
        )
        for k, v in r["before split"].items():
            after = r["split"].get(k, {}).get("cpu")
            shown = "-" if after is None else f"{after:.2f}"
            print(f"    {k:15s} before {v['cpu']:.2f}  after {shown}")
    print(f"load average at end: {load_end}")
    if args.write:
        _write(args, r, load_start, load_end)
    return 0


def _after_steps(split: dict) -> dict:
    """The split in the rows of :data:`BEFORE` (optimum, checks and trade-off together, as the issue)."""
    get = lambda k: split.get(k, {}).get("cpu", 0.0)  # noqa: E731
    return {
        "import": get("import") + get("load problem"),
        "front": get("front"),
        "tighter": get("tighter"),
        "recommendation": get("recommendation"),
        "knock_safe": get("knock_safe"),
        "optimum, checks, tradeoff": get("optimum") + get("checks") + get("tradeoff"),
        "figures": get("figures"),
        "writing": get("writing"),
        "total": get("total"),
    }


def _write(args, r: dict, load_start: list, load_end: list) -> None:
    """Replace the main-job block of benchmarks/results.md (or append it)."""
    date = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    n, p = r["numpy"], r["process"]
    after = _after_steps(r["split"])
    lines = [
        BEGIN,
        "## Main job: `designer pareto problems/indoor-manual.toml`, cold",
        "",
        f"Generated by `python -m benchmarks.main_job {args.problem} --repeats {args.repeats} --write` on {date} "
        f"({os.cpu_count()} CPUs, load average at start {load_start}, at end {load_end}). Fresh interpreters, "
        f'interleaved with `python -c "import numpy"` in the same run; median [min–max] of {args.repeats}. '
        "Bytecode caches on (an unmeasured run writes them first). Aim (issue 29): the whole process within "
        f"{AIM_WALL:g} × the wall time and {AIM_CPU:g} × the CPU of the numpy import.",
        "",
        "| whole process | wall [s] | × numpy | CPU [s] | × numpy |",
        "|---|---|---|---|---|",
        f'| `python -c "import numpy"` | {n["wall"]:.2f} [{n["wall_range"][0]:.2f}–{n["wall_range"][1]:.2f}] | 1 | '
        f"{n['cpu']:.2f} [{n['cpu_range'][0]:.2f}–{n['cpu_range'][1]:.2f}] | 1 |",
        f"| `designer pareto {args.problem}` | {p['wall']:.2f} [{p['wall_range'][0]:.2f}–{p['wall_range'][1]:.2f}] | "
        f"**{p['wall'] / n['wall']:.1f}** | {p['cpu']:.2f} [{p['cpu_range'][0]:.2f}–{p['cpu_range'][1]:.2f}] | "
        f"**{p['cpu'] / n['cpu']:.1f}** |",
        *(
            [
                f"| the same, before: `{args.before}` (same run, interleaved) | {r['before process']['wall']:.2f} | "
                f"{r['before process']['wall'] / n['wall']:.1f} | {r['before process']['cpu']:.2f} "
                f"[{r['before process']['cpu_range'][0]:.2f}–{r['before process']['cpu_range'][1]:.2f}] | "
                f"{r['before process']['cpu'] / n['cpu']:.1f} |"
            ]
            if "before process" in r
            else []
        ),
        f"| before: `designer pareto` (issue 29) | {BEFORE['process_wall']:.1f} | | {BEFORE['process_cpu']:.1f} | "
        f"{BEFORE['process_cpu_ratio']:.1f} |",
        "",
        f"Before: {BEFORE['source']}.",
        "",
        "CPU seconds per step (one child runs `report_data` and `write_report`, timing each step with "
        "`time.process_time`); before: issue 29's table, when `import numpy` took "
        f"{BEFORE['numpy_cpu']:.2f} s of CPU; after: this run, `import numpy` {n['cpu']:.2f} s.",
        "",
        "| step | before: CPU [s] | × numpy | after: CPU [s] | × numpy |",
        "|---|---|---|---|---|",
    ]
    for key, before in BEFORE["steps"].items():
        a = after[key]
        lines.append(f"| {key} | {before:.2f} | {before / BEFORE['numpy_cpu']:.1f} | {a:.2f} | {a / n['cpu']:.1f} |")
    block = "\n".join(lines + ["", END]) + "\n"
    text = RESULTS.read_text(encoding="utf-8")
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        after = rest.split(END, 1)[1]
        text = head + block + (after[1:] if after.startswith("\n") else after)  # the block ends in its newline
    else:
        text = text.rstrip("\n") + "\n\n" + block
    RESULTS.write_text(text, encoding="utf-8")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
