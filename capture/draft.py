"""A draft marker set from a take of a layout toonface has not seen.

Three things make a marker set usable: which markers ride on the skull (the head references),
the head frame's axes (x to the performer's left, y up, z out of the face), and every marker's
neutral in that frame, in millimetres. From a take alone they are estimated so:

* **head references**: the markers whose mutual distances vary least over the take (the skull
  does not deform; lips, brows and lids do), grown greedily from the steadiest pair that is at
  least :data:`MIN_SPREAD_MM` apart, up to :data:`REFERENCES` markers;
* **z**: the normal of the plane the neutral face fits best, pointing to where the face bulges
  (its middle stands further out than its edges);
* **x**: the direction in that plane across which the face is most nearly symmetric;
* **y**: z x x, turned so that a marker named as above the middle (``up``, a forehead marker) is
  above it; without one, so that the face is wider in its upper third than its lower (true of
  toon32 and the glue dots, not of AnimFace, whose chin row is wide: give ``up`` there); x is
  then y x z.

The origin is on the midline at the height and depth of the head references' centroid (the head
frame's is between the eyes; only differences matter to mapping). Everything found is said in
the draft's comments, to be checked with ``toonface info TAKE --plot`` and edited.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from capture.headframe import Frame, distance_spread, find_frame, sparse_frame
from capture.plot import neutral_pose
from capture.scale import check_scale
from capture.take import Take
from common import InputError


@dataclass(frozen=True)
class Draft:
    """A marker set estimated from a take (see the module docstring).

    Attributes
    ----------
    labels : tuple of str, length M
    neutral : ndarray, shape (M, 3)
        In the estimated head frame, mm.
    head_reference : tuple of str
    rotation : ndarray, shape (3, 3)
        Rows: the head frame's x, y and z axes in the take's coordinates.
    origin : ndarray, shape (3,)
        The head frame's origin in the take's coordinates.
    steadiness : dict of str to float
        Each marker's median variation (mm, standard deviation over the take) of its distances
        to the others: small for markers on the skull.
    frame : Frame
        How the axes were found and how sure each cue is (:mod:`capture.headframe`).
    """

    labels: tuple[str, ...]
    neutral: np.ndarray
    head_reference: tuple[str, ...]
    rotation: np.ndarray
    origin: np.ndarray
    steadiness: dict[str, float]
    frame: Frame

    @property
    def symmetry_mm(self) -> float:
        """How far the neutral is from its mirror image across the found midline (mean, mm)."""
        return self.frame.symmetry_mm


def draft_markerset(take: Take, up: str | None = None, front: str | None = None) -> Draft:
    """Estimate a marker set from ``take`` (see the module docstring); ``up`` names a marker above
    the face's middle (on the forehead) and ``front`` one on its front (the nose), which settle
    which way is up and which way the face points where the take's motion cannot.

    Raises
    ------
    InputError
        When too few markers are seen to place a head frame, ``up`` or ``front`` is no marker of
        the take, or the take is not the size of a face in millimetres (:mod:`capture.scale`:
        wrong units).
    """
    for option, name in (("--up", up), ("--front", front)):
        if name is not None and name not in take.labels:
            raise InputError(f'{option}: no marker "{name}" in the take (its markers: {", ".join(take.labels)})')
    said = take.meta.get("units") or {}
    scale = check_scale(take, None, float(said.get("mm_per_unit", 1.0)))
    if scale.off:  # a draft keeps millimetres: a take in other units would make a wrong layout
        raise InputError(f"{scale.words()}; give --units {scale.likely()}" if said.get("from") != "file"
                         else f"{scale.words()}, not the units its file states", take.meta.get("file"))
    rest = neutral_pose(take)
    seen = np.isfinite(rest).all(axis=1)
    if seen.sum() < 4:
        count = int(seen.sum())
        if count != 3 or take.markers != 3:
            raise InputError(f"only {count} marker{' is' if count == 1 else 's are'} ever seen: a marker set needs at "
                             "least 4, or 3 on a jaw and the mouth corners")
        return _sparse(take, rest, up, front)
    frame = find_frame(take.positions, rest, None if up is None else take.labels.index(up),
                       None if front is None else take.labels.index(front))
    x, _, _ = frame.rotation
    refs = list(frame.skull)
    centre = rest[seen].mean(axis=0)
    origin = rest[refs].mean(axis=0)
    origin = origin + ((centre - origin) @ x) * x  # on the midline: x = 0 between left and right
    neutral = (rest - origin) @ frame.rotation.T
    return Draft(take.labels, neutral, tuple(take.labels[i] for i in refs), frame.rotation, origin, _steadiness(take),
                 frame)


def _steadiness(take: Take) -> dict[str, float]:
    """Each marker's median variation (mm) of its distances to the others."""
    spread = distance_spread(take.positions)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return {label: float(np.nanmedian(np.delete(spread[i], i))) for i, label in enumerate(take.labels)}


