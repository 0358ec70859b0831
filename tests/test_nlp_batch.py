"""CasterNLP.solve_many: the batch is an MX map of the one-block NLP; every block reaches its own NLP's optimum."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from designer.problem import load_problem
from designer.solvers.nlp import CasterNLP

INDOOR = Path(__file__).resolve().parents[1] / "problems" / "indoor-manual.toml"


def test_batched_blocks_equal_single_solves():
    """Six ε-constraint NLPs solved in two 4-block chunks (4, then 2 padded with a copy) give, block by block, the
    optimum of the single solve from the same start: F_turn within 1e-9 relative, P within its cap and V_c >= V_req
    (the diameter is not compared: F_turn does not depend on it, the optimum is flat in d)."""
    problem = load_problem(INDOOR)
    nlp = CasterNLP(problem)
    p_lo = nlp.objectives(problem.upper())[1]
    p_hi = nlp.objectives(problem.lower())[1]
    caps = np.linspace(p_lo, p_hi, 8)[1:-1] if p_hi > p_lo else np.linspace(p_hi, p_lo, 8)[1:-1]
    start = problem.upper()
    batch = nlp.solve_many([start] * len(caps), (1.0, 0.0), caps)
    assert len(batch) == 6 and all(r.success for r in batch)
    for r, cap in zip(batch, caps):
        single = nlp.solve(start, (1.0, 0.0), cap)
        assert single.success
        f_batch, p_batch = nlp.objectives(r.design)[:2]
        f_single = nlp.objectives(single.design)[0]
        assert abs(f_batch - f_single) <= 1e-9 * f_single
        assert p_batch <= cap * (1 + 1e-7)
        assert nlp.objectives(r.design)[2] >= problem.required_speed * (1 - 1e-7)  # V_c (F_turn is flat in d)
    assert (4, False) in nlp._batch and (16, False) not in nlp._batch  # chunks of 4: 4 + 2 (padded)
