"""Multi-objective exploration with optuna (NSGA-II), docs/model.md#solvers, docs/commands.md.

``explore(problem, trials=N)`` runs a two-objective optuna study (minimise
turning effort F_turn [N] and threshold force P [N], Eq. 9 and Eq. 4A)
subject to the shimmy constraint V_c >= (1 + margin) V_target (Eq. 7) and the
optional swept-radius limit, both passed to optuna with
``trial.set_constraint`` (g <= 0 feasible).  Every trial is evaluated by
:func:`designer.solvers.nlp.evaluate_many`, i.e. by the one model
:func:`designer.model.performance`.

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
"""
from __future__ import annotations

import contextlib
import dataclasses
import itertools
import json
import math
import os
import platform
import re
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import designer
from designer.jsonsafe import finite
from designer.errors import InputError, StorageError
from designer.analysis.indicators import hypervolume_2d, igd_plus, nondominated, normalise
from designer.model import VARIABLES, Design
from designer.problem import Bound, Problem
from designer.solvers.nlp import evaluate_many, violation
from designer.physics.inertia import Catalog
import importlib.util
import casadi
from designer.solvers.nlp import BIG, CasterNLP

CATEGORICAL = ("wheel", "surface", "turning_mode")
"""Categorical dimensions, in this order in category labels and CSV columns."""

SURPLUS_ATTR = "explore_surplus"
RETRY_ATTR = "explore_retry_of"
ATTR_PREFIX = "designer:"

CSV_COLUMNS = ("trail", "diameter", "groove", "damping", "turning_effort", "threshold_force", "critical_speed")
"""SI columns of explore.csv: T [m], d [m], B [m], c_f [N·m/rad], F_turn [N], P [N], V_c [m/s]."""


# --------------------------------------------------------------------------- operators


@dataclass(frozen=True)
class Operators:
    """NSGA-II configuration.

    Attributes
    ----------
    name : "tuned" (SBX + polynomial mutation + duplicate filter) or "optuna" (library defaults)
    population_size : individuals per generation
    crossover : "sbx" or "uniform"
    crossover_eta : SBX distribution index η_c [-] (larger: children nearer the parents)
    crossover_prob : probability that a child is made by crossover [-]
    mutation : "polynomial" or "random" (optuna's resampling)
    mutation_eta : polynomial-mutation distribution index η_m [-]
    mutation_prob : per-variable mutation probability [-]; None: 1/n
    deduplicate : redraw a child whose parameters equal an earlier trial's
    """

    name: str = "tuned"
    population_size: int = 50
    crossover: str = "sbx"
    crossover_eta: float = 15.0
    crossover_prob: float = 1.0
    mutation: str = "polynomial"
    mutation_eta: float = 20.0
    mutation_prob: float | None = None
    deduplicate: bool = True

    @classmethod
    def for_budget(cls, trials: int, name: str = "tuned", population_size: int | None = None) -> "Operators":
        """Operators for a budget of ``trials`` trials.

        ``"tuned"``: population ≈ √N clipped to 20…100 (22 and ≈ 22 generations
        at 500 trials, 45 and ≈ 44 generations at 2000): on this problem the
        front lies on the intersection of the shimmy and swept-radius
        constraints, and more generations beat a wider population
        (benchmarks/explore_operators.py).  ``"optuna"``: optuna 5's NSGA-II defaults
        (population 50, uniform crossover with probability 0.9, resampling
        mutation with probability 1/n, no duplicate filter).
        """
        if name == "optuna":
            return cls(name="optuna", population_size=population_size or 50, crossover="uniform",
                       crossover_eta=float("nan"), crossover_prob=0.9, mutation="random",
                       mutation_eta=float("nan"), mutation_prob=None, deduplicate=False)
        if name != "tuned":
            raise InputError(f"operators = {name!r}: expected 'tuned' or 'optuna'")
        pop = population_size or int(min(100, max(20, round(math.sqrt(max(trials, 1))))))
        return cls(population_size=pop)

    def as_dict(self) -> dict:
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                for k, v in dataclasses.asdict(self).items()}

    @classmethod
    def from_dict(cls, data: dict) -> "Operators":
        values = {k: (float("nan") if v is None and k.endswith("_eta") else v) for k, v in data.items()}
        return cls(**values)

    def sampler(self, seed: int | None):
        """The configured :class:`optuna.samplers.NSGAIISampler`."""
        # late import: loads optuna only when this runs
        import optuna
        # late import: loads optuna only when this runs
        from optuna.samplers.nsgaii import PolynomialMutation, SBXCrossover, UniformCrossover

        crossover = SBXCrossover(eta=self.crossover_eta) if self.crossover == "sbx" else UniformCrossover()
        mutation = PolynomialMutation(eta=self.mutation_eta) if self.mutation == "polynomial" else None
        kwargs = dict(population_size=self.population_size, crossover=crossover, crossover_prob=self.crossover_prob,
                      mutation=mutation, mutation_prob=self.mutation_prob, seed=seed)
        if not self.deduplicate:
            return optuna.samplers.NSGAIISampler(**kwargs)
        # late import: loads optuna only when this runs
        from optuna.samplers._lazy_random_state import LazyRandomState
        # late import: loads optuna only when this runs
        from optuna.samplers.nsgaii._child_generation_strategy import NSGAIIChildGenerationStrategy

        rng = LazyRandomState(seed)
        inner = NSGAIIChildGenerationStrategy(crossover_prob=self.crossover_prob, mutation=mutation,
                                              mutation_prob=self.mutation_prob, swapping_prob=0.5,
                                              crossover=crossover, constraints_func=None, rng=rng)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sampler = optuna.samplers.NSGAIISampler(**kwargs, child_generation_strategy=_Deduplicated(inner))
        sampler._rng = rng  # reseed_rng() must reach the strategy's generator
        return sampler


