"""``face``: faces without markers, a real talking head (a GRID clip scaled to 640x480 H.264) on one core.

``track.face_fps``: frames per second of ``track --markers face``, decode included (goal 120, issue 65;
OpenSeeFace's models run at 44-68 frames/s per core).
``live.face_latency_ms``: median time from asking for a frame (its decode and the landmarker
included) to its motors leaving the live mapper (goal 25 ms); the 95th percentile beside.

Skipped (no figures) where ``../shared/realdata`` is absent.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

import av
import cv2
import numpy as np

from bench.core import REALDATA, Figure, median_rate, one_core
from capture import load_markerset
from capture.face_sources import face_source
from capture.video_tracking import track_video
from capture.videoio import write_video
from mapping import calibrate, load_mapping, prepare
from mapping.stepwise import LiveMapper

CLIP = REALDATA / "video" / "grid" / "bbaf2n.mpg"
SIZE = (640, 480)
GOAL_FPS = 120.0  # issue 65


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the face figures (none without the real clip)."""
    if not CLIP.is_file():
        return []
    repeats = 2 if quick else 5
    with tempfile.TemporaryDirectory() as tmp:
        with av.open(str(CLIP)) as container:
            images = [cv2.resize(f.to_ndarray(format="rgb24"), SIZE, interpolation=cv2.INTER_CUBIC)[:, :, ::-1]
                      for f in container.decode(video=0)]
        video = write_video(images, Path(tmp) / "talk.mp4", 25.0)
        with one_core() as pinned:
            fps, runs = median_rate(lambda: track_video(video, "face").frames, repeats)
            latencies = _latencies(video)
    detail = {"clip": CLIP.name, "size": list(SIZE), "frames": len(images), "one_core": pinned}
    return [Figure("track.face_fps", fps, "frames/s", GOAL_FPS, True, {**detail, "runs": [round(r, 1) for r in runs]}),
            Figure("live.face_latency_ms", statistics.median(latencies), "ms", 25.0, False,
                   {**detail, "p95_ms": round(float(np.percentile(latencies, 95)), 2)})]


def _latencies(video: Path) -> list[float]:
    """Milliseconds per frame from asking the source for it to the live mapper's motors."""
    take = track_video(video, "face")
    mapping, markerset = load_mapping("face"), load_markerset("face")
    profile = calibrate(mapping, prepare(take, markerset))
    source = face_source(video)
    mapper = LiveMapper(mapping, markerset, profile, source.labels, source.rate, rest_seconds=0.0,
                        channel_names=source.channel_names)
    out: list[float] = []
    frames = iter(source.frames)
    while True:
        start = time.perf_counter()
        frame = next(frames, None)
        if frame is None:
            return out
        mapper.step(frame.positions, frame.t, frame.channels)
        out.append((time.perf_counter() - start) * 1000)
