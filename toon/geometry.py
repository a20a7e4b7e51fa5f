"""One frame of a face as drawable outlines: what the renderer, the SVG export and the CPU oracle take."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from toon.validate import Color

if TYPE_CHECKING:
    from toon.images import Picture


@dataclass(frozen=True)
class DrawItem:
    """One thing to draw: an outline, filled and/or stroked.

    Attributes
    ----------
    vertices : ndarray, shape (N, 2)
        The outline in face units, y up.
    fill, stroke : RGBA tuple or None
        Colours in ``[0, 1]``; ``None`` draws no fill or no stroke.
    width : float
        Stroke width in face units.
    closed : bool
        Whether the outline closes (only closed outlines are filled).
    edge_visible : ndarray of bool or None
        Per stroked edge (``N`` closed, ``N - 1`` open), whether it is drawn; ``None``: all.
    kind : str
        Its A1.2.2 step (``hole``, ``pupil``, ``face``, ``free``, ``point``, ``feature``) or
        ``component``.
    mask_write : int
        Mask group a hole opens (0: none).
    mask_test : int or None
        Draw only where the mask is this group (0: where no hole is); ``None``: everywhere.
    key : int
        The item's place in its face's drawing order, stable from frame to frame.
    name : str
    picture : Picture or None
        An image component's picture (:mod:`toon.images`), stretched over the parallelogram of
        ``vertices`` (its four corners: top-left, top-right, bottom-right, bottom-left; ``kind``
        ``image``, no fill or stroke).
    opacity : float
        The picture's opacity (a stage fades a performer who left).
    """

    vertices: np.ndarray
    fill: Color | None
    stroke: Color | None = None
    width: float = 0.0
    closed: bool = True
    edge_visible: np.ndarray | None = None
    kind: str = "free"
    mask_write: int = 0
    mask_test: int | None = None
    key: int = 0
    name: str = ""
    picture: Picture | None = field(default=None, compare=False)
    opacity: float = 1.0

    def with_vertices(self, vertices: np.ndarray) -> DrawItem:
        """The same item at ``vertices`` (shape of :attr:`vertices`).

        Every item of every frame is made this way, so it copies the fields' dictionary (0.75 us)
        rather than running the frozen constructor (1.8 us) or :func:`dataclasses.replace`.
        """
        item = object.__new__(DrawItem)
        fields = item.__dict__
        fields.update(self.__dict__)
        fields["vertices"] = vertices
        return item


@dataclass(frozen=True)
class Geometry:
    """One frame of a face: items in drawing order plus the view."""

    items: tuple[DrawItem, ...]
    viewbox: tuple[float, float, float, float]
    background: Color
