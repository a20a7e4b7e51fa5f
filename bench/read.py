"""``read``: take-file read rates in marker-samples per second (one marker in one frame = one).

A 60 s, 60 Hz synthetic take (32 markers) is written once as C3D (float), CSV and TRC, then read
back repeatedly through :func:`capture.load_take`. No goals are set; the figures show what a
batch of takes costs to load.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from bench.core import Figure, median_rate
from capture import load_take, save_take, synthesize


def run(quick: bool = False) -> list[Figure]:
    """Measure and return ``read.<format>`` for c3d, csv and trc."""
    seconds, repeats = (5.0 if quick else 60.0), (2 if quick else 5)
    take = synthesize(seconds=seconds, rate=60.0).take
    samples = take.frames * take.markers
    figures = []
    with tempfile.TemporaryDirectory() as tmp:
        for suffix in ("c3d", "csv", "trc"):
            path = save_take(take, Path(tmp) / f"take.{suffix}")
            def read_once(path: Path = path) -> int:
                load_take(path)
                return samples

            rate, runs = median_rate(read_once, repeats)
            figures.append(Figure(f"read.{suffix}", rate, "marker-samples/s", None, True,
                                  {"frames": take.frames, "markers": take.markers, "bytes": path.stat().st_size,
                                   "runs": [round(r) for r in runs]}))
    return figures
