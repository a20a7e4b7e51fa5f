"""An SVG drawing (Inkscape, Illustrator, Affinity export) as a face's components.

Each visible shape (path, rect, circle, ellipse, line, polyline, polygon), with its group's and its
own transforms applied (``svgelements``, MIT), becomes one component per subpath, in document
order (the drawing's layer order) on the foreground layer: a closed subpath a ``polygon`` (filled
with the shape's fill where it has one), an open one a ``polyline``. The stroke and its width are
kept, the width scaled as the drawing is, and the shape's ``opacity`` times its groups' folds
into their alpha (a group drawn as one would differ where its shapes overlap: each shape is
faded alone). A gradient paint becomes its mean colour (its stops weighted by the share of the
gradient each spans, following ``href`` to the stops of another gradient, as Inkscape writes
them), and the import says which shapes it did so for.
Straight segments keep their end points; a curve becomes points about :data:`CURVE_STEP` face
units apart (2 to 32 of them). The drawing is fitted into the face's viewbox, centred, its aspect
kept (SVG's y runs down, a face's up). Every point is frozen where it lands, ready to be attached
to control points (``toonface studio``: Attach).

A component is named after its shape's ``id``, else its kind and number. A drawing beyond
:mod:`common.limits`' bounds (elements with ``<use>`` expanded, depth, points) is refused before
it is drawn (:mod:`toon.svg_size`).
"""

from __future__ import annotations

import io
import math
from typing import Any

from common.limits import MAX_SVG_POINTS
from toon.svg_size import check_svg_size

#: Face units between the points of a curve.
CURVE_STEP = 6.0
#: A subpath shorter than this (face units) is left out (a speck).
SMALLEST = 1.0


def svg_components(text: str, viewbox: tuple[float, float, float, float],
                   notes: list[str] | None = None) -> list[dict[str, Any]]:
    """The drawing ``text`` (SVG) as component entries of a face file, fitted into ``viewbox``
    ``(xmin, ymin, xmax, ymax)`` (see the module docstring); a ValueError naming what is wrong
    where it is not an SVG drawing or draws nothing. What was approximated (a gradient as its
    mean colour) is added to ``notes``, a line each."""
    import svgelements as se

    check_svg_size(text)  # before the drawing library expands its <use> elements
    try:
        drawing = se.SVG.parse(io.StringIO(text))
    except Exception as exc:  # noqa: BLE001 - the parser's own errors are many and unexported
        raise ValueError(f"not an SVG drawing ({type(exc).__name__}: {exc})") from None
    if not isinstance(drawing, se.SVG):
        raise ValueError("not an SVG drawing (no <svg> element)")
    every = [e for e in drawing.elements() if isinstance(e, se.Shape)]
    gradients, fades = _paint_servers(text, len(every))
    faded = dict(zip(map(id, every), fades, strict=True)) if fades is not None else {}
    shapes = [e for e in every if _visible(e)]
    paths = [(e, se.Path(e)) for e in shapes]
    said = notes if notes is not None else []
    if not paths:
        raise ValueError("the drawing has no shape to import (path, rect, circle, ellipse, line, polyline, polygon)")
    fit = _fit(drawing, [p for _, p in paths], viewbox)
    out: list[dict[str, Any]] = []
    made = 0
    for number, (shape, path) in enumerate(paths, start=1):
        base = str(shape.id) if getattr(shape, "id", None) else f"{type(shape).__name__.lower()} {number}"
        subpaths = list(path.as_subpaths())
        for k, sub in enumerate(subpaths):
            points, closed = _points(se, sub, fit)
            made += len(points)
            if made > MAX_SVG_POINTS:
                raise ValueError(f"the drawing's curves make more than {MAX_SVG_POINTS} points: simplify its paths "
                                 "(Inkscape: Path > Simplify) and import it again")
            if len(points) < 2 or _length(points) < SMALLEST:
                continue
            opacity = faded.get(id(shape), _opacity(shape))
            fill = _paint(se, shape, "fill", opacity, gradients, said, base) if closed else None
            stroke = _paint(se, shape, "stroke", opacity, gradients, said, base)
            if fill is None and stroke is None:
                continue
            spec: dict[str, Any] = {"kind": "polygon" if closed and len(points) >= 3 else "polyline",
                                    "name": base if len(subpaths) == 1 else f"{base} {k + 1}", "layer": 1,
                                    "points": [[round(x, 3), round(y, 3)] for x, y in points]}
            if fill is not None:
                spec["fill"] = fill
            if stroke is not None:
                width = float(getattr(shape, "implicit_stroke_width", None) or shape.stroke_width or 1.0)
                spec["stroke"], spec["width"] = stroke, round(max(width * fit[2], 0.1), 3)
            out.append(spec)
    if not out:
        raise ValueError("the drawing's shapes are all empty, invisible or specks")
    return out


