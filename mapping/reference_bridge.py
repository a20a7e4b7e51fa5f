"""Bridging a lost head reference: the head fitted on the references still seen, carried onto
the head fitted on all of them, so that nothing in the head frame jumps while one is lost
(:func:`mapping.stabilise.express` uses it)."""

from __future__ import annotations

import numpy as np

from common.rotations import best_rotation, rigid_fit
from mapping.robust import jitter

#: :func:`bridge_references` compares the head fitted on all references with the fit on fewer
#: over at most this many seconds either side of a stretch where one is lost (see :func:`bridge_edge`).
BRIDGE_SECONDS = 0.5
#: ... and averages the frames nearest the stretch until their mean departs from a nearer mean by
#: more than this many of its standard errors (:func:`steady_count`).
STEADY_ERRORS = 3.0
#: The difference read at a stretch's edge is carried into it fading as ``exp(-t / FADE_SECONDS)``,
#: ``t`` the time to the nearer edge (see :func:`bridge_references`).
FADE_SECONDS = 0.25


def bridge_edge(rate: float) -> int:
    """At most how many frames either side of a lost reference :func:`bridge_references` reads
    at a frame rate of ``rate`` Hz (:data:`BRIDGE_SECONDS`, at least one).

    >>> bridge_edge(60.0), bridge_edge(120.0), bridge_edge(1.0)
    (30, 60, 1)
    """
    return max(1, int(round(BRIDGE_SECONDS * rate)))


def fade_frames(rate: float) -> float:
    """:data:`FADE_SECONDS` in frames at a frame rate of ``rate`` Hz.

    >>> fade_frames(120.0)
    30.0
    """
    return FADE_SECONDS * rate


