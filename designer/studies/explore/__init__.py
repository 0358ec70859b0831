"""Multi-objective exploration with optuna (NSGA-II), docs/model.md#solvers, docs/commands.md.

``explore(problem, trials=N)`` runs a two-objective optuna study (minimise
turning effort F_turn [N] and threshold force P [N], Eq. 9 and Eq. 4A)
subject to the problem's shimmy constraint, risk-bounded as everywhere else (V_q >= (1 + margin) V_target:
P(V_c < V_target) <= α, or V_c >= (1 + margin) V_target (Eq. 7) for a nominal problem), and the
optional swept-radius limit, both passed to optuna with
``trial.set_constraint`` (g <= 0 feasible).  Every trial is evaluated by
:func:`designer.model.evaluate`, i.e. by the one model
:func:`designer.model._caster.performance`.

Search space
    the continuous design variables of the problem that are not fixed
    (trail T [m], diameter d [m], groove B [m], damping c_f [N·m/rad]) plus
    the categorical choices the problem declares: a Table 1 catalog wheel
    (``[inertia] model = "catalog"`` or ``[choices] wheel``; it fixes d and
    I_w), ``[choices] surface`` and ``[choices] turning_mode``.

Operators
    optuna's default NSGA-II (uniform crossover, resampling mutation,
    population 50) repeats parameter sets and leaves few distinct points on
    the front of this problem.  The default here ("tuned") is SBX crossover
    (η = 15) always applied, polynomial mutation (η = 20) with probability
    1/n per variable, a population sized to the budget (≈ √N, 20…100)
    and a duplicate filter that redraws a child equal to an earlier trial.
    ``operators="optuna"`` gives optuna's defaults for comparison.

Storage (``storage=``)
    ``None`` / ``"memory"``: in-memory (one process);
    ``"sqlite:///path.db"`` (or a path ending ``.db``/``.sqlite``),
    ``"postgresql://user:password@host:5432/db"``, ``"mysql://…"``: optuna's
    RDBStorage (a client–server database gets a heartbeat, 10 s, grace 60 s, so
    stale trials of a dead worker on another machine are failed and retried);
    ``"journal:///abs/path/study.log"`` (or a path ending ``.log``/``.journal``):
    optuna's JournalStorage with a file backend, the right choice for several
    processes on one machine.

Budget and exactness
    A study ends with exactly N COMPLETE trials, whatever the number of workers and however the machine
    schedules them, and timing never makes a candidate count twice (with the tuned operators, which
    redraw a repeated child, the N candidates are all different): a trial runs only if fewer than N
    waiting, running or complete trials precede it (by trial number); a surplus trial started in a race at the end is
    marked PRUNED with user attribute ``explore_surplus`` and never evaluated.  Every process draws from
    its own random stream (the seed and the number of its first trial, :func:`stream_seed`), so
    processes started with the same command never draw the same candidates.  A worker tells a trial only
    while it is RUNNING: a trial that the heartbeat failed while its process still evaluated it (a process
    starved of CPU or paused past the grace period) keeps its FAIL, its late result is discarded and a
    note says so; the storage retries its candidate (up to 3 times), and a retry runs only if no earlier
    trial of the same candidate (:func:`lineage`) is waiting, running or complete, else it is PRUNED with
    ``explore_duplicate_of``.  On a database with a heartbeat a worker that finds the budget held by
    running trials waits until they complete or are failed as stale, so the workers that survive a
    dead one finish the study.  ``resume=True`` first fails the stale RUNNING trials of an interrupted
    run and queues one retry of each candidate whose every trial failed (user attribute
    ``explore_retry_of``: the candidate's first trial), then continues to N.

Hybrid refinement (``refine=True``)
    every point of every per-category front is polished by the exact CasADi
    NLP of its category: minimise F_turn subject to P <= P_candidate
    (ε-constraint), so the categorical search plus the exact continuous
    answer gives an exact front per category.
Package layout
    ``_storage`` (storage URLs, opening a storage, journal repair, atomic writes),
    ``_operators`` (NSGA-II operators, the search space, the NLP refinement),
    ``_runner`` (:func:`explore`: arguments, create or resume the study, collect the fronts),
    ``_workers`` (the optuna objective, its budget and duplicate checks, the ask-and-tell loop of one
    worker with its heartbeat, the process pool),
    ``_progress`` (the live front, its hypervolume and the progress bar),
    ``_result`` (:class:`ExploreResult` and the comparison with the exact front).
    The public names are re-exported here: ``from designer.studies.explore import explore``.
"""

from __future__ import annotations

from designer.errors import StorageError
from designer.studies.explore._operators import (
    STREAM_STRIDE,
    Operators,
    SearchSpace,
    search_space,
    stream_seed,
)
from designer.studies.explore._result import (
    CSV_COLUMNS,
    ExploreResult,
    FrontComparison,
    compare_fronts,
    versions,
)
from designer.studies.explore._runner import MAX_TRIALS, MAX_WORKERS, explore
from designer.studies.explore._workers import DUPLICATE_ATTR, RETRY_ATTR, SURPLUS_ATTR, WORKER_ATTR, lineage
from designer.studies.explore._storage import (
    redact_url,
    open_storage,
    parse_storage,
    removed_if_failed,
)

__all__ = [
    "CSV_COLUMNS",
    "DUPLICATE_ATTR",
    "ExploreResult",
    "MAX_TRIALS",
    "MAX_WORKERS",
    "Operators",
    "redact_url",
    "removed_if_failed",
    "RETRY_ATTR",
    "STREAM_STRIDE",
    "SURPLUS_ATTR",
    "SearchSpace",
    "StorageError",
    "WORKER_ATTR",
    "compare_fronts",
    "FrontComparison",
    "explore",
    "lineage",
    "open_storage",
    "parse_storage",
    "search_space",
    "stream_seed",
    "versions",
]
