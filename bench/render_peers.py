"""The 2-D libraries a user would draw a face's frames with instead: skia-python and pycairo.

Each peer draws a :class:`toon.Geometry` as plainly as its library allows, into a numpy RGB
array at the same size with antialiasing: each outline a path, filled (even-odd) and stroked
(butt ends, miter joins with the same limit), holes kept as clip paths for the items masked by
them (A1.2.2). Written apart from :mod:`player.cairo_renderer` (points go in as each library's
own point objects or calls), so that the render bench compares ours with what a user would
write. Both come with ``make bench-deps`` (pycairo builds against Cairo's headers); a peer that
is not installed is left out.
"""

from __future__ import annotations

from collections.abc import Callable

import cv2
import numpy as np

from toon import Geometry, fit_viewbox, to_pixels
from toon.curves import MITER_LIMIT

Drawer = Callable[[Geometry], np.ndarray]


def _pixels(geometry: Geometry, size: tuple[int, int]) -> list[np.ndarray]:
    return [to_pixels(item.vertices, geometry.viewbox, size) for item in geometry.items]


def _runs(item_closed: bool, count: int, visible: np.ndarray | None) -> list[tuple[list[int], bool]]:
    """Stroked runs: all points (closed as the item) or each visible edge on its own."""
    if visible is None or bool(np.all(visible)):
        return [(list(range(count)), item_closed)]
    return [([e, (e + 1) % count], False) for e in np.flatnonzero(visible).tolist()]


def skia_peer(size: tuple[int, int]) -> Drawer | None:
    """A skia-python drawer of ``size`` (width, height), or None where skia-python is not installed."""
    try:
        import skia
    except ImportError:
        return None

    rgba = np.zeros((size[1], size[0], 4), np.uint8)
    canvas = skia.Surface(rgba).getCanvas()

    def draw(geometry: Geometry) -> np.ndarray:
        scale = fit_viewbox(geometry.viewbox, size)[0]
        canvas.clear(skia.Color4f(*geometry.background[:3], 1.0))
        groups: dict[int, skia.Path] = {}
        for item, points in zip(geometry.items, _pixels(geometry, size), strict=True):
            pts = [skia.Point(x, y) for x, y in points.tolist()]
            canvas.save()
            if item.mask_test:
                canvas.clipPath(groups.get(item.mask_test, skia.Path()), doAntiAlias=True)
            elif item.mask_test == 0:
                for hole in groups.values():
                    canvas.clipPath(hole, skia.ClipOp.kDifference, True)
            if item.fill is not None and item.closed:
                path = skia.Path.Polygon(pts, True, skia.PathFillType.kEvenOdd)
                if item.mask_write:
                    groups.setdefault(item.mask_write, skia.Path()).addPath(path)
                canvas.drawPath(path, skia.Paint(Color4f=skia.Color4f(*item.fill), AntiAlias=True))
            if item.stroke is not None and item.width > 0:
                paint = skia.Paint(Color4f=skia.Color4f(*item.stroke), AntiAlias=True, Style=skia.Paint.kStroke_Style,
                                   StrokeWidth=item.width * scale, StrokeJoin=skia.Paint.kMiter_Join,
                                   StrokeMiter=float(MITER_LIMIT))
                for run, closed in _runs(item.closed, len(pts), item.edge_visible):
                    canvas.drawPath(skia.Path.Polygon([pts[k] for k in run], closed), paint)
            canvas.restore()
        return cv2.cvtColor(rgba, cv2.COLOR_RGBA2RGB)

    return draw


def cairo_peer(size: tuple[int, int]) -> Drawer | None:
    """A pycairo drawer of ``size``, or None where pycairo is not installed."""
    try:
        import cairo
    except ImportError:
        return None
    width, height = size
    surface = cairo.ImageSurface(cairo.FORMAT_RGB24, width, height)
    pixels = np.ndarray((height, surface.get_stride() // 4, 4), np.uint8, surface.get_data())
    context = cairo.Context(surface)
    context.set_line_join(cairo.LINE_JOIN_MITER)
    context.set_miter_limit(float(MITER_LIMIT))
    context.set_line_cap(cairo.LINE_CAP_BUTT)

    def outline(points: np.ndarray, run: list[int], closed: bool) -> None:
        context.move_to(*points[run[0]])
        for k in run[1:]:
            context.line_to(*points[k])
        if closed:
            context.close_path()

    def draw(geometry: Geometry) -> np.ndarray:
        scale = fit_viewbox(geometry.viewbox, size)[0]
        context.set_source_rgb(*geometry.background[:3])
        context.paint()
        groups: dict[int, list[np.ndarray]] = {}
        for item, points in zip(geometry.items, _pixels(geometry, size), strict=True):
            listed = points.tolist()
            context.save()
            if item.mask_test:
                for hole in groups.get(item.mask_test, []):
                    outline(hole, list(range(len(hole))), True)
                context.set_fill_rule(cairo.FILL_RULE_EVEN_ODD)
                context.clip()
            elif item.mask_test == 0 and groups:
                context.rectangle(0, 0, width, height)
                for holes in groups.values():
                    for hole in holes:
                        outline(hole, list(range(len(hole))), True)
                context.set_fill_rule(cairo.FILL_RULE_EVEN_ODD)
                context.clip()
            if item.fill is not None and item.closed:
                outline(listed, list(range(len(listed))), True)
                if item.mask_write:
                    groups.setdefault(item.mask_write, []).append(listed)
                context.set_fill_rule(cairo.FILL_RULE_EVEN_ODD)
                context.set_source_rgba(*item.fill)
                context.fill()
            if item.stroke is not None and item.width > 0:
                context.set_line_width(item.width * scale)
                context.set_source_rgba(*item.stroke)
                for run, closed in _runs(item.closed, len(listed), item.edge_visible):
                    outline(listed, run, closed)
                context.stroke()
            context.restore()
        surface.flush()
        return cv2.cvtColor(pixels[:, :width], cv2.COLOR_BGRA2RGB)  # Cairo's RGB24 is BGRx in memory

    return draw
