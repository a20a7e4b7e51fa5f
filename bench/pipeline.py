"""``pipeline``: synthetic take to motor track, frames per second on one core.

Times :func:`toonface.map_take` (neutral calibration, head stabilisation, per-channel mapping) on
a 60 s synthetic take at 60 Hz, with the process pinned to one CPU core. The goal is the
telepresence sender's: keep up with 60 Hz capture on one core with a wide margin.
"""

from __future__ import annotations

import os

from bench.core import Figure, median_rate
from capture import synthesize
from toonface import map_take

GOAL_FPS = 600.0  # ten times the 60 Hz live rate


def run(quick: bool = False) -> list[Figure]:
    """Measure and return ``pipeline.fps``."""
    seconds, repeats = (10.0 if quick else 60.0), (3 if quick else 7)
    take = synthesize(seconds=seconds, rate=60.0).take
    pinned = hasattr(os, "sched_setaffinity")
    previous = os.sched_getaffinity(0) if pinned else None
    if pinned:
        os.sched_setaffinity(0, {min(previous)})
    try:
        fps, runs = median_rate(lambda: map_take(take).frames, repeats)
    finally:
        if pinned:
            os.sched_setaffinity(0, previous)
    return [Figure("pipeline.fps", fps, "frames/s", GOAL_FPS, True,
                   {"frames": take.frames, "markers": take.markers, "rate_hz": take.rate, "repeats": repeats,
                    "one_core": pinned, "runs": [round(r, 1) for r in runs]})]
