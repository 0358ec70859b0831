"""The input of a retrofit: the current caster as text (:func:`parse_current`) and the checks of the
caster and the observation the model can take (:func:`_check_inputs`, one-line InputErrors).

Part of :mod:`designer.studies.retrofit._retrofit`.
"""

from __future__ import annotations

import math

from designer.data.paper import WALKING_SPEED
from designer.display import shown
from designer.errors import InputError
from designer.model import VARIABLES, Design, check_design
from designer.physics.geometry import effective_trail
from designer.problem import INERTIA_RANGE
from designer.units import parse_quantity_text

MAX_STEM_ANGLE = math.radians(30.0)
"""Largest stem tilt accepted [rad]: seat-angle and dump changes tilt the stem by a few degrees."""


_KEYS = {"t": "trail", "d": "diameter", "b": "groove", "c": "damping", "c_f": "damping", "cf": "damping"} | {
    name: name for name in VARIABLES
}


def parse_current(text: str, option: str = "--current") -> Design:
    """Parse ``"T=1.5in,d=7.75in,B=0.5625in,c=1.3"`` into a :class:`Design` [SI].

    Keys: T (trail), d (diameter), B (groove), c (damping, N·m/rad); values
    with units, plain numbers in SI.  InputError names the piece that fails.
    """

    if not isinstance(text, str) or not text.strip():
        raise InputError(f'{option} {text!r}: expected T=..,d=..,B=..,c=.. (e.g. "T=1.5in,d=7.75in,B=0.5625in,c=1.3")')
    values: dict[str, float] = {}
    for piece in text.split(","):
        if "=" not in piece:
            raise InputError(
                f"{option} {text!r}: {piece.strip()!r} is not KEY=VALUE "
                f'(keys T, d, B, c; e.g. "T=1.5in,d=7.75in,B=0.5625in,c=1.3")'
            )
        key, value = (s.strip() for s in piece.split("=", 1))
        name = _KEYS.get(key.lower())
        if name is None:
            raise InputError(
                f"{option}: unknown key {key!r} in {text!r}; keys are T (trail), d (diameter), B (groove), c (damping)"
            )
        if name in values:
            raise InputError(f"{option}: {key!r} given twice in {text!r}")
        dimension = "damping" if name == "damping" else "length"
        # the one number-with-unit parser of the command line (evaluate's --damping 1.3e0 reads the same)
        values[name] = parse_quantity_text(value, dimension, f"{option} {key}")
    missing = [k for k, n in (("T", "trail"), ("d", "diameter"), ("B", "groove"), ("c", "damping")) if n not in values]
    if missing:
        raise InputError(f"{option} {text!r}: missing {', '.join(missing)} (give T, d, B and c)")
    try:
        return Design(**values)
    except InputError as exc:
        raise InputError(f"{option}: {exc}") from None


def _check_inputs(problem, current: Design, inertia, shimmied_at, stem_angle, onset_scatter) -> None:
    """InputError (one line naming the value) for a caster or observation the model cannot take (:func:`fix`'s
    boundary has made each a finite number already)."""
    check_design(current, "current ", error=InputError)
    h = problem.conditions.threshold_height
    if current.diameter <= 2 * h:
        raise InputError(
            f"current diameter = {shown(current.diameter, 'diameter', 'in')}: must exceed twice the sill height "
            f"({shown(2 * h, 'diameter', 'in')}); d/h <= 2 cannot climb the sill (Eq. 4A)"
        )
    c0 = problem.conditions.turning.bare_fork_damping
    if current.damping < c0 - 1e-12:
        raise InputError(
            f"current damping = {current.damping:g} N·m/rad: below the bare ball-bearing fork's "
            f"{c0:g} N·m/rad (Eq. 11C), the least spindle damping a caster has"
        )
    if inertia is not None and not INERTIA_RANGE[0] <= inertia <= INERTIA_RANGE[1]:
        raise InputError(
            f"inertia = {inertia!r} kg·m²: must be between {INERTIA_RANGE[0]:g} and "
            f"{INERTIA_RANGE[1]:g} kg·m² (Table 1: 0.00026 to 0.0046)"
        )
    if abs(stem_angle) > MAX_STEM_ANGLE:
        raise InputError(
            f"stem angle = {math.degrees(stem_angle):.4g} deg: must be within ±{math.degrees(MAX_STEM_ANGLE):.0f} deg "
            "of vertical"
        )
    t_eff = effective_trail(current.trail, current.diameter / 2, stem_angle)
    if t_eff <= 0:
        raise InputError(
            f"stem angle = {math.degrees(stem_angle):.3g} deg: the effective trail "
            f"{shown(t_eff, 'trail', 'in')} is not positive (the wheel would lead the stem)"
        )
    if shimmied_at is not None:
        if shimmied_at < WALKING_SPEED:
            raise InputError(
                f"shimmied at = {shimmied_at:g} m/s: below walking speed ({WALKING_SPEED:g} m/s); "
                f"a caster that shimmies that slowly is broken (loose bearing, bent fork), not "
                f"described by Eq. 7; or was the speed in km/h?"
            )
        if shimmied_at > 10.0:
            raise InputError(
                f"shimmied at = {shimmied_at:g} m/s: above 10 m/s, no wheelchair goes that fast; "
                f"was it given in km/h or mph?"
            )
    if not 0 < onset_scatter <= 1:
        raise InputError(f"onset scatter = {onset_scatter!r}: σ of the log onset must be in (0, 1]")
