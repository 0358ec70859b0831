"""Issue 12.7: one optuna study shared by several `designer explore` processes on a real PostgreSQL
server, started by the test itself (pgserver ships the server binaries and runs as root too)."""

from __future__ import annotations

import collections
import json
import os
import signal
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from conftest import ROOT

TRIALS = 60
STUDY = "pg-kill-resume"


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


def _explore(url, out, seed, resume, env):
    cmd = [
        sys.executable,
        "-m",
        "designer.cli",
        "explore",
        str(ROOT / "problems" / "indoor-manual.toml"),
        "--storage",
        url,
        "--study",
        STUDY,
        "--trials",
        str(TRIALS),
        "--seed",
        str(seed),
        "--no-compare",
        "--json",
        "--out",
        str(out),
    ] + (["--resume"] if resume else [])
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)


def _trials(url):
    import optuna

    from designer.studies.explore import parse_storage

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    try:  # the driver the designer picks (psycopg2 for a plain postgresql:// URL)
        return optuna.load_study(study_name=STUDY, storage=parse_storage(url).url).get_trials(deepcopy=False)
    except KeyError:
        return None


def _wait(predicate, timeout, procs=()):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        for p in procs:
            if p.poll() not in (None, 0):
                raise AssertionError(f"worker exited {p.returncode}: {p.stderr.read()}")
        time.sleep(0.2)
    return False


def test_postgres_three_workers_one_killed_resume_completes_exactly(postgres, tmp_path):
    """Three `designer explore` processes join one study on PostgreSQL; one is SIGKILLed a third of the way
    through; the others finish; `--resume` (after the killed worker's heartbeat has gone stale) fails its
    stale trial, retries it and completes the study: exactly TRIALS COMPLETE trials, no trial number and no
    candidate counted twice, every trial number accounted for, and explore.csv's front drawn from them."""
    from optuna.trial import TrialState

    url = postgres.get_uri()
    # short heartbeat and grace period so that the killed worker's trial is stale in seconds, not a minute
    env = {**os.environ, "DESIGNER_HEARTBEAT_SECONDS": "1", "DESIGNER_GRACE_SECONDS": "3"}
    out = tmp_path / "results"
    first = _explore(url, out, 0, False, env)  # creates the study
    assert _wait(lambda: _trials(url) is not None, 120, [first]), "the study was never created"
    others = [_explore(url, out, seed, True, env) for seed in (1, 2)]  # join it
    workers = [first] + others

    def complete():
        return sum(t.state == TrialState.COMPLETE for t in _trials(url) or [])

    assert _wait(lambda: complete() >= TRIALS // 3, 240, workers), "no progress"
    victim = others[0]
    victim.send_signal(signal.SIGKILL)
    victim.wait(timeout=30)
    assert victim.returncode == -signal.SIGKILL
    for p in (first, others[1]):
        stdout, stderr = p.communicate(timeout=300)
        assert p.returncode == 0, stderr
    time.sleep(4)  # past the grace period: the killed worker's RUNNING trial (if any) is now stale
    resume = _explore(url, out, 3, True, env)
    stdout, stderr = resume.communicate(timeout=300)
    assert resume.returncode == 0, stderr
    summary = json.loads(stdout)
    assert summary["trials"] == TRIALS

    trials = _trials(url)
    states = collections.Counter(t.state for t in trials)
    assert states[TrialState.COMPLETE] == TRIALS
    assert states[TrialState.RUNNING] == 0
    numbers = [t.number for t in trials]
    assert sorted(numbers) == list(range(len(trials)))  # none lost, none duplicated
    done = [t for t in trials if t.state == TrialState.COMPLETE]
    params = [tuple(sorted(t.params.items())) for t in done]
    assert len(set(params)) == TRIALS  # no candidate evaluated and counted twice
    import csv

    with open(out / "explore.csv", newline="") as fh:
        front = list(csv.DictReader(fh))
    assert front and {int(r["trial"]) for r in front} <= {t.number for t in done}  # the front is of this study
    # the README quotes these; printed with -s
    print(f"pgserver start {postgres.started_seconds:.1f} s")
