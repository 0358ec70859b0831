"""``designer validate``: the paper's checks (docs/checks.md) as a table; exit 1 only if one fails."""

from __future__ import annotations

import warnings

from designer.studies.checks import FAILS, law_checks, paper_checks, summary_line
from designer.cli._common import print_json
from designer.cli._terminal import console as terminal_console
from designer.units import INCH


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
    p.set_defaults(func=run)


def run(args) -> int:
    with warnings.catch_warnings():  # the checks' own wheels (3 in, Table 1's range): not the user's doing
        warnings.simplefilter("ignore", UserWarning)
        checks = paper_checks() + law_checks()
    failed = [c for c in checks if c.outcome == FAILS]
    if args.json:
        print_json([c.to_dict() for c in checks])
        return 1 if failed else 0
    from rich.markup import escape

    from rich.table import Table

    console = terminal_console()
    for kind, title in (
        ("paper", "Paper checks (against the paper's measurements and stated results)"),
        ("identity", "Implementation identities (the paper's numbers built into the model)"),
        ("law", "Risk-law checks (the law against the Table 1 wheels it was refitted without)"),
    ):
        table = Table(title=title, title_justify="left", show_lines=True)
        for col in ("check", "paper's claim", "expected", "ours", "result"):
            table.add_column(col)
        for c in checks:
            if c.kind == kind:
                table.add_row(
                    escape(c.name),
                    escape(c.claim),
                    escape(str(c.expected)),
                    escape(str(c.got)),
                    c.outcome.upper() if c.outcome == FAILS else c.outcome,
                )
        console.print(table)
    for c in checks:
        if c.rows:
            console.print(_pit_table(c))
    for c in checks:
        console.print(f"[bold]{escape(c.name)}[/bold]: {escape(c.detail)}")
        for line in c.disagreements:
            console.print(f"  disagrees: {escape(line)}")
    console.print(summary_line(checks))
    console.print(f"{len(checks) - len(failed)} do not fail, {len(failed)} failed")
    for c in failed:
        console.print(f"FAILED {escape(c.name)}: expected {escape(str(c.expected))}, got {escape(str(c.got))}")
    return 1 if failed else 0


def _pit_table(check):
    """Check 11's table: each Table 1 wheel left out, the law refitted without it, the PIT of its onset."""
    from rich.table import Table

    table = Table(
        title=f"{check.name}: the risk law refitted without each wheel (coarse: five wheels)",
        title_justify="left",
    )
    for col in (
        "wheel",
        "d (in)",
        "V measured (m/s)",
        "I_w scale (ν)",
        "model error (ν)",
        "PIT from d",
        "PIT from I_w",
    ):
        table.add_column(col)
    for r in check.rows:
        table.add_row(
            r["wheel"],
            f"{r['diameter'] / INCH:.0f}",
            f"{r['measured_speed']:.2f}",
            f"{r['inertia_scale']:.3f} ({r['inertia_dof']})",
            f"{r['model_error_scale']:.4f} ({r['model_error_dof']})",
            f"{r['pit_from_diameter']:.3f}" + ("" if r["inside_from_diameter"] else " outside"),
            f"{r['pit_from_inertia']:.3f}" + ("" if r["inside_from_inertia"] else " outside"),
        )
    return table
