"""Where rendered frames go: an H.264 MP4 (PyAV), a folder of PNG frames, or raw RGB on a pipe.

Both appear atomically: the MP4 is written to a temporary file and renamed on :meth:`close`; the
PNG folder is filled under a temporary name and renamed. :meth:`abort` (or leaving the ``with``
block by an exception) removes the partial output.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import sys
from collections import deque
from concurrent.futures import Future, ThreadPoolExecutor
from fractions import Fraction
from pathlib import Path
from typing import BinaryIO, Protocol

import av
import cv2
import numpy as np

from common import InputError, atomic_dir, atomic_path, check_folder
from common.cores import usable_cores
from player.yuv import rgb_to_i420


class FrameWriter(Protocol):
    """Anything that takes RGB frames of shape ``(height, width, 3)``."""

    def write(self, frame: np.ndarray) -> None: ...


class FrameSink(FrameWriter, Protocol):
    """An output of RGB frames that is kept (:meth:`close`) or dropped (:meth:`abort`) at the end.

    :meth:`skip` says that frame slots went by without a frame (a live player that could not
    keep up): the output keeps its timing, by a gap in the timestamps or by repeating a frame.
    """

    def skip(self, frames: int) -> None: ...
    def close(self) -> None: ...
    def abort(self) -> None: ...


#: Frames a background encoder may hold before :meth:`H264Encoder.write` waits for it.
ENCODE_AHEAD = 4


class H264Encoder:
    """RGB frames into a browser-playable H.264 MP4 (yuv420p, x264 ``veryfast``) on a path or a
    writable binary file object; :meth:`finish` flushes and closes it.

    ``fps`` is stored as an exact fraction (29.97 -> 2997/100); ``options`` are extra x264
    options, such as ``bframes="0"`` for pieces that are joined later. ``fragmented``: for a live
    recording, a file that plays up to its last second or two if the process is killed.
    ``background``: frames are encoded on a thread of the encoder's own, at most
    :data:`ENCODE_AHEAD` behind, so that drawing the next frame and encoding this one share the
    machine's cores (an offline render: its encoding was 40 % of ``retarget``'s time), x264 taking
    all of them but one; an encoding error is raised by a later :meth:`write` or by :meth:`finish`.
    """

    def __init__(self, target: str | os.PathLike | BinaryIO, fps: float, size: tuple[int, int], crf: int = 18,
                 fragmented: bool = False, background: bool = False, **options: str) -> None:
        width, height = size
        if width % 2 or height % 2:
            raise InputError(f"H.264 needs an even frame size, got {width}x{height}",
                             target if isinstance(target, (str, os.PathLike)) else None)
        self.size = (width, height)
        self.frames = 0
        # fragmented: a fragment per keyframe, each flushed to the file as written, so that a process
        # killed outright leaves a playable file (a plain MP4 is unreadable until its index is written)
        self._container = av.open(target if not isinstance(target, os.PathLike) else str(target), mode="w",
                                  format="mp4", options={"movflags": "frag_keyframe+empty_moov+default_base_moof",
                                                         "flush_packets": "1"} if fragmented else {})
        rate = Fraction(fps).limit_denominator(1001)
        self._stream = self._container.add_stream("libx264", rate=rate)
        self._time_base = 1 / rate  # a frame's pts counts frame slots, so a skipped slot leaves a gap
        self._stream.codec_context.time_base = self._time_base
        self._pts = 0
        self._stream.width, self._stream.height = width, height
        self._stream.pix_fmt = "yuv420p"
        # in the background x264 takes the cores the drawing leaves: its default (1.5 threads a
        # core) fought the drawing for them, a tenth more time in all on two cores
        threads = {"threads": str(max(1, usable_cores() - 1))} if background else {}
        self._stream.options = {"crf": str(crf), "preset": "veryfast", **threads, **(
            {"g": str(max(1, round(fps)))} if fragmented else {"movflags": "+faststart"}), **options}
        self._pool = ThreadPoolExecutor(1, thread_name_prefix="h264") if background else None
        self._pending: deque[Future] = deque()

    def write(self, frame: np.ndarray) -> None:
        """Encode one RGB frame of shape ``(height, width, 3)``."""
        if frame.shape != (self.size[1], self.size[0], 3):
            raise ValueError(f"frame shape {frame.shape} does not match {self.size}")
        # converted here, not by FFmpeg's scaler in the encoder (the same picture for a fifth less
        # time in all, :mod:`player.yuv`), into a new array: the caller may reuse its own
        video_frame = av.VideoFrame.from_ndarray(rgb_to_i420(frame), format="yuv420p")
        video_frame.pts, video_frame.time_base = self._pts, self._time_base
        if self._pool is None:
            self._encode(video_frame)
        else:
            self._pending.append(self._pool.submit(self._encode, video_frame))
            while len(self._pending) > ENCODE_AHEAD:
                self._pending.popleft().result()
        self.frames += 1
        self._pts += 1

    def _encode(self, frame: av.VideoFrame | None) -> None:
        """Encode ``frame`` (None: flush) and write its packets."""
        self._container.mux(self._stream.encode(frame))

    def skip(self, frames: int) -> None:
        """Leave ``frames`` slots without a frame: the previous one shows for longer."""
        self._pts += max(0, frames)

    def finish(self) -> None:
        """Flush the encoder and close the file (the container is closed even if flushing fails)."""
        try:
            while self._pending:
                self._pending.popleft().result()
            self._encode(None)
        finally:
            if self._pool is not None:  # nothing encoding while the file closes
                self._pool.shutdown(wait=True, cancel_futures=True)
            self._pending.clear()
            self._container.close()


def partial_name(target: str | os.PathLike, frames: int) -> Path:
    """Where an interrupted output keeps its ``frames``: ``out.mp4`` -> ``out.partial-318.mp4``, a
    folder ``frames`` -> ``frames.partial-318``."""
    target = Path(target)
    if target.suffix:
        return target.with_name(f"{target.stem}.partial-{frames}{target.suffix}")
    return target.with_name(f"{target.name}.partial-{frames}")


class _KeptOrDropped:
    """A sink as a context: kept (:meth:`close`) when the block ends normally, dropped
    (:meth:`abort`) on an exception."""

    def close(self) -> None:
        raise NotImplementedError

    def abort(self) -> None:
        raise NotImplementedError

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()


class _AtomicSink(_KeptOrDropped):
    """Shared lifetime: an atomic-output guard, left committed by :meth:`close` or rolled back."""

    def __init__(self, guard: contextlib.AbstractContextManager, target: str | os.PathLike) -> None:
        self._guard = guard
        self._target = Path(target)
        self._tmp: Path = guard.__enter__()
        self.frames = 0
        self._done = False

    def _finish(self) -> None:
        """Flush the format's trailer; overridden where there is one."""

    def _trim(self) -> None:
        """Drop what was written past :attr:`frames` (an interrupt between a write and its count)."""

    def close(self) -> None:
        """Finish the output and move it into place."""
        if self._done:
            return
        self._done = True
        try:
            self._finish()
        except BaseException as exc:
            self._guard.__exit__(type(exc), exc, exc.__traceback__)
            raise
        self._guard.__exit__(None, None, None)

    def keep_partial(self, named_after: str | os.PathLike | None = None) -> Path:
        """Finish what was written and keep it under a name that says it is partial, beside the
        target (``out.partial-318.mp4``, ``frames.partial-318``; named after ``named_after``
        instead where given), leaving the target, perhaps a complete earlier output, untouched.
        Returns the name kept."""
        kept = partial_name(named_after if named_after is not None else self._target, self.frames)
        if not self._done:
            self._done = True
            self._finish()
            self._trim()
            if kept.is_dir():
                shutil.rmtree(kept)
            os.replace(self._tmp, kept)
            self._guard.__exit__(RuntimeError, RuntimeError("kept as partial"), None)
        return kept

    def abort(self) -> None:
        """Drop the partial output."""
        if self._done:
            return
        self._done = True
        with contextlib.suppress(Exception):
            self._finish()
        reason = RuntimeError("output aborted")
        self._guard.__exit__(RuntimeError, reason, None)


