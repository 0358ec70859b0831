"""The rule that picks the caster from a buildable front: step 4 of :mod:`designer.studies.recommend._recommend`.

:func:`select_rows` is vectorised over rows (chairs) so ``designer fleet`` uses the same code: the knee of
the buildable front (the point farthest from the chord between its ends, objectives normalised to the
front's range, on the ideal side; with no knee, that is fewer than three points or none bulging toward the
ideal: the end with the least J = w_turn F + w_threshold P),
or with ``[objective] max_threshold_force`` / ``max_turning_effort`` the best on the other objective within
the cap.  :func:`rule_text` and :func:`weights_meaning` say the rule and the weights in words.
Re-exported by :mod:`designer.studies.recommend._recommend`.
"""

from __future__ import annotations

import numpy as np

from designer.model import weighted

RULES = {
    "any": "knee of the buildable risk-bounded front (its least-J end where it has no knee)",
    "knee": "knee of the buildable risk-bounded front",
    "cap_threshold": "least turning effort with sill force <= {cap:.1f} N",
    "cap_turning": "least sill force with turning effort <= {cap:.2f} N",
    "end": "least J = {w0:g} F_turn + {w1:g} P of a buildable front of fewer than three points (no knee)",
    "concave": "least J = {w0:g} F_turn + {w1:g} P: the buildable front has no knee (no caster between its ends "
    "bulges toward the ideal)",
}
"""How the recommendation is chosen (the text of ``Recommendation.rule``)."""


def select_rows(f: np.ndarray, p: np.ndarray, ok: np.ndarray, weights=(1.0, 1.0), cap_p=None, cap_f=None) -> dict:
    """The buildable front of each row and the rule's choice, vectorised over rows (chairs).

    Parameters
    ----------
    f, p : (rows, casters) turning effort and sill force [N]
    ok : (rows, casters) feasible (risk bound, swept radius, sill)
    weights : (w_turn, w_threshold) for ``best_j``
    cap_p, cap_f : cap on P or on F_turn [N] (at most one): the rule is then the best on the other objective

    Returns
    -------
    dict of (rows,) arrays: ``choice``, ``easiest_turn``, ``easiest_sill``, ``best_j`` (column indices, −1 if
    the row has nothing feasible or nothing within the cap), ``front_size``, ``knee`` (the choice is a knee:
    three or more points, one bulging toward the ideal; False under a cap), ``over_cap`` (a front exists but
    no point is within the cap), and (rows, casters) ``front`` (membership of the buildable front).
    """
    f = np.atleast_2d(np.asarray(f, float))
    p = np.atleast_2d(np.asarray(p, float))
    ok = np.atleast_2d(np.asarray(ok, bool))
    n, s = f.shape
    fm = np.where(ok, f, np.inf)
    pm = np.where(ok, p, np.inf)
    # each row's casters by P ascending, ties by F ascending (infeasible last)
    order = np.lexsort((fm, pm), axis=-1)
    fs = np.take_along_axis(fm, order, axis=1)
    ps = np.take_along_axis(pm, order, axis=1)
    previous = np.concatenate([np.full((n, 1), np.inf), np.minimum.accumulate(fs, axis=1)[:, :-1]], axis=1)
    front = np.isfinite(fs) & (fs < previous)
    size = front.sum(axis=1)
    has = size > 0
    rows = np.arange(n)
    first = np.argmax(front, axis=1)  # least P on the front
    last = s - 1 - np.argmax(front[:, ::-1], axis=1)  # least F on the front (largest P)
    easiest_sill = np.where(has, order[rows, first], -1)
    easiest_turn = np.where(has, order[rows, last], -1)
    w = np.asarray(weights, float)
    with np.errstate(invalid="ignore"):
        j = np.where(ok, weighted(f, p, w), np.inf)
    best_j = np.where(has, np.argmin(j, axis=1), -1)
    over_cap = np.zeros(n, bool)
    knee = np.zeros(n, bool)
    if cap_p is not None or cap_f is not None:
        within = front & ((ps <= cap_p * (1 + 1e-12)) if cap_p is not None else (fs <= cap_f * (1 + 1e-12)))
        key = fs if cap_p is not None else ps
        pick = np.argmin(np.where(within, key, np.inf), axis=1)
        anywhere = within.any(axis=1)
        choice = np.where(anywhere, order[rows, pick], -1)
        over_cap = has & ~anywhere
    else:
        pick, knee = _knee_or_end(fs, ps, front, size, first, last, weights)
        choice = np.where(has, order[rows, pick], -1)
    member = np.zeros((n, s), bool)
    np.put_along_axis(member, order, front, axis=1)
    return {
        "choice": choice,
        "easiest_turn": easiest_turn,
        "easiest_sill": easiest_sill,
        "best_j": best_j,
        "front_size": size,
        "knee": knee & has,
        "over_cap": over_cap,
        "front": member,
    }


