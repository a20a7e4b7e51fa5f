"""Where a face is and which way it points, found from a take's markers and their motion.

A draft marker set (:mod:`capture.draft`) needs the markers that ride on the skull and the head
frame's axes (x to the performer's left, y up, z out of the face). The first rule used for the
axes, the layout's thinnest extent as depth and its wider end as up, failed on a real layout as
deep as it is tall recorded in a camera frame with z up. These rules use what every face has:

* **skull** (:func:`rigid_group`): the largest group of markers whose mutual distances all stay
  within the take's noise (the skull does not deform); a group of brows that rise together is
  rigid too, but smaller, and a lone lip marker that barely moves does not stay within the
  noise of every skull marker;
* **x** (:func:`mirror_normal`): the normal of the plane across which the face is most nearly
  its own mirror image, searched over every direction (not only in a plane guessed first);
* **y**: in that plane, the line of the markers on the midline (forehead, nose, lips, chin: a
  face's profile) where three or more span 60 mm, else the direction along which the markers
  move most once the head's motion is removed (a jaw opens, brows rise, lids close: a face
  moves up and down, though brows and jaw also swing forward and back); up, not down, from the
  marker that moves most (:func:`_up_votes`): on the midline it is the jaw, below the skull and
  opening downwards; beside it a brow or a mouth corner, rising from rest;
* **z** = x × y, x's sign chosen so that z points out of the face: the markers near the midline
  (nose, lips) stand further forward than those at the sides.

Each cue's strength is kept (:class:`Frame`), so that a draft can say how sure it is and ask for
``--up``/``--front MARKER`` only where the data cannot tell.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from common import InputError

#: Skull markers must spread at least this far (mm) for a stable head frame.
MIN_SPREAD_MM = 20.0
#: A pair is rigid when its distance strays by at most this many times the take's noise floor
#: (the least straying of all pairs).
RIGID_FACTOR = 2.0
#: The noise floor is never taken below this (mm): clean synthetic takes have none.
MIN_NOISE_MM = 0.15
#: Markers within this distance (mm) of the mirror plane are on the midline (forehead, nose, lips, chin).
MIDLINE_MM = 5.0
#: The midline markers give y where they span at least this much (mm) of the face's height.
PROFILE_MM = 60.0


@dataclass(frozen=True)
class Frame:
    """A head frame found from a take, and how sure each of its cues is.

    Attributes
    ----------
    rotation : ndarray, shape (3, 3)
        Rows: x, y, z in the take's coordinates.
    skull : tuple of int
        Columns of the markers found to ride on the skull.
    symmetry_mm : float
        Mean distance from each mirrored marker to its nearest marker.
    vertical : float
        Share (0..1) of the in-plane motion variance along its main direction: near 1 when the
        face moves up and down, near 0.5 when no direction stands out.
    up_votes : tuple of int
        The two up cues (+1 agrees with the y chosen, -1 disagrees, 0 cannot tell): the skull above
        the largest mover (when that is the jaw), and the largest mover's one-sided travel.
    front_mm : float
        How much further forward (mm) the midline markers stand than the side ones.
    doubts : tuple of str
        What the data could not settle, in words, with the option that settles it.
    """

    rotation: np.ndarray
    skull: tuple[int, ...]
    symmetry_mm: float
    vertical: float
    up_votes: tuple[int, int]
    front_mm: float
    doubts: tuple[str, ...] = field(default=())


def _pair_distances(positions: np.ndarray, frames: int) -> np.ndarray:
    """Every pair's distance in about ``frames`` frames spread over the take, ``(F', M, M)``."""
    pos = positions[::max(1, len(positions) // frames)]
    return np.linalg.norm(pos[:, :, None, :] - pos[:, None, :, :], axis=3)


def distance_spread(positions: np.ndarray, frames: int = 2000) -> np.ndarray:
    """Standard deviation over the take of every pair's distance, ``(M, M)``, from positions
    ``(F, M, 3)`` (NaN where a pair is never seen together)."""
    dist = _pair_distances(positions, frames)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanstd(dist, axis=0)


def distance_reach(positions: np.ndarray, frames: int = 4000, share: float = 99.0) -> np.ndarray:
    """How far every pair's distance strays from its median, ``(M, M)``: the ``share`` percentile
    of the absolute deviation over the take. Unlike a standard deviation it sees what a marker
    does now and then: a lid that shuts in blinks, 6 % of the time, strays by its full travel."""
    dist = _pair_distances(positions, frames)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanpercentile(np.abs(dist - np.nanmedian(dist, axis=0)), share, axis=0)


def rigid_group(spread: np.ndarray, rest: np.ndarray) -> list[int]:
    """The columns of the largest group of markers rigid together (see the module docstring),
    given how far each pair's distance strays, ``spread`` ``(M, M)`` (:func:`distance_reach`),
    and the rest pose ``(M, 3)``; ties go to the group that strays least."""
    markers = len(rest)
    off = spread[~np.eye(markers, dtype=bool)]
    off = off[np.isfinite(off)]
    if not len(off):
        raise InputError("no two markers are seen together: cannot find the head")
    noise = max(float(np.percentile(off, 5)), MIN_NOISE_MM)
    rigid = np.isfinite(spread) & (spread <= RIGID_FACTOR * noise)
    np.fill_diagonal(rigid, True)
    best: list[int] = []
    best_cost = np.inf
    for seed in range(markers):  # grow a group greedily from each marker; M is tens at most
        group = [seed]
        while True:
            fits = [m for m in range(markers) if m not in group and rigid[m, group].all()]
            if not fits:
                break
            group.append(min(fits, key=lambda m: float(spread[m, group].max())))
        cost = float(np.nanmax(spread[np.ix_(group, group)])) if len(group) > 1 else np.inf
        if len(group) > len(best) or (len(group) == len(best) and cost < best_cost):
            best, best_cost = group, cost
    apart = np.linalg.norm(rest[best][:, None] - rest[best][None], axis=2) if len(best) > 1 else np.zeros((1, 1))
    if len(best) < 3 or not np.isfinite(apart).all() or apart.max() < MIN_SPREAD_MM:
        raise InputError(f"fewer than 3 markers at least {MIN_SPREAD_MM:g} mm apart move together with the head: "
                         "cannot find the head frame")
    return sorted(best)


def stabilise(positions: np.ndarray, skull: list[int], rest: np.ndarray) -> np.ndarray:
    """Positions ``(F, M, 3)`` with the head's motion removed: each frame turned and moved so that
    its skull markers lie on theirs in ``rest`` (a frame that sees fewer than 3 of them is NaN)."""
    from common.rotations import rigid_fit

    rotation, translation, _ = rigid_fit(rest[skull], positions[:, skull])  # rest -> each frame
    return np.einsum("fmi,fij->fmj", positions - translation[:, None], rotation)  # each frame -> rest


def _fibonacci(count: int) -> np.ndarray:
    """``count`` directions spread evenly over a hemisphere, ``(count, 3)``."""
    k = np.arange(count) + 0.5
    z = k / count
    phi = np.pi * (1 + 5 ** 0.5) * k
    r = np.sqrt(1 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def _mirror_cost(points: np.ndarray, normal: np.ndarray) -> float:
    mirrored = points - 2.0 * np.outer(points @ normal, normal)
    return float(np.linalg.norm(mirrored[:, None] - points[None], axis=2).min(axis=1).mean())


def mirror_normal(points: np.ndarray) -> tuple[np.ndarray, float]:
    """The unit normal of the plane through the centroid of ``points`` ``(M, 3)`` across which
    they are most nearly symmetric, searched over every direction and refined, and the mean
    distance (mm) from each mirrored point to its nearest."""
    centred = points - points.mean(axis=0)
    candidates = _fibonacci(3000)
    costs = np.array([_mirror_cost(centred, n) for n in candidates])
    best = candidates[int(np.argmin(costs))]
    step = np.radians(2.0)
    while step > np.radians(0.05):  # refine about the best
        a = np.cross(best, [1.0, 0.0, 0.0] if abs(best[0]) < 0.9 else [0.0, 1.0, 0.0])
        a /= np.linalg.norm(a)
        b = np.cross(best, a)
        nearby = [best] + [best + step * (i * a + j * b) for i in (-1, 0, 1) for j in (-1, 0, 1) if i or j]
        nearby = [n / np.linalg.norm(n) for n in nearby]
        cost = [_mirror_cost(centred, n) for n in nearby]
        if int(np.argmin(cost)) == 0:
            step /= 2
        best = nearby[int(np.argmin(cost))]
    return best, _mirror_cost(centred, best)


def _in_plane(direction: np.ndarray, normal: np.ndarray) -> np.ndarray:
    along = direction - (direction @ normal) * normal
    return along / np.linalg.norm(along)


def _profile(points: np.ndarray, normal: np.ndarray) -> np.ndarray | None:
    """The direction of the face's profile, forehead to chin: the main axis of the markers on
    the midline (within :data:`MIDLINE_MM` of the plane with ``normal``), where at least three
    of them span :data:`PROFILE_MM`; None otherwise. ``points``: ``(M, 3)``, centred."""
    across = points @ normal
    on = points[np.abs(across) <= MIDLINE_MM]
    if len(on) < 3:
        return None
    flat = on - np.outer(on @ normal, normal)
    flat = flat - flat.mean(axis=0)
    _, values, vectors = np.linalg.svd(flat, full_matrices=False)
    main = _in_plane(vectors[0], normal)
    extent = np.ptp(flat @ main)
    return main if extent >= PROFILE_MM else None


def _up_votes(local: np.ndarray, rest: np.ndarray, skull: list[int], mover: int, centre: np.ndarray, x: np.ndarray,
              y: np.ndarray) -> tuple[int, int]:
    """The two up cues for ``y`` (+1: it points up, -1: down, 0: cannot tell), from the marker
    that moves most. On the midline it is the jaw (a lip, the chin): the skull lies above it, and
    it travels from rest downwards (a jaw opens). Beside the midline it is a brow or a mouth
    corner: where the skull lies says nothing (a take of brows alone has a still lower face),
    and it travels from rest upwards (brows rise, a smile lifts the corners)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        along = (local[:, mover] - rest[mover]) @ y
        lo, hi = np.nanpercentile(along, [2, 98]) if np.isfinite(along).any() else (0.0, 0.0)
    one_sided = int(np.sign(lo + hi)) if abs(lo + hi) > 0.25 * max(hi - lo, 1e-9) else 0
    if abs(float((rest[mover] - centre) @ x)) > 2 * MIDLINE_MM:
        return 0, one_sided
    above = float((rest[skull].mean(axis=0) - rest[mover]) @ y)
    return (int(np.sign(above)) if abs(above) > 5.0 else 0), -one_sided


