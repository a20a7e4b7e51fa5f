"""Live gap filling: a lost marker regressed on the markers seen now, learned on the last seconds.

Offline, a long gap is filled from the markers seen through it (:mod:`mapping.gaps`); live, the
future is not there, and a lost marker used to be held where it was last seen for half a second,
then lost: a mouth corner hidden for a second read as still, then as lost. Here, as offline
at a take's end (a gap seen on one side only), a lost marker is ridge-regressed on markers seen
now, about their centre and each weighted by nearness (:func:`mapping.gap_fit.regression_design`'s
features), learned over the last :data:`WINDOW_SECONDS` of head-frame frames where all of them and
the marker were seen; what the regression missed on the marker's last seen samples (the median of
:data:`EDGE`) is held across the gap (:func:`mapping.gap_fit.edge_level`). The predictors are those
that tell most about the marker (:func:`mapping.gaps.predictors`, at most :data:`MOST`), and are
fitted once a gap, again only where one of them is lost in turn for longer than
:data:`BRIEF_SECONDS` (a predictor lost that briefly, a spike taken out, is read where it was last
seen). A marker lost again within :data:`REUSE_SECONDS` of its last fit reuses it, its miss
measured afresh on its last seen samples.

A marker that a ``pair`` rule reads (:class:`mapping.rules.MotorRules`: a brow, a lid, a pupil) is
only held, as before: once lost, its motor follows the other side's, which was nearer the truth
than a regression that had not seen the move (a brow raised by 9 mm filled as 2.5). Markers
``apart`` (the pupils) would be predicted only from each other. A marker unseen for longer than
:data:`REGRESS_SECONDS` (offline's longest fill), or held longer than the hold, is lost.

Chosen on the fourth bench performer's choice seeds 31-34, live fitted error after the sweep:
held, 2.71, 3.00, 5.05, 2.99 %; every lost marker regressed on all those seen, 3.00, 2.89, 5.11,
3.17 (the mouth better, the brows and lower lids worse); the markers no ``pair`` rule reads, on
all, 2.77, 2.96, 5.00, 2.95 (a mouth corner worse on 31); on the eight that tell most, 2.60,
2.96, 5.00, 2.95 (four: 2.61, 2.96, 5.00). Then on the bench's seeds 1-5: 2.80, 2.94, 3.48, 2.78,
3.24 -> 2.79, 2.89, 3.43, 2.56, 3.14; the other three performers' first seeds 2.86 -> 2.79,
3.55 -> 3.42, 4.02 -> 3.73. A fit costs about 3.5 ms (a 120 Hz frame's mapping about 4): the
slowest frame of a fourth-performer take, where several markers were lost at once, took 26 ms
against 13. Fits were made 268 times in that take's 2400 frames (seed 3, on 143 of them), 145 of
them again because a predictor dropped out for a frame or two; reusing a recent fit and reading
a briefly lost predictor where it was last seen, 167 times. Every frame of seeds 1-5 timed, two
runs each way: the 99th percentile 14.7, 13.6 -> 9.6, 8.5 ms, frames slower than the 8.3 ms
frame interval 4.3, 3.0 -> 1.5, 1.1 % (``fidelity.fourth_live_step_p99_ms``); the live fitted
error the same (``fidelity.fourth_live_fitted_pct`` 2.964 -> 2.965; choice seeds 31, 32, 34:
2.605, 2.960, 2.949 -> 2.605, 2.960, 2.949; the other performers' seed 31: 3.62 -> 3.55, 4.33 ->
4.33, 2.79 -> 2.79).
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass, replace

import numpy as np

from mapping.gap_fit import edge_level, features, nearness, ridge_fit
from mapping.gaps import RIDGE, SIGMA_MM, WINDOW_SECONDS, predictors
from mapping.settings import HOLD_SECONDS, MAX_GAP_SECONDS

#: The longest a marker is regressed, seconds (offline's longest fill). Offline's window either
#: side of a gap is the seconds of past frames a fill learns from, and its ridge penalty without
#: validation and nearness scale are the fill's (:mod:`mapping.gaps`).
REGRESS_SECONDS = MAX_GAP_SECONDS
#: The last seen samples whose median miss is held across the gap.
EDGE = 5
#: The most predictors a fill uses: those that tell most about the lost marker.
MOST = 8
#: A marker lost again within this many seconds of its last fit, its predictors all seen, reuses
#: that fit (its miss measured afresh): the window has moved by a tenth at most.
REUSE_SECONDS = 1.0
#: A predictor lost for at most this long (a spike taken out, a frame's dropout) is read where it
#: was last seen, not fitted around.
BRIEF_SECONDS = 0.025


@dataclass(frozen=True)
class _Fit:
    """One lost marker's regression: its predictors, their features' mean ``(f,)``, the weights
    ``(f, 3)``, the target's mean about the predictors' centre ``(3,)``, the nearness weights
    ``(P,)`` and the miss held across the gap ``(3,)``."""

    others: list[int]
    mean_x: np.ndarray
    coef: np.ndarray
    mean_y: np.ndarray
    weight: np.ndarray
    miss: np.ndarray

    def predict(self, local: np.ndarray) -> np.ndarray:
        """The marker in this frame's head-frame markers ``local`` ``(M, 3)``: ``(3,)``."""
        return self.regressed(local[None])[0] + self.miss

    def regressed(self, frames: np.ndarray) -> np.ndarray:
        """What the regression alone says of the marker in head-frame markers ``frames``
        ``(n, M, 3)``, without the miss: ``(n, 3)``."""
        centre, x = features(frames[:, self.others], self.weight)  # a copy: indexed by a list
        return (x - self.mean_x) @ self.coef + self.mean_y + centre

    def with_miss(self, past: np.ndarray, known: np.ndarray, m: int) -> _Fit | None:
        """This fit for marker ``m`` with the miss held across its gap: what the regression
        missed on the last :data:`EDGE` samples of ``m`` seen with every predictor in the frames
        kept ``past`` ``(n, M, 3)`` (``known`` ``(n, M)``: where each was seen), the median; None
        where there are none. A new fit's, and a reused one's measured afresh."""
        rows = np.flatnonzero(known[:, m] & known[:, self.others].all(axis=1))[-EDGE:]
        if not len(rows):
            return None
        return replace(self, miss=edge_level(past[rows, m] - self.regressed(past[rows]), -1, EDGE))


