"""The study loop: :func:`explore` checks its arguments, creates or resumes the study (failing and retrying
the trials of an interrupted run), runs it (:mod:`.workers`, with the live front of :mod:`.progress`) and
collects the fronts per category and overall.
"""

from __future__ import annotations

import dataclasses
import time
import warnings

import numpy as np

from designer.boundary import SEED, Count, checked
from designer.errors import DesignerError, InputError, StorageError, os_reason
from designer.studies.front import hypervolume_2d
from designer.problem import Problem, problem_argument
from designer.solvers import one_solve_at_a_time
from designer.studies.explore._operators import (
    Operators,
    _front_mask,
    _params_key,
    _refine,
    _row,
    category_label,
    search_space,
)
from designer.studies.explore._progress import _FrontTracker, _Progress
from designer.studies.explore._result import ExploreResult, _box_reference, _exact_front, compare_fronts
from designer.studies.explore._storage import StorageSpec, _one_line, open_storage, parse_storage, scrub
from designer.studies.explore._workers import RETRY_ATTR, _counts, _Evaluator, _run_study, lineage

ATTR_PREFIX = "designer:"

MAX_TRIALS = 1_000_000
"""Largest --trials: an optuna study keeps every trial in memory (about 2 kB each)."""
MAX_WORKERS = 256
"""Largest --workers (processes on this machine)."""

MAX_POPULATION = 10_000
"""Largest NSGA-II population (a generation; ``trials`` bounds the study), as ``designer explore --population``."""


def _prepare_resume(study, spec: StorageSpec, search_space_names, trials: int) -> list[str]:
    """Fail stale RUNNING trials and queue one retry of each candidate whose every trial failed; returns notes.

    A candidate (a :func:`lineage`: a trial and its retries) with a waiting, running or complete trial
    needs nothing; one whose trials all failed after its parameters were drawn gets one retry (user
    attribute ``explore_retry_of``: the candidate's first trial), as many as the budget still lacks.  A
    retry queued twice in a race (two processes resuming at once) is evaluated once
    (:meth:`_Evaluator.skip`).
    """
    import optuna

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
    candidates: dict[int, list] = {}
    for t in study.get_trials(deepcopy=False):
        candidates.setdefault(lineage(t), []).append(t)
    live = (TrialState.WAITING, TrialState.RUNNING, TrialState.COMPLETE)
    lacking = trials - sum(t.state in live for chain in candidates.values() for t in chain)
    names = set(search_space_names)
    for root, chain in sorted(candidates.items()):
        if lacking <= 0:
            break
        if any(t.state in live for t in chain):
            continue
        failed = [t for t in chain if t.state == TrialState.FAIL and set(t.params) >= names]
        if not failed:  # pruned, or killed before its parameters were drawn: no candidate to retry
            continue
        study.enqueue_trial(failed[-1].params, user_attrs={RETRY_ATTR: root}, skip_if_exists=False)
        notes.append(f"retrying trial {failed[-1].number}")
        lacking -= 1
    return notes


