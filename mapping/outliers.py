"""Outlier rejection on marker positions: a physical speed bound and robust spike detection.

Both work on whole markers (a rejected sample loses all its coordinates, which become a gap
for :mod:`mapping.gaps`), in the two forms of :mod:`mapping.filters`: ``apply(positions, t)``
on ``(frames, markers, dims)`` and ``step(sample, t)`` on ``(markers, dims)``, NaN meaning
unseen; ``apply`` equals stepping, frame for frame.
"""

from __future__ import annotations

import numpy as np

#: The fastest plausible facial motion, mm/s (0.0766 mm/ms, ``../shared/realdata/README.md``).
FACE_SPEED_MM_S = 76.6


class _MarkerStepwise:
    def reset(self) -> None:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:  # pragma: no cover
        raise NotImplementedError

    def apply(self, positions: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Reject outliers in a recording ``(frames, markers, dims)``; rejected samples become NaN."""
        pos = np.asarray(positions, dtype=np.float64)
        self.reset()
        out = np.empty_like(pos)
        for f in range(len(pos)):
            out[f] = self.step(pos[f], float(t[f]))
        self.reset()
        return out


class SpeedBound(_MarkerStepwise):
    """Reject a sample further from the marker's last accepted one than it could have moved.

    Allowed distance after ``dt`` seconds: ``max_speed * dt + tolerance``; the tolerance covers
    measurement jitter, and because the allowance grows with time, a marker that really moved
    while rejected is accepted again once enough time has passed.

    Parameters
    ----------
    max_speed : float
        mm/s; default the README's bound for faces. Apply it to head-stabilised positions: a
        turning head moves markers faster than the face does.
    tolerance : float
        mm.
    """

    def __init__(self, max_speed: float = FACE_SPEED_MM_S, tolerance: float = 2.0) -> None:
        if max_speed <= 0 or tolerance < 0:
            raise ValueError("max_speed must be > 0 and tolerance >= 0")
        self.max_speed, self.tolerance = max_speed, tolerance
        self.reset()

    def reset(self) -> None:
        self._last: np.ndarray | None = None  # (markers, dims) last accepted, NaN before any
        self._t: np.ndarray | None = None

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """One frame ``(markers, dims)``: the sample with rejected markers set to NaN."""
        x = np.asarray(sample, dtype=np.float64)
        if self._last is None:
            self._last, self._t = np.full(x.shape, np.nan), np.full(len(x), np.nan)
        seen = np.isfinite(x).all(axis=1)
        known = np.isfinite(self._last[:, 0])
        distance = np.linalg.norm(x - self._last, axis=1)
        allowed = self.max_speed * (t - self._t) + self.tolerance
        ok = seen & (~known | (distance <= allowed))
        self._last[ok], self._t[ok] = x[ok], t
        out = x.copy()
        out[~ok] = np.nan
        return out


class SpikeFilter(_MarkerStepwise):
    """Reject samples far from the median of the marker's recent accepted samples.

    A sample is a spike when its distance from the per-coordinate median of the last ``window``
    accepted samples exceeds ``threshold`` robust deviations (1.4826 × the median distance of
    those samples from their median) plus ``floor`` mm. Until ``window`` samples are accepted,
    everything is accepted. A marker that really jumped and stays is accepted again after
    ``window // 2 + 1`` rejections in a row (the new place is then the majority).

    Parameters
    ----------
    window : int
    threshold : float
    floor : float
        mm, so that a perfectly still marker does not reject its own jitter.
    """

    def __init__(self, window: int = 9, threshold: float = 6.0, floor: float = 3.0) -> None:
        if window < 3 or threshold <= 0 or floor < 0:
            raise ValueError("need window >= 3, threshold > 0 and floor >= 0")
        self.window, self.threshold, self.floor = window, threshold, floor
        self.reset()

    def reset(self) -> None:
        self._buf: np.ndarray | None = None  # (window, markers, dims) accepted, newest last
        self._count: np.ndarray | None = None
        self._streak: np.ndarray | None = None  # rejections in a row
        self._rejected: np.ndarray | None = None  # (window, markers, dims) the rejected ones

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """One frame ``(markers, dims)``: the sample with spikes set to NaN."""
        x = np.asarray(sample, dtype=np.float64)
        if self._buf is None:
            self._buf = np.full((self.window, *x.shape), np.nan)
            self._rejected = np.full((self.window, *x.shape), np.nan)
            self._count, self._streak = np.zeros(len(x), dtype=int), np.zeros(len(x), dtype=int)
        seen = np.isfinite(x).all(axis=1)
        ready = self._count >= self.window
        median = np.median(self._buf, axis=0)  # (markers, dims); NaN where not ready
        spread = np.median(np.linalg.norm(self._buf - median, axis=2), axis=0)
        distance = np.linalg.norm(x - median, axis=1)
        spike = seen & ready & (distance > self.threshold * 1.4826 * spread + self.floor)
        self._streak = np.where(spike, self._streak + 1, np.where(seen, 0, self._streak))
        moved = spike & (self._streak > self.window // 2)
        if moved.any():  # the marker is somewhere new: restart its history from the rejected run
            earlier = self.window // 2  # the rejections before this one
            self._buf[:, moved] = np.nan
            self._buf[-earlier:, moved] = self._rejected[-earlier:, moved]
            self._count[moved] = earlier
            spike &= ~moved
            self._streak[moved] = 0
        accept = seen & ~spike
        self._buf[:, accept] = np.roll(self._buf[:, accept], -1, axis=0)
        self._buf[-1, accept] = x[accept]
        self._count[accept] += 1
        self._rejected[:, spike] = np.roll(self._rejected[:, spike], -1, axis=0)
        self._rejected[-1, spike] = x[spike]
        out = x.copy()
        out[~accept] = np.nan
        return out
