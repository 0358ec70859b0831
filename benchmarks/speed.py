"""The speed guards of issue 44: the main job, the spec batch and the studio, each beside its yardstick.

    python -m benchmarks.speed [--repeats N] [--before CHECKOUT] [--write]
    python -m benchmarks.speed --show        # the last written run, in a few lines (docs/benchmarks.md)

In fresh interpreters, interleaved so that all of them see the same load (CPU = user + system of the child):

- ``python -c "import numpy"``: the yardstick of the main job;
- the main job, ``designer pareto problems/indoor-manual.toml --out TMP``: its CPU and the ratio to the numpy
  import's (issue 44: <= 9 x, aim 6.5 x);
- the spec batch, ``designer fix problems/indoor-manual.toml --current "T=1.25in,d=8in,B=0,c=1.3" --json
  --top 0``: every fix (329) with its spec, the whole command's CPU (issue 44: <= 2 s, aim 1.5 s);
- with ``--before CHECKOUT`` (a checkout of earlier code with its own ``CHECKOUT/.venv``, e.g. ``git worktree add
  --detach /tmp/before <commit>``): the same two commands of that checkout, and the after/before ratios.

The studio's key press to redraw is a browser session (``python -m benchmarks.studio_latency``, about a minute
per round): it is not run here; its last saved medians (``benchmarks/studio_latency.json``, after and before)
are quoted beside these with their date.

``--write`` saves the run to ``benchmarks/speed.json`` and puts its table into ``benchmarks/results.md`` between
the speed markers; ``--show`` prints the saved run.  :func:`measure` and :func:`summary` are what
``python -m benchmarks.run --quick`` calls for its own report of these figures.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import statistics
import sys
import tempfile
from pathlib import Path

from benchmarks.main_job import run

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results.md"
SAVED = ROOT / "benchmarks" / "speed.json"
STUDIO = ROOT / "benchmarks" / "studio_latency.json"
BEGIN, END = "<!-- speed 44: begin -->", "<!-- speed 44: end -->"
PROBLEM = "problems/indoor-manual.toml"
CURRENT = "T=1.25in,d=8in,B=0,c=1.3"
AIM_MAIN, GOAL_MAIN = 6.5, 9.0
"""Issue 44: the main job's CPU within 9 x that of ``python -c "import numpy"`` (aim 6.5 x)."""
AIM_SPECS, GOAL_SPECS = 1.5, 2.0
"""Issue 44: the spec batch (the whole ``designer fix ... --json --top 0`` command) <= 2 s of CPU (aim 1.5 s)."""
AIM_STUDIO = 150.0
"""Issue 44: the studio's key press to redraw <= 150 ms at the median."""


def commands(python: str, out: str) -> dict[str, list[str]]:
    """The measured commands of one checkout (``python`` its interpreter, ``out`` a scratch report folder)."""
    return {
        "main job": [python, "-m", "designer", "pareto", PROBLEM, "--out", out],
        "spec batch": [python, "-m", "designer", "fix", PROBLEM, "--current", CURRENT, "--json", "--top", "0"],
    }


def measure(repeats: int = 3, before: Path | None = None) -> dict:
    """Interleaved cold runs of the numpy import and of each checkout's commands: CPU and wall medians [s] with
    their ranges, the ratios to the numpy import and (with ``before``) after/before, the load at start and end."""
    load_start = [round(x, 2) for x in os.getloadavg()]
    trees = {"after": (ROOT, sys.executable)}
    if before is not None:
        trees["before"] = (Path(before), str(Path(before) / ".venv" / "bin" / "python"))
    rows: dict[str, list[tuple[float, float]]] = {"numpy import": []}
    with tempfile.TemporaryDirectory() as tmp:
        for tag, (tree, python) in trees.items():
            for name, cmd in commands(python, f"{tmp}/{tag}").items():
                run(cmd, tree)  # unmeasured: bytecode caches, and the report folder exists as on a rerun
                rows[f"{tag}: {name}"] = []
        for _ in range(repeats):
            rows["numpy import"].append(run([sys.executable, "-c", "import numpy"])[:2])
            for tag, (tree, python) in trees.items():
                for name, cmd in commands(python, f"{tmp}/{tag}").items():
                    rows[f"{tag}: {name}"].append(run(cmd, tree)[:2])
    med = statistics.median
    out: dict = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "cpus": os.cpu_count(),
        "repeats": repeats,
        "before": None if before is None else str(before),
        "load_start": load_start,
        "load_end": [round(x, 2) for x in os.getloadavg()],
        "runs": {
            name: {
                "cpu": med(c for _, c in r),
                "cpu_range": [min(c for _, c in r), max(c for _, c in r)],
                "wall": med(w for w, _ in r),
            }
            for name, r in rows.items()
        },
    }
    numpy_cpu = out["runs"]["numpy import"]["cpu"]
    for name, r in out["runs"].items():
        r["x_numpy"] = r["cpu"] / numpy_cpu
        if name.startswith("after: ") and f"before: {name[7:]}" in out["runs"]:
            r["x_before"] = r["cpu"] / out["runs"][f"before: {name[7:]}"]["cpu"]
    out["studio"] = studio_quote()
    return out


