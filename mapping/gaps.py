"""Gap filling: short gaps by cubic spline, long ones from the other markers' correlated motion.

Facial markers move together (a smile moves the corners, cheeks and lower lids at once), so a
marker missing for a while is better guessed from the markers still seen than from its own
past and future alone. After Gløersen & Federolf (2016, PLoS ONE 11(3): e0152616), who
reconstruct a missing marker from the principal components of the others: around a long gap,
the missing marker is regressed on the markers seen throughout it (``window_seconds`` either
side) by ridge regression, which keeps their strong principal directions and shrinks the weak
ones (a hard cut to the first few components lost small but telling motions such as the other
pupil's); what the regression misses at the gap's two ends is bridged by a straight line, so
the filled stretch meets the real samples at both ends (a spline through the noisy residuals
on either side swung by many millimetres across the gap).

Gaps of at most ``spline_frames`` frames use a cubic spline through the marker's own samples
(never worse than a spline there, by construction); gaps longer than ``max_gap_seconds`` stay
NaN (never invented), and the caller lowers the marker's confidence there.

Markers ``apart`` from the face (a marker set's ``independent`` ones: the pupils, whose gaze the
lips and brows do not foretell) are predicted only from each other, and never predict the rest;
where none of them is seen across a gap (both irises behind blinking lids) the gap is bridged by
a straight line, which neither dips with the lids nor overshoots as a spline through them does.
"""

from __future__ import annotations

from collections.abc import Sequence
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
    return list(zip(np.flatnonzero(edges == 1).tolist(), np.flatnonzero(edges == -1).tolist(), strict=True))


