"""The offscreen renderer: face geometry to RGB frames with moderngl.

Fills may be concave, so each outline is triangulated with mapbox earcut; a triangulation is kept
from frame to frame and re-used while every one of its triangles keeps the orientation it had when made
(for a simple outline that proves it still tiles it), so most frames triangulate nothing. Strokes
are the triangles of :func:`toon.curves.stroke_triangles`. All triangles of a frame go into one
vertex buffer, drawn in runs that differ only in depth state.

moderngl has no stencil API, so the depth buffer carries the masks of A1.2.2: holes write a depth
for their group (eye right, eye left, mouth), pupils and clipped components are drawn only where
the depth equals their group, and the face polygon only where no hole was drawn (the cleared
depth). Everything else ignores depth. Antialiasing is multisampling, resolved before readback.
"""

from __future__ import annotations

import mapbox_earcut
import moderngl
import numpy as np

from toon import DrawItem, Geometry, fit_viewbox
from toon.curves import stroke_many

_VERTEX_SHADER = """
#version 330
uniform vec4 u_map;  // scale x, scale y, offset x, offset y: face units -> clip space
in vec3 in_pos;      // x, y in face units; z: mask depth in [0, 1]
in vec4 in_color;
out vec4 v_color;
void main() {
    gl_Position = vec4(in_pos.xy * u_map.xy + u_map.zw, in_pos.z * 2.0 - 1.0, 1.0);
    v_color = in_color;
}
"""
_FRAGMENT_SHADER = """
#version 330
in vec4 v_color;
out vec4 f_color;
void main() { f_color = v_color; }
"""
_FLOATS_PER_VERTEX = 7
_CLEAR_DEPTH = 1.0


def mask_depth(group: int) -> float:
    """Depth written by the holes of mask group ``group`` (1, 2, 3, ...); 1.0 means no hole."""
    return group / 16.0


def triangulate(vertices: np.ndarray) -> np.ndarray:
    """Triangle corner indices of a simple polygon ``(N, 2)``; shape ``(3 * T,)``."""
    return mapbox_earcut.triangulate_float64(np.ascontiguousarray(vertices, dtype=np.float64),
                                             np.array([len(vertices)], dtype=np.uint32))