def find_frame(positions: np.ndarray, rest: np.ndarray, up: int | None = None, front: int | None = None) -> Frame:
    """The head frame of a take's ``positions`` ``(F, M, 3)`` about its ``rest`` ``(M, 3)`` (see the
    module docstring); ``up`` and ``front`` are columns of a marker above the face's middle and
    one on its front (the nose), which settle y's and z's signs where given."""
    seen = np.isfinite(rest).all(axis=1)
    spread = distance_reach(positions)
    skull = rigid_group(np.where(np.outer(seen, seen), spread, np.nan), np.where(seen[:, None], rest, np.nan))
    local = stabilise(positions, skull, rest)
    centre = rest[seen].mean(axis=0)
    x, symmetry = mirror_normal(rest[seen])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        moves = local - rest[None]
        moves = moves - np.outer(moves.reshape(-1, 3) @ x, x).reshape(moves.shape)  # in the midline plane
        flat = moves[np.isfinite(moves).all(axis=2)]
        travel = np.nanstd(np.linalg.norm(local - rest[None], axis=2), axis=0)
    covariance = flat.T @ flat / max(len(flat), 1)
    values, vectors = np.linalg.eigh(covariance)
    y = _in_plane(vectors[:, 2], x)
    in_plane = values[1] + values[2]
    vertical = float(values[2] / in_plane) if in_plane > 0 else 0.5
    profile = _profile(rest[seen] - centre, x)
    doubts = []
    if profile is not None:  # the markers on the midline, forehead to chin, are the steadier cue
        y = profile if profile @ y >= 0 else -profile
    travel[skull] = 0.0
    mover = int(np.nanargmax(np.where(seen, travel, -1.0)))
    votes = _up_votes(local, rest, skull, mover, centre, x, y)
    if up is not None:
        sign = 1 if (rest[up] - centre) @ y >= 0 else -1
    elif sum(votes) != 0:  # both agree, or one tells and the other cannot
        sign = 1 if sum(votes) > 0 else -1
    else:
        sign = 1
        doubts.append("which way is up: the skull and the largest mover's travel disagree or are unclear; "
                      "give --up MARKER (one on the forehead)")
    y = sign * y
    votes = (votes[0] * sign, votes[1] * sign)
    z = np.cross(x, y)
    across = (rest[seen] - centre) @ x
    middle = np.abs(across) <= np.median(np.abs(across))
    front_mm = float(((rest[seen] - centre) @ z)[middle].mean() - ((rest[seen] - centre) @ z)[~middle].mean())
    if front is not None:
        flip = (rest[front] - centre) @ z < 0
    else:
        flip = front_mm < 0
        if abs(front_mm) < 5.0:
            doubts.append(f"which way the face points: its middle stands only {abs(front_mm):.1f} mm out from its "
                          "sides; give --front MARKER (one on the nose)")
    if flip:
        x, z, front_mm = -x, -z, -front_mm
    if vertical < 0.6:
        doubts.append(f"which way is up: the face's motion has no main direction ({vertical:.0%} of it along the "
                      "one found); use a take with expressions and speech, or give --up MARKER")
    if symmetry > 8.0:
        doubts.append(f"the midline: the layout mirrors only to within {symmetry:.0f} mm; check the plot")
    return Frame(np.array([x, y, z]), tuple(skull), symmetry, vertical, votes, front_mm, tuple(doubts))


