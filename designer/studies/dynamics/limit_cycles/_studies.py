"""The studies of results/simulation: bifurcation diagram, Table 1, the (K, N) map, μ."""

from __future__ import annotations

import itertools
import math
import time

import numpy as np

from designer.studies.dynamics.limit_cycles._system import caster_dynamics
from designer.studies.dynamics._work import ARGUMENTS, bounded
from designer.studies.dynamics.limit_cycles._knock import knock_onset_speed, knock_safe_speed, scanned_onset_speed
from designer.studies.dynamics.limit_cycles._orbits import continue_orbits, speed_sweep, stable_orbit
from designer.studies.dynamics.limit_cycles._results import (
    BifurcationDiagram,
    Branch,
    ErrorStats,
    FrictionPoint,
    LimitCycleStudy,
    MapCell,
    PeriodicOrbit,
    RollingLimitCheck,
    StiffnessMassMap,
    Table1Comparison,
    Table1Row,
)
from designer.data.paper import (
    APPENDIX_C_CASE,
    BARE_FORK_DAMPING,
    TABLE1,
    TABLE1_STABLE_UP_TO,
    TABLE1_TRAIL,
    table1_wheel,
)
from designer.boundary import Count, Quantities, Quantity, checked
from designer.errors import InputError, SolverError
from designer.model import Conditions, Design, critical_speed
from designer.physics.inertia import Fixed
from designer.physics.shimmy import DynamicsParameters
from designer.physics.tyre import TyreParameters


