"""Outlier rejection on marker positions: a physical speed bound and robust spike detection.

All work on whole markers (a rejected sample loses all its coordinates, which become a gap
for :mod:`mapping.gaps`). The speed bound and the live spike test come in the two forms of
:mod:`mapping.filters`: ``apply(positions, t)`` on ``(frames, markers, dims)`` and
``step(sample, t)`` on ``(markers, dims)``, NaN meaning unseen; ``apply`` equals stepping, frame
for frame. Offline, :func:`centred_spikes` also looks ahead: a sample is judged against the
samples on both sides of it, which finds spikes several times smaller than a test that may
only look back.
"""

from __future__ import annotations

import warnings

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
        if self._last is None or self._t is None:
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


class SpikeFilter:
    """Reject samples far from where the marker's recent raw motion says it should be.

    For each marker and frame, the previous raw samples (seen ones only) give a robust line: the
    velocity is the median of the last ``recent`` successive differences over time, the level the
    median of the last ``recent`` samples carried forward along it to this frame (a one-frame
    spike spoils one of each, or two differences of opposite signs). A sample is a spike when it
    misses the line's prediction by more than ``threshold`` robust deviations (1.4826 × the median
    distance of the last ``window`` samples from the line, which grows when the motion bends)
    plus ``floor`` mm.
    Steady motion, a blink or a head turn predicts itself; a one- or two-frame spike cannot move
    the medians; a marker that really jumped and stays is accepted once most of the ``recent``
    samples have seen it there (after 2 rejected frames by default). Markers with fewer than
``min_seen`` seen samples in the window are not tested.

    Because the test reads raw samples only (not earlier decisions), ``apply`` is vectorised
    over frames and still equals ``step`` frame for frame.

    Parameters
    ----------
    window : int
        Previous samples that set the scale of a miss.
    recent : int
        Previous samples (and differences) that set the line; odd, at most ``window - 1``.
    threshold : float
    floor : float
        mm, so that a perfectly smooth marker does not reject its own jitter.
    min_seen : int
    """

    def __init__(self, window: int = 6, recent: int = 3, threshold: float = 6.0, floor: float = 3.0,
                 min_seen: int = 4) -> None:
        if window < 3 or not 1 <= recent < window or threshold <= 0 or floor < 0 or not 2 <= min_seen <= window:
            raise ValueError("need window >= 3, 1 <= recent < window, threshold > 0, floor >= 0 "
                             "and 2 <= min_seen <= window")
        self.window, self.recent, self.threshold, self.floor, self.min_seen = window, recent, threshold, floor, min_seen
        self.reset()

    def reset(self) -> None:
        self._past: np.ndarray | None = None  # (markers, dims, window): raw samples, oldest first
        self._past_t: np.ndarray | None = None  # (window,)

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """One frame ``(markers, dims)``: the sample with spikes set to NaN."""
        x = np.asarray(sample, dtype=np.float64)
        if self._past is None or self._past_t is None:
            self._past = np.full((*x.shape, self.window), np.nan)
            self._past_t = np.full(self.window, np.nan)
        spike = self._spikes(self._past, self._past_t, x, np.float64(t))
        self._past[..., :-1] = self._past[..., 1:]  # shifted in place: np.roll allocates a frame, and kept
        self._past[..., -1] = x  # some of it (28 kB a minute in the stream's soak)
        self._past_t[:-1] = self._past_t[1:]
        self._past_t[-1] = t
        out = x.copy()
        out[spike] = np.nan
        return out

    def apply(self, positions: np.ndarray, t: np.ndarray, block: int = 4096) -> np.ndarray:
        """Whole recording ``(frames, markers, dims)``; equal to stepping it from a fresh state."""
        x = np.asarray(positions, dtype=np.float64)
        times = np.asarray(t, dtype=np.float64)
        k = self.window
        padded = np.concatenate([np.full((k, *x.shape[1:]), np.nan), x])
        padded_t = np.concatenate([np.full(k, np.nan), times])
        out = x.copy()
        for start in range(0, len(x), block):
            stop = min(start + block, len(x))
            past = np.lib.stride_tricks.sliding_window_view(padded[start:stop + k - 1], k, axis=0)
            past_t = np.lib.stride_tricks.sliding_window_view(padded_t[start:stop + k - 1], k)
            spike = self._spikes(past, past_t, x[start:stop], times[start:stop])
            out[start:stop][spike] = np.nan
        return out

    def _spikes(self, past: np.ndarray, past_t: np.ndarray, x: np.ndarray, t: np.ndarray | float) -> np.ndarray:
        """Which markers of ``x`` (``(..., markers, dims)``) are spikes, given the raw samples
        before them ``(..., markers, dims, window)`` at times ``(..., window)``; ``(..., markers)``."""
        pt = past_t[..., None, None, :]  # broadcast over markers and dims
        r = self.recent
        velocity = _median_last((past[..., -r:] - past[..., -r - 1:-1]) / (pt[..., -r:] - pt[..., -r - 1:-1]))
        velocity = np.where(np.isfinite(velocity), velocity, 0.0)
        ahead = np.asarray(t)[..., None, None, None] - pt  # (..., 1, 1, window)
        level = _median_last(past[..., -r:] + velocity[..., None] * ahead[..., -r:])  # (..., markers, dims)
        off = past - (level[..., None] - velocity[..., None] * ahead)
        spread = _median_last(np.sqrt((off * off).sum(axis=-2)))  # (..., markers)
        miss = x - level
        miss = np.sqrt((miss * miss).sum(axis=-1))
        seen = np.isfinite(x).all(axis=-1)
        tested = np.isfinite(past).all(axis=-2).sum(axis=-1) >= self.min_seen
        return seen & tested & (miss > self.threshold * 1.4826 * spread + self.floor)


