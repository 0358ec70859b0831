"""Multi-objective exploration with optuna (NSGA-II), docs/model.md#solvers, docs/commands.md.

``explore(problem, trials=N)`` runs a two-objective optuna study (minimise
turning effort F_turn [N] and threshold force P [N], Eq. 9 and Eq. 4A)
subject to the shimmy constraint V_c >= (1 + margin) V_target (Eq. 7) and the
optional swept-radius limit, both passed to optuna with
``trial.set_constraint`` (g <= 0 feasible).  Every trial is evaluated by
:func:`designer.solvers.nlp.evaluate_many`, i.e. by the one model
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

Budget
    A study ends with exactly N COMPLETE trials, whatever the number of
    workers: a trial runs only if fewer than N waiting, running or complete
    trials precede it (by trial number); a surplus trial started in a race at
    the end is marked PRUNED with user attribute ``explore_surplus`` and never
    evaluated.  ``resume=True`` first fails the stale RUNNING trials of an
    interrupted run and re-enqueues the parameters of every failed trial once
    (user attribute ``explore_retry_of``), then continues to N.

Hybrid refinement (``refine=True``)
    every point of every per-category front is polished by the exact CasADi
    NLP of its category: minimise F_turn subject to P <= P_candidate
    (ε-constraint), so the categorical search plus the exact continuous
    answer gives an exact front per category.
Package layout
    ``_storage`` (storage URLs, opening a storage, journal repair, atomic writes),
    ``_operators`` (NSGA-II operators, the search space, the NLP refinement),
    ``_runner`` (:func:`explore`: arguments, create or resume the study, collect the fronts),
    ``_workers`` (the optuna objective and its budget, one worker, the process pool),
    ``_progress`` (the live front, its hypervolume and the progress bar),
    ``_result`` (:class:`ExploreResult` and the comparison with the exact front).
    The public names are re-exported here: ``from designer.studies.explore import explore``.
"""

from __future__ import annotations

from designer.errors import StorageError
from designer.studies.explore._operators import (
    Operators,
    SearchSpace,
    category_label,
    category_problem,
    search_space,
)
from designer.studies.explore._result import (
    CATEGORICAL,
    CSV_COLUMNS,
    ExploreResult,
    compare_fronts,
    versions,
)
from designer.studies.explore._runner import ATTR_PREFIX, MAX_TRIALS, MAX_WORKERS, RETRY_ATTR, SURPLUS_ATTR, explore
from designer.studies.explore._storage import (
    GRACE_SECONDS,
    HEARTBEAT_SECONDS,
    RDB_SCHEMES,
    StorageSpec,
    open_storage,
    parse_storage,
)

__all__ = [
    "ATTR_PREFIX",
    "CATEGORICAL",
    "CSV_COLUMNS",
    "ExploreResult",
    "GRACE_SECONDS",
    "HEARTBEAT_SECONDS",
    "MAX_TRIALS",
    "MAX_WORKERS",
    "Operators",
    "RDB_SCHEMES",
    "RETRY_ATTR",
    "SURPLUS_ATTR",
    "SearchSpace",
    "StorageError",
    "StorageSpec",
    "category_label",
    "category_problem",
    "compare_fronts",
    "explore",
    "open_storage",
    "parse_storage",
    "search_space",
    "versions",
]
