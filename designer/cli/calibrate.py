"""``designer calibrate``: fit the model's constants to a user's test data (Fig. 7, Fig. 2C, Fig. 3C)."""

from __future__ import annotations

from pathlib import Path

from designer.cli._common import SEED_MAX, count_option, print_json, ranged_option
from designer.display import number
from designer.errors import InputError
from designer.parameters import SURFACES
from designer.output import check_file, check_folder, output_folder, PLOT, signed, signed_kind, write_file

KINDS = {
    "turning": "moment per unit load k_surface [m] from drill-press data (Fig. 7); CSV columns load_N, moment_Nm",
    "damping": "spindle friction damping c_f = M_f/θ0 [N·m/rad] with Eq. 7 (Fig. 2C); CSV columns trail_m, "
    "inertia_kgm2, critical_speed_mps [, groove_m]",
    "slip": "tyre slip coefficient K_s [N] (Fig. 3C, Eq. 12C); CSV columns slip_ratio, force_N",
}


SNIPPET_WRITER = "designer calibrate --snippet"
"""The first line of a snippet names this writer (:func:`designer.output.signed`)."""

SNIPPET = signed_kind(SNIPPET_WRITER, "a snippet written by designer calibrate --snippet")
"""What ``--snippet`` may replace: a snippet it wrote, unchanged since; never a problem file of the user's."""


def register(sub) -> None:
    p = sub.add_parser(
        "calibrate",
        help="fit turning, damping or slip constants to test data (CSV)",
        description="Fit a model constant to your own measurements, print it with its 95 % "
        "confidence interval, plot residuals (--plot), write a report folder (--report) and write a TOML snippet for a "
        "problem file (--snippet). 'designer calibrate examples DIR' writes example CSVs.",
    )
    kinds = p.add_subparsers(dest="kind", metavar="KIND", parser_class=type(p))
    for kind, text in KINDS.items():
        k = kinds.add_parser(kind, help=text, description=text)
        k.add_argument("data", help="CSV file with a header row")
        k.add_argument("--plot", default=None, metavar="FILE.png", help="write data, fit and residuals")
        k.add_argument(
            "--report",
            default=None,
            metavar="DIR",
            help="write a report folder: index.html, report.md, calibration.json, figures/fit.png",
        )
        k.add_argument("--snippet", default=None, metavar="FILE.toml", help="write a problem-file TOML snippet")
        k.add_argument("--json", action="store_true", help="machine-readable output")
        if kind == "damping":
            k.add_argument("--slip-coefficient", default="1250 N", help="K_s held fixed (default 1250 N)")
        if kind == "turning":
            k.add_argument(
                "--surface",
                default="tile",
                choices=SURFACES,
                metavar="SURFACE",
                help="surface tested: tile (default) | carpet",
            )
        k.set_defaults(func=run)
    e = kinds.add_parser("examples", help="write the example CSVs (model + stated noise, seed 7)")
    e.add_argument("out", nargs="?", default=None, help="directory (default: the package's data/examples)")
    e.add_argument("--seed", type=int, default=None, help="random seed (default 7)")
    e.set_defaults(func=run_examples)
    p.set_defaults(func=lambda args: _missing_kind())


def _missing_kind() -> int:
    raise InputError(f"calibrate: missing KIND; expected one of {', '.join(KINDS)} or examples")


def run(args) -> int:
    from designer.studies.calibrate import calibrate_file

    from designer.report.calibration import OWNED, check_plot_name, plot_fit, write_calibration_report

    # every place the fit will be written to, checked before the fit (exit 2 for a bad name, 7 for a bad place)
    if args.plot:
        check_plot_name(args.plot)
        check_file(args.plot, "--plot", example="fit.png", kind=PLOT)
    if args.report:
        check_folder(args.report, "--report", owned=OWNED, command="designer calibrate")
    if args.snippet:
        check_file(args.snippet, "--snippet", example="calibration.toml", kind=SNIPPET)
    slip = 1250.0
    if args.kind == "damping":
        slip = ranged_option(args.slip_coefficient, "slip_coefficient", "--slip-coefficient")
    surface = args.surface if args.kind == "turning" else "tile"  # one of SURFACES (argparse's choices)
    result = calibrate_file(args.kind, args.data, slip_coefficient=slip, surface=surface)
    if args.plot:
        plot_fit(result, args.plot)
    if args.report:
        write_calibration_report(result, args.report, str(args.data))
    if args.snippet:
        text = signed(result.snippet(), SNIPPET_WRITER)
        write_file(args.snippet, text, "--snippet", example="calibration.toml", kind=SNIPPET)
    out = result.to_dict()
    out["data"] = str(args.data)
    out.update({key: getattr(args, key) for key in ("plot", "report", "snippet") if getattr(args, key)})
    if args.json:
        print_json(out)
        return 0
    lo, hi = result.interval
    print(
        f"{result.kind}: {result.name} = {number(result.value, digits=5)} {result.unit}  "
        f"(95 % CI {number(lo, digits=5)} to {number(hi, digits=5)}, standard error {number(result.stderr, digits=3)}, "
        f"n = {result.n}, rms residual {number(result.rms, digits=3)} {result.y_unit}; {result.equation})"
    )
    for key, value in result.notes.items():
        print(f"  {key} = {value}")
    if args.plot:
        print(f"  residual plot: {args.plot}")
    if args.report:
        print(f"  report: {(Path(args.report) / 'index.html').resolve()}")
    if args.snippet:
        print(f"  TOML snippet: {args.snippet}")
    else:
        print(result.snippet(), end="")
    return 0


def run_examples(args) -> int:
    from designer.studies.calibrate import EXAMPLE_SEED, EXAMPLES_DIR, write_examples

    count_option(args.seed, "--seed", 0, SEED_MAX)
    out = Path(args.out or EXAMPLES_DIR)
    # only the three CSVs are written; a folder holding a different file of one of their names is refused
    # (exit 7) when they are committed, except the package's own examples folder, which they are regenerated into
    with output_folder(
        out, (), option="examples DIR", force=args.out is None, command="designer calibrate examples"
    ) as tmp:
        paths = write_examples(tmp, EXAMPLE_SEED if args.seed is None else args.seed)
    for kind, path in paths.items():
        print(f"{kind}: {out / Path(path).name}")
    return 0
