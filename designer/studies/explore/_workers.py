"""The processes that run trials: the optuna objective and its budget (:class:`_Evaluator`), one worker
(:func:`_run_worker`, an ask-and-tell loop, :func:`_work`), the pool of worker processes (:func:`_run_pool`),
and :func:`_run_study`, which runs the study in this process or on the pool.
:func:`designer.studies.explore._runner.explore` calls it.  How every candidate counts exactly once (own random
streams, telling only a RUNNING trial, a retry only of a candidate no live trial holds): the package's text,
"Budget and exactness" (:mod:`designer.studies.explore`).
"""

from __future__ import annotations

import collections
import contextlib
import math
import multiprocessing
import os
import signal
import socket
import sys
import threading
import time
import warnings

import numpy as np

from designer.children import bind_to_parent
from designer.errors import StorageError, quiet_after_signal
from designer.model import FEASIBILITY_TOLERANCE, VARIABLES, Caster
from designer.problem import Problem
from designer.studies.explore._operators import Operators, SearchSpace, category_problem, search_space
from designer.studies.explore._storage import StorageSpec, _one_line, open_storage, parse_storage, scrub

SURPLUS_ATTR = "explore_surplus"
"""User attribute of a trial pruned because the budget was reached by other workers (never evaluated)."""
RETRY_ATTR = "explore_retry_of"
"""User attribute of a trial that re-evaluates a failed candidate: the number of the candidate's first trial."""
DUPLICATE_ATTR = "explore_duplicate_of"
"""User attribute of a retry pruned because an earlier trial holds the same candidate (never evaluated)."""
WORKER_ATTR = "explore_worker"
"""User attribute: the process (``host:pid``) that ran the trial."""

_WORKER = f"{socket.gethostname()}:{os.getpid()}"


def lineage(trial) -> int:
    """The number of the first trial of ``trial``'s candidate: itself, or the trial a retry re-evaluates.

    A retry made by ``--resume`` carries it as ``explore_retry_of``; a retry made by the storage's heartbeat
    callback carries optuna's ``failed_trial`` system attribute (the first failed trial of its chain) and the
    user attributes of the trial it copies.
    """
    return int(trial.user_attrs.get(RETRY_ATTR, trial.system_attrs.get("failed_trial", trial.number)))


class _Evaluator:
    """The optuna objective: suggest, evaluate with the one model, set constraints."""

    def __init__(self, problem: Problem, space: SearchSpace, budget: int, shared: bool = True):
        self.shared = shared  # several processes may work on the study: budget and duplicates by trial number
        self.problem = problem
        self.space = space
        self.budget = budget
        self.problems = {cat: category_problem(problem, cat) for cat in space.categories()}

    def design_array(self, category: tuple, params: dict) -> np.ndarray:
        """(T, d, B, c_f) [SI] of a trial: suggested values, else the category's fixed bound."""
        sub = self.problems[category]
        return np.array([params.get(name, sub.bounds[name].low) for name in VARIABLES], float)

    def skip(self, trial) -> str | None:
        """Why ``trial`` must not be evaluated (it is then pruned), or None.

        Surplus: ``budget`` waiting, running or complete trials precede it (by number).  Duplicate: an
        earlier waiting, running or complete trial holds the same candidate (:func:`lineage`), as when a
        failed trial was retried twice by processes in a race.  Trials are created one at a time, so every
        trial with a smaller number is visible here.
        """
        from optuna.trial import TrialState

        live = (TrialState.WAITING, TrialState.RUNNING, TrialState.COMPLETE)
        trials = trial.study.get_trials(deepcopy=False)
        me = next(t for t in trials if t.number == trial.number)  # a FrozenTrial: its system attributes too
        earlier = [t for t in trials if t.number < trial.number and t.state in live]
        if len(earlier) >= self.budget:
            trial.set_user_attr(SURPLUS_ATTR, True)
            return "budget reached by other workers"
        root = lineage(me)
        twin = next((t.number for t in earlier if lineage(t) == root), None)
        if twin is not None:
            trial.set_user_attr(DUPLICATE_ATTR, twin)
            return f"candidate already held by trial {twin}"
        return None

    def __call__(self, trial):
        import optuna

        if self.shared:
            trial.set_user_attr(WORKER_ATTR, _WORKER)
            reason = self.skip(trial)
            if reason is not None:
                raise optuna.TrialPruned(reason)
        category = tuple(
            (name, trial.suggest_categorical(name, list(choices))) for name, choices in self.space.categorical
        )
        params = {name: trial.suggest_float(name, lo, hi) for name, lo, hi in self.space.continuous}
        sub = self.problems[category]
        values = evaluate_trial(sub, self.design_array(category, params))
        f_turn, p = values.turning_effort, values.threshold_force
        # the model's constraint values less its one tolerance, so optuna's g <= 0 is the model's feasibility:
        # g_risk on V_q of the risk bound (V_c for a nominal problem), g_radius on the swept radius
        tol = FEASIBILITY_TOLERANCE
        trial.set_constraint("shimmy", values.g_risk - tol if math.isfinite(values.g_risk) else 1.0)
        if sub.swept_radius_max is not None:
            trial.set_constraint("swept_radius", values.g_radius - tol)
        return (f_turn if math.isfinite(f_turn) else 1e12), (p if math.isfinite(p) else 1e12)


