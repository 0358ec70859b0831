"""Exact Pareto fronts of (turning effort, threshold force) by the ε-constraint method.

For a problem, :func:`pareto_front` computes the designs that minimise the
turning effort F_turn for every cap ε on the threshold force P:

    min F_turn(x)  s.t.  P(x) <= ε,  V_c(x) >= V_req (Eq. 7),  bounds,  R_s <= R_max

on the CasADi NLP built once (``designer.solvers.nlp.CasterNLP``), warm-started
from point to point.  The two ends are solved for (lexicographic minima), the
points are then re-spaced evenly by arc length along the normalised front and
re-solved, each from the previous point and from the two competing design
families (grooved, damped) so a switch between them is found, not smoothed
over.  Points that fail are retried, then kept as failed (never plotted or
counted); dominated points are removed.
"""
from __future__ import annotations

import csv
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from designer.indicators import hypervolume_2d, igd_plus, nondominated, normalise
from designer.model import VARIABLES, Design, evaluate
from designer.problem import Problem
from designer.solvers.nlp import BIG, CasterNLP, best_starts, solve_best

REFERENCE_OFFSET = 0.1
"""Hypervolume reference point: 10 % beyond the nadir in normalised objectives, i.e. (1.1, 1.1)."""


@dataclass
class FrontPoint:
    """One point of the front.

    Attributes
    ----------
    design : the design (SI)
    turning_effort : F_turn [N]
    threshold_force : P [N]
    critical_speed : V_c [m/s]
    margins : constraint margins (>= 0 feasible) by name
    epsilon : the cap on P used [N]
    status : IPOPT return status
    success : IPOPT succeeded and the point is feasible
    multipliers : {"shimmy": λ, "threshold_cap": λ, ...} (CasADi sign convention)
    family : "bare fork" | "groove" | "damper" | "groove+damper"
    wheel : Table 1 wheel for catalog problems
    """

    design: Design
    turning_effort: float
    threshold_force: float
    critical_speed: float
    margins: dict
    epsilon: float
    status: str
    success: bool
    multipliers: dict = field(default_factory=dict)
    family: str = ""
    wheel: str | None = None

    def row(self) -> dict:
        """Flat dict for CSV/JSON (SI units)."""
        out = self.design.as_dict()
        out.update(
            turning_effort=self.turning_effort,
            threshold_force=self.threshold_force,
            critical_speed=self.critical_speed,
            epsilon=self.epsilon,
            family=self.family,
            status=self.status,
        )
        if self.wheel:
            out["wheel"] = self.wheel
        for name, value in self.multipliers.items():
            out[f"lambda_{name}"] = value
        return out


def family_of(problem: Problem, design: Design, tol: float = 1e-6) -> str:
    """Which mechanism stabilises the design: groove, added damper, both or neither."""
    grooved = design.groove > problem.bounds["groove"].low + tol * max(problem.bounds["groove"].high, 1e-3)
    damped = design.damping > problem.conditions.turning.bare_fork_damping * (1 + tol)
    return {(False, False): "bare fork", (True, False): "groove", (False, True): "damper",
            (True, True): "groove+damper"}[(grooved, damped)]


