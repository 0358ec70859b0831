"""Mutation score per module from mutmut's results and the list of equivalent mutants (docs/mutation.md).

    mutmut results --all true > /tmp/mutants.txt
    python benchmarks/mutation_score.py /tmp/mutants.txt                 # the table of benchmarks/mutation.md
    python benchmarks/mutation_score.py /tmp/mutants.txt --survivors     # not killed and not listed as equivalent

Score = killed / (total − equivalent).  "equivalent" counts the mutants of benchmarks/mutation-equivalent.txt that
were not killed, in two kinds: ``equivalent`` (cannot change any result) and ``tie`` (changes a comparison only when
a computed float equals a tolerance exactly; listed apart so the stricter score can be read off too).
"""

from __future__ import annotations

import collections
import sys
from pathlib import Path

EQUIVALENT = Path(__file__).with_name("mutation-equivalent.txt")


def read_equivalent(path: Path = EQUIVALENT) -> dict[str, str]:
    """{mutant name: kind} from the tab-separated list (name, kind, reason)."""
    out = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.strip() and not line.startswith("#"):
            name, kind, _reason = line.split("\t")
            out[name] = kind
    return out


def read_results(path: str) -> dict[str, str]:
    """{mutant name: status} from ``mutmut results --all true``."""
    out = {}
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        name, sep, status = line.strip().rpartition(": ")
        if sep and name.startswith("designer."):
            out[name] = status
    return out


def module_of(name: str) -> str:
    return name.split(".x_")[0].split(".xǁ")[0]


def table(results: dict[str, str], equivalent: dict[str, str]) -> str:
    rows: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    for name, status in results.items():
        row = rows[module_of(name)]
        row[status] += 1
        row["total"] += 1
        if status != "killed" and name in equivalent:
            row["equivalent"] += 1
            row["kind " + equivalent[name]] += 1
    rows = dict(sorted(rows.items()))
    rows["**all**"] = sum(rows.values(), collections.Counter())
    lines = [
        "| module | total | killed | survived | no tests | timeout | not run | equivalent (ties) "
        "| (killed + timeout) / (total − equivalent) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for module, r in rows.items():
        label = module if module.startswith("**") else f"`{module}`"
        detected = r["killed"] + r["timeout"]  # a timeout is a mutant the tests stop (an endless loop): detected
        score = 100 * detected / max(1, r["total"] - r["equivalent"])
        lines.append(
            f"| {label} | {r['total']} | {r['killed']} | {r['survived']} | {r['no tests']} | "
            f"{r['timeout']} | {r['not checked']} | {r['equivalent']} ({r['kind tie']}) | {score:.1f} % |"
        )
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    results = read_results(argv[0])
    equivalent = read_equivalent()
    if "--survivors" in argv:
        for name, status in results.items():
            if status != "killed" and name not in equivalent:
                print(f"{name}: {status}")
        return 0
    print(table(results, equivalent))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
