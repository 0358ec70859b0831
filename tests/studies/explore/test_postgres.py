"""Issue 12.7 and 23.3: one optuna study shared by several `designer explore` processes on a real PostgreSQL
server, started by the test itself (pgserver ships the server binaries and runs as root too), on a machine
whose every core is kept busy by the test."""

from __future__ import annotations

import collections
import contextlib
import csv
import functools
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from conftest import ROOT

pytestmark = pytest.mark.alone  # it saturates every core: under pytest-xdist no other test runs meanwhile

TRIALS = 60
STUDY = "pg-starved"
HEARTBEAT, GRACE = 1, 3  # [s]: a worker paused (or starved) for more than 3 s loses its trial
PATIENCE = 1800.0
"""[s] Bound of every wait of the test: a saturated 2-core machine runs it in about 3 minutes, a slower or
busier one may take many times longer; the waits end as soon as their condition holds."""


@pytest.fixture(scope="module")
def postgres(tmp_path_factory):
    """A PostgreSQL server in a fresh data folder, stopped and removed after the module's tests."""
    import pgserver  # in the `test` extra: a missing install must fail here, not skip

    # Not under pytest's basetemp: that is mode 0700, and as root pgserver runs the server as its own
    # unprivileged user, which must be able to reach the data folder.
    base = Path(tempfile.mkdtemp(prefix="designer-pg-"))
    base.chmod(0o755)
    data = base / "pgdata"
    t0 = time.perf_counter()
    server = pgserver.get_server(str(data), cleanup_mode="delete")
    server.started_seconds = time.perf_counter() - t0  # README: how long the server takes to start
    try:
        yield server
    finally:
        server.cleanup()
        shutil.rmtree(base, ignore_errors=True)


@contextlib.contextmanager
def _every_core_busy(seconds: float):
    """One spinning process per core, each ending by itself after ``seconds``; all stopped by PID on exit."""
    spin = f"import time\nend = time.monotonic() + {seconds}\nwhile time.monotonic() < end:\n    pass\n"
    procs: list[subprocess.Popen] = []
    try:
        for _ in range(os.cpu_count() or 1):
            procs.append(subprocess.Popen([sys.executable, "-c", spin]))
        yield [p.pid for p in procs]
    finally:
        for p in procs:
            p.kill()
        for p in procs:
            p.wait()


def _explore(url, out, resume, env):
    cmd = [sys.executable, "-m", "designer.cli", "explore", str(ROOT / "problems" / "indoor-manual.toml")]
    cmd += ["--storage", url, "--study", STUDY, "--trials", str(TRIALS), "--seed", "0"]
    cmd += ["--no-compare", "--json", "--out", str(out)] + (["--resume"] if resume else [])
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)


@functools.cache
def _storage(url):
    """One plain connection to the study's database for the test's own reads (no heartbeat)."""
    import optuna

    from designer.studies.explore import parse_storage

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    return optuna.storages.RDBStorage(parse_storage(url).url)  # the driver the designer picks (psycopg2)


def _trials(url):
    import optuna

    try:
        return optuna.load_study(study_name=STUDY, storage=_storage(url)).get_trials(deepcopy=False)
    except KeyError:
        return None


class _Clock:
    """Waits on conditions, all bounded by one deadline; a worker that exits with an error fails at once."""

    def __init__(self, patience: float, procs):
        self.end = time.monotonic() + patience
        self.procs = procs

    def wait(self, predicate, what: str, within: float | None = None) -> bool:
        """Poll ``predicate`` until it holds (True); False after ``within`` seconds; AssertionError at the
        deadline."""
        stop = self.end if within is None else min(self.end, time.monotonic() + within)
        while time.monotonic() < stop:
            if predicate():
                return True
            for p in self.procs:
                if p.poll() not in (None, 0, -signal.SIGKILL):
                    raise AssertionError(f"worker exited {p.returncode}: {p.stderr.read()}")
            time.sleep(0.2)
        if within is None or time.monotonic() >= self.end:
            raise AssertionError(f"{what}: not within {PATIENCE:.0f} s")
        return False


@functools.cache
def _names() -> frozenset:
    """The parameters of a drawn candidate of the problem explored."""
    import designer
    from designer.studies.explore import search_space

    return frozenset(search_space(designer.load_problem(ROOT / "problems" / "indoor-manual.toml")).names)


def _evaluating(url, pid):
    """The number of the RUNNING trial of the process ``pid`` (user attribute explore_worker) once its
    candidate is drawn (all parameters set), or None."""
    from optuna.trial import TrialState

    from designer.studies.explore import WORKER_ATTR

    me = f"{socket.gethostname()}:{pid}"
    for t in _trials(url) or []:
        if t.state == TrialState.RUNNING and t.user_attrs.get(WORKER_ATTR) == me and set(t.params) >= _names():
            return t.number
    return None


def _state(url, number):
    return next(t.state for t in _trials(url) if t.number == number)


