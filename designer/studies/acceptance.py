"""Joint acceptance limits: a box of part limits inside which every caster meets the risk bound.

The one-at-a-time limits of :mod:`designer.studies.spec` are each where P(shimmy) = α with every *other* part at
nominal: parts inspected one by one can pass together and still shimmy.  A drawing's tolerances are chosen so that
any part inside all of them works (worst-case stack-up); this module gives that box for shimmy.

For one caster (T, B, c_f, I_w, d) the box has one interval per inspectable part:

- trail T in [trail_min, trail_max]: trail_min is a **risk** limit; trail_max is the **footrest** limit
  T + d/2 <= R_max with the diameter at the box's largest, diameter_max (geometric, not a risk limit: P falls as
  T grows); without a swept-radius limit there is no trail maximum;
- groove B >= groove_min, bearing friction moment M_f = c_f θ0 >= friction_moment_min, measured wheel inertia
  I_w <= wheel_inertia_max: risk limits;
- diameter d <= diameter_max when the footrest depends on it (a swept-radius limit: d + its stated ±, the nominal
  when none is stated) and >= diameter_min when the problem states a diameter tolerance (the stated ±).

**The risk corners.**  A corner's wheel is a measured wheel at the box's I_w bound (the measured-wheel law of
:func:`designer.physics.uncertainty.shimmy_probability_exact`, as the one-at-a-time I_w limit uses): its diameter
then does not enter the risk (Eq. 7 has no d).  P(V_c,true < V_req) is monotone in every risk part: the measured
wheel's linear part (model error and σ_I) does not depend on the caster (log V_c's slope in log I_w is −1/2
whatever B), and at every quadrature node of (ξ_c, ξ_K) Eq. 7's V_c² = 4 c_f T²/(π I_w) + K_s B² T/(2 I_w) rises
with T, B and c_f and falls with I_w.  So P falls as T, B or M_f grows and rises with I_w, and the worst corner is
(trail_min, groove_min, friction_moment_min, wheel_inertia_max).  :func:`joint_limits_many` still evaluates all 2^k
corners (k the parts with a window: each risk part's limit and its mirror about nominal, the trail's footrest
maximum) in one array call of the exact law and records whether the worst of them is that corner.

**The box's shape.**  Each risk part's window (nominal − limit, relative to nominal) is s·w_p: w_p the part's
stated relative tolerance when the problem has ``[tolerances]`` ("tolerances": ± trail / T, ± groove / B, the
friction moment's ±; the wheel's accepted I_w over nominal, or for a catalogue wheel the power law's I_w at
d + ± d over that at d; a part the tolerances leave out gets their mean), else w_p = 1 for every part ("equal
relative": the largest equal relative window).  The scale s is the root of P(worst corner(s)) = α (bracketed,
on Φ⁻¹(P) − Φ⁻¹(α) like the one-at-a-time limits); s >= 1 means the stated tolerances fit inside the box.
"""

from __future__ import annotations

import itertools
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from designer.physics.acceptance import friction_moment, measured_probabilities, probit, probits
from designer.physics.roots import bracketed_roots
from designer.physics.uncertainty import Uncertainty
from designer.reprs import Key, Record
from designer.units import limit_shown

if TYPE_CHECKING:
    from designer.model import Design
    from designer.problem import Problem

RISK_KEYS = ("trail_min", "groove_min", "friction_moment_min", "wheel_inertia_max")
"""The box's risk limits (P = α at the worst corner)."""

BOX_KEYS = ("trail_min", "trail_max", "groove_min", "friction_moment_min", "wheel_inertia_max")
"""The box's keys that are always there (SI); ``diameter_min``/``diameter_max`` when the diameter is in the box."""

SCALE_RTOL = 1e-7
"""Relative tolerance of the box's scale [-]: the worst corner's P is α to about 1e-6 relative (stepped inside, never
above), far finer than any part's measurement, in about 8 quadratures instead of 12 at the limits' 1e-9."""

