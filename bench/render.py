"""``render``: frames per second of the renderer, with readback, against a one-draw-call floor.

``render.fps``: the default face at 512x512 (4x MSAA): geometry built from motor values and
triangulated every frame, uploaded, drawn in its depth-masked steps and read back.
``render.floor_fps``: the same triangles (the face at rest), uploaded once and drawn in a single
call into the same framebuffer with the same readback: what drawing this many corners costs with
no per-frame work. ``render.ratio`` = fps / floor_fps.
"""

from __future__ import annotations

from collections.abc import Callable

import moderngl

from bench.core import Figure, median_rate
from capture import synthesize
from player import Renderer, create_context
from player.renderer import triangles_of
from toon import FaceRig, load_face, standard_neutral
from toonface import map_take

GOAL_FPS = 30.0  # real-time playback of a 30 fps take on this CPU-only machine
GOAL_RATIO = 0.5  # per-frame deformation, triangulation and upload at most as costly as drawing


def run(quick: bool = False) -> list[Figure]:
    """Measure and return ``render.fps``, ``render.floor_fps`` and ``render.ratio``."""
    size, frames, repeats = (512, 512), (10 if quick else 60), (2 if quick else 5)
    values = map_take(synthesize(seconds=max(frames / 30, 1.0), rate=30.0).take).values[:frames]
    rig = FaceRig(load_face("classic"))
    ctx = create_context()
    try:
        gl_renderer = ctx.info.get("GL_RENDERER", "unknown")
        with Renderer(ctx, size, samples=4) as renderer:
            def face_frames() -> int:
                for row in values:
                    renderer.render(rig.geometry(row))
                return len(values)

            fps, fps_runs = median_rate(face_frames, repeats)
            rest = rig.geometry(standard_neutral())
            floor_draw, release, corners = _one_call_scene(ctx, renderer, rest, frames)
            try:
                floor, floor_runs = median_rate(floor_draw, repeats)
            finally:
                release()
    finally:
        ctx.release()
    detail = {"size": list(size), "samples": 4, "frames_per_repeat": len(values), "repeats": repeats,
              "triangle_corners": corners, "gl_renderer": gl_renderer}
    return [
        Figure("render.fps", fps, "frames/s", GOAL_FPS, True, {**detail, "runs": _rounded(fps_runs)}),
        Figure("render.floor_fps", floor, "frames/s", None, True, {**detail, "runs": _rounded(floor_runs)}),
        Figure("render.ratio", fps / floor, "ratio", GOAL_RATIO, True, detail),
    ]


def _one_call_scene(ctx: moderngl.Context, renderer: Renderer, geometry, frames: int
                    ) -> tuple[Callable[[], int], Callable[[], None], int]:
    """Draw ``geometry``'s triangles, static, in one call ``frames`` times: (draw, release, corner count)."""
    data, _ = triangles_of(geometry)
    data[:, 2] = 1.0
    vbo = ctx.buffer(data.tobytes())
    vao = ctx.vertex_array(renderer.program, [(vbo, "3f 4f", "in_pos", "in_color")])
    renderer.set_view(geometry.viewbox)

    def draw() -> int:
        for _ in range(frames):
            renderer.fbo.use()
            renderer.fbo.clear(*geometry.background[:3], 1.0, depth=1.0)
            vao.render(moderngl.TRIANGLES)
            renderer.read()
        return frames

    def release() -> None:
        vao.release()
        vbo.release()

    return draw, release, len(data)


def _rounded(values: list[float]) -> list[float]:
    return [round(v, 2) for v in values]
