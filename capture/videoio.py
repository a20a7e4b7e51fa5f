"""Video frames in (OpenCV first, PyAV where OpenCV cannot decode) and out (PyAV, H.264)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import av
import cv2
import numpy as np

from common import InputError
from common.video import upright


@dataclass(frozen=True)
class VideoInfo:
    """What is known of a video before decoding it: ``frames`` may be 0 where the container does not say."""

    path: Path
    width: int
    height: int
    rate: float
    frames: int
    backend: str


def open_capture(target: str | int) -> cv2.VideoCapture:
    """OpenCV's capture of a file or a camera, with FFmpeg's own complaints kept off the terminal
    (they would break a one-line error). OpenCV reads the setting when it first opens a video,
    so every capture in the process goes through here."""
    os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")
    return cv2.VideoCapture(target)


def probe(path: str | os.PathLike) -> VideoInfo:
    """Size, rate and frame count of a video; an undecodable file is an :class:`InputError`."""
    path = Path(path)
    if not path.is_file():
        raise InputError("no such video file", path)
    if path.stat().st_size == 0:
        raise InputError("empty file (0 bytes), not a video", path)
    cap = open_capture(str(path))
    try:
        if cap.isOpened():
            ok, frame = cap.read()
            if ok and frame is not None:
                rate = video_rate(path, cap.get(cv2.CAP_PROP_FPS) or 0.0)
                count = int(cap.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
                return VideoInfo(path, frame.shape[1], frame.shape[0], rate, max(count, 0), "opencv")
    finally:
        cap.release()
    try:
        with av.open(str(path)) as container:
            if not container.streams.video:
                raise InputError("no video stream in the file", path)
            stream = container.streams.video[0]
            rate = video_rate(path, float(stream.average_rate) if stream.average_rate else 0.0)
            return VideoInfo(path, stream.codec_context.width, stream.codec_context.height, rate,
                             int(stream.frames or 0), "pyav")
    except InputError:
        raise
    except (av.error.FFmpegError, ValueError, OSError) as exc:
        why = getattr(exc, "strerror", None) or str(exc)
        raise InputError(f"cannot be decoded: damaged, cut short or not a video ({why})", path) from None


def frames(info: VideoInfo) -> Iterator[np.ndarray]:
    """Decode every frame as BGR ``uint8`` ``(height, width, 3)``, with the backend :func:`probe` chose,
    turned upright by the container's display matrix (OpenCV turns its own)."""
    if info.backend == "opencv":
        cap = open_capture(str(info.path))
        try:
            while True:
                ok, frame = cap.read()
                if not ok:
                    return
                yield frame
        finally:
            cap.release()
    else:
        try:
            with av.open(str(info.path)) as container:
                for decoded in container.decode(video=0):
                    yield upright(decoded, "bgr24")
        except av.error.FFmpegError as exc:
            raise InputError(f"decoding failed part-way ({exc})", info.path) from None


def write_video(images: list[np.ndarray] | Iterator[np.ndarray], path: str | os.PathLike, rate: float,
                crf: int = 18) -> Path:
    """Write BGR frames as H.264 (yuv420p) into ``path``; size from the first frame (even sides)."""
    path = Path(path)
    with av.open(str(path), mode="w") as container:
        stream = None
        for image in images:
            if stream is None:
                stream = container.add_stream("libx264", rate=round(rate))
                stream.width, stream.height = image.shape[1], image.shape[0]
                stream.pix_fmt = "yuv420p"
                stream.options = {"crf": str(crf), "preset": "veryfast"}
            frame = av.VideoFrame.from_ndarray(np.ascontiguousarray(image), format="bgr24")
            for packet in stream.encode(frame):
                container.mux(packet)
        if stream is not None:
            for packet in stream.encode():
                container.mux(packet)
    return path


#: Frame rates a container may say of itself and be believed (Hz).
PLAUSIBLE_RATES = (1.0, 240.0)


def video_rate(path: str | os.PathLike, claimed: float, frames: int = 60) -> float:
    """The frame rate of a video: what its container says (``claimed``) where that is plausible,
    else the median step between its first ``frames`` frames' timestamps (a container that says
    18 750 fps of a 25 fps clip); an :class:`InputError` where neither tells."""
    low, high = PLAUSIBLE_RATES
    if np.isfinite(claimed) and low <= claimed <= high:
        return float(claimed)
    stamps: list[float] = []
    try:
        with av.open(str(path)) as container:
            stream = container.streams.video[0]
            for packet in container.demux(stream):
                if packet.pts is not None and packet.time_base is not None:
                    stamps.append(float(packet.pts * packet.time_base))
                if len(stamps) >= frames:
                    break
    except (av.error.FFmpegError, IndexError, ValueError, OSError):
        stamps = []
    steps = np.diff(np.sort(stamps))
    steps = steps[steps > 0]
    measured = 1.0 / float(np.median(steps)) if len(steps) else 0.0
    if not low <= measured <= high:
        said = f"{claimed:g} fps" if np.isfinite(claimed) and claimed > 0 else "no frame rate"
        raise InputError(f"its container says {said} and its frames' times do not tell another: cannot tell its "
                         "frame rate (re-encode it, e.g. ffmpeg -i IN -r 30 OUT.mp4)", path)
    return round(measured, 3)
