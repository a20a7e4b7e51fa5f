"""``MotorTrack``: motor values over time, the hand-off between mapping and player."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from common import InputError, readonly
from toon.motors import MOTOR_CODES, N_MOTORS, motor_index


@dataclass(frozen=True, eq=False)
class MotorTrack:
    """Positions of the 21 motors, one row per frame.

    Parameters
    ----------
    values : array_like, shape (frames, 21)
        Each motor's position in ``[0, 1]`` between its min and max (ToonFace's ``P_CTRL``);
        columns in ``MOTOR_CODES`` order. Must be finite.
    rate : float
        Frames per second.
    confidence : array_like, shape (frames, 21), optional
        How much each value is backed by observed data, in ``[0, 1]``.
    meta : dict, optional
        Free-form provenance (source file, mapping, ...).
    """

    values: np.ndarray
    rate: float
    confidence: np.ndarray | None = None
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        values = np.asarray(self.values, dtype=np.float64)
        if values.ndim != 2 or values.shape[1] != N_MOTORS:
            raise InputError(f"motor values must have shape (frames, {N_MOTORS}), got {values.shape}")
        if not np.all(np.isfinite(values)):
            bad = np.argwhere(~np.isfinite(values))[0]
            raise InputError(f"motor value is not finite at frame {bad[0]}, motor {MOTOR_CODES[bad[1]]}")
        if values.size and (values.min() < 0.0 or values.max() > 1.0):
            frame, col = np.unravel_index(np.argmax((values < 0) | (values > 1)), values.shape)
            raise InputError(f"motor {MOTOR_CODES[col]} at frame {frame} is {values[frame, col]:.6g}, "
                             "outside [0, 1]")
        if not (np.isfinite(self.rate) and self.rate > 0):
            raise InputError(f"rate must be a positive number of frames per second, got {self.rate!r}")
        object.__setattr__(self, "values", readonly(values))
        object.__setattr__(self, "rate", float(self.rate))
        if self.confidence is not None:
            conf = np.asarray(self.confidence, dtype=np.float64)
            if conf.shape != values.shape:
                raise InputError(f"confidence shape {conf.shape} differs from values shape {values.shape}")
            object.__setattr__(self, "confidence", readonly(conf))

    @classmethod
    def from_columns(cls, codes: tuple[str, ...] | list[str], values: np.ndarray, rate: float,
                     **kwargs) -> MotorTrack:
        """Build a track from columns in any order, named by motor code (all 21 needed)."""
        codes = list(codes)
        missing = [c for c in MOTOR_CODES if c not in codes]
        if missing or len(codes) != N_MOTORS:
            raise InputError(f"motor columns must name each of the 21 motors once; missing {missing}")
        order = [codes.index(c) for c in MOTOR_CODES]
        return cls(np.asarray(values, dtype=np.float64)[:, order], rate, **kwargs)

    @property
    def frames(self) -> int:
        """Number of frames."""
        return self.values.shape[0]

    @property
    def times(self) -> np.ndarray:
        """Frame times in seconds, shape ``(frames,)``, starting at 0."""
        return np.arange(self.frames) / self.rate

    @property
    def duration(self) -> float:
        """Seconds from the first frame to the end of the last."""
        return self.frames / self.rate

    def column(self, code: str) -> np.ndarray:
        """One motor's values, shape ``(frames,)``."""
        return self.values[:, motor_index(code)]
