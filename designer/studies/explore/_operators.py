"""The NSGA-II operators, the search space (categories and their sub-problems) and the NLP refinement.

See :mod:`designer.studies.explore` for what the operators are and why they are tuned.
"""

from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from designer.errors import InputError
from designer.studies.front import nondominated
from designer.model import VARIABLES, Design
from designer.problem import Bound, Problem
from designer.reprs import Key, Record

from designer.physics.inertia import Catalog


# --------------------------------------------------------------------------- operators


ETAS = ("crossover_eta", "mutation_eta")
"""The distribution indices of the operators: NaN when the operator has none (None in :meth:`Operators.to_dict`)."""


@dataclass(frozen=True)
class Operators(Record):
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

    _keys = (
        "*",
        *(Key(n, lambda o, n=n: getattr(o, n) if math.isfinite(getattr(o, n)) else None) for n in ETAS),
    )
    """The configuration as plain data (an unused η as None); :meth:`from_dict` reads it back."""

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
            return cls(
                name="optuna",
                population_size=population_size or 50,
                crossover="uniform",
                crossover_eta=float("nan"),
                crossover_prob=0.9,
                mutation="random",
                mutation_eta=float("nan"),
                deduplicate=False,
            )
        if name != "tuned":
            raise InputError(f"operators = {name!r}: expected 'tuned' or 'optuna'")
        pop = population_size or int(min(100, max(20, round(math.sqrt(max(trials, 1))))))
        return cls(population_size=pop)

    @classmethod
    def from_dict(cls, data: dict) -> "Operators":
        values = {k: (float("nan") if v is None and k.endswith("_eta") else v) for k, v in data.items()}
        return cls(**values)

    def sampler(self, seed: int | None):
        """The configured :class:`optuna.samplers.NSGAIISampler`."""
        import optuna

        from optuna.samplers.nsgaii import PolynomialMutation, SBXCrossover, UniformCrossover

        crossover = SBXCrossover(eta=self.crossover_eta) if self.crossover == "sbx" else UniformCrossover()
        mutation = PolynomialMutation(eta=self.mutation_eta) if self.mutation == "polynomial" else None
        operators = dict(
            crossover=crossover, crossover_prob=self.crossover_prob, mutation=mutation, mutation_prob=self.mutation_prob
        )
        kwargs = dict(population_size=self.population_size, seed=seed, **operators)
        if not self.deduplicate:
            return optuna.samplers.NSGAIISampler(**kwargs)
        from optuna.samplers._lazy_random_state import LazyRandomState

        from optuna.samplers.nsgaii._child_generation_strategy import NSGAIIChildGenerationStrategy

        rng = LazyRandomState(seed)
        inner = NSGAIIChildGenerationStrategy(**operators, swapping_prob=0.5, constraints_func=None, rng=rng)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sampler = optuna.samplers.NSGAIISampler(**kwargs, child_generation_strategy=_Deduplicated(inner))
        sampler._rng = rng  # reseed_rng() must reach the strategy's generator
        return sampler

    def process_sampler(self, seed: int | None):
        """The sampler of one process working on a study: :meth:`sampler` seeded with
        :func:`stream_seed` ``(seed, n)``, ``n`` the number of the first trial this process runs.

        Trial numbers are unique, so processes that join one study at the same moment with the same
        ``seed`` (or seeds whose sum with the trial count coincides) still draw different candidates; a
        process alone on a study (a fresh single-worker run, or a resume) is repeatable, and a fresh run
        (first trial 0) uses ``seed`` itself.
        """
        return _PerProcessSampler(self, seed)


STREAM_STRIDE = 0x9E3779B1
"""Odd multiplier of :func:`stream_seed`: ``(STREAM_STRIDE * k) mod 2**32`` is at least 1637 away from 0 for
every ``0 < |k| < 2**20``, so processes whose seeds differ by less than 1637 never share a stream."""


def stream_seed(seed: int | None, first_trial: int) -> int | None:
    """Seed of the random stream of a process whose first trial is number ``first_trial``:
    ``(seed + STREAM_STRIDE * first_trial) mod 2**32`` (``seed`` itself for trial 0; None stays None)."""
    return None if seed is None else (seed + STREAM_STRIDE * first_trial) % 2**32


