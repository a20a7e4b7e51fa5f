"""Label swaps: two neighbouring markers that trade labels for a few frames, found and undone.

A labelling solver that loses two markers close together (an upper and a lower lid, two lip
markers, two brow markers) may give each the other's label for a few frames. Neither sample is
a spike on its own (each sits where a marker really is), so a test of one marker's path at a time
finds only the first frame of the swap, if any: every frame after it agrees with the one before.
A swap shows as both markers jumping at once, each to where the other just was, at its start and
again at its end; :func:`find_swaps` looks for that pair of jumps on every pair of markers close
at rest, and keeps a swap only where each marker between the jumps sits nearer the other's usual
place than its own. :func:`undo_swaps` gives the samples their labels back.

It works in the head frame (a turning head moves every marker more between two frames than a
face does) and looks both ways, so it is offline cleaning's (:func:`mapping.clean.clean_stabilised`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Markers this close at rest (mm, head frame) are a pair whose labels a solver may swap.
NEIGHBOUR_MM = 30.0
#: The longest swap undone (s): a labeller that has gone wrong for longer has lost the markers,
#: and which was which is no longer a matter of two jumps.
LONGEST_SWAP_SECONDS = 0.5
#: A jump is looked for across at most this long without both markers seen (s): across a longer
#: gap the face may have moved as far as a swap would.
LONGEST_STEP_SECONDS = 0.05
#: A swap's jump: both markers move at least this far (mm, summed) ...
JUMP_MM = 3.0
#: ... and each lands at least this many times nearer where the other was than where it was.
CLOSER = 4.0
#: The share of the frames between the two jumps where the markers must sit nearer each other's
#: usual places than their own (a blink brings an upper lid down past a lower lid's usual place).
MOSTLY = 0.8


@dataclass(frozen=True)
class Swap:
    """Markers ``first`` and ``second`` carry each other's labels in frames ``[start, end)``."""

    first: int
    second: int
    start: int
    end: int


def find_swaps(local: np.ndarray, times: np.ndarray) -> list[Swap]:
    """The label swaps in ``local`` ``(F, M, D)`` (head frame, mm, NaN unseen) at ``times`` ``(F,)``.

    Returns
    -------
    list of Swap
        In no particular order; no two share a marker in overlapping frames.
    """
    seen = np.isfinite(local).all(axis=2)
    usual = np.full(local.shape[1:], np.nan)
    counted = seen.any(axis=0)
    if counted.any():
        usual[counted] = np.nanmedian(local[:, counted], axis=0)
    apart = np.linalg.norm(usual[:, None] - usual[None, :], axis=2)
    pairs = np.argwhere(np.triu(apart < NEIGHBOUR_MM, k=1))
    swaps: list[Swap] = []
    busy: dict[int, list[tuple[int, int]]] = {}
    for i, j in pairs.tolist():
        for swap in _pair_swaps(local, times, seen, usual, i, j):
            if any(s < swap.end and swap.start < e for m in (i, j) for s, e in busy.get(m, [])):
                continue
            swaps.append(swap)
            for m in (i, j):
                busy.setdefault(m, []).append((swap.start, swap.end))
    return swaps


def undo_swaps(values: np.ndarray, swaps: list[Swap]) -> None:
    """Give the samples of ``values`` ``(F, M, ...)`` (markers second) their labels back, in place."""
    for s in swaps:
        rows = slice(s.start, s.end)
        values[rows, [s.first, s.second]] = values[rows, [s.second, s.first]]


def _pair_swaps(local: np.ndarray, times: np.ndarray, seen: np.ndarray, usual: np.ndarray, i: int, j: int
                ) -> list[Swap]:
    """The swaps of markers ``i`` and ``j``: a run of stretches between their jumps (:func:`_jumps`)
    where :data:`MOSTLY` of the samples sit nearer the other's usual place than their own, at most
    :data:`LONGEST_SWAP_SECONDS` long. Stretches, not every other jump: one swap may begin with a
    jump of each marker where the two were not seen in the same frames. A single sample is not a
    swap: one marker's one frame near a hidden neighbour's place is as likely a spike (which the
    spike tests blank) as a swap."""
    jumps = _jumps(local, times, seen, usual, i, j).tolist()
    crossed, samples = [], []
    for start, end in zip(jumps[:-1], jumps[1:], strict=True):
        nearer = np.concatenate([np.linalg.norm(local[start:end, m][seen[start:end, m]] - usual[o], axis=1)
                                 < np.linalg.norm(local[start:end, m][seen[start:end, m]] - usual[m], axis=1)
                                 for m, o in ((i, j), (j, i))])
        crossed.append(len(nearer) > 0 and nearer.mean() >= MOSTLY)
        samples.append(len(nearer))
    out: list[Swap] = []
    k = 0
    while k < len(crossed):
        if not crossed[k]:
            k += 1
            continue
        last = k
        while last + 1 < len(crossed) and crossed[last + 1]:
            last += 1
        start, end = jumps[k], jumps[last + 1]
        if times[end] - times[start] <= LONGEST_SWAP_SECONDS and sum(samples[k:last + 1]) >= 2:
            out.append(Swap(i, j, int(start), int(end)))
        k = last + 1
    return out


def _jumps(local: np.ndarray, times: np.ndarray, seen: np.ndarray, usual: np.ndarray, i: int, j: int
           ) -> np.ndarray:
    """The frames (sorted) where markers ``i`` and ``j`` jump to where the other just was: both at
    once where both are seen either side (each lands :data:`CLOSER` times nearer the other's last
    sample than its own), or one alone where the other is not (it moves by the pair's offset, as
    last seen or, never seen together, as usual)."""
    found = []
    both = np.flatnonzero(seen[:, i] & seen[:, j])
    if len(both) >= 2:
        a, b = local[both, i], local[both, j]
        same = np.linalg.norm(a[1:] - a[:-1], axis=1) + np.linalg.norm(b[1:] - b[:-1], axis=1)
        cross = np.linalg.norm(a[1:] - b[:-1], axis=1) + np.linalg.norm(b[1:] - a[:-1], axis=1)
        close = np.diff(times[both]) <= LONGEST_STEP_SECONDS
        found.append(both[1:][close & (same >= JUMP_MM) & (cross * CLOSER <= same)])
    index = np.where(seen[:, i] & seen[:, j], np.arange(len(seen)), -1)
    last_both = np.maximum.accumulate(index)  # the latest frame up to each with both seen (-1: none)
    for m, o in ((i, j), (j, i)):
        own = np.flatnonzero(seen[:, m])
        if len(own) < 2:
            continue
        before, after = own[:-1], own[1:]
        alone = (np.diff(times[own]) <= LONGEST_STEP_SECONDS) & ~(seen[before, o] & seen[after, o])
        step = local[after, m] - local[before, m]
        at = last_both[before]
        offset = np.where((at >= 0)[:, None], local[np.maximum(at, 0), o] - local[np.maximum(at, 0), m],
                          usual[o] - usual[m])
        size = np.linalg.norm(step, axis=1)
        miss = np.minimum(np.linalg.norm(step - offset, axis=1), np.linalg.norm(step + offset, axis=1))
        found.append(after[alone & (size >= JUMP_MM / 2) & (miss * CLOSER <= size)])
    return np.unique(np.concatenate(found)) if found else np.zeros(0, int)
