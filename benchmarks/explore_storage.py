"""Trials per second of ``designer explore`` by storage (in-memory, journal file, SQLite), one worker.

python benchmarks/explore_storage.py problems/indoor-manual.toml --trials 500 --dir /tmp
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import designer
from designer.studies.explore import explore


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("problem")
    parser.add_argument("--trials", type=int, default=500)
    parser.add_argument("--dir", default="/tmp")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    problem = designer.load_problem(args.problem)
    folder = Path(args.dir)
    stamp = int(time.time())
    for label, url in (
        ("in-memory", None),
        ("journal file", f"journal://{folder / f'bench-{stamp}.log'}"),
        ("SQLite", f"sqlite:///{folder / f'bench-{stamp}.db'}"),
    ):
        r = explore(problem, trials=args.trials, seed=0, storage=url, compare=False)
        print(f"{label:14s} {r.trials} trials in {r.seconds:6.2f} s = {r.trials_per_second:7.1f} trials/s", flush=True)
    for suffix in (".log", ".db", ".log.lock"):
        (folder / f"bench-{stamp}{suffix}").unlink(missing_ok=True)


if __name__ == "__main__":
    main()
