"""One side of one motor learned from a range-of-motion sweep, robustly (:func:`side_basis`), and a
motor's two sides made whole where the sweep did not show one (:func:`either_side`); used by
:func:`mapping.solver.learn_solver`.

A sweep is capture too: labels swap for a few frames, samples spike, markers hide at a face's
extremes. What one side of a motor does to each marker is a robust regression through rest on
the motor's share, and a marker the side never saw is taken from the other side.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from mapping.robust import column_nan_median
from mapping.roles import mirror_pairs
from toon.motors import MIRROR_OF

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


def own_motion(up: np.ndarray, down: np.ndarray, own: np.ndarray) -> np.ndarray:
    """How far each marker moves per unit of share, at most, for a motor whose rule reads it,
    ``(M,)``, 0 for a marker no rule reads; ``up`` and ``down`` ``(K, M, 3)``: the motors' sides,
    ``own`` ``(M, K)``: which markers each motor's rule reads.

    >>> up = np.zeros((2, 2, 3)); up[0, 0, 1], up[1, 0, 1], up[1, 1, 1] = 3.0, 0.9, 8.9
    >>> own_motion(up, np.zeros_like(up), np.array([[True, False], [False, True]])).tolist()
    [3.0, 8.9]
    """
    motion = np.maximum(np.linalg.norm(up, axis=2), np.linalg.norm(down, axis=2)).T  # (M, K)
    return np.where(own, np.nan_to_num(motion), 0.0).max(axis=1, initial=0.0)


def _shared_part(part: np.ndarray, seen: np.ndarray) -> np.ndarray:
    """Each marker's mean ``part`` ``(F, M)`` of the motion over the frames it is ``seen``, ``(M,)``."""
    return (part * seen).sum(axis=0) / np.maximum(seen.sum(axis=0), 1)


Side = tuple[np.ndarray, np.ndarray] | None


def from_mirror(codes: Sequence[str], learned: dict[int, list[Side]], far: np.ndarray, rest: np.ndarray
                ) -> list[str]:
    """Each side of a motor the sweep showed without its own markers in view, taken from its
    mirror motor's side (mirrored across the face's midline, x = 0 of the head frame), in place
    in ``learned`` (motor row -> its high and low sides, :func:`side_basis`'s pairs, or None);
    the sides taken (``"ELU low"``), for a note.

    Markers hide most at a face's extremes: on a draw of the fourth performer the left upper
    lid's marker was lost for the whole of the left eye's closing, so that side was learned from
    no seen sample of the lid and taken through rest from its opening (1.3 mm a share where its
    closing is 6): every squint then read as a shut eye (ELU r 0.84). A sweep moves both sides of
    a face together, and a face is closer to symmetric than an opening is to a closing (mirrored,
    or the same way across where the motors' other sides move so). A side is
    taken only where its mirror's saw the mirror motor's own markers, on the motor's own half of
    the face and the midline, scaled as the two motors' other sides compare
    (:func:`_as_other_sides`). ``far`` ``(M, K)``: each marker's distance from each motor's own
    markers (0: one its rule reads); ``rest`` ``(M, 3)``: where the markers rest (their mirror
    partners are :func:`mapping.roles.mirror_pairs`, the motor's own markers the mirror motor's,
    :func:`_own_partners`; one with none is left still)."""
    everyone = mirror_pairs(rest)
    own = far == 0.0
    taken: list[str] = []
    for k, sides in learned.items():
        mirror = codes.index(MIRROR_OF[codes[k]]) if MIRROR_OF.get(codes[k]) in codes else -1
        for i, side in enumerate(sides):
            theirs = learned.get(mirror, [None, None])[i]
            if mirror < 0 or theirs is None or not (theirs[1] & own[:, mirror]).any() or (
                    side is not None and (side[1] & own[:, k]).any()):
                continue  # no mirror, the mirror's side did not see its own markers, or this side saw its own
            partner = _own_partners(everyone, own[:, k], own[:, mirror], rest)  # only for a side to take
            seen = np.where(partner >= 0, theirs[1][partner] & own[partner, mirror], False)  # (M,)
            if not (seen & own[:, k]).any():
                continue  # the mirror's own markers are not this motor's mirrored (a layout not symmetric)
            mine = (partner >= 0) & (far[:, k] <= far[:, mirror])  # its own half of the face and the midline
            scale, flip = _as_other_sides(sides[1 - i], learned[mirror][1 - i], own[:, k] & seen, partner)
            sides[i] = (np.where(mine[:, None], theirs[0][partner] * flip * scale, 0.0),
                        np.where(mine, theirs[1][partner], False))
            taken.append(f"{codes[k]} {'high' if i == 0 else 'low'}")
    return taken


