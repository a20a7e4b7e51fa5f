"""What a range-of-motion sweep did not show: a side a source lost to a dropout, taken from
the mirror motor's.

Markers drop out most at a face's extremes (a lid marker hidden by the fold of a raised brow,
a lip marker swallowed by a wide mouth), which are what a range-of-motion sweep is for. Gap
filling guesses those samples. The profile takes a guess that reaches further than the seen
samples (:func:`mapping.profile.build_profile`), but a guess can miss either way: one from
loosely coupled markers falls short (regressing on other markers shrinks toward their mean),
and one overshot the second performer's upper lid by a quarter of its 1.9 mm. Where a source
was unseen for most of the frames in which its mirror source (the same source of the mirror
motor's rule, ``toon.MIRROR_PAIRS``) held that side's end in view, and its own seen samples
reach less far than the mirror's do, that side takes the mirror's seen reach from rest
(:func:`mirror_lost_sides`), whatever the guesses said: a sweep moves both sides of the face
together, and a face is closer to symmetric than a guess is to the truth. A mirror whose end
was itself guessed (its range reaching further than it was seen) did not hold it in view.
Otherwise the range stays as measured (taking the mirror's reach wherever a side was lost cost
more on the project's own performer, whose both lids drop out in its sweep, than it gained).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mapping.mapfile import Mapping
from mapping.plan import span_of
from mapping.profile import Profile, SourceRange
from mapping.sources import Source
from mapping.stabilise import Stabilised
from toon.motors import MIRROR_OF

#: A mirror source this far along its way to one end (a share of that side's reach) holds it.
HELD = 0.9
#: The least such frames (a held extreme of a quick sweep lasts a few), and the share of them
#: the source must have been unseen in, before its side is taken from the mirror.
MIN_FRAMES = 5
LOST_SHARE = 0.5


def mirror_lost_sides(mapping: Mapping, profile: Profile, stable: Stabilised, columns: dict[str, int],
                      frames: np.ndarray, percentiles: tuple[float, float]) -> tuple[Profile, list[str]]:
    """``profile`` with each side a source lost while its mirror held it taken from the mirror
    (see the module docstring), and the changed sides (``"KEY low"``/``"KEY high"``) for its notes.

    Parameters
    ----------
    profile : Profile
        Ranges measured over the range frames (seen samples, and gap filling's guesses where they
        reach further: :func:`mapping.profile.build_profile`).
    stable : Stabilised
        The range take, cleaned (``filled`` says which samples were made up).
    columns : dict
        Marker-set label -> column of ``stable.local``.
    frames : ndarray of bool, shape (F,)
        The range frames.
    percentiles : tuple of float
        The profile's: a mirror's seen reach is the same percentile of its seen samples.
    """
    rules = {rule.code: rule for rule in mapping.rules}
    made_up = stable.filled if stable.filled is not None else np.zeros(stable.local.shape[:2], bool)
    sources = dict(profile.sources)
    changed: list[str] = []
    for a_code, b_code in MIRROR_OF.items():
        if a_code not in rules or b_code not in rules:
            continue
        a_rule, b_rule = rules[a_code], rules[b_code]
        for a, b in zip(a_rule.sources, b_rule.sources, strict=False):
            if a.kind != "marker" or b.kind != "marker" or a.key not in sources or b.key not in sources:
                continue
            for up in (False, True):  # the motor's way down, then up
                a_high = up != (a.invert != a_rule.invert)
                b_high = up != (b.invert != b_rule.invert)
                reach = _lost_reach(sources[a.key], sources[b.key], a, b, a_high, b_high, stable, columns,
                                    made_up, frames & stable.ok, percentiles)
                if reach is not None:
                    r = sources[a.key]
                    sources[a.key] = (SourceRange(r.neutral, r.low, r.neutral + reach) if a_high
                                      else SourceRange(r.neutral, r.neutral - reach, r.high))
                    changed.append(f"{a.key} {'high' if a_high else 'low'}")
    return replace(profile, sources=sources), changed


def _lost_reach(a_range: SourceRange, b_range: SourceRange, a: Source, b: Source, a_high: bool, b_high: bool,
                stable: Stabilised, columns: dict[str, int], made_up: np.ndarray, frames: np.ndarray,
                percentiles: tuple[float, float]) -> float | None:
    """The mirror's seen reach from rest on its side (mm), where source ``a`` lost that side
    while ``b`` held it in view and ``a``'s seen samples reach less far; None otherwise. ``b``
    holds the end of its range as measured (:func:`mapping.profile.build_profile`): where gap
    filling's guesses took that further than ``b`` was seen, ``b`` lost the end too, and its
    seen reach says nothing of it."""
    b_value, b_seen = _seen(stable, made_up, frames, columns[b.markers[0]], b.axis)
    if b_seen.sum() < MIN_FRAMES:
        return None
    b_reach = _seen_reach(b_value[b_seen], b_range.neutral, b_high, percentiles)
    a_value, a_seen = _seen(stable, made_up, frames, columns[a.markers[0]], a.axis)
    a_reach = _seen_reach(a_value[a_seen], a_range.neutral, a_high, percentiles) if a_seen.any() else 0.0
    if b_reach <= a_reach:
        return None
    _, above, below = span_of(b_range)
    held = b_seen & ((b_value - b_range.neutral) * (1.0 if b_high else -1.0) >= HELD * (above if b_high else below))
    if held.sum() < MIN_FRAMES:
        return None
    return b_reach if (~a_seen[held]).mean() > LOST_SHARE else None  # held frames are range frames


def _seen(stable: Stabilised, made_up: np.ndarray, frames: np.ndarray, column: int, axis: int
          ) -> tuple[np.ndarray, np.ndarray]:
    """A marker axis's values ``(F,)`` and which of ``frames`` saw them, ``(F,)`` bool (not
    guessed, not NaN)."""
    value = stable.local[:, column, axis]
    return value, frames & ~made_up[:, column] & np.isfinite(value)


def _seen_reach(values: np.ndarray, neutral: float, high: bool, percentiles: tuple[float, float]) -> float:
    """How far ``values`` (a source's seen samples) reach from ``neutral`` toward its high or low
    end: the profile's percentile of them."""
    end = float(np.percentile(values, percentiles[1] if high else percentiles[0]))
    return (end - neutral) * (1.0 if high else -1.0)
