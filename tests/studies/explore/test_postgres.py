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
PATIENCE = 900.0
"""[s] Bound of every wait of the test: a saturated 2-core machine runs it in a few minutes, a slower or busier
one may take several times longer; the waits end as soon as their condition holds, and at once (not at the
deadline) when no worker is left that could make it hold."""

WORKER = """
import os, signal, sys, time
from pathlib import Path
from designer.studies.explore import _workers
from designer.cli import main

role, marker, gate, start = sys.argv[1:5]
evaluate = _workers.evaluate_trial
calls = 0


def instrumented(*args, **kwargs):  # the worker's evaluation of a drawn candidate (no database transaction open)
    global calls
    calls += 1
    if role == "first" and calls == 1:  # hold the first trial (heartbeats go on) until the test opens the gate
        while not Path(gate).exists():
            time.sleep(0.05)
    elif role == "paused" and calls == 1:  # a starved process, made certain: stopped inside its first trial
        Path(marker).touch()
        os.kill(os.getpid(), signal.SIGSTOP)
    elif role == "victim":  # paced, so that it is still working when the test asks it to stop
        while not Path(start).exists():  # begins once the paused worker is stopped
            time.sleep(0.05)
        if Path(gate).exists():
            Path(marker).touch()
            os.kill(os.getpid(), signal.SIGSTOP)
        time.sleep(0.2)
    return evaluate(*args, **kwargs)


_workers.evaluate_trial = instrumented
sys.exit(main(sys.argv[5:]))
"""
"""A `designer explore` process whose evaluations the test choreographs by files: ``first`` holds its first trial
until ``gate`` exists; ``paused`` stops itself (SIGSTOP) inside its first trial after touching ``marker``;
``victim`` waits for ``start``, then evaluates one candidate per 0.2 s and stops itself inside a trial once
``gate`` exists."""


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


def _explore(url, out, resume, env, role=None, files=(os.devnull,) * 3):
    """`designer explore` joining the study (``resume``); with a ``role``, instrumented by :data:`WORKER`."""
    launch = [sys.executable, "-m", "designer.cli"] if role is None else [sys.executable, "-c", WORKER, role, *files]
    cmd = [*launch, "explore", str(ROOT / "problems" / "indoor-manual.toml")]
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
            if all(p.poll() is not None for p in self.procs) and not predicate():
                raise AssertionError(f"{what}: every worker has exited")
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


def test_postgres_starved_paused_and_killed_workers_complete_exactly(postgres, tmp_path):
    """With every core busy, three `designer explore` processes (same command, same seed) join one study on
    PostgreSQL. One is paused while it evaluates a trial until another fails that trial for its missing
    heartbeat (a starved process, made certain: it stops itself inside the evaluation, so the choreography does
    not depend on catching a fast trial by polling); continued, it finishes the trial too late: its result is
    discarded with a note and the candidate counts once, through its retry. Another is SIGKILLed inside a
    trial; the survivors retry its stale trial and end the study themselves; a `--resume` afterwards finds
    nothing to do. The study holds exactly TRIALS COMPLETE trials of TRIALS distinct candidates, no trial number twice,
    nothing left RUNNING or WAITING, and explore.csv's front drawn from them."""
    from optuna.trial import TrialState

    from designer.studies.explore import DUPLICATE_ATTR, SURPLUS_ATTR, lineage

    url = postgres.get_uri()
    env = {**os.environ, "DESIGNER_HEARTBEAT_SECONDS": str(HEARTBEAT), "DESIGNER_GRACE_SECONDS": str(GRACE)}
    out = tmp_path / "results"
    t0 = time.monotonic()
    gate, paused_at, victim_gate, victim_at = (tmp_path / n for n in ("gate", "paused", "stop-victim", "victim"))
    with _every_core_busy(PATIENCE) as spinning:
        assert len(spinning) == (os.cpu_count() or 1)
        first = _explore(url, out, False, env, "first", (os.devnull, str(gate), os.devnull))  # creates the study
        workers = [first]
        clock = _Clock(PATIENCE, workers)
        try:
            clock.wait(lambda: _trials(url) is not None, "the study was never created")
            paused = _explore(url, out, True, env, "paused", (str(paused_at), os.devnull, os.devnull))  # same seed
            victim = _explore(url, out, True, env, "victim", (str(victim_at), str(victim_gate), str(paused_at)))
            workers += [paused, victim]
            # the paused worker stops itself inside a trial; the victim, still working, fails it when its
            # heartbeat is GRACE seconds late
            clock.wait(paused_at.exists, "the paused worker never ran a trial")
            clock.wait(lambda: _evaluating(url, paused.pid) is not None, "the paused worker's trial is not running")
            late = _evaluating(url, paused.pid)
            clock.wait(lambda: _state(url, late) == TrialState.FAIL, "the paused worker's trial was never failed")
            victim_gate.touch()  # the victim stops itself inside its next trial and is killed there
            clock.wait(victim_at.exists, "the victim never stopped inside a trial")
            clock.wait(lambda: _evaluating(url, victim.pid) is not None, "the victim's trial is not running")
            victim.send_signal(signal.SIGKILL)
            assert victim.wait(timeout=PATIENCE) == -signal.SIGKILL
            paused.send_signal(signal.SIGCONT)  # its result comes too late and must not count
            gate.touch()
            for p in (first, paused):
                stdout, stderr = p.communicate(timeout=PATIENCE)
                assert p.returncode == 0, stderr
                assert json.loads(stdout)["trials"] == TRIALS  # the survivors end the study themselves
            said = " ".join(stderr.split())  # notes are wrapped at the terminal's width
            assert f"trial {late} was failed by another process while this one still evaluated it" in said
            resume = _explore(url, out, True, env)
            stdout, stderr = resume.communicate(timeout=PATIENCE)
            assert resume.returncode == 0, stderr
        finally:
            for p in workers:
                if p.poll() is None:
                    p.send_signal(signal.SIGCONT)
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
