"""Head poses across frames whose references do not pin the head: carried across from the
poses either side (:func:`bridge_lost_poses`), then set right by the references still seen
there, as far as they pin it (:func:`refine_poses`).

A frame with fewer than three head references seen, or three on nearly one line (``toon32``'s
forehead, nose bridge and nose tip: :func:`mapping.stabilise.well_posed`), has no pose of its
own. The pose carried across from either side is right while the head turns steadily, and wrong
by degrees where it changes course inside the stretch (a nod that stops); the references still
seen pin some of its rotations well (the midline's three pin a nod), and those they pin follow
them. The face's other markers help as weak references (:func:`weak_references`): two temples
cannot pin a nod about the line through them, but a cheek, the nose or the chin, which hardly
move in the head, can.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mapping.gaps import gap_runs
from mapping.stabilise import least_moment

#: The longest stretch without a head pose that :func:`bridge_lost_poses` bridges, seconds: cleaning
#: passes its longest gap filled (:attr:`mapping.settings.CleanSettings.max_gap_seconds`, 2 s by
#: default), since a longer stretch is left unseen and a shorter one's markers would otherwise be
#: filled one by one, each by a spline of its own across the whole face's gap (at 1 s, a forehead
#: marker lost for 1.3 s while the head was turned past a temple's view left the fourth performer's
#: raised brows to splines that swung them to fully lowered: brows at r 0.4-0.6).
LONGEST_LOST_POSE = 2.0
#: Seconds of fitted poses either side of a lost stretch that the bridge is fitted to, at most
#: (the stretch's own length, at least).
POSE_CONTEXT = 0.3


def bridge_lost_poses(rotation: np.ndarray, translation: np.ndarray, ok: np.ndarray, times: np.ndarray,
                      longest: float = LONGEST_LOST_POSE, trust: np.ndarray | None = None
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The head pose carried across short stretches of frames without one, and which frames
    it was carried across ``(F,)``.

    A frame with fewer than three head references seen has no pose, and without one every
    marker seen in it is lost to the head frame: when two references' gaps overlap for half a
    second, a whole face's worth of seen motion (a blink, a smile starting) would be left to gap
    filling, and even over a few frames each marker's spline through its noisy neighbours swung
    by a millimetre. A head turns slowly next to a face's motion, so across a stretch of at most
    ``longest`` seconds with a fitted pose on both sides, the pose is a quadratic in time fitted
    to the poses either side, as many frames as the stretch is long, from 3 up to
    :data:`POSE_CONTEXT` seconds (the rotation as a rotation vector from the last pose before
    it, which keeps the angles small), and the markers seen there are expressed in it.

    Parameters
    ----------
    rotation : ndarray, shape (F, 3, 3)
    translation : ndarray, shape (F, 3)
        Head frame to world, as fitted (anything where ``ok`` is False).
    ok : ndarray of bool, shape (F,)
        Frames with a fitted pose.
    times : ndarray, shape (F,)
        Seconds.
    longest : float
        Seconds; longer stretches stay without a pose.
    trust : ndarray, shape (F,), optional
        How far each fitted pose is to be trusted (:func:`mapping.stabilise.posedness`: a fit
        on three references close to a line swings more than one on five); the fit either side
        weighs each pose by it. Equal trust by default.
    """
    from scipy.spatial.transform import Rotation

    rot, trans, bridged = rotation.copy(), translation.copy(), np.zeros(len(ok), bool)
    step = _step(times)
    most = _context_frames(step)
    for start, end in gap_runs(~ok):
        if start == 0 or end == len(ok) or times[end] - times[start - 1] > longest + 1.5 * step:
            continue
        reach = min(max(3, end - start), most)
        around = np.r_[max(0, start - reach):start, end:min(len(ok), end + reach)]
        around = around[ok[around]]
        base = rotation[start - 1]
        offsets = Rotation.from_matrix(np.einsum("ji,fjk->fik", base, rotation[around])).as_rotvec()
        t = times[around] - times[start - 1]
        degree = 2 if len(around) >= 6 else 1
        weight = np.sqrt(trust[around])[:, None] if trust is not None else np.ones((len(around), 1))
        design = np.vander(t, degree + 1)
        coef, *_ = np.linalg.lstsq(design * weight, np.hstack([offsets, translation[around]]) * weight, rcond=None)
        inside = np.vander(times[start:end] - times[start - 1], degree + 1) @ coef
        rot[start:end] = base @ Rotation.from_rotvec(inside[:, :3]).as_matrix()
        trans[start:end] = inside[:, 3:]
        bridged[start:end] = True
    return rot, trans, bridged


