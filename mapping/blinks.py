"""The blinks a take shows: where an upper lid shuts, so that a range made on the take keeps it shut.

A lid marker's travel in a blink is the performer's own closed lid: 2-5 mm on a real face whose
markers sit on the lid's edge, where a typical face's range says 10. A profile widened to a
typical face's range turns every blink into a squint (issue 69), so where a take shows blinks,
its lids' closing side is the blinks' depth instead (:func:`mapping.typical.bound_by_typical`).

A blink is a brief excursion towards closing and back: the lid's distance from its own running
median (over :data:`BASELINE_SECONDS`) rises above :data:`DEPTH_SIGMAS` times its robust spread
and falls back within :data:`LONGEST_SECONDS` (a squint, a held expression or a sleepy lid lasts
longer and is left to the typical range), and at least :data:`LEAST_MM` deep. Half blinks
(shallower than :data:`FULL_SHARE` of the median blink's depth) do not count; the shallowest full
blink sets the closed lid, so that every full blink the take shows shuts the cartoon's eye.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import median_filter

#: The running median the lid's excursions are measured from.
BASELINE_SECONDS = 1.0
#: A blink's trough is at least this many robust standard deviations from the baseline.
DEPTH_SIGMAS = 5.0
#: A blink is back (below half its depth) within this time.
LONGEST_SECONDS = 0.5
#: Blinks shallower than this share of the median blink's depth are half blinks.
FULL_SHARE = 0.6
#: Fewer blinks than this are not a clear sign of where the lid shuts.
FEWEST = 2
#: A blink moves its lid's marker at least this far (mm): a marker on the lid's edge travels 2-5 mm
#: (the jaw take's shallowest blink 1.6). On a clean marker the robust sigmas alone counted wiggles
#: of 0.03-0.2 mm as blinks (the third performer: 16 of 22), and the shallowest left the lid no
#: closing side at all (shut 38 % of the take).
LEAST_MM = 1.0


@dataclass(frozen=True)
class Blinks:
    """The full blinks of one lid.

    Attributes
    ----------
    frames : tuple of int
        Each full blink's deepest frame.
    closed : float
        The lid's closed value (the source's own units): the shallowest full blink's trough.
    """

    frames: tuple[int, ...]
    closed: float


def find_blinks(values: np.ndarray, rate: float, closing: float = -1.0, least: float = LEAST_MM) -> Blinks | None:
    """The full blinks in a lid's ``values`` ``(frames,)`` (mm, NaN where unseen) sampled at
    ``rate`` Hz, ``closing`` -1 where the lid's value falls as it shuts (+1 where it rises); None
    where fewer than :data:`FEWEST` show (see the module docstring). A blink's trough is also at
    least ``least`` from the baseline (:data:`LEAST_MM`; another value for other units).

    >>> t = np.arange(600) / 60.0
    >>> lid = 0.05 * np.sin(7 * t) - 3.0 * (np.abs(t[:, None] - [2.0, 6.0, 8.0]).min(axis=1) < 0.06)
    >>> found = find_blinks(lid, 60.0)
    >>> found.frames, round(found.closed, 2)
    ((117, 363, 477), -2.96)
    """
    seen = np.isfinite(values)
    if seen.sum() < rate:
        return None
    frames = np.flatnonzero(seen)
    level = np.interp(np.arange(len(values)), frames, values[frames])  # unseen frames bridged, not judged
    away = closing * (level - median_filter(level, size=max(3, int(BASELINE_SECONDS * rate) | 1), mode="nearest"))
    spread = 1.4826 * float(np.median(np.abs(away - np.median(away))))  # 0 on a lid still between blinks
    threshold = max(DEPTH_SIGMAS * spread, least)
    if threshold <= 0:
        return None
    high = np.concatenate([[False], away > threshold / 2, [False]])
    edges = np.flatnonzero(np.diff(high.astype(np.int8)))
    troughs = []
    for start, end in zip(edges[::2], edges[1::2], strict=True):
        deepest = start + int(np.argmax(away[start:end]))
        if (away[deepest] >= threshold and end - start <= LONGEST_SECONDS * rate and seen[deepest]
                and start > 0 and end < len(values)):  # back on both sides within the take
            troughs.append(deepest)
    if len(troughs) < FEWEST:
        return None
    depth = away[troughs]
    full = [f for f, d in zip(troughs, depth, strict=True) if d >= FULL_SHARE * np.median(depth)]
    if len(full) < FEWEST:
        return None
    closed = values[full]
    return Blinks(tuple(int(f) for f in full), float(closed.max() if closing < 0 else closed.min()))