class Mp4Sink(_AtomicSink):
    """H.264 (yuv420p, browser-playable) MP4 through PyAV.

    Parameters
    ----------
    path : path-like
        Output ``.mp4``.
    fps : float
        Frame rate; non-integer rates are stored as exact fractions (29.97 -> 2997/100).
    size : (width, height)
        Must be even (yuv420p).
    crf : int
        x264 quality, 0 (lossless) to 51; 18 is visually lossless.
    """

    def __init__(self, path: str | os.PathLike, fps: float, size: tuple[int, int], crf: int = 18) -> None:
        if size[0] % 2 or size[1] % 2:
            raise InputError(f"H.264 needs an even frame size, got {size[0]}x{size[1]}", path)
        super().__init__(atomic_path(path), path)
        self._encoder = H264Encoder(self._tmp, fps, size, crf, background=True)
        self.size = self._encoder.size

    def write(self, frame: np.ndarray) -> None:
        """Encode one RGB frame."""
        self._encoder.write(frame)
        self.frames += 1

    def skip(self, frames: int) -> None:
        """Slots without a frame: a gap in the timestamps, so the video keeps real time."""
        self._encoder.skip(frames)

    def _finish(self) -> None:
        self._encoder.finish()


class LiveMp4Sink(_KeptOrDropped):
    """An MP4 recorded live (``play -o``, ``receive -o``), which a kill must not lose: written as
    it goes to ``NAME.partial.mp4`` beside the target, fragmented with a keyframe every second
    and flushed as each fragment ends, so that after SIGKILL that file plays up to its last
    second or two (the encoder holds that much). :meth:`close` (the run's end, Ctrl-C included)
    renames it to the target; :meth:`keep_partial` keeps it as ``NAME.partial-N.mp4`` beside an
    earlier target left as it was.

    Parameters are those of :class:`Mp4Sink`.
    """

    def __init__(self, path: str | os.PathLike, fps: float, size: tuple[int, int], crf: int = 18) -> None:
        self._target = Path(path)
        self.partial = self._target.with_name(f"{self._target.stem}.partial{self._target.suffix}")
        check_folder(self._target)
        self._encoder = H264Encoder(self.partial, fps, size, crf, fragmented=True)
        self.size = self._encoder.size
        self.frames = 0
        self._done = False

    def write(self, frame: np.ndarray) -> None:
        """Encode one RGB frame."""
        self._encoder.write(frame)
        self.frames += 1

    def skip(self, frames: int) -> None:
        """Slots without a frame: a gap in the timestamps, so the video keeps real time."""
        self._encoder.skip(frames)

    def _end(self, to: Path | None) -> None:
        if self._done:
            return
        self._done = True
        try:
            self._encoder.finish()
        finally:
            if to is None:
                self.partial.unlink(missing_ok=True)
            else:
                os.replace(self.partial, to)

    def close(self) -> None:
        """Finish the recording and move it into place."""
        self._end(self._target)

    def keep_partial(self, named_after: str | os.PathLike | None = None) -> Path:
        """Finish what was recorded and keep it as ``NAME.partial-N.mp4``; returns that name."""
        kept = partial_name(named_after if named_after is not None else self._target, self.frames)
        self._end(kept)
        return kept

    def abort(self) -> None:
        """Drop the recording."""
        with contextlib.suppress(Exception):
            self._end(None)


