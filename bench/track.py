"""``track``: coloured dots from a 640x480 H.264 video with known truth.

A generated dot video of the synthetic performer (blur, lighting change, a passing hand, sensor
noise, JPEG artefacts; see :mod:`capture.videogen`) is written to H.264 once, then decoded and
tracked repeatedly. The performer turns its head up to ±20° (front-facing capture: beyond
about 25° the temple dots cross the outer brow dots in the picture). Figures:

``track.fps``: frames per second including decode (goal 200).
``track.centroid_error_px``: median distance of tracked dots from the true centres, over the
samples tracked while visible (goal 0.3 px).
``track.swap_frames_pct``: share of frames where some track sits on another marker (goal 0.1 %).
``track.found_pct`` and ``track.gross_frames_pct`` (frames with a track more than 3 px off; the
lids of a blinking eye merge into one dot) are reported beside, without goals.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from bench.core import Figure, median_rate
from capture import load_markerset, synthesize
from capture.dots import front_layout, track_dots
from capture.performance import default_performance
from capture.videogen import dot_video, score_tracking
from capture.videoio import frames, probe, write_video

MAX_TURN_DEG = 20.0


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``track.*`` figures."""
    seconds, repeats = (3.0 if quick else 20.0), (2 if quick else 5)
    performance = default_performance(seconds, max_turn_deg=MAX_TURN_DEG)
    take = synthesize(rate=30.0, noise_mm=0.0, performance=performance).take
    truth, images = dot_video(take, seed=0)
    ms = load_markerset("toon32")
    layout = front_layout(ms, truth.labels)
    with tempfile.TemporaryDirectory() as tmp:
        info = probe(write_video(images, Path(tmp) / "dots.mp4", truth.rate))
        result: dict = {}

        def once() -> int:
            pixels, _ = track_dots(frames(info), layout)
            result["pixels"] = pixels
            return len(pixels)

        fps, runs = median_rate(once, repeats)
    score = score_tracking(result["pixels"], truth)
    detail = {"size": list(truth.size), "frames": len(result["pixels"]), "markers": len(truth.labels),
              "codec": "h264", "decoder": info.backend, "max_turn_deg": MAX_TURN_DEG}
    return [
        Figure("track.fps", fps, "frames/s", 200.0, True, {**detail, "runs": [round(r, 1) for r in runs]}),
        Figure("track.centroid_error_px", score["median_error_px"], "px", 0.3, False, detail),
        Figure("track.swap_frames_pct", 100 * score["swap_frames"], "%", 0.1, False, detail),
        Figure("track.found_pct", 100 * score["found"], "%", None, True, detail),
        Figure("track.gross_frames_pct", 100 * score["gross_frames"], "%", None, False, detail),
    ]