def _knee_or_end(fs, ps, front, size, first, last, weights) -> tuple[np.ndarray, np.ndarray]:
    """The rule without a cap, per row: the column (in the sorted order of ``fs``, ``ps``) of the knee of the
    front, or of the end with the least J when the front has no knee (fewer than three points, or no point on
    the ideal side of the chord: a front bulging away from the ideal has its best trade at an end, and the
    farthest-from-the-chord rule would pick an end by the order of a tie); and whether it was a knee."""
    n, s = fs.shape
    rows = np.arange(n)
    # knee in the front's order of decreasing P: a = largest-P end (least F), b = least-P end
    fa, pa = fs[rows, last], ps[rows, last]
    fb, pb = fs[rows, first], ps[rows, first]
    with np.errstate(invalid="ignore"):
        span_f = np.where(fb - fa > 0, fb - fa, 1.0)
        span_p = np.where(pa - pb > 0, pa - pb, 1.0)
        nf = (fs - fa[:, None]) / span_f[:, None]
        np_ = (ps - pb[:, None]) / span_p[:, None]
        a_p = (pa - pb) / span_p  # normalised ends: a = (0, a_p), b = (b_f, 0)
        b_f = (fb - fa) / span_f
    chord_f, chord_p = b_f, -a_p
    norm = np.hypot(chord_f, chord_p)
    with np.errstate(invalid="ignore", divide="ignore"):
        dist = np.abs(chord_f[:, None] * (np_ - a_p[:, None]) - chord_p[:, None] * nf) / norm[:, None]
        below = nf * chord_p[:, None] - (np_ - a_p[:, None]) * chord_f[:, None]
    dist = np.where(below >= 0, dist, -dist)
    dist = np.where(front, dist, -np.inf)
    # the first maximum in the decreasing-P order (as Front.knee)
    knee = s - 1 - np.argmax(dist[:, ::-1], axis=1)
    small = (size < 3) | ~(norm > 0) | ~(np.max(dist, axis=1) > 0)
    # no knee (fewer than three points, or none bulging toward the ideal): the end with the least J = w_turn F + w_threshold P (the problem's
    # weights, their stated meaning), the easiest-to-turn end on a tie
    w_ = np.asarray(weights, float)
    with np.errstate(invalid="ignore"):
        j_last = weighted(fa, pa, w_)
        j_first = weighted(fb, pb, w_)
    end = np.where(j_first < j_last, first, last)
    return np.where(small, end, knee), ~small


def front_roles(turning_effort: np.ndarray, sel: dict) -> list[tuple[int, str]]:
    """Every caster of the buildable front (row 0 of :func:`select_rows`'s ``sel``) with its role, from the
    easiest to turn to the easiest over the sill: (index, "easiest to turn" | "between the ends" |
    "easiest over the sill"); one caster best on both is "easiest to turn"."""
    members = np.flatnonzero(sel["front"][0])
    members = members[np.argsort(turning_effort[members], kind="stable")]
    turn, sill = int(sel["easiest_turn"][0]), int(sel["easiest_sill"][0])
    return [
        (int(i), "easiest to turn" if i == turn else "easiest over the sill" if i == sill else "between the ends")
        for i in members
    ]


def rule_text(problem, front_size: int | None = None, knee: bool = True) -> str:
    """The rule in words (what ``Recommendation.rule`` says); ``knee``: :func:`select_rows`'s flag; without
    ``front_size`` the rule of every front (a fleet's ``rule``: one front a chair)."""
    if problem.max_threshold_force is not None:
        return RULES["cap_threshold"].format(cap=problem.max_threshold_force)
    if problem.max_turning_effort is not None:
        return RULES["cap_turning"].format(cap=problem.max_turning_effort)
    if front_size is None:
        return RULES["any"]
    if front_size < 3:
        return RULES["end"].format(w0=problem.weights[0], w1=problem.weights[1])
    return RULES["knee"] if knee else RULES["concave"].format(w0=problem.weights[0], w1=problem.weights[1])


def weights_meaning(weights) -> str:
    """What the weights of J = w_turn F_turn + w_threshold P mean, in one sentence."""
    w_turn, w_threshold = (float(x) for x in weights)
    if w_turn == 0:
        return "J = P: the weights ignore turning effort"
    return (
        f"J = {w_turn:g} F_turn + {w_threshold:g} P: 1 N of sill force is worth {w_threshold / w_turn:g} N "
        f"of turning effort"
    )
