"""Head stabilisation: a rigid fit per frame on the head-reference markers."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from common import Failure
from common.rotations import best_rotation, rigid_fit, rotate
from mapping.reference_bridge import bridge_references


def nearest_rotation(matrices: np.ndarray) -> np.ndarray:
    """The rotation nearest (Frobenius) to each ``(..., 3, 3)`` matrix."""
    return best_rotation(matrices)


def to_head_frame(positions: np.ndarray, rotation: np.ndarray, translation: np.ndarray, block: int = 256
                  ) -> np.ndarray:
    """Express world positions in the head frame: ``R.T @ (p - t)`` per frame; ``(F, M, 3)``.

    In blocks of frames: one whole-take temporary costs more in fresh pages than the arithmetic."""
    out = np.empty(np.broadcast_shapes(positions.shape, (len(rotation), 1, 3)))
    for start in range(0, len(out), block):
        part = slice(start, start + block)
        np.matmul(positions[part] - translation[part, None, :], rotation[part], out=out[part])
    return out


def yaw_pitch_degrees(rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Yaw (toward +x) and pitch (face toward +y, chin up) of head rotations, degrees, ``(F,)`` each.

    Inverse of ``Ry(yaw) @ Rx(-pitch)``: the face direction ``R @ [0, 0, 1]`` is
    ``(cos p sin y, sin p, cos p cos y)``.
    """
    face = rotation[:, :, 2]
    yaw = np.degrees(np.arctan2(face[:, 0], face[:, 2]))
    pitch = np.degrees(np.arcsin(np.clip(face[:, 1], -1.0, 1.0)))
    return yaw, pitch


@dataclass(frozen=True, eq=False)
class Stabilised:
    """A take with head motion removed.

    Attributes
    ----------
    local : ndarray, shape (F, M, 3)
        Every marker in the head frame (the marker set's axes), mm; NaN where unseen or where the
        frame has no head pose.
    rotation : ndarray, shape (F, 3, 3)
    translation : ndarray, shape (F, 3)
        Head frame to world per frame (NaN without a pose).
    ok : ndarray of bool, shape (F,)
        Frames with a head pose.
    reference : ndarray, shape (K, 3)
        The head references' shape on this performer (head frame), which the fit used.
    filled : ndarray of bool, shape (F, M), optional
        Samples made up by gap filling (set by cleaning).
    channels : dict of str to ndarray, shape (F,)
        The take's channels by name (blendshape scores), NaN where not measured; they have no
        head frame and pass through as they are.
    """

    local: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    ok: np.ndarray
    reference: np.ndarray
    filled: np.ndarray | None = None
    channels: dict[str, np.ndarray] = field(default_factory=dict)

    def frames(self, part: slice) -> Stabilised:
        """The frames ``part`` of this take (views: nothing copied)."""
        return Stabilised(self.local[part], self.rotation[part], self.translation[part], self.ok[part], self.reference,
                          None if self.filled is None else self.filled[part],
                          {name: values[part] for name, values in self.channels.items()})

    def world(self) -> np.ndarray:
        """``local`` back in world coordinates, ``(F, M, 3)``."""
        return rotate(self.local, self.rotation) + self.translation[:, None, :]


#: Frames fitted at once: each frame's fit stands alone, and a long take's working copies of its
#: references, a few ``(F, K, 3)`` arrays, raised an hour's peak memory by 300 MB with 7 references.
FIT_FRAMES = 1 << 13


