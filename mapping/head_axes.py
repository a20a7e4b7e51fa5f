"""The head's own turning axes, learnt from the head turns of a range-of-motion take.

The head frame is fitted on the head-reference markers, so its axes are the marker set's: where
a performer's references sit a few millimetres off nominal (a temple 2.5 mm high, the other low),
that frame is rolled by a degree or more against the head's own axes, and a turn of the head
about its own vertical axis reads, in it, as a turn and a nod: on the fourth synthetic performer
(a frame 3 degrees off), 1.5 degrees of nod at 40 degrees of turn, HV's error 3 % of its range.
A range-of-motion take turns the head alone and nods it alone, so its motion shows the two
axes: the head's turn over each 50 ms as an axis and an angle in the head frame (the axis its
own, whatever the head's pose then; a turn measured from rest instead carried a slow roll of the
head into the axis), those near the frame's vertical (or its side-to-side axis) averaged, each
weighted by how far the head turned. :func:`mapping.sources.head_angles` then reads yaw and pitch
about those axes.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

#: The head's turn is read over this long (seconds): long enough to lift a sweep's turn well over
#: the head fit's jitter, short enough that a slow roll or drift adds little to it.
STEP_SECONDS = 0.05
#: A step's axis counts toward the vertical (or side-to-side) axis within this angle (degrees)
#: of the head frame's: a turn and a nod at once lie between them and count for neither.
NEAR_DEGREES = 15.0
#: The head must turn at least this far in all (degrees) about an axis before it is believed.
LEAST_TURN_DEGREES = 30.0


def turning_axes(rotation: np.ndarray, frames: np.ndarray, rate: float) -> np.ndarray | None:
    """The head's turning axes in the head frame, ``(3, 3)``: columns the nodding (side-to-side)
    axis, the turning (vertical) axis and their cross product (toward the face), from the head
    rotations ``(F, 3, 3)`` (head frame to world, NaN without a pose) over ``frames`` ``(F,)``
    of a range-of-motion take sampled at ``rate`` Hz. None where the head turns too little about
    its vertical (:data:`LEAST_TURN_DEGREES`); without nods the side-to-side axis is the head
    frame's own, made square to the vertical found.

    >>> tilt = Rotation.from_euler("z", 3, degrees=True).as_matrix()  # a frame rolled 3 degrees
    >>> turns = Rotation.from_euler("y", 40 * np.sin(np.linspace(0, 6, 300))[:, None], degrees=True).as_matrix()
    >>> axes = turning_axes(turns @ tilt, np.ones(300, bool), 50.0)  # the turns as that frame sees them
    >>> bool(np.allclose(axes[:, 1], tilt.T @ [0.0, 1.0, 0.0])), bool(np.allclose(axes.T @ axes, np.eye(3)))
    (True, True)
    """
    step = max(1, int(round(STEP_SECONDS * rate)))
    posed = np.isfinite(rotation).all(axis=(1, 2)) & frames
    pairs = np.flatnonzero(posed[:-step] & posed[step:]) if len(posed) > step else np.zeros(0, int)
    if not len(pairs):
        return None
    moves = np.transpose(rotation[pairs], (0, 2, 1)) @ rotation[pairs + step]  # each step's turn, head frame
    turns = Rotation.from_matrix(moves).as_rotvec()  # (P, 3): axis times angle
    found = [_axis(turns, k) for k in (0, 1)]
    vertical = found[1]
    if vertical is None:
        return None
    across = found[0] if found[0] is not None else np.eye(3)[0]
    across = across - (across @ vertical) * vertical
    across /= np.linalg.norm(across)
    return np.column_stack([across, vertical, np.cross(across, vertical)])


def _axis(turns: np.ndarray, k: int) -> np.ndarray | None:
    """The mean axis of the turns ``turns`` ``(P, 3)`` (axis times angle) within
    :data:`NEAR_DEGREES` of the head frame's axis ``k``, each turned to point along it and
    weighted by its angle; None where they add up to less than :data:`LEAST_TURN_DEGREES`."""
    angle = np.linalg.norm(turns, axis=1)
    along = turns[:, k] / np.maximum(angle, 1e-12)
    near = np.abs(along) >= np.cos(np.radians(NEAR_DEGREES))
    if np.degrees(angle[near].sum()) < LEAST_TURN_DEGREES:
        return None
    mean = (turns[near] * np.sign(along[near])[:, None]).sum(axis=0)
    return mean / np.linalg.norm(mean)


def axes_note(axes: np.ndarray) -> str:
    """What a profile's notes say of learnt ``axes`` ``(3, 3)``: how far they are from the head frame's."""
    off = float(np.degrees(np.arccos(np.clip((np.trace(axes) - 1.0) / 2.0, -1.0, 1.0))))
    return f"learnt from the range's head turns and nods, {off:.1f} degrees from the head frame's"
