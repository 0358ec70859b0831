"""Exact NLP of a caster design problem with CasADi and IPOPT.

The NLP is built once per (continuous) problem with every physical constant,
the weights and the ε-bounds as CasADi parameters, so scalarised optima,
ε-constraint Pareto points and sensitivities all reuse one solver.

Variables are scaled by their upper bounds so IPOPT sees numbers near 1.
Constraints (CasADi convention lbg <= g <= ubg):

    shimmy     V_c / V_req − 1 >= 0                (Eq. 7)
    threshold  (P − ε_P) / P_ref <= 0              (ε-constraint, Eq. 4A)
    turning    (F_turn − ε_F) / F_ref <= 0         (ε-constraint, Eq. 9)
    swept      (T + d/2) / R_max − 1 <= 0          (only with swept_radius_max)
"""

from __future__ import annotations

import contextlib
import copy
import functools
import sys
import threading
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, TextIO
from pathlib import Path

import casadi as ca
import numpy as np

from designer import parameters
from designer.errors import check_interrupt
from designer.model import VARIABLES, Design, performance, weighted
from designer.physics import enable_casadi
from designer.problem import Problem
from designer.reprs import Record
from designer.solvers.base import design_rows

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt

enable_casadi()  # NumPy mode: the physics functions build CasADi symbols here

BIG = 1e9

QUIET: dict[str, Any] = {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes", "show_eval_warnings": False}
"""Options of every IPOPT solver built here: no iteration log, no timing table, no banner, and no CasADi
"NaN detected" evaluation warnings (a NaN in the model shows as a failed solve, which the callers report
in one line). Solver output never reaches the user's terminal."""


class _DropCasadiLines:
    """A stand-in for sys.stderr while a solver runs: CasADi writes its remaining warnings (e.g. "Failed to
    calculate multipliers" after a NaN, which no option turns off) through Python's sys.stderr, a line in
    several writes starting with "CasADi - "; from such a write to the end of its line everything is
    dropped, every other write passes to the real stream at once."""

    def __init__(self, stream: TextIO):
        self.stream = stream
        self.dropping = False

    def write(self, text: str) -> int:
        if not self.dropping and not text.startswith("CasADi - "):
            return int(self.stream.write(text))
        self.dropping = True
        if "\n" in text:
            self.dropping = False
            rest = text.split("\n", 1)[1]
            if rest:
                self.write(rest)
        return len(text)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.stream, name)


_QUIET_LOCK = threading.Lock()
_QUIET_DEPTH = 0


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """Run a solver call with :class:`_DropCasadiLines` on sys.stderr (re-entrant across threads)."""
    global _QUIET_DEPTH
    with _QUIET_LOCK:
        if _QUIET_DEPTH == 0:
            sys.stderr = _DropCasadiLines(sys.stderr)  # type: ignore[assignment]
        _QUIET_DEPTH += 1
    try:
        yield
    finally:
        with _QUIET_LOCK:
            _QUIET_DEPTH -= 1
            if _QUIET_DEPTH == 0 and isinstance(sys.stderr, _DropCasadiLines):
                sys.stderr = sys.stderr.stream  # type: ignore[unreachable]


PARAMETER_INFO = {p.name: (p.symbol, p.shown_unit, p.description) for p in parameters.SOLVER_PARAMETERS}
"""Fixed parameters whose sensitivity d log J / d log p is reported (from :mod:`designer.parameters`)."""


@dataclass(frozen=True, kw_only=True)
class NLPResult(Record):
    """One IPOPT solve.

    Attributes
    ----------
    design : the optimum (SI)
    success : IPOPT reported success and the point is feasible
    status : IPOPT return status string
    objective : J in newtons (weighted) at the optimum
    lam_g, lam_x : multipliers (CasADi sign convention, scaled variables)
    iterations : IPOPT iterations
    seconds : wall time of the solve
    """

    design: Design
    success: bool
    status: str
    objective: float
    lam_g: np.ndarray
    lam_x: np.ndarray
    iterations: int
    seconds: float
    z: np.ndarray | None = field(repr=False, default=None)

    _units = {"objective": "N", "seconds": "s"}


