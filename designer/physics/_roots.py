"""Brent's root finder, written out so the main job does not load ``scipy.optimize`` (about 0.35 s of CPU).

:func:`brentq` takes the steps of ``scipy.optimize.brentq`` (its C code: the same tests, the same steps, the
same floating-point operations in the same order), so it returns the same root to the bit; tests/test_roots.py
compares the two on the knock simulations' roots and on random functions.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

EPS = float(np.finfo(float).eps)
"""Machine epsilon of float64 [-]; ``4 * EPS`` is the least relative tolerance (as scipy's)."""


def _value(f: Callable[[float], float], x: float) -> float:
    """f(x) as a float; NaN raises ValueError (as scipy's wrapper does)."""
    fx = float(f(x))
    if fx != fx:
        raise ValueError(f"The function value at x={x} is NaN; solver cannot continue.")
    return fx


# long: Brent's method as one loop, step for step as scipy's C code (splitting it would hide that)
def brentq(  # noqa: C901 - the branches of Brent's method, kept as in scipy's C code
    f: Callable[[float], float],
    a: float,
    b: float,
    xtol: float = 2e-12,
    rtol: float = 4 * EPS,
    maxiter: int = 100,
    fa: float | None = None,
    fb: float | None = None,
) -> float:
    """A root of f in [a, b], where f(a) and f(b) have opposite signs (Brent 1973, ch. 4) [units of a].

    Parameters
    ----------
    f : the function (a float in, a float out)
    a, b : the bracket
    xtol, rtol : the root is within ``xtol + rtol |x|`` of the returned x (``rtol`` >= 4 eps)
    maxiter : most iterations; RuntimeError beyond
    fa, fb : f(a) and f(b) when the caller has them already (saves two calls; the same values)

    Returns
    -------
    float
        The root (``a`` or ``b`` when f is exactly 0 there), bit for bit ``scipy.optimize.brentq``'s.
    """
    if xtol <= 0:
        raise ValueError(f"xtol too small ({xtol:g} <= 0)")
    if rtol < 4 * EPS:
        raise ValueError(f"rtol too small ({rtol:g} < {4 * EPS:g})")
    xpre, xcur = float(a), float(b)
    fpre = _value(f, xpre) if fa is None else float(fa)
    fcur = _value(f, xcur) if fb is None else float(fb)
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if (fpre < 0) == (fcur < 0):
        raise ValueError("f(a) and f(b) must have different signs")
    xblk = fblk = spre = scur = 0.0
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and (fpre < 0) != (fcur < 0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            bound = 3 * abs(sbis) - delta
            if 2 * abs(stry) < (abs(spre) if abs(spre) < bound else bound):  # good short step (C's MIN)
                spre, scur = scur, stry
            else:  # bisect
                spre = scur = sbis
        else:  # bisect
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0 else -delta)
        fcur = _value(f, xcur)
    raise RuntimeError(f"Failed to converge after {maxiter} iterations, value is {xcur}")
