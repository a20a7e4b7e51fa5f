"""The offscreen renderer: face geometry to RGB frames with moderngl.

Polygons may be concave, so each is triangulated (mapbox earcut) every frame; all triangles of a
frame go into one vertex buffer, drawn in four calls that differ only in depth state.
moderngl has no stencil API, so the depth buffer carries the masks of A1.2.2: holes write a depth
for their group (eye right, eye left, mouth), pupils are drawn only where the depth equals their
eye's group, and the face polygon only where no hole was drawn (the cleared depth). Later
polygons ignore depth. Antialiasing is multisampling, resolved before readback.
"""

from __future__ import annotations

import mapbox_earcut
import moderngl
import numpy as np

from toon import Geometry, fit_viewbox

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


def triangles_of(geometry: Geometry) -> tuple[np.ndarray, list[tuple[str, int, int]]]:
    """All triangle vertices of a frame and the draw ranges of each drawing step.

    Returns
    -------
    vertices : ndarray of float32, shape (V, 7)
        ``x, y, z, r, g, b, a`` per triangle corner.
    steps : list of (kind, first, count)
        Consecutive runs of the same drawing step, in drawing order.
    """
    chunks, steps = [], []
    start = 0
    for poly in geometry.polygons:
        idx = triangulate(poly.vertices)
        if len(idx) == 0:
            continue
        corners = poly.vertices[idx]
        block = np.empty((len(idx), _FLOATS_PER_VERTEX), dtype=np.float32)
        block[:, :2] = corners
        block[:, 2] = mask_depth(poly.mask) if poly.kind in ("hole", "pupil") else _CLEAR_DEPTH
        block[:, 3:] = poly.color
        chunks.append(block)
        step = "rest" if poly.kind in ("free", "point", "feature") else poly.kind
        if steps and steps[-1][0] == step:
            steps[-1] = (step, steps[-1][1], steps[-1][2] + len(idx))
        else:
            steps.append((step, start, len(idx)))
        start += len(idx)
    if not chunks:
        return np.empty((0, _FLOATS_PER_VERTEX), dtype=np.float32), []
    return np.concatenate(chunks), steps


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
        data, steps = triangles_of(geometry)
        self.set_view(geometry.viewbox)
        self.fbo.use()
        self.fbo.clear(*geometry.background[:3], 1.0, depth=_CLEAR_DEPTH)
        self.ctx.enable(moderngl.BLEND | moderngl.DEPTH_TEST)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        if len(data):
            self._upload(data)
        for step, first, count in steps:
            self._depth_state(step)
            self.vao.render(moderngl.TRIANGLES, vertices=count, first=first)
        self.fbo.depth_mask = True
        self.ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        return self.read()

    def _depth_state(self, step: str) -> None:
        """Depth as the mask of A1.2.2 (see the module docstring)."""
        if step == "hole":
            self.ctx.depth_func, self.fbo.depth_mask = "1", True  # always pass, write the group
        elif step in ("pupil", "face"):
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