def studio_quote(path: Path = STUDIO) -> dict | None:
    """The last saved studio medians (key press to redraw [ms], after and before) and their date, or None."""
    if not path.is_file():
        return None
    saved = json.loads(path.read_text(encoding="utf-8"))
    medians = {
        name: run_["summary"]["redraw_ms"]["median"]
        for name, run_ in saved.get("runs", {}).items()
        if run_.get("summary", {}).get("redraw_ms")
    }
    return {"date": saved.get("date"), "redraw_ms": medians} if medians else None


def summary(result: dict) -> list[str]:
    """The run in a few lines at most 80 wide: each figure with its ratio to the numpy import or the before
    checkout, and the issue's goal."""
    runs = result["runs"]
    numpy_cpu = runs["numpy import"]["cpu"]
    main, specs = runs["after: main job"], runs["after: spec batch"]
    lines = [
        f"{result['date'][:10]}, {result['cpus']} CPUs, load {result['load_start'][0]:.1f} -> "
        f"{result['load_end'][0]:.1f}, median of {result['repeats']}; CPU [s]:",
        f"  import numpy            {numpy_cpu:5.2f}",
        f"  main job (pareto)       {main['cpu']:5.2f} = {main['x_numpy']:4.1f} x numpy "
        f"(goal <= {GOAL_MAIN:g} x, aim {AIM_MAIN:g} x)",
        f"  spec batch (fix, 329)   {specs['cpu']:5.2f}          (goal <= {GOAL_SPECS:g} s, aim {AIM_SPECS:g} s)",
    ]
    if "before: main job" in runs:
        b_main, b_specs = runs["before: main job"], runs["before: spec batch"]
        lines += [
            f"  before: main job        {b_main['cpu']:5.2f} = {b_main['x_numpy']:4.1f} x numpy; "
            f"after/before {main['x_before']:.2f}",
            f"  before: spec batch      {b_specs['cpu']:5.2f}; after/before {specs['x_before']:.3f}",
        ]
    studio = result.get("studio")
    if studio:
        shown = ", ".join(f"{k} {v:.0f} ms" for k, v in studio["redraw_ms"].items())
        lines.append(f"studio, key to redraw ({str(studio['date'])[:10]}): {shown} (aim <= {AIM_STUDIO:g})")
    return lines


def _table(result: dict) -> str:
    """The results.md section of a run."""
    runs = result["runs"]
    before = "before: main job" in runs
    lines = [
        BEGIN,
        "## Speed guards of issue 44: main job, spec batch, studio",
        "",
        f"Generated by `python -m benchmarks.speed --repeats {result['repeats']}"
        f"{' --before ' + result['before'] if before else ''} --write` on {result['date']} ({result['cpus']} CPUs, "
        f"load average at start {result['load_start']}, at end {result['load_end']}). Fresh interpreters, "
        "interleaved, bytecode caches on, the report folder already there (a rerun); CPU = user + system of the "
        f"child, median [min–max] of {result['repeats']}.",
        "",
        "| command | CPU [s] | × `import numpy` | after / before | goal (aim) |",
        "|---|---|---|---|---|",
    ]
    goals = {
        "main job": f"<= {GOAL_MAIN:g} × numpy ({AIM_MAIN:g} ×)",
        "spec batch": f"<= {GOAL_SPECS:g} s ({AIM_SPECS:g} s)",
    }
    shown = {
        "numpy import": '`python -c "import numpy"`',
        "main job": f"`designer pareto {PROBLEM}`",
        "spec batch": f'`designer fix {PROBLEM} --current "{CURRENT}" --json --top 0` (329 fixes with their specs)',
    }
    for name, r in runs.items():
        tag, _, what = name.partition(": ")
        label = shown[name] if name == "numpy import" else f"{tag}: {shown[what]}"
        ratio = f"{r['x_before']:.2f}" if "x_before" in r else ""
        goal = goals.get(what, "") if tag == "after" else ""
        lines.append(
            f"| {label} | {r['cpu']:.2f} [{r['cpu_range'][0]:.2f}–{r['cpu_range'][1]:.2f}] | {r['x_numpy']:.1f} | "
            f"{ratio} | {goal} |"
        )
    studio = result.get("studio")
    if studio:
        medians = ", ".join(f"{k} {v:.0f} ms" for k, v in studio["redraw_ms"].items())
        lines += [
            "",
            f"Studio (not run here: `python -m benchmarks.studio_latency`, its section below): key press to redraw, "
            f"median, last saved run {studio['date']}: {medians}; aim <= {AIM_STUDIO:g} ms.",
        ]
    return "\n".join(lines + ["", END]) + "\n"


def write(result: dict) -> None:
    """Save ``result`` to benchmarks/speed.json and its section into benchmarks/results.md (replaced, or
    appended)."""
    SAVED.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    block = _table(result)
    text = RESULTS.read_text(encoding="utf-8")
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + block + rest.split(END, 1)[1]
    else:
        text = text.rstrip("\n") + "\n\n" + block
    RESULTS.write_text(text, encoding="utf-8")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.speed", description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--before", type=Path, help="a checkout of earlier code with its own .venv, measured beside")
    parser.add_argument("--write", action="store_true", help="save to benchmarks/speed.json and results.md")
    parser.add_argument("--show", action="store_true", help="print the saved run; run nothing")
    args = parser.parse_args(argv)
    if args.show:
        print("\n".join(summary(json.loads(SAVED.read_text(encoding="utf-8")))))
        return 0
    result = measure(args.repeats, args.before)
    print("\n".join(summary(result)))
    if args.write:
        write(result)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