# long only by its docstring, which documents every option; the body is about 75 lines
@checked(
    trials=Count(1, MAX_TRIALS, what="trials"),
    seed=SEED,
    workers=Count(1, MAX_WORKERS, what="worker processes"),
    population_size=Count(2, MAX_POPULATION, optional=True, what="NSGA-II's population"),
)
@one_solve_at_a_time
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
        Sampler seed; a run alone on its study (a fresh single-worker run, or a
        resume) is repeatable.  Each process draws from its own stream, chosen by
        the number of the first trial it runs (:func:`stream_seed`), so workers and
        processes that join the study never share draws, and a resume does not
        replay the first run's.
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
        Compare with the exact front of :func:`designer.studies.front._pareto.pareto_front` (HV and IGD+).
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
    import optuna

    from optuna.trial import TrialState

    problem = problem_argument(problem)
    spec = parse_storage(storage)
    if workers > 1 and not spec.shared:  # the counts' ranges: ``checked`` above
        raise InputError(
            f"--workers {workers}: several processes need a shared storage; add --storage "
            f"journal:///path/study.log (one machine) or sqlite:///study.db / postgresql://…"
        )
    if resume and not spec.shared:
        raise InputError("--resume: an in-memory study cannot be resumed; use --storage journal:///path/study.log")
    space = search_space(problem)
    if not space.continuous and not space.categorical:
        raise InputError(f"{problem.name}: every variable is fixed; nothing to explore")
    study_name = study_name or f"{problem.name}-explore"
    if isinstance(operators, str):  # a named set sized to the budget, or the given ones (population overridden)
        ops = Operators.for_budget(trials, operators, population_size)
    else:
        ops = dataclasses.replace(operators, population_size=population_size or operators.population_size)

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    exact = _exact_front(problem) if compare else None
    reference = exact["reference_point"] if exact and "reference_point" in exact else _box_reference(problem)

    storage_obj = open_storage(spec, break_lock=resume)
    notes: list[str] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if resume:  # its stored operators, stale trials failed and retried, the notes saying so
            try:  # the study to resume and its operators (as first run); InputError if missing or of another problem
                study = optuna.load_study(study_name=study_name, storage=storage_obj)
            except KeyError:
                raise InputError(f"--resume: no study {study_name!r} in {spec.shown}") from None
            except Exception as exc:  # noqa: BLE001
                raise StorageError(
                    f"storage {spec.shown}: {type(exc).__name__}: {scrub(_one_line(exc), spec.url)}"
                ) from None
            attrs = study.user_attrs
            if attrs.get(ATTR_PREFIX + "problem_digest") not in (None, problem.digest()):
                raise InputError(
                    f"--resume: study {study_name!r} was run on a different problem "
                    f"({attrs.get(ATTR_PREFIX + 'problem_name')!r}); use another --study"
                )
            if ATTR_PREFIX + "operators" in attrs:
                ops = Operators.from_dict(attrs[ATTR_PREFIX + "operators"])
            notes += _prepare_resume(study, spec, space.names, trials)
        else:  # a new two-objective study, labelled with the problem, budget, seed, operators and space
            try:
                study = optuna.create_study(
                    study_name=study_name, storage=storage_obj, directions=["minimize", "minimize"]
                )
            except optuna.exceptions.DuplicatedStudyError:
                raise InputError(
                    f"--study {study_name}: a study of that name already exists in {spec.shown}; "
                    f"add --resume to continue it or choose another --study"
                ) from None
            except Exception as exc:  # noqa: BLE001
                raise StorageError(
                    f"storage {spec.shown}: {type(exc).__name__}: {scrub(_one_line(exc), spec.url)}"
                ) from None
            for key, value in (
                ("problem_name", problem.name),
                ("problem_digest", problem.digest()),
                ("trials", trials),
                ("seed", seed),
                ("operators", ops.to_dict()),
                ("space", space.to_dict()),
            ):
                study.set_user_attr(ATTR_PREFIX + key, value)

    complete_before = _counts(study)[TrialState.COMPLETE]
    tracker = _FrontTracker(reference)
    bar = _Progress(trials, enabled=progress, initial=complete_before)
    t0 = time.perf_counter()
    try:
        notes += _run_study(
            problem,
            spec,
            study_name,
            trials,
            seed,
            ops,
            workers,
            storage_obj,
            tracker,
            bar,
            check_budget=spec.remote or resume,
            progress=progress,
        )
    except Exception as exc:
        raise _storage_failure(exc, spec) from None
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


def _storage_failure(exc: Exception, spec: StorageSpec) -> Exception:
    """A failure while trials are stored, as the storage's one line (exit 6): a full disk under the SQLite file
    or the journal ("database or disk is full", ENOSPC), a lost database, a journal file named as standard output
    that cannot take more; the tool's own errors and anything else (a bug) pass as they are."""
    if isinstance(exc, DesignerError):
        return exc
    chain: list[BaseException] = []  # optuna wraps the database's error (StorageInternalError from OperationalError)
    link: BaseException | None = exc
    while link is not None and link not in chain:
        chain.append(link)
        link = link.__cause__ or link.__context__
    for cause in reversed(chain):  # the innermost cause says why
        if isinstance(cause, OSError) and cause.errno is not None and spec.kind == "journal":
            return StorageError(f"storage {spec.shown}: cannot write the journal ({os_reason(cause)})")
        if type(cause).__module__.split(".")[0] in ("sqlalchemy", "sqlite3"):
            line = scrub(_one_line(cause), spec.url)
            if "disk is full" in line or "disk I/O error" in line:
                line = f"no space left on device ({line})"
            return StorageError(f"storage {spec.shown}: {type(cause).__name__}: {line}")
    return exc


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
        values = sub.evaluate(x)
        ok = values.feasible & np.isfinite(values.turning_effort) & np.isfinite(values.threshold_force)
        feasible_total += int(ok.sum())
        if not ok.any():
            category_fronts[category_label(cat)] = []
            continue
        objs = np.column_stack([values.turning_effort, values.threshold_force])
        idx = np.flatnonzero(ok)[_front_mask(objs[ok])]
        front = [_row(cat, rows[i].number, x[i], values.row(i), False) for i in idx]
        if refine:
            front = _refine(sub, cat, front, nlps)
        front.sort(key=lambda r: r["threshold_force"])
        category_fronts[category_label(cat)] = front
        all_rows += front
    objs = np.array([[r["turning_effort"], r["threshold_force"]] for r in all_rows], float).reshape(-1, 2)
    overall = sorted((all_rows[i] for i in np.flatnonzero(_front_mask(objs))), key=lambda r: r["threshold_force"])
    objs = np.array([[r["turning_effort"], r["threshold_force"]] for r in overall], float).reshape(-1, 2)
    comparison = {}
    if exact is not None and "points" in exact:
        comparison = compare_fronts(objs, exact["points"], exact["reference_point"]).to_dict()
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
