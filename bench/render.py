"""``render``: frames per second of the renderers on every built-in face, beside the 2-D libraries
a user would pick instead, drawing the same geometry.

For each built-in face, at 512x512 with antialiasing, the geometry of a mapped synthetic take
(built once, so that every drawer draws exactly the same outlines) is drawn into a numpy RGB
array by:

``render.fps.<face>``: the default offline path (:func:`player.backends.open_renderer`: Cairo on
the CPU where OpenGL would be a software rasteriser, as here without a GPU; OpenGL on a GPU);
``render.gl_fps.<face>``: the OpenGL renderer (4x MSAA, readback), whatever the machine;
``render.skia_fps.<face>`` and ``render.cairo_fps.<face>``: the peers of
:mod:`bench.render_peers` (each where it is installed: ``make bench-deps``);
``render.peer_ratio.<face>``: the default path's rate over the fastest peer's (goal 1.5, issue 65);
``render.picture_mad.<face>``: the default path's picture against the OpenGL renderer's, mean
absolute difference in 1/255 over every tenth frame (goal 1; 0 where the default is OpenGL).
``render.gl_ratio.<face>``: the OpenGL renderer over its floor, the same face's triangles at rest
drawn by a bare shader in one call with the same readback (goal 0.7: per-frame work under half
the drawing; on a GPU, where drawing is cheap, it shows the Python per frame).

Drawers alternate in blocks of 10 frames over 5 passes, so that each block of each sees the same
machine; each rate is the median of its blocks (quartiles in the detail), each ratio the median
of the blocks' ratios. ``render.fps`` and ``render.peer_ratio`` are the slowest face's figures.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable

import moderngl
import numpy as np

from bench.core import Figure
from bench.render_peers import cairo_peer, skia_peer
from capture import synthesize
from player import Renderer, create_context
from player.backends import open_renderer
from player.layout import triangulate
from toon import FaceRig, Geometry, builtin_faces, load_face
from toon.curves import stroke_triangles
from toonface import map_onto_face

GOAL_RATIO = 0.7  # per-frame deformation, triangulation and upload cost under half the drawing
GOAL_PEER = 1.5  # ours against the fastest peer renderer, worst face (issue 65)
GOAL_MAD = 1.0  # of 255: the default picture against the OpenGL renderer's
BLOCK = 10  # frames per timed block: the drawers alternate block by block


def run(quick: bool = False) -> list[Figure]:
    """Measure every built-in face; return per-face figures and the slowest face's summary."""
    size, frames, passes = (512, 512), (20 if quick else 60), (1 if quick else 5)
    values = map_onto_face(synthesize(seconds=max(frames / 30, 1.0), rate=30.0).take).values[:frames]
    figures: list[Figure] = []
    ctx = create_context()
    try:
        gl_renderer = ctx.info.get("GL_RENDERER", "unknown")
        for name in builtin_faces():
            rig = FaceRig(load_face(name))
            geometries = [rig.geometry(row) for row in values]
            with Renderer(ctx, size, samples=4) as gl, open_renderer(size, 4, ctx=ctx) as ours:
                floor_draw, release, corners = _one_call_scene(ctx, gl, geometries[0])
                drawers: dict[str, Callable[[Geometry], np.ndarray]] = {"ours": ours.render, "gl": gl.render}
                peers_here = {"skia": skia_peer(size), "cairo": cairo_peer(size)}
                drawers.update({p: draw for p, draw in peers_here.items() if draw is not None})
                try:
                    rates = _blocks(drawers, geometries, floor_draw, passes)
                finally:
                    release()
                mad = float(np.mean([np.abs(ours.render(g).astype(int) - gl.render(g).astype(int)).mean()
                                     for g in geometries[::10]]))
                backend = type(ours).__name__
            peers = [p for p in ("skia", "cairo") if p in rates]
            gl_ratio = [a / b for a, b in zip(rates["gl"], rates["floor"], strict=True)]
            detail = {"face": name, "size": list(size), "frames": len(values), "passes": passes, "block_frames": BLOCK,
                      "default_renderer": backend, "gl_renderer": gl_renderer}
            figures += [
                Figure(f"render.fps.{name}", statistics.median(rates["ours"]), "frames/s", None, True,
                       {**detail, **_spread(rates["ours"]),
                        **({} if peers else {"peers": "none installed: run `make bench-deps`"})}),
                Figure(f"render.gl_fps.{name}", statistics.median(rates["gl"]), "frames/s", None, True,
                       {**detail, "samples": 4, **_spread(rates["gl"])}),
                *[Figure(f"render.{p}_fps.{name}", statistics.median(rates[p]), "frames/s", None, True,
                         {**detail, **_spread(rates[p])}) for p in peers],
                Figure(f"render.picture_mad.{name}", mad, "of 255", GOAL_MAD, False, detail),
                Figure(f"render.gl_ratio.{name}", statistics.median(gl_ratio), "ratio", GOAL_RATIO, True,
                       {**detail, "triangle_corners_at_rest": corners, **_spread(gl_ratio)}),
            ]
            if peers:
                fastest = max(peers, key=lambda p: statistics.median(rates[p]))
                peer_ratio = [a / b for a, b in zip(rates["ours"], rates[fastest], strict=True)]
                figures.append(Figure(f"render.peer_ratio.{name}", statistics.median(peer_ratio), "ratio", GOAL_PEER,
                                      True, {**detail, "fastest_peer": fastest, "peers": peers,
                                             **_spread(peer_ratio)}))
    finally:
        ctx.release()
    by = {f.name: f for f in figures}
    slowest = min(builtin_faces(), key=lambda n: by[f"render.fps.{n}"].value)
    summary = [Figure("render.fps", by[f"render.fps.{slowest}"].value, "frames/s", None, True, {"face": slowest})]
    ratios = {n: by[f"render.peer_ratio.{n}"].value for n in builtin_faces() if f"render.peer_ratio.{n}" in by}
    if ratios:
        worst = min(ratios, key=ratios.__getitem__)
        summary.append(Figure("render.peer_ratio", ratios[worst], "ratio", GOAL_PEER, True, {"face": worst}))
    return figures + summary


def _blocks(drawers: dict[str, Callable[[Geometry], np.ndarray]], geometries: list[Geometry],
            floor: Callable[[int], int], passes: int) -> dict[str, list[float]]:
    """Rates of each drawer (and the GL floor) on each block of frames, the drawers one after
    another within a block. One untimed pass warms them first."""
    rates: dict[str, list[float]] = {name: [] for name in [*drawers, "floor"]}
    for timed in [False] + [True] * passes:
        for first in range(0, len(geometries), BLOCK):
            block = geometries[first:first + BLOCK]
            for name, draw in drawers.items():
                start = time.perf_counter()
                for geometry in block:
                    draw(geometry)
                if timed:
                    rates[name].append(len(block) / (time.perf_counter() - start))
            start = time.perf_counter()
            floor(len(block))
            if timed:
                rates["floor"].append(len(block) / (time.perf_counter() - start))
    return rates


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
