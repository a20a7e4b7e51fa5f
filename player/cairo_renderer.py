"""The CPU renderer: face geometry to RGB frames with Cairo (through cairocffi), for machines
without a GPU.

It draws the same :class:`toon.Geometry` as :class:`player.renderer.Renderer`, in the same order,
with the same masking (A1.2.2) and the same strokes, into an image Cairo owns and numpy reads:

- fills are their outline's path (even-odd, as the CPU oracle fills);
- strokes are Cairo's own stroking of the outline (butt ends, miter joins cut to a bevel beyond
  :data:`toon.curves.MITER_LIMIT`, as :func:`toon.curves.stroke_triangles` builds them), each
  run of visible edges its own sub-path;
- holes keep their outlines by mask group; pupils and clipped components are clipped to their
  group's outlines, the face polygon to everything outside the holes drawn before it;
- an image component's picture is painted through the matrix that takes it onto its corners,
  filtered bilinearly, its edges padded and clipped to its outline (as the CPU oracle samples it).

Outlines reach Cairo as ``cairo_path_data_t`` arrays (the C struct is Cairo's public interface)
written by numpy, one array for the whole frame whose headers are kept from frame to frame, not
one call a point. Antialiasing is Cairo's exact coverage instead
of 4x multisampling: on the built-in faces the two pictures differ by 0.2 to 0.5 of 255 on
average, along edges (a test holds it under 1). On llvmpipe it draws a 512x512 frame in about a
third of the GL path's time (``python -m bench render``); :func:`player.backends.open_renderer`
picks it where OpenGL would be a software rasteriser. Cairo itself is the system's libcairo
(``libcairo2``), which cairocffi loads; where it is missing the GL renderer draws.
"""

from __future__ import annotations

import cv2
import numpy as np

from player.alpha import straight
from toon import Geometry, fit_viewbox
from toon.curves import MITER_LIMIT

#: cairo_path_data_type_t
MOVE_TO, LINE_TO, CLOSE_PATH = 0, 1, 3
#: cairo_fill_rule_t, cairo_antialias_t
EVEN_ODD, ANTIALIAS_NONE, ANTIALIAS_DEFAULT = 1, 1, 0
#: cairo_operator_t
OPERATOR_SOURCE, OPERATOR_OVER = 1, 2


