"""Offline smoothing that is heavier where a marker holds still than where it moves.

A face spends most of a take holding a pose (a lid at rest, a gaze held, a smile kept) and
a small part moving between poses (a blink, a saccade, a syllable). One low-pass for all of it
must keep the fast moves, so it leaves the holds as noisy as the moves: on a lower lid that
travels 3 mm, 0.3 mm of sensor jitter through the 8 Hz cleaning low-pass is still 5 % of the
lid's range. :class:`HoldSmoother` keeps the take's low-pass where the marker moves and, where
it holds, takes heavier zero-phase low-passes (:data:`LEVELS`, one after another).

Whether a marker moves is judged against its own noise, measured on its raw samples (the
median absolute second difference, which motion hardly reaches at a face's speeds), not
against one threshold for every marker, take and sensor: at each level, where the heavier
low-pass departs from the lighter one by more than that noise can explain (the expected spread
of their difference follows from the two filters' responses), the lighter one is kept, and
the switch is widened and eased over half a period of the heavier cut-off so that it leaves no
step. A marker that moves all the time (lips through a speech) cannot claim its motion as
noise: each marker's noise is capped at twice the take's median over its markers.

That cascade is symmetric: where it judges a marker to hold next to a move (a saccade's
landing, a lid settling into a squint, a move too small against the noise for the test to see),
its heavy low-passes, half a second to a second long, reach across the move and round its start
and end. So where the cascade's first level did not keep the take's low-pass, most of the result
(:data:`ICI_SHARE`) is a second estimate that keeps such edges, by LPA-ICI (local approximation
with the intersection of confidence intervals; Katkovnik, Egiazarian and Astola, *Local
Approximation Techniques in Signal and Image Processing*, 2006): at each sample, the mean of the
samples in windows reaching back from it, reaching forward from it, and about it, each window grown
(:data:`ICI_WINDOWS`) while its confidence interval (:data:`ICI_GAMMA` of its standard
deviation, from the same noise) still meets those of all the shorter ones and of the sample
itself, the three means weighted by the inverse of their variances. At a pose's first samples
the window reaching forward grows long and the one reaching back stays short; along a slow,
smooth motion the cascade's low-passes are the better guess, and the two errors differ enough
that a blend of the two beats either. Where the cascade sees motion (a blink, a saccade) the take's
low-pass is kept as before: ICI accepts a window whose mean misses by up to its interval, which
took 0.13 mm off a 3.5 mm blink's depth.

The take's low-pass itself is too slow for the fastest moves: at 8 Hz a 30 ms saccade becomes a
100 ms ramp. Where a lighter low-pass departs from it by more than the marker's noise explains,
:func:`fast_moves` keeps the lighter one (:data:`FAST_HZ`).
"""

from __future__ import annotations

from types import ModuleType

import numpy as np

from mapping.gaps import gap_runs
from mapping.robust import jitter

