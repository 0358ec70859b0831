"""The main job's CPU split, cold: ``python -m benchmarks.main_job [PROBLEM] [--repeats N]``.

Runs ``designer pareto PROBLEM`` (default problems/indoor-manual.toml) in a fresh interpreter per repeat,
against ``python -c "import numpy"`` in the same run, and prints the CPU seconds [s] of each step: import
(the package, the pipeline and the report), front, tighter front (check 8c), recommendation, weighted
optimum, checks, groove-damper table, figures, writing, and the total.  The steps come from
``ReportData.run`` (``compute_cpu_seconds`` and ``render_cpu_seconds``), measured with time.process_time.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile

CHILD = r"""
import json, sys, time, warnings
c0 = time.process_time()
import designer
from designer.problem import load_problem
from designer.pipeline import report_data
from designer.report import write_report
imp = time.process_time() - c0
warnings.simplefilter("ignore")
data = report_data(load_problem(sys.argv[1]))
write_report(data, sys.argv[2])
out = {"import": imp, **data.run["compute_cpu_seconds"], **data.run["render_cpu_seconds"],
       "total": time.process_time()}
print(json.dumps(out))
"""


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.main_job")
    parser.add_argument("problem", nargs="?", default="problems/indoor-manual.toml")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    numpy = []
    runs = []
    for _ in range(args.repeats):
        code = "import time, numpy; print(time.process_time())"
        numpy.append(float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                          check=True).stdout))
        with tempfile.TemporaryDirectory() as tmp:
            out = subprocess.run([sys.executable, "-c", CHILD, args.problem, f"{tmp}/r"], capture_output=True,
                                 text=True, check=True).stdout
        runs.append(json.loads(out.strip().splitlines()[-1]))
    keys = list(runs[0])
    print(f"main job {args.problem}, {args.repeats} cold runs, CPU seconds (median):")
    print(f"  python -c 'import numpy': {sorted(numpy)[len(numpy) // 2]:.2f}")
    for k in keys:
        values = sorted(r[k] for r in runs)
        print(f"  {k:15s} {values[len(values) // 2]:.2f}  [{values[0]:.2f}–{values[-1]:.2f}]")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
