"""Several faces in one picture: each face's frame placed in its own cell of a stage.

A stage is a picture ``width`` by ``height`` units (y up, origin at the bottom left) cut into
cells ``(x0, y0, x1, y1)``. Each face's frame is fitted into its cell as the renderer fits a
single face into a picture (its view box scaled to the cell, aspect kept, centred), its items
moved and scaled with it (stroke widths too), over a rectangle of its own background, and faded
by an opacity (0..1) that scales every colour's alpha. Items keep their drawing order, face after
face; their keys are made distinct per cell, so a renderer's caches keep them apart. Faces'
holes share mask groups, which is harmless as long as cells do not overlap.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from toon.geometry import DrawItem, Geometry
from toon.validate import Color

#: Keys per cell: a face's item keys stay below this.
KEYS_PER_CELL = 1 << 20


def grid(count: int, width: float, height: float) -> list[tuple[float, float, float, float]]:
    """``count`` equal cells filling a ``width`` x ``height`` stage, row by row from the top, in
    the most nearly square grid whose cells are closest to square."""
    if count <= 0:
        return []
    best = min(range(1, count + 1), key=lambda columns: abs(math.log(
        (width / columns) / (height / math.ceil(count / columns)))))
    columns, rows = best, math.ceil(count / best)
    w, h = width / columns, height / rows
    return [((k % columns) * w, height - (k // columns + 1) * h, (k % columns + 1) * w, height - (k // columns) * h)
            for k in range(count)]


def _faded(color: Color | None, opacity: float) -> Color | None:
    return None if color is None else (color[0], color[1], color[2], color[3] * opacity)


def stage(frames: list[Geometry], cells: list[tuple[float, float, float, float]], width: float, height: float,
          background: Color, opacities: list[float] | None = None) -> Geometry:
    """One frame of several faces: ``frames[k]`` fitted into ``cells[k]`` with ``opacities[k]``
    (1 by default) on a ``width`` x ``height`` stage of ``background``."""
    items: list[DrawItem] = []
    for k, (frame, cell) in enumerate(zip(frames, cells, strict=True)):
        opacity = 1.0 if opacities is None else float(opacities[k])
        x0, y0, x1, y1 = frame.viewbox
        cx0, cy0, cx1, cy1 = cell
        scale = min((cx1 - cx0) / (x1 - x0), (cy1 - cy0) / (y1 - y0))
        centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
        middle = np.array([(cx0 + cx1) / 2, (cy0 + cy1) / 2])
        base = k * KEYS_PER_CELL
        corners = np.array([[cx0, cy0], [cx1, cy0], [cx1, cy1], [cx0, cy1]], dtype=float)
        items.append(DrawItem(corners, _faded(frame.background, opacity), key=base + KEYS_PER_CELL - 1,
                              name="background"))
        for item in frame.items:
            items.append(replace(item, vertices=(item.vertices - centre) * scale + middle,
                                 fill=_faded(item.fill, opacity), stroke=_faded(item.stroke, opacity),
                                 width=item.width * scale, key=base + item.key % KEYS_PER_CELL,
                                 opacity=item.opacity * opacity))
    return Geometry(tuple(items), (0.0, 0.0, float(width), float(height)), background)
