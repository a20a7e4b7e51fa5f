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

import numpy as np

from mapping.filters import Stepwise
from mapping.robust import column_nan_median, nan_median

#: The fastest plausible facial motion, mm/s (0.0766 mm/ms, ``../shared/realdata/README.md``).
FACE_SPEED_MM_S = 76.6
#: A sample at a gap's edge is judged against a line carried on from one side, whose jitter
#: is twice that of the line between two neighbours (:func:`centred_spikes`): twice the bound.
EDGE_FACTOR = 2.0
#: Frames whose centred misses :func:`_centred_misses` works out at once: a whole-take copy of an
#: hour's take is hundreds of MB.
FRAMES_AT_ONCE = 8192


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
        self._past: np.ndarray | None = None  # (window, markers, dims): raw samples, oldest first
        self._past_t: np.ndarray | None = None  # (window,)

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """One frame ``(markers, dims)``: the sample with spikes set to NaN."""
        x = np.asarray(sample, dtype=np.float64)
        if self._past is None or self._past_t is None:
            self._past = np.full((self.window, *x.shape), np.nan)
            self._past_t = np.full(self.window, np.nan)
        spike = self._spikes(np.concatenate([self._past, x[None]]), np.append(self._past_t, t))[0]
        self._past[:-1] = self._past[1:]  # shifted in place: np.roll allocates a frame, and kept
        self._past[-1] = x  # some of it (28 kB a minute in the stream's soak)
        self._past_t[:-1] = self._past_t[1:]
        self._past_t[-1] = t
        out = x.copy()
        out[spike] = np.nan
        return out

    def apply(self, positions: np.ndarray, t: np.ndarray, block: int = 512) -> np.ndarray:
        """Whole recording ``(frames, markers, dims)``; equal to stepping it from a fresh state."""
        out = np.array(positions, dtype=np.float64, copy=True)
        out[self.spikes(out, t, block)] = np.nan
        return out

    def spikes(self, positions: np.ndarray, t: np.ndarray, block: int = 512) -> np.ndarray:
        """Which seen samples of a whole recording ``(frames, markers, dims)`` stepping it from a
        fresh state would reject, ``(frames, markers)``; without a copy of the recording (an
        hour's is hundreds of MB)."""
        x = np.asarray(positions, dtype=np.float64)
        times = np.asarray(t, dtype=np.float64)
        k = self.window
        spike = np.zeros(x.shape[:2], bool)
        head = min(k, len(x))  # the first window alone: its past is padding
        spike[:head] = self._spikes(np.concatenate([np.full((k, *x.shape[1:]), np.nan), x[:head]]),
                                    np.concatenate([np.full(k, np.nan), times[:head]]))
        for start in range(k, len(x), block):  # blocks small enough for the cache
            stop = min(start + block, len(x))
            spike[start:stop] = self._spikes(x[start - k:stop], times[start - k:stop])
        return spike

    def _spikes(self, run: np.ndarray, run_t: np.ndarray) -> np.ndarray:
        """Which markers are spikes in each of the last ``len(run) - window`` frames of ``run``
        ``(window + N, markers, dims)`` (raw samples) at times ``run_t`` ``(window + N,)``, each
        judged on the ``window`` samples before it; ``(N, markers)``.

        Each frame's past is a shifted view of ``run``, so every step is one pass over
        ``(N, markers, dims)``; a run with every sample seen skips the bookkeeping of unseen ones."""
        k, r = self.window, self.recent
        n = len(run) - k
        complete = bool(np.isfinite(run).all() and (np.diff(run_t) > 0).all())
        with np.errstate(invalid="ignore", divide="ignore"):  # unseen samples and padding give NaN
            steps = np.diff(run, axis=0) / np.diff(run_t)[:, None, None]  # steps[i]: frame i to i + 1
        velocity = nan_median([steps[j - 1:j - 1 + n] for j in range(k - r, k)], complete)
        if not complete:
            velocity = np.where(np.isfinite(velocity), velocity, 0.0)
        ahead = [(run_t[k:] - run_t[j:j + n])[:, None, None] for j in range(k)]  # (N, 1, 1) each
        level = nan_median([run[j:j + n] + velocity * ahead[j] for j in range(k - r, k)], complete)
        with np.errstate(invalid="ignore"):
            miss = _length(run[k:] - level)  # (N, markers)
            # A sample within ``floor`` of the line is no spike whatever the spread: the spread (the
            # costly part) is measured only where a sample misses by more.
            f, m = np.nonzero(miss > self.floor)
        spike = np.zeros(miss.shape, bool)
        if len(f):
            # the window's samples (oldest first) carried along the line to the frame judged: (S, dims) each
            carried = [run[f + j, m] + velocity[f, m] * ahead[j][f, 0] for j in range(k)]
            spread = nan_median([_length(c - level[f, m]) for c in carried], complete)
            with np.errstate(invalid="ignore"):
                spike[f, m] = miss[f, m] > self.threshold * 1.4826 * spread + self.floor  # False where NaN
        if complete:
            return spike
        seen = _seen(run)  # (window + N, markers)
        tested = seen[:n].astype(np.intp)
        for j in range(1, k):
            tested += seen[j:j + n]
        return seen[k:] & (tested >= self.min_seen) & spike


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
    rejected costs little: it becomes a one-frame gap that gap filling bridges.

    A sample at the edge of a gap (no seen sample within two frames on one side) is judged in
    the same rounds against the line through the two nearest samples on its other side, carried
    on to it: carrying a line doubles its jitter and what a bend costs, so its bound is
    :data:`EDGE_FACTOR` times the centred one. Left untested, a spike just before a gap stayed
    in the take whole, its neighbours were rejected in its place (they missed their lines by
    half the spike, it missed none), and the low-pass spread it over what was left: a 13 mm
    spike beside a mouth corner's gap read as 3 mm of motion.

    Parameters
    ----------
    positions : ndarray, shape (F, M, D)
        Head-frame positions (a turning head would bend every path), NaN where unseen.
    t : ndarray, shape (F,)
        Times, s.
    """
    x = np.asarray(positions, dtype=np.float64)
    times = np.asarray(t, dtype=np.float64)
    frames, markers = x.shape[:2]
    rejected = np.zeros((frames, markers), bool)
    if frames < 3:
        return rejected
    active, current = np.arange(markers), x  # a marker is judged on its own samples: only those that lost one
    for _ in range(rounds):                  # are tested again, without what they lost
        peak = _centred_peaks(current, times, threshold, floor)
        if not peak.any():
            break
        rejected[:, active] |= peak
        active = active[peak.any(axis=0)]
        current = np.where(rejected[:, active, None], np.nan, x[:, active])
    return rejected


def _centred_peaks(x: np.ndarray, times: np.ndarray, threshold: float, floor: float) -> np.ndarray:
    """One round of :func:`centred_spikes` on ``x`` ``(F, M, D)``: the samples to reject, ``(F, M)``.

    A sample at a gap's edge takes part with its miss of the line carried on to it: a spike
    there makes its neighbour miss its own centred line by half as much, and the larger miss
    is the one rejected."""
    miss, ok, seen, before, after = _centred_misses(x, times)
    bound = _bound(miss, ok, threshold, floor)
    edge, carried = _edge_misses(x, times, seen, before, after)
    peak = (ok & (miss > bound)) | (edge & (carried > EDGE_FACTOR * bound))
    value = np.where(edge, carried, miss)
    peak[1:] &= value[1:] >= value[:-1]
    peak[:-1] &= value[:-1] >= value[1:]
    return peak


def _edge_misses(x: np.ndarray, times: np.ndarray, seen: np.ndarray, before: np.ndarray, after: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Which samples of ``x`` ``(F, M, D)`` are at a gap's edge (no seen sample within two
    frames on one side, two on the other, each within two frames of the last) and how far each
    misses the line through those two carried on to it; both ``(F, M)``. ``seen``, ``before``
    and ``after``: which samples are seen and each one's nearest seen frame either side
    (:func:`_centred_misses`)."""
    frames, markers = before.shape
    here = np.arange(frames)[:, None]
    lone_after = (after - here > 2) & (here - before <= 2) & (before >= 0)  # a gap after, seen before
    lone_before = (here - before > 2) & (after - here <= 2) & (after < frames)
    edge, carried = np.zeros((frames, markers), bool), np.zeros((frames, markers))
    for lone, near in ((lone_after, before), (lone_before, after)):
        f, m = np.nonzero(seen & lone)
        a = near[f, m]  # the nearest sample on the seen side, and the next one beyond it
        b = near[a, m]
        use = (b >= 0) & (b < frames) & (np.abs(a - b) <= 2)
        f, m, a, b = f[use], m[use], a[use], b[use]
        w = ((times[f] - times[a]) / (times[a] - times[b]))[:, None]
        edge[f, m] = True
        carried[f, m] = _length(x[f, m] - (x[a, m] + (x[a, m] - x[b, m]) * w))
    return edge, carried