def _step(times: np.ndarray) -> float:
    """The typical seconds between frames of ``times`` (1 for a single frame)."""
    return float(np.median(np.diff(times))) if len(times) > 1 else 1.0


def _context_frames(step: float) -> int:
    """:data:`POSE_CONTEXT` in frames ``step`` seconds apart (at least 3)."""
    return max(3, int(round(POSE_CONTEXT / step))) if step > 0 else 3


@dataclass(frozen=True)
class WeakReferences:
    """The face's other markers as weak head references in frames whose pose was carried
    (:func:`weak_references`).

    Attributes
    ----------
    place : ndarray, shape (F, J, 3)
        Where each marker is expected in the head frame (mm), in the frames it helps in.
    world : ndarray, shape (F, J, 3)
        Where it was seen (NaN where not).
    weight : ndarray, shape (F, J)
        What it counts for against a head reference seen in the same frame (0: nothing).
    """

    place: np.ndarray
    world: np.ndarray
    weight: np.ndarray


def weak_references(local: np.ndarray, world: np.ndarray, ok: np.ndarray, carried: np.ndarray, times: np.ndarray,
                    noise: float) -> WeakReferences:
    """The markers other than the head references as weak references in ``carried`` frames.

    In a stretch whose pose was carried across, each marker is expected where it was in the head
    frame on the fitted frames either side (their mean, :data:`POSE_CONTEXT` seconds each side
    at most), and counts ``noise² / (noise² + v)`` of a head reference, where ``v`` is its
    variance in the head frame (mean over the axes, its own jitter included), the larger of that
    over the frames either side and over the whole take: a head reference's error is its
    jitter, this marker's also how far it moves. A marker still on both sides but moving
    somewhere in the take (a mouth corner) counts for little, since it may move inside the
    stretch, and even a still one for half a reference at most: a brow still until now may rise
    inside it. (Counting a still one as a whole reference, ``noise² / v``, took one draw of the
    second bench performer from 1.33 to 1.65 % fitted error.) The carried pose's own weight
    (:data:`CARRIED_WEIGHT`) stays: where the other markers pin what the references do not,
    they halve a nod's error, not end it.

    Parameters
    ----------
    local : ndarray, shape (F, J, 3)
        The markers in the head frame (NaN where unseen or without a pose).
    world : ndarray, shape (F, J, 3)
        The same markers as seen (NaN where unseen).
    ok : ndarray of bool, shape (F,)
        Frames with a fitted pose.
    carried : ndarray of bool, shape (F,)
        Frames whose pose was carried across (:func:`bridge_lost_poses`).
    times : ndarray, shape (F,)
        Seconds.
    noise : float
        The head references' jitter, mm (a standard deviation per axis).
    """
    frames, count = local.shape[:2]
    place, weight = np.full((frames, count, 3), np.nan), np.zeros((frames, count))
    if not carried.any() or not ok.any() or not noise > 0:
        return WeakReferences(place, world, weight)
    _, moves, _ = _spread(local[ok])
    reach = _context_frames(_step(times))
    for start, end in gap_runs(carried):
        around = np.r_[max(0, start - reach):start, end:min(frames, end + reach)]
        mean, varies, seen = _spread(local[around[ok[around]]])
        share = noise ** 2 / (noise ** 2 + np.fmax(varies, moves))
        place[start:end] = mean
        weight[start:end] = np.where((seen >= 3) & np.isfinite(share), share, 0.0)
    return WeakReferences(place, world, weight)


