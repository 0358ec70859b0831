"""``designer studio [PROBLEM]``: the trade-off live in the browser (:mod:`designer.studio`)."""

from __future__ import annotations

from designer.output import check_folder
from designer.cli._common import PROBLEM_HELP, count_option
from designer.errors import InputError


def register(sub) -> None:
    p = sub.add_parser(
        "studio",
        help="live design studio in the browser (needs the 'studio' extra)",
        description="Start a local web app: move the load, sill, target speed, risk, bounds and "
        "stock and watch the fronts and the recommendation follow; click a point for "
        "its card; check your own caster. Serves on 127.0.0.1; Ctrl-C stops it. "
        "Exit 8 if the port is in use.",
    )
    p.add_argument("problem", nargs="?", default=None, help=PROBLEM_HELP + "; default indoor-manual")
    p.add_argument("--port", type=int, default=8050, help="port to listen on (default 8050; 0 = any free port)")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1: this machine only)")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser, only print the URL")
    p.add_argument(
        "--out", default="studio-output", help="folder for 'Save problem' and 'Write report' (default studio-output)"
    )
    p.set_defaults(func=run)


def run(args) -> int:
    count_option(args.port, "--port", 0, 65535)
    check_folder(args.out)  # "Save problem" and "Write report" write here: exit 7 now, not a failure later
    try:
        import dash  # noqa: F401 - the web framework is optional: only the studio needs it
    except ImportError:
        raise InputError("designer studio needs Dash: pip install 'caster-designer[studio]'") from None
    from designer.studio import serve  # the web app, loaded only for this command

    return serve(
        args.problem,
        port=args.port,
        host=args.host,
        open_browser=not args.no_browser,
        out_dir=args.out,
        debug=getattr(args, "debug", False),
    )
