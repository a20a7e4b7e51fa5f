"""How a long gap's regression is set up, chosen and bridged (:class:`mapping.gaps.GapFiller`).

The design of a marker's regression on the markers seen through its gap (about their centre,
each weighted by nearness), the predictors' local mean, the choice of ridge penalty, blend and
bridge on stand-in gaps cut from the marker's own seen frames, the ridge fit itself, and the
straight lines that bridge what the regression misses at a gap's two ends.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.linalg import solve_banded


def regression_design(source: np.ndarray, rows: np.ndarray, others: list[int], weight: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """The centre of the predictors ``others`` at ``rows`` of ``source`` ``(F, M, D)``, ``(rows,
    D)``, and the regression's design about it, ``(rows, features)``, each predictor weighted by
    ``weight`` and every feature centred."""
    centre, x = features(source[rows][:, others], weight)  # whole rows first, a quicker gather
    x -= x.mean(axis=0)
    return centre, x


def features(picked: np.ndarray, weight: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The centre ``(rows, D)`` of the predictors ``picked`` ``(rows, P, D)`` (a copy of their own:
    it is overwritten) and their features about it, each weighted by ``weight`` ``(P,)``, not
    centred over the rows: ``(rows, features)``. A live fill makes one frame's so."""
    centre = picked.mean(axis=1)  # the frame moving with the subject
    picked -= centre[:, None]
    picked *= weight[None, :, None]
    x = picked.reshape(len(picked), -1)
    if picked.shape[1] < 4:  # a centre of so few is mostly the predictors: keep its motion too
        x = np.hstack([x, centre])
    return centre, x


def nearness(target: np.ndarray, others: np.ndarray, sigma: float) -> np.ndarray:
    """Each predictor's weight ``exp(-d^2 / (2 sigma^2))`` from its mean distance ``d`` to the
    target over the rows seen, ``target`` ``(rows, D)``, ``others`` ``(rows, P, D)``: ``(P,)``."""
    distance = np.mean(np.linalg.norm(others - target[:, None], axis=2), axis=0)
    return np.exp(-distance ** 2 / (2 * sigma ** 2))


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


#: Knots either side of a stand-in gap that :func:`stand_in_splines` fits through. A cubic spline's
#: reach decays by 2 - sqrt(3) (about 0.27) a knot, so the samples and the end condition beyond 40
#: knots move its values inside the gap by under 1e-22 of theirs: the spline through every sample.
SPLINE_REACH = 40