SHAPES = {
    "tolerances": "in proportion to the stated [tolerances]",
    "equal relative": "the largest equal relative window (no [tolerances] stated)",
}
"""How the box is shaped, in words."""


@dataclass(frozen=True, kw_only=True)
class JointLimits(Record):
    """The joint acceptance box of one caster (SI): any caster whose parts all lie inside meets P(shimmy) <= α.

    Attributes
    ----------
    trail_min, trail_max : T's interval [m] (on the fork offset of a tilted stem); trail_max None without a
        swept-radius limit (P falls as T grows: no risk maximum)
    groove_min : B's least [m]
    friction_moment_min : M_f = c_f θ0's least [N·m]
    wheel_inertia_max : the largest measured wheel inertia [kg·m²]
    diameter_min, diameter_max : d's interval [m] when the diameter is in the box (None: not in the box)
    nominal : {part: nominal value [SI]}
    protects : {key: "risk" (P = α at the worst corner) or "footrest" (T + d/2 <= R_max)}
    shape : "tolerances" or "equal relative" (:data:`SHAPES`)
    weights : {part: w_p} the relative window per unit scale
    scale : s, the box's windows are s·w_p relative to nominal (>= 1: the stated tolerances fit inside)
    probability : P(V_c,true < V_req) at the worst corner [-] (α up to the root's tolerance)
    corners : how many corners were evaluated (2^k)
    corner_max : the largest P over all corners [-]
    monotone : the largest P is at the corner of every risk part's limit (P monotone in each part)
    alpha : α [-]
    required_speed : the speed of the bound [m/s] (V_req; divided by a retrofit's calibration)
    notes : {key: sentence} for a limit that leaves no window (or none at all) and the fix it suggests
    """

    trail_min: float
    trail_max: float | None
    groove_min: float
    friction_moment_min: float
    wheel_inertia_max: float
    diameter_min: float | None
    diameter_max: float | None
    nominal: dict[str, float]
    protects: dict[str, str]
    shape: str
    weights: dict[str, float]
    scale: float
    probability: float
    corners: int
    corner_max: float
    monotone: bool
    alpha: float
    required_speed: float
    notes: dict[str, str] = field(default_factory=dict)

    _keys = (
        *BOX_KEYS,
        Key("diameter_min", omit="none"),
        Key("diameter_max", omit="none"),
        "protects",
        "shape",
        Key("shape_text", lambda s: SHAPES[s.shape]),
        "scale",
        "weights",
        Key("worst_corner_probability", "probability"),
        "corners",
        "corner_max",
        "monotone",
        "alpha",
        "required_speed",
        Key("notes", omit="empty"),
    )
    """The JSON record (SI): the box's limits by part and side, what each protects, the shape and scale, the
    worst corner's P and the check over all 2^k corners."""

    @property
    def limits(self) -> dict[str, float | None]:
        """{key: value [SI]} of the box (the diameter's only when it is in the box)."""
        keys = (*BOX_KEYS, "diameter_min", "diameter_max")
        return {k: getattr(self, k) for k in keys if k in BOX_KEYS or getattr(self, k) is not None}

    def window(self, part: str) -> float:
        """The box's relative window of a risk part below (trail, groove, friction moment) or above (wheel
        inertia) nominal [-]: s·w_p."""
        return self.scale * self.weights.get(part, 0.0)

    def contains(self, parts: dict[str, float]) -> bool:
        """Whether a measured caster {trail, groove, friction_moment, wheel_inertia[, diameter]} [SI] lies inside
        (to 1e-9 relative: a diameter written in mm and the box's in inches agree)."""
        lim, eps = self.limits, 1e-9
        for part, (low, high) in _BOX_PARTS.items():
            if part == "diameter" and part not in parts:
                continue
            if low is not None and lim.get(low) is not None and not parts[part] >= lim[low] * (1 - eps):
                return False
            if high is not None and lim.get(high) is not None and not parts[part] <= lim[high] * (1 + eps):
                return False
        return True

    def cells(self, units: str = "mm") -> dict[str, str]:
        """{part: the box's interval as an inspector reads it, lengths in the problem's ``units`` first} ("min
        54.91 mm (2.162 in) [risk]; max 63.50 mm ... [footrest; no window above nominal]"), rounded toward the safe
        side (:func:`designer.units.limit_shown`); "—" when the part is not in the box."""
        out: dict[str, str] = {}
        lim = self.limits
        for part, keys in _BOX_PARTS.items():
            cells = []
            for side, key in zip(("min", "max"), keys):
                if key is None or key not in lim:
                    continue
                value = lim[key]
                if value is None:
                    cells.append(f"{side} none [{self.notes.get(key, 'no limit: P falls as the part grows')}]")
                    continue
                tag = self.protects.get(key, "risk")
                if key in self.notes:  # "no window above nominal", "no lower limit": the sentence says the fix
                    tag += "; " + self.notes[key].split(":")[0]
                cells.append(f"{side} {limit_shown(value, UNITS[part], side, units)} [{tag}]")
            out[part] = "; ".join(cells) or "—"
        return out

    def sentence(self) -> str:
        """How the box was found and what it guarantees, one paragraph."""
        shape = SHAPES[self.shape]
        scale = (
            f"the stated tolerances × {self.scale:.3g}"
            if self.shape == "tolerances"
            else f"{self.scale:.1%} of nominal"
        )
        fit = ""
        if self.shape == "tolerances":
            fit = (
                " (the stated tolerances fit inside)"
                if self.scale >= 1
                else " (SMALLER than the stated tolerances: parts built to them can fail)"
            )
        return (
            f"Joint acceptance box: a caster whose parts are all inside it meets P(shimmy at {self.required_speed:.3g} "
            f"m/s) ≤ α = {self.alpha:.3g} (worst-case stack: P at all {self.corners} corners by the exact law, the "
            f"largest {self.corner_max:.2%}; the wheel's I_w measured). Shape: {shape}; the risk windows are {scale}{fit}. "
            + (
                "P falls as trail, groove and M_f grow and rises with I_w (checked at every corner), so the risk side of "
                "each part is one-sided."
                if self.monotone
                else "The worst corner is not the one of every limit: P is not monotone here."
            )
            + "".join(f" {k}: {v}." for k, v in self.notes.items() if k == "box")
        )