def _pause_until_failed(url, worker, clock) -> int:
    """Stop ``worker`` (SIGSTOP) while it evaluates a drawn candidate and keep it stopped until the other
    workers have failed that trial for its missing heartbeat; then continue it.  Returns the trial's number."""
    from optuna.trial import TrialState

    while True:
        clock.wait(lambda: _evaluating(url, worker.pid) is not None, "the paused worker never ran a trial")
        number = _evaluating(url, worker.pid)
        worker.send_signal(signal.SIGSTOP)
        try:
            if number is not None and _state(url, number) == TrialState.RUNNING:  # stopped inside it
                # a stop inside a database transaction holds a lock the others wait on: then try again
                if clock.wait(lambda n=number: _state(url, n) == TrialState.FAIL, "stale trial", within=60 + GRACE):
                    return number
        finally:
            worker.send_signal(signal.SIGCONT)


def test_postgres_starved_paused_and_killed_workers_complete_exactly(postgres, tmp_path):
    """With every core busy, three `designer explore` processes (same command, same seed) join one study on
    PostgreSQL. One is paused while it evaluates a trial until the others fail that trial for its missing
    heartbeat (a starved process, made certain); continued, it finishes the trial too late: its result is
    discarded with a note and the candidate counts once, through its retry. Another is SIGKILLed; the
    survivors retry its stale trial and end the study themselves; a `--resume` afterwards finds nothing to
    do. The study holds exactly TRIALS COMPLETE trials of TRIALS distinct candidates, no trial number twice,
    nothing left RUNNING or WAITING, and explore.csv's front drawn from them."""
    from optuna.trial import TrialState

    from designer.studies.explore import DUPLICATE_ATTR, SURPLUS_ATTR, lineage

    url = postgres.get_uri()
    env = {**os.environ, "DESIGNER_HEARTBEAT_SECONDS": str(HEARTBEAT), "DESIGNER_GRACE_SECONDS": str(GRACE)}
    out = tmp_path / "results"
    t0 = time.monotonic()
    with _every_core_busy(PATIENCE) as spinning:
        assert len(spinning) == (os.cpu_count() or 1)
        first = _explore(url, out, False, env)  # creates the study
        workers = [first]
        clock = _Clock(PATIENCE, workers)
        try:
            clock.wait(lambda: _trials(url) is not None, "the study was never created")
            workers += [_explore(url, out, True, env) for _ in range(2)]  # join it with the same seed
            paused, victim = workers[1], workers[2]
            late = _pause_until_failed(url, paused, clock)
            clock.wait(lambda: _evaluating(url, victim.pid) is not None, "the victim never ran a trial")
            victim.send_signal(signal.SIGKILL)
            assert victim.wait(timeout=PATIENCE) == -signal.SIGKILL
            for p in (first, paused):
                stdout, stderr = p.communicate(timeout=PATIENCE)
                assert p.returncode == 0, stderr
                assert json.loads(stdout)["trials"] == TRIALS  # the survivors end the study themselves
            assert f"trial {late} was failed by another process while this one still evaluated it" in stderr
            resume = _explore(url, out, True, env)
            stdout, stderr = resume.communicate(timeout=PATIENCE)
            assert resume.returncode == 0, stderr
        finally:
            for p in workers:
                if p.poll() is None:
                    p.kill()
                    p.wait()
        load = os.getloadavg()[0]
    summary = json.loads(stdout)
    assert summary["trials"] == TRIALS and summary["trials_run"] == 0

    trials = _trials(url)
    states = collections.Counter(t.state for t in trials)
    assert states[TrialState.COMPLETE] == TRIALS
    assert states[TrialState.RUNNING] == states[TrialState.WAITING] == 0
    assert sorted(t.number for t in trials) == list(range(len(trials)))  # none lost, none duplicated
    done = [t for t in trials if t.state == TrialState.COMPLETE]
    params = [tuple(sorted(t.params.items())) for t in done]
    assert len(set(params)) == TRIALS  # no candidate evaluated and counted twice
    assert len({lineage(t) for t in done}) == TRIALS
    # the paused worker's trial stays failed; its candidate is complete once, through a retry
    assert _state(url, late) == TrialState.FAIL
    failed_params = next(t.params for t in trials if t.number == late)
    chain = [(t.number, t.state.name) for t in trials if lineage(t) == late]
    assert [lineage(t) for t in done if t.params == failed_params] == [late], chain
    for t in trials:  # nothing pruned without its reason
        if t.state == TrialState.PRUNED:
            assert (SURPLUS_ATTR in t.user_attrs or DUPLICATE_ATTR in t.user_attrs) and t.values is None
    with open(out / "explore.csv", newline="") as fh:
        front = list(csv.DictReader(fh))
    assert front and {int(r["trial"]) for r in front} <= {t.number for t in done}  # the front is of this study
    # the README quotes the server start; the rest is the record of a saturated run (printed with -s)
    print(
        f"pgserver start {postgres.started_seconds:.1f} s; {len(spinning)} spinning processes; "
        f"{time.monotonic() - t0:.0f} s; load average {load:.1f}; states "
        f"{ {s.name: n for s, n in states.items()} }; the paused worker's candidate: {chain}"
    )
