"""Knock onset and knock-safe speed: bisection in speed on simulated knocks."""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable

from designer.studies.dynamics.limit_cycles._results import KnockSafe, OnsetBracket, OnsetScan
from designer.studies.dynamics.limit_cycles._system import CasterDynamics, caster_dynamics, simulate_knock
from designer.boundary import Quantity, checked
from designer.errors import InputError, SolverError
from designer.studies.dynamics._work import ARGUMENTS, bisect_speed, bounded, bracket_speed
from designer.model import Conditions, Design
from designer.physics.inertia import Fixed
from designer.physics.tyre import TyreParameters

FAST_BRACKET = (0.96, 1.04)
"""Start of the knock-safe bisection around Eq. 7's V_c (c_f,eff = M_f/θ_i) [-]: the simulated onset of the
rolling model lies close to that guess, for θ0 and 2 θ0, and :func:`knock_onset_speed` widens a bracket that
does not hold it."""


@bounded("knock onset search")
def knock_onset_speed(
    sys: CasterDynamics,
    angle: float,
    angular_velocity: float = 0.0,
    rtol: float = 0.005,
    cycles: float = 30.0,
    guess: float | None = None,
    bracket: tuple[float, float] = (0.8, 1.25),
    widen: float = 1.5,
    tries: int = 12,
    exact: bool = False,
) -> OnsetBracket:
    """Lowest speed at which a knock θ_i is sustained (bisection in log V) [m/s].

    The bracket starts at ``guess`` (default Eq. 7's V_c with c_f,eff = M_f/θ_i) × ``bracket``, widened
    × ``widen`` (at most ``tries`` times, within the model's speeds: :func:`~designer.studies.dynamics._work.bracket_speed`)
    until it holds a decaying and a sustained speed; bisection stops
    when high/low − 1 < ``rtol``.  ``exact``: simulate with the closed-form integration of the rolling model
    (:func:`~designer.studies.dynamics.limit_cycles._system.simulate_knock`).
    """
    v7 = sys.eq7_speed(angle)
    guess = v7 if guess is None else guess
    cache: dict[float, bool] = {}  # one knock simulation a speed: len(cache) counts them

    def sustained(v: float) -> bool:
        if v not in cache:
            cache[v] = simulate_knock(sys.at(v), angle, angular_velocity, cycles, exact=exact).shimmy
        return cache[v]

    low, high = bracket_speed(sustained, bracket[0] * guess, bracket[1] * guess, widen, tries, v7, "knock onset")
    low, high = bisect_speed(sustained, low, high, rtol)
    return OnsetBracket(low=low, high=high, evaluations=len(cache))


@checked(
    **ARGUMENTS,
    angle=Quantity("angle", optional=True),
    rtol=Quantity("dimensionless"),
)
@bounded("knock-safe speed")
def knock_safe_speed(
    design: Design,
    conditions: Conditions = Conditions(),
    angle: float | None = None,
    tyre: TyreParameters | None = None,
    rtol: float = 0.005,
    exact: bool = True,
) -> float:
    """Highest speed at which a knock of θ_i decays instead of growing into shimmy [m/s].

    The low end of the knock-onset bracket (:func:`knock_onset_speed`, relative width ``rtol``): the knock
    was simulated and seen to decay there.  Rolling tyre (``exact``): each knock is integrated in closed
    form and the bisection starts at Eq. 7 × :data:`FAST_BRACKET`, a few simulations and 0.02–0.05 s of
    CPU on an idle machine.  ``exact=False`` (and the brush tyre) integrate with DOP853 from Eq. 7 × [0.8,
    1.25] (about 9 simulations, 0.3–1 s of CPU with the rolling tyre, seconds with the brush tyre): the
    results/simulation study uses that; the two agree within ``rtol`` (tests/studies/dynamics/test_limit_cycles.py).

    Parameters
    ----------
    design : T [m], d [m], B [m], c_f [N·m/rad]
    conditions : K_s, θ0 (M_f = c_f θ0), inertia model, dynamics (K, N)
    angle : knock θ_i [rad]; default the design θ0 of the conditions (20°); the report also gives 2 θ0
    tyre : None for the paper's rolling tyre (Eq. 6B; the default, as for Eq. 7), else the brush tyre
    rtol : relative width of the bracket [-]
    exact : closed-form integration and the narrow start bracket (rolling tyre only; ignored with a tyre)

    Returns
    -------
    float
        The speed [m/s]; 0.0 when the knock is sustained at every speed down to 1 % of Eq. 7's V_c (no safe speed).
    """
    theta = float(conditions.disturbance_angle if angle is None else angle)
    if not math.isfinite(theta) or not 0 < theta < math.pi / 2:
        raise InputError(f"angle = {angle!r}: knock angle must be between 0 and 90 deg (in rad)")
    sys = caster_dynamics(design, conditions, 1.0, tyre)
    try:
        if exact and tyre is None:
            return _rolling_knock_safe(sys, theta, float(rtol))
        return float(knock_onset_speed(sys, theta, rtol=rtol).low)
    except SolverError:
        # not bracketed: a knock that is sustained even at a crawl has no safe speed
        if simulate_knock(sys.at(0.01 * sys.eq7_speed(theta)), theta, exact=exact).shimmy:
            return 0.0
        raise