def _sparse(take: Take, rest: np.ndarray, up: str | None, front: str | None) -> Draft:
    """A draft of three markers, a jaw and the mouth corners (:func:`capture.headframe.sparse_frame`):
    no head references, the origin between the corners."""
    frame = sparse_frame(take.positions, rest, None if up is None else take.labels.index(up),
                         None if front is None else take.labels.index(front))
    corners = rest[np.argsort(np.abs((rest - rest.mean(axis=0)) @ frame.rotation[0]))[1:]]
    origin = corners.mean(axis=0)
    neutral = (rest - origin) @ frame.rotation.T
    return Draft(take.labels, neutral, (), frame.rotation, origin, _steadiness(take), frame)


@dataclass(frozen=True)
class Match:
    """A take's columns matched to a marker set's labels by the shape of their neutrals.

    Attributes
    ----------
    labels : tuple of str
        For each column of the take, the marker set label it is.
    distance : ndarray, shape (M,)
        Each column's distance (mm) from its label's neutral after the best rigid fit.
    rms_mm : float
    """

    labels: tuple[str, ...]
    distance: np.ndarray
    rms_mm: float


def match_layout(take: Take, labels: tuple[str, ...], neutral: np.ndarray, rounds: int = 20) -> Match:
    """Which of ``labels`` (a marker set's, with neutrals ``(M, 3)`` in mm) each column of ``take``
    is, by shape alone: the columns' neutral is turned onto the set's (its principal axes, each
    of the four right-handed sign choices tried) and matched one to one (Hungarian), then the fit
    and the matching are refined in turn.

    Raises
    ------
    InputError
        When the take and the set have different numbers of markers, or markers never seen.
    """
    from scipy.optimize import linear_sum_assignment

    rest = neutral_pose(take)
    if len(rest) != len(labels):
        raise InputError(f"the take has {len(rest)} markers and the marker set {len(labels)}: cannot match them")
    if not np.isfinite(rest).all():
        raise InputError("some markers are never seen in the take: cannot match them by shape")
    source = rest - rest.mean(axis=0)
    target = neutral - neutral.mean(axis=0)
    _, _, axes_s = np.linalg.svd(source, full_matrices=False)
    _, _, axes_t = np.linalg.svd(target, full_matrices=False)
    best: tuple[float, np.ndarray, np.ndarray] | None = None
    for signs in ((1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)):
        turn = axes_t.T @ np.diag(signs) @ axes_s  # the take's axes onto the set's
        if np.linalg.det(turn) < 0:
            turn = axes_t.T @ np.diag([signs[0], signs[1], -signs[2]]) @ axes_s
        for _ in range(rounds):
            moved = source @ turn.T
            cost = np.linalg.norm(moved[:, None] - target[None], axis=2)
            rows, cols = linear_sum_assignment(cost)
            u, _, vt = np.linalg.svd(source[rows].T @ target[cols])
            fix = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
            turn = (u @ fix @ vt).T
        moved = source @ turn.T
        distance = np.linalg.norm(moved[rows] - target[cols], axis=1)
        rms = float(np.sqrt(np.mean(distance ** 2)))
        if best is None or rms < best[0]:
            best = (rms, cols.copy(), distance)
    assert best is not None
    rms, cols, distance = best
    return Match(tuple(labels[c] for c in cols), distance, rms)
