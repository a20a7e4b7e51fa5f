"""``MotorTrack``: motor values over time, the hand-off between mapping and player."""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

import numpy as np

from common import InputError, readonly
from toon.motors import EXTRA_CODE, MOTOR_CODES, N_MOTORS, motor_index


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
    extra_codes : tuple of str
        Parameters beyond the 21 (a face's own, such as ``HT``, :data:`toon.motors.STANDARD_EXTRAS`).
    extra : array_like, shape (frames, len(extra_codes)), optional
        Their values in ``[0, 1]``; none where ``extra_codes`` is empty.
    """

    values: np.ndarray
    rate: float
    confidence: np.ndarray | None = None
    meta: dict = field(default_factory=dict)
    extra_codes: tuple[str, ...] = ()
    extra: np.ndarray | None = None

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
        self._check_extra(values.shape[0])
        object.__setattr__(self, "rate", float(self.rate))
        if self.confidence is not None:
            conf = np.asarray(self.confidence, dtype=np.float64)
            if conf.shape != values.shape:
                raise InputError(f"confidence shape {conf.shape} differs from values shape {values.shape}")
            object.__setattr__(self, "confidence", readonly(conf))

    @classmethod
    def from_columns(cls, codes: tuple[str, ...] | list[str], values: np.ndarray, rate: float,
                     **kwargs) -> MotorTrack:
        """Build a track from columns in any order, named by motor code (all 21 needed); columns
        with other codes (``HT``...) are its extra parameters, in the order given."""
        codes = list(codes)
        missing = [c for c in MOTOR_CODES if c not in codes]
        if missing or len(codes) != len(set(codes)):
            raise InputError(f"motor columns must name each of the 21 motors once; missing {missing}")
        table = np.asarray(values, dtype=np.float64)
        order = [codes.index(c) for c in MOTOR_CODES]
        extra = [i for i, c in enumerate(codes) if c not in MOTOR_CODES]
        if not extra:
            return cls(table[:, order], rate, **kwargs)
        return cls(table[:, order], rate, extra_codes=tuple(codes[i] for i in extra), extra=table[:, extra], **kwargs)

    def _check_extra(self, frames: int) -> None:
        codes = tuple(self.extra_codes)
        bad = [c for c in codes if c in MOTOR_CODES or not re.fullmatch(EXTRA_CODE, c)]
        if bad or len(set(codes)) != len(codes):
            raise InputError("extra parameter codes must be new, unique and like HT (capitals, digits, _); "
                             f"got {bad or codes}")
        if not codes:
            object.__setattr__(self, "extra", None)
            return
        extra = np.asarray(self.extra if self.extra is not None else [], dtype=np.float64)
        if extra.shape != (frames, len(codes)):
            raise InputError(f"extra values must have shape ({frames}, {len(codes)}), got {extra.shape}")
        if not np.all(np.isfinite(extra)) or (extra.size and (extra.min() < 0.0 or extra.max() > 1.0)):
            raise InputError(f"extra parameters {', '.join(codes)} must be finite and within [0, 1]")
        object.__setattr__(self, "extra_codes", codes)
        object.__setattr__(self, "extra", readonly(extra))

    def table(self) -> np.ndarray:
        """The 21 motors and then the extra parameters, ``(frames, 21 + len(extra_codes))``."""
        return self.values if self.extra is None else np.hstack([self.values, self.extra])

    def extra_at(self, row: np.ndarray) -> dict[str, float]:
        """A row of :meth:`table` 's extra columns by code."""
        return {code: float(row[N_MOTORS + k]) for k, code in enumerate(self.extra_codes)}

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

    def part(self, start: float | None = None, end: float | None = None) -> MotorTrack:
        """The frames with times in ``[start, end)`` seconds (None: from the first, to the last),
        as a track of their own (its first frame at 0 s); raises :class:`InputError` where no
        frame is in it.

        >>> track = MotorTrack(np.full((10, N_MOTORS), 0.5), 5.0)
        >>> track.part(0.5, 1.2).frames, track.part(start=1.0).frames
        (3, 5)
        """
        rows = kept_rows(self.frames, self.rate, start, end, "the track")
        high = None if end is None else float(end)
        return replace(self, values=self.values[rows], meta={**self.meta, "part": [float(start or 0.0), high]},
                       confidence=None if self.confidence is None else self.confidence[rows],
                       extra=None if self.extra is None else self.extra[rows])

    def column(self, code: str) -> np.ndarray:
        """One motor's values, or a parameter's beyond the 21 (:attr:`extra_codes`), ``(frames,)``."""
        if code in self.extra_codes and self.extra is not None:
            return self.extra[:, self.extra_codes.index(code)]
        return self.values[:, motor_index(code)]


def kept_rows(count: int, rate: float, start: float | None, end: float | None, what: str) -> slice:
    """The rows of ``count`` samples at ``rate`` Hz from 0 s whose times lie in ``[start, end)``
    seconds (None: from the first, to the last): the one trimming rule of tracks and of a voice's
    10 ms shapes (``--start``/``--end``); raises :class:`InputError` where none does, naming
    ``what`` and how long it lasts.

    >>> kept_rows(10, 5.0, 0.5, 1.2, "it"), kept_rows(10, 5.0, 1.0, None, "it")
    (slice(3, 6, None), slice(5, 10, None))
    """
    low, high = 0.0 if start is None else float(start), np.inf if end is None else float(end)
    if high <= low:
        raise InputError(f"the end ({high:g} s) must come after the start ({low:g} s)")
    times = np.arange(count) / rate
    kept = np.flatnonzero((times >= low - 1e-9) & (times < high - 1e-9))
    if not len(kept):
        raise InputError(f"no frame from {low:g} s{'' if end is None else f' to {high:g} s'}: {what} "
                         f"lasts {count / rate:g} s")
    return slice(int(kept[0]), int(kept[-1]) + 1)
