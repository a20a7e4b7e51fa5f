"""Clean a take offline: spikes out, gaps filled, trajectories smoothed.

The order matters: spikes first (a spike would pull the fill and the smoothing), then gaps
(filled from both sides and from the other markers), then zero-phase smoothing, which has no
lag because it may look ahead. Samples left unseen (gaps too long to fill) stay NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture import Take
from mapping.filters import Butterworth
from mapping.gaps import GapFiller
from mapping.outliers import SpikeFilter


@dataclass(frozen=True)
class CleanSettings:
    """What :func:`clean_take` does; each stage can be switched off.

    Attributes
    ----------
    spikes : bool
        Reject one-frame spikes (:class:`~mapping.outliers.SpikeFilter`).
    max_gap_seconds : float
        Fill gaps up to this long (0: fill none).
    cutoff_hz : float
        Zero-phase Butterworth low-pass (0: no smoothing); capped below half the frame rate.
    """

    spikes: bool = True
    max_gap_seconds: float = 2.0
    cutoff_hz: float = 8.0


@dataclass(frozen=True, eq=False)
class CleanReport:
    """What cleaning did: counts of marker-samples ``rejected``, ``filled`` and ``still_missing``."""

    rejected: int
    filled: int
    still_missing: int


def clean_take(take: Take, settings: CleanSettings = CleanSettings()) -> tuple[Take, CleanReport]:
    """The cleaned take (same labels, rate and times) and a report of what changed."""
    pos = take.positions.copy()
    before = np.isnan(pos).any(axis=2)
    if settings.spikes:
        pos = SpikeFilter().apply(pos, take.times)
    rejected = int((np.isnan(pos).any(axis=2) & ~before).sum())
    filled = 0
    if settings.max_gap_seconds > 0 and take.frames > 1:
        result = GapFiller(max_gap_seconds=settings.max_gap_seconds).apply(pos, take.times)
        pos, filled = result.positions, int(result.filled.sum())
    if settings.cutoff_hz > 0 and take.frames > 1:
        cutoff = min(settings.cutoff_hz, 0.45 * take.rate)
        flat = pos.reshape(take.frames, -1)
        pos = Butterworth(cutoff, take.rate).smooth_offline(flat).reshape(pos.shape)
    meta = {**take.meta, "cleaned": {"spikes": settings.spikes, "max_gap_seconds": settings.max_gap_seconds,
                                     "cutoff_hz": settings.cutoff_hz, "rejected": rejected, "filled": filled}}
    cleaned = Take(pos, take.labels, take.rate, times=take.times, dims=take.dims, meta=meta)
    return cleaned, CleanReport(rejected, filled, int(np.isnan(pos).any(axis=2).sum()))