def _visible(shape: Any) -> bool:
    values = getattr(shape, "values", {}) or {}
    return values.get("visibility") != "hidden" and values.get("display") != "none"


#: ``(svg centre x, svg centre y, scale, face centre x, face centre y)``.
Fit = tuple[float, float, float, float, float]


def _fit(drawing: Any, paths: list, viewbox: tuple[float, float, float, float]) -> Fit:
    """``(svg centre x, svg centre y, scale, face centre x, face centre y)``: the drawing's viewBox
    (else its shapes' bounds) fitted into the face's viewbox."""
    box = drawing.viewbox
    if box is not None and box.width and box.height:
        left, top, width, height = float(box.x), float(box.y), float(box.width), float(box.height)
    else:
        bounds = [p.bbox() for p in paths if p.bbox() is not None]
        left, top = min(b[0] for b in bounds), min(b[1] for b in bounds)
        width, height = max(b[2] for b in bounds) - left, max(b[3] for b in bounds) - top
    if not (width > 0 and height > 0):
        raise ValueError("the drawing has no size (an empty viewBox or a single point)")
    xmin, ymin, xmax, ymax = viewbox
    scale = min((xmax - xmin) / width, (ymax - ymin) / height)
    return left + width / 2, top + height / 2, scale, (xmin + xmax) / 2, (ymin + ymax) / 2


def _points(se: Any, sub: Any, fit: Fit) -> tuple[list[tuple[float, float]], bool]:
    """A subpath's points in face units, and whether it is closed."""
    sx, sy, scale, fx, fy = fit

    def face(p: Any) -> tuple[float, float]:
        return fx + (float(p.x) - sx) * scale, fy - (float(p.y) - sy) * scale

    points: list[tuple[float, float]] = []
    closed = False
    for segment in sub:
        if isinstance(segment, se.Move):
            points = [face(segment.end)]
        elif isinstance(segment, se.Close):
            closed = True
        elif isinstance(segment, se.Line):
            points.append(face(segment.end))
        else:  # a curve: points about CURVE_STEP apart
            steps = min(32, max(2, math.ceil(float(segment.length()) * scale / CURVE_STEP)))
            points += [face(segment.point(i / steps)) for i in range(1, steps + 1)]
    if len(points) > 2 and math.dist(points[0], points[-1]) < 1e-6:
        points.pop()
        closed = True
    return points, closed


def _length(points: list[tuple[float, float]]) -> float:
    return sum(math.dist(a, b) for a, b in zip(points, points[1:], strict=False))


def _paint(se: Any, shape: Any, which: str, opacity: float, gradients: dict[str, tuple[float, ...] | None],
           said: list[str], name: str) -> str | None:
    """The shape's fill or stroke as a colour (:func:`_colour`); a gradient as its mean colour,
    said in ``said``."""
    written = str((getattr(shape, "values", {}) or {}).get(which, "")).strip()
    if not written.startswith("url("):
        return _colour(getattr(shape, which), opacity)
    ref = written[4:].split(")", 1)[0].strip().strip("'\"").lstrip("#")
    mean = gradients.get(ref)
    if mean is None:
        line = f"{name}: its {which} ({written}) names no gradient with stops: left out"
    else:
        r, g, b, a = mean
        colour = se.Color(f"#{round(r * 255):02x}{round(g * 255):02x}{round(b * 255):02x}")
        colour.alpha = round(a * 255)
        line = f"{name}: its gradient {which} became its mean colour {str(colour.hex)[:7]}"
    if line not in said:
        said.append(line)
    return None if mean is None else _colour(colour, opacity)


#: Elements whose shapes are not drawn where they stand.
_UNDRAWN = {"defs", "clipPath", "mask", "symbol", "marker", "pattern", "linearGradient", "radialGradient"}
_SHAPES = {"path", "rect", "circle", "ellipse", "line", "polyline", "polygon"}


