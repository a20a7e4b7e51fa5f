"""``pipeline``: synthetic take to motor track, frames per second on one core.

Times :func:`toonface.map_onto_face` (cleaning with head stabilisation, the built-in profile with the
rest pose from the take, the toon32 mapping) on a 60 s synthetic take at 60 Hz. "One core" is
enforced from the start: the measurement runs in a
child process pinned to one CPU before it imports numpy, with the BLAS/OpenMP pools set to one
thread (pinning a running process leaves its already-started BLAS threads fighting for the core,
which made the figure noisy). The goal is the telepresence sender's: keep up with 60 Hz capture
on one core with a wide margin.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

from bench.core import Figure

GOAL_FPS = 600.0  # ten times the 60 Hz live rate
_ONE_THREAD = {name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}


def run(quick: bool = False) -> list[Figure]:
    """Measure and return ``pipeline.fps``."""
    seconds, repeats = (10.0 if quick else 60.0), (3 if quick else 7)
    measured = pinned_rate(seconds, repeats, 60.0)
    return [Figure("pipeline.fps", measured["fps"], "frames/s", GOAL_FPS, True,
                   {"frames": measured["frames"], "markers": measured["markers"], "rate_hz": 60.0,
                    "repeats": repeats, "one_core": measured["one_core"], "runs": measured["runs"],
                    "kept_freed_memory": measured["kept_freed_memory"]})]


def pinned_rate(seconds: float, repeats: int, rate: float, keep_freed: bool = True) -> dict:
    """Frames per second of :func:`toonface.map_onto_face` (clean + map) on a synthetic take, measured
    in a child process pinned to one CPU with one BLAS thread; a dict with ``fps``, ``runs``,
    ``frames``, ``markers`` and ``one_core``. ``keep_freed``: the allocator set as the
    ``toonface`` command sets it (:func:`common.memory.keep_freed_memory`); False measures a
    program that leaves glibc's defaults."""
    return pinned_child(f"import bench.pipeline as p; p._child({seconds!r}, {repeats!r}, {rate!r}, {keep_freed!r})")


def pinned_child(code: str) -> dict:
    """Run ``code`` in a fresh Python pinned to one CPU before it imports numpy, with one BLAS
    thread; the JSON object it prints, with ``one_core`` (whether it could be pinned)."""
    pinned = hasattr(os, "sched_setaffinity")
    cpu = min(os.sched_getaffinity(0)) if pinned else 0
    result = subprocess.run([sys.executable, "-c", code], env={**os.environ, **_ONE_THREAD}, capture_output=True,
                            text=True, check=True,
                            preexec_fn=(lambda: os.sched_setaffinity(0, {cpu})) if pinned else None)
    return {**json.loads(result.stdout), "one_core": pinned}


def _child(seconds: float, repeats: int, rate: float, keep_freed: bool) -> None:
    """Runs in the pinned child: measure and print one JSON object."""
    from bench.core import median_rate
    from capture import synthesize
    from common.memory import keep_freed_memory
    from toonface import map_onto_face

    kept = keep_freed and keep_freed_memory()
    take = synthesize(seconds=seconds, rate=rate).take
    fps, runs = median_rate(lambda: map_onto_face(take).frames, repeats)
    print(json.dumps({"fps": fps, "runs": [round(r, 1) for r in runs], "frames": take.frames,
                      "markers": take.markers, "kept_freed_memory": kept}))
