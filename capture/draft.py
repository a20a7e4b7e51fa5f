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

from capture.plot import neutral_pose
from capture.scale import check_scale
from capture.take import Take
from common import InputError

#: Head references a draft picks.
REFERENCES = 4
#: The two steadiest references must be at least this far apart (mm), so that the fit is stable.
MIN_SPREAD_MM = 20.0


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
    symmetry_mm : float
        How far the neutral is from its mirror image across the found midline (mean, mm).
    """

    labels: tuple[str, ...]
    neutral: np.ndarray
    head_reference: tuple[str, ...]
    rotation: np.ndarray
    origin: np.ndarray
    steadiness: dict[str, float]
    symmetry_mm: float


def _distance_spread(take: Take, frames: int = 2000) -> np.ndarray:
    """Standard deviation over the take of every pair's distance, ``(M, M)`` (NaN where a pair is
    never seen together)."""
    step = max(1, take.frames // frames)
    pos = take.positions[::step]
    dist = np.linalg.norm(pos[:, :, None, :] - pos[:, None, :, :], axis=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanstd(dist, axis=0)


def head_references(take: Take, spread: np.ndarray, rest: np.ndarray, count: int = REFERENCES) -> list[int]:
    """Columns of the markers that deform least together (see the module docstring), given each
    pair's distance variation ``spread`` ``(M, M)`` and the neutral ``rest`` ``(M, 3)``."""
    apart = np.linalg.norm(rest[:, None] - rest[None], axis=2)
    usable = np.isfinite(spread) & (apart >= MIN_SPREAD_MM)
    if not usable.any():
        raise InputError(f"no two markers are seen together {MIN_SPREAD_MM:g} mm apart: cannot find the head")
    score = np.where(usable, spread, np.inf)
    first, second = np.unravel_index(np.argmin(score), score.shape)
    chosen = [int(first), int(second)]
    while len(chosen) < min(count, take.markers):
        with np.errstate(invalid="ignore"):
            cost = np.nanmax(spread[:, chosen], axis=1)
        cost[chosen] = np.inf
        cost[~np.isfinite(cost)] = np.inf
        candidate = int(np.argmin(cost))
        if not np.isfinite(cost[candidate]):
            break
        chosen.append(candidate)
    if len(chosen) < 3:
        raise InputError("fewer than 3 markers move together with the head: cannot find the head frame")
    return chosen


def _best_mirror(points: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, float]:
    """The unit direction in the plane with normal ``normal`` across which ``points`` (centred)
    are most nearly symmetric, and the mean distance from each mirrored point to its nearest."""
    a = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(normal, a)
    best, best_cost = a, np.inf
    for angle in np.radians(np.arange(0.0, 180.0, 1.0)):
        u = np.cos(angle) * a + np.sin(angle) * b
        mirrored = points - 2.0 * np.outer(points @ u, u)
        cost = float(np.linalg.norm(mirrored[:, None] - points[None], axis=2).min(axis=1).mean())
        if cost < best_cost:
            best, best_cost = u, cost
    return best, best_cost


def _width(cloud: np.ndarray, x: np.ndarray, y: np.ndarray, upper: bool) -> float:
    """The spread across (along ``x``, 10th to 90th percentile) of the upper or lower third."""
    height = cloud @ y
    third = height >= np.percentile(height, 67) if upper else height <= np.percentile(height, 33)
    across = cloud[third] @ x
    return float(np.percentile(across, 90) - np.percentile(across, 10))


def draft_markerset(take: Take, up: str | None = None) -> Draft:
    """Estimate a marker set from ``take`` (see the module docstring); ``up`` names a marker above
    the face's middle (on the forehead), which settles which way is up.

    Raises
    ------
    InputError
        When too few markers are seen to place a head frame, ``up`` is no marker of the take, or
        the take is not the size of a face in millimetres (:mod:`capture.scale`: wrong units).
    """
    if up is not None and up not in take.labels:
        raise InputError(f'no marker "{up}" in the take (its markers: {", ".join(take.labels)})')
    said = take.meta.get("units") or {}
    scale = check_scale(take, None, float(said.get("mm_per_unit", 1.0)))
    if scale.off:  # a draft keeps millimetres: a take in other units would make a wrong layout
        raise InputError(f"{scale.words()}; give --units {scale.likely()}" if said.get("from") != "file"
                         else f"{scale.words()}, not the units its file states", take.meta.get("file"))
    rest = neutral_pose(take)
    seen = np.isfinite(rest).all(axis=1)
    if seen.sum() < 4:
        count = int(seen.sum())
        raise InputError(f"only {count} marker{' is' if count == 1 else 's are'} ever seen: a marker set needs at "
                         "least 4")
    spread = _distance_spread(take)
    refs = head_references(take, spread, rest)
    centre = rest[seen].mean(axis=0)
    cloud = rest[seen] - centre
    _, _, axes = np.linalg.svd(cloud, full_matrices=False)
    z = axes[2]
    radius = np.linalg.norm(cloud - np.outer(cloud @ z, z), axis=1)
    if np.corrcoef(cloud @ z, -radius)[0, 1] < 0:  # the middle (nose) stands out: that is +z
        z = -z
    x, symmetry = _best_mirror(cloud, z)
    y = np.cross(z, x)
    if up is not None:
        if (rest[take.labels.index(up)] - centre) @ y < 0:
            y = -y
    elif _width(cloud, x, y, upper=True) < _width(cloud, x, y, upper=False):  # faces narrow toward the chin
        y = -y
    x = np.cross(y, z)
    rotation = np.array([x, y, z])
    origin = rest[refs].mean(axis=0)
    origin = origin + ((centre - origin) @ x) * x  # on the midline: x = 0 between left and right
    neutral = (rest - origin) @ rotation.T
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        steadiness = {label: float(np.nanmedian(np.delete(spread[i], i))) for i, label in enumerate(take.labels)}
    return Draft(take.labels, neutral, tuple(take.labels[i] for i in refs), rotation, origin, steadiness, symmetry)


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
