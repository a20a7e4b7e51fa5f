"""One side of one motor learned from a range-of-motion sweep, robustly (:func:`side_basis`), and a
motor's two sides made whole where the sweep did not show one (:func:`either_side`); used by
:func:`mapping.solver.learn_solver`.

A sweep is capture too: labels swap for a few frames, samples spike, markers hide at a face's
extremes. What one side of a motor does to each marker is a robust regression through rest on
the motor's share, and a marker the side never saw is taken from the other side.
"""

from __future__ import annotations

import numpy as np

from mapping.robust import column_nan_median

#: Robust weights fall to a half at this many times the sweep's residual per marker.
ROBUST_SCALE = 3.0
#: ... and never below this (mm): a face's motion is not the sweep's sum of motors to a tenth of a
#: millimetre, and a marker off by that much is not an outlier.
ROBUST_FLOOR_MM = 1.0
#: A marker seen in fewer of a side's frames is not learned on that side (it takes the other's): a
#: lid closing is often seen in a handful, a marker behind a shut lid is a stray sample or two.
SEEN_FRAMES = 3
#: A marker is a motor's where it is nearest the motor in at least this share of the frames of a
#: side that see it: a few frames where a neighbour motor seemed still (a label swap read by its
#: rule) do not make its markers another motor's.
MOSTLY = 0.5
#: Weighted passes of learning each side of a motor (:func:`side_basis`).
LEARN_PASSES = 3


def side_basis(s: np.ndarray, ok: np.ndarray, part: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What one side of a motor does to each marker, ``(M, 3)``, and which markers that side's
    frames saw in at least :data:`SEEN_FRAMES` ``(M,)`` (bool): each marker's displacement ``d``
    ``(F, M, 3)`` regressed through rest on the motor's share ``s`` ``(F,)`` over the frames it is
    seen in (``ok`` ``(F, M)``), robustly, and times its ``part`` ``(F, M)`` of it (a marker shared
    by two moving motors is half each's).

    A sweep is capture too: a label swapped for a few frames (two brow markers 20 mm apart) or a
    spike, believed, becomes motion of the motor that moved then (on the fourth performer a swap of
    the right brow's markers while the left brow rose taught BLM to move the right brow, and BLM
    followed its truth at r 0.47). So the fit starts from each marker's median displacement per
    unit of share, and is weighted :data:`LEARN_PASSES` times by Cauchy weights of each sample's
    miss, at :data:`ROBUST_SCALE` times the motor's median miss (at least :data:`ROBUST_FLOOR_MM`);
    and a marker that is the motor's in under :data:`MOSTLY` of the frames that see it is not its
    (there the swap made the neighbour's rule read its motor as still, and its markers went to
    the motor that moved with it)."""
    seen = ok & (part > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(seen[..., None], d / s[:, None, None], np.nan).reshape(len(s), -1)
    basis = np.nan_to_num(column_nan_median(ratio).reshape(d.shape[1:]))
    for _ in range(LEARN_PASSES):
        miss = np.linalg.norm(d - s[:, None, None] * basis, axis=2)  # (F, M)
        scale = max(ROBUST_SCALE * float(np.median(miss[seen])) if seen.any() else 0.0, ROBUST_FLOOR_MM)
        weight = seen / (1.0 + (miss / scale) ** 2)
        basis = np.einsum("f,fm,fmc->mc", s, weight, d) / np.maximum(weight.T @ (s ** 2), 1e-12)[:, None]
    mostly = (seen.sum(axis=0) >= MOSTLY * ok.sum(axis=0)) & seen.any(axis=0)
    return np.where(mostly[:, None], basis * _shared_part(part, seen)[:, None], 0.0), ok.sum(axis=0) >= SEEN_FRAMES


def either_side(high: tuple[np.ndarray, np.ndarray] | None, low: tuple[np.ndarray, np.ndarray] | None,
                 own: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A motor's two sides, ``(M, 3)`` each, from what each side's frames taught (its basis, and
    which markers they saw, :func:`side_basis`); ``own`` ``(M,)``: the markers its rule reads.

    A side the sweep did not show is the other side through rest. So is a marker one side never
    saw (an upper lid's marker hidden for all of a shut eye's frames), scaled by how much further
    the motor's own markers seen on both sides reach on that side than on the other (their
    median; 1 where there are none): a jaw's chin hidden while it opened took its clench, 3 mm a
    share, for its opening, 20, and every opening then read several times too wide."""
    if high is None or low is None:
        only = high if high is not None else low
        assert only is not None, "a motor with neither side is not learned"
        return only[0], only[0]
    (up, seen_up), (down, seen_down) = high, low
    both = seen_up & seen_down & own
    reach = (np.linalg.norm(up[both], axis=1), np.linalg.norm(down[both], axis=1))
    ratio = float(np.median(reach[0] / np.maximum(reach[1], 1e-9))) if both.any() and reach[1].min() > 0 else 1.0
    return (np.where((seen_down & ~seen_up)[:, None], down * ratio, up),
            np.where((seen_up & ~seen_down)[:, None], up / ratio, down))


def _shared_part(part: np.ndarray, seen: np.ndarray) -> np.ndarray:
    """Each marker's mean ``part`` ``(F, M)`` of the motion over the frames it is ``seen``, ``(M,)``."""
    return (part * seen).sum(axis=0) / np.maximum(seen.sum(axis=0), 1)
