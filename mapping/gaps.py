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
on either side swung by many millimetres across the gap). A gap that a marker seen through part
of it could have told about is filled again once every gap has been filled once.

Gaps of at most ``spline_frames`` frames use a cubic spline through the marker's own samples
(never worse than a spline there, by construction); gaps longer than ``max_gap_seconds`` stay
NaN (never invented), and the caller lowers the marker's confidence there. A gap longer than
``spline_frames`` at the start or the end of the take (half a face turned away for the last
second) is regressed on the markers seen through it as a long gap is, with what the regression
misses held at its level beside the gap, blended with the marker's nearest sample held where its
own stand-in gaps say so (no spline or line reaches past an end); a shorter one, one with too few
frames to learn from, or one of a marker apart stays NaN.

Markers ``apart`` from the face (a marker set's ``independent`` ones: the pupils, whose gaze the
lips and brows do not foretell) are predicted only from each other, and never predict the rest;
where none of them is seen at any moment of a gap (both irises behind blinking lids) the gap is
bridged by a straight line, which neither dips with the lids nor overshoots as a spline through
them does; it runs between the medians of one or five samples either side, whichever the
marker's own stand-in gaps fill better (:func:`mapping.gap_fit.line_edge`). Where another is seen
through part of the gap, the gap is regressed on it as the face's are on theirs, once that one's
own gap has been bridged: the eyes move together, and a look that starts after one pupil is lost
and before the other is shows in the other (a straight line across held the lost one where it
was: on one take of the own bench performer a glance aside of half a second read as none,
fitted error 1.77 -> 1.30 %).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from mapping.gap_fit import (
    PREDICTOR_MEAN_SECONDS,
    bridge_residual,
    edge_level,
    line_edge,
    local_mean,
    nearness,
    regression_design,
    ridge_predict,
    straight_line,
    validate_gap,
)
from mapping.settings import MAX_GAP_SECONDS


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


