"""Label swaps: two neighbouring markers that trade labels for a few frames, found and undone.

A labelling solver that loses two markers close together (an upper and a lower lid, two lip
markers, two brow markers) may give each the other's label for a few frames. Neither sample is
a spike on its own (each sits where a marker really is), so a test of one marker's path at a time
finds only the first frame of the swap, if any: every frame after it agrees with the one before.
A swap shows as both markers jumping at once, each to where the other just was, at its start and
again at its end (or one alone, where the other is hidden); :func:`find_swaps` looks for those
jumps on every pair of markers close at rest (across a frame, or two where a spike on the frame
between hides the jump), and keeps a swap only where most samples between the jumps sit nearer
the other marker's usual place than their own. :func:`undo_swaps` gives the samples their labels
back.

It works in the head frame (a turning head moves every marker more between two frames than a
face does; a marker set without head references is judged in its one fixed placement) and looks
both ways, so it is offline cleaning's (:func:`mapping.clean.clean_stabilised`); the live mapper,
which can only look back, has the spike test alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mapping.robust import column_nan_median

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
#: The share of the samples between the two jumps that must sit nearer the other marker's usual
#: place than their own (a blink brings an upper lid down past a lower lid's usual place).
MOSTLY = 0.8
#: The usual place of a marker is its median over about this many frames spread evenly over the
#: take (a long take's median over every frame costs more than the rest and says no more).
USUAL_FRAMES = 1000
#: Frames whose steps are measured at once.
BLOCK_FRAMES = 65536


@dataclass(frozen=True)
class Swap:
    """Markers ``first`` and ``second`` carry each other's labels in frames ``[start, end)``."""

    first: int
    second: int
    start: int
    end: int


