"""``designer validate``: the paper's checks (docs/checks.md) as a table; exit 1 only if one fails."""

from __future__ import annotations

import warnings

from designer.studies.checks import (
    FAILS,
    NOT_APPLICABLE,
    REPRODUCED,
    WITHIN_SCATTER,
    law_checks,
    paper_checks,
    summary_line,
)
from designer.cli._terminal import fit
from designer.cli._common import print_json
from designer.cli._terminal import console as terminal_console, table
from designer.display import number, shown


def register(sub) -> None:
    p = sub.add_parser(
        "validate",
        help="run the paper's checks (docs/checks.md) and print them as a table",
        description="Checks that need no optimisation (1–7, 9, 10 and the Table 1 inertia fit), "
        "counted apart: paper checks (against the paper's measurements; each reproduced, "
        "disagreeing within the paper's stated scatter, or failing) and implementation "
        "identities (3, 4, 5: the paper's numbers built into the model); and check 11, the "
        "risk law left one Table 1 wheel out at a time. Exit 1 only if a check fails. "
        "Check 8 runs on every front computed by 'designer pareto'.",
    )
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--verbose", action="store_true", help="the full tables: each paper's claim, the details")
    p.set_defaults(func=run)


RESULT = {
    REPRODUCED: "agrees",
    WITHIN_SCATTER: "agrees within the paper's scatter",
    FAILS: "DISAGREES",
    NOT_APPLICABLE: "not applicable",
}
"""Each outcome as the list says it: a passing check agrees (within the paper's scatter where that is the
criterion), a failing one disagrees."""

KINDS = (
    ("paper", "Against the paper's measurements and stated results"),
    ("identity", "The paper's numbers built into the model (each must hold)"),
    ("law", "The risk law against each Table 1 wheel it was fitted without"),
)
"""The three groups of checks, in order, each with its heading."""


def count_line(checks) -> str:
    """The count in the words of ``designer pareto``: "checks 11/11 pass"; the failing ones named."""
    failed = [c for c in checks if c.outcome == FAILS]
    text = f"checks {len(checks) - len(failed)}/{len(checks)} pass"
    return text + (f"; disagreeing: {', '.join(_name(c) for c in failed)}" if failed else "")


def _name(check) -> str:
    """A check's name without the number docs/checks.md gives it ("Eq. 8" for "1 Eq. 8")."""
    head, _, rest = check.name.partition(" ")
    return rest if head.isdigit() and rest else check.name


def run(args) -> int:
    with warnings.catch_warnings():  # the checks' own wheels (3 in, Table 1's range): not the user's doing
        warnings.simplefilter("ignore", UserWarning)
        checks = paper_checks() + law_checks()
    failed = [c for c in checks if c.outcome == FAILS]
    if args.json:
        print_json([c.to_dict() for c in checks])
        return 1 if failed else 0
    if not args.verbose:  # a numbered list in one screen (about 40 lines at 80 columns); claims and details: --verbose
        out, n = [f"The paper's checks (docs/checks.md): {count_line(checks)}."], 0
        for kind, title in KINDS:
            group = [c for c in checks if c.kind == kind]
            if group:
                out.append(f"{title}:")
            for c in group:
                n += 1
                out += [
                    f"{n:2d}. {_name(c)}: {RESULT.get(c.outcome, c.outcome)}",
                    f"    expected {c.expected}; ours {c.got}",
                ]
        out.append("--verbose: each claim in the paper's words and the details.")
        print(fit("\n".join(out)))
        return 1 if failed else 0
    from rich.markup import escape

    console = terminal_console()
    for kind, title in KINDS:
        rows = [
            (c.name, c.claim, c.expected, c.got, RESULT.get(c.outcome, c.outcome)) for c in checks if c.kind == kind
        ]
        console.print(table(title, ("check", "paper's claim", "expected", "ours", "result"), rows, show_lines=True))
    for c in checks:
        if c.rows:
            console.print(_pit_table(c))
    for c in checks:
        console.print(f"[bold]{escape(c.name)}[/bold]: {escape(c.detail)}")
        for line in c.disagreements:
            console.print(f"  apart: {escape(line)}")
    console.print(summary_line(checks))
    console.print(count_line(checks))
    for c in failed:
        console.print(f"FAILED {escape(c.name)}: expected {escape(str(c.expected))}, got {escape(str(c.got))}")
    return 1 if failed else 0


PIT_COLUMNS = ("wheel", "d", "V measured", "I_w scale (ν)", "model error (ν)", "PIT from d", "PIT from I_w")
"""The columns of check 11's table."""


def _pit_table(check):
    """Check 11's table: each Table 1 wheel left out, the law refitted without it, the PIT of its onset."""
    rows = [
        (
            r["wheel"],
            shown(r["diameter"], "diameter", "in"),
            shown(r["measured_speed"], "critical_speed"),
            f"{number(r['inertia_scale'])} ({r['inertia_dof']})",
            f"{number(r['model_error_scale'])} ({r['model_error_dof']})",
            number(r["pit_from_diameter"]) + ("" if r["inside_from_diameter"] else " outside"),
            number(r["pit_from_inertia"]) + ("" if r["inside_from_inertia"] else " outside"),
        )
        for r in check.rows
    ]
    return table(f"{check.name}: the risk law refitted without each wheel (coarse: five wheels)", PIT_COLUMNS, rows)
