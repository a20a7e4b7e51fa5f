"""Markerless sources: a talking-head video tracked as it plays, and a camera (or a video played
as one), both through MediaPipe's Face Landmarker (:mod:`capture.face_landmarks`).

Frames carry the marker set ``face``'s points in camera-space mm and the 51 blendshape scores
as channels (:data:`~capture.face_landmarks.BLENDSHAPES`), NaN where no face is seen.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from capture.blendshapes import BLENDSHAPES
from capture.face_landmarks import LANDMARKS, FaceTracker
from capture.sources import Frame, Source
from common import InputError
from common.video import upright

if TYPE_CHECKING:
    from capture.videoio import VideoInfo


def face_source(path: str | os.PathLike, info: VideoInfo | None = None, repeat: bool = False, **_: Any) -> Source:
    """A video's face tracked as it plays (and again, if ``repeat``, each time a frame period
    after the last). Times are the container's, counted from the first frame (a variable frame
    rate is kept); ``meta["start_time"]`` is that frame's time on the container's clock, where the
    sound's clock lines up. ``info``: the video's probe, where the caller has it."""
    import av

    from capture.videoio import probe

    info = probe(path) if info is None else info
    meta = _meta(Path(path).name, [info.width, info.height])

    def images() -> Iterator[tuple[float, np.ndarray]]:
        offset, last = 0.0, None
        while True:
            try:
                with av.open(str(path)) as container:
                    for index, image in enumerate(container.decode(container.streams.video[0])):
                        clock = float(image.time) if image.time is not None else index / (info.rate or 30.0)
                        meta.setdefault("start_time", clock)
                        last = offset + clock - meta["start_time"]
                        yield last, upright(image)
            except av.error.FFmpegError as exc:
                raise InputError(f"cannot decode the video ({exc})", path) from None
            if not repeat or last is None:
                return
            offset = last + 1.0 / (info.rate or 30.0)
    return Source(tuple(LANDMARKS), info.rate or 30.0, _tracked(images(), meta), Path(path).name, meta=meta,
                  channel_names=BLENDSHAPES)


def camera_source(target: str, clock: Callable[[], float] = time.perf_counter,
                  sleep: Callable[[float], None] = time.sleep, repeat: bool = False, **_: Any) -> Source:
    """A camera (``N``: the N-th device, V4L2 through OpenCV) or a video file played as one: its
    frames come in real time, each stamped on ``clock`` when it arrives (before it is tracked;
    ``meta["clock_start"]``: ``clock`` at ``t`` 0, once the first is read), and the source is
    ``live`` (nothing waits for it). A file is read at its own frame rate (checked against its
    frames' times), from its start again at its end if ``repeat``."""
    import cv2

    from capture.videoio import open_capture, video_rate

    device = int(target) if target.isdigit() else None
    capture = open_capture(device if device is not None else str(target))
    if not capture.isOpened():
        capture.release()
        raise InputError("cannot open it as a camera" if device is None else f"no camera {device}", target)
    claimed = capture.get(cv2.CAP_PROP_FPS) or 30.0
    try:  # a file's rate checked against its frames' times; a camera's, within what a camera does
        rate = video_rate(target, claimed) if device is None else min(max(claimed, 1.0), 240.0)
    except InputError:
        capture.release()
        raise
    size = [int(capture.get(cv2.CAP_PROP_FRAME_WIDTH)), int(capture.get(cv2.CAP_PROP_FRAME_HEIGHT))]
    meta = _meta(f"camera {target}", size)

    def images() -> Iterator[tuple[float, np.ndarray]]:
        start, index = clock(), 0
        meta["clock_start"] = start  # a frame's t is its grab on ``clock`` less this, before tracking
        try:
            while True:
                if device is None:  # a file stands in for a camera: its frames come when due
                    wait = start + index / rate - clock()
                    if wait > 0:
                        sleep(wait)
                ok, image = capture.read()
                if not ok and repeat and device is None and index:
                    capture.set(cv2.CAP_PROP_POS_FRAMES, 0)  # the file again, its frames still due one by one
                    ok, image = capture.read()
                if not ok:
                    return
                index += 1
                yield clock() - start, image[:, :, ::-1]
        finally:
            capture.release()
    return Source(tuple(LANDMARKS), rate, _tracked(images(), meta), f"camera {target}", live=True, meta=meta,
                  channel_names=BLENDSHAPES)


def _meta(name: str, size: list[int]) -> dict[str, Any]:
    return {"source": "video", "file": name, "tracker": "face", "markerset": "face", "image_size": size}


def _tracked(images: Iterator[tuple[float, np.ndarray]], meta: dict[str, Any]) -> Iterator[Frame]:
    """Each ``(t, RGB image)`` through one face tracker, made when the first image comes and
    released when the images end."""
    columns = list(LANDMARKS.values())
    tracker: FaceTracker | None = None
    try:
        for t, image in images:
            tracker = tracker or FaceTracker()
            face = tracker.track(image, t)
            if face is None:
                yield Frame(t, np.full((len(columns), 3), np.nan), np.full(len(BLENDSHAPES), np.nan))
            else:
                yield Frame(t, face.points[columns], face.blendshapes)
    finally:
        if tracker is not None:
            tracker.close()
