"""Serve the studio: bind the port first (one line if it is taken), warm the solver, then serve until Ctrl-C.

The studio is a local server and stays one (:func:`guard`): it answers only requests addressed to a loopback
name (``localhost``, ``127.0.0.1``, ``[::1]``) or to the ``--host`` given, with or without the port, and
403 otherwise (a DNS-rebinding page names its own host), or sent by a page whose ``Origin`` (scheme, host and
port) is not the studio's own; a request body above :data:`MAX_REQUEST_BYTES` is
413; and each bad request is one line on the console, never a traceback or the body (``designer --debug
studio`` logs the traceback too).
"""

from __future__ import annotations

import errno
import logging
import os
import re
import sys
import threading
from pathlib import Path

from designer.errors import ServerError
import socket
from werkzeug.serving import WSGIRequestHandler
import designer.studio.helper as helper
import designer.studio.view as view
import json
import signal
import webbrowser
import designer.studio.state as state

HOST = "127.0.0.1"
"""The studio listens on the local machine only unless --host says otherwise."""

LOOPBACK_NAMES = ("localhost", "127.0.0.1", "[::1]")
"""Host names (the HTTP ``Host`` header, without the port) the studio always answers."""

MAX_REQUEST_BYTES = 1_000_000
"""Largest request body [bytes]: a callback's JSON is a few kB (a problem file's controls and a front)."""

LOG = logging.getLogger("designer.studio")
"""One line per bad request (403, 413, a callback that fails); :func:`serve` prints it on stderr."""

_SHOWN_CHARS = 200
"""Longest message logged for a failed request (an exception may quote the whole body)."""


def allowed_hosts(host: str, port: int) -> frozenset[str]:
    """The ``Host`` header values the studio answers: the loopback names and ``host`` (the --host given),
    each alone or with ``:port``; lower case (an IPv6 address in brackets)."""
    given = f"[{host}]" if ":" in host and not host.startswith("[") else host
    names = {name.lower() for name in (*LOOPBACK_NAMES, given) if name}
    return frozenset(names | {f"{name}:{int(port)}" for name in names})


def allowed_origins(hosts: frozenset[str]) -> frozenset[str]:
    """The ``Origin`` header values of the studio's own pages: an origin is scheme, host and port, so
    ``http://<name>:<port>`` for each name of ``hosts`` at the studio's port, and ``http://<name>`` (the
    default port) only when that port is 80; ``http://localhost`` is another site's for a studio on 8050."""
    out = set()
    for entry in hosts:
        match = re.fullmatch(r"(?P<name>.+):(?P<port>[0-9]+)", entry)
        if match is None or entry.endswith("]"):  # a name without its port ("[::1]" ends in "]")
            continue
        out.add(f"http://{match['name']}:{int(match['port'])}")
        if int(match["port"]) == 80:
            out.add(f"http://{match['name']}")
    return frozenset(out)


def _short(text: str) -> str:
    """The first line of ``text``, at most :data:`_SHOWN_CHARS` characters."""
    first = next((line.strip() for line in str(text).splitlines() if line.strip()), "")
    return first if len(first) <= _SHOWN_CHARS else first[:_SHOWN_CHARS] + "…"


SECURITY_HEADERS = {
    "X-Content-Type-Options": "nosniff",
    "X-Frame-Options": "DENY",
    "Content-Security-Policy": "frame-ancestors 'none'",
    "Referrer-Policy": "no-referrer",
}
"""Headers of every answer: no content sniffing, and no other site may show the studio in a frame (a framed
page could steer a click on "Save problem" or "Write report" past the Origin check)."""

MALFORMED = {
    400: "a malformed callback request (not one this studio's page sends)",
    404: "no such file",
}
"""The body of a 4xx answer to a malformed request, by status: a fixed sentence, nothing of the exception."""

_OWN_CODE = str(Path(__file__).resolve().parents[1]) + os.sep
"""The package's folder: a failure inside a callback passes through a frame of it; one raised by Dash while it
reads the request (a body of the wrong shape, a callback that does not exist, an unknown file) does not."""


def _malformed(exc: BaseException, path: str) -> int | None:
    """The 4xx status of a request Dash could not read (``exc`` raised by Dash itself, before any function of
    the package ran): 400 for a callback post, 404 for a component file; None for a failure of the studio's own
    code (a 500, an internal error)."""
    frame = exc.__traceback__
    while frame is not None:
        if frame.tb_frame.f_code.co_filename.startswith(_OWN_CODE):
            return None
        frame = frame.tb_next
    if path.startswith("/_dash-component-suites/"):
        return 404
    if path.startswith("/_dash-"):
        return 400
    return None