def _weights(problem: Problem, design: Design, inertia: float, measured: bool, offset: float) -> tuple[str, dict]:
    """The box's shape and each risk part's relative window per unit scale w_p (module text)."""
    parts = ["trail", "friction_moment", "wheel_inertia"] + (["groove"] if design.groove > 0 else [])
    tol = problem.tolerances
    if tol is None:
        return "equal relative", {p: 1.0 for p in parts}
    stated: dict[str, float] = {}
    if tol.trail is not None and design.trail > 0:
        stated["trail"] = tol.trail / design.trail
    if tol.groove is not None and design.groove > 0:
        stated["groove"] = tol.groove / design.groove
    if tol.friction_moment is not None:
        stated["friction_moment"] = float(tol.friction_moment)
    if tol.wheel is not None and tol.wheel > inertia:
        stated["wheel_inertia"] = tol.wheel / inertia - 1
    elif tol.wheel is None and tol.diameter is not None and not measured:
        # the fit's range warning is the caster's own, said elsewhere
        with warnings.catch_warnings(action="ignore", category=UserWarning):
            model = problem.conditions.inertia
            stated["wheel_inertia"] = float(model(design.diameter + tol.diameter)) / float(model(design.diameter)) - 1
    stated = {k: v for k, v in stated.items() if v > 0 and k in parts}
    if not stated:
        return "equal relative", {p: 1.0 for p in parts}
    fill = sum(stated.values()) / len(stated)
    return "tolerances", {p: stated.get(p, fill) for p in parts}