class _Deduplicated:
    """Child generation that redraws (up to 20 times) a child equal to an earlier trial.

    The parameter sets of finished trials are cached, so each child costs
    O(running trials), not O(all trials).
    """

    def __init__(self, inner):
        self.inner = inner
        self._finished: set = set()
        self._scanned = 0

    def _seen(self, study) -> set:
        # late import: loads optuna only when this runs
        from optuna.trial import TrialState

        trials = study.get_trials(deepcopy=False)
        pending = set()
        contiguous = True
        for t in trials[self._scanned:]:
            if t.state.is_finished():
                self._finished.add(_params_key(t.params))
                if contiguous:
                    self._scanned += 1
            else:
                contiguous = False
                if t.state in (TrialState.RUNNING, TrialState.WAITING):
                    pending.add(_params_key(t.params))
        return self._finished | pending if pending else self._finished

    def __call__(self, study, search_space, parent_population):
        seen = self._seen(study)
        child = self.inner(study, search_space, parent_population)
        for _ in range(20):
            if len(child) < len(search_space) or _params_key(child) not in seen:
                break
            child = self.inner(study, search_space, parent_population)
        return child


MAX_TRIALS = 1_000_000
"""Largest --trials: an optuna study keeps every trial in memory (about 2 kB each)."""
MAX_WORKERS = 256
"""Largest --workers (processes on this machine)."""

def _params_key(params: dict) -> tuple:
    return tuple(sorted((k, round(v, 12) if isinstance(v, float) else v) for k, v in params.items()))


# --------------------------------------------------------------------------- search space


@dataclass(frozen=True)
class SearchSpace:
    """The exploration space of a problem.

    Attributes
    ----------
    continuous : ((variable, low, high), ...) [SI] of the free continuous variables
    categorical : ((dimension, choices), ...) for wheel, surface, turning_mode
    """

    continuous: tuple
    categorical: tuple

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.categorical) + tuple(name for name, _, _ in self.continuous)

    def categories(self) -> list[tuple]:
        """Every combination of categorical values, as ((dimension, value), ...) tuples."""
        dims = [[(name, value) for value in choices] for name, choices in self.categorical]
        return [tuple(combo) for combo in itertools.product(*dims)] if dims else [()]

    def as_dict(self) -> dict:
        return {"continuous": {n: [lo, hi] for n, lo, hi in self.continuous},
                "categorical": {n: list(c) for n, c in self.categorical}}


def search_space(problem: Problem) -> SearchSpace:
    """Continuous and categorical dimensions of ``problem`` (see the module docstring)."""
    wheels = tuple(problem.wheels)
    chosen = problem.choices.get("wheel")
    if wheels and chosen:
        wheels = tuple(w for w in wheels if w in chosen)
        if not wheels:
            raise InputError(f"choices.wheel = {list(chosen)}: none of them is in inertia.wheels {list(problem.wheels)}")
    elif chosen:
        wheels = tuple(chosen)
    categorical = []
    if wheels:
        categorical.append(("wheel", wheels))
    for key in ("surface", "turning_mode"):
        if problem.choices.get(key):
            categorical.append((key, tuple(problem.choices[key])))
    continuous = []
    for name in VARIABLES:
        if name == "diameter" and wheels:
            continue
        bound = problem.bounds[name]
        if not bound.fixed:
            continuous.append((name, float(bound.low), float(bound.high)))
    return SearchSpace(tuple(continuous), tuple(categorical))


