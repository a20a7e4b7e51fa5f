"""Contact sheets in one PNG: every expression of a repertoire on one face, or frames picked through a
motor track, each labelled."""

from __future__ import annotations

import math
import os
from pathlib import Path

import cv2
import numpy as np

from common import InputError, atomic_path
from player.backends import open_renderer
from player.offline import undrawn_extras
from toon import Expression, FaceRig, MotorTrack

_LABEL_HEIGHT = 28


def expression_sheet(rig: FaceRig, expressions: dict[str, Expression], cell: tuple[int, int] = (256, 256),
                     columns: int = 0, samples: int = 4) -> np.ndarray:
    """Render each expression on a face into a labelled grid, then each of the face's parameters
    beyond the 21 at its extremes (:func:`parameter_poses`).

    Parameters
    ----------
    rig : FaceRig
        The face, prepared.
    expressions : dict of name to Expression
        In the order to show them.
    cell : (width, height)
        Pixels of each face picture.
    columns : int
        Pictures per row; 0 picks a near-square grid.

    Returns
    -------
    ndarray of uint8, shape (rows * (height + 28), columns * width, 3)
        RGB; each picture has its expression's name written under it.
    """
    neutral = rig.face.neutral()
    declared = rig.face.extra_neutral()
    poses: list[Pose] = [(name, expression.pose(neutral), expression.extra_pose(declared))
                         for name, expression in expressions.items()]
    return labelled_grid(rig, [*poses, *parameter_poses(rig)], cell, columns, samples)


#: A picture of a contact sheet: its label, the 21 motor values ``(21,)`` and extra parameters by code.
Pose = tuple[str, np.ndarray, dict[str, float]]


def parameter_poses(rig: FaceRig) -> list[Pose]:
    """The face at rest with each of its extra parameters (HT, UL...) at the ends of its range away
    from its neutral (both ends for one that rests between them), labelled ``"UL 1"``."""
    neutral = rig.face.neutral()
    poses: list[Pose] = []
    for code, rest in rig.face.extra_neutral().items():
        poses += [(f"{code} {end}", neutral, {code: float(end)}) for end in (0, 1) if end != rest]
    return poses


def track_sheet(rig: FaceRig, track: MotorTrack, count: int = 12, cell: tuple[int, int] = (192, 192),
                columns: int = 4, samples: int = 4) -> np.ndarray:
    """A contact sheet of a motor track: ``count`` frames evenly spaced from its first to its last,
    each labelled with its time, in a grid ``columns`` wide (fewer frames for a shorter track).

    Returns
    -------
    ndarray of uint8, shape (rows * (height + 28), columns * width, 3)
        RGB.
    """
    picks = np.unique(np.round(np.linspace(0, track.frames - 1, min(count, track.frames))).astype(int))
    skipped = undrawn_extras(track, rig.face)
    table = track.table()
    poses: list[Pose] = [(f"{track.times[i]:.2f} s", track.values[i],
                          {k: v for k, v in track.extra_at(table[i]).items() if k not in skipped}) for i in picks]
    return labelled_grid(rig, poses, cell, min(columns, len(poses)), samples)


def labelled_grid(rig: FaceRig, poses: list[Pose], cell: tuple[int, int] = (256, 256),
                  columns: int = 0, samples: int = 4) -> np.ndarray:
    """Render poses ``(label, values (21,), extra parameters)`` on a face into a grid, each labelled
    under it.

    ``columns`` 0 picks a near-square grid. Returns RGB uint8 of shape
    ``(rows * (height + 28), columns * width, 3)``.
    """
    width, height = cell
    columns = columns or math.ceil(math.sqrt(len(poses)))
    rows = math.ceil(len(poses) / columns)
    sheet = np.full((rows * (height + _LABEL_HEIGHT), columns * width, 3), 255, dtype=np.uint8)
    with open_renderer(cell, samples) as renderer:
        for i, (label, values, extra) in enumerate(poses):
            top, left = (i // columns) * (height + _LABEL_HEIGHT), (i % columns) * width
            sheet[top:top + height, left:left + width] = renderer.render(rig.geometry(values, extra))
            _label(sheet, label, left, top + height, width)
    return sheet


def _label(sheet: np.ndarray, text: str, left: int, top: int, width: int) -> None:
    font, scale, thickness = cv2.FONT_HERSHEY_SIMPLEX, 0.6, 1
    (w, h), _ = cv2.getTextSize(text, font, scale, thickness)
    org = (left + max((width - w) // 2, 2), top + (_LABEL_HEIGHT + h) // 2)
    cv2.putText(sheet, text, org, font, scale, (20, 20, 20), thickness, cv2.LINE_AA)


def check_image_suffix(path: str | os.PathLike) -> None:
    """Refuse a path whose suffix names no picture format :func:`save_image` writes."""
    suffix = Path(path).suffix.lower()
    if suffix not in IMAGE_SUFFIXES:
        raise InputError(f"cannot write a picture as {suffix or '(no suffix)'!r} (formats: "
                         f"{', '.join(IMAGE_SUFFIXES)})", path)


#: Picture formats :func:`save_image` writes, by suffix (OpenCV's encoders).
IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".webp", ".bmp", ".tif", ".tiff")


def save_image(image: np.ndarray, path: str | os.PathLike) -> Path:
    """Write an RGB image ``(H, W, 3)`` in the format its suffix names, atomically.

    Raises
    ------
    InputError
        For a suffix that names no picture format (the known ones are listed).
    """
    path = Path(path)
    check_image_suffix(path)
    ok, data = cv2.imencode(path.suffix.lower(), np.ascontiguousarray(image[:, :, ::-1]))
    if not ok:
        raise OSError(f"{path}: could not encode the picture")
    with atomic_path(path) as tmp:
        tmp.write_bytes(data.tobytes())
    return path
