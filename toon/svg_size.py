"""How big an SVG drawing is once drawn, measured before it is parsed for drawing.

A ``<use>`` element draws another element again, and that one may hold ``<use>`` elements of its
own: seven levels that each repeat the level below ten times are ten million shapes from a file of
2 kB, which a drawing library expands in memory without limit. :func:`check_svg_size` reads the
file's element tree once (no drawing), and counts with every ``<use>`` expanded, without expanding
anything: each element's size is counted once and reused wherever it is referred to. A drawing
beyond :mod:`common.limits`' bounds (elements, depth, coordinate pairs) is refused before anything
is built from it; a ``<use>`` that refers to itself, directly or through others, is refused too.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass
from typing import Any

from common.limits import MAX_SVG_BYTES, MAX_SVG_DEPTH, MAX_SVG_ELEMENTS, MAX_SVG_POINTS

_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_XLINK = "{http://www.w3.org/1999/xlink}href"


@dataclass(frozen=True)
class Size:
    """What one element draws with its children and the elements its ``<use>`` refer to."""

    elements: int
    depth: int
    points: int


def check_svg_size(text: str) -> Size:
    """The size of the drawing ``text`` (an SVG document) with every ``<use>`` expanded.

    Raises
    ------
    ValueError
        One line naming the bound a drawing passes (:data:`~common.limits.MAX_SVG_BYTES`,
        :data:`~common.limits.MAX_SVG_ELEMENTS`, :data:`~common.limits.MAX_SVG_DEPTH`,
        :data:`~common.limits.MAX_SVG_POINTS`), or that it is not XML.

    Examples
    --------
    >>> check_svg_size('<svg><path id="p" d="M0 0 L1 1"/><use href="#p"/><use href="#p"/></svg>')
    Size(elements=6, depth=3, points=9)
    """
    if len(text) > MAX_SVG_BYTES:
        raise ValueError(f"a drawing of {len(text)} characters: at most {MAX_SVG_BYTES} are imported")
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as exc:
        raise ValueError(f"not an SVG drawing ({exc})") from None
    ids = {e.get("id"): e for e in root.iter() if e.get("id")}
    sizes: dict[int, Size] = {}
    open_: set[int] = set()

    def size(element: Any, depth: int) -> Size:
        key = id(element)
        if key in sizes:
            return sizes[key]
        if key in open_:
            raise ValueError(f"a <use> that refers to itself (through #{element.get('id')})")
        if depth > MAX_SVG_DEPTH:
            raise ValueError(f"a drawing nested deeper than {MAX_SVG_DEPTH} elements with its <use> expanded")
        open_.add(key)
        elements, deepest, points = 1, 0, _coordinates(element)
        parts = list(element)
        href = element.get(_XLINK) or element.get("href") or ""
        if _local(element.tag) == "use" and href.startswith("#") and href[1:] in ids:
            parts.append(ids[href[1:]])
        for part in parts:
            inner = size(part, depth + 1)
            elements, points = elements + inner.elements, points + inner.points
            deepest = max(deepest, inner.depth)
            _check(elements, points)
        open_.discard(key)
        sizes[key] = Size(elements, deepest + 1, points)
        return sizes[key]

    whole = size(root, 0)
    if whole.depth > MAX_SVG_DEPTH:
        raise ValueError(f"a drawing nested deeper than {MAX_SVG_DEPTH} elements with its <use> expanded")
    return whole


def _check(elements: int, points: int) -> None:
    if elements > MAX_SVG_ELEMENTS:
        raise ValueError(f"a drawing of more than {MAX_SVG_ELEMENTS} elements with its <use> expanded: "
                         "simplify it, or import its parts one at a time")
    if points > MAX_SVG_POINTS:
        raise ValueError(f"a drawing of more than {MAX_SVG_POINTS} points with its <use> expanded: simplify its "
                         "paths (Inkscape: Path > Simplify) and import it again")


def _coordinates(element: Any) -> int:
    """The coordinate pairs an element's own geometry writes (a path's ``d``, a polyline's
    ``points``; a shape of fixed size counts as a few)."""
    tag = _local(element.tag)
    if tag == "path":
        return len(_NUMBER.findall(element.get("d") or "")) // 2 + 1
    if tag in ("polyline", "polygon"):
        return len(_NUMBER.findall(element.get("points") or "")) // 2 + 1
    return 4 if tag in ("rect", "circle", "ellipse", "line") else 0


def _local(tag: object) -> str:
    return str(tag).rsplit("}", 1)[-1]
