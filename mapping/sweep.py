"""What a range-of-motion sweep did not show: ranges taken from samples actually seen, and a
side lost to a dropout taken from the mirror motor's.

Markers drop out most at a face's extremes (a lid marker hidden by the fold of a raised brow,
a lip marker swallowed by a wide mouth), which are what a range-of-motion sweep is for. Gap
filling guesses those samples, and a guess reaches less far than the face did (regressing on
other markers shrinks toward their mean), so a range taken over filled samples comes out short
on that side and the motor later overshoots there. A calibration therefore takes its ranges
from seen samples only (:func:`seen_only`). Where a source was unseen for most of the frames in
which its mirror source (the same source of the mirror motor's rule, ``toon.MIRROR_PAIRS``)
held that side's extreme, and so reached less far, that side takes the mirror's reach from rest
(:func:`mirror_lost_sides`): a sweep moves both sides of the face together, and a face is
closer to symmetric than a guess is to the truth.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mapping.mapfile import Mapping
from mapping.profile import Profile, SourceRange
from mapping.sources import Source
from mapping.stabilise import Stabilised
from toon.motors import MIRROR_PAIRS

#: A mirror source this far along its way to one end (a share of that side's reach) holds it.
HELD = 0.9
#: The least such frames, and the share of them the source must have been unseen in, before
#: its side is taken from the mirror.
MIN_FRAMES = 10
LOST_SHARE = 0.5


def seen_only(stable: Stabilised) -> Stabilised:
    """``stable`` with the samples gap filling made up set unseen (NaN), to measure ranges on."""
    if stable.filled is None or not stable.filled.any():
        return stable
    return replace(stable, local=np.where(stable.filled[..., None], np.nan, stable.local))


def mirror_lost_sides(mapping: Mapping, profile: Profile, stable: Stabilised, columns: dict[str, int],
                      frames: np.ndarray) -> tuple[Profile, list[str]]:
    """``profile`` with each side a source lost while its mirror held it taken from the mirror
    (see the module docstring), and the changed sides (``"KEY low"``/``"KEY high"``) for its notes.

    Parameters
    ----------
    stable : Stabilised
        The range take, cleaned (``filled`` says which samples were made up).
    columns : dict
        Marker-set label -> column of ``stable.local``.
    frames : ndarray of bool, shape (F,)
        The range frames.
    """
    rules = {rule.code: rule for rule in mapping.rules}
    made_up = stable.filled if stable.filled is not None else np.zeros(stable.local.shape[:2], bool)
    sources = dict(profile.sources)
    changed: list[str] = []
    for a_code, b_code in (*MIRROR_PAIRS, *((b, a) for a, b in MIRROR_PAIRS)):
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
                                    made_up, frames)
                if reach is not None:
                    r = sources[a.key]
                    sources[a.key] = (SourceRange(r.neutral, r.low, r.neutral + reach) if a_high
                                      else SourceRange(r.neutral, r.neutral - reach, r.high))
                    changed.append(f"{a.key} {'high' if a_high else 'low'}")
    return replace(profile, sources=sources), changed


def _lost_reach(a_range: SourceRange, b_range: SourceRange, a: Source, b: Source, a_high: bool, b_high: bool,
                stable: Stabilised, columns: dict[str, int], made_up: np.ndarray, frames: np.ndarray
                ) -> float | None:
    """The mirror's reach from rest on its side (mm), where source ``a`` lost that side while
    ``b`` held it and reached less far; None otherwise."""
    a_reach = a_range.high - a_range.neutral if a_high else a_range.neutral - a_range.low
    b_reach = b_range.high - b_range.neutral if b_high else b_range.neutral - b_range.low
    if b_reach <= a_reach:
        return None
    b_col, a_col = columns[b.markers[0]], columns[a.markers[0]]
    value = stable.local[:, b_col, b.axis]
    along = (value - b_range.neutral) * (1.0 if b_high else -1.0)
    held = frames & ~made_up[:, b_col] & np.isfinite(value) & (along >= HELD * b_reach)
    if held.sum() < MIN_FRAMES:
        return None
    lost = made_up[held, a_col] | ~np.isfinite(stable.local[held, a_col, a.axis])
    return float(b_reach) if lost.mean() > LOST_SHARE else None
