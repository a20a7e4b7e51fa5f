"""Blinks that cleaning made up on both eyes at once run their course as the take's own blinks do.

Upper-lid markers are lost most often in a blink (the lashes and the brow hide them as the lid
shuts). Where one eye's marker is lost, its lid follows the other's (the ``pair`` rule of
:class:`mapping.rules.MotorRules`). Where both are lost at once, the gap filler can only bridge
what no seen marker shows: its fill reopens the lids along a line across the whole gap (the third
performer, bench seed 3: both lids' markers lost for 0.5 s from a blink's deepest frame, filled as
a reopening over 0.45 s where the lids reopened in 0.2 s: a fifth of that take's squared error).

Offline, after the per-frame rules, each upper lid (ERU, ELU) whose values are made up on both
eyes at once (:func:`mapping.mapper.made_up`) and which goes into that stretch in a blink (its value
at least half the take's median blink depth below its value after the stretch) finishes the blink:
it goes on closing at the speed it was closing, down to the take's shut lid, then reopens to its
value after the stretch as the take's own blinks reopen (their median way back, frame by frame),
and stays there. The take's blinks are its full blinks on the lid's values where they were
measured (:func:`mapping.blinks.find_blinks`); a take with fewer than two, or a stretch shorter
than their reopening (the fill bridges it as well), keeps the fill. The track's
``blinks_finished_s`` says where. Live, a held marker is not filled from the future and this
does not apply.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import median_filter

from mapping.blinks import BASELINE_SECONDS, FEWEST, LONGEST_SECONDS, find_blinks
from toon.motors import code_index

#: The upper lids, whose blinks are finished.
LIDS = ("ERU", "ELU")
#: A blink found on motor values moves its lid at least this far (a tenth of its way).
LEAST_MOVE = 0.1
#: A stretch starts in a blink where the lid is at least this share of the take's median blink
#: depth below its value after the stretch.
IN_BLINK_SHARE = 0.5
#: A blink has reopened when its lid is back within this share of its depth from its baseline.
BACK_SHARE = 0.1


@dataclass(frozen=True)
class BlinkTiming:
    """How one lid's measured blinks go, in motor units.

    Attributes
    ----------
    closed : float
        The shut lid: the shallowest full blink's deepest value (of those seen whole).
    depth : float
        The median full blink's depth below its baseline.
    reopening : ndarray, shape (n,)
        The median blink's way back from its deepest frame, a frame at a time from the one after
        it: 0 at its deepest, 1 at its baseline (its running median).
    """

    closed: float
    depth: float
    reopening: np.ndarray

    @property
    def reopen_frames(self) -> int:
        """Frames from the deepest until the median blink is back within :data:`BACK_SHARE` of
        its depth (the whole reopening where it never is)."""
        back = np.flatnonzero(self.reopening >= 1.0 - BACK_SHARE)
        return int(back[0]) + 1 if len(back) else len(self.reopening)


def blink_timing(values: np.ndarray, rate: float) -> BlinkTiming | None:
    """The blinks of one upper lid's values ``(F,)`` (NaN where not measured; the lid falls as it
    shuts), or None where fewer than two full blinks show whole (their troughs and the
    :data:`~mapping.blinks.LONGEST_SECONDS` after measured)."""
    found = find_blinks(values, rate, closing=-1.0, least=LEAST_MOVE)
    if found is None:
        return None
    reach = int(LONGEST_SECONDS * rate)
    whole = np.array([f for f in found.frames  # its trough and way back measured
                      if f + reach < len(values) and np.isfinite(values[f:f + reach + 1]).all()], dtype=int)
    if len(whole) < FEWEST:
        return None
    seen = np.flatnonzero(np.isfinite(values))
    level = np.interp(np.arange(len(values)), seen, values[seen])  # the baseline as find_blinks takes it
    baseline = median_filter(level, size=max(3, int(BASELINE_SECONDS * rate) | 1), mode="nearest")[whole]
    depth = baseline - level[whole]  # (blinks,): at least find_blinks's least
    after = level[whole[:, None] + np.arange(1, reach + 1)]  # (blinks, reach)
    reopening = np.median((after - level[whole, None]) / depth[:, None], axis=0)
    return BlinkTiming(float(level[whole].max()), float(np.median(depth)), reopening)


def finish_blinks(values: np.ndarray, made_up: np.ndarray, rate: float) -> tuple[np.ndarray, list[float]]:
    """Motor values ``(F, C)`` after the rules (``C`` at least 21) with the upper lids' blinks
    finished where both lids were made up (``made_up`` ``(F, C)``; see the module docstring): a
    new array, and the frames (seconds from the first) where a blink was finished."""
    out = values.copy()
    lids = [code_index(code) for code in LIDS]
    both = made_up[:, lids].all(axis=1)
    if not both.any():
        return out, []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], both.astype(np.int8), [0]])))
    spans = [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True) if a >= 2 and b < len(values)]
    finished = set()
    for col in lids:
        timing = blink_timing(np.where(made_up[:, col], np.nan, values[:, col]), rate)
        if timing is None:
            continue
        for start, end in spans:
            before, after = values[start - 1, col], values[end, col]
            if after - before < IN_BLINK_SHARE * timing.depth or end - start < timing.reopen_frames:
                continue  # not in a blink, or too short a stretch for the fill to lag a reopening
            out[start:end, col] = _finished(before, before - values[start - 2, col], after, end - start, timing)
            finished.add(start)
    return out, [k / rate for k in sorted(finished)]


def _finished(before: float, speed: float, after: float, frames: int, timing: BlinkTiming) -> np.ndarray:
    """A blink's last ``frames`` from a lid at ``before`` moving ``speed`` a frame: on closing
    (``speed`` < 0) to ``timing.closed``, then back to ``after`` as the take's median blink
    reopens (:attr:`BlinkTiming.reopening` up to its baseline or its highest, from wherever the lid
    is: a blink's lid moves faster the further it goes, so its reopening lasts about as long from
    any depth), then ``after``.
    Where the stretch ends before the reopening does, the rest of it is squeezed into the frames
    left, so that the lid meets its measured value there."""
    out = np.full(frames, after)
    value, k = before, 0
    if speed < 0 and before > timing.closed:  # still closing: on to the shut lid
        k = min(frames, int(np.ceil((before - timing.closed) / -speed - 1e-9)))
        out[:k] = np.maximum(before + speed * np.arange(1, k + 1), timing.closed)
        value = out[k - 1]
    back = np.flatnonzero(timing.reopening >= 1.0)  # to the baseline, or to the highest it reaches
    shape = timing.reopening[:(back[0] if len(back) else int(np.argmax(timing.reopening))) + 1]
    steps = min(len(shape), frames - k)
    if steps:
        way = np.interp(np.linspace(0.0, len(shape) - 1, steps), np.arange(len(shape)), shape) if steps < len(shape) \
            else shape
        out[k:k + steps] = value + (after - value) * way / max(float(shape[-1]), 1e-9)
    return out
