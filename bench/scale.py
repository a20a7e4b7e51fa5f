"""``scale``: a long take costs what its length says (issue 65).

A synthetic 120 Hz toon32 take of ``minutes`` (60; ``--quick``: 5) is cleaned and mapped
(:func:`toonface.map_onto_face`) in a child process pinned to one core, beside one minute of the
same performer mapped on its own; both children start fresh, so each one's peak memory is its own.

``scale.map_ratio``
    The long take's time over ``minutes`` times the one minute's (goal 1.2: no worse than cutting
    it into one-minute takes).
``scale.map_peak_mb``
    The long take's child's peak resident memory, the take itself and Python included (goal 2048 at
    60 minutes; ``--quick`` states it without a goal); the detail gives the memory before mapping.

Rendering a long take is not measured here (``render.*`` measures its rate, which does not
depend on the length); the takes have no gaps (``fidelity.gapfill_fps`` measures gap filling).
"""

from __future__ import annotations

import json

from bench.core import Figure
from bench.pipeline import pinned_child

RATE_HZ = 120.0


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``scale.*`` figures."""
    minutes = 5.0 if quick else 60.0
    one = _child(1.0)
    long = _child(minutes)
    ratio = long["seconds"] / (minutes * one["seconds"])
    detail = {"minutes": minutes, "rate_hz": RATE_HZ, "markerset": "toon32", "long_seconds": round(long["seconds"], 2),
              "one_minute_seconds": round(one["seconds"], 3), "one_core": long["one_core"]}
    return [Figure("scale.map_ratio", ratio, "x", 1.2, False, detail),
            Figure("scale.map_peak_mb", long["peak_mb"], "MB", None if quick else 2048.0, False,
                   {**detail, "before_mb": round(long["before_mb"], 1),
                    "one_minute_peak_mb": round(one["peak_mb"], 1)})]


def _child(minutes: float) -> dict:
    """Map ``minutes`` of the synthetic take in a fresh child process pinned to one CPU, after a
    two-second take's warm-up; its seconds (the mean of three for a minute), peak and starting
    memory (MB)."""
    return pinned_child(f"import bench.scale as s; s._measure({minutes!r})")


def _measure(minutes: float) -> None:
    """Runs in the child: synthesise, map, print one JSON object."""
    import resource
    import time

    from capture import synthesize
    from common.memory import keep_freed_memory
    from toonface import map_onto_face

    keep_freed_memory()
    map_onto_face(synthesize(seconds=2.0, rate=RATE_HZ).take)  # the imports' and caches' warm-up, paid by neither
    take = synthesize(seconds=60.0 * minutes, rate=RATE_HZ).take
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    times = []
    for _ in range(3 if minutes <= 1.0 else 1):  # a batch of one-minute takes reuses its memory: their mean
        start = time.perf_counter()
        map_onto_face(take)
        times.append(time.perf_counter() - start)
    print(json.dumps({"seconds": sum(times) / len(times), "before_mb": before,
                      "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