def bridge_references(target: np.ndarray, shape: np.ndarray, rotation: np.ndarray, translation: np.ndarray,
                      ok: np.ndarray, edge: int = 1, fade: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """The head pose ``(F, 3, 3)``, ``(F, 3)`` with no jump where references drop out (the pose
    as given where none does); ``target`` ``(F, K, 3)``: the references, NaN where unseen.

    Real head references are not quite rigid, so a head fitted on fewer of them sits a little
    off the one fitted on all: every marker expressed in the head frame would jump by that much
    for as long as one is lost. Over each stretch where the same references are missing, the
    head is fitted on the others (``rotation``, ``translation``: that fit, ``shape`` ``(K, 3)``
    the references' place in the head frame); on the frames either side, where all of them are
    seen, the fit on all of them is compared with the fit on the others, and that difference (in
    the head frame) is bridged straight across the stretch. A stretch inside a longer run of
    frames that miss some reference (a spike taken out during another's loss) is bridged from
    that run's edges, and blended and faded as across the run (:func:`enclosing`).

    On each side the difference is the mean over the nearest frames with every reference seen
    (within ``edge`` frames of the stretch), as many as hold steady (:func:`steady_count`): read
    from one frame, it carried that frame's jitter through the whole stretch (on rigid
    references with 0.3 mm of jitter a pupil sat 0.25 mm low for as long as a temple was lost),
    while real references that slide with the skin (the AnimFace jaw take) want the nearest
    frame alone.

    What is read at an edge is the slide of that moment's expression, and it holds near the edge
    only: a face turned away for two seconds hides its far temple through a smile and a rest, and
    the smile's slide, read where the temple went out of view, carried whole to the other edge
    moved the resting face by the smile's share. So the difference fades into the stretch as
    :func:`held` says, over ``fade`` frames (:func:`fade_frames`; ``np.inf``: carried whole).
    :data:`FADE_SECONDS` chosen among 0.001 (none carried), 0.25, 0.5, 1 and whole: on draws kept
    apart from the bench's seeds (31-34 of the four synthetic performers) the fitted error fell
    the more the shorter the fade (solver, summed over the 16 takes: 22.15 whole, 22.11 at 1 s,
    22.08 at 0.5, 22.03 at 0.25, 21.79 none; the rules the same way), while on the real AnimFace
    jaw take, three markers cut for 250 ms (``tests/mapping/test_stabilise.py``), the cut markers'
    error over a spline's was 1.45 whole, 1.41 at 1 s and 0.25 s, 1.39 at 0.5, 1.52 at 0.15, 1.67
    at 0.1 and 2.96 none: a short loss wants the edges, a long one does not. 0.25 s keeps nearly
    all of the real take's gain and some of the synthetic ones'.
    """
    missing = np.isnan(target[..., 0]) & ok[:, None]
    if not missing.any():
        return rotation, translation
    rot, trans = rotation.copy(), translation.copy()
    frames = len(target)
    whole = ok & np.isfinite(target[..., 0]).all(axis=1)  # frames fitted on every reference
    whole_at = np.flatnonzero(whole)
    for start, end in stretches(missing):
        keep = ~missing[start]
        if keep.all() or keep.sum() < 3:
            continue
        first, last = enclosing(whole_at, frames, start, end)
        near = [np.arange(first - 1, max(first - edge, 0) - 1, -1), np.arange(last, min(last + edge, frames))]
        sides = [side[whole[side]] for side in near]  # nearest first, every reference seen
        corrections = [_correction(shape, keep, target[side][:, keep], rotation[side], translation[side])
                       for side in sides if len(side)]
        if not corrections:
            continue
        (first_rot, first_trans), (last_rot, last_trans) = corrections[0], corrections[-1]
        inside = slice(start - first, end - first)
        w, kept = across(first, last)[inside, None, None], held(first, last, fade)[inside, None, None]
        c_rot = best_rotation(kept * ((1 - w) * first_rot + w * last_rot) + (1 - kept) * np.eye(3))
        c_trans = kept[:, :, 0] * ((1 - w[:, :, 0]) * first_trans + w[:, :, 0] * last_trans)
        rot[start:end] = rotation[start:end] @ c_rot
        trans[start:end] = np.einsum("fij,fj->fi", rotation[start:end], c_trans) + translation[start:end]
    return rot, trans


def stretches(missing: np.ndarray) -> list[tuple[int, int]]:
    """The runs of frames ``[start, end)``, in order, over which the same references are missing
    (``missing`` ``(F, K)``, bool), every frame in one.

    >>> stretches(np.array([[0, 0], [1, 0], [1, 0], [0, 1]], bool))
    [(0, 1), (1, 3), (3, 4)]
    """
    pattern = np.packbits(missing, axis=1, bitorder="little")  # one code per set of missing references
    changes = np.flatnonzero(np.any(np.diff(pattern, axis=0) != 0, axis=1)) + 1
    return [(int(a), int(b)) for a, b in zip(np.r_[0, changes], np.r_[changes, len(missing)], strict=True)]


def enclosing(whole_at: np.ndarray, frames: int, start: int, end: int) -> tuple[int, int]:
    """The run of frames ``[first, last)`` that holds the stretch ``[start, end)`` of a take of
    ``frames`` frames and has no frame that sees every reference (those are ``whole_at``, in
    order: ``np.flatnonzero`` of a whole-frame mask, found once per take, since a take has a
    stretch for every spike taken out of a reference): a stretch is bridged from that run's
    edges, and blended across and faded into from them, not from its own. A reference lost for a
    frame (a spike taken out) inside a longer loss of another splits that loss in three; bridged
    from their own edges, the parts either side took the difference read where the whole loss
    began, or found none to take, at full weight again beside the lost frame, wherever it had
    faded to (the fourth performer's bench seeds, solved: 1.151, 1.300, 1.400, 1.387, 1.204 ->
    1.126, 1.302, 1.369, 1.376, 1.205 % fitted, seed 1's lowest r 0.927 -> 0.941).

    >>> whole_at = np.flatnonzero(np.array([1, 0, 0, 0, 0, 1, 0], bool))
    >>> enclosing(whole_at, 7, 2, 3), enclosing(whole_at, 7, 1, 5), enclosing(whole_at, 7, 6, 7)
    ((1, 5), (1, 5), (6, 7))
    """
    i, j = np.searchsorted(whole_at, start), np.searchsorted(whole_at, end)
    return (int(whole_at[i - 1]) + 1 if i > 0 else 0), (int(whole_at[j]) if j < len(whole_at) else frames)


def across(start: int, end: int) -> np.ndarray:
    """How far each frame of the stretch ``[start, end)`` is across it, ``(end - start,)``: 0 at
    the frame before it, 1 at the frame after (the bridge blends the two sides' differences so).

    >>> across(1, 4).tolist()
    [0.25, 0.5, 0.75]
    """
    return (np.arange(start, end) - (start - 1)) / (end - start + 1)


def held(start: int, end: int, fade: float) -> np.ndarray:
    """How much of the edges' difference each frame of the stretch ``[start, end)`` keeps,
    ``(end - start,)``: ``exp(-n / fade)``, ``n`` the frames to the nearer frame outside it; 1
    throughout where ``fade`` is ``np.inf`` (the whole difference carried, as before the fade).

    >>> held(1, 6, 2.0).round(3).tolist()
    [0.607, 0.368, 0.223, 0.368, 0.607]
    """
    frame = np.arange(start, end)
    return np.exp(-np.minimum(frame - (start - 1), end - frame) / fade)


def _correction(shape: np.ndarray, keep: np.ndarray, target: np.ndarray, rotation: np.ndarray,
                translation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The head-frame correction ``(3, 3)``, ``(3,)`` that carries the head fitted on the
    references ``keep`` ``(K,)`` of ``shape`` ``(K, 3)`` (seen at ``target`` ``(E, k, 3)``) onto
    the head fitted on all of them (``rotation`` ``(E, 3, 3)``, ``translation`` ``(E, 3)``),
    in ``E`` frames nearest first: the full fit is the partial one after the correction, its
    mean over the frames that hold steady (judged by where it puts every reference)."""
    sub_rot, sub_trans, _ = rigid_fit(shape[keep], target)
    c_rot = np.transpose(sub_rot, (0, 2, 1)) @ rotation
    c_trans = np.einsum("eji,ej->ei", sub_rot, translation - sub_trans)
    moved = (np.einsum("eij,kj->eki", c_rot, shape) + c_trans[:, None]).reshape(len(target), -1)
    count = steady_count(moved)
    return best_rotation(c_rot[:count].mean(axis=0)), c_trans[:count].mean(axis=0)


def steady_count(values: np.ndarray, errors: float = STEADY_ERRORS) -> int:
    """How many of the first rows of ``values`` ``(n, P)`` to average: the most whose running
    means' intervals (each mean ± ``errors`` standard errors) still share a point in every
    column, the noise measured from the rows' second differences (the intersection of
    confidence intervals rule of Goldenshluger & Nemirovski, 1997; the noise by
    :func:`mapping.robust.jitter`). Noisy rows that hold steady
    are all averaged; rows that drift more than their noise explains stop it early. One with
    fewer than five rows (too few to tell noise from drift).

    >>> rng = np.random.default_rng(0)
    >>> steps = np.r_[np.zeros(8), np.ones(22)][:, None]  # a step of ten times the noise after 8 rows
    >>> steady_count(rng.normal(0.0, 1.0, (30, 2))), steady_count(steps + rng.normal(0, 0.1, (30, 1)))
    (30, 11)
    """
    n = len(values)
    if n < 5:
        return min(n, 1)
    noise = jitter(values)  # (P,)
    count = np.arange(1, n + 1)[:, None]
    mean = np.cumsum(values, axis=0) / count
    half = errors * noise / np.sqrt(count)
    low, high = np.maximum.accumulate(mean - half, axis=0), np.minimum.accumulate(mean + half, axis=0)
    apart = np.flatnonzero((low > high).any(axis=1))
    return int(apart[0]) if len(apart) else n
