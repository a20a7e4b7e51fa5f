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
    """

    def __init__(self, rate: float, cutoff: float, levels: tuple[float, ...] = LEVELS,
                 threshold: float = THRESHOLD) -> None:
        if rate <= 0 or not 0 < cutoff < rate / 2:
            raise ValueError(f"the cutoff must be between 0 and half the rate ({rate / 2:g} Hz), got {cutoff:g}")
        self.rate, self.threshold = rate, threshold
        kept = [fc for fc in levels if 0 < fc < cutoff]
        self.levels = [(fc, _signal().butter(2, fc, fs=rate, output="sos")) for fc in kept]
        self.spreads = _spreads(_signal().butter(2, cutoff, fs=rate, output="sos"), [sos for _, sos in self.levels])

    def smooth(self, smoothed: np.ndarray, raw: np.ndarray, overwrite: bool = False) -> np.ndarray:
        """Markers ``(F, M, D)`` smoothed by the take's low-pass (NaN where unseen), made
        steadier where they hold; ``raw`` ``(F, M, D)``: the same markers before any smoothing
        or gap filling (NaN where not seen), to measure each one's noise on. ``overwrite``: the
        result may be written into ``smoothed`` (a float64 array the caller no longer needs: a
        long take's copy saved)."""
        out = np.asarray(smoothed, dtype=np.float64)
        if not self.levels or len(out) < 2:
            return out if overwrite else out.copy()
        noise = _noise(np.asarray(raw, dtype=np.float64))  # (M, D)
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
        from scipy import ndimage

        weight = judged / judged.sum(axis=1, keepdims=True)  # (K, D): the mean over the judged axes
        scale = np.where(judged, noise, 1.0)[..., None]
        current = x
        for (fc, sos), spread in zip(self.levels, self.spreads, strict=True):
            heavy = _signal().sosfiltfilt(sos, x)
            diff = current - heavy
            scaled = diff / (scale * spread)
            np.square(scaled, out=scaled)
            departure = np.sqrt(np.einsum("kdn,kd->kn", scaled, weight))  # (K, n): RMS over the judged axes
            keep = np.clip(departure / self.threshold - 1.0, 0.0, 1.0)
            width = max(3, int(round(0.5 * self.rate / fc)))
            keep = ndimage.uniform_filter1d(ndimage.maximum_filter1d(keep, width, axis=-1), width, axis=-1)
            diff *= keep[:, None]
            heavy += diff
            current = heavy
        return current


def _rows(markers: np.ndarray) -> np.ndarray:
    """Markers ``(n, K, D)`` as C-ordered rows ``(K, D, n)``."""
    return np.ascontiguousarray(markers.transpose(1, 2, 0))


def _noise(raw: np.ndarray) -> np.ndarray:
    """Each marker's noise per axis ``(M, D)`` from raw positions ``(F, M, D)``: the median
    absolute second difference (seen samples three in a row) as a standard deviation, capped
    at :data:`NOISE_CAP` times the median over the markers."""
    spread = jitter(raw, least=10)
    if np.isfinite(spread).any():
        spread = np.minimum(spread, NOISE_CAP * np.nanmedian(spread))
    return spread


def _spreads(light: np.ndarray, heavier: list[np.ndarray]) -> list[float]:
    """For each heavier low-pass (second-order sections), the standard deviation of the
    difference between it and the previous, lighter one, both forward-backward, on white noise
    of unit standard deviation (from the filters' responses)."""
    spreads, previous = [], _power(light)
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