def category_label(category: tuple) -> str:
    """``"wheel=C, surface=tile"`` (``"all"`` for a problem without categories)."""
    return ", ".join(f"{k}={v}" for k, v in category) or "all"


def category_problem(problem: Problem, category: tuple) -> Problem:
    """The continuous sub-problem of one category (wheel: fixed d and I_w; surface; turning mode)."""

    values = dict(category)
    changes = {k: values[k] for k in ("surface", "turning_mode") if k in values}
    bounds = dict(problem.bounds)
    if "wheel" in values:
        model = Catalog.from_key(values["wheel"])
        d = model.fixed_diameter
        bounds["diameter"] = Bound(d, d)
        changes["inertia"] = model
    return problem.replace(conditions=problem.conditions.replace(**changes), bounds=bounds, wheels=())


# --------------------------------------------------------------------------- storage


@dataclass(frozen=True)
class StorageSpec:
    """A parsed storage URL.

    Attributes
    ----------
    kind : "memory" | "journal" | "rdb"
    url : the URL as optuna takes it (journal: the file path)
    shown : the URL with any password replaced by ``***`` (safe for reports)
    """

    kind: str
    url: str | None
    shown: str

    @property
    def shared(self) -> bool:
        """True when several processes can work on one study."""
        return self.kind != "memory"

    @property
    def remote(self) -> bool:
        """A client–server database (heartbeat decides which RUNNING trials are stale)."""
        return self.kind == "rdb" and not self.url.startswith("sqlite")


RDB_SCHEMES = ("sqlite", "postgresql", "postgres", "mysql", "mariadb", "oracle", "mssql")


def parse_storage(storage: str | None) -> StorageSpec:
    """Parse a storage argument; :class:`StorageError` (exit 6) when it is not one of the forms.

    Forms: ``None``/``"memory"``; ``journal:///abs/path.log`` or any path ending
    ``.log``/``.journal``; ``sqlite:///path.db`` or a path ending ``.db``/``.sqlite``/``.sqlite3``;
    ``postgresql://user:password@host:port/database`` (also ``postgresql+psycopg2://``, ``mysql://``).
    """
    if storage is None or storage.strip() in ("", "memory", ":memory:", "inmemory"):
        return StorageSpec("memory", None, "memory")
    text = storage.strip()
    if text.startswith("journal://"):
        path = text[len("journal://"):]
        if not path:
            raise StorageError(f"storage {text!r}: journal URL without a file path; use journal:///abs/path/study.log")
        return StorageSpec("journal", path, f"journal://{path}")
    match = re.match(r"^([A-Za-z][A-Za-z0-9+.-]*)://", text)
    if match:
        scheme = match.group(1).lower().split("+")[0]
        if scheme not in RDB_SCHEMES:
            raise StorageError(
                f"storage {_redact(text)!r}: unknown scheme {match.group(1)!r}; use sqlite:///file.db, "
                f"postgresql://user:password@host/db or journal:///path/file.log")
        url = "postgresql" + text[len(match.group(1).split("+")[0]):] if scheme == "postgres" else text
        if scheme == "postgres" or match.group(1).lower() == "postgresql":
            url = _postgres_driver(url)
        return StorageSpec("rdb", url, _redact(url))
    lower = text.lower()
    if lower.endswith((".log", ".journal")):
        return StorageSpec("journal", text, f"journal://{text}")
    if lower.endswith((".db", ".sqlite", ".sqlite3")):
        return StorageSpec("rdb", f"sqlite:///{text}", f"sqlite:///{text}")
    raise StorageError(
        f"storage {_redact(text)!r}: not a storage URL; use sqlite:///file.db, postgresql://user:password@host/db, "
        f"journal:///path/file.log (or a path ending .db or .log)")


def _postgres_driver(url: str) -> str:
    """``postgresql://`` with the driver that is installed: SQLAlchemy 2.1 reads it as psycopg (3), but the
    README (and the `test` extra) install psycopg2-binary; an explicit ``postgresql+driver://`` is kept."""

    if importlib.util.find_spec("psycopg") is None and importlib.util.find_spec("psycopg2") is not None:
        return "postgresql+psycopg2://" + url[len("postgresql://"):]
    return url