#: The heavier low-passes, Hz, tried one after another where a marker holds (each used only
#: below the take's own cut-off), an octave apart. Against (2, 0.7): the third bench
#: performer's fitted error 2.08 -> 2.07 % on the bench's seeds and 2.17 -> 2.15 % on nine
#: other sensor draws, the others' unchanged, for about 6 ms more per 30 s of 120 Hz toon32
#: (45 -> 51 ms, the smoother alone). A 4 Hz level first did better still (2.03 %) but made
#: blinks shallower and a 1.5 Hz motion smaller.
LEVELS: tuple[float, ...] = (2.0, 1.0, 0.5)
#: A level is left where the two low-passes differ by more than this many times the spread their
#: difference has on noise alone (RMS over the axes), and wholly from twice that.
THRESHOLD = 1.8
#: Each marker's noise is at most this many times the take's median over its markers.
NOISE_CAP = 2.0
#: Seen stretches shorter than this many frames keep the take's low-pass alone.
MIN_RUN = 30
#: The half-widths (seconds) of the windows LPA-ICI grows on each side of a sample and about it,
#: shortest first, the width of each one's confidence interval in its standard deviations, and
#: the share of its estimate where the cascade holds. Chosen on draws of the four bench performers
#: kept apart from the bench's seeds and the held-out ones (seeds 31 and 32), among widths 0.8 to
#: 1.5 and shares 0.3 to 1: mean fitted error (rules and solver) 1.628 -> 1.576 %, the third
#: performer's 1.653 -> 1.537, the own 1.460 -> 1.384, the fourth's 2.272 -> 2.256, the second's
#: 1.129 -> 1.127 (a share of 0.75 took the second to 1.152; ICI in moves too, 1.558, but blinks
#: lost 4 % of their depth). The share chosen again once the solver had taken the lids' cross-talk
#: out, on seeds 31-34 of the four (the third performer's jittered lids now its largest error),
#: among 0.3, 0.5, 0.7 and 0.85: 0.5 -> 0.7 took the mean (rules and solver) 1.470 -> 1.463 %
#: (0.3: 1.488, 0.85: 1.465), the third's solver 1.479 -> 1.450 (0.85: 1.444), the own's 1.235 ->
#: 1.216 and the fourth's 1.938 -> 1.932, the second's 1.072 -> 1.093 (0.85: 1.117); a heavier
#: level (0.25 Hz) as well: no change.
ICI_WINDOWS: tuple[float, ...] = (0.025, 0.05, 0.1, 0.2, 0.4, 0.8)
ICI_GAMMA = 1.5
ICI_SHARE = 0.7
#: Where a marker moves faster than the take's low-pass follows (a 30 ms saccade, a blink's
#: closing), a lighter zero-phase low-pass (Hz) is kept instead (:func:`fast_moves`), judged by
#: the same test as the levels, at this threshold. Chosen on draws of the four bench performers
#: kept apart from the bench's seeds (seeds 31 and 32) among 20 and 30 Hz and thresholds 1.8 and
#: 2.5: mean fitted error (rules and solver) 1.590 -> 1.566 %, the fourth's 2.26 -> 2.18, the
#: second's 1.13 -> 1.11, the third's and the own unchanged (30 Hz: 1.578; 1.8: the third 1.54 ->
#: 1.55). (Chosen with a prototype that judged the 20 Hz low-pass against the 8 Hz low-pass of it;
#: on the bench's seeds the two agree to 0.001 %.)
FAST_HZ = 20.0
FAST_THRESHOLD = 2.5
#: Frames LPA-ICI works on at once (its dozen working arrays of a long take's four markers).
ICI_FRAMES = 1 << 15
#: Markers smoothed at once: each marker is smoothed on its own, and the filters' working copies
#: of a long take's every marker were six times its positions (3.9 GB at an hour of 120 Hz toon32).
MARKERS_AT_ONCE = 4


