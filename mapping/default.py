"""The default mapping from the ``toon32`` marker set onto the 21 motors (v1).

Each motor follows one marker coordinate in the head frame:
``value = neutral_value + (position - neutral_position) / mm_per_unit``, where the neutral
position comes from calibration (by default the take's first second) and ``mm_per_unit`` is a
typical performer's travel for the motor's full 0-1 range (:data:`CHANNELS`). HH and HV follow
the head's yaw and pitch from its rest pose, 60 degrees per unit. Values are clipped to [0, 1].
A motor whose marker (or the head pose) is unseen in a frame holds its last value and gets
confidence 0 for that frame.
"""

from __future__ import annotations

import numpy as np

from capture import MarkerSet, Take, load_markerset
from common import InputError
from mapping.calibrate import HeadPose, NeutralCalibration, calibrate_neutral, head_pose
from mapping.stabilise import to_head_frame, yaw_pitch_degrees
from toon import MotorTrack, mirror_values, motor_index, standard_neutral

#: (motor, marker, axis, millimetres of marker travel per unit of motor value).
CHANNELS: tuple[tuple[str, str, int, float], ...] = (
    ("BRL", "BROW_R_LAT", 1, 20.0), ("BRC", "BROW_R_CEN", 1, 20.0), ("BRM", "BROW_R_MED", 1, 20.0),
    ("BLL", "BROW_L_LAT", 1, 20.0), ("BLC", "BROW_L_CEN", 1, 20.0), ("BLM", "BROW_L_MED", 1, 20.0),
    ("ERU", "LID_R_UP", 1, 14.0), ("ERL", "LID_R_LOW", 1, 6.0),
    ("ELU", "LID_L_UP", 1, 14.0), ("ELL", "LID_L_LOW", 1, 6.0),
    ("PLH", "PUPIL_L", 0, 12.0), ("PLV", "PUPIL_L", 1, 8.0),
    ("PRH", "PUPIL_R", 0, 12.0), ("PRV", "PUPIL_R", 1, 8.0),
    ("MLH", "MOUTH_L", 0, 20.0), ("MLV", "MOUTH_L", 1, 20.0),
    ("MRH", "MOUTH_R", 0, -20.0), ("MRV", "MOUTH_R", 1, 20.0),
    ("MB", "LIP_LOW", 1, -24.0),
)
HEAD_DEGREES_PER_UNIT = 60.0


class DefaultMapping:
    """Calibrate on a take's neutral window, then turn takes into motor tracks.

    Parameters
    ----------
    neutral_window : tuple of float
        Seconds ``[start, end)`` where the performer holds a neutral face.
    target_neutral : ndarray, shape (21,), optional
        Motor values the performer's neutral face maps to; defaults to the standard neutral
        that every built-in face is drawn in. Pass ``face.neutral()`` to map for one face.
    mirror : bool
        Drive the character's left with the performer's right (a mirror image).
    markerset : MarkerSet or str
        The take's marker layout (its head references define the head frame).

    Attributes
    ----------
    markerset_ : MarkerSet
        The resolved marker set (loaded once, by :meth:`fit`).
    calibration_ : NeutralCalibration
        Set by :meth:`fit`.
    """

    def __init__(self, neutral_window: tuple[float, float] = (0.0, 1.0), target_neutral: np.ndarray | None = None,
                 mirror: bool = False, markerset: MarkerSet | str = "toon32") -> None:
        self.neutral_window = neutral_window
        self.target_neutral = target_neutral
        self.mirror = mirror
        self.markerset = markerset

    def fit(self, take: Take) -> DefaultMapping:
        """Calibrate the neutral pose on ``take``; raises :class:`InputError` saying why if it cannot."""
        self._fit(take)
        return self

    def transform(self, take: Take) -> MotorTrack:
        """Map a take (of the same performer and marker set) onto a :class:`MotorTrack`."""
        if not hasattr(self, "calibration_"):
            raise RuntimeError("call fit() before transform()")
        pose = head_pose(take, self.markerset_)
        if not pose:
            raise InputError(f"cannot remove head motion: {pose}")
        return self._transform(take, pose)

    def fit_transform(self, take: Take) -> MotorTrack:
        """:meth:`fit` then :meth:`transform` on the same take, fitting its head pose once."""
        return self._transform(take, self._fit(take))

    def _fit(self, take: Take) -> HeadPose:
        """Resolve the marker set, fit the head pose, calibrate; returns the pose for reuse."""
        missing = sorted({marker for _, marker, _, _ in CHANNELS} - set(take.labels))
        if missing:
            raise InputError(f"the default mapping needs toon32 markers missing from the take: {missing}")
        markerset = self.markerset if isinstance(self.markerset, MarkerSet) else load_markerset(self.markerset)
        pose = head_pose(take, markerset)
        if not pose:
            raise InputError(f"cannot calibrate: {pose}")
        calibration = calibrate_neutral(take, markerset, self.neutral_window, pose)
        if not calibration:
            raise InputError(f"cannot calibrate: {calibration}")
        self.markerset_: MarkerSet = markerset
        self.calibration_: NeutralCalibration = calibration
        return pose

    def _transform(self, take: Take, pose: HeadPose) -> MotorTrack:
        target = standard_neutral() if self.target_neutral is None else np.asarray(self.target_neutral, float)
        values = np.tile(target, (take.frames, 1))
        local = to_head_frame(take.positions, pose.rotation, pose.translation)
        cal = self.calibration_
        for code, marker, axis, mm in CHANNELS:
            col, row = motor_index(code), take.index(marker)
            rest = cal.neutral[cal.labels.index(marker), axis]
            values[:, col] = target[col] + (local[:, row, axis] - rest) / mm
        relative = np.einsum("ji,fjk->fik", cal.rest_rotation, pose.rotation)
        yaw, pitch = yaw_pitch_degrees(relative)
        values[:, motor_index("HH")] = target[motor_index("HH")] + yaw / HEAD_DEGREES_PER_UNIT
        values[:, motor_index("HV")] = target[motor_index("HV")] + pitch / HEAD_DEGREES_PER_UNIT
        seen = ~np.isnan(values)
        values = np.clip(_hold_last(values, target), 0.0, 1.0)
        if self.mirror:
            values = mirror_values(values, target)
        meta = {"mapping": "toon32-default-v1", "neutral_window": list(cal.window), "mirror": self.mirror,
                **{k: v for k, v in take.meta.items() if k == "source"}}
        return MotorTrack(values, take.rate, confidence=seen.astype(float), meta=meta)

    def describe(self) -> str:
        """The channels, one line each."""
        lines = [f"{code:>3} <- {marker}.{'xyz'[axis]} / {mm:+g} mm" for code, marker, axis, mm in CHANNELS]
        lines += [f" HH <- head yaw / {HEAD_DEGREES_PER_UNIT:g} deg", f" HV <- head pitch / {HEAD_DEGREES_PER_UNIT:g} deg"]
        if hasattr(self, "calibration_"):
            lines.append(f"neutral from {self.calibration_.window[0]:g}-{self.calibration_.window[1]:g} s")
        return "\n".join(lines)


def _hold_last(values: np.ndarray, initial: np.ndarray) -> np.ndarray:
    """Replace NaN by the column's last finite value (``initial`` before the first)."""
    out = values.copy()
    for col in range(out.shape[1]):
        column = out[:, col]
        bad = np.isnan(column)
        if bad.any():
            idx = np.where(~bad, np.arange(len(column)), -1)
            np.maximum.accumulate(idx, out=idx)
            column[:] = np.where(idx >= 0, column[np.maximum(idx, 0)], initial[col])
    return out

