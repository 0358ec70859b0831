"""``designer spec PROBLEM [--out FILE]``: the one-page inspection sheet of the recommended caster (HTML, print-ready)."""

from __future__ import annotations

import warnings
from pathlib import Path

from designer.output import check_file, FileKind, write_file
from designer import load_problem, recommend
from designer.cli._common import PROBLEM_HELP, say
from designer.display import percent


def register(sub) -> None:
    p = sub.add_parser(
        "spec",
        help="write the inspection sheet of the recommended caster (one printable page)",
        description="The recommended caster's inspection sheet: the caster drawn to scale, each part's nominal "
        "value, tolerance ([tolerances]), acceptance limit and how to measure it, P(shimmy) at nominal and at the "
        "worst corner, and the problem it was designed for. One A4 or Letter page from a browser's Print. "
        "Writes results/<name>/spec.html by default.",
    )
    p.add_argument("problem", help=PROBLEM_HELP)
    p.add_argument("--out", default=None, help="the HTML file (default results/<name>/spec.html)")
    p.set_defaults(func=run)


def run(args) -> int:
    from designer.report.sheet import sheet_html  # the report package loads matplotlib

    kind = FileKind("an inspection sheet written by designer spec")
    problem = load_problem(args.problem)
    out = Path(args.out) if args.out else Path("results") / problem.name / "spec.html"
    check_file(out, "--out", "spec.html", kind=kind)  # before computing: never over a file of the user's
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the sheet states the caster's own numbers
        rec = recommend(problem)
    write_file(out, sheet_html(rec), "--out", "spec.html", kind=kind)
    spec = rec.spec
    corner = (
        ""
        if spec.corner is None
        else f"; worst corner {percent(spec.corner['probability'])} "
        f"({'holds' if spec.corner['holds'] else 'does NOT hold'})"
    )
    note = say(out)  # onto stderr when the sheet went to stdout
    note(f"P(shimmy) {percent(spec.probability)} at nominal (exact law){corner}; bound {percent(spec.alpha)}")
    note(f"inspection sheet: {out if note is not print else out.resolve()}")
    return 0
