"""What a motor can follow: measurements on head-stabilised markers and on the head itself.

Kinds (all in the marker set's head frame: x to the performer's left, y up, z out of the face):

``marker``
    One coordinate of one marker, mm: ``{ marker = "LID_R_UP", axis = "y" }``.
``distance``
    The distance between two markers, mm: ``{ distance = ["LIP_UP", "LIP_LOW"] }``.
``difference``
    One coordinate of the first marker minus the second's, mm:
    ``{ difference = ["BROW_R_LAT", "EYE_R_OUT"], axis = "y" }``.
``angle``
    The angle at the middle marker between the other two, degrees:
    ``{ angle = ["MOUTH_R", "LIP_LOW", "MOUTH_L"] }``.
``head``
    The head's ``yaw`` (toward the performer's left), ``pitch`` (chin up) or ``roll``
    (counter-clockwise as the camera sees it) from its rest pose, degrees: ``{ head = "yaw" }``.
``blendshape``
    A blendshape score, 0..1, from a take's channels (a markerless tracker's, ARKit's names):
    ``{ blendshape = "jawOpen" }``. Not head-relative: the tracker has taken the head out.

Every source has a canonical text key (``LID_R_UP.y``, ``distance(LIP_UP,LIP_LOW)``,
``head.yaw``, ``blendshape.jawOpen``) under which a performer profile keeps its neutral value
and range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture.blendshapes import BLENDSHAPES
from mapping.stabilise import yaw_pitch_degrees

AXES = "xyz"
KINDS = ("marker", "distance", "difference", "angle", "head", "blendshape")
#: A ``head`` source's axes: turn, nod and roll (degrees from the rest pose).
HEAD_AXES = ("yaw", "pitch", "roll")
#: A score's worth of one millimetre, where thresholds written in mm (the least range a source
#: must span, the span a range starts from) apply to blendshape scores: 4 mm, a small deliberate
#: motion of a lip or a brow, is 0.2 of a score.
SCORE_PER_MM = 0.05
#: The names a blendshape source may read: ARKit's 52 (MediaPipe reports all but ``tongueOut``).
BLENDSHAPE_NAMES = frozenset(BLENDSHAPES) | {"tongueOut"}


@dataclass(frozen=True)
class Source:
    """One measurement (see the module docstring).

    Attributes
    ----------
    kind : str
    markers : tuple of str
        Marker-set labels: 1 (marker), 2 (distance, difference), 3 (angle) or none (head,
        blendshape).
    axis : int
        0, 1, 2 for x, y, z (marker, difference); for head, 0 yaw, 1 pitch and 2 roll.
    invert : bool
        Follow the source's decrease instead of its increase.
    weight : float
        Weight in a weighted combine.
    channel : str
        The blendshape's name (blendshape).
    only : str
        ``increase`` or ``decrease``: only the source's motion that way from rest counts (the
        other way reads as rest), before ``invert``; empty: both ways.
    """

    kind: str
    markers: tuple[str, ...] = ()
    axis: int = 1
    invert: bool = False
    weight: float = 1.0
    channel: str = ""
    only: str = ""

    @property
    def key(self) -> str:
        """Canonical text, the profile's key for this measurement (``invert``, ``weight`` and
        ``only`` aside)."""
        if self.kind == "marker":
            return f"{self.markers[0]}.{AXES[self.axis]}"
        if self.kind == "head":
            return f"head.{HEAD_AXES[self.axis]}"
        if self.kind == "blendshape":
            return f"blendshape.{self.channel}"
        axis = f".{AXES[self.axis]}" if self.kind == "difference" else ""
        return f"{self.kind}({','.join(self.markers)}){axis}"


def mm_scale(key: str) -> float:
    """What one millimetre is worth in the units of the source keyed ``key`` (1 but for a
    blendshape score's :data:`SCORE_PER_MM`), to scale thresholds written in mm."""
    return SCORE_PER_MM if key.startswith("blendshape.") else 1.0


def measure(source: Source, local: np.ndarray, columns: dict[str, int], head: np.ndarray | None,
            channels: dict[str, np.ndarray] | None = None) -> np.ndarray:
    """Values of ``source`` per frame.

    Parameters
    ----------
    local : ndarray, shape (F, M, 3)
        Head-frame marker positions, NaN where unseen.
    columns : dict
        Marker-set label -> column of ``local``.
    head : ndarray, shape (F, 2), optional
        Head yaw and pitch from rest, degrees (needed by ``head`` sources).
    channels : dict of str to ndarray, shape (F,), optional
        The take's channels by name (read by ``blendshape`` sources).

    Returns
    -------
    ndarray, shape (F,)
        NaN where a marker it needs is unseen (or the channel it reads is absent).
    """
    if source.kind == "blendshape":
        found = (channels or {}).get(source.channel)
        return np.full(len(local), np.nan) if found is None else np.asarray(found, dtype=float)
    points = [local[:, columns[m]] for m in source.markers]
    if source.kind == "marker":
        return points[0][:, source.axis]
    if source.kind == "difference":
        return points[0][:, source.axis] - points[1][:, source.axis]
    if source.kind == "distance":
        return np.linalg.norm(points[0] - points[1], axis=1)
    if source.kind == "angle":
        a, b = points[0] - points[1], points[2] - points[1]
        cos = (a * b).sum(axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    if head is None:
        return np.full(len(local), np.nan)
    return head[:, source.axis]


def head_angles(rotation: np.ndarray, rest: np.ndarray, axes: np.ndarray | None = None) -> np.ndarray:
    """Yaw, pitch and roll (degrees) of head rotations ``(F, 3, 3)`` from the rest rotation
    ``(3, 3)``; ``(F, 3)``, NaN for frames without a pose. Roll is the head's up direction
    turned about the view axis, counter-clockwise as the camera sees it positive (the head
    frame's x to the right of the picture, y up, z toward the camera). ``axes`` ``(3, 3)``:
    the head's own turning axes in the head frame (:func:`mapping.head_axes.turning_axes`),
    about which the angles are read; the head frame's where None."""
    if axes is not None:
        rotation, rest = rotation @ axes, np.asarray(rest) @ axes
    ok = np.isfinite(rotation).all(axis=(1, 2))
    relative = np.asarray(rest).T @ np.where(ok[:, None, None], rotation, np.eye(3))
    yaw, pitch = yaw_pitch_degrees(relative)
    up = relative[:, :, 1]
    roll = np.degrees(np.arctan2(-up[:, 0], up[:, 1]))
    angles = np.column_stack([yaw, pitch, roll])
    angles[~ok] = np.nan
    return angles
