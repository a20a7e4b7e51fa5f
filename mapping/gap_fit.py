"""How a long gap's regression is set up, chosen and bridged (:class:`mapping.gaps.GapFiller`).

The design of a marker's regression on the markers seen through its gap (about their centre,
each weighted by nearness), the predictors' local mean, the choice of ridge penalty, blend and
bridge on stand-in gaps cut from the marker's own seen frames, the ridge fit itself, and the
straight lines that bridge what the regression misses at a gap's two ends.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline


def regression_design(source: np.ndarray, rows: np.ndarray, others: list[int], weight: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """The centre of the predictors ``others`` at ``rows`` of ``source`` ``(F, M, D)``, ``(rows,
    D)``, and the regression's design about it, ``(rows, features)``, each predictor weighted by
    ``weight`` and every feature centred."""
    centre = source[rows][:, others].mean(axis=1)  # the frame moving with the subject
    x = ((source[rows][:, others] - centre[:, None]) * weight[None, :, None]).reshape(len(rows), -1)
    if len(others) < 4:  # a centre of so few is mostly the predictors: keep its motion too
        x = np.hstack([x, centre])
    return centre, x - x.mean(axis=0)


def local_mean(pos: np.ndarray, half: int) -> np.ndarray:
    """Each sample of ``pos`` ``(F, M, D)`` as the mean of the seen samples within ``half``
    frames either side, where it is seen itself (NaN elsewhere).

    >>> local_mean(np.array([1.0, 2.0, 6.0, np.nan, 4.0]).reshape(5, 1, 1), 1).ravel().tolist()
    [1.5, 3.0, 4.0, nan, 4.0]
    """
    seen = np.isfinite(pos).all(axis=2)
    sums = np.cumsum(np.where(seen[..., None], pos, 0.0), axis=0)
    counts = np.cumsum(seen, axis=0)
    sums, counts = np.concatenate([np.zeros_like(sums[:1]), sums]), np.concatenate([np.zeros_like(counts[:1]), counts])
    frames = np.arange(len(pos))
    low, high = np.maximum(frames - half, 0), np.minimum(frames + half + 1, len(pos))
    mean = (sums[high] - sums[low]) / np.maximum(counts[high] - counts[low], 1)[..., None]
    return np.where(seen[..., None], mean, np.nan)


def bridge_residual(residual: np.ndarray, own: np.ndarray, start: int, end: int, times: np.ndarray, edge: int = 1
            ) -> np.ndarray:
    """The regression's residual (at the frames ``own``) across the gap ``[start, end)``,
    ``(end - start, dims)``: a straight line from its level at the last sample before the gap to
    the first after it, each level the median of up to ``edge`` samples on its side (:func:`_line`)."""
    before = max(int(np.searchsorted(own, start)) - 1, 0)
    after = min(int(np.searchsorted(own, end)), len(own) - 1)
    return _line(residual, times[own], before, after, times[start:end], edge)


def _line(values: np.ndarray, times: np.ndarray, before: int, after: int, at: np.ndarray, edge: int
          ) -> np.ndarray:
    """The straight line from ``values`` ``(n, ...)`` (rows first) at row ``before`` to row
    ``after``, at the times ``at``; ``(len(at), ...)``. With ``edge`` > 1 each end is the median
    of up to ``edge`` rows reaching away from the gap (at their mean time), which carries less
    of one sample's noise across it, and none of a spike's that the spike tests could not judge
    (one beside a gap)."""
    left, right = slice(max(before - edge + 1, 0), before + 1), slice(after, after + edge)
    a, b = np.median(values[left], axis=0), np.median(values[right], axis=0)
    t0, t1 = times[left].mean(), times[right].mean()
    share = np.clip((at - t0) / (t1 - t0), 0.0, 1.0) if t1 > t0 else np.full(len(at), 0.5)
    return a + share.reshape(-1, *([1] * (values.ndim - 1))) * (b - a)


def straight_line(values: np.ndarray, times: np.ndarray, start: int, end: int) -> np.ndarray:
    """The straight line across the gap ``[start, end)`` of ``values`` ``(F, ...)`` (frames first)
    from the sample before it to the one after, at ``times`` ``(F,)``; ``(end - start, ...)``.

    >>> straight_line(np.array([0.0, np.nan, np.nan, 3.0]), np.arange(4.0), 1, 3).tolist()
    [1.0, 2.0]
    """
    return _line(values, times, start - 1, end, times[start:end], 1)


#: The ridge penalties :func:`validate_gap` chooses among, the shares of the regression (against the
#: marker's own spline) and the samples either side whose median a bridge starts and ends at
#: (:func:`bridge_residual`: one follows a smooth residual best, five carry less of a noisy one's jitter
#: and none of a spike beside the gap) it tries.
RIDGES = (0.003, 0.01, 0.03, 0.1)
SHARES = (0.0, 0.25, 0.5, 0.75, 1.0)
EDGES = (1, 5)
#: Predictors may be read as their mean over this many seconds either side (one frame at 60 Hz),
#: where the stand-in gaps fill better so: a regression on noisy predictors shrinks their weights
#: (errors in variables; a lid filled from the other lid blinked two thirds as deep), while on
#: clean ones the mean only blurs a saccade or a step. The marker's own samples stay as seen.
PREDICTOR_MEAN_SECONDS = 0.0125


def validate_gap(x: np.ndarray, y: np.ndarray, t: np.ndarray, length: int, straight: bool,
              fallback: tuple[float, float, int]) -> tuple[float, tuple[float, float, int]]:
    """The summed error of the best fill of the stand-ins (infinite where there are none) and
    its ridge penalty, the regression's share (against the marker's own spline, or its
    straight line where ``straight``) and the bridge's edge samples (:data:`EDGES`) that best
    fill stand-in gaps of ``length`` rows cut from the marker's own seen rows (``x``
    ``(n, features)``, ``y`` ``(n, dims)`` at times ``t``), up to eight spread evenly along
    them, each filled as a real gap is. Motion differs from take to take (a face's few tightly
    coupled markers, a body's many loosely coupled ones; slow drifts, quick syllables; clean and
    noisy sensors), so all are chosen on the take itself; ``fallback`` where the take is too
    short to spare the rows."""
    n = len(y)
    count = min(8, (n - 60) // max(length, 1) - 1)  # stand-ins, as many as the rows allow, up to 8
    if count < 2:
        return np.inf, fallback
    blocks = [(middle - length // 2, middle - length // 2 + length)
              for middle in (n * k // (count + 1) for k in range(1, count + 1))]
    truth = np.stack([y[lo:hi] for lo, hi in blocks])  # (blocks, length, dims)
    own = []
    for lo, hi in blocks:
        keep = np.r_[0:lo, hi:n]
        if straight:
            own.append(straight_line(y, t, lo, hi))
        else:
            own.append(CubicSpline(t[keep], y[keep], axis=0)(t[lo:hi]))
    spline = np.stack(own)
    starts = np.array([lo for lo, _ in blocks])
    shares = np.asarray(SHARES)[:, None, None, None]
    best = (np.inf, fallback)
    moments = Moments(x, y, blocks)
    reach = max(EDGES)  # rows either side a bridge may read
    rows = np.clip(starts[:, None] + np.arange(-reach, length + reach), 0, n - 1)  # (blocks, rows)
    for ridge in RIDGES:
        residual = y[rows] - moments.predict(ridge, rows)  # (blocks, rows, dims): only where read
        inside = residual[:, reach:reach + length]
        for edge in EDGES:  # the stand-ins bridged row by row, as _line bridges a real gap
            a = np.median(residual[:, reach - edge:reach], axis=1)[:, None]
            b = np.median(residual[:, reach + length:reach + length + edge], axis=1)[:, None]
            t0 = rows[:, reach - edge:reach].mean(axis=1)
            t1 = rows[:, reach + length:reach + length + edge].mean(axis=1)
            share = ((rows[:, reach:reach + length] - t0[:, None]) / (t1 - t0)[:, None])[..., None]
            regressed = truth - inside + a + share * (b - a)
            miss = shares * regressed + (1 - shares) * spline - truth  # (shares, blocks, length, dims)
            error = np.linalg.norm(miss, axis=-1).mean(axis=-1).sum(axis=-1)
            pick = int(np.argmin(error))
            if error[pick] < best[0]:
                best = (float(error[pick]), (ridge, SHARES[pick], edge))
    return best


def ridge_predict(x: np.ndarray, fit: np.ndarray, y: np.ndarray, ridge: float) -> np.ndarray:
    """Ridge regression of ``y`` on the rows ``fit`` of ``x`` ``(rows, features)``, predicted for
    every row ``(rows, dims)``. ``ridge`` is relative to the mean feature variance, so it does not
    depend on units; the intercept is not penalised."""
    xf = x[fit]
    centre = xf.mean(axis=0)
    xc = xf - centre
    gram = xc.T @ xc
    penalty = ridge * np.trace(gram) / max(len(gram), 1)
    coef = np.linalg.solve(gram + penalty * np.eye(len(gram)), xc.T @ (y - y.mean(axis=0)))
    return (x - centre) @ coef + y.mean(axis=0)


class Moments:
    """The sums a ridge regression of ``y`` ``(n, dims)`` on ``x`` ``(n, features)`` needs, over
    all rows less each block ``[lo, hi)`` of ``blocks``: taken once for the whole and once per
    block, so that each stand-in's fit costs a small solve instead of a pass over every row. The
    same fit as :func:`ridge_predict` on the rows outside the block."""

    def __init__(self, x: np.ndarray, y: np.ndarray, blocks: list[tuple[int, int]]) -> None:
        self.x = x
        self.count = np.array([len(y) - (hi - lo) for lo, hi in blocks], dtype=float)
        parts = [(x[lo:hi], y[lo:hi]) for lo, hi in blocks]
        self.sx = x.sum(axis=0) - np.stack([bx.sum(axis=0) for bx, _ in parts])  # (B, f)
        self.sy = y.sum(axis=0) - np.stack([by.sum(axis=0) for _, by in parts])  # (B, d)
        self.xx = x.T @ x - np.stack([bx.T @ bx for bx, _ in parts])  # (B, f, f)
        self.xy = x.T @ y - np.stack([bx.T @ by for bx, by in parts])  # (B, f, d)

    def predict(self, ridge: float, rows: np.ndarray) -> np.ndarray:
        """The predictions of each block's fit at its ``rows`` ``(B, R)``, ``(B, R, dims)``."""
        mx, my = self.sx / self.count[:, None], self.sy / self.count[:, None]
        gram = self.xx - self.count[:, None, None] * mx[:, :, None] * mx[:, None, :]
        cross = self.xy - self.count[:, None, None] * mx[:, :, None] * my[:, None, :]
        size = gram.shape[-1]
        penalty = ridge * np.trace(gram, axis1=1, axis2=2) / max(size, 1)
        coef = np.linalg.solve(gram + penalty[:, None, None] * np.eye(size), cross)
        return (self.x[rows] - mx[:, None]) @ coef + my[:, None]