class GapFiller:
    """Fill the gaps of marker trajectories (see the module docstring).

    Parameters
    ----------
    spline_frames : int
        Gaps this long or shorter are filled by a cubic spline of the marker's own samples.
    max_gap_seconds : float
        Longer gaps are left NaN.
    ridge : float
        Ridge penalty of the regression on the other markers, relative to their mean variance
        (it shrinks their weakest principal directions, the soft form of keeping a few
        principal components), where ``validate`` is off or the take too short to choose one.
    window_seconds : float
        How far either side of a gap the relation between the markers is learnt.
    blend_seconds : tuple of float
        Without validation: gaps up to the first length take the marker's own spline, from the
        second the regression, and a linear blend of the two between.
    sigma_mm : float
        Predictors are weighted by ``exp(-d^2 / (2 sigma^2))`` of their mean distance ``d`` to
        the missing marker (R2's weighting and its 200 mm), so that near markers lead.
    validate : bool
        Choose each gap's ridge penalty (:data:`RIDGES`) and its blend with the spline
        (:data:`SHARES`) on stand-in gaps cut from the marker's own seen frames
        (:func:`_validate`): a face's few tightly coupled markers and a body's many loosely
        coupled ones want different ones; and whether the predictors are read as seen or as
        their local mean (``predictor_mean_seconds``).
    predictor_mean_seconds : float, optional
        The half-width of that local mean (:data:`PREDICTOR_MEAN_SECONDS` by default; 0: the
        predictors as seen only).

    Long gaps are regressed about the centre of the markers that predict them (a body walks
    across the room; a face's markers move about their own), the centre's own motion kept as a
    predictor where fewer than four predict.
    """

    def __init__(self, spline_frames: int = 5, max_gap_seconds: float = 2.0, ridge: float = 3e-2,
                 window_seconds: float = 10.0, blend_seconds: tuple[float, float] = (0.1, 0.5),
                 sigma_mm: float = 200.0, validate: bool = True, predictor_mean_seconds: float | None = None
                 ) -> None:
        if spline_frames < 0 or max_gap_seconds <= 0 or window_seconds <= 0:
            raise ValueError("spline_frames must be >= 0, max_gap_seconds and window_seconds > 0")
        self.spline_frames, self.max_gap_seconds = spline_frames, max_gap_seconds
        if not 0 <= blend_seconds[0] < blend_seconds[1]:
            raise ValueError("blend_seconds must be (low, high) with 0 <= low < high")
        self.ridge, self.window_seconds, self.blend_seconds = ridge, window_seconds, blend_seconds
        self.sigma_mm, self.validate = sigma_mm, validate
        self.predictor_mean_seconds = (PREDICTOR_MEAN_SECONDS if predictor_mean_seconds is None
                                       else predictor_mean_seconds)

    def apply(self, positions: np.ndarray, times: np.ndarray, apart: Sequence[int] = ()) -> Filled:
        """Fill ``positions`` ``(frames, markers, dims)`` sampled at ``times`` ``(frames,)``;
        the markers (columns) ``apart`` are filled from each other or straight across (see the
        module docstring)."""
        pos = np.array(positions, dtype=np.float64, copy=True)
        frames, markers, dims = pos.shape
        missing = np.asarray(np.isnan(pos).any(axis=2))
        pos[missing] = np.nan
        rate = (frames - 1) / (times[-1] - times[0]) if frames > 1 and times[-1] > times[0] else 1.0
        max_frames = int(round(min(self.max_gap_seconds, 86400.0) * rate))  # 1e308 s overflowed: a day is all
        short, long_, lined = np.zeros_like(missing), np.zeros_like(missing), np.zeros_like(missing)
        brief = np.zeros_like(missing)  # an apart marker's brief dropouts, bridged before its partners need it
        for m in apart:
            for start, end in gap_runs(missing[:, m]):
                brief[start:end, m] = 0 < start and end < frames and end - start <= self.spline_frames
        for m in range(markers):
            for start, end in gap_runs(missing[:, m]):
                if start == 0 or end == frames or end - start > max_frames:
                    continue  # nothing on one side, or too long: left unseen
                if m in apart:
                    partnered = any(k != m and not (missing & ~brief)[start:end, k].any() for k in apart)
                    (long_ if partnered and not brief[start, m] else lined)[start:end, m] = True
                    continue
                (short if end - start <= self.spline_frames else long_)[start:end, m] = True
        out = pos.copy()
        for m in map(int, np.flatnonzero(lined.any(axis=0))):
            for start, end in gap_runs(lined[:, m]):
                out[start:end, m] = straight_line(out[:, m], times, start, end)
        if short.any():  # first, so that brief dropouts do not disqualify a marker as a predictor
            self._splines(out, times, short)
        if long_.any():
            self._from_neighbours(out, times, long_, rate, set(apart))
        return Filled(out, short | long_ | lined)

    def _splines(self, pos: np.ndarray, times: np.ndarray, wanted: np.ndarray) -> None:
        """Cubic spline through each marker's seen samples, written where ``wanted``."""
        for m in map(int, np.flatnonzero(wanted.any(axis=0))):
            seen = np.isfinite(pos[:, m, 0]) & ~wanted[:, m]
            if seen.sum() < 2:
                continue
            spline = CubicSpline(times[seen], pos[seen, m], axis=0)
            pos[wanted[:, m], m] = spline(times[wanted[:, m]])

    def _from_neighbours(self, pos: np.ndarray, times: np.ndarray, wanted: np.ndarray, rate: float,
                         apart: set[int]) -> None:
        """Fill each long gap from the markers seen through it, written into ``pos``.

        The predictors are the other markers seen throughout the gap; around it (``window_seconds``,
        at least the gap's length, on each side) the missing marker is ridge-regressed on them
        over the frames where all of them are seen; the regression's residual is
        bridged across the gap (:func:`_bridge`) and added to its prediction there.
        """
        frames, markers, dims = pos.shape
        seen_all = np.isfinite(pos).all(axis=2)  # kept current as gaps fill: a filled marker predicts too
        half = int(round(self.predictor_mean_seconds * rate))
        steady = _local_mean(pos, max(1, half)) if self.predictor_mean_seconds > 0 else pos  # what predictors say
        for m in map(int, np.flatnonzero(wanted.any(axis=0))):
            candidates = [k for k in range(markers) if (k in apart) == (m in apart)]
            for start, end in gap_runs(wanted[:, m]):
                pad = max(int(self.window_seconds * rate), end - start)
                lo, hi = max(0, start - pad), min(frames, end + pad)
                others, rows, own = _predictors(pos, seen_all, m, start, end, lo, hi, candidates)
                if len(own) < 8 and m in apart:
                    pos[start:end, m] = straight_line(pos[:, m], times, start, end)
                    seen_all[start:end, m] = np.isfinite(pos[start:end, m]).all(axis=1)
                    continue
                if len(own) < 8:
                    self._splines(pos, times, _only(wanted, start, end, m))
                    seen_all[start:end, m] = np.isfinite(pos[start:end, m]).all(axis=1)
                    continue
                near = pos[own][:, others] - pos[own, m][:, None]
                weight = np.exp(-np.mean(np.linalg.norm(near, axis=2), axis=0) ** 2 / (2 * self.sigma_mm ** 2))
                fit = np.isin(rows, own)
                low, high = self.blend_seconds
                ridge, share = self.ridge, float(np.clip((times[end - 1] - times[start] - low) / (high - low), 0, 1))
                edge = 1
                centre, x = _design(pos, rows, others, weight)
                if self.validate:  # the predictors as seen, or their local mean, whichever fills stand-ins better
                    best = np.inf
                    for source in (pos, steady) if steady is not pos else (pos,):
                        c, xs = (centre, x) if source is pos else _design(source, rows, others, weight)
                        error, params = _validate(xs[fit], pos[own, m] - c[fit], times[own], end - start, m in apart,
                                                  (ridge, share, edge))
                        if error < best:
                            best, (ridge, share, edge), centre, x = error, params, c, xs
                predicted = _ridge_predict(x, fit, pos[own, m] - centre[fit], ridge) + centre
                gap = np.isin(rows, np.arange(start, end))
                bridge = _bridge(pos[own, m] - predicted[fit], own, start, end, times, edge)
                regressed = predicted[gap] + bridge
                if share < 1.0:  # the marker's own line or spline about the centre, as _validate judged it
                    relative = pos[own, m] - centre[fit]
                    if m in apart:
                        spline = _bridge(relative, own, start, end, times)
                    else:
                        spline = CubicSpline(times[own], relative, axis=0)(times[start:end])
                    regressed = share * regressed + (1.0 - share) * (spline + centre[gap])
                pos[start:end, m] = steady[start:end, m] = regressed
                seen_all[start:end, m] = True