def _paint_servers(text: str, count: int) -> tuple[dict[str, tuple[float, ...] | None], list[float] | None]:
    """The drawing's gradients by id, each as its mean RGBA in [0, 1] (None: no stops), and the
    opacity of each drawn shape in document order, its own times its groups' (None where the
    shapes found here are not the ``count`` the drawing draws: a ``<use>`` repeats some)."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(text)
    except ET.ParseError:
        return {}, None
    local = lambda tag: str(tag).rsplit("}", 1)[-1]  # noqa: E731 - the tag without its namespace
    found = {e.get("id"): e for e in root.iter() if local(e.tag) in ("linearGradient", "radialGradient")}

    def stops(element: Any, seen: set) -> list:
        own = [s for s in element if local(s.tag) == "stop"]
        href = element.get("{http://www.w3.org/1999/xlink}href") or element.get("href") or ""
        if own or not href.startswith("#") or href in seen:
            return own
        target = found.get(href[1:])
        return stops(target, seen | {href}) if target is not None else []

    gradients = {name: _mean_stop(stops(element, set())) for name, element in found.items() if name}
    fades: list[float] = []
    if any(local(e.tag) == "use" for e in root.iter()):
        return gradients, None

    def walk(element: Any, fade: float) -> None:
        if local(element.tag) in _UNDRAWN:
            return
        fade *= _number(_style(element, "opacity"), 1.0)
        if local(element.tag) in _SHAPES:
            fades.append(min(1.0, max(0.0, fade)))
        for child in element:
            walk(child, fade)
    walk(root, 1.0)
    return gradients, fades if len(fades) == count else None


def _style(element: Any, name: str) -> str | None:
    """A presentation property, from ``style`` first, then the attribute."""
    for part in (element.get("style") or "").split(";"):
        key, _, value = part.partition(":")
        if key.strip() == name:
            return value.strip()
    return element.get(name)


def _number(text: str | None, default: float) -> float:
    if text is None:
        return default
    try:
        return float(text[:-1]) / 100 if text.endswith("%") else float(text)
    except ValueError:
        return default


def _mean_stop(stops: list) -> tuple[float, ...] | None:
    """The mean RGBA of a gradient along its line from its ``<stop>`` elements (the colour
    blends linearly between stops and holds beyond the ends): each stop weighted by half the gap
    to each neighbour, the first and last also by the way to 0 and to 1."""
    import svgelements as se

    if not stops:
        return None
    offsets, colours = [], []
    for stop in stops:
        offsets.append(min(1.0, max(0.0, _number(stop.get("offset"), 0.0))))
        colour = se.Color(_style(stop, "stop-color") or "black")
        alpha = colour.alpha / 255 * min(1.0, max(0.0, _number(_style(stop, "stop-opacity"), 1.0)))
        colours.append((colour.red / 255, colour.green / 255, colour.blue / 255, alpha))
    for i in range(1, len(offsets)):  # offsets never go back (SVG's rule)
        offsets[i] = max(offsets[i], offsets[i - 1])
    edges = [0.0, *((a + b) / 2 for a, b in zip(offsets, offsets[1:], strict=False)), 1.0]
    weights = [b - a for a, b in zip(edges, edges[1:], strict=False)]
    total = sum(weights)
    if total <= 0:
        return colours[-1]
    return tuple(sum(w * c[k] for w, c in zip(weights, colours, strict=True)) / total for k in range(4))


def _opacity(shape: Any) -> float:
    """The shape's own ``opacity`` (which its paints' alpha leaves out; a group's is not applied)."""
    try:
        return min(1.0, max(0.0, float((getattr(shape, "values", {}) or {}).get("opacity", 1.0))))
    except (TypeError, ValueError):
        return 1.0


def _colour(value: Any, opacity: float = 1.0) -> str | None:
    """An SVG paint as ``#rrggbb`` (``#rrggbbaa`` where not opaque), its alpha times ``opacity``;
    None for none or a gradient."""
    if value is None or getattr(value, "value", None) is None:
        return None
    try:
        alpha = round(int(value.alpha) * opacity)
        rgb = str(value.hex)[:7]
    except (AttributeError, TypeError):
        return None
    if alpha == 0:
        return None
    return rgb if alpha >= 255 else f"{rgb}{alpha:02x}"