def _footrest(
    problem: Problem, design: Design, notes: dict[str, str]
) -> tuple[float | None, float | None, float | None, dict[str, str]]:
    """The box's geometric limits: the trail's and the diameter's largest (the footrest T + d/2 <= R_max with d at
    its stated upper edge), the diameter's least (the stated tolerance's), what each key protects; a note (with
    the fix) in ``notes`` when the footrest leaves the trail no window above nominal."""
    tol = problem.tolerances
    r_max = problem.swept_radius_max
    tol_d = tol.diameter if tol is not None and tol.diameter is not None else 0.0
    in_box = r_max is not None or (tol is not None and tol.diameter is not None)
    d_max = design.diameter + tol_d if in_box else None
    # the diameter's least protects nothing of the risk (a measured wheel's law has no d) nor the footrest: it is
    # the stated tolerance's, or none
    d_min = design.diameter - tol_d if tol is not None and tol.diameter is not None else None
    trail_max = None if r_max is None else r_max - (design.diameter + tol_d) / 2
    protects = {k: "risk" for k in RISK_KEYS} | ({} if r_max is None else {"trail_max": "footrest"})
    if d_max is not None:
        protects["diameter_max"] = "tolerance" if r_max is None else "footrest"
    if d_min is not None:
        protects["diameter_min"] = "tolerance"
    if trail_max is not None and trail_max <= design.trail + 1e-12:
        edge = f" with the diameter at its +{tol_d * 1000:.2f} mm edge" if tol_d else ""
        notes["trail_max"] = (
            "no window above nominal: the footrest limit T + d/2 ≤ R_max"
            + edge
            + (" is below the nominal trail" if trail_max < design.trail - 1e-12 else " equals the nominal trail")
            + "; fix: a shorter trail step or a smaller wheel"
        )
    return trail_max, d_min, d_max, protects


def _corners(axes: dict[str, tuple[float, float]]) -> dict[str, np.ndarray]:
    """Every corner of one box: ``axes`` {trail, groove, damping, inertia: (the risk limit, the other end)}; row 0
    has every part at its risk limit; a part whose two ends agree adds no corner (2^k rows, k the parts with a
    window)."""
    live = [k for k, (lo, hi_) in axes.items() if lo != hi_]
    grid = np.array(list(itertools.product((0, 1), repeat=len(live))), dtype=int).reshape(2 ** len(live), len(live))
    rows = len(grid)
    return {k: np.array(axes[k])[grid[:, live.index(k)]] if k in live else np.full(rows, axes[k][0]) for k in axes}