def sparse_frame(positions: np.ndarray, rest: np.ndarray, up: int | None = None, front: int | None = None) -> Frame:
    """The head frame of a take of three markers, a jaw (a lip, the chin) and the mouth corners,
    which cannot fix a head pose: the corners are the pair the third lies equally far from, x
    runs between them, y is the jaw's main travel against the corners' midpoint (down the way it
    opens from rest), z points from the corners toward the jaw (the lips stand in front of the
    corners), and x = y × z. The head's own motion stays in the take: :attr:`Frame.doubts` says so."""
    if len(rest) != 3 or not np.isfinite(rest).all():
        raise InputError("a layout of fewer than 4 markers needs exactly 3, each seen: a jaw and the mouth corners")
    apart = np.linalg.norm(rest[:, None] - rest[None], axis=2)
    jaw = int(np.argmin([abs(apart[k, (k + 1) % 3] - apart[k, (k + 2) % 3]) for k in range(3)]))
    corners = [(jaw + 1) % 3, (jaw + 2) % 3]
    x = rest[corners[1]] - rest[corners[0]]
    x /= np.linalg.norm(x)
    mid = positions[:, corners].mean(axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        moves = (positions[:, jaw] - mid) - (rest[jaw] - rest[corners].mean(axis=0))
        moves = moves[np.isfinite(moves).all(axis=1)]
    moves = moves - np.outer(moves @ x, x)
    values, vectors = np.linalg.eigh(moves.T @ moves / max(len(moves), 1))
    y = _in_plane(vectors[:, 2], x)
    lo, hi = np.percentile(moves @ y, [2, 98]) if len(moves) else (0.0, 0.0)
    opens = int(np.sign(lo + hi)) if abs(lo + hi) > 0.25 * max(hi - lo, 1e-9) else 0
    doubts = ["head motion is not removed: three markers cannot fix a head frame, so a nod moves the jaw's "
              "motors as a jaw drop would; add three markers on the skull (forehead, temples, nose bridge) for it"]
    if up is not None:
        y = y if (rest[up] - rest[corners].mean(axis=0)) @ y >= 0 else -y
    elif opens:
        y = -opens * y  # the jaw opens downwards
    else:
        doubts.append("which way is up: the jaw's travel does not say; give --up MARKER")
    ahead = (rest[jaw] - rest[corners].mean(axis=0)) - ((rest[jaw] - rest[corners].mean(axis=0)) @ y) * y
    if front is not None:
        ahead = rest[front] - rest[corners].mean(axis=0) if front != jaw else ahead
    ahead = ahead - (ahead @ x) * x
    if np.linalg.norm(ahead) < 2.0:
        doubts.append("which way the face points: the jaw is level with the corners; give --front MARKER")
        ahead = np.cross(x, y)
    z = ahead / np.linalg.norm(ahead)
    z = z - (z @ y) * y
    z /= np.linalg.norm(z)
    x = np.cross(y, z)
    vertical = float(values[2] / max(values[1] + values[2], 1e-12))
    return Frame(np.array([x, y, z]), (), 0.0, vertical, (0, opens and 1), float(np.linalg.norm(ahead)),
                 tuple(doubts))
