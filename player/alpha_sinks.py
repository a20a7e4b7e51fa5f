"""Moving pictures that keep their transparency, for compositors, editors and web pages.

- ``.webm``: VP9 with alpha (``yuva420p``, libvpx-vp9), what browsers and OBS play transparent.
  FFmpeg's own VP9 decoder drops the alpha; read it back with ``libvpx-vp9``
  (:func:`decode_rgba` does).
- ``.mov``: Apple ProRes 4444 with alpha (``yuva444p10le``), what editors and compositors take.
- ``.apng``: animated PNG, lossless RGBA, for short loops on web pages and in chats.
- ``.webp``: animated WebP, lossless RGBA, the same use, smaller.

Each takes straight RGBA frames ``(height, width, 4)`` (or RGB, which is opaque) and appears
atomically like :class:`player.sinks.Mp4Sink`. A PNG folder keeps alpha too
(:class:`player.sinks.PngSink`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import cast

import av
import numpy as np
from av.video.stream import VideoStream

from common import InputError, atomic_path
from player.sinks import _AtomicSink


@dataclass(frozen=True)
class AlphaFormat:
    """A container and codec that keep alpha: FFmpeg's ``container`` and ``codec`` names, the
    codec's pixel format, its options and the container's, and what it is called for a person."""

    container: str
    codec: str
    pix_fmt: str
    options: tuple[tuple[str, str], ...]
    name: str
    even: bool = False  # needs an even frame size (chroma subsampled)
    muxer: tuple[tuple[str, str], ...] = ()


#: The moving-picture formats with alpha, by suffix.
ALPHA_FORMATS: dict[str, AlphaFormat] = {
    ".webm": AlphaFormat("webm", "libvpx-vp9", "yuva420p", (("crf", "10"), ("b", "0"), ("row-mt", "1"),
                                                            ("deadline", "good"), ("cpu-used", "4")),
                         "WebM (VP9 with alpha)", even=True),
    ".mov": AlphaFormat("mov", "prores_ks", "yuva444p10le", (("profile", "4"), ("vendor", "apl0")),
                        "QuickTime (ProRes 4444 with alpha)"),
    ".apng": AlphaFormat("apng", "apng", "rgba", (), "animated PNG", muxer=(("plays", "0"),)),  # 0: for ever
    ".webp": AlphaFormat("webp", "libwebp_anim", "bgra", (("lossless", "1"),), "animated WebP",
                         muxer=(("loop", "0"),)),
}


class AlphaVideoSink(_AtomicSink):
    """A moving picture with alpha (one of :data:`ALPHA_FORMATS`, by ``path``'s suffix).

    Parameters
    ----------
    path : path-like
        The output file.
    fps : float
        Frame rate (stored as an exact fraction).
    size : (width, height)
    """

    alpha = True

    def __init__(self, path: str | os.PathLike, fps: float, size: tuple[int, int]) -> None:
        self.format = ALPHA_FORMATS[Path(path).suffix.lower()]
        if self.format.even and (size[0] % 2 or size[1] % 2):
            raise InputError(f"{self.format.name} needs an even frame size, got {size[0]}x{size[1]}", path)
        super().__init__(atomic_path(path), path)
        self.size = size
        self._container = av.open(str(self._tmp), mode="w", format=self.format.container,
                                  options=dict(self.format.muxer))
        rate = Fraction(fps).limit_denominator(1001)
        self._stream = cast(VideoStream, self._container.add_stream(self.format.codec, rate=rate))
        self._stream.width, self._stream.height = size
        self._stream.pix_fmt = self.format.pix_fmt
        self._stream.options = dict(self.format.options)
        self._time_base = 1 / rate
        self._stream.codec_context.time_base = self._time_base
        self._pts = 0

    def write(self, frame: np.ndarray) -> None:
        """Encode one frame: straight RGBA ``(height, width, 4)``, or RGB (opaque)."""
        frame = np.ascontiguousarray(frame, dtype=np.uint8)
        if frame.shape[:2] != (self.size[1], self.size[0]) or frame.shape[2] not in (3, 4):
            raise ValueError(f"frame shape {frame.shape} does not match {self.size}")
        picture = av.VideoFrame.from_ndarray(frame, format="rgba" if frame.shape[2] == 4 else "rgb24")
        picture.pts, picture.time_base = self._pts, self._time_base
        self._container.mux(self._stream.encode(picture))
        self.frames += 1
        self._pts += 1

    def skip(self, frames: int) -> None:
        """Slots without a frame: a gap in the timestamps (the previous frame shows for longer)."""
        self._pts += max(0, frames)

    def _finish(self) -> None:
        try:
            self._container.mux(self._stream.encode())
        finally:
            self._container.close()


def decode_rgba(path: str | os.PathLike) -> list[np.ndarray]:
    """Every frame of a moving picture as straight RGBA ``(height, width, 4)`` ``uint8``; VP9
    through libvpx-vp9 (FFmpeg's own decoder drops its alpha), animated WebP through Pillow
    (FFmpeg's WebP decoder reads still pictures only)."""
    if Path(path).suffix.lower() == ".webp":
        from PIL import Image, ImageSequence

        with Image.open(path) as image:
            return [np.asarray(page.convert("RGBA")) for page in ImageSequence.Iterator(image)]
    frames: list[np.ndarray] = []
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        if stream.codec_context.name == "vp9":
            decoder = av.CodecContext.create("libvpx-vp9", "r")
            for packet in container.demux(stream):  # the last, empty, packet flushes the decoder
                frames += [f.to_ndarray(format="rgba") for f in decoder.decode(packet)]
        else:
            frames = [f.to_ndarray(format="rgba") for f in container.decode(stream)]
    return frames
