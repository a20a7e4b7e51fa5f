"""Image components' pictures drawn by the OpenGL renderer (:class:`player.renderer.Renderer`).

A picture is a texture made once per picture (premultiplied RGBA, filtered linearly, its edges
clamped, as the CPU oracle samples it), drawn as a quad on its four corners in the frame's drawing
order, with the depth of its mask group so that a clipped picture shows only inside its holes.
"""

from __future__ import annotations

import moderngl
import numpy as np

from toon import DrawItem

_VERTEX_SHADER = """
#version 330
uniform vec4 u_map;    // face units -> clip space, as the outlines' program maps them
uniform float u_depth; // the mask group's depth (or the cleared depth)
in vec2 in_pos;
in vec2 in_uv;
out vec2 v_uv;
void main() {
    v_uv = in_uv;
    gl_Position = vec4(in_pos * u_map.xy + u_map.zw, u_depth * 2.0 - 1.0, 1.0);
}
"""
_FRAGMENT_SHADER = """
#version 330
uniform sampler2D u_picture;  // premultiplied
uniform float u_opacity;
in vec2 v_uv;
out vec4 f_color;
void main() { f_color = texture(u_picture, v_uv) * u_opacity; }
"""
#: The quad's corners as a triangle strip: top-left, top-right, bottom-left, bottom-right (rows of
#: :attr:`toon.DrawItem.vertices`: top-left, top-right, bottom-right, bottom-left), with their
#: texture coordinates (the picture's first row at v = 0).
_STRIP = np.array([0, 1, 3, 2])
_UV = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])


class PictureDrawer:
    """Draws pictures on ``ctx``; owns its program, buffer and textures (:meth:`release`)."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.program = ctx.program(vertex_shader=_VERTEX_SHADER, fragment_shader=_FRAGMENT_SHADER)
        self.quad = ctx.buffer(reserve=4 * 4 * 4, dynamic=True)
        self.vao = ctx.vertex_array(self.program, [(self.quad, "2f 2f", "in_pos", "in_uv")])
        self._textures: dict[str, moderngl.Texture] = {}  # a picture's data -> its texture

    def _set(self, name: str, value: object) -> None:
        uniform = self.program[name]
        assert isinstance(uniform, moderngl.Uniform)
        uniform.value = value

    def draw(self, item: DrawItem, u_map: tuple[float, float, float, float], depth: float,
             blend: tuple[int, int, int, int]) -> None:
        """Draw ``item``'s picture on its corners at ``depth``, blending premultiplied colour over
        the frame (the caller has set the depth test for its mask); the frame's ``blend`` function
        is set again after."""
        picture = item.picture
        assert picture is not None and len(item.vertices) == 4
        texture = self._textures.get(picture.href)
        if texture is None:
            rgba = picture.pixels.astype(np.float32)
            rgba[..., :3] *= rgba[..., 3:] / 255.0
            texture = self.ctx.texture(picture.size, 4, np.round(rgba).astype(np.uint8).tobytes())
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            texture.repeat_x = texture.repeat_y = False
            self._textures[picture.href] = texture
        self.quad.write(np.hstack([item.vertices[_STRIP], _UV]).astype(np.float32).tobytes())
        self._set("u_map", u_map)
        self._set("u_depth", depth)
        self._set("u_opacity", float(item.opacity))
        texture.use(0)
        self._set("u_picture", 0)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA  # the texture is premultiplied
        self.vao.render(moderngl.TRIANGLE_STRIP)
        self.ctx.blend_func = blend  # type: ignore[assignment]  # moderngl's stub knows 2 only

    def release(self) -> None:
        """Release every GL object this drawer made."""
        for texture in self._textures.values():
            texture.release()
        self._textures.clear()
        for obj in (self.vao, self.quad, self.program):
            obj.release()