class LiveGapFiller:
    """Fill lost head-frame markers frame by frame (see the module docstring).

    Parameters
    ----------
    markers : int
        Markers per frame.
    rate : float
        Frames per second.
    regressed : collection of int
        The markers (columns) regressed when lost; the others are only held.
    hold_seconds : float
        How long a marker not regressed (or with nothing to regress on) is held.
    regress_seconds : float
        How long a regressed marker is filled (0: none is, all are held).
    apart : sequence of int
        Markers predicted only from each other.
    """

    def __init__(self, markers: int, rate: float, regressed: Collection[int], hold_seconds: float = HOLD_SECONDS,
                 regress_seconds: float = REGRESS_SECONDS, apart: Sequence[int] = ()) -> None:
        self.rows = max(int(round(WINDOW_SECONDS * rate)), 2)
        self.regressed, self.apart = frozenset(regressed), frozenset(apart)
        self.hold_seconds, self.regress_seconds = hold_seconds, regress_seconds
        self.markers = markers
        self.reset()

    def reset(self) -> None:
        """Forget every frame (the head frame changed: what was learned is in the old one)."""
        self._past = np.full((self.rows, self.markers, 3), np.nan)  # a ring of the last frames
        self._count = 0
        self._last = np.full((self.markers, 3), np.nan)
        self._seen_at = np.full(self.markers, -np.inf)
        self._fits: dict[int, _Fit | None] = {}
        self._recent: dict[int, tuple[float, _Fit]] = {}  # each marker's last fit, and when

    def step(self, local: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """This frame's head-frame markers ``(M, 3)`` (NaN: lost) at ``t`` seconds with the lost
        ones filled where they may be, ``(M, 3)``, and which were, ``(M,)``."""
        seen = np.isfinite(local).all(axis=1)
        self._past[self._count % self.rows] = local
        self._count += 1
        self._last[seen], self._seen_at[seen] = local[seen], t
        for m in [m for m in self._fits if seen[m]]:
            del self._fits[m]
        out, filled = local.copy(), np.zeros(len(local), dtype=bool)
        since = t - self._seen_at
        usable = since <= BRIEF_SECONDS  # a predictor lost this briefly is read where it was last seen
        reading: np.ndarray | None = None  # the frame with those, made once a frame where a fit reads it
        window: tuple[np.ndarray, np.ndarray] | None = None  # the frames kept, gathered once a frame
        for m in map(int, np.flatnonzero(~seen & (since <= max(self.hold_seconds, self.regress_seconds)))):
            fit = None
            if m in self.regressed and since[m] <= self.regress_seconds:
                known = self._fits.get(m)
                if m not in self._fits or (known is not None and not usable[known.others].all()):
                    window = window or self._window()
                    self._fits[m] = self._refit(m, seen, usable, t, *window)  # (None: nothing to learn from)
                fit = self._fits[m]
            if fit is not None:
                reading = np.where(seen[:, None], local, self._last) if reading is None else reading
                out[m] = fit.predict(reading)
            elif since[m] <= self.hold_seconds:
                out[m] = self._last[m]
            filled[m] = np.isfinite(out[m]).all()
        return out, filled

    def _window(self) -> tuple[np.ndarray, np.ndarray]:
        """The frames kept, oldest first, ``(n, M, 3)``, and where each marker was seen, ``(n, M)``."""
        kept = min(self._count, self.rows)
        past = self._past[np.arange(self._count - kept, self._count) % self.rows]
        return past, np.isfinite(past).all(axis=2)

    def _refit(self, m: int, seen: np.ndarray, usable: np.ndarray, t: float, past: np.ndarray, known: np.ndarray
               ) -> _Fit | None:
        """Marker ``m``'s fit at ``t``: its last one where that was made within
        :data:`REUSE_SECONDS` and every predictor of it is ``usable`` now (its miss measured
        afresh), a new one on those ``seen`` (:meth:`_fit`) otherwise."""
        recent = self._recent.get(m)
        if recent is not None and t - recent[0] <= REUSE_SECONDS and usable[recent[1].others].all():
            again = recent[1].with_miss(past, known, m)
            if again is not None:
                return again
        fit = self._fit(m, seen, past, known)
        if fit is not None:
            self._recent[m] = (t, fit)
        return fit

    def _fit(self, m: int, seen: np.ndarray, past: np.ndarray, known: np.ndarray) -> _Fit | None:
        """Marker ``m``'s regression on the markers ``seen`` now, over the frames kept ``past``
        (:meth:`_window`; None where they are too few: under 60, or 9 per predictor)."""
        kept = len(past)
        candidates = [k for k in range(self.markers) if seen[k] and (k in self.apart) == (m in self.apart)]
        others, _, own = predictors(past, known, m, kept - 1, kept, 0, kept, candidates, MOST)
        if not others:
            return None
        weight = nearness(past[own, m], past[own][:, others], SIGMA_MM)
        centre, x = features(past[own][:, others], weight)
        target = past[own, m] - centre
        mean_x, coef, mean_y = ridge_fit(x, target, RIDGE)
        return _Fit(others, mean_x, coef, mean_y, weight, np.zeros(3)).with_miss(past, known, m)
