"""Outlier rejection on marker positions: a physical speed bound and robust spike detection.

Both work on whole markers (a rejected sample loses all its coordinates, which become a gap
for :mod:`mapping.gaps`), in the two forms of :mod:`mapping.filters`: ``apply(positions, t)``
on ``(frames, markers, dims)`` and ``step(sample, t)`` on ``(markers, dims)``, NaN meaning
unseen; ``apply`` equals stepping, frame for frame.
"""

from __future__ import annotations

import numpy as np

from mapping.filters import Stepwise

#: The fastest plausible facial motion, mm/s (0.0766 mm/ms, ``../shared/realdata/README.md``).
FACE_SPEED_MM_S = 76.6


class SpeedBound(Stepwise):
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


class SpikeFilter(Stepwise):
    """Reject samples far from where the marker's recent motion says it should be.

    The prediction extends the line through the marker's last two accepted samples to this
    frame's time (so steady motion, a blink or a head turn, predicts itself). A sample is a spike
    when it misses the prediction by more than ``threshold`` robust deviations (1.4826 × the
    median miss over the last ``window`` accepted samples) plus ``floor`` mm. A marker back from
    a gap of more than 3 frame intervals is not tested and starts a new history there, so a
    marker that really jumped and stays is accepted again after 3 rejected frames.

    Parameters
    ----------
    window : int
    threshold : float
    floor : float
        mm, so that a perfectly smooth marker does not reject its own jitter.
    """

    def __init__(self, window: int = 9, threshold: float = 6.0, floor: float = 3.0) -> None:
        if window < 3 or threshold <= 0 or floor < 0:
            raise ValueError("need window >= 3, threshold > 0 and floor >= 0")
        self.window, self.threshold, self.floor = window, threshold, floor
        self.reset()

    def reset(self) -> None:
        self._last: np.ndarray | None = None  # (2, markers, dims): the last two accepted, newest last
        self._t: np.ndarray | None = None  # (2, markers)
        self._miss: np.ndarray | None = None  # (window, markers): recent prediction misses, mm

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """One frame ``(markers, dims)``: the sample with spikes set to NaN."""
        x = np.asarray(sample, dtype=np.float64)
        markers = len(x)
        if self._last is None:
            self._last, self._t = np.full((2, *x.shape), np.nan), np.full((2, markers), np.nan)
            self._miss = np.full((self.window, markers), np.nan)
        seen = np.isfinite(x).all(axis=1)
        span = self._t[1] - self._t[0]
        slope = (self._last[1] - self._last[0]) / np.where(span > 0, span, np.inf)[:, None]
        predicted = np.where(np.isfinite(slope), self._last[1] + slope * (t - self._t[1])[:, None], self._last[1])
        miss = np.linalg.norm(x - predicted, axis=1)
        # Only a recent line predicts: after a gap the marker is taken where it reappears.
        ready = np.isfinite(self._miss).all(axis=0) & (t - self._t[1] <= 3 * span)
        spread = np.median(self._miss, axis=0)
        spike = seen & ready & (miss > self.threshold * 1.4826 * spread + self.floor)
        accept = seen & ~spike
        back = accept & (t - self._t[1] > 3 * span)  # back from a gap: its history restarts
        self._miss[:, back] = np.nan
        fresh = accept & ~back & np.isfinite(self._last[1, :, 0])
        self._miss[:, fresh] = np.roll(self._miss[:, fresh], -1, axis=0)
        self._miss[-1, fresh] = miss[fresh]
        self._last[0, accept], self._t[0, accept] = self._last[1, accept], self._t[1, accept]
        self._last[1, accept], self._t[1, accept] = x[accept], t
        self._last[0, back], self._t[0, back] = np.nan, np.nan
        out = x.copy()
        out[~accept] = np.nan
        return out
