"""The offscreen renderer: face geometry to RGB frames with moderngl.

Fills may be concave, so each outline is triangulated with mapbox earcut; a triangulation is kept
from frame to frame and re-used while every one of its triangles keeps the outline's orientation
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
from toon.curves import stroke_triangles

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


def _orientation_kept(vertices: np.ndarray, indices: np.ndarray) -> bool:
    """Whether every triangle has the same, non-zero orientation as the outline."""
    x, y = vertices[:, 0], vertices[:, 1]
    area = float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    if abs(area) < 1e-9:
        return False
    t = vertices[indices].reshape(-1, 3, 2)
    e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    cross = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    return bool(np.all(cross * np.sign(area) > 0))


class Triangulator:
    """Fill triangulations of a face's items, kept by item key and re-used while still valid."""

    def __init__(self) -> None:
        self._cache: dict[int, np.ndarray] = {}
        self.reused = 0
        self.computed = 0

    def fill(self, item: DrawItem) -> np.ndarray:
        """Triangle corner indices ``(3 * T,)`` that fill ``item``'s outline."""
        known = self._cache.get(item.key)
        if known is not None and len(known) and int(known.max()) < len(item.vertices) \
                and _orientation_kept(item.vertices, known):
            self.reused += 1
            return known
        indices = triangulate(item.vertices)
        self._cache[item.key] = indices
        self.computed += 1
        return indices


def _mode(item: DrawItem, stroke: bool) -> str:
    if item.mask_write and not stroke:
        return "write"
    return "none" if item.mask_test is None else "test"


def triangles_of(geometry: Geometry, triangulator: Triangulator | None = None
                 ) -> tuple[np.ndarray, list[tuple[str, int, int]]]:
    """All triangle corners of a frame and the draw runs of each depth mode.

    Returns
    -------
    vertices : ndarray of float32, shape (V, 7)
        ``x, y, z, r, g, b, a`` per triangle corner; ``z`` is the mask depth written or tested.
    runs : list of (mode, first, count)
        Consecutive corners drawn with the same depth mode (``write``, ``test`` or ``none``).
    """
    triangulator = triangulator or Triangulator()
    chunks, runs = [], []
    start = 0
    for item in geometry.items:
        parts = []
        if item.fill is not None and item.closed:
            idx = triangulator.fill(item)
            if len(idx):
                parts.append((item.vertices[idx], item.fill, False))
        if item.stroke is not None and item.width > 0:
            corners = stroke_triangles(item.vertices, item.width, item.closed, item.edge_visible)
            if len(corners):
                parts.append((corners, item.stroke, True))
        for corners, color, stroke in parts:
            mode = _mode(item, stroke)
            group = item.mask_write if mode == "write" else (item.mask_test or 0)
            block = np.empty((len(corners), _FLOATS_PER_VERTEX), dtype=np.float32)
            block[:, :2] = corners
            block[:, 2] = mask_depth(group) if group else _CLEAR_DEPTH
            block[:, 3:] = color
            chunks.append(block)
            if runs and runs[-1][0] == mode:
                runs[-1] = (mode, runs[-1][1], runs[-1][2] + len(corners))
            else:
                runs.append((mode, start, len(corners)))
            start += len(corners)
    if not chunks:
        return np.empty((0, _FLOATS_PER_VERTEX), dtype=np.float32), []
    return np.concatenate(chunks), runs


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
        self._capacity = 0
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
        self.ctx.enable(moderngl.BLEND | moderngl.DEPTH_TEST)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        if len(data):
            self._upload(data)
        for mode, first, count in runs:
            self._depth_state(mode)
            self.vao.render(moderngl.TRIANGLES, vertices=count, first=first)
        self.fbo.depth_mask = True
        self.ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        return self.read()

    def _depth_state(self, mode: str) -> None:
        """Depth as the mask of A1.2.2 (see the module docstring)."""
        if mode == "write":
            self.ctx.depth_func, self.fbo.depth_mask = "1", True  # always pass, write the group
        elif mode == "test":
            self.ctx.depth_func, self.fbo.depth_mask = "==", False  # own group / no hole
        else:
            self.ctx.depth_func, self.fbo.depth_mask = "1", False

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