def _design(source: np.ndarray, rows: np.ndarray, others: list[int], weight: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """The centre of the predictors ``others`` at ``rows`` of ``source`` ``(F, M, D)``, ``(rows,
    D)``, and the regression's design about it, ``(rows, features)``, each predictor weighted by
    ``weight`` and every feature centred."""
    centre = source[rows][:, others].mean(axis=1)  # the frame moving with the subject
    x = ((source[rows][:, others] - centre[:, None]) * weight[None, :, None]).reshape(len(rows), -1)
    if len(others) < 4:  # a centre of so few is mostly the predictors: keep its motion too
        x = np.hstack([x, centre])
    return centre, x - x.mean(axis=0)


def _local_mean(pos: np.ndarray, half: int) -> np.ndarray:
    """Each sample of ``pos`` ``(F, M, D)`` as the mean of the seen samples within ``half``
    frames either side, where it is seen itself (NaN elsewhere).

    >>> _local_mean(np.array([1.0, 2.0, 6.0, np.nan, 4.0]).reshape(5, 1, 1), 1).ravel().tolist()
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


def _bridge(residual: np.ndarray, own: np.ndarray, start: int, end: int, times: np.ndarray, edge: int = 1
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


def _predictors(pos: np.ndarray, seen: np.ndarray, m: int, start: int, end: int, lo: int, hi: int,
                candidates: list[int]) -> tuple[list[int], np.ndarray, np.ndarray]:
    """Markers to predict marker ``m``'s gap ``[start, end)`` from, and the rows of ``[lo, hi)``
    where they are all seen (``rows``) and ``m`` too (``own``).

    Candidates (among ``candidates``) are the markers seen throughout the gap; while the rows
    where all are seen are too few for a regression (under 9 per predictor, or 60), the one
    that tells least about ``m`` (:func:`_relevance`) is dropped: the other brow, which moves
    with a missing one, stays; a marker that hardly moves with it goes first."""
    others = [k for k in candidates if k != m and seen[start:end, k].all()]
    window = seen[lo:hi]
    score = {k: _relevance(pos[lo:hi, m], pos[lo:hi, k], window[:, m] & window[:, k]) for k in others}
    others.sort(key=lambda k: score[k], reverse=True)
    while others:
        rows = np.flatnonzero(window[:, others].all(axis=1)) + lo
        own = rows[seen[rows, m]]
        if len(own) >= max(60, 9 * len(others)):
            return others, rows, own
        others.pop()
    return [], np.zeros(0, int), np.zeros(0, int)


def _relevance(target: np.ndarray, other: np.ndarray, both: np.ndarray) -> float:
    """The share of ``target``'s variance that ``other``'s position explains linearly (the R² of
    a least-squares fit, 0 with fewer than 10 frames) over the frames ``both`` sees them;
    positions ``(F, dims)``, ``both`` ``(F,)``."""
    if both.sum() < 10:
        return 0.0
    y = target[both] - target[both].mean(axis=0)
    x = other[both] - other[both].mean(axis=0)
    total = float((y * y).sum())
    if total <= 0:
        return 0.0
    coef, *_ = np.linalg.lstsq(x, y, rcond=None)
    residual = y - x @ coef
    return 1.0 - float((residual * residual).sum()) / total


def _only(mask: np.ndarray, start: int, end: int, marker: int) -> np.ndarray:
    out = np.zeros_like(mask)
    out[start:end, marker] = True
    return out


#: The ridge penalties :func:`_validate` chooses among, the shares of the regression (against the
#: marker's own spline) and the samples either side whose median a bridge starts and ends at
#: (:func:`_bridge`: one follows a smooth residual best, five carry less of a noisy one's jitter
#: and none of a spike beside the gap) it tries.
RIDGES = (0.003, 0.01, 0.03, 0.1)
#: Predictors may be read as their mean over this many seconds either side (one frame at 60 Hz),
#: where the stand-in gaps fill better so: a regression on noisy predictors shrinks their weights
#: (errors in variables; a lid filled from the other lid blinked two thirds as deep), while on
#: clean ones the mean only blurs a saccade or a step. The marker's own samples stay as seen.
PREDICTOR_MEAN_SECONDS = 0.0125
SHARES = (0.0, 0.25, 0.5, 0.75, 1.0)
EDGES = (1, 5)


def _validate(x: np.ndarray, y: np.ndarray, t: np.ndarray, length: int, straight: bool,
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
    moments = _Moments(x, y, blocks)
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


def _ridge_predict(x: np.ndarray, fit: np.ndarray, y: np.ndarray, ridge: float) -> np.ndarray:
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


class _Moments:
    """The sums a ridge regression of ``y`` ``(n, dims)`` on ``x`` ``(n, features)`` needs, over
    all rows less each block ``[lo, hi)`` of ``blocks``: taken once for the whole and once per
    block, so that each stand-in's fit costs a small solve instead of a pass over every row. The
    same fit as :func:`_ridge_predict` on the rows outside the block."""

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
