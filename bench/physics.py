"""``physics``: what the face's physics costs a render, and that it is the same at any frame rate.

For each built-in face, a synthetic performer's mapped take (its head turns, its brows and jaw:
what the drivers read) is drawn offline at 512x512, the whole path of ``render`` (the frames'
geometry, the physics, the renderer), with the face's drivers and without them (``--no-physics``),
drawn side by side frame by frame (each first in turn, after a warm-up: whole renders one after
the other spread single passes from 0.72 to 1.36 on this shared machine for the same work), 9
passes (the median ratio):

``physics.render_ratio.<face>``: frames a second with physics over without (goal 0.95, issue 65; the first issue's
"within 10 %"); ``physics.render_ratio`` is the worst face's.
``physics.fps_gap``: the largest difference, over every face, between a parameter's value drawn
at 30 and at 60 frames a second at their shared instants (goal 1e-9: the drivers are integrated
exactly between the track's samples, whatever the frame rate).
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from bench.core import Figure
from capture import synthesize
from player.backends import open_renderer
from player.motion import SecondaryMotion
from player.offline import geometries
from toon import FaceRig, builtin_faces, load_face
from toonface import map_onto_face

GOAL_RATIO = 0.95  # issue 65


def run(quick: bool = False) -> list[Figure]:
    """Measure every built-in face; the per-face ratios, the worst, and the frame-rate gap."""
    seconds, passes = (2.0, 3) if quick else (4.0, 9)
    take = synthesize(seconds=seconds, rate=30.0, seed=4).take
    figures: list[Figure] = []
    gap = 0.0
    for name in builtin_faces():
        face = load_face(name)
        track = map_onto_face(take, face=face)
        rig = FaceRig(face)
        with open_renderer((512, 512), 4) as renderer:
            for geometry in geometries(track, rig, track.rate, 0, 10):  # warm the renderer and the caches
                renderer.render(geometry)
            ratios = [_ratio(track, rig, renderer) for _ in range(passes)]
        figures.append(Figure(f"physics.render_ratio.{name}", statistics.median(ratios), "ratio", GOAL_RATIO, True,
                              {"face": name, "frames": track.frames, "passes": passes,
                               "drivers": len(face.physics), "ratios": [round(r, 3) for r in ratios]}))
        gap = max(gap, _rate_gap(face, track))
    worst = min(figures, key=lambda f: f.value)
    return [*figures,
            Figure("physics.render_ratio", worst.value, "ratio", GOAL_RATIO, True, {"face": worst.detail["face"]}),
            Figure("physics.fps_gap", gap, "parameter units", 1e-9, False, {"faces": list(builtin_faces())})]


def _ratio(track, rig, renderer) -> float:
    """One pass: the render with physics and the one without drawn side by side, frame by frame
    (each first in turn), each frame's geometry and drawing timed; frames a second with over
    frames a second without. Side by side, a slower stretch of the machine costs both alike."""
    sources = {True: geometries(track, rig, track.rate, physics=True),
               False: geometries(track, rig, track.rate, physics=False)}
    spent = {True: 0.0, False: 0.0}
    for number in range(track.frames):
        for physics in ((True, False) if number % 2 == 0 else (False, True)):
            began = time.perf_counter()
            renderer.render(next(sources[physics]))
            spent[physics] += time.perf_counter() - began
    return spent[False] / spent[True]


def _rate_gap(face, track) -> float:
    """The largest difference of a driven parameter between 30 and 60 frames a second at the instants both draw."""
    drawn = {}
    for fps in (30.0, 60.0):
        motion = SecondaryMotion(face, track)
        times = np.arange(int(track.duration * fps)) / fps
        rows = [np.array([np.interp(t, track.times, c) for c in track.values.T]) for t in times]
        drawn[fps] = {round(t, 9): motion.extra_at(t, row, {}) for t, row in zip(times, rows, strict=True)}
    return max(abs(drawn[30.0][t][p] - drawn[60.0][t][p]) for t in drawn[30.0] for p in drawn[30.0][t])