def find_swaps(local: np.ndarray, times: np.ndarray) -> list[Swap]:
    """The label swaps in ``local`` ``(F, M, D)`` (head frame, mm, NaN unseen) at ``times`` ``(F,)``.

    Only frames where a marker lands after a step of :data:`JUMP_MM` / 2 or after being unseen
    can end a jump (each jump has one of the two, or both, so), and they are few: a face moves
    under a millimetre a frame at 120 Hz.

    Returns
    -------
    list of Swap
        In no particular order; no two share a marker in overlapping frames.
    """
    seen = np.isfinite(local).all(axis=2)
    frames = len(local)
    spread = local[::max(1, frames // USUAL_FRAMES)]
    usual = column_nan_median(spread.reshape(len(spread), -1)).reshape(local.shape[1:])  # NaN: never seen
    apart = np.linalg.norm(usual[:, None] - usual[None, :], axis=2)
    pairs = np.argwhere(np.triu(apart < NEIGHBOUR_MM, k=1))
    landing = np.zeros_like(seen)  # where a marker lands after a step that could be a jump, or after a gap
    for lo in range(1, frames, BLOCK_FRAMES):  # a block at a time: an hour's steps at once are hundreds of MB
        hi = min(lo + BLOCK_FRAMES, frames)
        step = local[lo:hi] - local[lo - 1:hi - 1]
        moved = np.einsum("fmd,fmd->fm", step, step) >= (JUMP_MM / 2) ** 2  # NaN: False
        landing[lo:hi] = moved | (seen[lo:hi] & ~seen[lo - 1:hi - 1])
    landing, seen_each = np.ascontiguousarray(landing.T), np.ascontiguousarray(seen.T)  # (M, F): a marker's row
    swaps: list[Swap] = []
    busy: dict[int, list[tuple[int, int]]] = {}
    for i, j in pairs.tolist():
        at = np.flatnonzero(landing[i] | landing[j])
        if len(at) < 2:  # a swap has two jumps
            continue
        jumps = _jumps(local, times, seen_each, usual, i, j, at)
        for swap in _pair_swaps(local, times, seen, usual, i, j, jumps):
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


def _pair_swaps(local: np.ndarray, times: np.ndarray, seen: np.ndarray, usual: np.ndarray, i: int, j: int,
                jumps: np.ndarray) -> list[Swap]:
    """The swaps of markers ``i`` and ``j``: a run of stretches between their ``jumps``
    (:func:`_jumps`) where :data:`MOSTLY` of the samples sit nearer the other's usual place than
    their own, at most :data:`LONGEST_SWAP_SECONDS` long. Stretches, not every other jump: one
    swap may begin with a jump of each marker where the two were not seen in the same frames. A
    single sample is not a swap: one marker's one frame near a hidden neighbour's place is as
    likely a spike (which the spike tests blank) as a swap."""
    edges = jumps.tolist()
    crossed, samples = [], []
    for start, end in zip(edges[:-1], edges[1:], strict=True):
        placed = [(local[start:end, m][seen[start:end, m]], m, o) for m, o in ((i, j), (j, i))]
        nearer = np.concatenate([np.linalg.norm(x - usual[o], axis=1) < np.linalg.norm(x - usual[m], axis=1)
                                 for x, m, o in placed])
        crossed.append(len(nearer) > 0 and nearer.mean() >= MOSTLY)
        samples.append(len(nearer))
    out: list[Swap] = []
    k = 0
    while k < len(crossed):
        if not crossed[k]:
            k += 1
            continue
        end = k
        while end + 1 < len(crossed) and crossed[end + 1]:
            end += 1
        first, after = edges[k], edges[end + 1]
        if times[after] - times[first] <= LONGEST_SWAP_SECONDS and sum(samples[k:end + 1]) >= 2:
            out.append(Swap(i, j, int(first), int(after)))
        k = end + 1
    return out


def _jumps(local: np.ndarray, times: np.ndarray, seen: np.ndarray, usual: np.ndarray, i: int, j: int,
           at: np.ndarray) -> np.ndarray:
    """The frames among ``at`` (sorted) where markers ``i`` and ``j`` jump to where the other just
    was: both at once where both are seen there and in an earlier frame (each lands
    :data:`CLOSER` times nearer the other's sample there than its own), or one alone where the
    other is not seen both before and after (it moves by the pair's offset, as last seen
    together or, never seen together, as usual). ``seen`` ``(M, F)``: where each marker is seen."""
    both = np.flatnonzero(seen[i] & seen[j])
    found = []
    landed = at[seen[i, at] & seen[j, at]]
    k = np.searchsorted(both, landed) - 1  # the frame before with both seen
    for back in (0, 1):  # from that frame, and from the one before it (a spike there hides the jump)
        kept = k - back >= 0
        to, before = landed[kept], both[k[kept] - back]
        if not len(to):
            continue
        a, b, a0, b0 = local[to, i], local[to, j], local[before, i], local[before, j]
        same = np.linalg.norm(a - a0, axis=1) + np.linalg.norm(b - b0, axis=1)
        cross = np.linalg.norm(a - b0, axis=1) + np.linalg.norm(b - a0, axis=1)
        close = times[to] - times[before] <= LONGEST_STEP_SECONDS
        found.append(to[close & (same >= JUMP_MM) & (cross * CLOSER <= same)])
    for m, o in ((i, j), (j, i)):
        after = at[seen[m, at]]
        own = np.flatnonzero(seen[m])
        k = np.searchsorted(own, after) - 1  # m's sample before
        after, before = after[k >= 0], own[k[k >= 0]]
        alone = (times[after] - times[before] <= LONGEST_STEP_SECONDS) & ~(seen[o, before] & seen[o, after])
        after, before = after[alone], before[alone]
        if not len(after):
            continue
        step = local[after, m] - local[before, m]
        k = np.searchsorted(both, before, side="right") - 1  # the latest frame up to before with both seen
        together = both[np.maximum(k, 0)] if len(both) else before
        offset = np.where((k >= 0)[:, None], local[together, o] - local[together, m], usual[o] - usual[m])
        size = np.linalg.norm(step, axis=1)
        miss = np.minimum(np.linalg.norm(step - offset, axis=1), np.linalg.norm(step + offset, axis=1))
        found.append(after[(size >= JUMP_MM / 2) & (miss * CLOSER <= size)])
    return np.unique(np.concatenate(found)) if found else np.zeros(0, int)
