"""A take's markers drawn from three sides, labelled, so that a person can tell which is which.

The views are along the take's own axes (x to the right and y up; z and y; x and z), one scale
for all three; a take in a camera's frame is seen from wherever that camera stood, so a take can
first be placed in a marker set's head frame (:func:`in_head_frame`), and the views are then the
face's front, side and top. Each marker is drawn at its neutral (the median of the take's first
second where it is seen) with its label and, given a mapping, the motors it drives; head
references are ringed.
With ``motion``, every marker's path over the take is drawn under it, so the markers that move
(lips, brows, lids) stand out from those that ride on the skull.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from capture.markerset import MarkerSet
from capture.take import Take
from common import InputError, atomic_path

VIEWS = (("front", 0, 1, "x", "y"), ("side", 2, 1, "z", "y"), ("top", 0, 2, "x", "z"))
_PANEL, _MARGIN, _TITLE = 520, 40, 30


def neutral_pose(take: Take, seconds: float = 1.0) -> np.ndarray:
    """Each marker's median position over the first ``seconds`` where it is seen, ``(M, 3)``
    (over the whole take for a marker not seen then; NaN for one never seen)."""
    first = take.window(float(take.times[0]), float(take.times[0]) + seconds)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a marker never seen: NaN
        early = np.nanmedian(take.positions[first], axis=0)
        whole = np.nanmedian(take.positions, axis=0)
    return np.where(np.isnan(early), whole, early)


def in_head_frame(take: Take, markerset: MarkerSet) -> Take:
    """``take`` in ``markerset``'s head frame: the head's motion removed frame by frame where
    three of the set's head references are seen (:func:`capture.headframe.stabilise`), then the
    rigid fit of its rest pose onto the set's neutral over the markers both have."""
    from capture.headframe import stabilise

    found = markerset.match(take.labels)
    rest = neutral_pose(take)
    skull = [take.labels.index(found[r]) for r in markerset.head_reference if r in found]
    if len(skull) >= 3 and np.isfinite(rest[skull]).all():
        steady = stabilise(take.positions, skull, rest)
        take = replace(take, positions=np.where(np.isnan(steady), take.positions, steady))
    pairs = [(take.labels.index(mine), markerset.neutral_of(label)) for label, mine in found.items()
             if np.isfinite(rest[take.labels.index(mine)]).all()]
    if len(pairs) < 3:
        raise InputError(f"only {len(pairs)} of its markers are in marker set {markerset.name}: cannot place the "
                         "take in its head frame")
    from common.rotations import rigid_fit

    rotation, translation, _ = rigid_fit(np.array([n for _, n in pairs]), rest[[m for m, _ in pairs]][None])
    return replace(take, positions=(take.positions - translation[0]) @ rotation[0])


def plot_take(take: Take, path: str | os.PathLike, motion: bool = False, head_reference: tuple[str, ...] = (),
              roles: dict[str, str] | None = None, frame: str | None = None) -> Path:
    """Draw ``take`` from three sides into a PNG at ``path``; returns the path.

    Parameters
    ----------
    take : Take
    path : path-like
        A ``.png`` file.
    motion : bool
        Also draw each marker's path over the whole take.
    head_reference : tuple of str
        Labels to ring (a marker set's head references).
    roles : dict of str to str, optional
        Words after a marker's label (the motors a mapping drives from it).
    frame : str, optional
        The head frame the take is in (a marker set's name, see :func:`in_head_frame`): the panels
        are then the face's front, side and top; without one they are named by the take's own
        axes, which need not be the face's.
    """
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise InputError(f"cannot draw markers as {path.suffix or '(no suffix)'!r} (format: .png)", path)
    roles = roles or {}
    rest = neutral_pose(take)
    seen = np.isfinite(rest).all(axis=1)
    if not seen.any():
        raise InputError("no marker is ever seen: nothing to draw", path)
    cloud = take.positions[:, seen].reshape(-1, 3) if motion else rest[seen]
    cloud = cloud[np.isfinite(cloud).all(axis=1)]
    low, high = cloud.min(axis=0), cloud.max(axis=0)
    span = max(float((high - low).max()), 1e-6)
    scale = (_PANEL - 2 * _MARGIN) / span  # pixels per mm, the same in every view
    image = np.full((_PANEL + _TITLE, _PANEL * len(VIEWS), 3), 255, np.uint8)
    centre = (low + high) / 2

    def to_px(points: np.ndarray, h: int, v: int, panel: int) -> np.ndarray:
        x = panel * _PANEL + _PANEL / 2 + (points[..., h] - centre[h]) * scale
        y = _TITLE + _PANEL / 2 - (points[..., v] - centre[v]) * scale
        return np.stack([x, y], axis=-1)

    for panel, (name, h, v, h_name, v_name) in enumerate(VIEWS):
        left = panel * _PANEL
        cv2.rectangle(image, (left + 4, _TITLE), (left + _PANEL - 4, _TITLE + _PANEL - 4), (200, 200, 200), 1)
        title = (f"{name} ({frame}): {h_name} right, {v_name} up" if frame
                 else f"take's {h_name} right, {v_name} up")
        cv2.putText(image, f"{title} ({1 / scale:.2g} mm/px)", (left + 10, 22),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.5, (40, 40, 40), 1, cv2.LINE_AA)
        if motion:
            for m in np.flatnonzero(seen):
                track = to_px(take.positions[:, m], h, v, panel)
                track = track[np.isfinite(track).all(axis=1)].round().astype(np.int32)
                if len(track) > 1:
                    cv2.polylines(image, [track.reshape(-1, 1, 2)], False, (255, 190, 150), 1, cv2.LINE_AA)
        for m in np.flatnonzero(seen):
            x, y = to_px(rest[m], h, v, panel).round().astype(int)
            ringed = take.labels[m] in head_reference
            cv2.circle(image, (int(x), int(y)), 4, (200, 60, 30), -1, cv2.LINE_AA)
            if ringed:
                cv2.circle(image, (int(x), int(y)), 8, (30, 140, 30), 2, cv2.LINE_AA)
            text = f"{take.labels[m]} {roles[take.labels[m]]}" if take.labels[m] in roles else take.labels[m]
            cv2.putText(image, text, (int(x) + 6, int(y) - 5), cv2.FONT_HERSHEY_SIMPLEX, 0.38,
                        (20, 20, 20) if take.labels[m] not in roles else (20, 20, 160), 1, cv2.LINE_AA)
    ok, data = cv2.imencode(".png", image)
    if not ok:
        raise OSError(f"{path}: could not encode the picture")
    with atomic_path(path) as tmp:
        tmp.write_bytes(data.tobytes())
    return path
