"""Performer ranges learned while a live take runs, as face-tracking apps do (OpenSeeFace).

A live source with no profile (a camera, a video played as one) cannot be calibrated ahead. Its
rest comes from the first still second (:class:`mapping.stepwise.LiveMapper`); each source's
range then starts ``min_side`` either side of that rest, widens at once to every value beyond
it, and eases back toward its starting span by a share of the excess each second, so that one
wild frame does not set the range for good. After ``freeze_after`` seconds the ranges stop
changing: the performer has shown their range, and the motors stop drifting with it. The
learned ranges are an ordinary :class:`~mapping.profile.Profile`, saved and reused next time.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from mapping.profile import Profile, SourceRange
from mapping.sources import mm_scale


@dataclass
class RangeLearner:
    """Ranges of ``profile``'s sources learned frame by frame (see the module docstring).

    Attributes
    ----------
    profile : Profile
        Its ranges' rests are kept; its lows and highs are learned.
    min_side : float
        Starting span either side of rest, mm or degrees (scaled for blendshape scores by
        :func:`~mapping.sources.mm_scale`).
    decay_seconds : float
        Time constant of the ease back toward the starting span.
    freeze_after : float
        Seconds of learning, from the first update.
    """

    profile: Profile
    min_side: float = 4.0
    decay_seconds: float = 20.0
    freeze_after: float = 60.0
    _start: float | None = field(default=None, init=False)
    _last: float | None = field(default=None, init=False)

    def __post_init__(self) -> None:
        sources = {key: SourceRange(span.neutral, min(span.low, span.neutral - self._side(key)),
                                    max(span.high, span.neutral + self._side(key)))
                   for key, span in self.profile.sources.items()}
        self.profile = replace(self.profile, sources=sources,
                               notes={**self.profile.notes, "range": f"learned live over {self.freeze_after:g} s"})

    def _side(self, key: str) -> float:
        return self.min_side * mm_scale(key)

    @property
    def frozen(self) -> bool:
        """Whether learning has ended."""
        return self._start is not None and self._last is not None and self._last - self._start >= self.freeze_after

    def update(self, values: dict[str, float], t: float) -> Profile:
        """Widen or ease each range with this frame's source ``values`` (NaN: not seen) at ``t``
        seconds; returns the profile as it now stands."""
        if self.frozen:
            return self.profile
        self._start = t if self._start is None else self._start
        dt = 0.0 if self._last is None else max(t - self._last, 0.0)
        self._last = t
        ease = min(dt / self.decay_seconds, 1.0)
        for key, value in values.items():
            span = self.profile.sources.get(key)
            if span is None or value != value:  # NaN
                continue
            side = self._side(key)
            floor_low, floor_high = span.neutral - side, span.neutral + side
            high = max(value, floor_high + (span.high - floor_high) * (1.0 - ease))  # spans start at the floor
            low = min(value, floor_low + (span.low - floor_low) * (1.0 - ease))
            self.profile.sources[key] = SourceRange(span.neutral, low, high)
        return self.profile
