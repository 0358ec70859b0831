"""``designer validate``: the paper's checks of DESIGN §5 as a table; non-zero exit on failure."""
from __future__ import annotations

from designer.analysis.checks import paper_checks
from designer.commands._common import print_json


def register(sub) -> None:
    p = sub.add_parser("validate", help="run the paper's checks (DESIGN §5) and print them as a table",
                       description="Checks that need no optimisation (1–7, 9, 10 and the Table 1 inertia fit). "
                                   "Check 8 runs on every front computed by 'designer pareto'.")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=run)


def run(args) -> int:
    checks = paper_checks()
    failed = [c for c in checks if not c.passed]
    if args.json:
        print_json([c.to_dict() for c in checks])
    else:
        from rich.console import Console
        from rich.table import Table

        table = Table(title="Paper checks (DESIGN §5)", title_justify="left", show_lines=True)
        for col in ("check", "paper's claim", "expected", "ours", "result"):
            table.add_column(col)
        for c in checks:
            table.add_row(c.name, c.claim, str(c.expected), str(c.got), "pass" if c.passed else "FAIL")
        console = Console(width=160)
        console.print(table)
        for c in checks:
            console.print(f"[bold]{c.name}[/bold]: {c.detail}")
        console.print(f"{len(checks) - len(failed)} passed, {len(failed)} failed")
        for c in failed:
            console.print(f"FAILED {c.name}: expected {c.expected}, got {c.got}")
    return 1 if failed else 0