class CairoRenderer:
    """Draws :class:`toon.Geometry` into RGB frames on the CPU.

    Parameters
    ----------
    size : (width, height)
        Pixels.
    samples : int
        As for the GL renderer: more than 1 antialiases (Cairo's coverage, whatever the number),
        0 or 1 does not.

    Raises
    ------
    OSError
        Where the system's libcairo cannot be loaded.

    :meth:`close` releases the Cairo surface and context; it is safe to call twice.
    """

    def __init__(self, size: tuple[int, int] = (512, 512), samples: int = 4) -> None:
        import cairocffi  # loads libcairo: OSError where it is missing

        self.size = (int(size[0]), int(size[1]))
        if min(self.size) < 1 or max(self.size) > 8192:
            raise ValueError(f"frame size must be 1..8192 pixels per side, got {self.size}")
        width, height = self.size
        self._ffi, self._lib = cairocffi.ffi, cairocffi.cairo
        self._surface = cairocffi.ImageSurface(cairocffi.FORMAT_ARGB32, width, height)  # premultiplied
        self._context = cairocffi.Context(self._surface)
        self._cr = self._context._pointer
        lib = self._lib
        lib.cairo_set_line_join(self._cr, cairocffi.LINE_JOIN_MITER)
        lib.cairo_set_miter_limit(self._cr, float(MITER_LIMIT))
        lib.cairo_set_line_cap(self._cr, cairocffi.LINE_CAP_BUTT)
        lib.cairo_set_antialias(self._cr, ANTIALIAS_DEFAULT if samples > 1 else ANTIALIAS_NONE)
        stride = self._surface.get_stride()
        data = self._ffi.buffer(lib.cairo_image_surface_get_data(self._surface._pointer), height * stride)
        self._bgra = np.ndarray((height, stride // 4, 4), np.uint8, buffer=data)[:, :width]  # Cairo's ARGB32
        self._path = self._ffi.new("cairo_path_t *")
        self._layout_key: tuple[tuple[int, bool], ...] | None = None
        self._layout: tuple[np.ndarray, np.ndarray, list[tuple[int, int]]] = (np.zeros((0, 2)), np.zeros(0, int), [])
        self._pictures: dict[str, tuple[object, np.ndarray]] = {}  # a picture's data -> its surface, its pixels
        self._closed = False

    def render(self, geometry: Geometry, alpha: bool = False) -> np.ndarray:
        """Draw one frame; returns RGB ``uint8`` of shape ``(height, width, 3)``, row 0 at the top,
        or with ``alpha`` straight RGBA ``(height, width, 4)`` (:mod:`player.alpha`)."""
        if self._closed:
            raise RuntimeError("renderer is closed")
        lib, cr = self._lib, self._cr
        items = geometry.items
        scale, ox, oy = fit_viewbox(geometry.viewbox, self.size)
        x0, y0 = ox - geometry.viewbox[0] * scale, oy + geometry.viewbox[3] * scale
        data, bounds = self._outlines(geometry, scale, x0, y0)
        lib.cairo_set_operator(cr, OPERATOR_SOURCE)  # the background replaces the last frame, alpha too
        lib.cairo_set_source_rgba(cr, *geometry.background)
        lib.cairo_paint(cr)
        lib.cairo_set_operator(cr, OPERATOR_OVER)
        groups: dict[int, list[np.ndarray]] = {}  # mask group -> its holes' path data so far
        for item, (start, stop) in zip(items, bounds, strict=True):
            outline = data[start:stop]  # closed where the item is
            test = item.mask_test
            clipped = test is not None and (test != 0 or bool(groups))
            if clipped:
                lib.cairo_save(cr)
                if test:
                    for hole in groups.get(test, []):
                        self._append(hole)
                else:  # outside every hole: the frame, with the holes cut out (even-odd)
                    lib.cairo_rectangle(cr, 0.0, 0.0, float(self.size[0]), float(self.size[1]))
                    for holes in groups.values():
                        for hole in holes:
                            self._append(hole)
                lib.cairo_set_fill_rule(cr, EVEN_ODD)
                lib.cairo_clip(cr)
            if item.fill is not None and item.closed:
                if item.mask_write:
                    groups.setdefault(item.mask_write, []).append(outline)
                self._append(outline)
                lib.cairo_set_fill_rule(cr, EVEN_ODD)
                lib.cairo_set_source_rgba(cr, *item.fill)
                lib.cairo_fill(cr)
            if item.stroke is not None and item.width > 0:
                visible = item.edge_visible
                whole = visible is None or bool(visible.all())
                runs = [] if whole else visible_runs(len(item.vertices), item.closed, visible)
                if whole or runs:
                    self._append(outline if whole else path_data(runs, outline[1::2]))
                    lib.cairo_set_line_width(cr, item.width * scale)
                    lib.cairo_set_source_rgba(cr, *item.stroke)
                    lib.cairo_stroke(cr)
            if item.picture is not None and len(item.vertices) == 4:
                self._paint_picture(item, outline, scale, x0, y0)
            if clipped:
                lib.cairo_restore(cr)
        lib.cairo_surface_flush(self._surface._pointer)
        if alpha:
            return straight(cv2.cvtColor(self._bgra, cv2.COLOR_BGRA2RGBA))
        return cv2.cvtColor(self._bgra, cv2.COLOR_BGRA2RGB)

    def _outlines(self, geometry: Geometry, scale: float, x0: float, y0: float
                  ) -> tuple[np.ndarray, list[tuple[int, int]]]:
        """Every item's outline as path data (see :func:`path_data`) in one array, in pixels, and
        each item's rows in it. The headers depend only on the items' point counts and closing,
        so they are written once for a face and re-used while those stay the same; each frame
        writes its points into them in one go."""
        items = geometry.items
        key = tuple((len(item.vertices), item.closed and len(item.vertices) > 0) for item in items)
        if key != self._layout_key:
            bounds, point_rows, start = [], [], 0
            for count, closed in key:
                point_rows.append(np.arange(start + 1, start + 2 * count, 2))
                bounds.append((start, start + 2 * count + closed))
                start += 2 * count + closed
            template = np.zeros((start, 2))
            for (count, closed), (first, _) in zip(key, bounds, strict=True):
                template[first:first + 2 * count + closed] = path_data([(None, closed)], np.zeros((count, 2)))
            self._layout_key = key
            self._layout = (template, np.concatenate(point_rows) if point_rows else np.zeros(0, int), bounds)
        data, rows, bounds = self._layout
        if len(rows):
            points = np.concatenate([item.vertices for item in items])
            data[rows, 0] = x0 + scale * points[:, 0]
            data[rows, 1] = y0 - scale * points[:, 1]
        return data, bounds

    def _paint_picture(self, item, outline: np.ndarray, scale: float, x0: float, y0: float) -> None:
        """Paint an image item's picture onto its corners, clipped to its outline."""
        import cairocffi

        from toon.images import pixel_affine

        picture = item.picture
        corners = np.column_stack([x0 + scale * item.vertices[:, 0], y0 - scale * item.vertices[:, 1]])
        (xx, xy, tx), (yx, yy, ty) = pixel_affine(corners, picture.size)
        if abs(xx * yy - xy * yx) < 1e-12:
            return  # collapsed to a line: nothing shows (and Cairo refuses such a matrix)
        surface = self._surface_of(picture)
        context = self._context
        context.save()
        self._append(outline)
        self._lib.cairo_set_fill_rule(self._cr, EVEN_ODD)
        context.clip()
        context.transform(cairocffi.Matrix(xx, yx, xy, yy, tx, ty))
        context.set_source_surface(surface, 0, 0)
        pattern = context.get_source()
        pattern.set_filter(cairocffi.FILTER_BILINEAR)
        pattern.set_extend(cairocffi.EXTEND_PAD)
        context.paint_with_alpha(float(item.opacity))
        context.restore()

    def _surface_of(self, picture) -> object:
        """The picture as a Cairo surface (premultiplied ARGB32), made once."""
        import cairocffi

        kept = self._pictures.get(picture.href)
        if kept is None:
            rgba = picture.pixels.astype(np.float32)
            rgba[..., :3] *= rgba[..., 3:] / 255.0
            bgra = np.ascontiguousarray(np.round(rgba[..., [2, 1, 0, 3]]).astype(np.uint8))
            height, width = bgra.shape[:2]
            surface = cairocffi.ImageSurface.create_for_data(bgra.reshape(-1).data, cairocffi.FORMAT_ARGB32,
                                                             width, height, width * 4)
            kept = self._pictures[picture.href] = (surface, bgra)  # the pixels live as long as the surface
        return kept[0]

    def _append(self, data: np.ndarray) -> None:
        """Add ``data`` (see :func:`path_data`; rows of one array, contiguous) to the current path."""
        path = self._path
        path.status, path.num_data = 0, len(data)
        path.data = self._ffi.cast("cairo_path_data_t *", self._ffi.from_buffer(data))
        self._lib.cairo_append_path(self._cr, path)

    def close(self) -> None:
        """Release the Cairo context and surface; safe to call more than once."""
        if self._closed:
            return
        self._closed = True
        del self._bgra
        self._context = None
        self._surface.finish()

    def __enter__(self) -> CairoRenderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def path_data(runs: list[tuple[list[int] | None, bool]], points: np.ndarray) -> np.ndarray:
    """Cairo's ``cairo_path_data_t`` array for polylines through ``points`` ``(n, 2)``: for each
    run (point indices, None for all of them, and whether it closes) a move-to, line-tos and
    maybe a close-path. Returns float64 ``(k, 2)``, 16 bytes an element as the C union lays
    them out: a header (type and length as int32) before each point, the close-path a header
    alone."""
    parts = [np.zeros((0, 2))]
    for run, closed in runs:
        pts = points if run is None else points[run]
        count = len(pts)
        if count == 0:
            continue
        data = np.zeros((2 * count + closed, 2))
        data[1:2 * count:2] = pts
        header = data.view(np.int32).reshape(-1, 4)  # [type, length, padding, padding]
        header[0:2 * count:2, :2] = (LINE_TO, 2)
        header[0, 0] = MOVE_TO
        if closed:
            header[-1, :2] = (CLOSE_PATH, 1)
        parts.append(data)
    return parts[-1] if len(parts) == 2 else np.concatenate(parts)


def visible_runs(count: int, closed: bool, visible: np.ndarray | None) -> list[tuple[list[int] | None, bool]]:
    """The stroked runs of an outline of ``count`` points: point indices (None: all of them) and
    whether the run closes. ``visible`` flags each edge (``count`` of them closed, ``count - 1``
    open); a run is a maximal chain of visible edges, joined where two meet as the GL strokes join."""
    edges = count if closed else count - 1
    if edges < 1:
        return []
    if visible is None or bool(np.all(visible)):
        return [(None, closed)]  # every point, in order
    flags = np.asarray(visible, dtype=bool)
    start = 0
    if closed:  # begin after a hidden edge so that a run through the closing point stays whole
        start = int(np.flatnonzero(~flags)[0]) + 1
    runs: list[tuple[list[int] | None, bool]] = []
    current: list[int] = []
    for step in range(edges):
        e = (start + step) % edges
        if flags[e]:
            current = current or [e % count]
            current.append((e + 1) % count)
        elif current:
            runs.append((current, False))
            current = []
    if current:
        runs.append((current, False))
    return runs
