"""Issue 12.5, mutation testing, second round: what the paper checks and check 8 report, word for word, and
the edges of their tolerances (``designer/analysis/checks.py``; benchmarks/mutation.md)."""
from __future__ import annotations

import pytest

import designer.analysis.checks as ck


def test_check_rejects_unknown_kind():
    """A check's kind must be paper, identity or front; the error names the check, its outcome and its kind."""
    with pytest.raises(ValueError, match=r"^check x: outcome 'reproduced' / kind 'other' unknown$"):
        ck.Check("x", "c", 1, 1, True, kind="other")