class HoldSmoother:
    """Smooth markers more where they hold still (see the module docstring).

    Parameters
    ----------
    rate : float
        Frame rate, Hz.
    cutoff : float
        The low-pass the input was smoothed by (Hz): the lightest level.
    levels : tuple of float
        Heavier cut-offs, Hz, highest first; those at or above ``cutoff`` are skipped.
    threshold : float
        See :data:`THRESHOLD`.
    ici_share : float
        The share of the LPA-ICI estimate in the result (:data:`ICI_SHARE`; 0: the cascade alone).
    """

    def __init__(self, rate: float, cutoff: float, levels: tuple[float, ...] = LEVELS,
                 threshold: float = THRESHOLD, ici_share: float = ICI_SHARE) -> None:
        if rate <= 0 or not 0 < cutoff < rate / 2:
            raise ValueError(f"the cutoff must be between 0 and half the rate ({rate / 2:g} Hz), got {cutoff:g}")
        if not 0 <= ici_share <= 1:
            raise ValueError(f"ici_share must be between 0 and 1, got {ici_share:g}")
        self.rate, self.threshold, self.ici_share = rate, threshold, ici_share
        kept = [fc for fc in levels if 0 < fc < cutoff]
        self.levels = [(fc, _signal().butter(2, fc, fs=rate, output="sos")) for fc in kept]
        light = _power(_signal().butter(2, cutoff, fs=rate, output="sos"))
        self.spreads = _spreads(light, [sos for _, sos in self.levels])
        #: the input's noise variance over the raw samples': what the take's low-pass leaves
        self.light_variance = float(np.mean(light ** 2))
        self.windows = sorted({max(1, int(round(seconds * rate))) for seconds in ICI_WINDOWS})

    def smooth(self, smoothed: np.ndarray, raw: np.ndarray, overwrite: bool = False,
               noise: np.ndarray | None = None) -> np.ndarray:
        """Markers ``(F, M, D)`` smoothed by the take's low-pass (NaN where unseen), made
        steadier where they hold; ``raw`` ``(F, M, D)``: the same markers before any smoothing
        or gap filling (NaN where not seen), to measure each one's noise on. ``overwrite``: the
        result may be written into ``smoothed`` (a float64 array the caller no longer needs: a
        long take's copy saved). ``noise`` ``(M, D)``: :func:`marker_noise` of ``raw``, where
        already measured."""
        out = np.asarray(smoothed, dtype=np.float64)
        if not self.levels or len(out) < 2:
            return out if overwrite else out.copy()
        noise = marker_noise(raw) if noise is None else noise  # (M, D)
        judged = np.isfinite(noise) & (noise > 0)  # a flat axis (a 2-D tracker's depth) tells nothing
        usable = judged.any(axis=1)  # a marker never seen three times in a row, or without noise: left be
        whole = usable & np.isfinite(out).all(axis=(0, 2))
        out = out if overwrite and out is smoothed else out.copy()
        if whole.any():  # every marker seen throughout (gaps filled): a few at a time (each on its own)
            columns = np.flatnonzero(whole)
            for first in range(0, len(columns), MARKERS_AT_ONCE):
                part = columns[first:first + MARKERS_AT_ONCE]
                out[:, part] = self._run(_rows(out[:, part]), judged[part], noise[part]).transpose(2, 0, 1)
        for m in np.flatnonzero(usable & ~whole):
            for start, end in gap_runs(np.asarray(np.isfinite(out[:, m]).all(axis=1))):
                if end - start >= MIN_RUN:
                    out[start:end, m:m + 1] = self._run(_rows(out[start:end, m:m + 1]), judged[m:m + 1],
                                                        noise[m:m + 1]).transpose(2, 0, 1)
        return out

    def _run(self, x: np.ndarray, judged: np.ndarray, noise: np.ndarray) -> np.ndarray:
        """Seen stretches of ``K`` markers as rows ``(K, D, n)`` (C order: filtered along the last
        axis, scipy's filters copy no transposition), judged on the axes ``judged`` ``(K, D)``
        whose noise is ``noise`` ``(K, D)``; the same shape."""
        weight = judged / judged.sum(axis=1, keepdims=True)  # (K, D): the mean over the judged axes
        scale = np.where(judged, noise, 1.0)[..., None]
        current, moving = x, None  # moving (K, n): where the first level keeps the lightest (no ICI there)
        for (fc, sos), spread in zip(self.levels, self.spreads, strict=True):
            heavy = _signal().sosfiltfilt(sos, x)
            diff = current - heavy
            scaled = diff / (scale * spread)
            np.square(scaled, out=scaled)
            departure = np.sqrt(np.einsum("kdn,kd->kn", scaled, weight))  # (K, n): RMS over the judged axes
            keep = _kept(departure, self.threshold, self.rate, fc, axis=-1)
            if moving is None:
                moving = keep
            diff *= keep[:, None]
            heavy += diff
            current = heavy
        if self.ici_share > 0 and moving is not None:  # where the first level held: a share of LPA-ICI's
            ici = self._ici(x, judged, noise)
            ici -= current
            ici *= (self.ici_share * (1.0 - moving))[:, None]
            current += ici
        return current

    def _ici(self, x: np.ndarray, judged: np.ndarray, noise: np.ndarray) -> np.ndarray:
        """The LPA-ICI estimate (see the module docstring) of rows ``x`` ``(K, D, n)``, judged
        axes ``judged`` ``(K, D)`` with noise ``noise`` ``(K, D)``; the same shape (``x`` itself
        on an axis not judged). Each judged axis is read in units of its noise, so that every
        interval's width is one number a frame; made :data:`ICI_FRAMES` frames at a time, each
        block read with the longest window's reach either side (an hour's working arrays small)."""
        n, reach = x.shape[-1], self.windows[-1]
        rows = np.flatnonzero(judged.ravel())
        flat = x.reshape(-1, n)
        scale = noise.ravel()[rows][:, None]
        out = flat.copy()
        for start in range(0, n, ICI_FRAMES):
            lo, hi = max(start - reach, 0), min(start + ICI_FRAMES + reach, n)
            block = self._ici_block(flat[rows, lo:hi] / scale)
            out[rows, start:start + ICI_FRAMES] = block[:, start - lo:start - lo + ICI_FRAMES] * scale
        return out.reshape(x.shape)

    def _ici_block(self, z: np.ndarray) -> np.ndarray:
        """:meth:`_ici` of rows ``z`` ``(R, n)`` in units of their noise."""
        rows, n = z.shape
        reach = self.windows[-1]
        # the running sums padded by the longest reach: a window's sum is two slices apart, clipped at the ends
        sums = np.empty((rows, n + 1 + 2 * reach))
        sums[:, :reach + 1] = 0.0
        np.cumsum(z, axis=1, out=sums[:, reach + 1:reach + 1 + n])
        sums[:, reach + 1 + n:] = sums[:, reach + n:reach + n + 1]
        frames = np.arange(n)
        before, after = np.minimum(frames[None], np.array(self.windows)[:, None]), \
            np.minimum(n - 1 - frames[None], np.array(self.windows)[:, None])  # (windows, n) samples in reach
        light = self.light_variance
        weighed, weights = np.zeros_like(z), np.zeros_like(z)
        mean, test, low, high = np.empty_like(z), np.empty_like(z), np.empty_like(z), np.empty_like(z)
        best, variance = np.empty_like(z), np.empty_like(z)
        ok, alive = np.empty(z.shape, dtype=bool), np.empty(z.shape, dtype=bool)
        for back, ahead in ((True, False), (False, True), (True, True)):
            np.subtract(z, ICI_GAMMA * light ** 0.5, out=low)
            np.add(z, ICI_GAMMA * light ** 0.5, out=high)
            best[:], variance[:], alive[:] = z, light, True
            for k, h in enumerate(self.windows):
                first, last = reach + 1 - (h + 1 if back else 1), reach + 1 + (h if ahead else 0)
                np.subtract(sums[:, last:last + n], sums[:, first:first + n], out=mean)
                share = 1.0 / (1 + (before[k] if back else 0) + (after[k] if ahead else 0))  # (n,): 1 / samples
                spread = np.minimum(share, light)  # a mean over samples the low-pass tied together
                half = ICI_GAMMA * np.sqrt(spread)
                mean *= share
                np.subtract(mean, half, out=test)
                np.maximum(low, test, out=low)
                np.add(mean, half, out=test)
                np.minimum(high, test, out=high)
                np.less_equal(low, high, out=ok)
                alive &= ok
                np.copyto(best, mean, where=alive)
                np.copyto(variance, spread, where=alive)
            best /= variance
            weighed += best
            np.divide(1.0, variance, out=variance)
            weights += variance
        return weighed / weights


