"""Contact sheets: every expression of a repertoire on one face, labelled, in one PNG."""

from __future__ import annotations

import math
import os
from pathlib import Path

import cv2
import numpy as np

from common import atomic_path
from player.gl import create_context
from player.renderer import Renderer
from toon import Expression, FaceRig

_LABEL_HEIGHT = 28


def expression_sheet(rig: FaceRig, expressions: dict[str, Expression], cell: tuple[int, int] = (256, 256),
                     columns: int = 0, samples: int = 4) -> np.ndarray:
    """Render each expression on a face into a labelled grid.

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
    width, height = cell
    columns = columns or math.ceil(math.sqrt(len(expressions)))
    rows = math.ceil(len(expressions) / columns)
    sheet = np.full((rows * (height + _LABEL_HEIGHT), columns * width, 3), 255, dtype=np.uint8)
    neutral = rig.face.neutral()
    ctx = create_context()
    try:
        with Renderer(ctx, cell, samples=samples) as renderer:
            for i, (name, expression) in enumerate(expressions.items()):
                top, left = (i // columns) * (height + _LABEL_HEIGHT), (i % columns) * width
                sheet[top:top + height, left:left + width] = renderer.render(rig.geometry(expression.pose(neutral)))
                _label(sheet, name, left, top + height, width)
    finally:
        ctx.release()
    return sheet


def _label(sheet: np.ndarray, text: str, left: int, top: int, width: int) -> None:
    font, scale, thickness = cv2.FONT_HERSHEY_SIMPLEX, 0.6, 1
    (w, h), _ = cv2.getTextSize(text, font, scale, thickness)
    org = (left + max((width - w) // 2, 2), top + (_LABEL_HEIGHT + h) // 2)
    cv2.putText(sheet, text, org, font, scale, (20, 20, 20), thickness, cv2.LINE_AA)


def save_png(image: np.ndarray, path: str | os.PathLike) -> Path:
    """Write an RGB image as PNG, atomically."""
    path = Path(path)
    ok, data = cv2.imencode(".png", np.ascontiguousarray(image[:, :, ::-1]))
    if not ok:
        raise OSError(f"{path}: could not encode PNG")
    with atomic_path(path) as tmp:
        tmp.write_bytes(data.tobytes())
    return path