#: The defaults of :class:`GapFiller` that a live fill (:mod:`mapping.live_gaps`) shares: the ridge
#: penalty without validation, the seconds learned from either side and the predictors' nearness
#: scale (mm); the longest gap filled is :data:`mapping.settings.MAX_GAP_SECONDS`.
RIDGE, WINDOW_SECONDS, SIGMA_MM = 3e-2, 10.0, 200.0


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
        Choose each gap's ridge penalty (:data:`mapping.gap_fit.RIDGES`) and its blend with the spline
        (:data:`mapping.gap_fit.SHARES`) on stand-in gaps cut from the marker's own seen frames
        (:func:`mapping.gap_fit.validate_gap`): a face's few tightly coupled markers and a body's many loosely
        coupled ones want different ones; and whether the predictors are read as seen or as
        their local mean (``predictor_mean_seconds``).
    predictor_mean_seconds : float, optional
        The half-width of that local mean (:data:`mapping.gap_fit.PREDICTOR_MEAN_SECONDS` by default; 0: the
        predictors as seen only).

    Long gaps are regressed about the centre of the markers that predict them (a body walks
    across the room; a face's markers move about their own), the centre's own motion kept as a
    predictor where fewer than four predict.
    """

    def __init__(self, spline_frames: int = 5, max_gap_seconds: float = MAX_GAP_SECONDS, ridge: float = RIDGE,
                 window_seconds: float = WINDOW_SECONDS, blend_seconds: tuple[float, float] = (0.1, 0.5),
                 sigma_mm: float = SIGMA_MM, validate: bool = True, predictor_mean_seconds: float | None = None
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

    def apply(self, positions: np.ndarray, times: np.ndarray, apart: Sequence[int] = (),
              progress: Callable[[int], Callable[[int], None]] | None = None) -> Filled:
        """Fill ``positions`` ``(frames, markers, dims)`` sampled at ``times`` ``(frames,)``;
        the markers (columns) ``apart`` are filled from each other or straight across (see the
        module docstring). ``progress``, given the number of long gaps, gives a callback told
        of each one filled."""
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
        lasting = missing & ~brief  # what a partner cannot be bridged across
        for m in range(markers):
            for start, end in gap_runs(missing[:, m]):
                at_edge = start == 0 or end == frames
                if end - start > max_frames or (at_edge and (m in apart or end - start == frames)):
                    continue  # too long, or a pupil with nothing on one side: left unseen
                if at_edge:  # the markers seen through it say where it went; no spline reaches past an end
                    long_[start:end, m] = end - start > self.spline_frames
                    continue
                if m in apart:  # another seen at some moment of the gap tells where this one went
                    partnered = any(k != m and not lasting[start:end, k].all() for k in apart)
                    (long_ if partnered and not brief[start, m] else lined)[start:end, m] = True
                    continue
                (short if end - start <= self.spline_frames else long_)[start:end, m] = True
        out = pos  # already this call's own copy
        for m in map(int, np.flatnonzero(lined.any(axis=0))):
            for start, end in gap_runs(lined[:, m]):
                out[start:end, m] = self._line(out, times, m, start, end, rate)
        if short.any():  # first, so that brief dropouts do not disqualify a marker as a predictor
            self._splines(out, times, short)
        if long_.any():
            self._from_neighbours(out, times, long_, rate, set(apart), progress)
        return Filled(out, (short | long_ | lined) & np.isfinite(out).all(axis=2))  # an end's gap may stay unseen

    def _line(self, pos: np.ndarray, times: np.ndarray, m: int, start: int, end: int, rate: float) -> np.ndarray:
        """Marker ``m``'s straight line across its gap ``[start, end)`` of ``pos`` ``(F, M, D)``:
        from the median of the samples before it to that of the samples after, as many as
        :func:`mapping.gap_fit.line_edge` finds best on the marker's own samples around it
        (:attr:`window_seconds`, at least the gap's length, either side); ``(end - start, D)``."""
        pad = max(int(self.window_seconds * rate), end - start)
        near = np.arange(max(0, start - pad), min(len(pos), end + pad))
        own = near[np.isfinite(pos[near, m]).all(axis=1)]
        edge = line_edge(pos[own, m], times[own], end - start)
        return bridge_residual(pos[own, m], own, start, end, times, edge)

    def _splines(self, pos: np.ndarray, times: np.ndarray, wanted: np.ndarray) -> None:
        """Cubic spline through each marker's seen samples, written where ``wanted``."""
        for m in map(int, np.flatnonzero(wanted.any(axis=0))):
            seen = np.isfinite(pos[:, m, 0]) & ~wanted[:, m]
            if seen.sum() < 2:
                continue
            spline = CubicSpline(times[seen], pos[seen, m], axis=0)
            pos[wanted[:, m], m] = spline(times[wanted[:, m]])

    def _from_neighbours(self, pos: np.ndarray, times: np.ndarray, wanted: np.ndarray, rate: float,
                         apart: set[int], progress: Callable[[int], Callable[[int], None]] | None = None) -> None:
        """Fill each long gap from the markers seen through it, written into ``pos``.

        The predictors are the other markers seen throughout the gap; around it (``window_seconds``,
        at least the gap's length, on each side) the missing marker is ridge-regressed on them
        over the frames where all of them are seen; the regression's residual is
        bridged across the gap (:func:`mapping.gap_fit.bridge_residual`) and added to its prediction there.

        A marker seen through only part of the gap cannot predict it (the other upper lid, lost
        when the gap starts, seen when both blink), yet its seen part holds what the gap lacks.
        So each gap that had such a marker is filled a second time, once every gap has been
        filled once and that marker has a position throughout: on the second performer a blink
        inside one lid's gap was lost this way (fitted error 1.50 -> 1.39 % over 5 seeds).
        """
        half = int(round(self.predictor_mean_seconds * rate))
        # what predictors say, read as their local mean: only ever chosen by validation
        steady = local_mean(pos, max(1, half)) if self.validate and self.predictor_mean_seconds > 0 else pos
        state = _Filling(pos, steady, np.isfinite(pos).all(axis=2), times, rate, apart)
        gaps = [(m, start, end) for m in map(int, np.flatnonzero(wanted.any(axis=0)))
                for start, end in gap_runs(wanted[:, m])]
        sources = (pos, steady) if steady is not pos else (pos,)
        again = []  # (gap, how its predictors were read) where one was seen through part of it
        told = progress(len(gaps)) if progress is not None else None
        for gap in gaps:
            source = self._fill(state, sources, *gap)
            if told is not None:
                told(1)
            if source is not None:
                again.append((gap, source))
        for (m, start, end), source in again:  # once more, now that every predictor has a position throughout
            state.forget(start, end, m)
            self._fill(state, (source,), m, start, end)

    def _fill(self, state: _Filling, sources: tuple[np.ndarray, ...], m: int, start: int, end: int
              ) -> np.ndarray | None:
        """Fill marker ``m``'s gap ``[start, end)`` (see :meth:`_from_neighbours`), written into
        ``state``, validation choosing among the predictors as read from ``sources``
        (``state.pos``, ``state.steady`` or both). Where a marker that could predict it was seen
        through part of the gap only (and so did not), the source it chose (``state.pos`` where
        it had no choice), for a second fill; None elsewhere."""
        pos, seen_all, times, rate, apart = state.pos, state.seen, state.times, state.rate, state.apart
        frames, markers, dims = pos.shape
        candidates = [k for k in range(markers) if (k in apart) == (m in apart)]
        pad = max(int(self.window_seconds * rate), end - start)
        lo, hi = max(0, start - pad), min(frames, end + pad)
        others, rows, own = predictors(pos, seen_all, m, start, end, lo, hi, candidates)
        during = seen_all[start:end, candidates]
        partly = bool((during.any(axis=0) & ~during.all(axis=0)).any())  # m itself is unseen throughout
        one_side = 1 if start == 0 else -1 if end == frames else 0  # a gap at an end: seen on one side
        if len(own) < 8:  # too few frames to learn from: its own line (apart) or spline
            if one_side:  # neither reaches past the take's end: left unseen
                return None
            if m in apart:
                pos[start:end, m] = straight_line(pos[:, m], times, start, end)
            else:
                self._splines(pos, times, _only(seen_all, start, end, m))
            state.filled(start, end, m)
            return pos if partly else None
        weight = nearness(pos[own, m], pos[own][:, others], self.sigma_mm)
        fit = np.isin(rows, own)
        low, high = self.blend_seconds
        ridge, share = self.ridge, float(np.clip((times[end - 1] - times[start] - low) / (high - low), 0, 1))
        edge = 1
        centre, x = regression_design(pos, rows, others, weight)
        chosen = pos
        if self.validate:  # the predictors as seen, or their local mean, whichever fills stand-ins better
            best = np.inf
            for source in sources:
                c, xs = (centre, x) if source is pos else regression_design(source, rows, others, weight)
                error, params = validate_gap(xs[fit], pos[own, m] - c[fit], times[own], end - start,
                                             m in apart, (ridge, share, edge), one_side)
                if error < best:
                    best, (ridge, share, edge), centre, x, chosen = error, params, c, xs, source
        predicted = ridge_predict(x, fit, pos[own, m] - centre[fit], ridge) + centre
        gap = np.isin(rows, np.arange(start, end))
        if one_side:  # what the regression misses, held at its level beside the gap
            bridge = edge_level(pos[own, m] - predicted[fit], one_side, edge)
        else:
            bridge = bridge_residual(pos[own, m] - predicted[fit], own, start, end, times, edge)
        regressed = predicted[gap] + bridge
        if share < 1.0:  # the marker's own line or spline about the centre, as validate_gap judged it
            relative = pos[own, m] - centre[fit]
            if one_side:  # its nearest sample, held: nothing reaches past the take's end
                spline = relative[-1 if one_side < 0 else 0]
            elif m in apart:
                spline = bridge_residual(relative, own, start, end, times)
            else:
                spline = CubicSpline(times[own], relative, axis=0)(times[start:end])
            regressed = share * regressed + (1.0 - share) * (spline + centre[gap])
        pos[start:end, m] = regressed
        state.filled(start, end, m)
        return chosen if partly else None


def predictors(pos: np.ndarray, seen: np.ndarray, m: int, start: int, end: int, lo: int, hi: int,
               candidates: list[int], most: int | None = None) -> tuple[list[int], np.ndarray, np.ndarray]:
    """Markers to predict marker ``m``'s gap ``[start, end)`` from, and the rows of ``[lo, hi)``
    where they are all seen (``rows``) and ``m`` too (``own``).

    Candidates (among ``candidates``) are the markers seen throughout the gap, at most ``most``
    of them (those that tell most about ``m``, :func:`_relevance`) where given; while the rows
    where all are seen are too few for a regression (under 9 per predictor, or 60), the one
    that tells least about ``m`` is dropped: the other brow, which moves with a missing one,
    stays; a marker that hardly moves with it goes first."""
    others = [k for k in candidates if k != m and seen[start:end, k].all()]
    window = seen[lo:hi]
    share = _relevance(pos[lo:hi, m], pos[lo:hi][:, others], window[:, [m]] & window[:, others])
    score = dict(zip(others, share.tolist(), strict=True))
    others.sort(key=lambda k: score[k], reverse=True)
    del others[len(others) if most is None else most:]
    while others:
        rows = np.flatnonzero(window[:, others].all(axis=1)) + lo
        own = rows[seen[rows, m]]
        if len(own) >= max(60, 9 * len(others)):
            return others, rows, own
        others.pop()
    return [], np.zeros(0, int), np.zeros(0, int)


def _relevance(target: np.ndarray, others: np.ndarray, both: np.ndarray) -> np.ndarray:
    """The share of ``target``'s variance that each of ``others``' positions explains linearly
    (the R² of a least-squares fit, 0 with fewer than 10 frames) over the frames ``both`` sees
    the two; positions ``target`` ``(F, dims)`` and ``others`` ``(F, K, dims)``, ``both``
    ``(F, K)``; ``(K,)``."""
    weight = both.astype(np.float64)  # (F, K)
    count = np.maximum(weight.sum(axis=0), 1.0)  # (K,)
    y = np.where(np.isfinite(target), target, 0.0)  # (F, dims): read only where weighted
    x = np.where(both[..., None], others, 0.0)  # (F, K, dims): 0 where unweighted, so sums run over both
    my = weight.T @ y / count[:, None]  # (K, dims): each pair's own means
    mx = x.sum(axis=0) / count[:, None]
    across = x.transpose(1, 2, 0)  # (K, dims, F)
    sxx = across @ x.transpose(1, 0, 2) - count[:, None, None] * mx[:, :, None] * mx[:, None, :]
    sxy = across @ y - count[:, None, None] * mx[:, :, None] * my[:, None, :]
    total = weight.T @ (y * y).sum(axis=1) - count * (my * my).sum(axis=1)
    explained = np.einsum("kij,kij->k", sxy, np.linalg.pinv(sxx, hermitian=True) @ sxy)
    share = np.where(total > 0, explained / np.where(total > 0, total, 1.0), 0.0)
    return np.where(both.sum(axis=0) >= 10, share, 0.0)


@dataclass(frozen=True, eq=False)
class _Filling:
    """The long gaps of one :meth:`GapFiller.apply` being filled: what each fill reads and writes.

    Attributes
    ----------
    pos : ndarray, shape (frames, markers, dims)
        The positions, filled in place.
    steady : ndarray, shape (frames, markers, dims)
        The predictors as their local mean (``pos`` itself where they are not read so).
    seen : ndarray of bool, shape (frames, markers)
        Where a marker has a position, kept current as gaps fill: a filled marker predicts too.
    times : ndarray, shape (frames,)
    rate : float
    apart : set of int
        The markers filled only from each other.
    """

    pos: np.ndarray
    steady: np.ndarray
    seen: np.ndarray
    times: np.ndarray
    rate: float
    apart: set[int]

    def filled(self, start: int, end: int, m: int) -> None:
        """Marker ``m``'s gap ``[start, end)`` just filled in ``pos``: what it predicts later
        gaps from as seen (``seen``) and as read (``steady``: the filled samples as they are),
        wherever the fill gave a position."""
        if self.steady is not self.pos:
            self.steady[start:end, m] = self.pos[start:end, m]
        self.seen[start:end, m] = np.isfinite(self.pos[start:end, m]).all(axis=1)

    def forget(self, start: int, end: int, m: int) -> None:
        """Marker ``m``'s gap ``[start, end)`` unfilled again, to be filled once more."""
        self.pos[start:end, m] = np.nan
        self.seen[start:end, m] = False
        if self.steady is not self.pos:
            self.steady[start:end, m] = np.nan


def _only(mask: np.ndarray, start: int, end: int, marker: int) -> np.ndarray:
    out = np.zeros_like(mask)
    out[start:end, marker] = True
    return out
