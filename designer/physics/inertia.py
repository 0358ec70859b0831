"""Moment of inertia of the caster wheel about a diameter, I_w(d).

Eq. 7 shows the critical speed falls as I_w rises, and I_w rises steeply with
the diameter d that lowers the threshold force (Eq. 1): this coupling is the
heart of the design trade-off (Appendix A, last paragraph).  Three models:

``PowerLaw``  I_w = C d^n fitted by least squares in log space to Table 1
              (the default, ``table1-power-law``);
``Disc``      uniform disc of tyre width w and density ρ;
``Catalog``   one wheel of Table 1 with its own d, mass and I_w.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Mapping

import numpy as np

from designer.data.paper import TABLE1, Wheel, table1_wheel
from designer.errors import InertiaExtrapolationWarning, InputError
from designer.physics._checks import is_symbolic, require_positive
from designer.physics.scatter import inertia_prediction
from designer.physics.types import Scalar
from designer.units import INCH


@lru_cache(maxsize=1)
def fit_table1_power_law() -> tuple[float, float]:
    """Least-squares fit of I_w = C d^n to the seven wheels of Table 1.

    The fit is linear in log space: log I_w = log C + n log d, over wheels A–G
    (d in m, I_w in kg·m², Table 1's printed column × 1e-3, docs/model.md#wheel-inertia).

    Returns
    -------
    (C, n) : tuple of float
        Coefficient C [kg·m^(2-n)] and exponent n [-]; n ≈ 3.50 and
        C·(0.2032 m)^n ≈ 1.87e-3 kg·m².
    """
    d = np.array([w.diameter for w in TABLE1])
    inertia = np.array([w.inertia for w in TABLE1])
    n, log_c = np.polyfit(np.log(d), np.log(inertia), 1)
    return float(math.exp(log_c)), float(n)


def power_law_inertia(diameter: Scalar, coefficient: float | None = None, exponent: float | None = None) -> Scalar:
    """Wheel moment of inertia from the power law I_w = C d^n [kg·m²].

    Parameters
    ----------
    diameter : float | array | casadi
        Wheel diameter d [m].
    coefficient, exponent : float, optional
        C and n; default: the Table 1 fit of :func:`fit_table1_power_law`.
    """
    c, n = fit_table1_power_law()
    return (c if coefficient is None else coefficient) * diameter ** (n if exponent is None else exponent)


def disc_mass(diameter: Scalar, tyre_width: Scalar, density: Scalar) -> Scalar:
    """Mass of a uniform solid disc wheel m = ρ π d² w / 4 [kg].

    Parameters
    ----------
    diameter : wheel diameter d [m]
    tyre_width : tyre (disc) width w [m]
    density : material density ρ [kg/m³]
    """
    return density * np.pi * diameter**2 * tyre_width / 4


def disc_inertia(diameter: Scalar, tyre_width: Scalar, density: Scalar) -> Scalar:
    """Moment of inertia of a uniform disc about a diameter [kg·m²].

    I_w = m (d²/16 + w²/12) with m = ρ π d² w / 4 (docs/model.md#wheel-inertia; the thin-disc
    limit m r²/4 reproduces Table 1's wheels A and B).
    """
    mass = disc_mass(diameter, tyre_width, density)
    return mass * (diameter**2 / 16 + tyre_width**2 / 12)


class InertiaModel:
    """Base class: I_w as a function of diameter, callable on floats, arrays, CasADi.

    ``measured``: the model gives a measured wheel's I_w (catalogue, fixed), to which the risk law applies
    the measurement's scatter; otherwise I_w is predicted from the diameter and the risk law applies Table
    1's prediction interval (:mod:`designer.physics.scatter`).
    """

    name = "abstract"
    fixed_diameter: float | None = None
    measured = False

    def __call__(self, diameter: Scalar) -> Scalar:  # pragma: no cover - interface
        raise NotImplementedError

    def describe(self) -> str:  # pragma: no cover - interface
        raise NotImplementedError

    def data_range(self) -> tuple[float, float] | None:
        """Diameters [m] over which the model rests on data (None: everywhere)."""
        return None

    def parameters(self) -> dict[str, float]:
        """The model's constants, named as in :mod:`designer.parameters` (the solvers' parameters)."""
        return {}

    def with_parameters(self, values: Mapping[str, Any]) -> "InertiaModel":
        """The same kind of model with the constants ``values`` (floats or CasADi symbols: Any)."""
        return self


@dataclass(frozen=True)
class PowerLaw(InertiaModel):
    """I_w = C d^n; default C, n from the Table 1 least-squares fit.

    Warns (``UserWarning``) when evaluated numerically outside the diameters of
    Table 1 (4–8 in), where the fit is an extrapolation.

    ``measured``: False (default), a wheel bought by its diameter, whose I_w the risk law scatters by Table 1's
    prediction interval; True, a wheel measured and accepted at (at most) the power law's value, whose I_w gets
    the measurement's scatter (the "if you measure the wheel" recommendation).
    """

    coefficient: float | None = None
    exponent: float | None = None
    measured: bool = False
    name = "table1-power-law"

    def constants(self) -> tuple[float, float]:
        """Return (C, n) actually used."""
        c, n = fit_table1_power_law()
        return (c if self.coefficient is None else self.coefficient, n if self.exponent is None else self.exponent)

    def __call__(self, diameter: Scalar) -> Scalar:
        arr = None if is_symbolic(diameter) else np.asarray(diameter, dtype=float)
        if arr is not None and np.any(inertia_prediction().extrapolated(arr)):
            warnings.warn(
                f"inertia power law used at d = {np.min(arr) / INCH:.2f}–{np.max(arr) / INCH:.2f} in, "
                f"outside Table 1's 4–8 in: an extrapolation",
                InertiaExtrapolationWarning,
                stacklevel=2,
            )
        return power_law_inertia(diameter, self.coefficient, self.exponent)

    def data_range(self) -> tuple[float, float]:
        return inertia_prediction().low, inertia_prediction().high

    def parameters(self) -> dict[str, float]:
        c, n = self.constants()
        return {"inertia_coefficient": c, "inertia_exponent": n}

    def with_parameters(self, values: Mapping[str, Any]) -> "PowerLaw":
        return PowerLaw(values["inertia_coefficient"], values["inertia_exponent"], self.measured)

    def describe(self) -> str:
        c, n = self.constants()
        measured = "; wheels measured at its value" if self.measured else ""
        return f"I_w = {c:.4g} d^{n:.3f} (least squares on Table 1, d in m, I_w in kg·m²{measured})"


@dataclass(frozen=True)
class Disc(InertiaModel):
    """Uniform disc wheel of width ``tyre_width`` [m] and ``density`` [kg/m³]."""

    tyre_width: float = 0.025
    density: float = 1200.0
    name = "disc"

    def __post_init__(self) -> None:
        require_positive("inertia.tyre_width", self.tyre_width)
        require_positive("inertia.density", self.density)

    def __call__(self, diameter: Scalar) -> Scalar:
        return disc_inertia(diameter, self.tyre_width, self.density)

    def parameters(self) -> dict[str, float]:
        return {"tyre_width": self.tyre_width, "density": self.density}

    def with_parameters(self, values: Mapping[str, Any]) -> "Disc":
        return Disc(values["tyre_width"], values["density"])

    def describe(self) -> str:
        return (
            f"uniform disc, I_w = m(d²/16 + w²/12), m = ρπd²w/4, w = {self.tyre_width * 1000:.1f} mm, "
            f"ρ = {self.density:.0f} kg/m³"
        )


@dataclass(frozen=True)
class Catalog(InertiaModel):
    """One Table 1 wheel: its diameter is fixed and its I_w is the measured one."""

    wheel: Wheel = TABLE1[0]
    name = "catalog"
    measured = True

    @classmethod
    def from_key(cls, key: str) -> "Catalog":
        """Build from a Table 1 letter; InputError for an unknown letter."""
        try:
            return cls(table1_wheel(key))
        except KeyError as exc:
            raise InputError(str(exc.args[0])) from None

    @property
    def fixed_diameter(self) -> float:  # type: ignore[override]
        return self.wheel.diameter

    def __call__(self, diameter: Scalar) -> Scalar:
        # Measured inertia: independent of the diameter argument, which the
        # catalog fixes; keep the argument's type (0*d) for CasADi graphs.
        return self.wheel.inertia + 0 * diameter

    def parameters(self) -> dict[str, float]:
        return {"wheel_inertia": self.wheel.inertia}

    def with_parameters(self, values: Mapping[str, Any]) -> "InertiaModel":
        return Fixed(values["wheel_inertia"])  # the measured I_w, now a parameter

    def describe(self) -> str:
        w = self.wheel
        return (
            f"Table 1 wheel {w.key} ({w.name}): d = {w.diameter / INCH:.0f} in, "
            f"m = {w.mass:.3f} kg, I_w = {w.inertia:.3g} kg·m²"
        )


@dataclass(frozen=True)
class Fixed(InertiaModel):
    """A measured wheel: I_w given directly [kg·m²], independent of the diameter.

    Use with a fixed diameter (e.g. the Invacare 7¾ in wheel of Fig. 4 and
    Eq. 8, I_w = 0.00127 kg·m²).
    """

    inertia: float = 0.00127
    name = "fixed"
    measured = True

    def __post_init__(self) -> None:
        require_positive("inertia.inertia", self.inertia)

    def __call__(self, diameter: Scalar) -> Scalar:
        return self.inertia + 0 * diameter

    def parameters(self) -> dict[str, float]:
        return {"wheel_inertia": self.inertia}

    def with_parameters(self, values: Mapping[str, Any]) -> "Fixed":
        return Fixed(values["wheel_inertia"])

    def describe(self) -> str:
        return f"measured wheel, I_w = {self.inertia:.4g} kg·m²"