@dataclass
class Front:
    """An exact Pareto front (valid points sorted by decreasing threshold force).

    Iterating yields the valid points, from the cheapest-to-turn design to the
    lowest-threshold-force design.
    """

    problem: Problem
    points: list
    failed: list = field(default_factory=list)
    meta: dict = field(default_factory=dict)

    def __iter__(self):
        return iter(self.points)

    def __len__(self):
        return len(self.points)

    def objectives(self) -> np.ndarray:
        """(N, 2) array of (turning_effort, threshold_force) [N] of the valid points."""
        return np.array([[p.turning_effort, p.threshold_force] for p in self.points]).reshape(-1, 2)

    def designs(self) -> np.ndarray:
        """(N, 4) array of the designs (SI)."""
        return np.array([p.design.as_array() for p in self.points]).reshape(-1, 4)

    def ideal_nadir(self) -> tuple[np.ndarray, np.ndarray]:
        """Ideal (best of each objective) and nadir (worst on the front) [N]."""
        f = self.objectives()
        return f.min(axis=0), f.max(axis=0)

    def reference_point(self) -> np.ndarray:
        """Stated hypervolume reference: nadir + 10 % of the front's extent, in newtons."""
        ideal, nadir = self.ideal_nadir()
        return nadir + REFERENCE_OFFSET * np.where(nadir > ideal, nadir - ideal, 1.0)

    def hypervolume(self, ref=None, ideal=None, nadir=None) -> float:
        """Normalised hypervolume of the front.

        Objectives are normalised by (f − ideal)/(nadir − ideal) with the
        front's own ideal and nadir unless given (give another front's to
        compare fronts); the reference point is (1.1, 1.1) in normalised
        units unless ``ref`` (normalised) is given.
        """
        own_ideal, own_nadir = self.ideal_nadir()
        ideal = own_ideal if ideal is None else np.asarray(ideal, float)
        nadir = own_nadir if nadir is None else np.asarray(nadir, float)
        ref = np.full(2, 1 + REFERENCE_OFFSET) if ref is None else np.asarray(ref, float)
        return hypervolume_2d(normalise(self.objectives(), ideal, nadir), ref)

    def knee(self) -> FrontPoint | None:
        """The knee: the point farthest from the chord between the two ends, in normalised objectives."""
        if len(self.points) < 3:
            return self.points[0] if self.points else None
        ideal, nadir = self.ideal_nadir()
        f = normalise(self.objectives(), ideal, nadir)
        a, b = f[0], f[-1]
        chord = b - a
        norm = np.hypot(*chord)
        if norm == 0:
            return self.points[0]
        distance = np.abs(chord[0] * (f[:, 1] - a[1]) - chord[1] * (f[:, 0] - a[0])) / norm
        below = (f[:, 0] - a[0]) * chord[1] - (f[:, 1] - a[1]) * chord[0]
        distance = np.where(below >= 0, distance, -distance)  # the knee bulges toward the ideal
        return self.points[int(np.argmax(distance))]

    def weighted_best(self, weights=None) -> FrontPoint | None:
        """The front point minimising J = w_turn F_turn + w_threshold P (default weights: the problem's)."""
        if not self.points:
            return None
        w = np.asarray(self.problem.weights if weights is None else weights, float)
        return self.points[int(np.argmin(self.objectives() @ w))]

    def gaps(self, factor: float = 3.0) -> list[tuple[int, str]]:
        """Discontinuities: family switches and jumps larger than ``factor`` × the median spacing.

        Returns (index of the point after the gap, description) pairs.
        """
        out = []
        if len(self.points) < 3:
            return out
        ideal, nadir = self.ideal_nadir()
        f = normalise(self.objectives(), ideal, nadir)
        steps = np.hypot(*np.diff(f, axis=0).T)
        median = np.median(steps) if np.any(steps > 0) else 0
        for i in range(1, len(self.points)):
            a, b = self.points[i - 1], self.points[i]
            if a.family != b.family:
                out.append((i, f"family switch {a.family} → {b.family} at P ≈ {b.threshold_force:.2f} N"))
            elif median > 0 and steps[i - 1] > factor * median:
                out.append((i, f"jump in the front between P = {a.threshold_force:.2f} and {b.threshold_force:.2f} N"))
        return out

    def compare(self, other: "Front") -> dict:
        """Compare with another front on common normalisation (this front's ideal/nadir).

        Returns hypervolumes of both, IGD+ of ``other`` against this front, and
        ``dominated_fraction``: the share of ``other``'s points weakly dominated
        by one of this front's points (a discrete test: a point of ``other``
        that falls between two of this front's points can be dominated by the
        continuous front and still count as not dominated; see
        :func:`designer.checks.front_checks` for the exact test).
        """
        ideal, nadir = self.ideal_nadir()
        mine = normalise(self.objectives(), ideal, nadir)
        theirs = normalise(other.objectives(), ideal, nadir)
        tol = 1e-6
        dominated = [bool(np.any(np.all(mine <= q + tol, axis=1))) for q in theirs]
        return {
            "hypervolume_self": self.hypervolume(ideal=ideal, nadir=nadir),
            "hypervolume_other": other.hypervolume(ideal=ideal, nadir=nadir),
            "igd_plus_other": igd_plus(theirs, mine),
            "dominated_fraction": float(np.mean(dominated)) if dominated else float("nan"),
        }

    def rows(self) -> list[dict]:
        """One flat dict per valid point (SI units)."""
        return [p.row() for p in self.points]

    def to_csv(self, path) -> None:
        """Write the valid points: trail, diameter, groove, damping, turning_effort, threshold_force, critical_speed, …"""
        rows = self.rows()
        columns = list(VARIABLES) + ["turning_effort", "threshold_force", "critical_speed", "epsilon", "family", "status"]
        extra = sorted({k for r in rows for k in r} - set(columns))
        with open(path, "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=columns + extra)
            writer.writeheader()
            for r in rows:
                writer.writerow({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in r.items()})

    def to_dict(self) -> dict:
        """Plain data: points, failed points, indicators and run metadata."""
        knee = self.knee()
        best = self.weighted_best()
        return {
            "problem": self.problem.name,
            "points": self.rows(),
            "failed": [p.row() for p in self.failed],
            "hypervolume": self.hypervolume() if self.points else None,
            "hypervolume_reference": {
                "normalisation": "(f - ideal) / (nadir - ideal), ideal and nadir of this front",
                "ideal": self.ideal_nadir()[0].tolist() if self.points else None,
                "nadir": self.ideal_nadir()[1].tolist() if self.points else None,
                "reference_normalised": [1 + REFERENCE_OFFSET] * 2,
            },
            "knee": self.points.index(knee) if knee is not None else None,
            "weighted_best": self.points.index(best) if best is not None else None,
            "gaps": [{"index": i, "what": what} for i, what in self.gaps()],
            "meta": self.meta,
        }


# --------------------------------------------------------------------------- computing fronts


def _point(nlp: CasterNLP, problem: Problem, result, epsilon: float, wheel=None) -> FrontPoint:
    from designer.optimise import constraint_margins

    values = evaluate(result.design, problem.conditions) if result.success else None
    if values is None:
        f, p, v, _ = nlp.objectives(result.design)
        margins = {}
    else:
        f, p, v = values["turning_effort"], values["threshold_force"], values["critical_speed"]
        margins, _ = constraint_margins(problem, result.design, values)
    multipliers = {name: float(lam) for name, lam in zip(nlp.constraint_names, result.lam_g)}
    return FrontPoint(result.design, float(f), float(p), float(v), margins, float(epsilon), result.status,
                      result.success, multipliers, family_of(problem, result.design), wheel)


def _family_starts(problem: Problem, design: Design) -> list[np.ndarray]:
    """The previous design moved to each competing family (grooved / damped)."""
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    x = design.as_array()
    grooved = np.array([x[0], x[1], hi[2], lo[3]])
    damped = np.array([x[0], x[1], lo[2], hi[3]])
    return [grooved, damped]


def _solve_eps(nlp, problem, epsilon, previous, extra_starts=()):
    """min F s.t. P <= ε from the previous point (warm) and the family starts; best success."""
    results = []
    if previous is not None:
        results.append(nlp.solve(previous.design, (1.0, 0.0), epsilon, lam_g0=previous.lam_g, lam_x0=previous.lam_x))
        starts = _family_starts(problem, previous.design)
    else:
        starts = []
    starts += list(extra_starts)
    for s in starts:
        results.append(nlp.solve(s, (1.0, 0.0), epsilon))
    good = [r for r in results if r.success]
    if not good:
        # retry from a fresh sample of the box
        for s in best_starts(problem, (1.0, 0.0), k=4, threshold_cap=epsilon, seed=len(results)):
            r = nlp.solve(s, (1.0, 0.0), epsilon)
            results.append(r)
            if r.success:
                good.append(r)
    if not good:
        return None, results[0] if results else None
    return min(good, key=lambda r: nlp.objectives(r.design)[0]), None


def _ends(nlp: CasterNLP, problem: Problem):
    """Lexicographic ends: (min F, then min P) and (min P, then min F)."""
    best_f, _ = solve_best(nlp, best_starts(problem, (1.0, 0.0)), (1.0, 0.0))
    best_p, _ = solve_best(nlp, best_starts(problem, (0.0, 1.0)), (0.0, 1.0))
    if best_f is None or best_p is None:
        return None, None
    f_min = nlp.objectives(best_f.design)[0]
    p_min = nlp.objectives(best_p.design)[1]
    # second stage: the other objective, the first capped at its optimum
    end_a, _ = solve_best(nlp, [best_f.design], (0.0, 1.0), turning_cap=f_min * (1 + 1e-9))
    end_b, _ = solve_best(nlp, [best_p.design] + _family_starts(problem, best_p.design), (1.0, 0.0),
                          threshold_cap=p_min * (1 + 1e-9))
    return end_a or best_f, end_b or best_p


def pareto_front(problem: Problem, points: int | None = None, progress=None) -> Front:
    """Exact Pareto front of (turning effort, threshold force) for ``problem``.

    Parameters
    ----------
    problem : the problem (catalog problems: one point per wheel, dominated ones removed)
    points : number of points (default ``problem.pareto_points``)
    progress : optional callable ``progress(done, total)`` for long runs

    Returns
    -------
    Front
    """
    n = int(points or problem.pareto_points)
    if n < 2:
        from designer.errors import InputError

        raise InputError(f"points = {n}: a front needs at least 2 points")
    t0 = time.perf_counter()
    all_points: list[FrontPoint] = []
    failed: list[FrontPoint] = []
    build = 0.0
    solves = 0
    variants = problem.variants()
    single_d = all(v.bounds["diameter"].fixed for v in variants)
    for k, variant in enumerate(variants):
        nlp = CasterNLP(variant)
        build += nlp.build_seconds
        wheel = variant.conditions.inertia.wheel.key if problem.wheels else None
        end_a, end_b = _ends(nlp, variant)
        solves += 8
        if end_a is None:
            continue  # infeasible variant (e.g. a catalog wheel that cannot reach the target)
        if single_d:
            all_points.append(_point(nlp, variant, end_b, BIG, wheel))
            if progress:
                progress(k + 1, len(variants))
            continue
        p_a = nlp.objectives(end_a.design)[1]
        p_b = nlp.objectives(end_b.design)[1]
        # pass 1: uniform in ε; pass 2: uniform in arc length of pass 1
        eps = np.linspace(p_a, p_b, n)
        total = 2 * n
        first, done = _sweep(nlp, variant, eps, end_a, end_b, wheel, progress, 0, total)
        solves += done
        good = [p for p in first if p.success]
        if len(good) >= 3:
            eps2 = _respace(good, n)
            second, done = _sweep(nlp, variant, eps2, end_a, end_b, wheel, progress, n, total)
            solves += done
        else:
            second = first
        all_points += [p for p in second if p.success]
        failed += [p for p in second if not p.success]
    valid = _clean(all_points)
    meta = {
        "points_requested": n,
        "points_valid": len(valid),
        "points_failed": len(failed),
        "build_seconds": build,
        "total_seconds": time.perf_counter() - t0,
        "nlp_solves": solves,
        "method": "ε-constraint on the CasADi/IPOPT NLP (min F_turn s.t. P <= ε), warm-started, "
                  "arc-length re-spaced, family restarts",
        "solver": "ipopt (tol 1e-10, exact Hessian)",
    }
    return Front(problem, valid, failed, meta)


def _sweep(nlp, problem, eps_values, end_a, end_b, wheel, progress, offset, total):
    out = []
    previous = end_a
    solves = 0
    for i, eps in enumerate(eps_values):
        if i == 0:
            result = end_a
        elif i == len(eps_values) - 1:
            result = end_b
        else:
            result, failure = _solve_eps(nlp, problem, float(eps), previous)
            solves += 3
            if result is None:
                out.append(_point(nlp, problem, failure, eps, wheel))
                if progress:
                    progress(offset + i + 1, total)
                continue
        out.append(_point(nlp, problem, result, eps, wheel))
        previous = result
        if progress:
            progress(offset + i + 1, total)
    return out, solves


def _respace(points: list[FrontPoint], n: int) -> np.ndarray:
    """ε values evenly spaced by arc length along the normalised front of ``points``."""
    f = np.array([[p.turning_effort, p.threshold_force] for p in points])
    ideal, nadir = f.min(axis=0), f.max(axis=0)
    g = normalise(f, ideal, nadir)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(g, axis=0).T))])
    if s[-1] <= 0:
        return np.array([p.threshold_force for p in points])
    targets = np.linspace(0, s[-1], n)
    return np.interp(targets, s, f[:, 1])


def _clean(points: list[FrontPoint]) -> list[FrontPoint]:
    """Remove dominated and duplicate points; sort by decreasing threshold force."""
    if not points:
        return []
    f = np.array([[p.turning_effort, p.threshold_force] for p in points])
    # tolerance: treat differences below 1e-9 relative as ties
    scale = np.maximum(np.abs(f).max(axis=0), 1e-12)
    rounded = np.round(f / scale, 9)
    keep = nondominated(rounded)
    kept = [p for p, k in zip(points, keep) if k]
    kept.sort(key=lambda p: -p.threshold_force)
    return kept