def centred_spikes(positions: np.ndarray, t: np.ndarray, threshold: float = 4.0, floor: float = 1.0,
                   rounds: int = 3) -> np.ndarray:
    """Spikes found by looking both ways (offline): which samples ``(frames, markers)`` to reject.

    Each seen sample with a seen neighbour on each side (within two frames) is compared with the
    straight line between them, at its own time. A spike of size *s* misses that line by *s* and
    makes its neighbours miss theirs by about *s*/2, so a sample is rejected where its miss is
    the largest of itself and its neighbours and exceeds ``threshold`` × the marker's robust
    scale of misses (1.4826 × their median over the take) plus ``floor`` mm. Rejected samples
    are taken out and the test repeated (``rounds`` times at most), so that a spike beside
    another is judged against clean samples.

    Motion that bends sharply between frames (the bottom of a fast blink) misses the line too,
    by about one frame's travel; ``threshold`` and ``floor`` keep that in, and a sample wrongly
    rejected costs little: it becomes a one-frame gap that gap filling bridges. A sample at the
    edge of a gap is not tested here (carrying a line on from one side doubles its jitter and
    what a bend costs; measured on the second bench performer, rejecting there lost more
    than it caught).

    Parameters
    ----------
    positions : ndarray, shape (F, M, D)
        Head-frame positions (a turning head would bend every path), NaN where unseen.
    t : ndarray, shape (F,)
        Times, s.
    """
    x = np.array(positions, dtype=np.float64)
    times = np.asarray(t, dtype=np.float64)
    frames, markers = x.shape[:2]
    rejected = np.zeros((frames, markers), bool)
    if frames < 3:
        return rejected
    here = np.arange(frames)[:, None]
    columns = np.arange(markers)[None, :]
    for _ in range(rounds):
        seen = np.isfinite(x).all(axis=2)
        last_seen = np.maximum.accumulate(np.where(seen, here, -1), axis=0)
        before = np.vstack([np.full((1, markers), -1), last_seen[:-1]])
        next_seen = np.minimum.accumulate(np.where(seen, here, frames)[::-1], axis=0)[::-1]
        after = np.vstack([next_seen[1:], np.full((1, markers), frames)])
        ok = seen & (before >= 0) & (after < frames) & (here - before <= 2) & (after - here <= 2)
        b, a = np.clip(before, 0, frames - 1), np.clip(after, 0, frames - 1)
        span = np.where(ok, times[a] - times[b], 1.0)
        share = np.where(ok, (times[:, None] - times[b]) / span, 0.0)[..., None]
        miss = np.linalg.norm(x - (x[b, columns] * (1 - share) + x[a, columns] * share), axis=2)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a marker never tested: its scale is NaN
            scale = 1.4826 * np.nanmedian(np.where(ok, miss, np.nan), axis=0)
        miss = np.where(ok, miss, 0.0)
        peak = ok & (miss > threshold * np.nan_to_num(scale) + floor)
        peak[1:] &= miss[1:] >= miss[:-1]
        peak[:-1] &= miss[:-1] >= miss[1:]
        if not peak.any():
            break
        rejected |= peak
        x[peak] = np.nan
    return rejected


def _median_last(a: np.ndarray) -> np.ndarray:
    """Median over the last axis ignoring NaN (NaN where all are NaN); vectorised by sorting
    (by a min/max network for three values, the common case, which is several times faster)."""
    if a.shape[-1] == 3:
        x, y, z = a[..., 0], a[..., 1], a[..., 2]
        n = np.isfinite(a).sum(axis=-1)
        all_three = np.maximum(np.minimum(x, y), np.minimum(np.maximum(x, y), z))
        with np.errstate(invalid="ignore", divide="ignore"):
            fewer = np.where(np.isfinite(a), a, 0.0).sum(axis=-1) / n  # the mean of one or two
        return np.where(n == 3, all_three, np.where(n > 0, fewer, np.nan))
    ordered = np.sort(a, axis=-1)  # NaN sort last
    n = np.isfinite(ordered).sum(axis=-1)
    low = np.take_along_axis(ordered, np.maximum((n - 1) // 2, 0)[..., None], axis=-1)[..., 0]
    high = np.take_along_axis(ordered, (n // 2)[..., None], axis=-1)[..., 0]
    return np.where(n > 0, 0.5 * (low + high), np.nan)
