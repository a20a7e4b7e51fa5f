"""Neutral calibration: where the performer's markers rest, in the head frame."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from capture import MarkerSet, Take
from common import Failure
from mapping.stabilise import rigid_fit, to_head_frame


@dataclass(frozen=True, eq=False)
class NeutralCalibration:
    """The performer at rest.

    Attributes
    ----------
    labels : tuple of str, length M
        The take's markers.
    neutral : ndarray, shape (M, 3)
        Rest positions in the marker set's head frame, mm (NaN for markers never seen at rest).
    rest_rotation : ndarray, shape (3, 3)
        Head frame to world at rest; head turns are measured from it.
    window : tuple of float
        The time range (seconds) it was computed from.
    """

    labels: tuple[str, ...]
    neutral: np.ndarray
    rest_rotation: np.ndarray
    window: tuple[float, float]


@dataclass(frozen=True, eq=False)
class HeadPose:
    """Per-frame head pose, head frame to world: ``rotation`` (F, 3, 3), ``translation`` (F, 3), ``ok`` (F,)."""

    rotation: np.ndarray
    translation: np.ndarray
    ok: np.ndarray


def head_pose(take: Take, markerset: MarkerSet) -> HeadPose | Failure:
    """Fit the marker set's neutral head references to every frame of ``take``."""
    missing = [r for r in markerset.head_reference if r not in take.labels]
    if missing:
        return Failure(f"head reference markers {missing} are not in the take")
    source = np.array([markerset.neutral_of(r) for r in markerset.head_reference])
    rot, trans, ok = rigid_fit(source, take.select(markerset.head_reference))
    if not ok.any():
        return Failure("fewer than 3 head reference markers are seen in every frame")
    return HeadPose(rot, trans, ok)


def calibrate_neutral(take: Take, markerset: MarkerSet, window: tuple[float, float] = (0.0, 1.0),
                      pose: HeadPose | None = None) -> NeutralCalibration | Failure:
    """Neutral positions from the frames in ``window`` (seconds, ``[start, end)``).

    Returns a :class:`~common.Failure` saying why when the window holds no frames, or no frame
    in it has a head pose.
    """
    start, end = window
    frames = take.window(start, end)
    if not frames.any():
        return Failure(f"no frames in the neutral window {start:g}-{end:g} s "
                       f"(take spans {take.times[0]:g}-{take.times[-1]:g} s)")
    if pose is None:
        pose = head_pose(take, markerset)
        if not pose:
            return pose  # the Failure
    usable = frames & pose.ok
    if not usable.any():
        return Failure(f"head reference markers are missing in every frame of {start:g}-{end:g} s")
    local = to_head_frame(take.positions[usable], pose.rotation[usable], pose.translation[usable])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN columns: markers never seen at rest
        neutral = np.nanmedian(local, axis=0)
    rest = _mean_rotation(pose.rotation[usable])
    neutral.setflags(write=False)
    return NeutralCalibration(take.labels, neutral, rest, (start, end))


def _mean_rotation(rotations: np.ndarray) -> np.ndarray:
    """The rotation nearest to the element-wise mean of ``(F, 3, 3)`` rotations."""
    u, _, vt = np.linalg.svd(rotations.mean(axis=0))
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1
        r = u @ vt
    return r