class CasterNLP:
    """The exact NLP of one continuous problem, built once and solved many times.

    Parameters
    ----------
    problem : Problem
        A problem without catalog choices (use ``problem.variants()``).
    ipopt_options : dict, optional
        Extra IPOPT options.
    """

    def __init__(self, problem: Problem, ipopt_options: dict[str, Any] | None = None):
        if problem.wheels:
            raise ValueError("CasterNLP needs a continuous problem; iterate over problem.variants()")
        t0 = time.perf_counter()
        self.problem = problem
        lo = problem.lower().as_array()
        hi = problem.upper().as_array()
        self.scale = np.maximum(hi, np.array(parameters.SCALES))
        self.lbz = lo / self.scale
        self.ubz = hi / self.scale
        self.param_names, self.param_values, conditions_sym, psym = self._symbolic_conditions(problem)
        # control parameters: weights, ε bounds
        w = ca.SX.sym("w", 2)
        eps = ca.SX.sym("eps", 2)
        z = ca.SX.sym("z", 4)
        x = z * ca.DM(self.scale)
        perf = performance(**parameters.named(x), conditions=conditions_sym)
        self._perf_function = ca.Function(
            "perf",
            [z, psym],
            [perf["turning_effort"], perf["threshold_force"], perf["critical_speed"], perf["swept_radius"]],
        )
        # references for scaling, at the centre of the box
        self.f_ref, self.p_ref = f_ref, p_ref = self.references()
        v_req = (1 + problem.margin) * psym[self.param_names.index("target_speed")]
        # J = w_turn F + w_thr P, divided by its value at the box centre so IPOPT sees O(1)
        objective = weighted(perf["turning_effort"], perf["threshold_force"], w) / weighted(f_ref, p_ref, w)
        g = [
            perf["confident_speed"] / v_req - 1,
            (perf["threshold_force"] - eps[0]) / p_ref,
            (perf["turning_effort"] - eps[1]) / f_ref,
        ]
        self.constraint_names = ["shimmy", "threshold_cap", "turning_cap"]
        if problem.swept_radius_max is not None:
            r_max = psym[self.param_names.index("swept_radius_max")]
            g.append(perf["swept_radius"] / r_max - 1)
            self.constraint_names.append("swept_radius")
        g = ca.vertcat(*g)
        self.lbg = np.array([0.0] + [-np.inf] * (g.shape[0] - 1))
        self.ubg = np.array([np.inf] + [0.0] * (g.shape[0] - 1))
        p_all = ca.vertcat(psym, w, eps)
        self.n_phys = psym.shape[0]
        options: dict[str, Any] = {
            **QUIET,
            "ipopt.tol": 1e-10,
            "ipopt.acceptable_tol": 1e-8,
            "ipopt.constr_viol_tol": 1e-10,
            "ipopt.bound_relax_factor": 0.0,
            "ipopt.max_iter": 500,
            "ipopt.mu_strategy": "adaptive",
            "ipopt.hessian_approximation": "exact",
            "error_on_fail": False,
        }
        options.update(ipopt_options or {})
        self.solver = ca.nlpsol("caster", "ipopt", {"x": z, "p": p_all, "f": objective, "g": g}, options)
        # One block (objective, constraints) for batched solves of many independent NLPs (solve_many)
        self._block = ca.Function("block", [z, p_all], [objective, g])
        # Gradient of the objective and Jacobian of the constraints (multipliers of a known optimum)
        self._kkt = ca.Function("kkt", [z, p_all], [ca.gradient(objective, z), ca.jacobian(g, z), g])
        self._options = options
        self._batch: dict[Any, Any] = {}
        # Sensitivity of the Lagrangian with respect to the physical parameters.
        lam_g = ca.SX.sym("lam_g", g.shape[0])
        lagrangian = objective + ca.dot(lam_g, g)
        self._dlag_dp = ca.Function("dL_dp", [z, p_all, lam_g], [ca.gradient(lagrangian, psym)])
        self.build_seconds = time.perf_counter() - t0

    # ----------------------------------------------------------------- parameters
    def for_problem(self, problem: Problem) -> "CasterNLP":
        """This NLP for ``problem``, which may differ from the one it was built for only in parameter values.

        A new object sharing the compiled solvers (and the lazily built batch solvers) with this one, with
        ``problem`` and its own parameter vector (:func:`designer.parameters.solver_values`); this NLP is
        not changed.  The caller guarantees that the structure (bounds, margin, swept-radius limit, models)
        is the same; ``build_seconds`` of the new object starts at 0.
        """
        view = copy.copy(self)
        view.problem = problem
        view.param_values = np.array(list(parameters.solver_values(problem).values()), dtype=float)
        view.build_seconds = 0.0
        return view

    def references(self) -> tuple[float, float]:
        """(F_turn [N], P [N]) at the centre of the box with this NLP's parameter values: the scales of the
        objective and the ε constraints that a build for ``self.problem`` bakes in."""
        centre = (self.lbz + self.ubz) / 2
        f_ref, p_ref, _, _ = (float(v) for v in self._perf_function(centre, self.param_values))
        return f_ref, p_ref

    @staticmethod
    def _symbolic_conditions(problem: Problem) -> tuple[list[str], np.ndarray, Any, Any]:
        """Replace every fixed constant of the conditions by a CasADi symbol (:mod:`designer.parameters`)."""
        values = parameters.solver_values(problem)
        names = list(values)
        p = ca.SX.sym("p", len(names))
        conditions = parameters.with_solver_values(problem, {name: p[i] for i, name in enumerate(names)})
        return names, np.array(list(values.values()), dtype=float), conditions, p

    def parameter_vector(
        self,
        weights: npt.ArrayLike = (1.0, 1.0),
        threshold_cap: float = BIG,
        turning_cap: float = BIG,
        overrides: dict[str, float] | None = None,
    ) -> np.ndarray:
        """Full parameter vector: physical values (optionally overridden), weights, ε caps."""
        phys = self.param_values.copy()
        for name, value in (overrides or {}).items():
            phys[self.param_names.index(name)] = value
        return np.concatenate([phys, np.asarray(weights, float), [threshold_cap, turning_cap]])

    # ----------------------------------------------------------------- solving
    def to_z(self, design: Design | npt.ArrayLike) -> np.ndarray:
        """Scaled variables of a design (clipped into the box)."""
        z: np.ndarray = np.clip(design_rows([design])[0] / self.scale, self.lbz, self.ubz)
        return z

    def solve(
        self,
        start: Design | npt.ArrayLike,
        weights: npt.ArrayLike = (1.0, 1.0),
        threshold_cap: float = BIG,
        turning_cap: float = BIG,
        lam_g0: npt.ArrayLike | None = None,
        lam_x0: npt.ArrayLike | None = None,
        overrides: dict[str, float] | None = None,
    ) -> NLPResult:
        """One IPOPT solve from ``start`` (a Design or SI array)."""
        p = self.parameter_vector(weights, threshold_cap, turning_cap, overrides)
        args: dict[str, Any] = dict(x0=self.to_z(start), p=p, lbx=self.lbz, ubx=self.ubz, lbg=self.lbg, ubg=self.ubg)
        if lam_g0 is not None:
            args["lam_g0"] = lam_g0
        if lam_x0 is not None:
            args["lam_x0"] = lam_x0
        t0 = time.perf_counter()
        with _quiet():
            sol = self.solver(**args)
        check_interrupt()  # CasADi swallows KeyboardInterrupt: the SIGINT flag
        seconds = time.perf_counter() - t0
        stats = self.solver.stats()
        z = np.asarray(sol["x"]).ravel()
        design = Design.from_array(z * self.scale)
        g = np.asarray(sol["g"]).ravel()
        viol = max(float(np.max(self.lbg - g)), float(np.max(g - self.ubg)), 0.0)
        success = bool(stats.get("success", False)) and viol <= 1e-6 and bool(np.all(np.isfinite(z)))
        objective = self.weighted(design, weights)
        return NLPResult(
            design=design,
            success=success,
            status=str(stats.get("return_status")),
            objective=objective,
            lam_g=np.asarray(sol["lam_g"]).ravel(),
            lam_x=np.asarray(sol["lam_x"]).ravel(),
            iterations=int(stats.get("iter_count", -1)),
            seconds=seconds,
            z=z,
        )

    BATCH_SIZES = (4, 16, 40, 64)
    """Block counts of the batched solvers (built lazily, once each per problem)."""

    WARM_OPTIONS = {
        "ipopt.warm_start_init_point": "yes",
        "ipopt.mu_init": 1e-6,
        "ipopt.warm_start_bound_push": 1e-9,
        "ipopt.warm_start_mult_bound_push": 1e-9,
        "ipopt.warm_start_slack_bound_push": 1e-9,
        "ipopt.warm_start_slack_bound_frac": 1e-9,
        "ipopt.warm_start_bound_frac": 1e-9,
    }
    """IPOPT options of a warm batch: start from the given primal and dual point with a small barrier."""

    EXPAND = False
    """Batches as expanded SX (~0.25 s more to build, ~40 % less CPU a solve): for a long-lived ``designer studio``."""

    def _batch_solver(self, size: int, warm: bool) -> tuple[Any, Any]:
        """The IPOPT solver of ``size`` blocks (built once per size and start kind): an MX ``map`` of the one-block
        SX function, so IPOPT's derivatives are maps of the block's (differentiated once), or with :attr:`EXPAND`
        its SX expansion. The same NLP: fronts of the two builds agree to 1e-9 relative (shipped problems)."""
        key = (size, warm)
        if key not in self._batch:
            t0 = time.perf_counter()
            nz, npar = 4, self.n_phys + 4
            kind: Any = ca.SX if self.EXPAND else ca.MX
            zz, pp = kind.sym("Z", nz, size), kind.sym("P", npar, size)
            f, g = self._block.map(size)(zz, pp)
            options = dict(self._options, calc_lam_p=False)  # dL/dp of the batch is never used
            if warm:
                options.update(self.WARM_OPTIONS)
            solver = ca.nlpsol(
                f"caster_{size}", "ipopt", {"x": ca.vec(zz), "p": ca.vec(pp), "f": ca.sum2(f), "g": ca.vec(g)}, options
            )
            self._batch[key] = (solver, self._perf_function.map(size))
            self.build_seconds += time.perf_counter() - t0
        built: tuple[Any, Any] = self._batch[key]
        return built

    def _batch_bounds(self, size: int) -> dict[str, np.ndarray]:
        """lbx, ubx, lbg, ubg of a batch of ``size`` blocks (tiled once per size)."""
        key = ("bounds", size)
        if key not in self._batch:
            bounds = {"lbx": self.lbz, "ubx": self.ubz, "lbg": self.lbg, "ubg": self.ubg}
            self._batch[key] = {name: np.tile(value, size) for name, value in bounds.items()}
        tiled: dict[str, np.ndarray] = self._batch[key]
        return tiled

    def _chunk(self, left: int) -> int:
        """Size of the next chunk for ``left`` blocks: full large chunks, then the least padding."""
        sizes = self.BATCH_SIZES
        if left >= sizes[-1]:
            return sizes[-1]
        for small, large in zip(sizes, sizes[1:]):
            if left <= small:
                return small
            if left <= large:
                # one large padded chunk, unless two small ones cover it
                return small if left <= 2 * small else large
        return sizes[-1]

    def solve_many(
        self,
        starts: Sequence[Design | npt.ArrayLike] | np.ndarray,
        weights: npt.ArrayLike = (1.0, 1.0),
        threshold_caps: npt.ArrayLike = BIG,
        turning_caps: npt.ArrayLike = BIG,
        lam_g0: npt.ArrayLike | None = None,
        lam_x0: npt.ArrayLike | None = None,
    ) -> list[NLPResult]:
        """Solve K independent NLPs (one per start) in a few IPOPT calls.

        The K problems are stacked into block-diagonal NLPs of
        :data:`BATCH_SIZES` blocks (CasADi ``map``; a short last chunk is padded
        with copies of its first block), which costs a fraction of K separate
        calls.  Each block is exactly the NLP of :meth:`solve` with its own
        start, weights and ε caps, so every block's optimum satisfies that
        NLP's KKT conditions to IPOPT's tolerance.  With ``lam_g0``/``lam_x0``
        (shape (K, m) and (K, 4)) the chunks are solved warm (primal-dual
        start, small barrier parameter).  A chunk that IPOPT does not solve is
        re-solved block by block with :meth:`solve`.

        Parameters
        ----------
        starts : (K, 4) designs in SI units (or a list of Designs)
        weights : (2,) or (K, 2) weights (w_turn, w_threshold)
        threshold_caps, turning_caps : scalar or (K,) ε caps [N]
        lam_g0, lam_x0 : optional multipliers to start from (CasADi convention)

        Returns
        -------
        list of NLPResult, in the order of ``starts``; ``seconds`` is the
        chunk's wall time shared equally by its blocks.
        """
        x, w, caps, params = self._stack(starts, weights, threshold_caps, turning_caps)
        k = len(x)
        if k == 0:
            return []
        z0 = np.clip(x / self.scale, self.lbz, self.ubz)
        warm = lam_g0 is not None and lam_x0 is not None
        out: list[NLPResult] = []
        i = 0
        while i < k:  # chunks of BATCH_SIZES blocks, the last one padded with copies of its first block
            size = self._chunk(k - i)
            take = min(size, k - i)
            idx = np.concatenate([np.arange(i, i + take), np.full(size - take, i)])
            args = dict(x0=z0[idx].ravel(), p=params[idx].ravel(), **self._batch_bounds(size))
            if warm:
                args["lam_g0"] = np.asarray(lam_g0, float)[idx].ravel()
                args["lam_x0"] = np.asarray(lam_x0, float)[idx].ravel()
            out += self._solve_chunk(size, warm, args, x[i : i + take], w[i : i + take], caps[i : i + take])
            i += take
        return out

    def _stack(
        self,
        designs: Sequence[Design | npt.ArrayLike] | np.ndarray,
        weights: npt.ArrayLike,
        threshold_caps: npt.ArrayLike,
        turning_caps: npt.ArrayLike,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """K designs (SI, or Designs) as a (K, 4) array with their (K, 2) weights, (K, 2) ε caps and (K, n) full
        parameter vectors (:meth:`solve_many`, :meth:`multipliers_many`)."""
        x = design_rows(designs)
        k = len(x)
        w = np.broadcast_to(np.asarray(weights, float), (k, 2))
        caps = np.column_stack(
            [
                np.broadcast_to(np.asarray(threshold_caps, float), (k,)),
                np.broadcast_to(np.asarray(turning_caps, float), (k,)),
            ]
        )
        params = np.column_stack([np.tile(self.param_values, (k, 1)), w, caps])
        return x, w, caps, params

    def _solve_chunk(
        self, size: int, warm: bool, args: dict[str, Any], x: np.ndarray, w: np.ndarray, caps: np.ndarray
    ) -> list[NLPResult]:
        """One IPOPT call of the batch solver of ``size`` blocks on ``args``; the results of its first len(x)
        blocks (SI starts ``x``, weights ``w``, ε caps ``caps``).  If IPOPT fails on the batch, each of those
        blocks is solved alone (:meth:`solve`)."""
        solver, perf = self._batch_solver(size, warm)
        ng = len(self.lbg)
        t0 = time.perf_counter()
        with _quiet():
            sol = solver(**args)
        check_interrupt()
        seconds = time.perf_counter() - t0
        stats = solver.stats()
        if not bool(stats.get("success", False)):
            return [self.solve(x[j], w[j], caps[j, 0], caps[j, 1]) for j in range(len(x))]
        zs = np.asarray(sol["x"]).reshape(size, 4)
        gs = np.asarray(sol["g"]).reshape(size, ng)
        lg = np.asarray(sol["lam_g"]).reshape(size, ng)
        lx = np.asarray(sol["lam_x"]).reshape(size, 4)
        values = np.vstack([np.asarray(v).ravel() for v in perf(zs.T, np.tile(self.param_values[:, None], (1, size)))])
        viol = np.maximum(np.max(self.lbg - gs, axis=1), np.max(gs - self.ubg, axis=1)).clip(min=0.0)
        status, iterations = str(stats.get("return_status")), int(stats.get("iter_count", -1))
        return [
            NLPResult(
                design=Design.from_array(zs[j] * self.scale),
                success=viol[j] <= 1e-6 and bool(np.all(np.isfinite(zs[j]))),
                status=status,
                objective=float(weighted(values[0, j], values[1, j], w[j])),
                lam_g=lg[j].copy(),
                lam_x=lx[j].copy(),
                iterations=iterations,
                seconds=seconds / len(x),
                z=zs[j].copy(),
            )
            for j in range(len(x))
        ]

    def multipliers_many(
        self,
        designs: Sequence[Design | npt.ArrayLike] | np.ndarray,
        weights: npt.ArrayLike = (1.0, 0.0),
        threshold_caps: npt.ArrayLike = BIG,
        turning_caps: npt.ArrayLike = BIG,
        tol: float = 1e-9,
    ) -> tuple[np.ndarray, np.ndarray]:
        """KKT multipliers (lam_g (K, m), lam_x (K, 4), CasADi convention) of K designs taken as optima.

        The active set is read off the designs (bounds and constraints within ``tol``, scaled), and the
        multipliers solve ∇J + J_gᵀ λ_g + λ_x = 0 on it in least squares; a warm start of
        :meth:`solve_many` from a known optimum and these multipliers needs only a few iterations.
        """
        x, _, _, params = self._stack(designs, weights, threshold_caps, turning_caps)
        k, ng = len(x), len(self.lbg)
        z = np.clip(x / self.scale, self.lbz, self.ubz)
        grad, jac, g = self._kkt.map(k)(z.T, params.T)
        grad = np.asarray(grad).T.reshape(k, 4)
        jac = np.asarray(jac).reshape(ng, k, 4).transpose(1, 0, 2) if ng else np.zeros((k, 0, 4))
        g = np.asarray(g).T.reshape(k, ng)
        active = np.hstack(
            [
                (np.abs(g - self.lbg) <= tol) | (np.abs(g - self.ubg) <= tol),
                (np.abs(z - self.lbz) <= tol) | (np.abs(z - self.ubz) <= tol),
            ]
        )
        normals = np.concatenate([jac, np.broadcast_to(np.eye(4), (k, 4, 4))], axis=1)  # of constraints, bounds
        lam = np.zeros((k, ng + 4))
        for i, cols in enumerate(np.flatnonzero(row) for row in active):
            if len(cols):
                lam[i, cols] = np.linalg.lstsq(normals[i, cols].T, -grad[i], rcond=None)[0]
        return lam[:, :ng], lam[:, ng:]

    def objectives(
        self, design: Design, overrides: dict[str, float] | None = None
    ) -> tuple[float, float, float, float]:
        """(F_turn [N], P [N], V_c [m/s], R_s [m]) of a design, through the same CasADi graph."""
        phys = self.parameter_vector(overrides=overrides)[: self.n_phys]
        f, p, v, r = (float(v) for v in self._perf_function(design.as_array() / self.scale, phys))
        return f, p, v, r

    def objectives_many(self, designs: Sequence[Design | npt.ArrayLike] | np.ndarray) -> np.ndarray:
        """(N, 4) array of (F_turn, P, V_c, R_s) of N designs (SI array or Designs), one call of the same graph.

        Row i equals :meth:`objectives` of design i (the same CasADi function, evaluated column by column).
        """
        x = design_rows(designs)
        if not len(x):
            return np.zeros((0, 4))
        out = self._perf_function((x / self.scale).T, self.param_values)
        return np.vstack([np.asarray(v).reshape(-1) for v in out]).T

    def weighted(self, design: Design, weights: npt.ArrayLike) -> float:
        """J = w_turn F_turn + w_threshold P [N]."""
        f, p, _, _ = self.objectives(design)
        return float(weighted(f, p, weights))

    def sensitivities(
        self,
        result: NLPResult,
        weights: npt.ArrayLike = (1.0, 1.0),
        threshold_cap: float = BIG,
        turning_cap: float = BIG,
    ) -> dict[str, float]:
        """d log J / d log p at an optimum for every fixed parameter and active bound.

        Envelope theorem: dJ*/dp = ∂L/∂p with L = f + λ_gᵀ g (the bounds on x do
        not depend on p).  For an active variable bound b, dJ*/db = −λ_x/scale.
        J is the objective actually minimised (weighted sum; F_turn on ε-points).
        """
        p = self.parameter_vector(weights, threshold_cap, turning_cap)
        z = result.z if result.z is not None else self.to_z(result.design)
        grad = np.asarray(self._dlag_dp(z, p, result.lam_g)).ravel()
        f_scaled = self.weighted(result.design, weights) / weighted(self.f_ref, self.p_ref, weights)
        if f_scaled <= 0:
            return {}
        out = {name: float(g * v / f_scaled) for name, g, v in zip(self.param_names, grad, self.param_values)}
        for i, var in enumerate(VARIABLES):
            lam = result.lam_x[i]
            if abs(lam) < 1e-9 or self.lbz[i] == self.ubz[i]:
                continue
            side = "max" if lam > 0 else "min"
            bound = (self.ubz if lam > 0 else self.lbz)[i] * self.scale[i]
            if bound == 0:
                continue
            out[f"{var}.{side}"] = float(-lam * bound / self.scale[i] / f_scaled)
        return out


# --------------------------------------------------------------------------- multi-start


SOBOL_FILE = Path(__file__).resolve().parents[2] / "data" / "sobol_d4_seed0.npy"
"""``scipy.stats.qmc.Sobol(d=4, scramble=True, seed=0).random(1024)``, stored exactly as float64 in NumPy's ``.npy``
format (tests/solvers/test_closed_form.py checks that it is a Sobol net): the default sample, read without importing
scipy.stats (0.7 s of CPU)."""


@functools.lru_cache(maxsize=1)
def _stored_sobol() -> np.ndarray:
    unit: np.ndarray = np.load(SOBOL_FILE, allow_pickle=False)
    unit.setflags(write=False)
    return unit


def sample_designs(problem: Problem, n: int = 1024, seed: int = 0) -> np.ndarray:
    """A scrambled Sobol sample of the design box, shape (n, 4), SI units.

    The points of ``scipy.stats.qmc.Sobol(d=4, scramble=True, seed=seed).random(n)``; the default
    (n = 1024, seed 0) is read from :data:`SOBOL_FILE`.
    """
    if n == 1024 and seed == 0 and SOBOL_FILE.exists():
        unit = _stored_sobol()
    else:
        from scipy.stats import qmc

        unit = qmc.Sobol(d=4, scramble=True, seed=seed).random(n)
    lo = problem.lower().as_array()
    hi = problem.upper().as_array()
    designs: np.ndarray = lo + unit * (hi - lo)
    return designs


def best_starts(
    problem: Problem,
    weights: Sequence[float],
    k: int = 4,
    n: int = 1024,
    threshold_cap: float = BIG,
    seed: int = 0,
    samples: np.ndarray | None = None,
) -> list[np.ndarray]:
    """The k best sample points by weighted objective among the (least) infeasible.

    Also adds the corners of the two competing families (pure groove, pure damper)
    at maximum trail, which is where the optima of this problem live.
    """
    x = sample_designs(problem, n, seed) if samples is None else samples
    values = problem.evaluate(x)
    viol = values.violation() + np.maximum(0.0, values.threshold_force / threshold_cap - 1)
    j = values.J(weights)
    feasible = viol <= 0
    order = np.argsort(j[feasible])[:k] if np.any(feasible) else np.array([], int)
    starts = [x[feasible][i] for i in order]
    if len(starts) < k:
        starts += [x[i] for i in np.argsort(viol)[: k - len(starts)]]
    lo, hi = problem.lower(), problem.upper()
    mid_d = (lo.diameter + hi.diameter) / 2
    starts.append(Design(hi.trail, mid_d, hi.groove, lo.damping).as_array())  # grooved family
    starts.append(Design(hi.trail, mid_d, lo.groove, hi.damping).as_array())  # damped family
    return starts


# --------------------------------------------------------------------------- public API


def solve_best(
    nlp: CasterNLP,
    starts: Sequence[Design | npt.ArrayLike],
    weights: Sequence[float] = (1.0, 1.0),
    threshold_cap: float = BIG,
    turning_cap: float = BIG,
) -> tuple[NLPResult | None, list[NLPResult]]:
    """Solve from every start; return the best successful result and all results."""
    results = [nlp.solve(s, weights, threshold_cap, turning_cap) for s in starts]
    good = [r for r in results if r.success]
    return (min(good, key=lambda r: r.objective) if good else None), results


def max_critical_speed(problem: Problem) -> tuple[float, Design, list[str]]:
    """Highest V_c reachable inside the bounds (and swept-radius limit), its design, active bounds.

    Used to diagnose an infeasible target speed.  Solved with IPOPT from several starts.
    """
    lo, hi = problem.lower().as_array(), problem.upper().as_array()
    scale = np.maximum(hi, np.array(parameters.SCALES))
    z = ca.SX.sym("z", 4)
    x = z * ca.DM(scale)
    perf = performance(**parameters.named(x), conditions=problem.conditions)
    g = []
    if problem.swept_radius_max is not None:
        g.append(perf["swept_radius"] / problem.swept_radius_max - 1)
    nlp = {"x": z, "f": -perf["confident_speed"], "g": ca.vertcat(*g) if g else ca.SX(0, 1)}
    solver = ca.nlpsol("vmax", "ipopt", nlp, {**QUIET, "error_on_fail": False})
    best: tuple[float, Design] | None = None
    for start in sample_designs(problem, 16, seed=1):
        with _quiet():
            sol = solver(
                x0=np.clip(start / scale, lo / scale, hi / scale),
                lbx=lo / scale,
                ubx=hi / scale,
                ubg=0 if g else [],
                lbg=-np.inf if g else [],
            )
        check_interrupt()
        v = -float(sol["f"])
        if best is None or v > best[0]:
            best = (v, Design.from_array(np.asarray(sol["x"]).ravel() * scale))
    assert best is not None  # 16 starts: at least one result
    v, design = best
    arr, free = design.as_array(), lo != hi
    at_max = free & (np.abs(arr - hi) <= 1e-6 * np.maximum(1.0, np.abs(hi)))
    at_min = free & ~at_max & (np.abs(arr - lo) <= 1e-6 * np.maximum(1.0, np.abs(lo)))
    active = [
        f"variables.{v}.{side}"
        for v, a, b in zip(VARIABLES, at_max, at_min)
        for side, on in (("max", a), ("min", b))
        if on
    ]
    if problem.swept_radius_max is not None and design.trail + design.diameter / 2 >= problem.swept_radius_max * (
        1 - 1e-6
    ):
        active.append("constraints.swept_radius_max")
    return v, design, active