def stand_in_splines(t: np.ndarray, y: np.ndarray, blocks: list[tuple[int, int]]) -> np.ndarray:
    """The cubic spline through the rows of ``y`` ``(n, dims)`` at times ``t`` ``(n,)`` outside
    each block ``[lo, hi)`` of ``blocks`` (all of one length ``L``), at the block's own times:
    ``(blocks, L, dims)``. Where a block lies :data:`SPLINE_REACH` rows from both ends, all such
    are fitted at once through those rows (one banded solve; natural ends that far away), else
    through every row (:class:`scipy.interpolate.CubicSpline`, not-a-knot) as before."""
    n, reach = len(y), SPLINE_REACH
    length = blocks[0][1] - blocks[0][0]
    out = np.empty((len(blocks), length, y.shape[1]))
    inner = [b for b, (lo, hi) in enumerate(blocks) if lo >= reach and hi + reach <= n]
    for b, (lo, hi) in enumerate(blocks):
        if b not in inner:
            keep = np.r_[0:lo, hi:n]
            out[b] = CubicSpline(t[keep], y[keep], axis=0)(t[lo:hi])
    if not inner:
        return out
    starts = np.array([blocks[b][0] for b in inner])
    rows = np.concatenate([starts[:, None] + np.arange(-reach, 0), starts[:, None] + length + np.arange(reach)], axis=1)
    x, v = t[rows], y[rows]  # (B, m), (B, m, dims): each block's knots
    h = np.diff(x, axis=1)  # (B, m - 1)
    rhs = 6.0 * np.diff(np.diff(v, axis=1) / h[..., None], axis=1)  # (B, m - 2, dims)
    count, inside = len(inner), rows.shape[1] - 2
    band = np.zeros((3, count, inside))  # the second derivatives' tridiagonal system, block by block
    band[0, :, 1:] = h[:, 1:-1]
    band[1] = 2.0 * (h[:, :-1] + h[:, 1:])
    band[2, :, :-1] = h[:, 1:-1]
    second = np.zeros_like(v)
    second[:, 1:-1] = solve_banded((1, 1), band.reshape(3, -1), rhs.reshape(count * inside, -1)).reshape(rhs.shape)
    a, b = reach - 1, reach  # the knots either side of the block
    wide = (x[:, b] - x[:, a])[:, None, None]
    at = t[starts[:, None] + np.arange(length)]
    left, right = (x[:, b, None] - at)[..., None], (at - x[:, a, None])[..., None]
    out[inner] = (second[:, a, None] * left ** 3 + second[:, b, None] * right ** 3) / (6.0 * wide) \
        + (v[:, a, None] / wide - second[:, a, None] * wide / 6.0) * left \
        + (v[:, b, None] / wide - second[:, b, None] * wide / 6.0) * right
    return out


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
              fallback: tuple[float, float, int], one_side: int = 0) -> tuple[float, tuple[float, float, int]]:
    """The summed error of the best fill of the stand-ins (infinite where there are none) and
    its ridge penalty, the regression's share (against the marker's own spline, or its
    straight line where ``straight``) and the bridge's edge samples (:data:`EDGES`) that best
    fill stand-in gaps of ``length`` rows cut from the marker's own seen rows (``x``
    ``(n, features)``, ``y`` ``(n, dims)`` at times ``t``), up to eight spread evenly along
    them, each filled as a real gap is. Motion differs from take to take (a face's few tightly
    coupled markers, a body's many loosely coupled ones; slow drifts, quick syllables; clean and
    noisy sensors), so all are chosen on the take itself; ``fallback`` where the take is too
    short to spare the rows. A gap at an end of the take, seen on ``one_side`` only (-1: before
    it, 1: after it), has no spline or line across it: its regression's residual is held at its
    level on that side (:func:`edge_level`), and the marker's own part is its nearest sample
    there, held; each stand-in is judged as seen from the same side."""
    n = len(y)
    blocks = stand_ins(n, length)
    if not blocks:
        return np.inf, fallback
    truth = np.stack([y[lo:hi] for lo, hi in blocks])  # (blocks, length, dims)
    if one_side:  # the marker's own part: held at its nearest sample on the seen side
        near = np.array([lo - 1 if one_side < 0 else hi for lo, hi in blocks])
        spline = np.repeat(y[near][:, None], length, axis=1)
    else:
        spline = np.stack([straight_line(y, t, lo, hi) for lo, hi in blocks]) if straight \
            else stand_in_splines(t, y, blocks)
    starts = np.array([lo for lo, _ in blocks])
    shares = np.asarray(SHARES)[:, None, None, None]
    best = (np.inf, fallback)
    reach = max(EDGES)  # rows either side a bridge may read
    rows = np.clip(starts[:, None] + np.arange(-reach, length + reach), 0, n - 1)  # (blocks, rows)
    moments = Moments(x, y, blocks, rows)
    lines = []  # each edge's share of the way across each stand-in, as _line bridges a real gap
    for edge in EDGES:
        t0 = rows[:, reach - edge:reach].mean(axis=1)
        t1 = rows[:, reach + length:reach + length + edge].mean(axis=1)
        lines.append(((rows[:, reach:reach + length] - t0[:, None]) / (t1 - t0)[:, None])[..., None])
    own_part = (1 - shares) * spline  # (shares, blocks, length, dims)
    for ridge in RIDGES:
        residual = y[rows] - moments.predict(ridge)  # (blocks, rows, dims): only where read
        inside = residual[:, reach:reach + length]
        for edge, share in zip(EDGES, lines, strict=True):  # the stand-ins bridged row by row
            a = _median_rows(residual[:, reach - edge:reach])[:, None]
            b = _median_rows(residual[:, reach + length:reach + length + edge])[:, None]
            regressed = truth - inside + ((a if one_side < 0 else b) if one_side else a + share * (b - a))
            miss = shares * regressed + own_part - truth  # (shares, blocks, length, dims)
            error = np.linalg.norm(miss, axis=-1).mean(axis=-1).sum(axis=-1)
            pick = int(np.argmin(error))
            if error[pick] < best[0]:
                best = (float(error[pick]), (ridge, SHARES[pick], edge))
    return best


def edge_level(residual: np.ndarray, one_side: int, edge: int) -> np.ndarray:
    """The level a regression's ``residual`` ``(n, dims)`` (rows in time order) is held at across
    a gap at an end of the take seen on ``one_side`` only (-1: the rows are all before it, 1: all
    after): the median of the ``edge`` rows nearest the gap, ``(dims,)``."""
    return np.median(residual[-edge:] if one_side < 0 else residual[:edge], axis=0)


