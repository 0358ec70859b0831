"""The processes that run trials: the optuna objective and its budget (:class:`_Evaluator`), one worker
(:func:`_run_worker`), the pool of worker processes (:func:`_run_pool`), and :func:`_run_study`, which runs
the study in this process or on the pool.  :func:`designer.studies.explore._runner.explore` calls it.
"""

from __future__ import annotations

import math
import sys
import time
import warnings

import numpy as np

from designer.errors import StorageError
from designer.model import VARIABLES
from designer.problem import Problem
from designer.solvers.nlp import evaluate_many
from designer.studies.explore._operators import Operators, SearchSpace, category_problem, search_space
from designer.studies.explore._storage import StorageSpec, _one_line, open_storage, parse_storage

SURPLUS_ATTR = "explore_surplus"
"""User attribute of a trial pruned because the budget was reached by other workers (never evaluated)."""


class _Evaluator:
    """The optuna objective: suggest, evaluate with the one model, set constraints."""

    def __init__(self, problem: Problem, space: SearchSpace, budget: int, shared: bool = True):
        self.shared = shared  # several workers: check the budget by trial number (single: the callback stops)
        self.problem = problem
        self.space = space
        self.budget = budget
        self.problems = {cat: category_problem(problem, cat) for cat in space.categories()}
        self.on_trial = None

    def design_array(self, category: tuple, params: dict) -> np.ndarray:
        """(T, d, B, c_f) [SI] of a trial: suggested values, else the category's fixed bound."""
        sub = self.problems[category]
        return np.array([params.get(name, sub.bounds[name].low) for name in VARIABLES], float)

    def __call__(self, trial):
        # late import: loads optuna only when this runs
        import optuna

        # late import: loads optuna only when this runs
        from optuna.trial import TrialState

        study = trial.study
        ahead = (
            0
            if not self.shared
            else sum(
                1
                for t in study.get_trials(
                    deepcopy=False, states=(TrialState.WAITING, TrialState.RUNNING, TrialState.COMPLETE)
                )
                if t.number < trial.number
            )
        )
        if ahead >= self.budget:
            trial.set_user_attr(SURPLUS_ATTR, True)
            study.stop()
            raise optuna.TrialPruned("budget reached by other workers")
        category = tuple(
            (name, trial.suggest_categorical(name, list(choices))) for name, choices in self.space.categorical
        )
        params = {name: trial.suggest_float(name, lo, hi) for name, lo, hi in self.space.continuous}
        sub = self.problems[category]
        values = evaluate_many(sub, self.design_array(category, params)[None, :])
        f_turn = float(values["turning_effort"][0])
        p = float(values["threshold_force"][0])
        v_c = float(values["critical_speed"][0])
        shimmy = 1.0 - v_c / sub.required_speed if math.isfinite(v_c) else 1.0
        trial.set_constraint("shimmy", shimmy)
        if sub.swept_radius_max is not None:
            trial.set_constraint("swept_radius", float(values["swept_radius"][0]) / sub.swept_radius_max - 1.0)
        return (f_turn if math.isfinite(f_turn) else 1e12), (p if math.isfinite(p) else 1e12)


def _counts(study) -> dict:
    # late import: loads optuna only when this runs
    from optuna.trial import TrialState

    out = {s: 0 for s in TrialState}
    for t in study.get_trials(deepcopy=False):
        out[t.state] += 1
    return out


def _stopper(budget: int, evaluator: _Evaluator):
    # late import: loads optuna only when this runs
    from optuna.trial import TrialState

    def callback(study, frozen):
        c = _counts(study)
        if evaluator.on_trial is not None:
            evaluator.on_trial(study, frozen, c)
        if c[TrialState.COMPLETE] + c[TrialState.RUNNING] >= budget:
            study.stop()

    return callback


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
) -> None:
    """Run trials on one study until it holds ``budget`` COMPLETE trials (one process).

    ``check_budget``: other processes may work on the study, so each trial
    checks by its number that fewer than ``budget`` trials precede it.
    """
    # late import: loads optuna only when this runs
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if storage_obj is None:
            storage_obj = open_storage(parse_storage(storage))
        ops = Operators.from_dict(operators)
        study = optuna.load_study(study_name=study_name, storage=storage_obj, sampler=ops.sampler(seed))
        if _counts(study)[optuna.trial.TrialState.COMPLETE] >= budget:
            return
        evaluator = _Evaluator(problem, search_space(problem), budget, shared=check_budget)
        evaluator.on_trial = on_trial
        study.optimize(evaluator, n_trials=None, callbacks=[_stopper(budget, evaluator)], gc_after_trial=False)


def _worker_entry(args) -> None:  # top level: picklable for multiprocessing
    try:
        _run_worker(*args)
    except KeyboardInterrupt:
        pass
    except Exception as exc:  # one line, no traceback: the parent says which workers failed and what to do
        print(f"designer: explore worker: {type(exc).__name__}: {_one_line(exc)}", file=sys.stderr, flush=True)
        sys.exit(1)


def _run_study(
    problem,
    spec: StorageSpec,
    study_name: str,
    trials: int,
    base_seed,
    ops: Operators,
    workers: int,
    storage_obj,
    tracker,
    bar,
    check_budget: bool,
    progress: bool,
) -> None:
    """Run the study to ``trials`` COMPLETE trials: in this process, or on a pool of ``workers`` processes."""
    # late import: loads optuna only when this runs
    from optuna.trial import TrialState

    try:
        with bar:
            if workers == 1:

                def on_trial(study_, frozen, counts):
                    if frozen.state == TrialState.COMPLETE and all(v <= 0 for v in frozen.constraints.values()):
                        tracker.add(frozen.values)
                    bar.update(counts[TrialState.COMPLETE], tracker)

                _run_worker(
                    problem,
                    spec.url,
                    study_name,
                    trials,
                    base_seed,
                    ops.as_dict(),
                    storage_obj=storage_obj,
                    on_trial=on_trial if progress else None,
                    check_budget=check_budget,
                )
            else:
                _run_pool(problem, spec, study_name, trials, base_seed, ops, workers, storage_obj, tracker, bar)
    except KeyboardInterrupt:
        raise KeyboardInterrupt(
            f"interrupted; continue with --resume --storage {spec.shown} --study {study_name}"
        ) from None


def _run_pool(problem, spec, study_name, trials, base_seed, ops, workers, storage_obj, tracker, bar):
    # late import: loads multiprocessing only when this runs
    import multiprocessing

    # late import: loads optuna only when this runs
    from optuna.trial import TrialState

    ctx = multiprocessing.get_context("spawn")
    args = [
        (problem, spec.url, study_name, trials, None if base_seed is None else base_seed + i, ops.as_dict())
        for i in range(workers)
    ]
    procs = [ctx.Process(target=_worker_entry, args=(a,), daemon=False) for a in args]
    for p in procs:
        p.start()
    # late import: loads optuna only when this runs
    import optuna

    study = optuna.load_study(study_name=study_name, storage=storage_obj)
    seen = 0
    try:
        while any(p.is_alive() for p in procs):
            time.sleep(0.25)
            done = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
            for t in done[seen:]:
                if all(v <= 0 for v in t.constraints.values()):
                    tracker.add(t.values)
            seen = len(done)
            bar.update(len(done), tracker)
    except KeyboardInterrupt:
        for p in procs:
            p.join(timeout=10)
        raise
    for p in procs:
        p.join()
    bad = [p.exitcode for p in procs if p.exitcode not in (0, None)]
    if bad:
        raise StorageError(
            f"{len(bad)} worker process(es) failed (exit codes {bad}); check the storage, then continue with --resume"
        )