class _PerProcessSampler:
    """An NSGA-II sampler built when the process asks its first trial, seeded by that trial's number: optuna's
    ``ask`` calls ``before_trial`` first, and every other call of a sampler goes to the built one."""

    def __init__(self, operators: Operators, seed: int | None):
        self.operators = operators
        self.seed = seed
        self.inner = None

    def before_trial(self, study, trial) -> None:
        if self.inner is None:
            self.inner = self.operators.sampler(stream_seed(self.seed, trial.number))
        self.inner.before_trial(study, trial)

    def __getattr__(self, name: str):
        if name == "inner":  # not set yet (a copy being built)
            raise AttributeError(name)
        return getattr(self.inner, name)

    def reseed_rng(self) -> None:
        if self.inner is not None:
            self.inner.reseed_rng()


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
        from optuna.trial import TrialState

        trials = study.get_trials(deepcopy=False)
        pending = set()
        contiguous = True
        for t in trials[self._scanned :]:
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


def _params_key(params: dict) -> tuple:
    return tuple(sorted((k, round(v, 12) if isinstance(v, float) else v) for k, v in params.items()))


# --------------------------------------------------------------------------- search space


@dataclass(frozen=True)
class SearchSpace(Record):
    """The exploration space of a problem.

    Attributes
    ----------
    continuous : ((variable, low, high), ...) [SI] of the free continuous variables
    categorical : ((dimension, choices), ...) for wheel, surface, turning_mode
    """

    continuous: tuple
    categorical: tuple

    _keys = (
        Key("continuous", lambda s: {n: [lo, hi] for n, lo, hi in s.continuous}),
        Key("categorical", lambda s: {n: list(c) for n, c in s.categorical}),
    )
    """{"continuous": {variable: [low, high]} [SI], "categorical": {dimension: [choices]}}."""

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.categorical) + tuple(name for name, _, _ in self.continuous)

    def categories(self) -> list[tuple[tuple[str, Any], ...]]:
        """Every combination of categorical values, as ((dimension, value), ...) tuples."""
        dims = [[(name, value) for value in choices] for name, choices in self.categorical]
        return [tuple(combo) for combo in itertools.product(*dims)] if dims else [()]


def search_space(problem: Problem) -> SearchSpace:
    """Continuous and categorical dimensions of ``problem`` (see the module docstring)."""
    wheels = tuple(problem.wheels)
    chosen = problem.choices.get("wheel")
    if wheels and chosen:
        wheels = tuple(w for w in wheels if w in chosen)
        if not wheels:
            raise InputError(
                f"choices.wheel = {list(chosen)}: none of them is in inertia.wheels {list(problem.wheels)}"
            )
    elif chosen:
        wheels = tuple(chosen)
    choices = {"wheel": wheels, **{key: tuple(problem.choices.get(key) or ()) for key in ("surface", "turning_mode")}}
    b = problem.bounds  # a catalog wheel fixes the diameter
    free = [name for name in VARIABLES if not b[name].fixed and not (name == "diameter" and wheels)]
    return SearchSpace(
        continuous=tuple((name, float(b[name].low), float(b[name].high)) for name in free),
        categorical=tuple((key, values) for key, values in choices.items() if values),
    )


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


# --------------------------------------------------------------------------- NLP refinement


def _front_mask(objs: np.ndarray) -> np.ndarray:
    """Non-dominated rows, ties within 1e-9 relative (e.g. refined points equal to rounding) counted as equal."""
    objs = np.asarray(objs, float)
    return nondominated(np.array([[float(f"{v:.9g}") for v in row] for row in objs]).reshape(-1, 2))


def _row(cat: tuple, number: int, x: np.ndarray, values: dict, refined: bool) -> dict:
    """A front point: the design (T, d, B, c_f [SI]), F_turn, P [N], V_c [m/s], the category, trial and flag."""
    outputs = {k: float(values[k]) for k in ("turning_effort", "threshold_force", "critical_speed")}
    return {**dict(zip(VARIABLES, map(float, x))), **outputs, **dict(cat), "trial": int(number), "refined": refined}


def _refine(sub: Problem, cat: tuple, front: list, nlps: dict) -> list:
    """ε-constraint polish: min F_turn s.t. P <= P_candidate from each candidate (exact NLP of the category)."""

    from designer.solvers.nlp import BIG, CasterNLP  # CasADi: the polish only, never a trial

    nlp = nlps.get(cat) or nlps.setdefault(cat, CasterNLP(sub))
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
        values = sub.evaluate(x[None, :]).row(0)
        better = values["turning_effort"] <= row["turning_effort"] * (1 + 1e-9)
        if values.feasible and better and values["threshold_force"] <= row["threshold_force"] * (1 + 1e-9):
            out.append(_row(cat, row["trial"], x, values, True))
        else:
            out.append(row)
    objs = np.array([[r["turning_effort"], r["threshold_force"]] for r in out])
    return [out[i] for i in np.flatnonzero(_front_mask(objs))]