@functools.lru_cache(maxsize=512)
def _rolling_knock_safe(sys: CasterDynamics, theta: float, rtol: float) -> float:
    """:func:`knock_safe_speed` of the rolling model, cached by caster (its dynamics at 1 m/s), knock and
    rtol: the same design on two cards, two problems of ``designer pareto --all`` or a studio redraw
    simulates once.  A bracket that fails raises (not cached)."""
    return float(knock_onset_speed(sys, theta, rtol=rtol, bracket=FAST_BRACKET, widen=1.15, tries=32, exact=True).low)


def knock_safe_speeds(
    designs: Iterable[Design],
    conditions: Conditions = Conditions(),
    rtol: float = 0.005,
    inertias: Iterable[float | None] | None = None,
) -> list[KnockSafe]:
    """Knock-safe speeds of a few designs (the recommendation card): knocks of θ0 and 2 θ0, rolling tyre.

    Each design costs two bisections of :func:`knock_safe_speed` with the closed-form integration (about
    7 simulations and 0.02 s of CPU each on an idle machine; a design seen before in this process is
    taken from the cache); compute it for the designs a page shows, not for a whole front.

    Parameters
    ----------
    designs : iterable of Design (T [m], d [m], B [m], c_f [N·m/rad])
    conditions : θ0 [rad] (``disturbance_angle``), K_s, inertia model, dynamics (K, N)
    rtol : relative width of the onset bracket [-]
    inertias : optional I_w per design [kg·m²] (None entries: the conditions' inertia model), e.g. a
        catalogue wheel's measured I_w, the one its V_c used

    Returns
    -------
    list of KnockSafe
        One per design: ``knock_safe_speed`` (θ0 knock) and ``knock_safe_speed_double`` (2 θ0 knock; None
        when 2 θ0 ≥ 90°) [m/s] (None with ``knock_safe_error`` when the onset could not be bracketed),
        ``knock_angle`` θ0 [rad], ``knock_safe_rtol`` [-]; ``to_dict()`` gives the dict of before.
    """
    theta0 = float(conditions.disturbance_angle)
    items = list(designs)
    known: list[float | None] = [None] * len(items) if inertias is None else list(inertias)
    out: list[KnockSafe] = []
    for design, inertia in zip(items, known):
        cond = conditions
        if inertia is not None and math.isfinite(float(inertia)):
            cond = conditions.replace(inertia=Fixed(float(inertia)))
        speeds: list[float | None] = []
        error = None
        for factor in (1.0, 2.0):
            speeds.append(None)
            if factor * theta0 >= math.pi / 2:
                continue
            try:
                speeds[-1] = knock_safe_speed(design, cond, angle=factor * theta0, rtol=rtol)
            except SolverError as exc:
                error = str(exc)
        out.append(
            KnockSafe(
                knock_angle=theta0,
                knock_safe_rtol=rtol,
                knock_safe_speed=speeds[0],
                knock_safe_speed_double=speeds[1],
                knock_safe_error=error,
            )
        )
    return out


def scanned_onset_speed(sys: CasterDynamics, angle: float, speeds: Iterable[float], rtol: float = 0.01) -> OnsetScan:
    """Lowest speed at which a knock θ_i [rad] is sustained, from a scan over ``speeds`` [m/s] then bisection.

    Unlike :func:`knock_onset_speed` it does not assume one transition: the brush tyre on a stiff frame has
    islands of shimmy in speed.  Islands narrower than the scan spacing can be missed.

    Returns an :class:`OnsetScan`: ``speed`` [m/s] (NaN if sustained nowhere in the scan), ``monotone``
    (sustained at every scanned speed above the first), ``below_scan`` (sustained already at the lowest scanned
    speed), ``evaluations``.
    """
    scan = [float(v) for v in speeds]
    outcomes = [simulate_knock(sys.at(v), angle).shimmy for v in scan]
    n = len(scan)
    if not any(outcomes):
        return OnsetScan(speed=math.nan, monotone=True, below_scan=False, evaluations=n)
    k = outcomes.index(True)
    monotone = all(outcomes[k:])
    if k == 0:
        return OnsetScan(speed=scan[0], monotone=monotone, below_scan=True, evaluations=n)

    def sustained(v: float) -> bool:
        nonlocal n
        n += 1
        return simulate_knock(sys.at(v), angle).shimmy

    low, high = bisect_speed(sustained, scan[k - 1], scan[k], rtol)
    return OnsetScan(speed=math.sqrt(low * high), monotone=monotone, below_scan=False, evaluations=n)
