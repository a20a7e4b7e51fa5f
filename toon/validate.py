"""Checks for pieces of a face or component-library document.

Every check raises :class:`common.InputError` naming the document and the path of the bad field
(``polygons[3].attach``), so a user can find what to fix without reading a traceback.
"""

from __future__ import annotations

import math
import os
import re
from typing import Any, NoReturn

from common import InputError

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


def is_number(x: Any) -> bool:
    """A finite int or float that is not a bool."""
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


class Validator:
    """Checks pieces of a document, raising :class:`InputError` with the field's path.

    Parameters
    ----------
    source : path or None
        The document's file, named in every error.
    """

    def __init__(self, source: str | os.PathLike | None) -> None:
        self.source = source

    def require(self, ok: bool, message: str, where: str) -> None:
        """Raise ``InputError(message)`` at ``where`` unless ``ok``."""
        if not ok:
            self.fail(message, where)

    def fail(self, message: str, where: str) -> NoReturn:
        """Raise ``InputError(message)`` at ``where``."""
        raise InputError(message, self.source, where or None)

    def fields(self, value: Any, allowed: set[str], where: str, what: str) -> None:
        """``value`` is an object with no keys outside ``allowed``."""
        self.require(isinstance(value, dict), "must be an object", where)
        extra = sorted(set(value) - allowed)
        self.require(not extra, f"unexpected field(s) {extra} for {what}", where)

    def numbers(self, value: Any, n: int, where: str) -> list[float]:
        """A list of exactly ``n`` finite numbers."""
        ok = isinstance(value, list) and len(value) == n and all(is_number(x) for x in value)
        self.require(ok, f"expected {n} finite number{'s' if n > 1 else ''}, got {value!r}", where)
        return [float(x) for x in value]

    def number(self, value: Any, where: str, low: float = -math.inf, high: float = math.inf) -> float:
        """One finite number in ``[low, high]``."""
        self.require(is_number(value), f"expected a finite number, got {value!r}", where)
        self.require(low <= value <= high, f"must be between {low} and {high}, got {value}", where)
        return float(value)

    def integer(self, value: Any, where: str, low: int, high: int) -> int:
        """One integer in ``[low, high]``."""
        ok = isinstance(value, int) and not isinstance(value, bool) and low <= value <= high
        self.require(ok, f"expected an integer from {low} to {high}, got {value!r}", where)
        return int(value)

    def boolean(self, value: Any, where: str) -> bool:
        """``true`` or ``false``."""
        self.require(isinstance(value, bool), f"expected true or false, got {value!r}", where)
        return bool(value)

    def choice(self, value: Any, options: tuple[str, ...] | list[str], where: str, what: str) -> str:
        """One of ``options``; the error lists them."""
        self.require(value in options, f'unknown {what} "{value}" (one of {", ".join(options)})'
                     if isinstance(value, str) else f"expected a {what} name, got {value!r}", where)
        return str(value)

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
