"""``render``: frames per second of the renderer on every built-in face, against a bare floor.

For each built-in face, at 512x512 with 4x MSAA and readback:

``render.fps.<face>``: a mapped synthetic take played on the face: geometry built from motor
values every frame (features, skeletons, splines, head turn), fills triangulated or re-used,
points uploaded, strokes expanded by the geometry shader, drawn in their depth-masked runs and
read back.
``render.floor_fps.<face>``: the same face's triangles at rest (fills and strokes built on the
CPU), uploaded once and drawn by a bare shader in a single call into the same framebuffer with the
same readback: what drawing these triangles costs with no per-frame work. ``render.ratio.<face>`` = fps / floor, measured in alternating
repeats so that both see the same machine, and the median of the repeats' ratios reported.
``render.fps`` and ``render.ratio`` are the slowest face's figures.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable

import moderngl
import numpy as np

from bench.core import Figure
from capture import synthesize
from player import Renderer, create_context
from player.layout import triangulate
from toon import FaceRig, Geometry, builtin_faces, load_face
from toon.curves import stroke_many
from toonface import map_take

GOAL_FPS = 150.0  # the figure for this machine's 2 cores (0.7 of a floor near 215 fps)
GOAL_RATIO = 0.7  # per-frame deformation, triangulation and upload cost under half the drawing


def run(quick: bool = False) -> list[Figure]:
    """Measure every built-in face; return per-face figures and the slowest face's summary."""
    size, frames, repeats = (512, 512), (10 if quick else 60), (2 if quick else 5)
    values = map_take(synthesize(seconds=max(frames / 30, 1.0), rate=30.0).take).values[:frames]
    figures: list[Figure] = []
    worst: tuple[float, float, str] | None = None
    ctx = create_context()
    try:
        gl_renderer = ctx.info.get("GL_RENDERER", "unknown")
        for name in builtin_faces():
            face = load_face(name)
            rig = FaceRig(face)
            with Renderer(ctx, size, samples=4) as renderer:
                def face_frames() -> int:
                    for row in values:
                        renderer.render(rig.geometry(row))
                    return len(values)

                floor_draw, release, corners = _one_call_scene(ctx, renderer, rig.geometry(face.neutral()), frames)
                try:
                    fps_runs, floor_runs = _alternate(face_frames, floor_draw, repeats)
                finally:
                    release()
            ratios = [a / b for a, b in zip(fps_runs, floor_runs)]
            fps, floor, ratio = statistics.median(fps_runs), statistics.median(floor_runs), statistics.median(ratios)
            detail = {"face": name, "size": list(size), "samples": 4, "frames_per_repeat": len(values),
                      "repeats": repeats, "triangle_corners_at_rest": corners, "gl_renderer": gl_renderer}
            figures += [
                Figure(f"render.fps.{name}", fps, "frames/s", GOAL_FPS, True, {**detail, "runs": _rounded(fps_runs)}),
                Figure(f"render.floor_fps.{name}", floor, "frames/s", None, True,
                       {**detail, "runs": _rounded(floor_runs)}),
                Figure(f"render.ratio.{name}", ratio, "ratio", GOAL_RATIO, True,
                       {**detail, "runs": [round(r, 3) for r in ratios]}),
            ]
            if worst is None or ratio < worst[1]:
                worst = (fps, ratio, name)
    finally:
        ctx.release()
    assert worst is not None
    summary = {"face": worst[2], "faces": builtin_faces(), "gl_renderer": gl_renderer}
    return figures + [Figure("render.fps", min(f.value for f in figures if f.name.startswith("render.fps.")),
                             "frames/s", GOAL_FPS, True, {"slowest_of": builtin_faces()}),
                      Figure("render.ratio", worst[1], "ratio", GOAL_RATIO, True, summary)]


def _alternate(a: Callable[[], int], b: Callable[[], int], repeats: int) -> tuple[list[float], list[float]]:
    """Rates of ``a`` and ``b`` measured in alternation, after one warm-up of each."""
    a(), b()
    rates_a, rates_b = [], []
    for _ in range(repeats):
        for fn, out in ((a, rates_a), (b, rates_b)):
            start = time.perf_counter()
            items = fn()
            out.append(items / (time.perf_counter() - start))
    return rates_a, rates_b


_BARE_VERTEX_SHADER = """
#version 330
uniform vec4 u_map;
in vec2 in_pos;
in vec4 in_color;
out vec4 v_color;
void main() { gl_Position = vec4(in_pos * u_map.xy + u_map.zw, 0.0, 1.0); v_color = in_color; }
"""
_BARE_FRAGMENT_SHADER = """
#version 330
in vec4 v_color;
out vec4 f_color;
void main() { f_color = v_color; }
"""


def _one_call_scene(ctx: moderngl.Context, renderer: Renderer, geometry: Geometry, frames: int
                    ) -> tuple[Callable[[], int], Callable[[], None], int]:
    """Draw ``geometry``'s triangles, static, in one call ``frames`` times: (draw, release, corner count)."""
    data = _rest_triangles(geometry)
    program = ctx.program(vertex_shader=_BARE_VERTEX_SHADER, fragment_shader=_BARE_FRAGMENT_SHADER)
    renderer.set_view(geometry.viewbox)
    program["u_map"].value = renderer.program["u_map"].value
    vbo = ctx.buffer(data)
    vao = ctx.vertex_array(program, [(vbo, "2f 4f", "in_pos", "in_color")])

    def draw() -> int:
        ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        for _ in range(frames):
            renderer.fbo.use()
            renderer.fbo.clear(*geometry.background[:3], 1.0, depth=1.0)
            vao.render(moderngl.TRIANGLES)
            renderer.read()
        return frames

    def release() -> None:
        vao.release()
        vbo.release()
        program.release()

    return draw, release, len(data)


def _rest_triangles(geometry: Geometry) -> np.ndarray:
    """Every fill and stroke triangle corner of ``geometry`` with its colour: float32 ``(V, 6)``."""
    parts = []
    for item in geometry.items:
        if item.fill is not None and item.closed:
            parts.append((item.vertices[triangulate(item.vertices)], item.fill))
        if item.stroke is not None and item.width > 0:
            corners = stroke_many([(item.vertices, item.width, item.closed, item.edge_visible)])[0]
            parts.append((corners, item.stroke))
    return np.vstack([np.column_stack([c, np.tile(color, (len(c), 1))]) for c, color in parts]).astype(np.float32)


def _rounded(values: list[float]) -> list[float]:
    return [round(v, 2) for v in values]