def _redact(url: str) -> str:
    return re.sub(r"(://[^:/@]+:)[^@]*@", r"\1***@", url)


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    first = next((line.strip() for line in text if line.strip()), type(exc).__name__)
    return (first[:200] + "…") if len(first) > 200 else first


HEARTBEAT_SECONDS = 10
"""A worker on a remote (PostgreSQL/MySQL) study records a heartbeat this often (env DESIGNER_HEARTBEAT_SECONDS)."""
GRACE_SECONDS = 60
"""A RUNNING trial without a heartbeat for this long is failed and retried once (env DESIGNER_GRACE_SECONDS)."""


def _heartbeat() -> tuple[int, int]:
    """Heartbeat interval and grace period [s] of remote studies: the defaults, or the environment's."""
    out = []
    for name, default in (("DESIGNER_HEARTBEAT_SECONDS", HEARTBEAT_SECONDS), ("DESIGNER_GRACE_SECONDS", GRACE_SECONDS)):
        text = os.environ.get(name, str(default))
        try:
            value = int(text)
        except ValueError:
            value = 0
        if not 1 <= value <= 86400:
            raise InputError(f"{name} = {text!r}: expected whole seconds from 1 to 86400")
        out.append(value)
    if out[1] <= out[0]:
        raise InputError(f"DESIGNER_GRACE_SECONDS = {out[1]}: must exceed DESIGNER_HEARTBEAT_SECONDS = {out[0]}")
    return out[0], out[1]


def open_storage(spec: StorageSpec, break_lock: bool = False):
    """Open (and check) an optuna storage; any failure is one :class:`StorageError` line.

    ``break_lock`` (resume of a journal file): remove a lock file left by a
    killed process instead of waiting out its grace period.
    """
    # late import: loads optuna only when this runs
    import optuna

    if spec.kind == "memory":
        return optuna.storages.InMemoryStorage()
    if spec.kind == "journal":
        # late import: loads optuna only when this runs
        from optuna.storages.journal import JournalFileBackend, JournalFileOpenLock, JournalStorage

        path = Path(spec.url)
        if not path.parent.is_dir():
            raise StorageError(f"storage {spec.shown}: folder {path.parent} does not exist")
        if path.is_dir():
            raise StorageError(f"storage {spec.shown}: is a folder, expected a journal file")
        try:
            if break_lock:
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(f"{path}.lock")
            _repair_journal(path)
            backend = JournalFileBackend(str(path), lock_obj=JournalFileOpenLock(str(path), grace_period=10))
            return JournalStorage(backend)
        except Exception as exc:  # noqa: BLE001 - every failure becomes one line
            raise StorageError(f"storage {spec.shown}: cannot open it ({type(exc).__name__}: {_one_line(exc)})") from None
    if spec.url.startswith("sqlite:///"):
        path = Path(spec.url[len("sqlite:///"):])
        if str(path) and not path.parent.is_dir():
            raise StorageError(f"storage {spec.shown}: folder {path.parent} does not exist")
    engine_kwargs = {}
    if spec.remote:
        engine_kwargs = {"connect_args": {"connect_timeout": 10}, "pool_pre_ping": True}
        heartbeat, grace = _heartbeat()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if not spec.remote:  # SQLite: one machine; --resume fails every RUNNING trial, no heartbeat needed
                return optuna.storages.RDBStorage(spec.url)
            return optuna.storages.RDBStorage(
                spec.url, engine_kwargs=engine_kwargs, heartbeat_interval=heartbeat, grace_period=grace,
                failed_trial_callback=optuna.storages.RetryFailedTrialCallback(max_retry=1))
    except ImportError as exc:
        raise StorageError(f"storage {spec.shown}: the database driver is not installed ({_one_line(exc)}); "
                           f"PostgreSQL: pip install psycopg2-binary, MySQL: pip install pymysql") from None
    except Exception as exc:  # noqa: BLE001
        raise StorageError(f"storage {spec.shown}: cannot open it ({type(exc).__name__}: {_one_line(exc)})") from None


def _repair_journal(path: Path) -> None:
    """Drop a partial last line left by a process killed in mid-write (it would corrupt the next append)."""
    if not path.exists() or path.stat().st_size == 0:
        return
    with open(path, "rb+") as f:
        f.seek(-1, os.SEEK_END)
        if f.read(1) == b"\n":
            return
        data = f.seek(0) or f.read()
        f.truncate(data.rfind(b"\n") + 1)


