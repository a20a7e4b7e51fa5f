"""Checks for pieces of a face or component-library document: the project's one validator
(:mod:`common.validate`) with points, colours and outlines added.

Every check raises :class:`common.InputError` naming the document and the path of the bad field
(``polygons[3].attach``), so a user can find what to fix without reading a traceback.
"""

from __future__ import annotations

import re
from typing import Any

from common.validate import Validator

Color = tuple[float, float, float, float]
Vertices = tuple[tuple[float, float], ...]

_HEX = re.compile(r"^#([0-9a-fA-F]{6})([0-9a-fA-F]{2})?$")


def format_color(c: Color) -> str:
    """``"#rrggbb"`` (opaque) or ``"#rrggbbaa"`` for an RGBA colour in ``[0, 1]``.

    >>> format_color((1.0, 0.5, 0.0, 1.0))
    '#ff8000'
    """
    rgb = "".join(f"{round(x * 255):02x}" for x in c[:3])
    return f"#{rgb}" if c[3] >= 1.0 else f"#{rgb}{round(c[3] * 255):02x}"


class ShapeValidator(Validator):
    """The project's validator (:class:`common.validate.Validator`) with the checks of faces
    and component libraries: points, colours and outlines."""

    def point(self, value: Any, where: str) -> tuple[float, float]:
        """An ``[x, y]`` pair."""
        self.require(value is not None, "missing point [x, y]", where)
        x, y = self.numbers(value, 2, where)
        return (x, y)

    def color(self, value: Any, where: str) -> Color:
        """``"#rrggbb"`` or ``"#rrggbbaa"`` as RGBA floats."""
        m = _HEX.match(value) if isinstance(value, str) else None
        self.require(m is not None, f'expected a colour "#rrggbb" or "#rrggbbaa", got {value!r}', where)
        rgb = m.group(1)  # type: ignore[union-attr]
        alpha = int(m.group(2), 16) / 255 if m.group(2) else 1.0  # type: ignore[union-attr]
        return (int(rgb[0:2], 16) / 255, int(rgb[2:4], 16) / 255, int(rgb[4:6], 16) / 255, alpha)

    def optional_color(self, value: Any, where: str) -> Color | None:
        """A colour, or ``None`` for JSON ``null`` / absent."""
        return None if value is None else self.color(value, where)

    def vertices(self, value: Any, where: str, minimum: int = 3) -> Vertices:
        """A list of at least ``minimum`` ``[x, y]`` pairs."""
        self.require(isinstance(value, list) and len(value) >= minimum,
                     f"expected a list of at least {minimum} [x, y] points", where)
        return tuple(self.point(p, f"{where}[{i}]") for i, p in enumerate(value))

    def not_degenerate(self, vertices: Vertices, where: str) -> None:
        """A filled outline must enclose some area (shoelace formula)."""
        n = len(vertices)
        area = 0.5 * abs(sum(vertices[i][0] * vertices[(i + 1) % n][1] - vertices[(i + 1) % n][0] * vertices[i][1]
                             for i in range(n)))
        xs, ys = [v[0] for v in vertices], [v[1] for v in vertices]
        extent = max(max(xs) - min(xs), max(ys) - min(ys))
        self.require(area > 1e-6 * max(extent, 1e-9) ** 2,
                     f"degenerate polygon: its {n} vertices enclose no area (all on one line or one point)", where)
