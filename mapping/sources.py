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
    The head's ``yaw`` (toward the performer's left) or ``pitch`` (chin up) from its rest pose,
    degrees: ``{ head = "yaw" }``.

Every source has a canonical text key (``LID_R_UP.y``, ``distance(LIP_UP,LIP_LOW)``,
``head.yaw``) under which a performer profile keeps its neutral value and range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mapping.stabilise import yaw_pitch_degrees

AXES = "xyz"
KINDS = ("marker", "distance", "difference", "angle", "head")


@dataclass(frozen=True)
class Source:
    """One measurement (see the module docstring).

    Attributes
    ----------
    kind : str
    markers : tuple of str
        Marker-set labels: 1 (marker), 2 (distance, difference), 3 (angle) or none (head).
    axis : int
        0, 1, 2 for x, y, z (marker, difference); for head, 0 yaw and 1 pitch.
    invert : bool
        Follow the source's decrease instead of its increase.
    weight : float
        Weight in a weighted combine.
    """

    kind: str
    markers: tuple[str, ...] = ()
    axis: int = 1
    invert: bool = False
    weight: float = 1.0

    @property
    def key(self) -> str:
        """Canonical text, the profile's key for this measurement (``invert``/``weight`` aside)."""
        if self.kind == "marker":
            return f"{self.markers[0]}.{AXES[self.axis]}"
        if self.kind == "head":
            return f"head.{('yaw', 'pitch')[self.axis]}"
        axis = f".{AXES[self.axis]}" if self.kind == "difference" else ""
        return f"{self.kind}({','.join(self.markers)}){axis}"


def measure(source: Source, local: np.ndarray, columns: dict[str, int], head: np.ndarray | None) -> np.ndarray:
    """Values of ``source`` per frame.

    Parameters
    ----------
    local : ndarray, shape (F, M, 3)
        Head-frame marker positions, NaN where unseen.
    columns : dict
        Marker-set label -> column of ``local``.
    head : ndarray, shape (F, 2), optional
        Head yaw and pitch from rest, degrees (needed by ``head`` sources).

    Returns
    -------
    ndarray, shape (F,)
        NaN where a marker it needs is unseen.
    """
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


def head_angles(rotation: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """Yaw and pitch (degrees) of head rotations ``(F, 3, 3)`` from the rest rotation ``(3, 3)``;
    ``(F, 2)``, NaN for frames without a pose."""
    ok = np.isfinite(rotation).all(axis=(1, 2))
    relative = np.einsum("ji,fjk->fik", rest, np.where(ok[:, None, None], rotation, np.eye(3)))
    yaw, pitch = yaw_pitch_degrees(relative)
    angles = np.column_stack([yaw, pitch])
    angles[~ok] = np.nan
    return angles