# --------------------------------------------------------------------------- result


@dataclass
class ExploreResult:
    """The outcome of :func:`explore`.

    Attributes
    ----------
    problem : the problem explored
    study_name, storage : optuna study name and storage (password redacted)
    seed : sampler seed (None: not seeded)
    trials : COMPLETE trials in the study
    front : overall front, list of dicts with the CSV columns [SI], categories, ``trial``, ``refined``
    category_fronts : {category label: front (same dict rows)}
    distinct : distinct parameter sets among the COMPLETE trials
    feasible : COMPLETE trials meeting every constraint
    hypervolume : HV of the front [N²] with ``reference_point``
    comparison : explored vs exact (HV, ratio, IGD+, reference, normalisation) or a note
    operators : the NSGA-II configuration
    refined : whether the fronts were polished by the NLP
    seconds : wall time of the study [s] (trials_per_second = trials run / seconds)
    """

    problem: Problem
    study_name: str
    storage: str
    seed: int | None
    trials: int
    front: list
    category_fronts: dict
    distinct: int
    feasible: int
    hypervolume: float
    reference_point: tuple
    comparison: dict
    operators: Operators
    refined: bool
    seconds: float
    trials_run: int
    workers: int
    warnings: list = field(default_factory=list)

    @property
    def trials_per_second(self) -> float:
        return self.trials_run / self.seconds if self.seconds > 0 else float("nan")

    def objectives(self) -> np.ndarray:
        """(n, 2) array of (F_turn, P) [N] of the overall front."""
        return np.array([[r["turning_effort"], r["threshold_force"]] for r in self.front], float).reshape(-1, 2)

    def best_weighted(self, weights=None) -> dict | None:
        """The front point minimising J = w_turn F_turn + w_threshold P [N] (problem weights by default)."""
        w = self.problem.weights if weights is None else weights
        if not self.front:
            return None
        return min(self.front, key=lambda r: w[0] * r["turning_effort"] + w[1] * r["threshold_force"])

    def to_dict(self) -> dict:
        """Plain data for explore.json (SI units)."""
        return {
            "problem": self.problem.name,
            "problem_digest": self.problem.digest(),
            "study": self.study_name,
            "storage": self.storage,
            "seed": self.seed,
            "trials": self.trials,
            "trials_run": self.trials_run,
            "workers": self.workers,
            "seconds": self.seconds,
            "trials_per_second": self.trials_per_second,
            "distinct_parameter_sets": self.distinct,
            "feasible_trials": self.feasible,
            "refined": self.refined,
            "operators": self.operators.as_dict(),
            "units": {"trail": "m", "diameter": "m", "groove": "m", "damping": "N*m/rad", "turning_effort": "N",
                      "threshold_force": "N", "critical_speed": "m/s", "hypervolume": "N^2"},
            "hypervolume": self.hypervolume,
            "reference_point": list(self.reference_point),
            "front": self.front,
            "category_fronts": self.category_fronts,
            "comparison": self.comparison,
            "warnings": self.warnings,
            "versions": versions(),
        }

    def write(self, out_dir) -> tuple[Path, Path]:
        """Write explore.csv (every per-category front point, ``overall_front`` flag) and explore.json.

        Both are written to temporary files in ``out_dir`` and renamed into
        place, so a reader never sees a half-written file.
        """
        out = Path(out_dir)
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"--out {out}: cannot create the folder ({exc.strerror})") from None
        cats = [name for name in CATEGORICAL if any(name in r for rows in self.category_fronts.values() for r in rows)]
        overall = {(r["trial"], r["turning_effort"], r["threshold_force"]) for r in self.front}
        lines = [",".join(CSV_COLUMNS + tuple(cats) + ("overall_front", "refined", "trial"))]
        for rows in self.category_fronts.values():
            for r in rows:
                cells = [f"{r[c]:.10g}" for c in CSV_COLUMNS] + [str(r[c]) for c in cats]
                cells += [str((r["trial"], r["turning_effort"], r["threshold_force"]) in overall).lower(),
                          str(r["refined"]).lower(), str(r["trial"])]
                lines.append(",".join(cells))
        csv_path, json_path = out / "explore.csv", out / "explore.json"
        _atomic_write_many({csv_path: "\n".join(lines) + "\n",
                            json_path: json.dumps(finite(self.to_dict()), indent=2) + "\n"})
        return csv_path, json_path


