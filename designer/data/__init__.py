"""The reference paper's data: Table 1 and the constants of Appendix C.

Source: "Wheelchair Caster Shimmy and Turning Resistance" (the reference
paper in ``shared/paper``).  Every constant here names where in the paper it
comes from; nothing is fitted or tuned in this module.
"""

from designer.data.paper import (
    APPENDIX_C_CASE,
    BARE_FORK_DAMPING,
    DISTURBANCE_ANGLE,
    EQ8_CASE,
    INCH,
    SLIP_COEFFICIENT,
    TABLE1,
    TABLE1_STABLE_UP_TO,
    WALKING_SPEED,
    Wheel,
    table1_wheel,
)

__all__ = [
    "APPENDIX_C_CASE",
    "BARE_FORK_DAMPING",
    "DISTURBANCE_ANGLE",
    "EQ8_CASE",
    "INCH",
    "SLIP_COEFFICIENT",
    "TABLE1",
    "TABLE1_STABLE_UP_TO",
    "WALKING_SPEED",
    "Wheel",
    "table1_wheel",
]
