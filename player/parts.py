"""A long video in parts: frame ranges rendered to separate H.264 pieces, joined without re-encoding.

Each part is a complete MP4 held in memory (bytes), so it can travel between processes or
machines. Parts are encoded without B-frames, so every part starts on a keyframe and its decoding
order equals its display order; :func:`join_parts` then copies their packets one after the other
into one MP4, shifting each part's timestamps by the duration of the parts before it.
"""

from __future__ import annotations

import io
import math
import os
from collections.abc import Sequence
from itertools import pairwise
from pathlib import Path

import av
import numpy as np

from common import InputError, atomic_path
from player.backends import open_renderer
from player.offline import frame_count, render_track
from player.sinks import H264Encoder
from toon import FaceRig, MotorTrack


def frame_ranges(frames: int, part_frames: int) -> list[tuple[int, int]]:
    """Split ``frames`` into near-equal ``(start, stop)`` ranges of at most ``part_frames`` each.

    Examples
    --------
    >>> frame_ranges(10, 4)
    [(0, 3), (3, 7), (7, 10)]
    >>> frame_ranges(0, 4)
    []
    """
    if part_frames < 1:
        raise ValueError(f"part_frames must be at least 1, got {part_frames}")
    count = math.ceil(frames / part_frames)
    edges: list[int] = np.linspace(0, frames, count + 1).round().astype(int).tolist() if count else []
    return [(int(a), int(b)) for a, b in pairwise(edges)]


def render_part(track: MotorTrack, rig: FaceRig, start: int, stop: int, fps: float, size: tuple[int, int],
                samples: int = 4, crf: int = 18) -> bytes:
    """Render frames ``[start, stop)`` of a ``fps`` video of ``track`` into an MP4 held in memory.

    One x264 thread and no B-frames, so parts from many processes can be joined by
    :func:`join_parts`. Returns the MP4 file's bytes.
    """
    if not 0 <= start < min(stop, frame_count(track, fps)):
        raise ValueError(f"frames {start}:{stop} are outside the video's {frame_count(track, fps)} frames")
    buffer = io.BytesIO()
    with open_renderer(size, samples) as renderer:
        encoder = H264Encoder(buffer, fps, size, crf, bframes="0", threads="1")
        try:  # the whole track, from frame start: the face's physics runs from its start, as one render's
            render_track(track, rig, renderer, encoder, fps, start=start, stop=stop)
        finally:
            encoder.finish()
    return buffer.getvalue()


def join_parts(parts: Sequence[bytes], path: str | os.PathLike) -> int:
    """Join MP4 parts from :func:`render_part`, in order, into one MP4 at ``path``; returns its frames.

    The packets are copied, not re-encoded. The file appears only when complete.
    """
    if not parts:
        raise ValueError("no parts to join")
    path = Path(path)
    frames = 0
    with atomic_path(path) as tmp, av.open(str(tmp), mode="w", format="mp4") as output:
        out_stream, offset = None, 0
        for number, data in enumerate(parts):
            with av.open(io.BytesIO(data), mode="r") as part:
                stream = part.streams.video[0]
                if out_stream is None:
                    out_stream = output.add_stream_from_template(stream, options={"movflags": "+faststart"})
                elif stream.time_base != out_stream.time_base or stream.codec_context.width != out_stream.width:
                    raise InputError(f"part {number} does not match the first part's time base and size", path)
                end = offset
                for packet in part.demux(stream):
                    if packet.dts is None:  # the demuxer's end-of-stream marker
                        continue
                    pts = packet.dts if packet.pts is None else packet.pts  # no B-frames: pts == dts
                    packet.pts, packet.dts = pts + offset, packet.dts + offset
                    end = max(end, packet.pts + (packet.duration or 0))
                    packet.stream = out_stream
                    output.mux(packet)
                    frames += 1
                offset = end
    return frames
