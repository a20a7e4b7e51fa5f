"""mapping: turn a :class:`capture.Take` into a :class:`toon.MotorTrack`.

Imports ``capture`` (for takes) and ``toon`` (for motor codes and tracks), nothing else.
"""

from mapping.calibrate import HeadPose, NeutralCalibration, calibrate_neutral, head_pose
from mapping.default import DefaultMapping

__all__ = ["DefaultMapping", "HeadPose", "NeutralCalibration", "calibrate_neutral", "head_pose"]
