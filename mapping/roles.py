"""Which marker is the jaw, which the mouth corners and which the brows, found from how they move.

Laying a preset's markers over a new layout (:mod:`mapping.draft`) finds the roles of markers
placed as some preset places them; a layout unlike every preset keeps few. A face's motion
tells the main roles apart wherever the markers sit, once the head's motion is removed:

* **jaw**: on the midline, below the corners' height or near it, the marker that travels
  furthest downwards from rest, and (as a jaw opens) far more down than up;
* **mouth corners**: the mirror pair (one on each side, at the same height and depth) below the
  brows whose distance apart varies most (a smile spreads them, a pucker draws them in);
* **brows**: markers well above the corners that travel upwards from rest (brows rise far more
  than they fall), per side the medial, central and lateral by their distance from the midline.

The motors that follow from them read the markers as the presets do (MB the jaw's y, inverted;
a corner's x outward and y; a brow's y), in the set's head frame.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.optimize import linear_sum_assignment

from capture import MarkerSet

#: A marker within this distance (mm) of x = 0 is on the midline.
MIDLINE_MM = 10.0
#: A role's motion must reach at least this far (mm) to be told from noise.
MIN_TRAVEL_MM = 3.0
#: Brows lie at least this far (mm) above the mouth corners.
BROW_ABOVE_MM = 40.0
#: A marker's mirror partner lies within this share of the face's size of its mirror image.
PARTNER_FRACTION = 0.15
_LOSS = {"policy": "ease", "seconds": 0.5}


def mirror_partner(neutral: np.ndarray, i: int, within: float, itself: bool = False) -> int | None:
    """The row of ``neutral`` ``(M, 3)`` nearest marker ``i``'s mirror image across the midline
    (x = 0), if within ``within`` mm of it; ``itself``: a marker on the midline may be its own."""
    distance = np.linalg.norm(neutral - neutral[i] * np.array([-1.0, 1.0, 1.0]), axis=1)
    if not itself:
        distance[i] = np.inf
    j = int(np.argmin(distance))
    return j if distance[j] <= within else None


def mirror_pairs(rest: np.ndarray) -> np.ndarray:
    """Each marker's mirror partner across the midline (x = 0) among markers resting at ``rest``
    ``(M, 3)``, ``(M,)`` rows, -1 for none: the pairing of every marker with one whose mirror image
    it is nearest, taken as a whole (an assignment), so that where markers lie close together a
    lid's partner is the other lid, not the pupil beside it that a marker placed 2.5 mm off
    happens to be nearer; a pair further apart than :data:`PARTNER_FRACTION` of the
    face's size is none. A marker on the midline is its own partner; one whose rest is not known
    (NaN: never seen at rest) has none."""
    known = np.isfinite(rest).all(axis=1)
    if not known.any():
        return np.full(len(rest), -1)
    size = float(np.sqrt(np.mean(np.sum((rest[known] - rest[known].mean(axis=0)) ** 2, axis=1))))
    cost = np.linalg.norm(rest[None, :] - (rest * np.array([-1.0, 1.0, 1.0]))[:, None], axis=2)  # (M, M)
    rows, cols = linear_sum_assignment(np.where(np.isfinite(cost), cost, 1e12))  # an unknown rest: never paired
    partner = np.full(len(rest), -1)
    near = cost[rows, cols] <= PARTNER_FRACTION * size
    partner[rows[near]] = cols[near]
    return partner


def motion_roles(markerset: MarkerSet, local: np.ndarray) -> dict[str, dict]:
    """Motor rules (``{code: rule}``, as in a mapping file) for the roles the motion shows.

    Parameters
    ----------
    markerset : MarkerSet
        The layout, its neutral in its head frame.
    local : ndarray, shape (F, M, 3)
        The take in that head frame, head motion removed (:func:`capture.plot.in_head_frame`),
        columns in ``markerset.labels`` order (NaN where unseen). Each marker's travel is
        measured from where it mostly is (its median), so a neutral a little off does not tilt
        it; where markers lie is read from the set's neutral.
    """
    neutral = markerset.neutral
    size = float(np.sqrt(np.mean(np.sum((neutral - neutral.mean(axis=0)) ** 2, axis=1))))
    skull = {markerset.labels.index(r) for r in markerset.head_reference}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        moves = local - np.nanmedian(local, axis=0)[None]  # from where each marker mostly is: a face at rest
        low, high = np.nanpercentile(moves, 2, axis=0), np.nanpercentile(moves, 98, axis=0)  # (M, 3) each
    free = [m for m in range(len(neutral)) if m not in skull and np.isfinite(low[m]).all()]
    rules: dict[str, dict] = {}
    corners = _corners(neutral, local, free, size)
    if corners is not None:
        right, left = corners
        rules |= {"MLH": _rule(markerset.labels[left], "x"), "MLV": _rule(markerset.labels[left], "y"),
                  "MRH": _rule(markerset.labels[right], "x", invert=True), "MRV": _rule(markerset.labels[right], "y")}
    mouth_y = float(neutral[list(corners), 1].mean()) if corners is not None else None
    jaw = [m for m in free if abs(neutral[m, 0]) <= MIDLINE_MM and -low[m, 1] >= MIN_TRAVEL_MM
           and -low[m, 1] > 2 * max(high[m, 1], 0.0) and (mouth_y is None or neutral[m, 1] <= mouth_y + 5.0)]
    if jaw:
        rules["MB"] = _rule(markerset.labels[max(jaw, key=lambda m: -low[m, 1])], "y", invert=True)
    if mouth_y is not None:
        rises = [m for m in free if neutral[m, 1] >= mouth_y + BROW_ABOVE_MM and high[m, 1] >= MIN_TRAVEL_MM
                 and high[m, 1] > 1.5 * max(-low[m, 1], 0.0)]
        for side, sign in (("L", 1.0), ("R", -1.0)):
            brows = sorted((m for m in rises if sign * neutral[m, 0] > MIDLINE_MM / 2),
                           key=lambda m: abs(neutral[m, 0]))
            if not brows:
                continue
            medial, lateral = brows[0], brows[-1]
            central = brows[len(brows) // 2] if len(brows) >= 3 else None
            rules[f"B{side}M"] = _rule(markerset.labels[medial], "y")
            rules[f"B{side}L"] = _rule(markerset.labels[lateral], "y")
            if central is not None or medial == lateral:
                rules[f"B{side}C"] = _rule(markerset.labels[medial if central is None else central], "y")
            else:
                rules[f"B{side}C"] = {"sources": [{"marker": markerset.labels[medial], "axis": "y"},
                                                  {"marker": markerset.labels[lateral], "axis": "y"}],
                                      "combine": "mean", "loss": _LOSS}
    return rules


def _corners(neutral: np.ndarray, local: np.ndarray, free: list[int], size: float) -> tuple[int, int] | None:
    """The mirror pair ``(right, left)`` whose distance apart varies most, if it varies at all."""
    best, best_reach = None, MIN_TRAVEL_MM
    for i in free:
        j = mirror_partner(neutral, i, PARTNER_FRACTION * size)
        if j is None or j not in free or neutral[i, 0] <= MIDLINE_MM:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            apart = np.linalg.norm(local[:, i] - local[:, j], axis=1)
            reach = float(np.nanpercentile(apart, 98) - np.nanpercentile(apart, 2))
        if reach > best_reach:
            best, best_reach = (j, i), reach
    return best


def _rule(marker: str, axis: str, invert: bool = False) -> dict:
    source: dict = {"marker": marker, "axis": axis}
    if invert:
        source["invert"] = True
    return {"sources": [source], "loss": _LOSS}
