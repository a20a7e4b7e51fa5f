"""Gap filling: short gaps by cubic spline, long ones from the other markers' correlated motion.

Facial markers move together (a smile moves the corners, cheeks and lower lids at once), so a
marker missing for a while is better guessed from the markers still seen than from its own
past and future alone. After Gløersen & Federolf (2016, PLoS ONE 11(3): e0152616), who
reconstruct a missing marker from the principal components of the others: around a long gap,
the missing marker is regressed on the principal components of the markers seen throughout
(``window_seconds`` either side), and what the regression misses, small and smooth, is bridged
by a cubic spline, so the filled stretch meets the real samples at both ends.

Gaps of at most ``spline_frames`` frames use a cubic spline through the marker's own samples
(never worse than a spline there, by construction); gaps longer than ``max_gap_seconds`` stay
NaN (never invented), and the caller lowers the marker's confidence there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline


@dataclass(frozen=True, eq=False)
class Filled:
    """Positions with gaps filled, and where.

    Attributes
    ----------
    positions : ndarray, shape (frames, markers, dims)
    filled : ndarray of bool, shape (frames, markers)
        Samples that were missing and are now estimated.
    """

    positions: np.ndarray
    filled: np.ndarray


def gap_runs(missing: np.ndarray) -> list[tuple[int, int]]:
    """``[start, end)`` frame ranges of the runs of True in a ``(frames,)`` mask."""
    edges = np.diff(np.concatenate([[0], missing.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1).tolist(), np.flatnonzero(edges == -1).tolist()))


class GapFiller:
    """Fill the gaps of marker trajectories (see the module docstring).

    Parameters
    ----------
    spline_frames : int
        Gaps this long or shorter are filled by a cubic spline of the marker's own samples.
    max_gap_seconds : float
        Longer gaps are left NaN.
    rank : int or None
        Principal components of the other markers used to predict a missing one; default:
        enough for 99.9 % of their variance, at most 8.
    window_seconds : float
        How far either side of a gap the relation between the markers is learnt.
    """

    def __init__(self, spline_frames: int = 5, max_gap_seconds: float = 2.0, rank: int | None = None,
                 window_seconds: float = 10.0) -> None:
        if spline_frames < 0 or max_gap_seconds <= 0 or window_seconds <= 0:
            raise ValueError("spline_frames must be >= 0, max_gap_seconds and window_seconds > 0")
        self.spline_frames, self.max_gap_seconds = spline_frames, max_gap_seconds
        self.rank, self.window_seconds = rank, window_seconds

    def apply(self, positions: np.ndarray, times: np.ndarray) -> Filled:
        """Fill ``positions`` ``(frames, markers, dims)`` sampled at ``times`` ``(frames,)``."""
        pos = np.array(positions, dtype=np.float64, copy=True)
        frames, markers, dims = pos.shape
        missing = np.isnan(pos).any(axis=2)
        pos[missing] = np.nan
        rate = (frames - 1) / (times[-1] - times[0]) if frames > 1 and times[-1] > times[0] else 1.0
        max_frames = int(round(self.max_gap_seconds * rate))
        short, long_ = np.zeros_like(missing), np.zeros_like(missing)
        for m in range(markers):
            for start, end in gap_runs(missing[:, m]):
                if start == 0 or end == frames or end - start > max_frames:
                    continue  # nothing on one side, or too long: left unseen
                (short if end - start <= self.spline_frames else long_)[start:end, m] = True
        out = pos.copy()
        if long_.any():
            self._from_neighbours(out, times, long_, rate)
        if short.any():
            self._splines(out, times, short)
        return Filled(out, short | long_)

    def _splines(self, pos: np.ndarray, times: np.ndarray, wanted: np.ndarray) -> None:
        """Cubic spline through each marker's seen samples, written where ``wanted``."""
        for m in np.flatnonzero(wanted.any(axis=0)):
            seen = np.isfinite(pos[:, m, 0]) & ~wanted[:, m]
            if seen.sum() < 2:
                continue
            spline = CubicSpline(times[seen], pos[seen, m], axis=0)
            pos[wanted[:, m], m] = spline(times[wanted[:, m]])

    def _from_neighbours(self, pos: np.ndarray, times: np.ndarray, wanted: np.ndarray, rate: float) -> None:
        """Fill each long gap from the markers seen around and through it, written into ``pos``.

        Around a gap (a window of the gap's length, at least a second, on each side), the
        missing marker is regressed on the principal components of the markers seen throughout
        that window; the regression's residual, small and smooth, is bridged by a cubic spline
        and added back to its prediction inside the gap.
        """
        frames, markers, dims = pos.shape
        seen_all = np.isfinite(pos).all(axis=2)
        for m in np.flatnonzero(wanted.any(axis=0)):
            for start, end in gap_runs(wanted[:, m]):
                pad = max(int(self.window_seconds * rate), end - start)
                lo, hi = max(0, start - pad), min(frames, end + pad)
                others = [k for k in range(markers) if k != m and seen_all[lo:hi, k].all()]
                own = np.flatnonzero(seen_all[lo:hi, m]) + lo
                if not others or len(own) < 4:
                    self._splines(pos, times, _only(wanted, start, end, m))
                    continue
                x = pos[lo:hi][:, others].reshape(hi - lo, -1)
                x = x - x.mean(axis=0)
                u, sv, _ = np.linalg.svd(x, full_matrices=False)
                k = min(self.rank or _rank_for(sv, 0.999, most=8), len(own) // 4 or 1)
                design = np.column_stack([u[:, :k], np.ones(hi - lo)])
                coef, *_ = np.linalg.lstsq(design[own - lo], pos[own, m], rcond=None)
                predicted = design @ coef
                residual = CubicSpline(times[own], pos[own, m] - predicted[own - lo], axis=0)
                pos[start:end, m] = predicted[start - lo:end - lo] + residual(times[start:end])


def _only(mask: np.ndarray, start: int, end: int, marker: int) -> np.ndarray:
    out = np.zeros_like(mask)
    out[start:end, marker] = True
    return out


def _rank_for(singular: np.ndarray, share: float, most: int = 12) -> int:
    energy = np.cumsum(singular ** 2)
    if energy[-1] <= 0:
        return 1
    return int(min(np.searchsorted(energy / energy[-1], share) + 1, most, len(singular)))