def stand_ins(rows: int, length: int) -> list[tuple[int, int]]:
    """Stand-in gaps ``[lo, hi)`` of ``length`` rows centred at even steps along ``rows`` seen rows:
    one fewer than fit in all but 60 of them, up to eight; none where fewer than two would.

    >>> stand_ins(300, 30)
    [(22, 52), (60, 90), (97, 127), (135, 165), (172, 202), (210, 240), (247, 277)]
    """
    count = min(8, (rows - 60) // max(length, 1) - 1)
    if count < 2:
        return []
    return [(middle - length // 2, middle - length // 2 + length)
            for middle in (rows * k // (count + 1) for k in range(1, count + 1))]


def line_edge(y: np.ndarray, t: np.ndarray, length: int) -> int:
    """The samples either side (one of :data:`EDGES`) whose median a straight line across a gap of
    ``length`` rows best starts and ends at, judged on :func:`stand_ins` cut from a marker's own
    seen rows ``y`` ``(n, dims)`` at times ``t`` ``(n,)``; 1 where the rows are too few to judge.
    One sample follows a marker that moves up to the gap; more carry less of one sample's jitter,
    or of a spike beside the gap that the spike tests could not judge, across it."""
    blocks = stand_ins(len(y), length)
    if not blocks:
        return 1
    errors = [sum(float(np.linalg.norm(_line(y, t, lo - 1, hi, t[lo:hi], edge) - y[lo:hi], axis=-1).mean())
                  for lo, hi in blocks) for edge in EDGES]
    return EDGES[int(np.argmin(errors))]


def _median_rows(values: np.ndarray) -> np.ndarray:
    """The median over axis 1 of ``values`` ``(B, edge, ...)`` (one row: itself, without numpy's
    median's cost)."""
    return values[:, 0] if values.shape[1] == 1 else np.median(values, axis=1)


def ridge_predict(x: np.ndarray, fit: np.ndarray, y: np.ndarray, ridge: float) -> np.ndarray:
    """Ridge regression of ``y`` on the rows ``fit`` of ``x`` ``(rows, features)``, predicted for
    every row ``(rows, dims)`` (:func:`ridge_fit`)."""
    centre, coef, mean = ridge_fit(x[fit], y, ridge)
    return (x - centre) @ coef + mean


def ridge_fit(x: np.ndarray, y: np.ndarray, ridge: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ridge regression of ``y`` ``(rows, dims)`` on ``x`` ``(rows, features)``: the features'
    mean ``(features,)``, the weights ``(features, dims)`` and ``y``'s mean ``(dims,)``, which
    predict ``(x' - mean_x) @ weights + mean_y``. ``ridge`` is relative to the mean feature
    variance, so it does not depend on units; the intercept is not penalised."""
    centre = x.mean(axis=0)
    xc = x - centre
    gram = xc.T @ xc
    penalty = ridge * np.trace(gram) / max(len(gram), 1)
    mean = y.mean(axis=0)
    return centre, np.linalg.solve(gram + penalty * np.eye(len(gram)), xc.T @ (y - mean)), mean


class Moments:
    """The sums a ridge regression of ``y`` ``(n, dims)`` on ``x`` ``(n, features)`` needs, over
    all rows less each block ``[lo, hi)`` of ``blocks``: taken once for the whole and once per
    block, so that each stand-in's fit costs a small solve instead of a pass over every row. The
    same fit as :func:`ridge_predict` on the rows outside the block; what does not depend on the
    penalty (the centred sums, the design at each block's ``rows`` ``(B, R)``) is made once."""

    def __init__(self, x: np.ndarray, y: np.ndarray, blocks: list[tuple[int, int]], rows: np.ndarray) -> None:
        count = np.array([len(y) - (hi - lo) for lo, hi in blocks], dtype=float)
        parts = [(x[lo:hi], y[lo:hi]) for lo, hi in blocks]
        sx = x.sum(axis=0) - np.stack([bx.sum(axis=0) for bx, _ in parts])  # (B, f)
        sy = y.sum(axis=0) - np.stack([by.sum(axis=0) for _, by in parts])  # (B, d)
        xx = x.T @ x - np.stack([bx.T @ bx for bx, _ in parts])  # (B, f, f)
        xy = x.T @ y - np.stack([bx.T @ by for bx, by in parts])  # (B, f, d)
        mx, self.my = sx / count[:, None], sy / count[:, None]
        self.gram = xx - count[:, None, None] * mx[:, :, None] * mx[:, None, :]
        self.cross = xy - count[:, None, None] * mx[:, :, None] * self.my[:, None, :]
        self.trace = np.trace(self.gram, axis1=1, axis2=2) / max(self.gram.shape[-1], 1)
        self.design = x[rows] - mx[:, None]  # (B, R, f)

    def predict(self, ridge: float) -> np.ndarray:
        """The predictions of each block's fit at its rows, ``(B, R, dims)``."""
        size = self.gram.shape[-1]
        coef = np.linalg.solve(self.gram + (ridge * self.trace)[:, None, None] * np.eye(size), self.cross)
        return self.design @ coef + self.my[:, None]