def _own_partners(partner: np.ndarray, mine: np.ndarray, theirs: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """Mirror partners ``partner`` ``(M,)`` (-1: none) with a motor's own markers ``mine`` ``(M,)``
    paired with its mirror motor's own ``theirs`` ``(M,)``, as a whole by their mirrored rests
    ``rest`` ``(M, 3)``, however far apart (a marker these displace loses its partner).

    The two motors are each other's mirror by their roles, so their own markers are too, where
    the face or the markers' placement is not: on a draw of the fourth performer, with its eyes'
    centres 2.4 mm from symmetric and each lower lid's marker placed 5-6 mm off the other way,
    the lower lids' mirror images lay 14 mm apart, no pair by geometry alone, and a right lower
    lid lost through its raise took its lowering through rest (the lid solved at twice its
    truth's travel, ERL r 0.94)."""
    a, b = np.flatnonzero(mine & ~theirs), np.flatnonzero(theirs & ~mine)
    known = np.isfinite(rest[a]).all(axis=1)[:, None] & np.isfinite(rest[b]).all(axis=1)[None, :]
    if not known.any():
        return partner
    cost = np.linalg.norm(rest[a][:, None] * np.array([-1.0, 1.0, 1.0]) - rest[b][None], axis=2)
    rows, cols = linear_sum_assignment(np.where(known, cost, 1e12))
    out = partner.copy()
    for r, c in zip(rows, cols, strict=True):
        if known[r, c]:
            i, j = a[r], b[c]
            out[(out == i) | (out == j)] = -1  # their partners by geometry lose them
            out[i], out[j] = j, i
    return out


def _as_other_sides(mine: Side, theirs: Side, pairs: np.ndarray, partner: np.ndarray) -> tuple[float, np.ndarray]:
    """How a mirror motor's side stands for a motor's, as their other sides (``mine``, ``theirs``)
    compare on the markers ``pairs`` ``(M,)`` and their partners, both seen there: how much further
    the motor's reaches (the median ratio; 1 where none: two rules' shares need not have one
    scale, a side's range from a mirror's reach, the other's from its own, and a basis is per unit
    of its own rule's share), and ``(3,)``, mirrored across the midline (x flipped), or the same
    where the two move their markers the same way across. Two pupils turn together (PRH and PLH
    are mirror motors by name, and a right pupil's turn mirrored read every glance of the left
    backwards, PLH r 0.37 on a draw of the fourth performer). Mirrored where the other sides do
    not say."""
    mirrored = np.array([-1.0, 1.0, 1.0])
    if mine is None or theirs is None:
        return 1.0, mirrored
    both = pairs & mine[1] & np.where(partner >= 0, theirs[1][partner], False)
    reach = np.linalg.norm(mine[0][both], axis=1), np.linalg.norm(theirs[0][partner[both]], axis=1)
    usable = reach[1] > 1e-9
    scale = float(np.median(reach[0][usable] / reach[1][usable])) if usable.any() else 1.0
    same_way = float(np.sum(mine[0][both, 0] * theirs[0][partner[both], 0])) > 0.0
    return scale, np.ones(3) if same_way else mirrored
