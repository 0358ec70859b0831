"""The record of a check (:class:`Check`), its outcomes and kinds, and the summary line that counts them."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any, TypeAlias

from designer.reprs import Key, Record


REPRODUCED = "reproduced"
"""Outcome: the code reproduces the paper's number or property within the stated tolerance."""
WITHIN_SCATTER = "disagrees within the stated scatter"
"""Outcome: the code disagrees with a measurement, but by less than the paper's own stated scatter."""
FAILS = "fails"
"""Outcome: the disagreement is outside the stated scatter (or an identity does not hold)."""
NOT_APPLICABLE = "not applicable"
"""Outcome: the check cannot be made on this problem (e.g. check 8c when the tighter target is out of reach)."""
OUTCOMES = (REPRODUCED, WITHIN_SCATTER, FAILS, NOT_APPLICABLE)

KINDS = ("paper", "identity", "front", "law")
"""paper: against the paper's measurements or stated results; identity: a number the paper measured and
the model has built in (checks 3, 4, 5: they confirm the implementation, not the physics); front: check 8
on a computed Pareto front; law: the risk law against the Table 1 wheels it was not fitted to (11)."""


Model: TypeAlias = Callable[..., Any]
"""A model function a check runs (injectable, so a test can hand a check a wrong model and see it fail)."""

CheckValue: TypeAlias = float | int | str | bool | None
"""What a check expects or got: a number, a property in words, or None."""


@dataclass(frozen=True, kw_only=True)
class Check(Record):
    """One check of the paper's trade-offs (docs/checks.md).

    Attributes
    ----------
    name : short identifier, e.g. "1 Eq. 8"
    claim : what the paper says (its words or number)
    expected : the paper's number or property, as text or number
    got : what the code computes
    passed : False only when the outcome is :data:`FAILS`
    detail : the tolerance and any honest remark (e.g. per-wheel errors)
    kind : "paper", "identity", "front" or "law" (:data:`KINDS`)
    outcome : one of :data:`OUTCOMES` (default: reproduced if ``passed`` else fails)
    disagreements : one line per disagreement with the paper, with its size and direction
    rows : a table behind the check (check 11: one dict per wheel); in :meth:`to_dict` only when not empty
    """

    name: str
    claim: str
    expected: CheckValue
    got: CheckValue
    passed: bool
    detail: str = ""
    kind: str = "paper"
    outcome: str = ""
    disagreements: list[str] = field(default_factory=list)
    rows: list[dict[str, Any]] = field(default_factory=list)

    _keys = ("*", Key("rows", omit="empty"))
    """JSON-ready: name, claim, expected, got, passed, detail, kind, outcome, disagreements (and rows when any)."""

    def __post_init__(self) -> None:
        if not self.outcome:  # frozen: the outcome and the flag are set once, while the check is built
            object.__setattr__(self, "outcome", REPRODUCED if self.passed else FAILS)
        if self.outcome not in OUTCOMES or self.kind not in KINDS:
            raise ValueError(f"check {self.name}: outcome {self.outcome!r} / kind {self.kind!r} unknown")
        object.__setattr__(self, "passed", self.outcome != FAILS)


def count_outcomes(checks: Iterable[Check]) -> dict[str, dict[str, int]]:
    """Counts for a summary line: paper checks by outcome, identities, front checks, law checks by outcome."""
    out = {kind: {o: 0 for o in OUTCOMES} for kind in KINDS}
    for c in checks:
        out[c.kind][c.outcome] += 1
    return out


def summary_line(checks: Iterable[Check]) -> str:
    """ "n paper checks reproduced, k disagree within the stated scatter, f fail; m implementation identities hold"."""
    n = count_outcomes(checks)
    p, i = n["paper"], n["identity"]
    text = (
        f"{p[REPRODUCED]} paper checks reproduced, {p[WITHIN_SCATTER]} disagree within the paper's stated "
        f"scatter, {p[FAILS]} fail; {i[REPRODUCED]} of {sum(i.values())} implementation identities hold"
    )
    f = n["front"]
    if sum(f.values()):
        text += f"; front checks: {f[REPRODUCED]} pass, {f[FAILS]} fail" + (
            f", {f[NOT_APPLICABLE]} not applicable" if f[NOT_APPLICABLE] else ""
        )
    law = n["law"]
    if sum(law.values()):
        text += (
            f"; risk-law checks: {law[REPRODUCED]} reproduced, {law[WITHIN_SCATTER]} within the scatter, "
            f"{law[FAILS]} fail"
        )
    return text
