"""Type aliases of the physics: its functions take floats, NumPy arrays and CasADi symbols alike."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, TypeAlias, Union

import numpy as np

if TYPE_CHECKING:  # casadi is heavy and numpy.typing not free: named for the type checker only
    import casadi
    import numpy.typing as npt

Array: TypeAlias = "npt.NDArray[np.float64]"
"""A NumPy array of floats (SI units), broadcast element-wise."""

Scalar: TypeAlias = Union[float, Array, "casadi.SX"]
"""A quantity as the physics takes it: a float, an array of floats, or a CasADi SX symbol (the NLP's)."""

Numeric: TypeAlias = Union[float, Array]
"""A float or an array of floats: for the functions that are numeric only (no CasADi symbols)."""


def batch_or_symbol(value: Any) -> bool:
    """A NumPy array of values (one per design) or a CasADi expression: the solvers' and the vectorised model's own
    values, not a user's number (checked where it was read).  A 0-d array is one number: the boundary's."""
    return (isinstance(value, np.ndarray) and value.ndim > 0) or type(value).__module__.startswith("casadi")