def guard(flask_app, hosts: frozenset[str], debug: bool = False) -> None:
    """Keep the studio's Flask app a local server: 403 for a ``Host`` not in ``hosts``, 413 for a body above
    :data:`MAX_REQUEST_BYTES`, 400 for a callback request Dash cannot read and 404 for an unknown component file
    (:func:`_malformed`: a fixed sentence, nothing of the exception), :data:`SECURITY_HEADERS` on every answer,
    and one :data:`LOG` line per bad request or failed callback (with the traceback only when ``debug``) instead
    of Flask's traceback on the console."""
    from flask import abort, request
    from werkzeug.exceptions import HTTPException

    flask_app.config["MAX_CONTENT_LENGTH"] = MAX_REQUEST_BYTES  # a body without a length is cut there too
    origins = allowed_origins(hosts)

    @flask_app.before_request
    def _local_only():
        host = (request.environ.get("HTTP_HOST") or "").strip().lower()
        if host not in hosts:
            abort(403, description=f"Host {host[:80]!r} is not this studio's (open it at a loopback address)")
        origin = (request.environ.get("HTTP_ORIGIN") or "").strip().lower()
        if origin and origin.rstrip("/") not in origins:  # a page of another site (scheme, host, port) posting here
            abort(403, description=f"Origin {origin[:80]!r} is not this studio's")
        length = request.content_length
        if length is not None and length > MAX_REQUEST_BYTES:
            abort(413, description=f"a body of {length} bytes; at most {MAX_REQUEST_BYTES}")

    @flask_app.after_request
    def _headers(response):
        response.headers.update(SECURITY_HEADERS)
        return response

    @flask_app.errorhandler(Exception)
    def _one_line(exc):
        where = f"{request.method} {_short(request.path)}"
        if isinstance(exc, HTTPException):
            if exc.code != 404:
                LOG.warning("%s: %s %s: %s", where, exc.code, exc.name, _short(exc.description or ""))
            return exc
        malformed = _malformed(exc, request.path)
        if malformed is not None:  # the request's fault, found by Dash before any of the studio's code ran
            LOG.warning("%s: %s: %s: %s", where, malformed, type(exc).__name__, _short(str(exc)))
            return MALFORMED[malformed], malformed
        LOG.error("%s: %s: %s", where, type(exc).__name__, _short(str(exc)), exc_info=exc if debug else None)
        return "the studio could not answer this request (one line on its console says why)", 500


class _Quiet(WSGIRequestHandler):
    """werkzeug's request handler without a line per request, and its own errors (a malformed request line,
    a failure outside the app) as one :data:`LOG` line."""

    def log_request(self, *args, **kwargs):  # no line per request on the console
        pass

    def log(self, type: str, message: str, *args) -> None:
        if type == "error":
            LOG.error("%s", _short(message % args if args else message))


def _server_log(type: str, message: str, *args) -> None:
    """The server's log (werkzeug writes "Error on request" with a traceback here): one :data:`LOG` line."""
    if type == "error":
        text = message % args if args else message
        lines = [line for line in text.splitlines() if line.strip()]
        LOG.error("%s", _short(lines[-1] if lines else text))


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


def make_server(
    problem_path=None,
    port: int = 8050,
    host: str = HOST,
    out_dir="studio-output",
    debug: bool = False,
    parallel: bool = False,
):
    """Build the app for ``problem_path`` and bind ``host:port`` (0 = any free port), :func:`guard`-ed.

    Returns (werkzeug server, url).  Raises ProblemError for a bad problem file (before binding) and
    ServerError (exit 8) when the port is taken or cannot be bound.  ``debug``: failed requests log their
    traceback as well.  ``parallel``: start the helper process (:mod:`designer.studio.helper`; stop it
    with :func:`designer.studio.helper.stop`), warmed on the problem's front.
    """
    from werkzeug.serving import make_server as _make_server  # Dash's web server, loaded with the studio

    from designer.studio.app import create_app

    data, name = state.read_problem_data(problem_path)
    check_port(host, int(port))  # before the solver warms up: a taken port is said at once
    app = create_app(data, name, Path(out_dir), debug=debug)
    problem, merged = state.build_problem(data, state.control_values(data))

    helper.expand_batches()
    try:  # warm the solver and the cache: the first page then draws at once
        view.compute_fronts(problem, key=json.dumps(merged, sort_keys=True))
    except Exception:  # noqa: BLE001 - an infeasible start is shown on the page, beside the control
        pass
    if parallel:  # the helper warms its own solvers meanwhile, in the background
        helper.start(warm=problem)

    try:
        server = _make_server(host, int(port), app.server, threaded=True, request_handler=_Quiet)
    except (OSError, SystemExit):  # werkzeug prints and exits when the port was taken in between
        raise ServerError(f"--port {port}: cannot listen on {host} (in use?); choose another with --port") from None
    server.log = _server_log
    guard(app.server, allowed_hosts(host, server.server_port), debug)
    url = f"http://{host}:{server.server_port}/"
    return server, url


def serve(
    problem_path=None,
    port: int = 8050,
    host: str = HOST,
    open_browser: bool = True,
    out_dir="studio-output",
    debug: bool = False,
) -> int:
    """Run the studio until Ctrl-C; prints its URL (and opens it unless ``open_browser`` is False), and each
    bad request as one line on stderr. Returns 0 after Ctrl-C (the way to stop a server), 143 after SIGTERM."""
    if not LOG.handlers:
        console = logging.StreamHandler(sys.stderr)
        console.setFormatter(logging.Formatter("designer studio: %(message)s"))
        LOG.addHandler(console)
        LOG.setLevel(logging.INFO)
    server, url = make_server(problem_path, port, host, out_dir, debug, parallel=True)
    print(f"designer studio: serving {url} (Ctrl-C to stop)", flush=True)
    if open_browser:
        threading.Timer(0.5, webbrowser.open, args=(url,)).start()

    terminated = []

    def _stop(_signum, _frame):  # `kill` stops it as cleanly as Ctrl-C, and says so as every command does
        terminated.append(True)
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _stop)
    try:
        server.serve_forever()  # werkzeug's loop returns on Ctrl-C
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()
        helper.stop()
    if terminated:  # SIGTERM (a service manager, logout): one line and 143, as docs/commands.md's exit codes say
        print("designer: terminated (SIGTERM)", file=sys.stderr)
        return 128 + signal.SIGTERM
    print("designer studio: stopped", file=sys.stderr)
    return 0
