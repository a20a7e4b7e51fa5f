"""The offscreen renderer: face geometry to RGB frames with moderngl.

Each frame is planned by :class:`player.layout.FramePlanner`: per face structure, one index
buffer of four-index primitives over the frame's outline points, fills triangulated with mapbox
earcut (re-used from frame to frame while they still tile their outline) and strokes as segments
with their next neighbour. Only the points are uploaded per frame. A geometry shader turns each
primitive into triangles: a fill triangle as it is, a stroke segment into the quad and miter or
bevel join of :func:`toon.curves.stroke_triangles`, so the GPU builds the strokes the CPU oracle
draws. The primitives are drawn in runs that differ only in depth and blend state.

moderngl has no stencil API, so the depth buffer carries the masks of A1.2.2: holes write a depth
for their group (eye right, eye left, mouth), pupils and clipped components are drawn only where
the depth equals their group, and the face polygon only where no hole was drawn (the cleared
depth). Everything else ignores depth. Antialiasing is multisampling, resolved before readback.
"""

from __future__ import annotations

import cv2
import moderngl
import numpy as np

from player.alpha import premultiplied_clear, straight
from player.gl_pictures import PictureDrawer
from player.layout import CLEAR_DEPTH, CORNERS, PICTURE, DrawLayout, FramePlanner, mask_depth
from toon import Geometry, fit_viewbox
from toon.curves import MITER_LIMIT