def evaluate_trial(sub: Problem, x: np.ndarray) -> Caster:
    """One drawn candidate (T, d, B, c_f [SI]) by the model's evaluator under its category's problem: a Caster."""
    return sub.evaluate(x[None, :]).row(0)


def _counts(study) -> collections.Counter:
    """The number of the study's trials in each state (0 for a state none is in)."""
    return collections.Counter(t.state for t in study.get_trials(deepcopy=False))


@contextlib.contextmanager
def _heartbeat(storage, trial_id: int, interval: float | None):
    """Record the trial's heartbeat in ``storage`` every ``interval`` seconds while the block runs."""
    if interval is None:
        yield
        return
    storage.record_heartbeat(trial_id)  # now, not when the thread first runs: a stale trial is one with a beat
    stop = threading.Event()

    def beat():
        while not stop.wait(interval):
            with contextlib.suppress(Exception):  # a missed beat is retried; a dead database stops the main thread
                storage.record_heartbeat(trial_id)

    thread = threading.Thread(target=beat, name=f"heartbeat-{trial_id}", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()


def _tell(study, trial, values, state):
    """Tell ``trial`` only while it is still RUNNING: the told FrozenTrial, or None when another process has
    failed it meanwhile (then it keeps its FAIL and ``values`` count nowhere)."""
    from optuna.exceptions import UpdateFinishedTrialError

    from optuna.trial import TrialState

    try:
        told = study.tell(trial, values, state=state, skip_if_finished=True)
    except UpdateFinishedTrialError:  # failed between tell's check of the state and its write
        return None
    return told if told.state == (TrialState.COMPLETE if state is None else state) else None


def _work(study, evaluator: _Evaluator, budget: int, storage, on_trial=None) -> list[str]:
    """Ask, evaluate and tell trials until the study holds ``budget`` COMPLETE trials; returns notes.

    With a heartbeat (a client–server database), stale RUNNING trials are failed before every trial (the
    storage's callback queues their retries), and a worker that finds the budget taken by running trials
    waits: each of them completes, or goes stale and is retried, or is abandoned (:func:`_abandon`), so
    the study ends with exactly ``budget`` COMPLETE trials as long as one worker lives.  Without a
    heartbeat a running trial of another process cannot be told from a dead one: the worker stops
    (``--resume`` finishes such a study).
    """
    import optuna

    from optuna.exceptions import UpdateFinishedTrialError

    from optuna.trial import TrialState

    interval = storage.get_heartbeat_interval() if hasattr(storage, "get_heartbeat_interval") else None
    notes: list[str] = []
    waited_on: dict[int, float] = {}
    while True:
        if interval is not None:
            optuna.storages.fail_stale_trials(study)
        counts = _counts(study)
        if counts[TrialState.COMPLETE] >= budget:
            return notes
        if counts[TrialState.COMPLETE] + counts[TrialState.RUNNING] >= budget and not counts[TrialState.WAITING]:
            if interval is None or not evaluator.shared:
                return notes
            _abandon(study, storage, waited_on, 2.0 * (getattr(storage, "grace_period", None) or 2 * interval))
            time.sleep(min(interval, 1.0))
            continue
        waited_on.clear()
        trial, values, state = study.ask(), None, None
        try:
            with _heartbeat(storage, trial._trial_id, interval):
                try:
                    values = evaluator(trial)
                except optuna.TrialPruned:
                    state = TrialState.PRUNED
        except UpdateFinishedTrialError:  # a write to the trial (an attribute, a parameter) was refused
            told = None
        except BaseException:  # Ctrl-C or a bug: the trial fails (a resume retries it) and the error goes on
            _tell(study, trial, None, TrialState.FAIL)
            raise
        else:
            told = _tell(study, trial, values, state)  # None: another process failed the trial before
        if told is None:
            notes.append(
                f"trial {trial.number} was failed by another process while this one still evaluated it (its "
                f"heartbeat was late: this process was starved of CPU or paused); its result was discarded, so "
                f"its candidate counts at most once, through a retry"
            )
        elif on_trial is not None:
            on_trial(study, told, _counts(study))


def _abandon(study, storage, waited_on: dict, patience: float) -> None:
    """Fail the RUNNING trials that this waiting worker has seen running for over ``patience`` seconds.

    The heartbeat fails a trial only once it has a beat: a process killed between asking its trial and
    the first beat leaves it RUNNING for ever.  Failing a trial whose process is alive but slow is safe: its
    result is then discarded (:func:`_tell`) and the budget is filled by another trial.
    """
    from optuna.exceptions import UpdateFinishedTrialError

    from optuna.trial import TrialState

    now = time.monotonic()
    running = study.get_trials(deepcopy=False, states=(TrialState.RUNNING,))
    for number in set(waited_on) - {t.number for t in running}:
        del waited_on[number]
    for t in running:
        if now - waited_on.setdefault(t.number, now) > patience:
            with contextlib.suppress(UpdateFinishedTrialError):  # it has just finished after all
                storage.set_trial_state_values(t._trial_id, TrialState.FAIL)


def _run_worker(
    problem: Problem,
    storage: str | None,
    study_name: str,
    budget: int,
    seed: int | None,
    operators: dict,
    storage_obj=None,
    on_trial=None,
    check_budget: bool = True,
) -> list[str]:
    """Run trials on one study until it holds ``budget`` COMPLETE trials (one process); returns notes.

    ``check_budget``: other processes may work on the study, so each trial checks by its number that
    fewer than ``budget`` trials precede it and that no earlier trial holds its candidate.
    """
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # optuna's experimental heartbeat API, ask() with a heartbeat storage
        if storage_obj is None:
            storage_obj = open_storage(parse_storage(storage))
        ops = Operators.from_dict(operators)
        study = optuna.load_study(study_name=study_name, storage=storage_obj, sampler=ops.process_sampler(seed))
        evaluator = _Evaluator(problem, search_space(problem), budget, shared=check_budget)
        return _work(study, evaluator, budget, storage_obj, on_trial)


_signalled: list[int] = []
"""The signals a pool worker received (its parent sends SIGINT to stop it): an error after one is the stop's."""


def _worker_entry(args, notes=None, parent: int | None = None) -> None:  # top level: picklable for multiprocessing
    """One pool worker: run the study, put its notes on the ``notes`` queue (if given).  It ends with its
    parent ``parent`` (a pid), however the parent ends (:func:`designer.children.bind_to_parent`)."""
    bind_to_parent(parent)

    def note(signum, frame):  # SIGINT and SIGTERM still raise KeyboardInterrupt, and are remembered (_signalled),
        _signalled.append(signum)  # so an error they cause inside a library (a commit cut short) ends it quietly
        quiet_after_signal()  # a KeyboardInterrupt inside a weakref callback is not printed as "Exception ignored"
        raise KeyboardInterrupt

    with contextlib.suppress(ValueError):  # not the main thread
        signal.signal(signal.SIGINT, note)
        signal.signal(signal.SIGTERM, note)
    try:
        found = _run_worker(*args)
        if notes is not None:
            notes.put(found)
    except KeyboardInterrupt:
        pass
    except Exception as exc:  # one line, no traceback: the parent says which workers failed and what to do
        if _signalled:  # a commit cut short by the parent's SIGINT (StorageInternalError): the parent says it
            return
        line = scrub(_one_line(exc), args[1] if len(args) > 1 else None)  # args[1]: the storage URL (no password)
        print(f"designer: explore worker: {type(exc).__name__}: {line}", file=sys.stderr, flush=True)
        sys.exit(1)


def _run_study(
    problem,
    spec: StorageSpec,
    study_name: str,
    trials: int,
    seed,
    ops: Operators,
    workers: int,
    storage_obj,
    tracker,
    bar,
    check_budget: bool,
    progress: bool,
) -> list[str]:
    """Run the study to ``trials`` COMPLETE trials: in this process, or on a pool of ``workers`` processes.

    Returns the workers' notes (results that came too late to count)."""
    from optuna.trial import TrialState

    try:
        with bar:
            if workers == 1:

                def on_trial(study_, frozen, counts):
                    if frozen.state == TrialState.COMPLETE and all(v <= 0 for v in frozen.constraints.values()):
                        tracker.add(frozen.values)
                    bar.update(counts[TrialState.COMPLETE], tracker)

                return _run_worker(
                    problem,
                    spec.url,
                    study_name,
                    trials,
                    seed,
                    ops.to_dict(),
                    storage_obj=storage_obj,
                    on_trial=on_trial if progress else None,
                    check_budget=check_budget,
                )
            return _run_pool(problem, spec, study_name, trials, seed, ops, workers, storage_obj, tracker, bar)
    except KeyboardInterrupt:
        raise KeyboardInterrupt(
            f"interrupted; continue with --resume --storage {spec.shown} --study {study_name}"
        ) from None


def _run_pool(problem, spec, study_name, trials, seed, ops, workers, storage_obj, tracker, bar) -> list[str]:
    from optuna.trial import TrialState

    ctx = multiprocessing.get_context("spawn")
    notes_queue = ctx.SimpleQueue()
    args = (problem, spec.url, study_name, trials, seed, ops.to_dict())  # one seed: streams differ by process
    procs = [
        ctx.Process(target=_worker_entry, args=(args, notes_queue, os.getpid()), daemon=False) for _ in range(workers)
    ]
    for p in procs:
        p.start()
    import optuna

    study = optuna.load_study(study_name=study_name, storage=storage_obj)
    seen = 0
    notes: list[str] = []
    try:
        while any(p.is_alive() for p in procs):
            time.sleep(0.25)
            while not notes_queue.empty():  # read as they come: a full pipe would block a finishing worker
                notes += notes_queue.get()
            done = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
            for t in done[seen:]:
                if all(v <= 0 for v in t.constraints.values()):
                    tracker.add(t.values)
            seen = len(done)
            bar.update(len(done), tracker)
    except KeyboardInterrupt:  # Ctrl-C reaches the whole process group; SIGTERM (`kill PID`) only this process
        # stop the pool: workers that did not get the signal themselves get SIGINT and end their trial as after
        # Ctrl-C; one still running after 10 s is terminated (else the exit would wait for the whole study)
        for p in procs:
            p.join(timeout=2)  # after Ctrl-C at a terminal they stop by themselves
        for p in procs:
            if p.is_alive() and p.pid is not None:
                with contextlib.suppress(OSError):
                    os.kill(p.pid, signal.SIGINT)
        for p in procs:
            p.join(timeout=10)
            if p.is_alive():
                p.terminate()
                p.join(timeout=5)
        raise
    for p in procs:
        p.join()
    bad = [p.exitcode for p in procs if p.exitcode not in (0, None)]
    if bad:
        raise StorageError(
            f"{len(bad)} worker process(es) failed (exit codes {bad}); check the storage, then continue with --resume"
        )
    while not notes_queue.empty():
        notes += notes_queue.get()
    return notes
