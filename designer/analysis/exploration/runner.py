"""The study loop: the optuna objective, the budget, resume, the process pool, the progress bar, and
:func:`explore`, which runs them and collects the fronts.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings

import numpy as np

from designer.errors import InputError, StorageError
from designer.analysis.indicators import hypervolume_2d
from designer.model import VARIABLES
from designer.problem import Problem
from designer.solvers.nlp import evaluate_many, violation
from designer.analysis.exploration.operators import (
    Operators,
    SearchSpace,
    _front_mask,
    _params_key,
    _refine,
    _row,
    category_label,
    category_problem,
    search_space,
)
from designer.analysis.exploration.result import ExploreResult, _box_reference, _exact_front, compare_fronts
from designer.analysis.exploration.storage import StorageSpec, _one_line, open_storage, parse_storage


SURPLUS_ATTR = "explore_surplus"
RETRY_ATTR = "explore_retry_of"
ATTR_PREFIX = "designer:"

MAX_TRIALS = 1_000_000
"""Largest --trials: an optuna study keeps every trial in memory (about 2 kB each)."""
MAX_WORKERS = 256
"""Largest --workers (processes on this machine)."""


# --------------------------------------------------------------------------- the study


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


def _prepare_resume(study, spec: StorageSpec, search_space_names) -> list[str]:
    """Fail stale RUNNING trials and re-enqueue failed ones once; returns notes."""
    # late import: loads optuna only when this runs
    import optuna

    # late import: loads optuna only when this runs
    from optuna.trial import TrialState

    notes = []
    storage = study._storage
    if spec.remote:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            optuna.storages.fail_stale_trials(study)
    else:  # a file storage: nobody else works on the study while it is resumed
        stale = study.get_trials(deepcopy=False, states=(TrialState.RUNNING,))
        for t in stale:
            storage.set_trial_state_values(t._trial_id, TrialState.FAIL)
        if stale:
            notes.append(f"failed {len(stale)} stale running trial(s): {[t.number for t in stale]}")
    trials = study.get_trials(deepcopy=False)
    retried = {t.user_attrs.get(RETRY_ATTR) for t in trials} | {t.system_attrs.get("failed_trial") for t in trials}
    names = set(search_space_names)
    for t in trials:
        if t.state != TrialState.FAIL or t.number in retried or t.user_attrs.get(SURPLUS_ATTR):
            continue
        if set(t.params) >= names:  # killed after its parameters were drawn: evaluate the same candidate
            study.enqueue_trial(t.params, user_attrs={RETRY_ATTR: t.number}, skip_if_exists=False)
            notes.append(f"retrying trial {t.number}")
    return notes


# long only by its docstring, which documents every option; the body is about 45 lines
def explore(
    problem: Problem,
    trials: int = 500,
    seed: int | None = 0,
    storage: str | None = None,
    study_name: str | None = None,
    workers: int = 1,
    resume: bool = False,
    refine: bool = False,
    operators: str | Operators = "tuned",
    population_size: int | None = None,
    compare: bool = True,
    progress: bool = False,
) -> ExploreResult:
    """Explore the (F_turn, P) trade-off of ``problem`` with optuna's NSGA-II.

    Parameters
    ----------
    problem : Problem
        Any problem; catalog wheels and ``[choices]`` become categorical dimensions.
    trials : int
        The study ends with exactly this many COMPLETE trials.
    seed : int or None
        Sampler seed; a single-worker run with a seed is repeatable.  Worker i
        uses ``seed + i``; a resumed run adds the number of trials already in
        the study, so it does not replay the first run's random draws.
    storage : str or None
        Storage URL (module docstring); None = in-memory.
    study_name : str or None
        Default ``"<problem name>-explore"``.
    workers : int
        Processes working on the study (K > 1 needs a shared storage).
    resume : bool
        Continue an existing study (fail/retry stale trials, then run to ``trials``).
    refine : bool
        Polish each front point with the exact NLP (ε-constraint at its P).
    operators : "tuned" | "optuna" | Operators
        NSGA-II configuration (module docstring).
    population_size : int, optional
        Override the population size of the chosen operators.
    compare : bool
        Compare with the exact front of :func:`designer.analysis.pareto.pareto_front` (HV and IGD+).
    progress : bool
        Show a progress bar on stderr (front size and hypervolume).

    Returns
    -------
    ExploreResult

    Raises
    ------
    InputError
        Bad arguments (exit 2); StorageError for a bad or unreachable storage (exit 6).
    """
    # late import: loads optuna only when this runs
    import optuna

    # late import: loads optuna only when this runs
    from optuna.trial import TrialState

    spec = parse_storage(storage)
    _check_arguments(trials, workers, resume, spec)
    space = search_space(problem)
    if not space.continuous and not space.categorical:
        raise InputError(f"{problem.name}: every variable is fixed; nothing to explore")
    study_name = study_name or f"{problem.name}-explore"
    if isinstance(operators, str):
        ops = Operators.for_budget(trials, operators, population_size)
    else:
        ops = dataclasses.replace(operators, population_size=population_size or operators.population_size)

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    notes: list[str] = []
    exact = _exact_front(problem) if compare else None
    reference = exact["reference_point"] if exact and "reference_point" in exact else _box_reference(problem)

    storage_obj = open_storage(spec, break_lock=resume)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if resume:
            study, ops = _load_for_resume(problem, study_name, spec, storage_obj, ops)
            notes += _prepare_resume(study, spec, space.names)
        else:
            study = _create(problem, study_name, spec, storage_obj, trials, seed, ops, space)

    existing = len(study.get_trials(deepcopy=False))
    base_seed = None if seed is None else seed + (existing if resume else 0)
    complete_before = _counts(study)[TrialState.COMPLETE]
    tracker = _FrontTracker(reference)
    bar = _Progress(trials, enabled=progress, initial=complete_before)
    t0 = time.perf_counter()
    _run_study(
        problem,
        spec,
        study_name,
        trials,
        base_seed,
        ops,
        workers,
        storage_obj,
        tracker,
        bar,
        check_budget=spec.remote or resume,
        progress=progress,
    )
    seconds = time.perf_counter() - t0
    complete = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
    if len(complete) < trials:
        running = len(study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)))
        notes.append(
            f"{len(complete)} of {trials} trials complete ({running} still running elsewhere); run again with --resume"
        )
    result = _collect(problem, space, study, complete, ops, refine, exact, reference)
    result.update(
        study_name=study_name,
        storage=spec.shown,
        seed=seed,
        trials=len(complete),
        seconds=seconds,
        trials_run=len(complete) - complete_before,
        workers=workers,
        warnings=notes,
    )
    return ExploreResult(problem=problem, **result)


def _check_arguments(trials, workers, resume: bool, spec: StorageSpec) -> None:
    """InputError for a budget or worker count out of range, or workers/resume without a shared storage."""
    if isinstance(trials, bool) or not isinstance(trials, int) or not 1 <= trials <= MAX_TRIALS:
        raise InputError(f"--trials {trials!r}: must be a whole number from 1 to {MAX_TRIALS}")
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= MAX_WORKERS:
        raise InputError(f"--workers {workers!r}: must be a whole number from 1 to {MAX_WORKERS}")
    if workers > 1 and not spec.shared:
        raise InputError(
            f"--workers {workers}: several processes need a shared storage; add --storage "
            f"journal:///path/study.log (one machine) or sqlite:///study.db / postgresql://…"
        )
    if resume and not spec.shared:
        raise InputError("--resume: an in-memory study cannot be resumed; use --storage journal:///path/study.log")


def _load_for_resume(problem: Problem, study_name: str, spec: StorageSpec, storage_obj, ops: Operators):
    """The study to resume and its operators (as first run); InputError if it is missing or of another problem."""
    # late import: loads optuna only when this runs
    import optuna

    try:
        study = optuna.load_study(study_name=study_name, storage=storage_obj)
    except KeyError:
        raise InputError(f"--resume: no study {study_name!r} in {spec.shown}") from None
    except Exception as exc:  # noqa: BLE001
        raise StorageError(f"storage {spec.shown}: {type(exc).__name__}: {_one_line(exc)}") from None
    attrs = study.user_attrs
    if attrs.get(ATTR_PREFIX + "problem_digest") not in (None, problem.digest()):
        raise InputError(
            f"--resume: study {study_name!r} was run on a different problem "
            f"({attrs.get(ATTR_PREFIX + 'problem_name')!r}); use another --study"
        )
    if ATTR_PREFIX + "operators" in attrs:
        ops = Operators.from_dict(attrs[ATTR_PREFIX + "operators"])
    return study, ops


def _create(
    problem: Problem,
    study_name: str,
    spec: StorageSpec,
    storage_obj,
    trials: int,
    seed: int | None,
    ops: Operators,
    space: SearchSpace,
):
    """A new two-objective study, labelled with the problem, budget, seed, operators and space."""
    # late import: loads optuna only when this runs
    import optuna

    try:
        study = optuna.create_study(
            study_name=study_name, storage=storage_obj, directions=["minimize", "minimize"], load_if_exists=False
        )
    except optuna.exceptions.DuplicatedStudyError:
        raise InputError(
            f"--study {study_name}: a study of that name already exists in {spec.shown}; "
            f"add --resume to continue it or choose another --study"
        ) from None
    except Exception as exc:  # noqa: BLE001
        raise StorageError(f"storage {spec.shown}: {type(exc).__name__}: {_one_line(exc)}") from None
    for key, value in (
        ("problem_name", problem.name),
        ("problem_digest", problem.digest()),
        ("trials", trials),
        ("seed", seed),
        ("operators", ops.as_dict()),
        ("space", space.as_dict()),
    ):
        study.set_user_attr(ATTR_PREFIX + key, value)
    return study


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


class _FrontTracker:
    """Incremental non-dominated set of feasible (F_turn, P) points and its hypervolume."""

    def __init__(self, reference):
        self.reference = np.asarray(reference, float)
        self.points = np.empty((0, 2))

    def add(self, values) -> None:
        p = np.asarray(values, float)
        if len(self.points) and np.any(np.all(self.points <= p, axis=1)):
            return
        keep = ~np.all(p <= self.points, axis=1)
        self.points = np.vstack([self.points[keep], p])

    @property
    def hypervolume(self) -> float:
        return hypervolume_2d(self.points, self.reference)


class _Progress:
    def __init__(self, total: int, enabled: bool, initial: int = 0):
        self.enabled = enabled
        self.total = total
        self.initial = initial
        self._last = 0.0

    def __enter__(self):
        if self.enabled:
            # late import: loads rich only when this runs
            from rich.console import Console

            # late import: loads rich only when this runs
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self.progress = Progress(
                TextColumn("explore"),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("front {task.fields[front]:>3}  HV {task.fields[hv]:.5g} N²"),
                TimeElapsedColumn(),
                TimeRemainingColumn(),
                console=Console(stderr=True),
                transient=False,
            )
            self.progress.__enter__()
            self.task = self.progress.add_task("explore", total=self.total, completed=self.initial, front=0, hv=0.0)
        return self

    def update(self, complete: int, tracker: _FrontTracker) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last < 0.1 and complete < self.total:
            return
        self._last = now
        self.progress.update(self.task, completed=complete, front=len(tracker.points), hv=tracker.hypervolume)

    def __exit__(self, *exc):
        if self.enabled:
            self.progress.__exit__(*exc)
        return False


def _collect(problem, space, study, complete, ops, refine, exact, reference) -> dict:
    """Evaluate the COMPLETE trials by category (one model), fronts per category and overall."""
    evaluator = _Evaluator(problem, space, 0)
    by_cat: dict[tuple, list] = {}
    distinct = {_params_key(t.params) for t in complete}
    for t in complete:
        cat = tuple((name, t.params[name]) for name, _ in space.categorical)
        by_cat.setdefault(cat, []).append(t)
    category_fronts = {}
    all_rows = []
    feasible_total = 0
    nlps = {}
    for cat in space.categories():
        rows = by_cat.get(cat, [])
        if not rows:
            continue
        sub = evaluator.problems[cat]
        x = np.array([evaluator.design_array(cat, t.params) for t in rows])
        values = evaluate_many(sub, x)
        ok = (
            (violation(sub, values) <= 0)
            & np.isfinite(values["turning_effort"])
            & np.isfinite(values["threshold_force"])
        )
        feasible_total += int(ok.sum())
        if not ok.any():
            category_fronts[category_label(cat)] = []
            continue
        objs = np.column_stack([values["turning_effort"], values["threshold_force"]])
        idx = np.flatnonzero(ok)[_front_mask(objs[ok])]
        front = [_row(cat, rows[i].number, x[i], {k: v[i] for k, v in values.items()}, False) for i in idx]
        if refine:
            front = _refine(sub, cat, front, nlps)
        front.sort(key=lambda r: r["threshold_force"])
        category_fronts[category_label(cat)] = front
        all_rows += front
    overall = []
    if all_rows:
        objs = np.array([[r["turning_effort"], r["threshold_force"]] for r in all_rows])
        overall = sorted((all_rows[i] for i in np.flatnonzero(_front_mask(objs))), key=lambda r: r["threshold_force"])
    objs = np.array([[r["turning_effort"], r["threshold_force"]] for r in overall], float).reshape(-1, 2)
    comparison = {}
    if exact is not None and "points" in exact:
        comparison = compare_fronts(objs, exact["points"], exact["reference_point"])
    elif exact is not None:
        comparison = {"note": exact["note"]}
    return dict(
        front=overall,
        category_fronts=category_fronts,
        distinct=len(distinct),
        feasible=feasible_total,
        hypervolume=hypervolume_2d(objs, reference) if len(objs) else 0.0,
        reference_point=tuple(float(v) for v in reference),
        comparison=comparison,
        operators=ops,
        refined=refine,
    )