class Triangulator:
    """Fill triangulations of a face's items, kept by item key from frame to frame.

    A kept triangulation is re-used while the outline has the same number of vertices and every
    one of its triangles keeps the orientation it had against the outline when it was made (earcut
    emits a clockwise outline's triangles counter-clockwise): index triangles that tile an N-gon
    tile any simple N-gon whose vertices leave them all so oriented (their winding numbers add up
    to the outline's). The check runs on all of a frame's kept triangulations at once.
    """

    def __init__(self) -> None:
        self._cache: dict[int, tuple[int, np.ndarray]] = {}
        self._relation: dict[int, float] = {}  # +1: triangles wound like the outline, -1: against
        self.reused = 0
        self.computed = 0

    def kept(self, item: DrawItem) -> np.ndarray | None:
        """The kept triangulation of ``item`` if it still indexes its outline, else ``None``."""
        known = self._cache.get(item.key)
        if known is None or known[0] != len(item.vertices) or not len(known[1]):
            return None
        return known[1]

    def compute(self, item: DrawItem) -> np.ndarray:
        """Triangulate ``item``'s outline afresh and keep the result."""
        indices = triangulate(item.vertices)
        self._cache[item.key] = (len(item.vertices), indices)
        self._relation[item.key] = _winding_relation(item.vertices, indices)
        self.computed += 1
        return indices

    def still_valid(self, items: list[DrawItem], corners: list[np.ndarray]) -> np.ndarray:
        """For each item, whether its kept triangles ``corners`` (3T, 2) all keep their orientation."""
        verts = np.concatenate([it.vertices for it in items])
        sizes = np.array([len(it.vertices) for it in items])
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        following = np.arange(len(verts)) + 1
        following[starts + sizes - 1] = starts
        x, y = verts[:, 0], verts[:, 1]
        area = np.add.reduceat(x * y[following] - x[following] * y, starts)  # twice the signed area
        cross = _triangle_cross(np.concatenate(corners))
        counts = np.array([len(c) // 3 for c in corners])
        owner = np.repeat(np.arange(len(items)), counts)
        relation = np.array([self._relation[it.key] for it in items])
        good = cross * (np.sign(area) * relation)[owner] > 0
        valid = np.minimum.reduceat(good, np.concatenate([[0], np.cumsum(counts)[:-1]]))
        valid &= np.abs(area) > 1e-9
        self.reused += int(valid.sum())
        return valid


def _winding_relation(outline: np.ndarray, indices: np.ndarray) -> float:
    """+1 if the triangles ``indices`` of ``outline`` (N, 2) wind as it does, -1 if against it."""
    if not len(indices):
        return 1.0
    x, y = outline[:, 0], outline[:, 1]
    area = np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    return 1.0 if np.sum(_triangle_cross(outline[indices])) * area >= 0 else -1.0


def _triangle_cross(corners: np.ndarray) -> np.ndarray:
    """Twice the signed area of each triangle of ``corners`` ``(3T, 2)``; shape ``(T,)``."""
    tris = corners.reshape(-1, 3, 2)
    e1, e2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    return e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]


def _mode(item: DrawItem, stroke: bool) -> str:
    if item.mask_write and not stroke:
        return "write"
    return "none" if item.mask_test is None else "test"


def triangles_of(geometry: Geometry, triangulator: Triangulator | None = None
                 ) -> tuple[np.ndarray, list[tuple[tuple[str, bool], int, int]]]:
    """All triangle corners of a frame and the draw runs of each depth mode.

    Returns
    -------
    vertices : ndarray of float32, shape (V, 7)
        ``x, y, z, r, g, b, a`` per triangle corner; ``z`` is the mask depth written or tested.
    runs : list of ((mode, blend), first, count)
        Consecutive corners drawn with the same depth mode (``write``, ``test`` or ``none``) and
        the same need for blending (a colour that is not opaque).
    """
    triangulator = triangulator or Triangulator()
    corners: list[np.ndarray] = []
    attributes: list[tuple[float, float, float, float, float]] = []
    modes: list[tuple[str, bool]] = []
    to_check: list[tuple[int, DrawItem]] = []
    strokes: list[tuple[int, DrawItem]] = []
    for item in geometry.items:
        if item.fill is not None and item.closed:
            idx = triangulator.kept(item)
            if idx is None:
                idx = triangulator.compute(item)
            elif len(idx):
                to_check.append((len(corners), item))
            if len(idx):
                _add(corners, attributes, modes, item, item.vertices[idx], item.fill, False)
        if item.stroke is not None and item.width > 0:
            strokes.append((len(corners), item))
            _add(corners, attributes, modes, item, np.empty((0, 2)), item.stroke, True)
    if strokes:
        stroked = stroke_many([(it.vertices, it.width, it.closed, it.edge_visible) for _, it in strokes])
        for (k, _), tris in zip(strokes, stroked):
            corners[k] = tris
    if to_check:
        valid = triangulator.still_valid([it for _, it in to_check], [corners[k] for k, _ in to_check])
        for (k, item), ok in zip(to_check, valid):
            if not ok:
                corners[k] = item.vertices[triangulator.compute(item)]
    if not corners:
        return np.empty((0, _FLOATS_PER_VERTEX), dtype=np.float32), []
    counts = np.array([len(c) for c in corners])
    data = np.empty((int(counts.sum()), _FLOATS_PER_VERTEX), dtype=np.float32)
    data[:, :2] = np.concatenate(corners)
    data[:, 2:] = np.repeat(np.array(attributes, dtype=np.float32), counts, axis=0)
    runs: list[tuple[tuple[str, bool], int, int]] = []
    start = 0
    for mode, count in zip(modes, counts):
        if not count:
            continue
        if runs and runs[-1][0] == mode:
            runs[-1] = (mode, runs[-1][1], runs[-1][2] + int(count))
        else:
            runs.append((mode, start, int(count)))
        start += int(count)
    return data, runs


def _add(corners: list, attributes: list, modes: list, item: DrawItem, tris: np.ndarray,
         color: tuple[float, float, float, float], stroke: bool) -> None:
    mode = _mode(item, stroke)
    group = item.mask_write if mode == "write" else (item.mask_test or 0)
    corners.append(tris)
    attributes.append((mask_depth(group) if group else _CLEAR_DEPTH, *color))
    modes.append((mode, color[3] < 1.0))


class Renderer:
    """Draws :class:`toon.Geometry` into an offscreen framebuffer and reads it back.

    Parameters
    ----------
    ctx : moderngl.Context
        Owned by the caller; see :func:`player.gl.create_context`.
    size : (width, height)
        Pixels.
    samples : int
        Multisamples for antialiasing (0 or 1 for none); capped at what the context supports.

    The renderer owns its GL objects; :meth:`close` releases them and is safe to call twice.
    """

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int] = (512, 512), samples: int = 4) -> None:
        self.ctx = ctx
        self.size = (int(size[0]), int(size[1]))
        if min(self.size) < 1 or max(self.size) > 8192:
            raise ValueError(f"frame size must be 1..8192 pixels per side, got {self.size}")
        self.samples = min(max(samples, 0), ctx.max_samples) if samples > 1 else 0
        self.triangulator = Triangulator()
        self._objects: list = []
        self.program = self._own(ctx.program(vertex_shader=_VERTEX_SHADER, fragment_shader=_FRAGMENT_SHADER))
        self.vbo = self._own(ctx.buffer(reserve=4096, dynamic=True))
        self.vao = self._own(ctx.vertex_array(self.program, [(self.vbo, "3f 4f", "in_pos", "in_color")]))
        color = self._own(ctx.renderbuffer(self.size, 4, samples=self.samples))
        depth = self._own(ctx.depth_renderbuffer(self.size, samples=self.samples))
        self.fbo = self._own(ctx.framebuffer(color_attachments=[color], depth_attachment=depth))
        if self.samples:
            resolved = self._own(ctx.renderbuffer(self.size, 4))
            self.resolve_fbo = self._own(ctx.framebuffer(color_attachments=[resolved]))
        else:
            self.resolve_fbo = self.fbo
        self._closed = False

    def _own(self, obj):
        self._objects.append(obj)
        return obj

    def _upload(self, data: np.ndarray) -> None:
        nbytes = data.nbytes
        if nbytes > self.vbo.size:
            self.vbo.orphan(max(nbytes, 2 * self.vbo.size))
        self.vbo.write(data.tobytes())

    def set_view(self, viewbox: tuple[float, float, float, float]) -> None:
        """Map ``viewbox`` (face units) onto the framebuffer, centred, aspect kept."""
        width, height = self.size
        scale, ox, oy = fit_viewbox(viewbox, self.size)
        sx, sy = 2 * scale / width, 2 * scale / height
        # px = (x - xmin) * scale + ox  ->  clip x = 2 px / W - 1; clip y = 1 - 2 py / H.
        self.program["u_map"].value = (sx, sy, (2 * (ox - viewbox[0] * scale)) / width - 1,
                                       1 - 2 * (oy + viewbox[3] * scale) / height)

    def render(self, geometry: Geometry) -> np.ndarray:
        """Draw one frame; returns RGB ``uint8`` of shape ``(height, width, 3)``, row 0 at the top."""
        if self._closed:
            raise RuntimeError("renderer is closed")
        data, runs = triangles_of(geometry, self.triangulator)
        self.set_view(geometry.viewbox)
        self.fbo.use()
        self.fbo.clear(*geometry.background[:3], 1.0, depth=_CLEAR_DEPTH)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        if len(data):
            self._upload(data)
        for (mode, blend), first, count in runs:
            self._set_state(mode, blend)
            self.vao.render(moderngl.TRIANGLES, vertices=count, first=first)
        self.fbo.depth_mask = True
        self.ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        return self.read()

    def _set_state(self, mode: str, blend: bool) -> None:
        """Depth as the mask of A1.2.2 (see the module docstring); blending only where needed.

        Depth testing and blending cost per sample on a software rasteriser, so runs that need
        neither (opaque, unmasked) draw with both off.
        """
        if mode == "none":
            self.ctx.disable(moderngl.DEPTH_TEST)
        else:
            self.ctx.enable(moderngl.DEPTH_TEST)
            if mode == "write":
                self.ctx.depth_func, self.fbo.depth_mask = "1", True  # always pass, write the group
            else:
                self.ctx.depth_func, self.fbo.depth_mask = "==", False  # own group / no hole
        if blend:
            self.ctx.enable(moderngl.BLEND)
        else:
            self.ctx.disable(moderngl.BLEND)

    def read(self) -> np.ndarray:
        """Resolve and read back the framebuffer: RGB ``uint8`` ``(height, width, 3)``, row 0 on top."""
        if self.resolve_fbo is not self.fbo:
            self.ctx.copy_framebuffer(self.resolve_fbo, self.fbo)
        width, height = self.size
        raw = self.resolve_fbo.read(components=3, alignment=1)
        return np.frombuffer(raw, dtype=np.uint8).reshape(height, width, 3)[::-1]

    def close(self) -> None:
        """Release every GL object this renderer made; safe to call more than once."""
        if self._closed:
            return
        # moderngl re-binds the last used framebuffer whenever it makes another one; leave the
        # context on framebuffer 0 so it never re-binds one released here (GL_INVALID_OPERATION).
        if self.ctx.fbo is self.fbo or self.ctx.fbo is self.resolve_fbo:
            self.ctx.detect_framebuffer(0).use()
        for obj in reversed(self._objects):
            obj.release()
        self._objects.clear()
        self._closed = True

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