@checked(
    **ARGUMENTS,
    speed_range=Quantities("speed", 2),
    reference_speed=Quantity("speed", optional=True),
    points=Count(2, 10_000, what="amplitudes"),
    max_amplitude=Quantity("angle"),
)
# long: the docstring documents every argument and the result (the body is under 55 lines)
@bounded("bifurcation diagram", scale="points")
def bifurcation_diagram(
    design: Design,
    conditions: Conditions = Conditions(),
    tyre: TyreParameters | None = TyreParameters(),
    speed_range: tuple[float, float] = (0.3, 4.0),
    reference_speed: float | None = None,
    points: int = 24,
    max_amplitude: float = 3.0,
    progress=None,
) -> BifurcationDiagram:
    """Periodic orbits against speed: amplitude of the unstable (knock threshold) and stable (sustained
    shimmy) branches, with their Floquet multipliers.

    The unstable branch is followed in amplitude (:func:`continue_orbits`) from the amplitude whose
    describing-function speed is ``speed_range[1]`` up to ``max_amplitude`` or the first failures (round the
    fold it turns stable); the stable branch is found by simulating large knocks at ``reference_speed``
    (default Eq. 7's V_c) and followed in speed down to its fold and up to ``speed_range[1]``.

    Parameters
    ----------
    design, conditions : the caster (M_f = c_f θ0)
    tyre : the brush tyre (None: the paper's rolling tyre, which has no stable branch)
    speed_range : (low, high) speeds of the diagram [m/s]
    reference_speed : where the stable branch is first looked for [m/s]
    points : amplitudes on the unstable branch
    max_amplitude : largest amplitude followed [rad] (the small-angle model is not valid up there)

    Returns
    -------
    BifurcationDiagram
        ``branches`` [{"kind": "stable" | "unstable", "speed": [m/s], "amplitude": [rad]}],
        ``orbits`` (each a :class:`PeriodicOrbit`: speed, amplitude, period, multipliers, closure),
        ``fold_speed`` [m/s] (lowest speed of a periodic orbit: below it every knock decays),
        ``eq7_critical_speed`` [m/s], ``frequency`` (Eq. 15B) [rad/s], ``stable_at_reference`` (an orbit or
        None), ``max_closure`` [rad]; ``to_dict()`` gives the dict this function returned before.
    """
    lo, hi = (float(v) for v in speed_range)
    if not 0 < lo < hi:
        raise InputError(f"speed_range = {speed_range!r}: expected 0 < low < high [m/s]")
    sys = caster_dynamics(design, conditions, hi, tyre)
    inertia = sys.inertia
    v7 = float(critical_speed(design.trail, inertia, design.groove, design.damping, conditions.slip_coefficient))
    ref = v7 if reference_speed is None else float(reference_speed)
    c_d_hi = inertia * hi / sys.trail - sys.groove_coefficient / hi
    a_lo = 4 * sys.friction_moment / (math.pi * sys.frequency * c_d_hi) if c_d_hi > 0 else 0.01
    amplitudes = np.geomspace(a_lo, max_amplitude, int(points))
    unstable = continue_orbits(sys, amplitudes, progress=progress)
    orbits = [o for o in unstable.orbits if lo * 0.5 <= o.speed <= hi * 1.5]
    # the stable branch (sustained shimmy): simulated large knocks at ref, followed in speed down to lo and up to
    # hi (none with the rolling tyre, tyre None)
    stable_ref = None
    stable_orbits: list[PeriodicOrbit] = []
    if tyre is not None:
        stable_ref = stable_orbit(sys.at(ref))
        if stable_ref is not None:
            down = speed_sweep(sys, np.geomspace(ref, lo, max(5, 2 * points // 3))[1:], stable_ref)
            up = speed_sweep(sys, np.geomspace(ref, hi, max(4, points // 3))[1:], stable_ref)
            stable_orbits = [*down.orbits[::-1], stable_ref, *up.orbits]
    # merge: amplitude branch (unstable part and the stable part near the fold) + the speed sweep
    unstable_part = [o for o in orbits if not o.stable]
    fold_part = [o for o in orbits if o.stable and (not stable_orbits or o.amplitude < stable_orbits[0].amplitude)]
    stable_all = sorted(fold_part + stable_orbits, key=lambda o: o.amplitude)
    branches = Branch(orbits=unstable_part).pieces() + Branch(orbits=stable_all).pieces()
    every = unstable_part + stable_all
    fold = min((o.speed for o in every), default=math.nan) if stable_orbits or fold_part else math.nan
    return BifurcationDiagram(
        design=design,
        model="rolling" if tyre is None else "brush tyre",
        tyre=tyre,
        inertia=float(inertia),
        friction_moment=float(sys.friction_moment),
        frequency=float(sys.frequency),
        eq7_critical_speed=v7,
        disturbance_angle=float(conditions.disturbance_angle),
        branches=branches,
        orbits=every,
        fold_speed=float(fold),
        reference_speed=ref,
        stable_at_reference=stable_ref,
        max_closure=float(max((o.closure for o in every), default=math.nan)),
        failed_amplitudes=[float(a) for a in unstable.failed],
    )


def _stats(pred, meas) -> ErrorStats:
    e = np.asarray(pred, float) / np.asarray(meas, float) - 1
    return ErrorStats(
        rms=float(np.sqrt(np.mean(e**2))), bias=float(np.mean(e)), max_abs=float(np.max(np.abs(e))), n=int(e.size)
    )


def table1_comparison(
    conditions: Conditions = Conditions(),
    tyre: TyreParameters = TyreParameters(load=160.0),
    angle: float | None = None,
    rtol: float = 0.005,
    progress=None,
) -> Table1Comparison:
    """Table 1 (test fork, T = 2 in, bare fork c_f = 1.3, B = 0): measured onset, Eq. 7, the rolling
    simulation (the paper's model, Coulomb friction) and the brush-tyre simulation, from the same knock.

    Each wheel uses its own I_w and mass M_W (tyre model); the load is Table 1's 160 N.  Errors are
    prediction/measured − 1 over wheels C–G; wheels A and B were stable up to 3.8 m/s, and a prediction
    below that is flagged.

    Returns
    -------
    Table1Comparison
        ``rows`` (per wheel a :class:`Table1Row`: key, inertia, mass, measured, eq7, rolling_sim, tyre_sim
        (+ brackets), flagged) and ``stats`` {eq7, rolling_sim, tyre_sim: :class:`ErrorStats` (rms, bias,
        max_abs, n)}; ``to_dict()`` gives the dict this function returned before.
    """

    theta = float(conditions.disturbance_angle if angle is None else angle)
    rows = []
    for i, wheel in enumerate(TABLE1):
        cond = conditions.replace(inertia=Fixed(wheel.inertia))
        design = Design(trail=TABLE1_TRAIL, diameter=wheel.diameter, groove=0.0, damping=1.3)
        rolling_sys = caster_dynamics(design, cond, 1.0, None)
        rolling = knock_onset_speed(rolling_sys, theta, rtol=rtol)
        wheel_tyre = tyre.replace(wheel_mass=wheel.mass)
        slipping = knock_onset_speed(
            caster_dynamics(design, cond, 1.0, wheel_tyre), theta, rtol=rtol, guess=rolling.speed
        )
        # Eq. 7 with c_f,eff = M_f/θ_i and the two simulated onsets
        predicted = {"eq7": rolling_sys.eq7_speed(theta), "rolling_sim": rolling.speed, "tyre_sim": slipping.speed}
        flagged = [k for k, v in predicted.items() if wheel.critical_speed is None and v < TABLE1_STABLE_UP_TO]
        rows.append(
            Table1Row(
                wheel=wheel.key,
                name=wheel.name,
                inertia=wheel.inertia,
                mass=wheel.mass,
                measured=wheel.critical_speed,
                eq7=predicted["eq7"],
                rolling_sim=rolling.speed,
                tyre_sim=slipping.speed,
                rolling_sim_bracket=[rolling.low, rolling.high],
                tyre_sim_bracket=[slipping.low, slipping.high],
                flagged=flagged,
            )
        )
        if progress is not None:
            progress(i + 1, len(TABLE1))
    measured = [r for r in rows if r.measured is not None]
    stats = {
        k: _stats([r.prediction(k) for r in measured], [r.measured for r in measured])
        for k in ("eq7", "rolling_sim", "tyre_sim")
    }
    return Table1Comparison(
        rows=rows, stats=stats, angle=theta, trail=TABLE1_TRAIL, tyre=tyre, stable_up_to=TABLE1_STABLE_UP_TO
    )


MAP_FACTORS = (0.25, 1.0, 4.0)
"""Factors on the default frame stiffness K and lateral mass N of the (K, N) map [-]."""


def stiffness_mass_map(
    casters: dict,
    conditions: Conditions = Conditions(),
    tyre: TyreParameters = TyreParameters(),
    factors=MAP_FACTORS,
    angle: float | None = None,
    rtol: float = 0.01,
    progress=None,
) -> StiffnessMassMap:
    """Onset and sustained amplitude over a grid of frame stiffness K and lateral mass N.

    For each caster and each (K, N) = (f_K K0, f_N N0): the knock onset with the rolling tyre (bisection from
    Eq. 7) and with the brush tyre (lowest sustained speed of a 13-speed scan over 0.2-4 × the measured V_c,
    refined by bisection, :func:`scanned_onset_speed`), and the stable shimmy amplitude (brush tyre) at the
    caster's measured critical speed.

    Parameters
    ----------
    casters : {name: (design, inertia [kg·m²], wheel mass [kg], measured V_c [m/s])}
    conditions : base conditions; K0, N0 from ``conditions.dynamics`` (N split 60/40 fork/bearing block)
    factors : the grid factors for K and N
    angle : knock θ_i [rad] (default θ0)

    Returns
    -------
    StiffnessMassMap
        ``rows`` (a :class:`MapCell` each: caster, K, N, f_K, f_N, ω, rolling_onset, tyre_onset,
        stable_amplitude, eq7) and the defaults K0 (``stiffness``), N0 (``lateral_mass``); ``to_dict()`` gives
        the dict this function returned before.
    """

    K0, N0 = float(conditions.dynamics.stiffness), float(conditions.dynamics.lateral_mass)
    theta = float(conditions.disturbance_angle if angle is None else angle)
    rows = []
    total = len(casters) * len(factors) ** 2
    for name, (design, inertia, mass, measured) in casters.items():
        v7 = float(critical_speed(design.trail, inertia, design.groove, design.damping, conditions.slip_coefficient))
        for fk, fn in itertools.product(factors, factors):
            dyn = DynamicsParameters(frame_stiffness=K0 * fk, fork_mass=0.6 * N0 * fn, bearing_block_mass=0.4 * N0 * fn)
            cond = conditions.replace(inertia=Fixed(inertia), dynamics=dyn)
            try:
                rolling = knock_onset_speed(caster_dynamics(design, cond, 1.0, None), theta, rtol=rtol).speed
            except SolverError:
                rolling = math.nan
            t = tyre.replace(wheel_mass=mass)
            sys_t = caster_dynamics(design, cond, 1.0, t)
            scan = scanned_onset_speed(sys_t, theta, np.geomspace(0.2, 4.0, 13) * measured, rtol=rtol)
            orb = stable_orbit(sys_t.at(measured))
            rows.append(
                MapCell(
                    caster=name,
                    stiffness=K0 * fk,
                    lateral_mass=N0 * fn,
                    stiffness_factor=fk,
                    mass_factor=fn,
                    frequency=sys_t.frequency,
                    eq7=v7,
                    measured=measured,
                    rolling_onset=rolling,
                    tyre_onset=scan.speed,
                    tyre_onset_monotone=scan.monotone,
                    tyre_onset_below_scan=scan.below_scan,
                    stable_amplitude=math.nan if orb is None else orb.amplitude,
                    stable_max_multiplier=math.nan if orb is None else orb.max_abs_multiplier,
                )
            )
            if progress is not None:
                progress(len(rows), total)
    return StiffnessMassMap(rows=rows, stiffness=K0, lateral_mass=N0, factors=list(factors), angle=theta)


def map_casters() -> dict:
    """The three casters of the (K, N) map: Appendix C (T = 2.5 in) and Table 1 wheels C and G (T = 2 in)."""

    design, conditions = appendix_c_caster()
    out = {"Appendix C": (design, conditions.inertia(design.diameter), 0.444, APPENDIX_C_CASE.critical_speed)}
    for key in ("C", "G"):
        w = table1_wheel(key)
        out[f"Table 1 {key}"] = (
            Design(TABLE1_TRAIL, w.diameter, 0.0, BARE_FORK_DAMPING),
            w.inertia,
            w.mass,
            w.critical_speed,
        )
    return out


def friction_sensitivity(
    design: Design,
    conditions: Conditions,
    speed: float,
    coefficients=(0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0),
    tyre: TyreParameters = TyreParameters(),
) -> list[FrictionPoint]:
    """Fold and stable shimmy amplitude for several tyre friction coefficients μ [-].

    For each μ: the orbit branch followed in amplitude (0.03–3 rad); the fold (lowest speed of any orbit
    [m/s] and its amplitude [rad], the smallest sustained shimmy) and the stable amplitude at ``speed``:
    one :class:`FrictionPoint` per μ (``to_dict()``: the dict this function gave before).
    """
    rows = []
    for mu in coefficients:
        sys = caster_dynamics(design, conditions, speed, tyre.replace(friction_coefficient=float(mu)))
        branch = continue_orbits(sys, np.geomspace(0.03, 3.0, 26))
        fold = min(branch.orbits, key=lambda o: o.speed) if any(o.stable for o in branch.orbits) else None
        orb = stable_orbit(sys, angles=(0.6, 1.2, 0.3, 2.4, 0.15))
        rows.append(
            FrictionPoint(
                friction_coefficient=float(mu),
                fold_speed=math.nan if fold is None else fold.speed,
                fold_amplitude=math.nan if fold is None else fold.amplitude,
                stable_amplitude=math.nan if orb is None else orb.amplitude,
                max_abs_multiplier=math.nan if orb is None else orb.max_abs_multiplier,
                closure=math.nan if orb is None else orb.closure,
            )
        )
    return rows


def appendix_c_caster() -> tuple[Design, Conditions]:
    """The caster of Appendix C / Fig. 1C: T = 2.5 in, bare fork, I_w from V_c = 2.53 m/s by Eq. 7 (B = 0)."""

    case = APPENDIX_C_CASE
    i_c = 4 * BARE_FORK_DAMPING * case.trail**2 / (math.pi * case.critical_speed**2)
    return Design(case.trail, 0.2, 0.0, BARE_FORK_DAMPING), Conditions(inertia=Fixed(i_c))


def limit_cycle_study(progress=None, quick: bool = False) -> LimitCycleStudy:
    """Everything the results/simulation limit-cycle report shows; minutes of CPU.

    Appendix C caster: bifurcation diagrams (brush tyre and rolling tyre), stable amplitude against the
    measured 8° and its dependence on μ, knock-safe speeds (θ0, 2θ0); Table 1 comparison; (K, N) map.
    ``quick`` uses a 3 × 3 map and fewer orbits (for checking the pipeline, not for results).  Returns a
    :class:`LimitCycleStudy` (``to_dict()``: the dict this function returned before).
    """

    say = progress or (lambda text: None)
    t0 = time.perf_counter()
    design, cond = appendix_c_caster()
    say("bifurcation diagram (brush tyre)")
    bif = bifurcation_diagram(
        design,
        cond,
        TyreParameters(),
        speed_range=(0.3, 4.0),
        reference_speed=APPENDIX_C_CASE.critical_speed,
        points=12 if quick else 28,
    )
    say("bifurcation diagram (rolling tyre)")
    roll = bifurcation_diagram(design, cond, None, speed_range=(0.3, 4.0), points=8 if quick else 16, max_amplitude=1.5)
    say("stable amplitude against μ")
    fric = friction_sensitivity(
        design, cond, APPENDIX_C_CASE.critical_speed, (0.15, 0.7) if quick else (0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0)
    )
    say("knock-safe speeds")
    theta0 = float(cond.disturbance_angle)
    knock = {}
    for label, tyre in (("rolling", None), ("brush", TyreParameters())):
        for k in (1, 2):
            knock[f"{label}_{k}theta0"] = knock_safe_speed(design, cond, angle=k * theta0, tyre=tyre, exact=False)
    say("rolling limit of the brush tyre")
    from designer.studies.dynamics._simulate import onset_speed as _today_onset  # today's model (imports this room)

    factor = 30.0
    today = _today_onset(design, cond, rtol=0.002)
    limit = knock_onset_speed(
        caster_dynamics(design, cond, 1.0, TyreParameters().rolling_limit(factor)),
        theta0,
        rtol=0.002,
        guess=today.speed,
    )
    rolling_limit = RollingLimitCheck(
        factor=factor,
        today=today.speed,
        tyre_limit=limit.speed,
        today_bracket=[today.low, today.high],
        tyre_limit_bracket=[limit.low, limit.high],
    )
    say("Table 1")
    table = table1_comparison(rtol=0.01 if quick else 0.005)
    say("(K, N) map")
    kn = stiffness_mass_map(
        map_casters(),
        progress=None if progress is None else (lambda i, n: progress(f"map {i}/{n}")),
    )
    return LimitCycleStudy(
        bifurcation=bif,
        rolling=roll,
        friction=fric,
        knock_safe=knock,
        table1=table,
        rolling_limit=rolling_limit,
        stiffness_mass_map=kn,
        measured_speed=APPENDIX_C_CASE.critical_speed,
        measured_amplitude=APPENDIX_C_CASE.steady_amplitude,
        seconds=time.perf_counter() - t0,
        quick=quick,
    )
