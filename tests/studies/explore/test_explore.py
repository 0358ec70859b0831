"""Tests of ``designer explore`` (issue 5): optuna NSGA-II exploration, storages, budget, resume, refine."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import optuna
import pytest
from optuna.trial import TrialState

import designer
from designer.model import performance
from designer.cli import main
from designer.studies.explore import (
    CSV_COLUMNS,
    RETRY_ATTR,
    SURPLUS_ATTR,
    StorageError,
    explore,
    open_storage,
    parse_storage,
)
from designer.solvers.nlp import CasterNLP, best_starts, solve_best

ROOT = Path(__file__).resolve().parents[3]
INDOOR = ROOT / "problems" / "indoor-manual.toml"
CATALOG = ROOT / "problems" / "catalog-retrofit.toml"
STUDY = "indoor-manual-explore"

optuna.logging.set_verbosity(optuna.logging.WARNING)


def _load(url: str, name: str = STUDY):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return optuna.load_study(study_name=name, storage=open_storage(parse_storage(url)))


def _params_key(trial) -> tuple:
    return tuple(sorted(trial.params.items()))


def test_two_workers_on_journal_finish_exactly_n_trials(tmp_path):
    """Two processes on one journal file end with exactly N COMPLETE trials: unique trial numbers,
    unique parameter sets, nothing left RUNNING or WAITING, and surplus trials (if any) never evaluated."""
    url = f"journal://{tmp_path / 'study.log'}"
    n = 100
    result = explore(designer.load_problem(INDOOR), trials=n, storage=url, workers=2, compare=False)
    study = _load(url)
    trials = study.get_trials(deepcopy=False)
    complete = [t for t in trials if t.state == TrialState.COMPLETE]
    assert result.trials == n
    assert len(complete) == n
    assert len({t.number for t in trials}) == len(trials)
    assert len({_params_key(t) for t in complete}) == n
    assert not [t for t in trials if t.state in (TrialState.RUNNING, TrialState.WAITING)]
    for t in trials:
        if t.state == TrialState.PRUNED:
            assert t.user_attrs.get(SURPLUS_ATTR) and t.values is None
    # both processes worked (each draws from its own stream, chosen by its first trial; the uniqueness of all N
    # parameter sets above shows no worker repeated the other). The front size depends on how the two
    # processes interleave, so only its existence is asserted (">= 3" failed once in a full-suite run).
    assert result.workers == 2 and len(result.front) >= 1


def test_killed_run_resumes_to_exactly_n_trials(tmp_path):
    """A run killed (SIGKILL) midway and resumed with --resume ends with exactly N COMPLETE trials,
    no RUNNING trial left, unique trial numbers and parameter sets, and retried trials keep their parameters."""
    log = tmp_path / "study.log"
    url = f"journal://{log}"
    n = 400
    cmd = [
        sys.executable,
        "-m",
        "designer.cli",
        "explore",
        str(INDOOR),
        "--trials",
        str(n),
        "--storage",
        url,
        "--no-compare",
        "--json",
        "--out",
        str(tmp_path / "first"),
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp_path)
    done = 0
    deadline = time.time() + 30
    try:
        while time.time() < deadline and proc.poll() is None:
            time.sleep(0.2)
            if log.exists() and log.stat().st_size:
                try:
                    done = len(_load(url).get_trials(deepcopy=False, states=(TrialState.COMPLETE,)))
                except KeyError:
                    continue
                if done >= 40:
                    break
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    before = _load(url).get_trials(deepcopy=False)
    complete_before = sum(t.state == TrialState.COMPLETE for t in before)
    assert 40 <= complete_before < n, "the run must be killed midway"

    result = explore(designer.load_problem(INDOOR), trials=n, storage=url, resume=True, compare=False)
    trials = _load(url).get_trials(deepcopy=False)
    complete = [t for t in trials if t.state == TrialState.COMPLETE]
    assert result.trials == n and len(complete) == n
    assert not [t for t in trials if t.state in (TrialState.RUNNING, TrialState.WAITING)]
    assert len({t.number for t in trials}) == len(trials)
    assert len({_params_key(t) for t in complete}) == n
    # every trial that was complete before the kill is still there, unchanged
    survivors = {t.number: t.values for t in before if t.state == TrialState.COMPLETE}
    assert all(trials[k].values == v for k, v in survivors.items())
    # a retried trial evaluates the failed trial's parameters
    for t in trials:
        if RETRY_ATTR in t.user_attrs:
            assert t.params == trials[t.user_attrs[RETRY_ATTR]].params


def _enumerate_catalog(problem):
    """Best weighted J [N] per wheel by the exact NLP (multi-start), as {wheel: J}."""
    out = {}
    for variant in problem.variants():
        nlp = CasterNLP(variant)
        best, _ = solve_best(nlp, best_starts(variant, variant.weights), variant.weights)
        if best is not None:
            out[variant.conditions.inertia.wheel.key] = nlp.weighted(best.design, variant.weights)
    return out


@pytest.mark.parametrize("target_speed", [None, 2.6])
def test_catalog_best_wheel_matches_nlp_enumeration(target_speed):
    """On the categorical catalog problem the explored best wheel for J = F_turn + P is the one found by
    enumerating the catalog with the NLP (at 2.0 m/s wheels D and E tie exactly; at 2.6 m/s D is unique), and
    with --refine its J equals the NLP optimum to 1e-6.  500 trials: under the risk bound (issue 28.4) the
    feasible set at 2.6 m/s is narrow and 300 trials' best unrefined point was wheel E (J 104 N against D's
    96 N)."""
    problem = designer.load_problem(CATALOG)
    if target_speed is not None:
        problem = problem.replace(target_speed=target_speed)
    enumerated = _enumerate_catalog(problem)
    j_best = min(enumerated.values())
    best_wheels = {k for k, j in enumerated.items() if j <= j_best * (1 + 1e-6)}
    w = problem.weights

    def best_weighted(result):  # the front point of least J = w_turn F_turn + w_threshold P
        return min(result.front, key=lambda r: w[0] * r["turning_effort"] + w[1] * r["threshold_force"])

    explored = best_weighted(explore(problem, trials=500, seed=0, compare=False))
    assert explored["wheel"] in best_wheels
    refined = explore(problem, trials=500, seed=0, refine=True, compare=False)
    best = best_weighted(refined)
    assert best["wheel"] in best_wheels and best["refined"]
    assert w[0] * best["turning_effort"] + w[1] * best["threshold_force"] == pytest.approx(j_best, rel=1e-6)
    assert set(refined.category_fronts) == {f"wheel={k}" for k in problem.wheels}


def test_same_seed_same_front():
    """A single-worker seeded run is repeatable (identical fronts); another seed explores differently."""
    problem = designer.load_problem(INDOOR)
    a = explore(problem, trials=200, seed=7, compare=False)
    b = explore(problem, trials=200, seed=7, compare=False)
    c = explore(problem, trials=200, seed=8, compare=False)
    assert a.front == b.front and a.distinct == b.distinct == 200
    assert a.front != c.front


def test_front_is_feasible_and_constraints_reach_optuna():
    """Constraints go to optuna through trial.set_constraint (keys shimmy, swept_radius; g <= 0 feasible), and
    every front point meets the problem's risk bound (V_q >= V_target, so V_c too, Eq. 7), as the exact front
    it is compared with does (issue 28.4: it was V_c >= V_target alone), and T + d/2 <= R_max."""
    problem = designer.load_problem(INDOOR)
    storage = "sqlite:///" + str(Path(os.environ.get("TMPDIR", "/tmp")) / f"explore-test-{os.getpid()}.db")
    try:
        result = explore(problem, trials=20, seed=1, storage=storage, study_name="constraints", compare=False)
        trial = _load(storage, "constraints").trials[0]
        assert set(trial.constraints) == {"shimmy", "swept_radius"}
    finally:
        Path(storage[len("sqlite:///") :]).unlink(missing_ok=True)
    assert result.front
    assert problem.risk is not None
    for row in result.front:
        assert row["critical_speed"] >= problem.required_speed * (1 - 1e-12)
        values = performance(
            **{k: row[k] for k in ("trail", "diameter", "groove", "damping")}, conditions=problem.conditions
        )
        assert values["confident_speed"] >= problem.required_speed * (1 - 1e-12)
        assert row["trail"] + row["diameter"] / 2 <= problem.swept_radius_max * (1 + 1e-12)


def test_tuned_operators_beat_optuna_defaults():
    """The tuned operators (SBX, polynomial mutation, population ≈ √N, duplicate filter) give no repeated
    parameter sets and a higher hypervolume against the exact front than optuna's defaults at 500 trials, on
    average over seeds 0-19 by more than two standard errors of the mean paired difference (one seed proves
    nothing: at seed 0 the defaults win, 0.846 against 0.813; over 60 seeds the tuned mean is 0.832 ± 0.005
    against 0.798 ± 0.005, the README's numbers).  Whether optuna's own defaults repeat parameter sets is
    optuna's business, not asserted."""
    problem = designer.load_problem(INDOOR)
    gains = []
    for seed in range(20):
        tuned = explore(problem, trials=500, seed=seed)
        default = explore(problem, trials=500, seed=seed, operators="optuna")
        assert tuned.distinct == 500
        gains.append(tuned.comparison["hypervolume_ratio"] - default.comparison["hypervolume_ratio"])
    mean, se = float(np.mean(gains)), float(np.std(gains, ddof=1) / np.sqrt(len(gains)))
    assert mean > 2 * se, (mean, se)


@pytest.mark.parametrize(
    "url",
    [
        "foo://bar",
        "sqlite:////no/such/folder/x.db",
        "journal:///no/such/folder/x.log",
        "postgresql://user:secret@127.0.0.1:1/db",
        "not-a-url",
    ],
)
def test_bad_storage_is_one_line_exit_6(url, capsys, tmp_path):
    """A malformed or unreachable storage gives exit code 6 and one line on stderr, no traceback, no password."""
    code = main(["explore", str(INDOOR), "--trials", "10", "--storage", url, "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip()
    assert code == 6
    assert len(err.splitlines()) == 1 and err.startswith("designer: error: storage")
    assert "Traceback" not in err and "secret" not in err
    assert not list(tmp_path.iterdir())


def test_workers_need_shared_storage_and_resume_needs_study(capsys, tmp_path):
    """--workers 2 in memory is an input error (exit 2); --resume of a study that does not exist also (exit 2)."""
    assert main(["explore", str(INDOOR), "--workers", "2", "--out", str(tmp_path)]) == 2
    assert "--workers" in capsys.readouterr().err
    url = f"journal://{tmp_path / 'empty.log'}"
    assert main(["explore", str(INDOOR), "--resume", "--storage", url, "--out", str(tmp_path)]) == 2
    assert "no study" in capsys.readouterr().err


def test_cli_writes_csv_and_json(tmp_path, capsys):
    """The CLI writes explore.csv (each column's unit in its name, category column, front flags) and explore.json (fronts per category,
    HV, IGD+, study, storage, seed, trials, versions) atomically: no temporary files left."""
    code = main(
        ["explore", str(CATALOG), "--trials", "150", "--seed", "2", "--refine", "--json", "--out", str(tmp_path)]
    )
    assert code == 0
    printed = json.loads(capsys.readouterr().out)
    header = (tmp_path / "explore.csv").read_text().splitlines()[0].split(",")
    assert header[:7] == [
        "trail_in", "diameter_in", "groove_in", "damping_N_m_per_rad", "turning_effort_N", "threshold_force_N",
        "critical_speed_m_per_s",
    ]  # fmt: skip
    assert len(CSV_COLUMNS) == 7 and "wheel" in header and "overall_front" in header
    data = json.loads((tmp_path / "explore.json").read_text())
    assert data == printed
    for key in (
        "front",
        "category_fronts",
        "hypervolume",
        "comparison",
        "study",
        "storage",
        "seed",
        "trials",
        "versions",
    ):
        assert key in data
    assert data["trials"] == 150 and data["seed"] == 2 and data["storage"] == "memory"
    assert data["comparison"]["hypervolume_ratio"] == pytest.approx(1.0, abs=1e-6)
    assert data["comparison"]["igd_plus"] == pytest.approx(0.0, abs=1e-6)
    assert sorted(p.name for p in tmp_path.iterdir()) == [".designer-manifest.json", "explore.csv", "explore.json"]


def test_parse_storage_forms():
    """Storage URL forms: memory, journal URL or .log path, sqlite URL or .db path, postgres (password redacted)."""
    assert parse_storage(None).kind == "memory"
    assert parse_storage("journal:///tmp/a.log").url == "/tmp/a.log"
    assert parse_storage("runs/a.journal").kind == "journal"
    assert parse_storage("a.db").url == "sqlite:///a.db"
    spec = parse_storage("postgresql://me:pw@db.example:5432/caster")
    assert spec.kind == "rdb" and spec.remote and "pw" not in spec.shown
    with pytest.raises(StorageError):
        parse_storage("redis://localhost")


# --------------------------------------------------------------------------- exactly once (issue 23.3)


def _url(kind: str, folder: Path) -> str:
    return f"sqlite:///{folder / 'study.db'}" if kind == "sqlite" else f"journal://{folder / 'study.log'}"


@pytest.mark.parametrize("kind", ["sqlite", "journal"])
@pytest.mark.parametrize("moment", ["before its constraints are set", "before it is told"])
def test_a_trial_failed_while_evaluated_counts_once(kind, moment, tmp_path, monkeypatch):
    """A trial that another process fails (and retries, as the heartbeat's callback does) while this process
    still evaluates it keeps its FAIL: the late result is discarded with a note naming the trial, the worker
    carries on, and the study ends with exactly N COMPLETE trials of N distinct candidates, the failed
    trial's candidate complete once, through its retry."""
    from designer.studies.explore import _workers, lineage

    url, n = _url(kind, tmp_path), 12
    failed = []

    def other_process_fails_it():
        study = _load(url)  # a second connection: another process
        (running,) = study.get_trials(deepcopy=False, states=(TrialState.RUNNING,))
        study._storage.set_trial_state_values(running._trial_id, TrialState.FAIL)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the callback's deprecated name in optuna 5
            optuna.storages.RetryFailedTrialCallback(max_retry=1)(study, study.trials[running.number])
        failed.append(running.number)

    if moment == "before its constraints are set":
        evaluate = _workers.evaluate_trial

        def late_evaluate(sub, x):
            if not failed and len(_load(url).trials) == 4:
                other_process_fails_it()
            return evaluate(sub, x)

        monkeypatch.setattr(_workers, "evaluate_trial", late_evaluate)
    else:
        call = _workers._Evaluator.__call__

        def late_call(self, trial):
            values = call(self, trial)
            if not failed and trial.number == 3:
                other_process_fails_it()
            return values

        monkeypatch.setattr(_workers._Evaluator, "__call__", late_call)
    result = explore(designer.load_problem(INDOOR), trials=n, seed=3, storage=url, compare=False)
    trials = _load(url).get_trials(deepcopy=False)
    complete = [t for t in trials if t.state == TrialState.COMPLETE]
    assert failed == [3] and trials[3].state == TrialState.FAIL
    assert result.trials == n == len(complete) == len({_params_key(t) for t in complete})
    (retry,) = [t for t in trials if t.number != 3 and lineage(t) == 3]
    assert [t.number for t in complete if t.params == trials[3].params] == [retry.number]  # once, the retry
    assert [w for w in result.warnings if "trial 3 was failed by another process" in w]
    assert not [t for t in trials if t.state in (TrialState.RUNNING, TrialState.WAITING)]


def test_a_candidate_retried_twice_in_a_race_is_evaluated_once(tmp_path):
    """A failed candidate queued twice (two processes resuming at once, or a resume beside the heartbeat's
    callback) is evaluated by its first retry only: the second is PRUNED with explore_duplicate_of, never
    evaluated, and the study still ends with exactly N COMPLETE trials of N distinct candidates."""
    from designer.studies.explore import DUPLICATE_ATTR, lineage

    url, n = _url("journal", tmp_path), 10
    problem = designer.load_problem(INDOOR)
    explore(problem, trials=4, seed=0, storage=url, compare=False)
    study = _load(url)
    dists = study.trials[0].distributions
    study.add_trial(  # a trial killed after its parameters were drawn: the middle of the box
        optuna.trial.create_trial(
            state=TrialState.FAIL, params={k: (d.low + d.high) / 2 for k, d in dists.items()}, distributions=dists
        )
    )
    lost = study.trials[-1]
    study.enqueue_trial(lost.params, user_attrs={RETRY_ATTR: lost.number})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        optuna.storages.RetryFailedTrialCallback(max_retry=1)(study, lost)
    result = explore(problem, trials=n, seed=0, storage=url, resume=True, compare=False)
    trials = _load(url).get_trials(deepcopy=False)
    complete = [t for t in trials if t.state == TrialState.COMPLETE]
    assert result.trials == n == len(complete) == len({_params_key(t) for t in complete})
    twins = [t for t in trials if t.number > lost.number and lineage(t) == lost.number]
    assert [t.state for t in twins] == [TrialState.COMPLETE, TrialState.PRUNED]
    assert twins[0].params == lost.params and twins[1].values is None
    assert twins[1].user_attrs[DUPLICATE_ATTR] == twins[0].number


def test_processes_joining_one_study_draw_different_candidates(tmp_path):
    """Seeds no longer add up to a shared stream: a resume with seed 5 at 8 trials used to replay the draws of
    a resume with seed 10 at 3 trials (5 + 8 = 10 + 3), evaluating and counting 5 candidates twice. Each
    process's stream is now chosen by its first trial's number, unique in the study."""
    url = _url("journal", tmp_path)
    problem = designer.load_problem(INDOOR)
    explore(problem, trials=3, seed=0, storage=url, compare=False)
    explore(problem, trials=8, seed=10, storage=url, resume=True, compare=False)
    result = explore(problem, trials=13, seed=5, storage=url, resume=True, compare=False)
    assert result.trials == result.distinct == 13


def test_stream_seeds_of_two_processes_never_coincide():
    """stream_seed(seed, n) = (seed + STREAM_STRIDE n) mod 2**32: the same seed with two first trials below
    2**20 never gives one stream, nor do seeds that differ by less than 1637 (the smallest distance of
    STREAM_STRIDE k from a multiple of 2**32 for 0 < k < 2**20); a fresh run (first trial 0) keeps its seed."""
    import numpy as np

    from designer.studies.explore import STREAM_STRIDE, stream_seed

    k = np.arange(1, 2**20, dtype=np.uint64)
    r = (k * np.uint64(STREAM_STRIDE)) % np.uint64(2**32)
    assert int(np.minimum(r, np.uint64(2**32) - r).min()) == 1637
    assert stream_seed(7, 0) == 7 and stream_seed(None, 5) is None
    assert stream_seed(0, 1) != stream_seed(1, 0) and 0 <= stream_seed(2**32 - 1, 3) < 2**32