# long: the scales' roots, the notes they leave and the records are one computation (footrest and corners are helpers)
def joint_limits_many(
    problems: list[Problem],
    designs: list[Design],
    inertia: list[float],
    measured: list[bool],
    uncertainty: Uncertainty,
    *,
    offsets: list[float] | None = None,
    calibration: float = 1.0,
) -> list[JointLimits]:
    """The joint acceptance box of many casters under one risk law (module text), all searched together: for each,
    P(V_c,true < V_req) <= α at every corner.

    One entry per caster in ``problems`` (its V_req, tolerances and swept-radius limit), ``designs``, ``inertia``
    (the nominal I_w [kg·m²]: the power law's at d for a wheel known by its diameter), ``measured`` and
    ``offsets`` (what a tilted stem adds to the fork offset [m]: the law sees T + offset; the box states the trail
    as built); ``uncertainty``: the risk law (the problem's bound, a retrofit's calibrated law) with the problems'
    one slip coefficient (ValueError for a batch that mixes them: :func:`designer.studies.spec.caster_specs` groups); ``calibration``: k of a calibrated retrofit (the law is at V_req / k).  Each box's scale s
    is the root of Φ⁻¹(P_worst(s)) = Φ⁻¹(α) on [0, s_max) (s_max: where the trail reaches zero, P = 1), by
    :func:`designer.physics.roots.bracketed_roots` for all casters at once; then every caster's 2^k corners are
    evaluated in one call of :func:`measured_probabilities`.
    """
    n = len(designs)
    if not n:
        return []
    offset = np.zeros(n) if offsets is None else np.asarray(offsets, dtype=float)
    speed = np.array([p.required_speed for p in problems]) / calibration
    alpha = float(uncertainty.probability)
    ks = float(problems[0].conditions.slip_coefficient)
    if any(float(p.conditions.slip_coefficient) != ks for p in problems):
        raise ValueError("joint_limits_many: one slip coefficient K_s a batch (the law's linear part depends on it)")
    nominal = np.array([[d.trail, d.groove, d.damping, i] for d, i in zip(designs, inertia)]).reshape(n, 4)
    shapes = [_weights(p, d, i, m, o) for p, d, i, m, o in zip(problems, designs, inertia, measured, offset)]
    w = np.array(
        [[ws.get(k, 0.0) for k in ("trail", "groove", "friction_moment", "wheel_inertia")] for _, ws in shapes]
    )

    def box(s: np.ndarray, rows: np.ndarray | slice = slice(None)) -> np.ndarray:
        """The worst corner at scale s of the rows (T, B, c_f held at zero at the least, I_w above nominal)."""
        low = nominal[rows, :3] * np.maximum(1 - np.asarray(s)[:, None] * w[rows, :3], 0.0)
        return np.column_stack([low, nominal[rows, 3] * (1 + s * w[rows, 3])])

    def worst(s: np.ndarray, rows: np.ndarray | slice = slice(None)) -> np.ndarray:
        t, b, c, i = box(s, rows).T
        return measured_probabilities(t + offset[rows], i, b, c, ks, speed[rows], uncertainty)

    at_zero = worst(np.zeros(n))
    scale = np.zeros(n)
    live = np.flatnonzero(at_zero <= alpha)
    if live.size:
        top = (1 - 1e-9) / w[live, 0]  # the trail reaches zero: V_c = 0 (Eq. 7), P = 1
        scale[live] = bracketed_roots(
            lambda s, rows: probits(worst(s, live[rows])) - probit(alpha), np.zeros(live.size), top, 1e-15, SCALE_RTOL
        )
        while (above := live[worst(scale[live], live) > alpha]).size:  # a root a hair above α: step inside
            scale[above] *= 1 - 4 * SCALE_RTOL
    limits = box(scale)
    # every corner of every box: each risk part at its limit or its mirror about nominal, the trail's upper end the
    # footrest's, all casters' corners in one call of the law
    out, corners = [], []
    for k in range(n):
        problem, design, s = problems[k], designs[k], float(scale[k])
        notes: dict[str, str] = {}
        if s == 0.0:
            notes["box"] = (
                f"no window: even at nominal, with a measured wheel, P = {at_zero[k]:.2%} > α; the caster itself must "
                "change (a longer trail, more groove or friction, a lighter wheel)"
            )
        trail_max, d_min, d_max, protects = _footrest(problem, design, notes)
        for key, j in {"groove_min": 1, "friction_moment_min": 2}.items():
            if nominal[k, j] > 0 and s * w[k, j] >= 1:
                notes[key] = "no lower limit: the worst corner meets the bound with this part at zero"
        if s == 0.0:
            for key in RISK_KEYS:
                notes.setdefault(key, "no window: the limit equals the nominal (see box)")
        mirror = nominal[k] * (1 + np.array([1, 1, 1, -1]) * s * w[k])
        t_hi = trail_max if trail_max is not None else mirror[0]
        ends = zip(("trail", "groove", "damping", "inertia"), limits[k], (t_hi, *mirror[1:]))
        corners.append(_corners({key: (float(lo), float(hi)) for key, lo, hi in ends}))
        out.append((notes, trail_max, d_min, d_max, protects))
    sizes = [len(c["trail"]) for c in corners]
    cat = {key: np.concatenate([c[key] for c in corners]) for key in corners[0]}
    each = np.repeat(np.arange(n), sizes)
    p_all = measured_probabilities(
        cat["trail"] + offset[each], cat["inertia"], cat["groove"], cat["damping"], ks, speed[each], uncertainty
    )
    found = []
    theta0 = [float(p.conditions.disturbance_angle) for p in problems]
    for k, (p, (notes, trail_max, d_min, d_max, protects)) in enumerate(
        zip(np.split(p_all, np.cumsum(sizes)[:-1]), out)
    ):
        t_min, b_min, c_min, i_max = (float(v) for v in limits[k])
        found.append(
            JointLimits(
                trail_min=t_min,
                trail_max=trail_max,
                groove_min=b_min,
                friction_moment_min=friction_moment(c_min, theta0[k]),
                wheel_inertia_max=i_max,
                diameter_min=d_min,
                diameter_max=d_max,
                nominal={
                    "trail": designs[k].trail,
                    "groove": designs[k].groove,
                    "friction_moment": friction_moment(designs[k].damping, theta0[k]),
                    "wheel_inertia": float(inertia[k]),
                    "diameter": designs[k].diameter,
                },
                protects=protects,
                shape=shapes[k][0],
                weights=shapes[k][1],
                scale=float(scale[k]),
                probability=float(p[0]),  # row 0: every part at its risk limit
                corners=int(len(p)),
                corner_max=float(np.max(p)),
                monotone=bool(np.argmax(p) == 0 or np.max(p) <= p[0] * (1 + 1e-12)),
                alpha=alpha,
                required_speed=float(speed[k]),
                notes=notes,
            )
        )
    return found