#: Colour as before; coverage adds up in alpha, so the framebuffer holds premultiplied RGBA.
BLEND = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA)
_VERTEX_SHADER = """
#version 330
in vec2 in_pos;    // face units
in vec4 in_color;  // markers only: the primitive's colour
in vec2 in_extra;  // markers only: mask depth in [0, 1], half stroke width (0: a fill triangle)
out vec2 v_pos;
out vec4 v_color;
out vec2 v_extra;
void main() {
    v_pos = in_pos;
    v_color = in_color;
    v_extra = in_extra;
    gl_Position = vec4(0.0);
}
"""
# Corners 0-2: a fill triangle, or a segment a-b and the point c after it (c = b: no join).
# Corner 3: the marker. The stroke triangles are those of toon.curves.stroke_triangles.
_GEOMETRY_SHADER = """
#version 330
layout(lines_adjacency) in;
layout(triangle_strip, max_vertices = 8) out;
uniform vec4 u_map;  // scale x, scale y, offset x, offset y: face units -> clip space
in vec2 v_pos[];
in vec4 v_color[];
in vec2 v_extra[];
out vec4 g_color;
float depth;

void corner(vec2 p) {
    gl_Position = vec4(p * u_map.xy + u_map.zw, depth * 2.0 - 1.0, 1.0);
    g_color = v_color[3];
    EmitVertex();
}

void main() {
    depth = v_extra[3].x;
    float h = v_extra[3].y;
    vec2 a = v_pos[0], b = v_pos[1], c = v_pos[2];
    if (h <= 0.0) {
        corner(a); corner(b); corner(c); EndPrimitive();
        return;
    }
    float len = length(b - a);
    if (len <= 1e-12) return;
    vec2 d = (b - a) / len;
    vec2 n = vec2(-d.y, d.x) * h;
    corner(a + n); corner(b + n); corner(a - n); corner(b - n); EndPrimitive();
    float len2 = length(c - b);
    if (len2 <= 1e-12) return;
    vec2 d2 = (c - b) / len2;
    float cross = d.x * d2.y - d.y * d2.x;
    if (abs(cross) <= 1e-9) return;
    vec2 n2 = vec2(-d2.y, d2.x) * h;
    float side = -sign(cross);  // the outer side of the turn
    vec2 p0 = b + side * n, p1 = b + side * n2;
    vec2 bisector = n + n2;
    float bis_len = max(length(bisector), 1e-12);
    float ratio = 1.0 / max(dot(bisector, n) / (bis_len * h), 1e-12);
    if (ratio <= MITER_LIMIT) {
        vec2 tip = b + side * bisector / bis_len * (h * ratio);
        corner(p0); corner(tip); corner(b); corner(p1);
    } else {
        corner(b); corner(p0); corner(p1);
    }
    EndPrimitive();
}
""".replace("MITER_LIMIT", repr(float(MITER_LIMIT)))
_FRAGMENT_SHADER = """
#version 330
in vec4 g_color;
out vec4 f_color;
void main() { f_color = g_color; }
"""


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

    Notes
    -----
    The renderer owns its GL objects; :meth:`close` releases them and is safe to call twice.
    """

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int] = (512, 512), samples: int = 4) -> None:
        self.ctx = ctx
        self.size = (int(size[0]), int(size[1]))
        if min(self.size) < 1 or max(self.size) > 8192:
            raise ValueError(f"frame size must be 1..8192 pixels per side, got {self.size}")
        self.samples = min(max(samples, 0), ctx.max_samples) if samples > 1 else 0
        self.planner = FramePlanner()
        self._objects: list = []
        self.program = self._own(ctx.program(vertex_shader=_VERTEX_SHADER, geometry_shader=_GEOMETRY_SHADER,
                                              fragment_shader=_FRAGMENT_SHADER))
        self.points = self._own(ctx.buffer(reserve=4096, dynamic=True))
        self.attributes = self._own(ctx.buffer(reserve=4096))
        self.indices = self._own(ctx.buffer(reserve=4096))
        self.vao = self._own(ctx.vertex_array(
            self.program, [(self.points, "2f", "in_pos"), (self.attributes, "4f 2f", "in_color", "in_extra")],
            index_buffer=self.indices, index_element_size=4))
        self._pictures: PictureDrawer | None = None  # made with the first picture to draw
        self._layout: DrawLayout | None = None  # the layout whose indices and attributes are uploaded
        self._viewbox: tuple[float, float, float, float] | None = None  # the one u_map maps now
        color = self._own(ctx.renderbuffer(self.size, 4, samples=self.samples))
        depth = self._own(ctx.depth_renderbuffer(self.size, samples=self.samples))
        self.fbo = self._own(ctx.framebuffer(color_attachments=[color], depth_attachment=depth))
        if self.samples:
            resolved = self._own(ctx.renderbuffer(self.size, 4))
            self.resolve_fbo = self._own(ctx.framebuffer(color_attachments=[resolved]))
        else:
            self.resolve_fbo = self.fbo
        self._rgba = np.empty((self.size[1], self.size[0], 4), dtype=np.uint8)  # readback, re-used
        self._closed = False

    def _own(self, obj):
        self._objects.append(obj)
        return obj

    @staticmethod
    def _write(buffer: moderngl.Buffer, data: np.ndarray) -> None:
        """Write ``data`` at the start of ``buffer``, growing it (to at least double) if needed."""
        if data.nbytes > buffer.size:
            buffer.orphan(max(data.nbytes, 2 * buffer.size))
        buffer.write(data)

    def _upload(self, layout: DrawLayout, points: np.ndarray) -> None:
        """Points every frame; indices and marker attributes only when the layout changed.

        Markers are vertices too, so the points buffer spans them (their positions go unread).
        """
        if layout is not self._layout:
            self._write(self.indices, layout.indices)
            self._write(self.attributes, layout.attributes)
            point_bytes = len(layout.attributes) * 2 * 4
            if self.points.size < point_bytes:
                self.points.orphan(max(point_bytes, 2 * self.points.size))
            self._layout = layout
        self._write(self.points, np.ascontiguousarray(points, dtype=np.float32))

    def set_view(self, viewbox: tuple[float, float, float, float]) -> None:
        """Map ``viewbox`` (face units) onto the framebuffer, centred, aspect kept, upside down.

        GL's first row is the bottom one, so the picture is drawn upside down: its top row comes
        back first, and the readback needs no flip.
        """
        if viewbox == self._viewbox:
            return
        width, height = self.size
        scale, ox, oy = fit_viewbox(viewbox, self.size)
        sx, sy = 2 * scale / width, 2 * scale / height
        # px = (x - xmin) * scale + ox, py = (ymax - y) * scale + oy (rows down from the top)
        # -> clip x = 2 px / W - 1; clip y = 2 py / H - 1, so GL row 0 is picture row 0.
        self.program["u_map"].value = (sx, -sy, (2 * (ox - viewbox[0] * scale)) / width - 1,
                                       2 * (oy + viewbox[3] * scale) / height - 1)
        self._viewbox = viewbox

    def render(self, geometry: Geometry, alpha: bool = False) -> np.ndarray:
        """Draw one frame; returns RGB ``uint8`` of shape ``(height, width, 3)``, row 0 at the top,
        or with ``alpha`` straight RGBA ``(height, width, 4)`` (a transparent background stays
        transparent; :mod:`player.alpha`)."""
        if self._closed:
            raise RuntimeError("renderer is closed")
        layout, points = self.planner.plan(geometry)
        self.set_view(geometry.viewbox)
        self.fbo.use()
        self.fbo.clear(*premultiplied_clear(geometry.background), depth=CLEAR_DEPTH)
        self.ctx.blend_func = BLEND  # type: ignore[assignment]  # moderngl's stub knows 2 only
        if layout.runs:
            self._upload(layout, points)
        for (mode, blend), first, count in layout.runs:
            if mode.startswith(PICTURE):
                self._picture(geometry.items[int(mode.split()[1])])
                continue
            self._set_state(mode, blend)
            self.vao.render(moderngl.LINES_ADJACENCY, vertices=count * CORNERS, first=first * CORNERS)
        self.fbo.depth_mask = True
        self.ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        return self.read(alpha)

    def _picture(self, item) -> None:
        """An image component's picture, masked as a clipped component is."""
        if self._pictures is None:
            self._pictures = PictureDrawer(self.ctx)
        group = item.mask_test
        self._set_state("none" if group is None else "test", True)
        self._pictures.draw(item, tuple(self.program["u_map"].value), mask_depth(group) if group else CLEAR_DEPTH,
                            BLEND)

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

    def read(self, alpha: bool = False) -> np.ndarray:
        """Resolve and read back the framebuffer: RGB ``uint8`` ``(height, width, 3)``, row 0 on top
        (straight RGBA ``(height, width, 4)`` with ``alpha``).

        Mesa reads RGBA as a plain copy but converts pixel by pixel to RGB (about 1 ms more at
        512x512 on llvmpipe), so RGBA is read into a buffer kept for it and OpenCV drops alpha.
        The rows need no flip: :meth:`set_view` draws the picture upside down.
        """
        if self.resolve_fbo is not self.fbo:
            self.ctx.copy_framebuffer(self.resolve_fbo, self.fbo)
        self.resolve_fbo.read_into(self._rgba, components=4)
        if alpha:
            return straight(self._rgba)
        return cv2.cvtColor(self._rgba, cv2.COLOR_RGBA2RGB)

    def close(self) -> None:
        """Release every GL object this renderer made; safe to call more than once."""
        if self._closed:
            return
        # moderngl re-binds the last used framebuffer whenever it makes another one; leave the
        # context on framebuffer 0 so it never re-binds one released here (GL_INVALID_OPERATION).
        if self.ctx.fbo is self.fbo or self.ctx.fbo is self.resolve_fbo:
            self.ctx.detect_framebuffer(0).use()
        if self._pictures is not None:
            self._pictures.release()
            self._pictures = None
        for obj in reversed(self._objects):
            obj.release()
        self._objects.clear()
        self._closed = True

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
