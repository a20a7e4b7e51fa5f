"""Settings of the cleaning stage, apart from the filters so that reading them imports no SciPy."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

#: The longest gap filled, seconds: offline (:class:`CleanSettings`, :class:`mapping.gaps.GapFiller`)
#: and live, where a lost marker is regressed on those seen (:mod:`mapping.live_gaps`).
MAX_GAP_SECONDS = 2.0
#: Live, how long a lost marker that is not regressed (a ``pair`` rule's: a brow, a lid, a pupil)
#: or a lost blendshape channel is held at its last value, seconds (:mod:`mapping.live_gaps`).
HOLD_SECONDS = 0.5


@dataclass(frozen=True)
class CleanSettings:
    """What cleaning does; each stage can be switched off.

    Attributes
    ----------
    spikes : bool
        Reject spikes (:class:`~mapping.outliers.SpikeFilter`) and undo label swaps of two
        neighbouring markers (:mod:`mapping.swaps`).
    max_gap_seconds : float
        Fill gaps up to this long (0: fill none).
    cutoff_hz : float
        Zero-phase Butterworth low-pass (0: no smoothing); capped below half the frame rate.
    holds : bool
        Smooth more where a marker holds still than where it moves (:mod:`mapping.holds`);
        off, every frame gets the ``cutoff_hz`` low-pass alike.
    progress : callable, optional
        Given the number of long gaps to fill, a callback given how many more were filled (gap
        filling is most of a long take's cleaning: minutes for an hour); not a setting, so not
        compared.
    """

    spikes: bool = True
    max_gap_seconds: float = MAX_GAP_SECONDS
    cutoff_hz: float = 8.0
    holds: bool = True
    progress: Callable[[int], Callable[[int], None]] | None = field(default=None, compare=False, repr=False)

    def max_gap_frames(self, rate: float) -> int:
        """The longest gap filled, in frames at ``rate`` Hz (a huge ``max_gap_seconds``, which
        overflowed, means every gap: none is longer than a day of frames)."""
        return int(round(min(self.max_gap_seconds, 86400.0) * rate))
