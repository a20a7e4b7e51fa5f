"""``retarget``: a whole ``toonface retarget`` command against the clock, and what its video keeps.

A 60 s synthetic take at 60 Hz (its ``.npz``) is retargeted onto the classic face to a 512x512
H.264 MP4 at 30 fps (CRF 18), as a user runs it: a fresh interpreter, start-up, cleaning,
mapping, drawing and encoding, until the file is complete.

``retarget.realtime_x``: the take's seconds over the command's wall seconds, with the default
renderer (goal 8, issue 65). The detail has the same with the OpenGL renderer forced
(``TOONFACE_RENDERER=gl``), both runs alternating (median of each).
``retarget.psnr_db``: what the video keeps: the take's motors (``toonface map``) drawn by
``toonface render`` to the same MP4 (the encoder retarget uses), each frame against the same
frame drawn losslessly by the default renderer, PSNR in dB over every 30th frame (no goal); the
same with the OpenGL renderer forced in the detail, against the same lossless frames.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import av
import numpy as np

from bench.core import Figure
from capture import save_take, synthesize
from player.backends import open_renderer
from player.offline import geometries
from toon import FaceRig, load_face, load_track

GOAL_X = 8.0  # issue 65


def run(quick: bool = False) -> list[Figure]:
    """Time the command with each renderer; measure the videos' quality."""
    seconds, repeats = (10.0 if quick else 60.0), (1 if quick else 3)
    with tempfile.TemporaryDirectory(prefix="toonface-bench-retarget-") as folder:
        root = Path(folder)
        save_take(synthesize(seconds=seconds, rate=60.0).take, root / "take.npz")
        walls: dict[str, list[float]] = {"auto": [], "gl": []}
        for _ in range(repeats):
            for renderer in walls:
                walls[renderer].append(_retarget(root, renderer))
        _command(["map", str(root / "take.npz"), "-o", str(root / "motors.csv")], "auto")
        for renderer in walls:
            _command(["render", str(root / "motors.csv"), "-o", str(root / f"render-{renderer}.mp4"), "--fps", "30"],
                     renderer)
        psnr = {renderer: _psnr(root / f"render-{renderer}.mp4", root / "motors.csv") for renderer in walls}
    x = {renderer: seconds / statistics.median(times) for renderer, times in walls.items()}
    detail = {"take_seconds": seconds, "fps": 30, "size": [512, 512], "face": "classic", "repeats": repeats,
              "wall_s": {r: [round(t, 2) for t in times] for r, times in walls.items()},
              "gl_realtime_x": round(x["gl"], 3)}
    return [Figure("retarget.realtime_x", x["auto"], "x real time", GOAL_X, True, detail),
            Figure("retarget.psnr_db", psnr["auto"], "dB", None, True, {"gl_psnr_db": round(psnr["gl"], 2),
                                                                         "every_nth_frame": 30})]


def _retarget(root: Path, renderer: str) -> float:
    """Wall seconds of one ``toonface retarget`` of the take with ``renderer`` (``auto``: the default)."""
    start = time.perf_counter()
    _command(["retarget", str(root / "take.npz"), "-o", str(root / f"{renderer}.mp4"), "--fps", "30"], renderer)
    return time.perf_counter() - start


def _command(args: list[str], renderer: str) -> None:
    """Run ``toonface ARGS`` in a fresh interpreter with ``TOONFACE_RENDERER=renderer``."""
    subprocess.run([sys.executable, "-m", "toonface", *args], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, env={**os.environ, "TOONFACE_RENDERER": renderer})


def _psnr(video: Path, motors: Path) -> float:
    """PSNR (dB) of every 30th frame of ``video`` (a 30 fps render of ``motors``) against the
    default renderer's lossless frame of the same motors."""
    frames = geometries(load_track(motors), FaceRig(load_face("classic")), 30.0)  # as retarget draws them
    errors = []
    with av.open(str(video)) as container, open_renderer((512, 512)) as renderer:
        for k, (frame, geometry) in enumerate(zip(container.decode(video=0), frames, strict=False)):
            if k % 30 == 0:
                drawn = renderer.render(geometry).astype(float)
                errors.append(np.mean((frame.to_ndarray(format="rgb24").astype(float) - drawn) ** 2))
    return float(10 * np.log10(255.0 ** 2 / np.mean(errors)))