def _atomic_write_many(files: dict) -> None:
    temps = {}
    try:
        for path, text in files.items():
            fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
            os.chmod(tmp, 0o666 & ~_umask())
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
                f.flush()
                os.fsync(f.fileno())
            temps[path] = tmp
        for path, tmp in temps.items():
            os.replace(tmp, path)
    finally:
        for tmp in temps.values():
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def versions() -> dict:
    """Versions of the designer, Python and the numerical libraries (for reports)."""
    # late import: loads optuna only when this runs
    import optuna

    return {"designer": designer.__version__, "python": platform.python_version(), "optuna": optuna.__version__,
            "numpy": np.__version__, "casadi": casadi.__version__}


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
        ahead = 0 if not self.shared else sum(1 for t in study.get_trials(deepcopy=False, states=(
            TrialState.WAITING, TrialState.RUNNING, TrialState.COMPLETE)) if t.number < trial.number)
        if ahead >= self.budget:
            trial.set_user_attr(SURPLUS_ATTR, True)
            study.stop()
            raise optuna.TrialPruned("budget reached by other workers")
        category = tuple((name, trial.suggest_categorical(name, list(choices))) for name, choices in self.space.categorical)
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


def _run_worker(problem: Problem, storage: str | None, study_name: str, budget: int, seed: int | None,
                operators: dict, storage_obj=None, on_trial=None, check_budget: bool = True) -> None:
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


def explore(problem: Problem, trials: int = 500, seed: int | None = 0, storage: str | None = None,  # noqa: C901 - one branch per option (storage, workers, resume, refine, compare)
            study_name: str | None = None, workers: int = 1, resume: bool = False, refine: bool = False,
            operators: str | Operators = "tuned", population_size: int | None = None, compare: bool = True,
            progress: bool = False) -> ExploreResult:
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

    if isinstance(trials, bool) or not isinstance(trials, int) or not 1 <= trials <= MAX_TRIALS:
        raise InputError(f"--trials {trials!r}: must be a whole number from 1 to {MAX_TRIALS}")
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= MAX_WORKERS:
        raise InputError(f"--workers {workers!r}: must be a whole number from 1 to {MAX_WORKERS}")
    spec = parse_storage(storage)
    if workers > 1 and not spec.shared:
        raise InputError(f"--workers {workers}: several processes need a shared storage; add --storage "
                         f"journal:///path/study.log (one machine) or sqlite:///study.db / postgresql://…")
    if resume and not spec.shared:
        raise InputError("--resume: an in-memory study cannot be resumed; use --storage journal:///path/study.log")
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
            try:
                study = optuna.load_study(study_name=study_name, storage=storage_obj)
            except KeyError:
                raise InputError(f"--resume: no study {study_name!r} in {spec.shown}") from None
            except Exception as exc:  # noqa: BLE001
                raise StorageError(f"storage {spec.shown}: {type(exc).__name__}: {_one_line(exc)}") from None
            attrs = study.user_attrs
            if attrs.get(ATTR_PREFIX + "problem_digest") not in (None, problem.digest()):
                raise InputError(f"--resume: study {study_name!r} was run on a different problem "
                                 f"({attrs.get(ATTR_PREFIX + 'problem_name')!r}); use another --study")
            if ATTR_PREFIX + "operators" in attrs:
                ops = Operators.from_dict(attrs[ATTR_PREFIX + "operators"])
            notes += _prepare_resume(study, spec, space.names)
        else:
            try:
                study = optuna.create_study(study_name=study_name, storage=storage_obj,
                                            directions=["minimize", "minimize"], load_if_exists=False)
            except optuna.exceptions.DuplicatedStudyError:
                raise InputError(f"--study {study_name}: a study of that name already exists in {spec.shown}; "
                                 f"add --resume to continue it or choose another --study") from None
            except Exception as exc:  # noqa: BLE001
                raise StorageError(f"storage {spec.shown}: {type(exc).__name__}: {_one_line(exc)}") from None
            for key, value in (("problem_name", problem.name), ("problem_digest", problem.digest()),
                               ("trials", trials), ("seed", seed), ("operators", ops.as_dict()),
                               ("space", space.as_dict())):
                study.set_user_attr(ATTR_PREFIX + key, value)

    existing = len(study.get_trials(deepcopy=False))
    base_seed = None if seed is None else seed + (existing if resume else 0)
    complete_before = _counts(study)[TrialState.COMPLETE]
    tracker = _FrontTracker(reference)
    bar = _Progress(trials, enabled=progress, initial=complete_before)
    t0 = time.perf_counter()
    try:
        with bar:
            if workers == 1:
                def on_trial(study_, frozen, counts):
                    if frozen.state == TrialState.COMPLETE and all(v <= 0 for v in frozen.constraints.values()):
                        tracker.add(frozen.values)
                    bar.update(counts[TrialState.COMPLETE], tracker)

                _run_worker(problem, spec.url, study_name, trials, base_seed, ops.as_dict(),
                            storage_obj=storage_obj, on_trial=on_trial if progress else None,
                            check_budget=spec.remote or resume)
            else:
                _run_pool(problem, spec, study_name, trials, base_seed, ops, workers, storage_obj, tracker, bar)
    except KeyboardInterrupt:
        raise KeyboardInterrupt(f"interrupted; continue with --resume --storage {spec.shown} --study {study_name}") \
            from None
    seconds = time.perf_counter() - t0
    complete = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
    if len(complete) < trials:
        running = len(study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)))
        notes.append(f"{len(complete)} of {trials} trials complete ({running} still running elsewhere); "
                     f"run again with --resume")
    result = _collect(problem, space, study, complete, ops, refine, exact, reference)
    result.update(study_name=study_name, storage=spec.shown, seed=seed, trials=len(complete), seconds=seconds,
                  trials_run=len(complete) - complete_before, workers=workers, warnings=notes)
    return ExploreResult(problem=problem, **result)


