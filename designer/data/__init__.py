"""The reference paper's data: Table 1 and the constants of Appendix C (:mod:`designer.data.paper`), and check
11's leave-one-out tables (:mod:`designer.data.leave_one_out`).

Source: "Wheelchair Caster Shimmy and Turning Resistance" (the reference
paper in ``shared/paper``).  Every constant here names where in the paper it
comes from; nothing is fitted or tuned in this module.
"""

__all__ = ["leave_one_out", "paper"]