def fast_moves(filled: np.ndarray, raw: np.ndarray, rate: float, cutoff: float, fast: float = FAST_HZ,
               threshold: float = FAST_THRESHOLD, noise: np.ndarray | None = None
               ) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """What the take's low-pass takes off each marker's fastest moves, to be put back after smoothing.

    The take's low-pass (``cutoff``, Hz) turns a 30 ms saccade into a 100 ms ramp. Where a
    lighter zero-phase low-pass (``fast`` Hz, capped below 0.45 of the ``rate``) departs from
    the take's low-pass by more than the marker's noise explains (the test of
    :class:`HoldSmoother`'s levels, at ``threshold``, on the spread the two low-passes' difference
    has on noise alone; widened and eased over half a period of the cut-off), the lighter one is
    kept. Where a marker moves, :class:`HoldSmoother` keeps the take's low-pass, so adding the
    difference there after it (:func:`put_back_moves`) gives the lighter low-pass.

    Parameters
    ----------
    filled : ndarray, shape (F, M, D)
        Positions after gap filling, before any smoothing (NaN where still unseen).
    raw : ndarray, shape (F, M, D)
        The same before gap filling, to measure each marker's noise on (:func:`marker_noise`; or give ``noise``).
    rate, cutoff : float
        Frame rate and the take's low-pass, Hz.
    fast, threshold : float
        The lighter low-pass (Hz) and its test's threshold (:data:`FAST_HZ`, :data:`FAST_THRESHOLD`).
    noise : ndarray, shape (M, D), optional
        Each marker's noise (:func:`marker_noise` of ``raw``), where already measured.

    Returns
    -------
    list of (int, ndarray, ndarray)
        Per marker with such moves: its index, the frames ``(k,)`` and the difference to add
        there ``(k, D)``.
    """
    from mapping.filters import Butterworth

    fast = min(fast, 0.45 * rate)
    if fast <= cutoff or len(filled) < 2:
        return []
    light_filter, base_filter = Butterworth(fast, rate), Butterworth(cutoff, rate)
    # the spread of the two zero-phase low-passes' difference on white noise of unit deviation
    spread = float(np.sqrt(np.mean((_power(light_filter.sos) - _power(base_filter.sos)) ** 2)))
    noise = marker_noise(raw) if noise is None else noise  # (M, D)
    judged = np.isfinite(noise) & (noise > 0)
    frames, dims = filled.shape[0], filled.shape[2]
    out = []
    columns = np.flatnonzero(judged.any(axis=1))
    for first in range(0, len(columns), MARKERS_AT_ONCE):
        part = columns[first:first + MARKERS_AT_ONCE]
        block = filled[:, part].reshape(frames, -1)
        diff = (light_filter.smooth_offline(block) - base_filter.smooth_offline(block)).reshape(frames, len(part), dims)
        scaled = diff / (np.where(judged[part], noise[part], np.inf) * spread)  # an axis not judged counts 0
        departure = np.sqrt(np.nan_to_num(np.sum(scaled ** 2, axis=2) / judged[part].sum(axis=1)))  # (F, K): RMS
        keep = _kept(departure, threshold, rate, cutoff, axis=0)
        for k in np.flatnonzero(keep.any(axis=0)):
            at = np.flatnonzero(keep[:, k] > 0)
            out.append((int(part[k]), at, np.nan_to_num(keep[at, k, None] * diff[at, k])))
    return out