def _run_pool(problem, spec, study_name, trials, base_seed, ops, workers, storage_obj, tracker, bar):
    # late import: loads multiprocessing only when this runs
    import multiprocessing

    # late import: loads optuna only when this runs
    from optuna.trial import TrialState

    ctx = multiprocessing.get_context("spawn")
    args = [(problem, spec.url, study_name, trials, None if base_seed is None else base_seed + i, ops.as_dict())
            for i in range(workers)]
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
        raise StorageError(f"{len(bad)} worker process(es) failed (exit codes {bad}); check the storage, "
                           f"then continue with --resume")


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
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, \
                TimeRemainingColumn

            self.progress = Progress(TextColumn("explore"), BarColumn(), MofNCompleteColumn(),
                                     TextColumn("front {task.fields[front]:>3}  HV {task.fields[hv]:.5g} N²"),
                                     TimeElapsedColumn(), TimeRemainingColumn(), console=Console(stderr=True),
                                     transient=False)
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


# --------------------------------------------------------------------------- fronts


def _box_reference(problem: Problem) -> tuple[float, float]:
    """Fallback HV reference (F_turn, P) [N]: the worst corner of the box (min T, min d, max B, max c_f) of
    every category, +10 %; used only when the exact front (and its stated reference) is unavailable."""
    f, p = [], []
    for cat in search_space(problem).categories():
        sub = category_problem(problem, cat)
        lo, hi = sub.lower().as_array(), sub.upper().as_array()
        values = evaluate_many(sub, np.array([[lo[0], lo[1], hi[2], hi[3]]]))
        f.append(float(values["turning_effort"][0]))
        p.append(float(values["threshold_force"][0]))
    return (1.1 * max(f), 1.1 * max(p))


def _exact_front(problem: Problem) -> dict | None:
    """The exact front of :func:`designer.analysis.pareto.pareto_front`, or a note when it is unavailable."""
    try:  # late import: the exact front loads casadi, only for this comparison
        from designer.analysis.pareto import pareto_front
    except ImportError:
        return {"note": "designer.analysis.pareto is not available; no comparison with the exact front"}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            front = pareto_front(problem, points=problem.pareto_points)
            pts = np.asarray(front.objectives(), float).reshape(-1, 2)
            ref = tuple(float(v) for v in front.reference_point())
    except Exception as exc:  # noqa: BLE001 - the exploration is still valid without it
        return {"note": f"exact front failed ({type(exc).__name__}: {_one_line(exc)}); no comparison"}
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) == 0:
        return {"note": "the exact front has no valid points; no comparison"}
    return {"points": pts, "reference_point": ref}