def robust_rigid_fit(source: np.ndarray, target: np.ndarray, tolerance: float = 3.0
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`rigid_fit`, then once more without each frame's worst point where it misses by
    more than ``tolerance`` mm the head fitted on the others (a spike or a swapped label on one
    head marker) and at least 3 other points remain. The fit on every point shares out a spike's
    miss among them: a 5 mm spike on one of seven references, the last sample before a gap, where
    no spike test can judge it, missed by 2.4 mm and turned the head by 2.6 degrees. Same shapes
    and meaning as :func:`rigid_fit`; :data:`FIT_FRAMES` frames at a time."""
    if len(target) > FIT_FRAMES:
        parts = [_robust_fit(source, target[start:start + FIT_FRAMES], tolerance)
                 for start in range(0, len(target), FIT_FRAMES)]
        rotations, translations, posed = zip(*parts, strict=True)
        return np.concatenate(rotations), np.concatenate(translations), np.concatenate(posed)
    return _robust_fit(source, target, tolerance)


def _robust_fit(source: np.ndarray, target: np.ndarray, tolerance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`robust_rigid_fit` of one block of frames."""
    rot, trans, ok = rigid_fit(source, target)
    fitted = rotate(np.asarray(source, dtype=np.float64)[None], rot) + trans[:, None, :]
    miss = np.nan_to_num(np.linalg.norm(target - fitted, axis=2), nan=-1.0)  # (F, K); -1 unseen or no pose
    worst = np.argmax(miss, axis=1)
    seen = (~np.isnan(target[..., 0])).sum(axis=1)
    # a point that misses the fit on all by the tolerance is out; with at least OTHERS_JUDGE others
    # seen, one that misses it by SHARED_MISS of the tolerance is tested against the others' fit
    # (a clean frame costs no second fit)
    worst_miss = miss[np.arange(len(miss)), worst]
    suspect = np.flatnonzero(ok & (seen > 3) & ((worst_miss > tolerance) | (
        (worst_miss > SHARED_MISS * tolerance) & (seen > OTHERS_JUDGE))))
    used = ~np.isnan(target[..., 0])
    if len(suspect):
        trimmed = target[suspect].copy()
        trimmed[np.arange(len(suspect)), worst[suspect]] = np.nan
        t_rot, t_trans, _ = rigid_fit(source, trimmed)
        alone = rotate(np.asarray(source, dtype=np.float64)[worst[suspect]][:, None], t_rot)[:, 0] + t_trans
        out = (worst_miss[suspect] > tolerance) | (  # misses the others' head
            np.linalg.norm(target[suspect, worst[suspect]] - alone, axis=1) > tolerance)
        redo = suspect[out]
        rot[redo], trans[redo] = t_rot[out], t_trans[out]
        used[redo, worst[redo]] = False
    weak = ok & ~well_posed(np.asarray(source, dtype=np.float64), used)
    if weak.any():
        rot[weak], trans[weak], ok = np.nan, np.nan, ok & ~weak
    return rot, trans, ok


#: A point missing the fit on all by more than this share of the tolerance is judged against the
#: fit on the others (:func:`robust_rigid_fit`): a spike on one of several references pulls the fit
#: on all by a share of its miss that grows with the point's lever (the 5 mm temple spike: 2.4 mm
#: left); one pinning the fit nearly alone may stay under it, and is kept, as before.
SHARED_MISS = 0.5
#: ... only where more than this many references are seen: three others are no judges (the
#: glue-dot layout's four references sit on the cheeks and brows, and a smile moved two of them).
OTHERS_JUDGE = 4


#: A head fit stands where its seen references pin the worst-pinned rotation at least this share
#: as well as all of them do (:func:`well_posed`).
LEAST_POSED = 0.05


def well_posed(shape: np.ndarray, seen: np.ndarray) -> np.ndarray:
    """Whether the references seen in each frame ``(F, K)`` of ``shape`` ``(K, 3)`` pin the head's
    rotation: the smallest principal moment of inertia of the seen ones about their centre, at
    least :data:`LEAST_POSED` of all of theirs, ``(F,)``.

    Three references seen are enough for a fit but may lie nearly on one line: ``toon32``'s
    forehead, nose bridge and nose tip are all on the face's midline, and a turn about that
    line moves them by so little that 0.3 mm of jitter swings the fitted head by degrees, and
    every marker expressed in it by millimetres. Such a frame has no pose, as one with two
    references seen has none (a short stretch of them is bridged offline, held live).

    >>> shape = np.array([[0, 55, 8], [-66, 12, -28], [66, 12, -28], [0, -6, 14], [0, -44, 32]], float)
    >>> well_posed(shape, np.array([[1, 1, 1, 1, 1], [1, 0, 0, 1, 1], [0, 1, 0, 1, 1]], bool)).tolist()
    [True, False, True]
    """
    return posedness(shape, seen) >= LEAST_POSED


def posedness(shape: np.ndarray, seen: np.ndarray) -> np.ndarray:
    """How well the references seen in each frame ``(F, K)`` of ``shape`` ``(K, 3)`` pin the
    head's rotation, ``(F,)``: the smallest principal moment of inertia of the seen ones about
    their centre over all of theirs (1 with every reference seen; 0 with fewer than three)."""
    out = np.ones(len(seen))
    partial = ~seen.all(axis=1)  # every reference seen pins it fully: nothing to work out (a live frame, mostly)
    if partial.any():
        everything = max(least_moment(shape), 1e-12)
        patterns, inverse = np.unique(seen[partial], axis=0, return_inverse=True)
        share = np.array([least_moment(shape[row]) / everything if row.sum() >= 3 else 0.0 for row in patterns])
        out[partial] = share[inverse.reshape(-1)]
    return out


def least_moment(points: np.ndarray) -> float:
    """The smallest principal moment of inertia of ``points`` ``(K, 3)`` about their centre
    (mm²): how well they pin the rotation they pin worst."""
    centred = points - points.mean(axis=0)
    inertia = np.sum(centred ** 2) * np.eye(3) - centred.T @ centred
    return float(np.linalg.eigvalsh(inertia)[0])


#: At most about this many frames, spread over the take, measure the performer's reference shape.
SHAPE_FRAMES = 1000
#: The references' shape is measured again in the head fitted with it until it moves by under
#: this much (mm), at most :data:`SHAPE_ROUNDS` times.
SHAPE_SETTLED_MM = 0.05
SHAPE_ROUNDS = 6


@dataclass(frozen=True, eq=False)
class HeadFit:
    """The head pose fitted on the references frame by frame, before :func:`bridge_references`.

    Attributes
    ----------
    shape : ndarray, shape (K, 3)
        The references' shape in the head frame that the fit used.
    rotation : ndarray, shape (F, 3, 3)
    translation : ndarray, shape (F, 3)
    ok : ndarray of bool, shape (F,)
    """

    shape: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    ok: np.ndarray


def fit_head(positions: np.ndarray, reference_rows: list[int], reference_neutral: np.ndarray,
             own_shape: bool = True) -> HeadFit | Failure:
    """A robust rigid fit of the head references in every frame.

    A first fit uses the marker set's neutral shape of the references; their median shape in
    the head frame over the take (over :data:`SHAPE_FRAMES` frames spread across it) then
    replaces it, so a performer whose head markers sit a little differently from the marker
    set's gets no frame-to-frame wobble when a reference drops out. That shape is measured
    again in the head fitted with it until it settles (:data:`SHAPE_SETTLED_MM`): measured
    once, in a head fitted with a shape 7 mm too narrow (whose worst-fitting reference the
    robust fit drops), it kept the temples 1.8 mm too narrow, and each fit without one of them
    turned the head by degrees.

    Parameters
    ----------
    positions : ndarray, shape (F, M, 3)
        World positions, NaN where unseen.
    reference_rows : list of int, length K
        Columns of the head-reference markers.
    reference_neutral : ndarray, shape (K, 3)
        Their rest positions in the head frame (the marker set's).
    own_shape : bool
        Measure the performer's own reference shape and fit again with it; False when
        ``reference_neutral`` already is that shape (one fit instead of two).

    Returns
    -------
    HeadFit, or Failure saying why (fewer than 3 references seen in every frame).
    """
    target = positions[:, reference_rows]
    shape = np.asarray(reference_neutral, dtype=np.float64)
    if own_shape:  # measured on frames spread over the take: a median of thousands is no surer
        shape = measured_shape(target[::max(1, len(target) // SHAPE_FRAMES)], shape)
    rot, trans, ok = robust_rigid_fit(shape, target)
    if not ok.any():
        return Failure("fewer than 3 head reference markers are seen in every frame")
    return HeadFit(shape, rot, trans, ok)


def measured_shape(target: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """The performer's own head references ``(K, 3)``, measured on their world positions ``target``
    ``(F, K, 3)`` (NaN unseen) starting from the marker set's ``shape`` ``(K, 3)``: their median in
    the head fitted with the shape so far, until it settles (:data:`SHAPE_SETTLED_MM`, at most
    :data:`SHAPE_ROUNDS` rounds); a reference never seen keeps the set's place, and the origin is
    kept (see :func:`fit_head`; a live sender measures it on its rest, :class:`mapping.stepwise.LiveMapper`)."""
    shape = np.asarray(shape, dtype=np.float64)
    for _ in range(SHAPE_ROUNDS):
        rot, trans, ok = robust_rigid_fit(shape, target)
        if not ok.any():
            break
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a reference never seen keeps the set's shape
            own = np.nanmedian(to_head_frame(target[ok], rot[ok], trans[ok]), axis=0)
        own = np.where(np.isnan(own), shape, own)
        own = own - (own.mean(axis=0) - shape.mean(axis=0))  # keep the origin
        moved = float(np.abs(own - shape).max())
        shape = own
        if moved < SHAPE_SETTLED_MM:
            break
    return shape


def refit_head(fit: HeadFit, positions: np.ndarray, reference_rows: list[int], frames: np.ndarray
               ) -> HeadFit | Failure:
    """``fit`` after some references were taken out of ``frames`` ``(F,)`` of ``positions``: the
    fit is made again there only (with the same shape; every frame's fit stands alone)."""
    rot, trans, ok = fit.rotation.copy(), fit.translation.copy(), fit.ok.copy()
    if frames.any():
        rot[frames], trans[frames], ok[frames] = robust_rigid_fit(fit.shape, positions[frames][:, reference_rows])
    if not ok.any():
        return Failure("fewer than 3 head reference markers are seen in every frame")
    return HeadFit(fit.shape, rot, trans, ok)


def express(positions: np.ndarray, reference_rows: list[int], fit: HeadFit, edge: int = 1,
            fade: float = np.inf) -> Stabilised:
    """The take in the head frame of ``fit``, the pose kept continuous where a reference drops
    out (:func:`bridge_references`, reading up to ``edge`` frames either side, fading over
    ``fade`` frames); the lost reference itself is left to gap filling."""
    rot, trans = bridge_references(positions[:, reference_rows], fit.shape, fit.rotation, fit.translation, fit.ok,
                                   edge, fade)
    return Stabilised(to_head_frame(positions, rot, trans), rot, trans, fit.ok, fit.shape)


def stabilise(positions: np.ndarray, reference_rows: list[int], reference_neutral: np.ndarray,
              own_shape: bool = True) -> Stabilised | Failure:
    """Remove head motion: :func:`express` of :func:`fit_head` (the same parameters)."""
    fit = fit_head(positions, reference_rows, reference_neutral, own_shape)
    return fit if isinstance(fit, Failure) else express(positions, reference_rows, fit)