def put_back_moves(positions: np.ndarray, moves: list[tuple[int, np.ndarray, np.ndarray]]) -> np.ndarray:
    """``positions`` ``(F, M, D)`` with :func:`fast_moves`' differences added, in place."""
    for m, frames, delta in moves:
        positions[frames, m] += delta
    return positions


def _kept(departure: np.ndarray, threshold: float, rate: float, cutoff: float, axis: int) -> np.ndarray:
    """The share of the lighter low-pass kept, from each frame's ``departure`` (along ``axis``, in
    units of the spread on noise alone): none below ``threshold``, all from twice it, widened and
    eased over half a period of the heavier ``cutoff`` (Hz) so that the switch leaves no step."""
    from scipy import ndimage

    keep = np.clip(departure / threshold - 1.0, 0.0, 1.0)
    width = max(3, int(round(0.5 * rate / cutoff)))
    return ndimage.uniform_filter1d(ndimage.maximum_filter1d(keep, width, axis=axis), width, axis=axis)


def _rows(markers: np.ndarray) -> np.ndarray:
    """Markers ``(n, K, D)`` as C-ordered rows ``(K, D, n)``."""
    return np.ascontiguousarray(markers.transpose(1, 2, 0))


def marker_noise(raw: np.ndarray) -> np.ndarray:
    """Each marker's noise per axis ``(M, D)`` from raw positions ``(F, M, D)``: the median
    absolute second difference (seen samples three in a row) as a standard deviation, capped
    at :data:`NOISE_CAP` times the median over the markers. :class:`HoldSmoother` and
    :func:`fast_moves` measure it each unless given it (cleaning measures it once for both)."""
    spread = jitter(np.asarray(raw, dtype=np.float64), least=10)
    if np.isfinite(spread).any():
        spread = np.minimum(spread, NOISE_CAP * np.nanmedian(spread))
    return spread


def _spreads(light: np.ndarray, heavier: list[np.ndarray]) -> list[float]:
    """For each heavier low-pass (second-order sections), the standard deviation of the
    difference between it and the previous, lighter one (``light``: its :func:`_power`), both
    forward-backward, on white noise of unit standard deviation (from the filters' responses)."""
    spreads, previous = [], light
    for sos in heavier:
        current = _power(sos)
        spreads.append(float(np.sqrt(np.mean((previous - current) ** 2))))
        previous = current
    return spreads


def _power(sos: np.ndarray) -> np.ndarray:
    """The forward-backward response ``|H|^2`` of a low-pass over 4096 frequencies up to Nyquist."""
    _, response = _signal().sosfreqz(sos, worN=4096)
    return np.abs(response) ** 2


def _signal() -> ModuleType:
    """scipy.signal, imported when first needed: the live mapper, which imports the cleaning
    stage's rules, never smooths offline and should not pay its second of start-up."""
    from scipy import signal

    return signal
