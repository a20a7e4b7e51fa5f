"""The performer's own video beside the cartoon, frame for frame (``retarget --side-by-side``).

:class:`SideBySide` is a frame writer in front of a picture sink: each cartoon frame it is given
goes out with the source video's frame of the same moment on its left, scaled to the cartoon's
height. Output frame ``i`` shows the newest source frame at or before ``start + i / fps`` on the
source's clock, so a source with another frame rate stays in time.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

import av
import cv2
import numpy as np

from common.video import upright
from player.sinks import FrameWriter


def beside_width(video: str | os.PathLike, height: int) -> int:
    """Width (even) of ``video``'s frames, upright, scaled to ``height``."""
    with av.open(str(video)) as container:
        source_height, width = upright(next(container.decode(video=0))).shape[:2]
    return max(2, int(round(width * height / max(source_height, 1) / 2)) * 2)


class SideBySide:
    """Write ``[source | cartoon]`` frames to ``sink`` (see the module docstring).

    Parameters
    ----------
    sink : FrameWriter
        Takes frames ``(height, width + cartoon width, 3)``.
    video : path
        The source video.
    width, height : int
        The source's size in the output (:func:`beside_width`).
    fps : float
        The output's frame rate.
    start : float
        The source's time (its container's clock) of output frame 0.
    """

    def __init__(self, sink: FrameWriter, video: str | os.PathLike, width: int, height: int, fps: float,
                 start: float = 0.0) -> None:
        self.sink, self.size, self.fps, self.start = sink, (width, height), fps, start
        self._container = av.open(str(video))
        self._frames = self._decode()
        self._current: np.ndarray = np.zeros((height, width, 3), np.uint8)
        self._next: tuple[float, np.ndarray] | None = next(self._frames, None)
        self.written = 0

    def _decode(self) -> Iterator[tuple[float, np.ndarray]]:
        stream = self._container.streams.video[0]
        for index, frame in enumerate(self._container.decode(stream)):
            t = float(frame.time) if frame.time is not None else index / self.fps
            yield t, cv2.resize(upright(frame), self.size, interpolation=cv2.INTER_AREA)

    def write(self, frame: np.ndarray) -> None:
        """Put the source's frame of this moment beside ``frame`` and pass both on."""
        due = self.start + self.written / self.fps + 1e-6
        while self._next is not None and self._next[0] <= due:
            self._current = self._next[1]
            self._next = next(self._frames, None)
        self.sink.write(np.concatenate([self._current, frame], axis=1))
        self.written += 1

    def close(self) -> None:
        """Release the source video (the sink is the caller's)."""
        self._container.close()
