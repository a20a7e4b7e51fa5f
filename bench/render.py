"""``render``: frames per second of the renderer on every built-in face, against a bare floor.

For each built-in face, at 512x512 with 4x MSAA and readback:

``render.fps.<face>``: a mapped synthetic take played on the face: geometry built from motor
values every frame (features, skeletons, splines, head turn), fills triangulated or re-used,
strokes built, uploaded, drawn in their depth-masked runs and read back.
``render.floor_fps.<face>``: the same face's triangles at rest, uploaded once and drawn in a
single call into the same framebuffer with the same readback: what drawing this many corners
costs with no per-frame work. ``render.ratio.<face>`` = fps / floor, measured in alternating
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
from player.renderer import triangles_of
from toon import FaceRig, Geometry, builtin_faces, load_face
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


def _one_call_scene(ctx: moderngl.Context, renderer: Renderer, geometry: Geometry, frames: int
                    ) -> tuple[Callable[[], int], Callable[[], None], int]:
    """Draw ``geometry``'s triangles, static, in one call ``frames`` times: (draw, release, corner count)."""
    data, _ = triangles_of(geometry)
    data[:, 2] = 1.0
    vbo = ctx.buffer(np.ascontiguousarray(data).tobytes())
    vao = ctx.vertex_array(renderer.program, [(vbo, "3f 4f", "in_pos", "in_color")])
    renderer.set_view(geometry.viewbox)

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

    return draw, release, len(data)


def _rounded(values: list[float]) -> list[float]:
    return [round(v, 2) for v in values]