def _spread(values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Of ``values`` ``(n, J, 3)`` (NaN where unseen): each marker's mean ``(J, 3)``, its variance
    ``(J,)`` (sample variance, mean over the axes; NaN with fewer than two samples) and how many
    samples it has ``(J,)``."""
    seen = np.isfinite(values[..., 0])
    count = seen.sum(axis=0)
    mean = np.where(seen[..., None], values, 0.0).sum(axis=0) / np.maximum(count, 1)[:, None]
    square = np.where(seen[..., None], values - mean, 0.0) ** 2
    variance = square.sum(axis=0).mean(axis=-1) / np.where(count > 1, count - 1, np.nan)
    return np.where(count[:, None] > 0, mean, np.nan), variance, count


#: How much a carried pose counts against the references seen in its frame: as much as a fit
#: on all of them pins the rotation it pins worst (their least principal moment, times this).
#: A rotation the seen ones pin better than that follows them; one they pin worse stays near
#: the carried pose. On the bench's second and third performers (5 seeds each) the poses in
#: carried frames came 0.59 and 0.39 degrees RMS from the truth on average, against 0.77 and
#: 0.45 carried alone, no take worse by more than 0.01 (the worst take 1.83 -> 1.13); a third
#: of that weight gave 0.55 and 0.40 but three takes worse than carried alone.
CARRIED_WEIGHT = 1.0


def refine_poses(rotation: np.ndarray, translation: np.ndarray, shape: np.ndarray, target: np.ndarray,
                 frames: np.ndarray, iterations: int = 2, weak: WeakReferences | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Carried poses set right by the references seen in their frames, as far as those pin them.

    In each of ``frames`` the pose is the least-squares fit of the seen references ``target``
    to ``shape``, with the carried pose as a prior: a rotation away from it costs
    :data:`CARRIED_WEIGHT` times the least principal moment of all the references (mm² per
    radian², :func:`mapping.stabilise.least_moment`), the translation nothing. Solved by
    Gauss-Newton about the carried pose, ``iterations`` times. One reference seen moves the
    head along; the midline's three also pitch it; none leaves the carried pose. ``weak``
    (:func:`weak_references`): more markers in the fit, each counted at its weight.

    Parameters
    ----------
    rotation : ndarray, shape (F, 3, 3)
    translation : ndarray, shape (F, 3)
        Head frame to world, carried across where ``frames``.
    shape : ndarray, shape (K, 3)
        The references' place in the head frame.
    target : ndarray, shape (F, K, 3)
        The references in the world, NaN where unseen.
    frames : ndarray of bool, shape (F,)
        Frames whose pose was carried across.
    iterations : int
        Gauss-Newton steps.
    weak : WeakReferences, optional
        The face's other markers, ``(F, J, ...)``, each counted at its weight (none by default).

    Returns
    -------
    rotation : ndarray, shape (F, 3, 3)
    translation : ndarray, shape (F, 3)
        As given outside ``frames``.
    """
    from scipy.spatial.transform import Rotation

    rot, trans = rotation.copy(), translation.copy()
    index = np.flatnonzero(frames)
    if not len(index):
        return rot, trans
    seen = np.isfinite(target[index, :, 0])[..., None].astype(np.float64)  # (B, K, 1): each one's weight
    world = np.nan_to_num(target[index])
    head = np.broadcast_to(shape, (len(index), *shape.shape))  # (B, K, 3): where each is in the head frame
    if weak is not None:
        counts = weak.weight[index] * np.isfinite(weak.world[index, :, 0]) * np.isfinite(weak.place[index, :, 0])
        seen = np.concatenate([seen, counts[..., None]], axis=1)
        world = np.concatenate([world, np.nan_to_num(weak.world[index])], axis=1)
        head = np.concatenate([head, np.nan_to_num(weak.place[index])], axis=1)
    stiffness = CARRIED_WEIGHT * least_moment(shape)
    prior = np.diag([stiffness] * 3 + [1e-9] * 3)
    carried = rot[index]
    r, t = carried, trans[index]
    for _ in range(iterations):
        turned = Rotation.from_matrix(r @ np.transpose(carried, (0, 2, 1))).as_rotvec()  # (B, 3): from the carried
        placed = np.einsum("bij,bkj->bki", r, head)  # (B, K, 3): the references where the pose puts them
        miss = (world - placed - t[:, None, :]) * seen
        # d(placed)/d(rotation vector) = -[placed]x, d/d(translation) = I
        jacobian = np.concatenate([-_cross_matrix(placed), np.broadcast_to(np.eye(3), placed.shape + (3,))], -1)
        normal = np.einsum("bkia,bkic->bac", jacobian * seen[..., None], jacobian) + prior
        pull = np.einsum("bkia,bki->ba", jacobian, miss)
        pull[:, :3] -= stiffness * turned  # the prior's cost is of the whole turn, not of this step
        step = np.linalg.solve(normal, pull[..., None])[..., 0]
        r = Rotation.from_rotvec(step[:, :3]).as_matrix() @ r
        t = t + step[:, 3:]
    rot[index], trans[index] = r, t
    return rot, trans


def _cross_matrix(vectors: np.ndarray) -> np.ndarray:
    """``[v]x`` of each vector ``(..., 3)``, ``(..., 3, 3)``: ``[v]x @ w == cross(v, w)``."""
    out = np.zeros(vectors.shape + (3,))
    x, y, z = vectors[..., 0], vectors[..., 1], vectors[..., 2]
    out[..., 0, 1], out[..., 0, 2], out[..., 1, 0] = -z, y, z
    out[..., 1, 2], out[..., 2, 0], out[..., 2, 1] = -x, -y, x
    return out
