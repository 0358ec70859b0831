"""Serve the studio: bind the port first (one line if it is taken), warm the solver, then serve until Ctrl-C."""

from __future__ import annotations

import errno
import sys
import threading
from pathlib import Path

from designer.errors import ServerError
import socket
from werkzeug.serving import WSGIRequestHandler
import designer.studio.view as view
import json
import signal
import webbrowser

HOST = "127.0.0.1"
"""The studio listens on the local machine only unless --host says otherwise."""


def check_port(host: str, port: int) -> None:
    """Raise ServerError (one line, exit 8) if ``host:port`` cannot be bound, e.g. another server has it."""

    with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as werkzeug does
        try:
            probe.bind((host, port))
        except OSError as exc:
            if exc.errno == errno.EADDRINUSE:
                raise ServerError(
                    f"--port {port}: already in use on {host}; stop the other server or choose another port with --port"
                ) from None
            raise ServerError(f"--port {port}: cannot listen on {host}: {exc.strerror or exc}") from None


def make_server(problem_path=None, port: int = 8050, host: str = HOST, out_dir="studio-output"):
    """Build the app for ``problem_path`` and bind ``host:port`` (0 = any free port).

    Returns (werkzeug server, url).  Raises ProblemError for a bad problem file (before binding) and
    ServerError (exit 8) when the port is taken or cannot be bound.
    """
    from werkzeug.serving import make_server as _make_server  # Dash's web server, loaded with the studio

    import designer.studio.state as state

    # late import: loads dash, plotly (via designer.studio.app) only when this runs
    from designer.studio.app import create_app

    data, name = state.read_problem_data(problem_path)
    check_port(host, int(port))  # before the solver warms up: a taken port is said at once
    app = create_app(data, name, Path(out_dir))
    problem, merged = state.build_problem(data, state.control_values(data))

    try:  # warm the solver and the cache: the first page then draws at once
        view.compute_fronts(problem, key=json.dumps(merged, sort_keys=True))
    except Exception:  # noqa: BLE001 - an infeasible start is shown on the page, beside the control
        pass

    class _Quiet(WSGIRequestHandler):
        def log_request(self, *args, **kwargs):  # no line per request on the console
            pass

    try:
        server = _make_server(host, int(port), app.server, threaded=True, request_handler=_Quiet)
    except (OSError, SystemExit):  # werkzeug prints and exits when the port was taken in between
        raise ServerError(f"--port {port}: cannot listen on {host} (in use?); choose another with --port") from None
    url = f"http://{host}:{server.server_port}/"
    return server, url


def serve(
    problem_path=None, port: int = 8050, host: str = HOST, open_browser: bool = True, out_dir="studio-output"
) -> int:
    """Run the studio until Ctrl-C; prints its URL (and opens it unless ``open_browser`` is False). Returns 0."""
    server, url = make_server(problem_path, port, host, out_dir)
    print(f"designer studio: serving {url} (Ctrl-C to stop)", flush=True)
    if open_browser:
        threading.Timer(0.5, webbrowser.open, args=(url,)).start()

    def _stop(_signum, _frame):  # `kill` stops it as cleanly as Ctrl-C
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _stop)
    try:
        server.serve_forever()  # werkzeug's loop returns on Ctrl-C
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()
    print("designer studio: stopped", file=sys.stderr)
    return 0