class PngSink(_AtomicSink):
    """A folder of ``frame_000000.png`` files (replaced whole if it exists); RGBA where the
    frames have alpha (a transparent background)."""

    alpha = True

    def __init__(self, directory: str | os.PathLike) -> None:
        super().__init__(atomic_dir(directory), directory)

    def write(self, frame: np.ndarray) -> None:
        """Write one RGB (or straight RGBA) frame as the next PNG."""
        path = self._tmp / f"frame_{self.frames:06d}.png"
        order = [2, 1, 0, 3][:frame.shape[2]]  # OpenCV writes BGR(A)
        if not cv2.imwrite(str(path), np.ascontiguousarray(frame[:, :, order])):
            raise OSError(f"cannot write {path}")
        self.frames += 1

    def _trim(self) -> None:
        for path in self._tmp.glob("frame_*.png"):
            if int(path.stem.split("_")[1]) >= self.frames:
                path.unlink()

    def skip(self, frames: int) -> None:
        """Slots without a frame: the previous PNG is copied into each, so the sequence keeps its rate."""
        if not self.frames:
            return
        last = self._tmp / f"frame_{self.frames - 1:06d}.png"
        for _ in range(max(0, frames)):
            shutil.copyfile(last, self._tmp / f"frame_{self.frames:06d}.png")
            self.frames += 1


class RawSink:
    """Raw RGB frames (``width * height * 3`` bytes each, rows top to bottom) on a binary stream,
    standard output by default: ``toonface render m.csv -o - | ffmpeg -f rawvideo -pix_fmt rgb24
    -s 512x512 -r 30 -i - out.mkv``. A closed pipe ends the output quietly."""

    def __init__(self, stream=None) -> None:
        self._stream = stream if stream is not None else sys.stdout.buffer
        self.frames = 0
        self.broken = False
        self._last: np.ndarray | None = None

    def write(self, frame: np.ndarray) -> None:
        """Write one frame's bytes (nothing once the reader has gone)."""
        if self.broken:
            return
        self._last = np.ascontiguousarray(frame, dtype=np.uint8)  # no copy: frames are contiguous
        try:
            self._stream.write(self._last.data)
        except BrokenPipeError:
            self.broken = True
            return
        self.frames += 1

    def skip(self, frames: int) -> None:
        """Slots without a frame: the previous frame's bytes again, so the reader's rate holds."""
        if self._last is not None:
            for _ in range(max(0, frames)):
                self.write(self._last)

    def close(self) -> None:
        """Flush."""
        with contextlib.suppress(BrokenPipeError, ValueError):
            self._stream.flush()

    def keep_partial(self, named_after: str | os.PathLike | None = None) -> Path:
        """What a stream sent is the reader's already: flush it; the stream is ``-``."""
        self.close()
        return Path("-")

    def abort(self) -> None:
        """Nothing to roll back on a stream."""
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close()


def keeps_alpha(sink: object) -> bool:
    """Whether ``sink`` stores transparency (a PNG folder, WebM, ProRes, APNG, WebP; not MP4 or raw RGB)."""
    return bool(getattr(sink, "alpha", False))
