"""``render``: frames per second of the renderer on every built-in face, against a bare floor.

For each built-in face, at 512x512 with 4x MSAA and readback:

``render.fps.<face>``: a mapped synthetic take played on the face: geometry built from motor
values every frame (features, skeletons, splines, head turn), fills triangulated or re-used,
points uploaded, strokes expanded by the geometry shader, drawn in their depth-masked runs and
read back.
``render.floor_fps.<face>``: the same face's triangles at rest (fills and strokes built on the
CPU), uploaded once and drawn by a bare shader in a single call into the same framebuffer with the
same readback: what drawing these triangles costs with no per-frame work.
``render.ratio.<face>``: fps / floor. The take is timed in blocks of 10 frames, each followed by
the floor drawing as many, over 5 passes; each figure is the median of its 30 blocks (quartiles
in the detail), the ratio the median of the 30 paired ratios, so that both sides of a pair see
the same machine. ``render.fps`` and ``render.ratio`` are the slowest face's figures.
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
from toon.curves import stroke_triangles
from toonface import map_onto_face

GOAL_FPS = 150.0  # the figure for this machine's 2 cores (0.7 of a floor near 215 fps)
GOAL_RATIO = 0.7  # per-frame deformation, triangulation and upload cost under half the drawing
BLOCK = 10  # frames per timed block: the face and its floor alternate block by block


def run(quick: bool = False) -> list[Figure]:
    """Measure every built-in face; return per-face figures and the slowest face's summary."""
    size, frames, passes = (512, 512), (20 if quick else 60), (1 if quick else 5)
    values = map_onto_face(synthesize(seconds=max(frames / 30, 1.0), rate=30.0).take).values[:frames]
    figures: list[Figure] = []
    worst: tuple[float, float, str] | None = None
    ctx = create_context()
    try:
        gl_renderer = ctx.info.get("GL_RENDERER", "unknown")
        for name in builtin_faces():
            face = load_face(name)
            rig = FaceRig(face)
            with Renderer(ctx, size, samples=4) as renderer:
                def face_block(first: int, renderer: Renderer = renderer, rig: FaceRig = rig) -> int:
                    block = values[first:first + BLOCK]
                    for row in block:
                        renderer.render(rig.geometry(row))
                    return len(block)

                floor_draw, release, corners = _one_call_scene(ctx, renderer, rig.geometry(face.neutral()))
                try:
                    face_rates, floor_rates = _paired_blocks(face_block, floor_draw, len(values), passes)
                finally:
                    release()
            ratios = [a / b for a, b in zip(face_rates, floor_rates, strict=True)]
            fps, floor, ratio = statistics.median(face_rates), statistics.median(floor_rates), statistics.median(ratios)
            detail = {"face": name, "size": list(size), "samples": 4, "frames": len(values), "passes": passes,
                      "block_frames": BLOCK, "triangle_corners_at_rest": corners, "gl_renderer": gl_renderer}
            figures += [
                Figure(f"render.fps.{name}", fps, "frames/s", GOAL_FPS, True, {**detail, **_spread(face_rates)}),
                Figure(f"render.floor_fps.{name}", floor, "frames/s", None, True, {**detail, **_spread(floor_rates)}),
                Figure(f"render.ratio.{name}", ratio, "ratio", GOAL_RATIO, True, {**detail, **_spread(ratios)}),
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


def _paired_blocks(face_block: Callable[[int], int], floor: Callable[[int], int], frames: int, passes: int
                   ) -> tuple[list[float], list[float]]:
    """Rates of each block of the take and of the floor drawing as many frames right after it.

    Blocks are short (a fraction of a second) so that each pair sees the same machine: the noise
    of a shared machine comes and goes over seconds. One untimed pass warms both first.
    """
    for first in range(0, frames, BLOCK):
        floor(face_block(first))
    face_rates, floor_rates = [], []
    for _ in range(passes):
        for first in range(0, frames, BLOCK):
            start = time.perf_counter()
            count = face_block(first)
            middle = time.perf_counter()
            floor(count)
            face_rates.append(count / (middle - start))
            floor_rates.append(count / (time.perf_counter() - middle))
    return face_rates, floor_rates


def _spread(values: list[float]) -> dict[str, float | int]:
    """The quartiles of ``values`` and how many there are, for a figure's detail."""
    q1, q2, q3 = statistics.quantiles(values, n=4) if len(values) > 1 else (values[0],) * 3
    return {"q1": round(q1, 3), "median": round(q2, 3), "q3": round(q3, 3), "blocks": len(values)}


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


def _one_call_scene(ctx: moderngl.Context, renderer: Renderer, geometry: Geometry
                    ) -> tuple[Callable[[int], int], Callable[[], None], int]:
    """Draw ``geometry``'s triangles, static, in one call per frame: (draw N frames, release, corner count)."""
    data = _rest_triangles(geometry)
    program = ctx.program(vertex_shader=_BARE_VERTEX_SHADER, fragment_shader=_BARE_FRAGMENT_SHADER)
    renderer.set_view(geometry.viewbox)
    program["u_map"].value = renderer.program["u_map"].value  # type: ignore[union-attr]  # a uniform
    vbo = ctx.buffer(data)
    vao = ctx.vertex_array(program, [(vbo, "2f 4f", "in_pos", "in_color")])

    def draw(frames: int) -> int:
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
            parts.append((stroke_triangles(item.vertices, item.width, item.closed, item.edge_visible), item.stroke))
    return np.vstack([np.column_stack([c, np.tile(color, (len(c), 1))]) for c, color in parts]).astype(np.float32)
