"""Quality indicators of two-objective fronts (both objectives minimised).

Every indicator states its reference: the hypervolume's reference point and
normalisation are arguments, never hidden defaults.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # numpy.typing is for the checker only (import designer stays light)
    import numpy.typing as npt


def nondominated(points: np.ndarray) -> np.ndarray:
    """Boolean mask of the non-dominated rows of an (N, 2) array (minimisation).

    A point is dominated if another is no worse in both objectives and better
    in one.  Duplicates keep their first occurrence.
    """
    pts = np.asarray(points, float)
    order = np.lexsort((pts[:, 1], pts[:, 0]))
    second = pts[order, 1]  # by increasing first objective: kept where better than every point before it
    keep = np.empty(len(pts), bool)
    keep[order] = second < np.minimum.accumulate(np.concatenate([[np.inf], second[:-1]]))
    return keep


def normalise(points: np.ndarray, ideal: npt.ArrayLike, nadir: npt.ArrayLike) -> np.ndarray:
    """Map objectives to [0, 1] by (f − ideal) / (nadir − ideal)."""
    ideal = np.asarray(ideal, float)
    nadir = np.asarray(nadir, float)
    span = np.where(nadir - ideal > 0, nadir - ideal, 1.0)
    normalised: np.ndarray = (np.asarray(points, float) - ideal) / span
    return normalised


def hypervolume_2d(points: np.ndarray, reference: npt.ArrayLike) -> float:
    """Area dominated by ``points`` and bounded by ``reference`` (minimisation).

    Exact sweep over the sorted non-dominated points; points not strictly
    better than the reference in both objectives contribute nothing.
    """
    pts = np.asarray(points, float)
    if pts.size == 0:
        return 0.0
    ref = np.asarray(reference, float)
    pts = pts[np.all(pts < ref, axis=1)]
    if len(pts) == 0:
        return 0.0
    pts = pts[nondominated(pts)]
    pts = pts[np.argsort(pts[:, 0])]
    previous_y = np.concatenate([[ref[1]], pts[:-1, 1]])
    return float(np.sum((ref[0] - pts[:, 0]) * (previous_y - pts[:, 1])))


def igd_plus(points: np.ndarray, reference_front: np.ndarray) -> float:
    """IGD+ of ``points`` against a reference front (Ishibuchi et al. 2015).

    Mean over reference points r of min over points a of
    || max(a − r, 0) ||₂.  Zero when the points weakly dominate the whole
    reference front; compute it on normalised objectives.
    """
    a = np.asarray(points, float)
    r = np.asarray(reference_front, float)
    if len(a) == 0:
        return float("inf")
    diff = np.maximum(a[None, :, :] - r[:, None, :], 0.0)
    return float(np.mean(np.min(np.sqrt(np.sum(diff**2, axis=2)), axis=1)))
