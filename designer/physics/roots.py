"""A root of a scalar function in a sign-change bracket, without loading scipy.optimize.

Check 6 (the Routh–Hurwitz critical speed of Eq. 12B) and the knock simulations' event times need one root
of a continuous function in a bracket.  scipy.optimize's ``brentq`` does it, but importing scipy.optimize
costs about 0.35 s of CPU (its package loads linprog, the global optimisers and scipy.sparse), a quarter
of the main job (benchmarks/results.md).  This is the textbook Illinois variant of regula falsi
(Dowell & Jarratt 1971) with a bisection step whenever the bracket stops halving; tests check it against
scipy's ``brentq`` (tests/physics/test_roots.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from designer.physics.types import Array

EPS = 2.220446049250313e-16
"""Machine epsilon of float64 [-]."""


def bracketed_root(
    f: Callable[[float], float],
    a: float,
    b: float,
    xtol: float = 2e-12,
    rtol: float = 4 * EPS,
    maxiter: int = 200,
) -> float:
    """A zero of ``f`` in [a, b], where f(a) and f(b) have opposite signs (or one is zero).

    Regula falsi with the Illinois rule (the value kept at the end that stays is halved when the same end
    is kept twice, so both ends move and convergence is superlinear), and a bisection step when two steps
    did not halve the bracket.  Stops when the bracket is narrower than ``2 (xtol + rtol |x|)`` and returns
    the end with the smaller |f| (or an exact zero as soon as one is evaluated).

    Parameters
    ----------
    f : the function, float -> float
    a, b : the bracket ends (either order) [units of x]
    xtol, rtol : absolute [units of x] and relative [-] tolerances on the root
    maxiter : most evaluations of ``f`` inside the bracket

    Returns
    -------
    float
        x with |x − x*| ≤ 2 (xtol + rtol |x|) for a root x* of f in the bracket.

    Raises
    ------
    ValueError
        When f(a) and f(b) have the same sign, or the bracket or the tolerances are not finite.
    RuntimeError
        When ``maxiter`` evaluations do not reach the tolerance.
    """
    a, b = float(a), float(b)
    if not (math.isfinite(a) and math.isfinite(b) and xtol >= 0 and rtol >= 0):
        raise ValueError(f"bracket [{a!r}, {b!r}], xtol {xtol!r}, rtol {rtol!r}: must be finite, tolerances >= 0")
    fa, fb = float(f(a)), float(f(b))
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0) == (fb > 0):
        raise ValueError(f"f({a!r}) = {fa!r} and f({b!r}) = {fb!r}: the bracket must hold a sign change")
    ga, gb = fa, fb  # f at the ends (fa, fb are the chord's weights, halved by the Illinois rule)
    kept = 0  # which end the last step kept: +1 a, -1 b
    width = abs(b - a)
    for step in range(maxiter):
        tol = xtol + rtol * min(abs(a), abs(b))
        if abs(b - a) <= 2 * tol:
            break
        x = b - fb * (b - a) / (fb - fa)  # where the chord between the ends crosses zero
        low, high = min(a, b) + tol, max(a, b) - tol
        if step % 2 == 1:  # every second step: bisect if the last two steps did not halve the bracket
            if abs(b - a) > 0.5 * width:
                x = 0.5 * (a + b)
            width = abs(b - a)
        if not low <= x <= high:  # keep at least tol inside the bracket
            x = min(max(x, low), high)
        fx = float(f(x))
        if fx == 0.0:
            return x
        if (fx > 0) == (fb > 0):  # the root is between a and x: x replaces b
            b, fb, gb = x, fx, fx
            if kept == 1:
                fa *= 0.5  # Illinois: a kept twice
            kept = 1
        else:  # the root is between x and b: x replaces a
            a, fa, ga = x, fx, fx
            if kept == -1:
                fb *= 0.5
            kept = -1
    else:
        raise RuntimeError(f"no root within tolerance after {maxiter} steps; bracket [{a!r}, {b!r}]")
    return a if abs(ga) < abs(gb) else b


def bracketed_roots(
    f: Callable[[Array, Any], Array],
    a: Array,
    b: Array,
    xtol: Array | float = 2e-12,
    rtol: Array | float = 4 * EPS,
    maxiter: int = 200,
    fa: Array | None = None,
    fb: Array | None = None,
) -> Array:
    """:func:`bracketed_root` for many brackets at once: the same Illinois steps, each row on its own.

    ``f(x, rows)`` returns f at the points ``x`` of the rows ``rows`` (indices into the brackets): only the rows
    still searching are evaluated, all together.  ``a``, ``b``: 1-D arrays of bracket ends, each with a sign
    change of f (or a zero at an end); ``fa``, ``fb``: f there, when the caller has it.  ``xtol`` [units of x]
    and ``rtol`` [-] may differ from row to row.  Returns x per row with |x − x*| ≤ 2 (xtol + rtol |x|), the end with the smaller
    |f| as :func:`bracketed_root` does.

    Raises
    ------
    ValueError
        When a row's f(a) and f(b) have the same sign, or a bracket or a tolerance is not finite.
    RuntimeError
        When ``maxiter`` evaluations do not reach the tolerance in some row.
    """
    a, b = np.array(a, dtype=float), np.array(b, dtype=float)
    xtol = np.broadcast_to(np.asarray(xtol, dtype=float), a.shape)
    rtol = np.broadcast_to(np.asarray(rtol, dtype=float), a.shape)
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b)) and np.all(xtol >= 0) and np.all(rtol >= 0)):
        raise ValueError("brackets and tolerances must be finite, tolerances >= 0")
    every = np.arange(a.size)
    fa = np.array(f(a, every) if fa is None else fa, dtype=np.float64)
    fb = np.array(f(b, every) if fb is None else fb, dtype=np.float64)
    bad = (fa != 0) & (fb != 0) & ((fa > 0) == (fb > 0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"f({a[i]!r}) = {fa[i]!r} and f({b[i]!r}) = {fb[i]!r}: the bracket must hold a sign change")
    out = np.where(fa == 0, a, b)
    ga, gb = fa.copy(), fb.copy()
    kept = np.zeros(a.size, dtype=int)
    width = np.abs(b - a)
    active = (fa != 0) & (fb != 0)
    for step in range(maxiter):
        tol = xtol + rtol * np.minimum(np.abs(a), np.abs(b))
        done = active & (np.abs(b - a) <= 2 * tol)
        out[done] = np.where(np.abs(ga[done]) < np.abs(gb[done]), a[done], b[done])
        active &= ~done
        rows = np.flatnonzero(active)
        if not rows.size:
            return out
        ar, br, far, fbr, tr = a[rows], b[rows], fa[rows], fb[rows], tol[rows]
        x = br - fbr * (br - ar) / (fbr - far)
        low, high = np.minimum(ar, br) + tr, np.maximum(ar, br) - tr
        if step % 2 == 1:
            x = np.where(np.abs(br - ar) > 0.5 * width[rows], 0.5 * (ar + br), x)
            width[rows] = np.abs(br - ar)
        x = np.where((low <= x) & (x <= high), x, np.minimum(np.maximum(x, low), high))
        fx = np.asarray(f(x, rows), dtype=np.float64)
        zero = fx == 0.0
        out[rows[zero]] = x[zero]
        active[rows[zero]] = False
        right = ~zero & ((fx > 0) == (fbr > 0))  # the root is between a and x: x replaces b
        left = ~zero & ~right
        r, lft = rows[right], rows[left]
        b[r], fb[r], gb[r] = x[right], fx[right], fx[right]
        fa[r] = np.where(kept[r] == 1, 0.5 * fa[r], fa[r])
        kept[r] = 1
        a[lft], fa[lft], ga[lft] = x[left], fx[left], fx[left]
        fb[lft] = np.where(kept[lft] == -1, 0.5 * fb[lft], fb[lft])
        kept[lft] = -1
    if active.any():
        i = int(np.flatnonzero(active)[0])
        raise RuntimeError(f"no root within tolerance after {maxiter} steps; bracket [{a[i]!r}, {b[i]!r}]")
    return out


__all__ = ["EPS", "bracketed_root", "bracketed_roots"]