def _bound(miss: np.ndarray, ok: np.ndarray, threshold: float, floor: float) -> np.ndarray:
    """Each marker's bound on a centred miss ``(M,)``: ``threshold`` × the robust scale of its
    tested misses (``miss``, ``ok``: ``(F, M)``) plus ``floor``."""
    scale = 1.4826 * column_nan_median(np.where(ok, miss, np.nan))  # NaN for a marker never tested
    return threshold * np.nan_to_num(scale) + floor


def _centred_misses(x: np.ndarray, times: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """How far each sample of ``x`` ``(F, M, D)`` misses the line between its seen neighbours
    (within two frames either side), where it has both (``ok``); which samples are seen; and
    each sample's nearest seen frame before and after it (-1 and ``F`` where none); all ``(F, M)``.

    Where both neighbours are the next frames (nearly everywhere) the line between them comes
    from shifted views of the take; the samples beside a gap are gathered one by one."""
    frames, markers = x.shape[:2]
    index = np.int32 if frames < 2**31 - 1 else np.int64  # frame numbers: half the memory of a long take's
    here = np.arange(frames, dtype=index)[:, None]
    seen = _seen(x)
    before = np.full((frames, markers), -1, index)
    np.maximum.accumulate(np.where(seen[:-1], here[:-1], index(-1)), axis=0, out=before[1:])
    after = np.full((frames, markers), frames, index)
    np.minimum.accumulate(np.where(seen[:0:-1], here[:0:-1], index(frames)), axis=0, out=after[-2::-1])
    ok = seen & (before >= 0) & (after < frames) & (here - before <= 2) & (after - here <= 2)
    adjacent = ok & (before == here - 1) & (after == here + 1)
    miss = np.zeros((frames, markers))
    for first in range(1, frames - 1, FRAMES_AT_ONCE):  # a block at a time: a long take's copies stay small
        part = slice(first, min(first + FRAMES_AT_ONCE, frames - 1))
        earlier, later = slice(part.start - 1, part.stop - 1), slice(part.start + 1, part.stop + 1)
        share = ((times[part] - times[earlier]) / (times[later] - times[earlier]))[:, None, None]
        with np.errstate(invalid="ignore"):  # unseen samples: NaN, not used
            line = x[earlier] * (1 - share) + x[later] * share
        miss[part] = np.where(adjacent[part], _length(x[part] - line), 0.0)
    f, m = np.nonzero(ok & ~adjacent)
    if len(f):
        b, a = before[f, m], after[f, m]
        w = ((times[f] - times[b]) / (times[a] - times[b]))[:, None]
        miss[f, m] = _length(x[f, m] - (x[b, m] * (1 - w) + x[a, m] * w))
    return miss, ok, seen, before, after


def _seen(a: np.ndarray) -> np.ndarray:
    """Whether every coordinate (the last axis) is finite, ``(...)``."""
    total = a[..., 0].copy()
    for d in range(1, a.shape[-1]):
        total += a[..., d]
    return np.isfinite(total)


def _length(a: np.ndarray) -> np.ndarray:
    """Euclidean length over the last axis (2 or 3 coordinates), ``(...)``."""
    total = a[..., 0] * a[..., 0]
    for d in range(1, a.shape[-1]):
        total += a[..., d] * a[..., d]
    return np.sqrt(total)