_BOX_PARTS = {
    "trail": ("trail_min", "trail_max"),
    "diameter": ("diameter_min", "diameter_max"),
    "groove": ("groove_min", None),
    "friction_moment": ("friction_moment_min", None),
    "wheel_inertia": (None, "wheel_inertia_max"),
}
"""Each part's box limits (min key, max key; None: no such side)."""

UNITS = {"trail": "m", "groove": "m", "diameter": "m", "friction_moment": "N·m", "wheel_inertia": "kg·m²"}
"""SI unit of each inspectable part (a spec's and a box's; the JSON's ``units`` entry)."""


def box_short(joint: JointLimits, units: str = "mm") -> str:
    """The box on one line, lengths in the problem's ``units`` and the rest SI ("T 54.91–63.50 mm (max: footrest,
    no window), B >= 16.48 mm, ..."), each limit rounded toward the safe side; a geometric limit named as such."""

    def shown(key: str, side: str) -> str:
        value = getattr(joint, key)
        return limit_shown(value, UNITS[key.rsplit("_", 1)[0]], side, units).split(" (")[0]

    def mark(key: str) -> str:
        if joint.protects.get(key) != "footrest":
            return ""
        return " (max: footrest" + (", no window" if key in joint.notes else "") + ")"

    trail = f"T >= {shown('trail_min', 'min')}"
    if joint.trail_max is not None:
        trail = f"T {shown('trail_min', 'min')}–{shown('trail_max', 'max')}{mark('trail_max')}"
    out = [trail]
    if joint.diameter_max is not None:
        d_max = f"{shown('diameter_max', 'max')}{mark('diameter_max').replace(', no window', '')}"
        out.append(f"d {shown('diameter_min', 'min')}–{d_max}" if joint.diameter_min is not None else f"d <= {d_max}")
    out += [
        f"B >= {shown('groove_min', 'min')}",
        f"M_f >= {shown('friction_moment_min', 'min')}",
        f"I_w <= {shown('wheel_inertia_max', 'max')} measured",
    ]
    return ", ".join(out)