def compare_fronts(explored: np.ndarray, exact: np.ndarray, reference) -> dict:
    """Explored vs exact front: hypervolume with the same reference, ratio, IGD+ (normalised).

    Parameters
    ----------
    explored, exact : (n, 2) arrays of (F_turn, P) [N]
    reference : HV reference point (F_turn, P) [N] (the exact front's stated one)

    Returns
    -------
    dict with ``hypervolume_explored`` and ``hypervolume_exact`` [N²], their
    ``hypervolume_ratio``, ``igd_plus`` on objectives normalised by the exact
    front's ideal and nadir, ``reference_point`` and ``normalisation``.
    """
    exact = np.asarray(exact, float).reshape(-1, 2)
    explored = np.asarray(explored, float).reshape(-1, 2)
    ideal, nadir = exact.min(axis=0), exact.max(axis=0)
    hv_exact = hypervolume_2d(exact, reference)
    hv = hypervolume_2d(explored, reference)
    ref_n = normalise(np.asarray(reference, float)[None, :], ideal, nadir)[0]
    return {
        "hypervolume_explored": hv,
        "hypervolume_exact": hv_exact,
        "hypervolume_explored_normalised": hypervolume_2d(normalise(explored, ideal, nadir), ref_n),
        "hypervolume_exact_normalised": hypervolume_2d(normalise(exact, ideal, nadir), ref_n),
        "hypervolume_ratio": hv / hv_exact if hv_exact > 0 else float("nan"),
        "igd_plus": igd_plus(normalise(explored, ideal, nadir), normalise(exact, ideal, nadir)),
        "reference_point": [float(v) for v in reference],
        "normalisation": {"ideal": ideal.tolist(), "nadir": nadir.tolist(),
                          "reference_normalised": ref_n.tolist(),
                          "note": "(f - ideal)/(nadir - ideal) with the exact front's ideal and nadir; HV in N² "
                                  "and normalised with the exact front's reference point (nadir + 10 % of its "
                                  "extent, i.e. (1.1, 1.1) normalised); IGD+ normalised"},
        "exact_points": len(exact),
    }


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
        ok = (violation(sub, values) <= 0) & np.isfinite(values["turning_effort"]) & np.isfinite(values["threshold_force"])
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
    return dict(front=overall, category_fronts=category_fronts, distinct=len(distinct), feasible=feasible_total,
                hypervolume=hypervolume_2d(objs, reference) if len(objs) else 0.0,
                reference_point=tuple(float(v) for v in reference), comparison=comparison, operators=ops,
                refined=refine)


def _front_mask(objs: np.ndarray) -> np.ndarray:
    """Non-dominated rows, ties within 1e-9 relative (e.g. refined points equal to rounding) counted as equal."""
    objs = np.asarray(objs, float)
    return nondominated(np.array([[float(f"{v:.9g}") for v in row] for row in objs]).reshape(-1, 2))


def _row(cat: tuple, number: int, x: np.ndarray, values: dict, refined: bool) -> dict:
    row = {name: float(x[i]) for i, name in enumerate(VARIABLES)}
    row.update(turning_effort=float(values["turning_effort"]), threshold_force=float(values["threshold_force"]),
               critical_speed=float(values["critical_speed"]))
    row.update(dict(cat))
    row.update(trial=int(number), refined=refined)
    return row


def _refine(sub: Problem, cat: tuple, front: list, nlps: dict) -> list:
    """ε-constraint polish: min F_turn s.t. P <= P_candidate from each candidate (exact NLP of the category)."""

    if cat not in nlps:
        nlps[cat] = CasterNLP(sub)
    nlp = nlps[cat]
    out = []
    for row in front:
        start = Design(*(row[v] for v in VARIABLES))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            # with d fixed (catalog wheel) P is a constant: a cap equal to it would be a degenerate constraint
            cap = BIG if sub.bounds["diameter"].fixed else row["threshold_force"]
            res = nlp.solve(start, weights=(1.0, 0.0), threshold_cap=cap)
        if not res.success:
            out.append(row)
            continue
        x = res.design.as_array()
        values = evaluate_many(sub, x[None, :])
        values = {k: v[0] for k, v in values.items()}
        feasible = violation(sub, {k: np.atleast_1d(v) for k, v in values.items()})[0] <= 1e-9
        better = values["turning_effort"] <= row["turning_effort"] * (1 + 1e-9)
        if feasible and better and values["threshold_force"] <= row["threshold_force"] * (1 + 1e-9):
            out.append(_row(cat, row["trial"], x, values, True))
        else:
            out.append(row)
    objs = np.array([[r["turning_effort"], r["threshold_force"]] for r in out])
    return [out[i] for i in np.flatnonzero(_front_mask(objs))]
