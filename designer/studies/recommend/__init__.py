"""Build this caster: the recommended stock caster, its alternatives and the price of stock.

Modules
-------
_recommend  :func:`recommend`: the buildable front, the rule, the recommendation
_record     :class:`Recommendation`: the result record (reprs, drawing)
_rule       the selection rules and what the weights mean
_stock      stock candidates and their risk screen
"""

from __future__ import annotations

from designer.studies.recommend._record import Recommendation
from designer.studies.recommend._recommend import recommend, with_spec
from designer.studies.recommend._rule import rule_text, select_rows, weights_meaning
from designer.studies.recommend._stock import CandidateTable, stock_candidates

__all__ = [
    "CandidateTable",
    "Recommendation",
    "recommend",
    "rule_text",
    "select_rows",
    "stock_candidates",
    "weights_meaning",
    "with_spec",
]
