"""Force to push a caster wheel over a threshold (door sill), Appendix A."""

from __future__ import annotations

import numpy as np

from designer.errors import InputError
from designer.physics._checks import is_symbolic, require_positive
from designer.physics.types import Array, Scalar


def _check_ratio(diameter: Scalar, height: Scalar) -> None:
    if is_symbolic(diameter, height):
        return
    require_positive("diameter", diameter)
    require_positive("threshold height", height)
    ratio = np.asarray(diameter, dtype=float) / np.asarray(height, dtype=float)
    if np.any(ratio <= 2):
        worst = float(np.min(ratio))
        raise InputError(
            f"diameter/threshold height = {worst:.3g}: the wheel must be more than twice the sill "
            f"height (d/h > 2, Eq. 4A); a wheel this small cannot climb the sill"
        )


def threshold_force_ratio(diameter: Scalar, height: Scalar) -> Scalar:
    """Force per unit load to push a wheel over a sill, exact Eq. 1 = Eq. 4A [-].

    P/L = 2 sqrt(d/h − 1) / (d/h − 2), valid for d/h > 2 (InputError otherwise
    for numeric input).  Check: d/h = 10 gives 0.750, d/h = 6 gives 1.118.

    Parameters
    ----------
    diameter : wheel diameter d [m]
    height : threshold height h [m]
    """
    _check_ratio(diameter, height)
    ratio = diameter / height
    return 2 * np.sqrt(ratio - 1) / (ratio - 2)


def threshold_force_ratio_approx(diameter: Scalar, height: Scalar) -> Scalar:
    """Approximate force per unit load, Eq. 5A: P/L ≈ 2 sqrt(h/d) [-].

    Offered for comparison only; the exact Eq. 4A is always used in design.
    It underestimates: at d/h = 10 it gives 0.632 against the exact 0.750.
    """
    _check_ratio(diameter, height)
    return 2 * np.sqrt(height / diameter)


def threshold_force(diameter: Scalar, height: Scalar, load: Scalar) -> Scalar:
    """Force P [N] to push a caster carrying ``load`` L [N] over a sill of height h, Eq. 4A."""
    return load * threshold_force_ratio(diameter, height)


def threshold_series_coefficients(order: int) -> Array:
    """Coefficients c_k of P/L = 2 s^½ Σ_k c_k s^k, s = h/d (Eq. 4A expanded).

    P/L = 2 sqrt(s) sqrt(1 − s) / (1 − 2s); the series of sqrt(1−s)/(1−2s) is
    1 + 1.5 s + 2.875 s² + 5.6875 s³ + …, all terms positive (so the truncated
    sum is a posynomial, as the geometric program needs).  Returns c_0..c_order.
    """
    # sqrt(1 - s) = sum a_j s^j, 1/(1 - 2s) = sum 2^k s^k; convolve.
    a = np.empty(order + 1)
    a[0] = 1.0
    for j in range(1, order + 1):
        a[j] = a[j - 1] * (j - 1.5) / j
    c = np.array([sum(a[j] * 2.0 ** (k - j) for j in range(k + 1)) for k in range(order + 1)])
    return c


def threshold_series_remainder_bound(s: Scalar, order: int) -> Scalar:
    """Upper bound on the truncation error of :func:`threshold_series_coefficients` [-].

    Every c_k <= 2^k, so the omitted terms sum to at most
    2 sqrt(s) (2s)^(order+1) / (1 − 2s) for s = h/d < 1/2.  Relative to the exact
    P/L (>= 2 sqrt(s)) the error is at most (2s)^(order+1)/(1 − 2s).
    """
    return 2 * np.sqrt(s) * (2 * s) ** (order + 1) / (1 - 2 * s)
