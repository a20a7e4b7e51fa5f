"""Offline playback: a motor track drawn frame by frame into a sink, as fast as it renders."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

from player.backends import FrameRenderer
from player.sinks import FrameWriter, keeps_alpha
from toon import FaceRig, Geometry, MotorTrack
from toon.motors import N_MOTORS


def resample(track: MotorTrack, fps: float, start: int = 0, stop: int | None = None) -> np.ndarray:
    """Motor values at the frame times of a ``fps`` video of the same duration, frames
    ``[start, stop)`` of it (all by default); ``(frames, 21)``, and the track's extra parameters
    after them where it has any (:meth:`toon.MotorTrack.table`).

    Linear interpolation between the track's frames (CharToon's knot points interpolate
    linearly too); the track's own rate returns its values unchanged. Only the frames asked
    for are made (a part of a long video costs its own length).
    """
    table = track.table()
    if abs(fps - track.rate) < 1e-9:
        return table[start:stop]
    times = np.arange(frame_count(track, fps))[start:stop] / fps
    return np.column_stack([np.interp(times, track.times, col) for col in table.T])


def resampled(track: MotorTrack, fps: float, start: int = 0, stop: int | None = None) -> MotorTrack:
    """:func:`resample` as a track at ``fps`` (its extra parameters kept)."""
    table = resample(track, fps, start, stop)
    return MotorTrack(table[:, :N_MOTORS], fps, extra_codes=track.extra_codes,
                      extra=table[:, N_MOTORS:] if track.extra_codes else None)


def frame_count(track: MotorTrack, fps: float) -> int:
    """How many frames :func:`resample` makes of ``track`` at ``fps``, without making them."""
    return track.frames if abs(fps - track.rate) < 1e-9 else int(round(track.duration * fps))


def render_track(track: MotorTrack, rig: FaceRig, renderer: FrameRenderer, sink: FrameWriter, fps: float | None = None,
                 progress: Callable[[int], None] | None = None) -> int:
    """Render every frame of ``track`` on ``rig``'s face into ``sink``; returns the frame count.

    ``progress`` is called with the number of frames just finished (1) after each frame. The sink
    is not closed here: the caller decides whether the output is complete. A sink that keeps
    alpha (``sink.alpha``) gets straight RGBA frames where the face's background is transparent.
    """
    alpha = keeps_alpha(sink) and rig.face.background[3] < 1.0  # transparency kept
    vector = getattr(sink, "write_geometry", None)  # an SVG output: the geometry, nothing rasterised
    count = 0
    for geometry in geometries(track, rig, fps or track.rate):
        count += 1
        if vector is not None:
            vector(geometry)
        else:
            sink.write(renderer.render(geometry, alpha) if alpha else renderer.render(geometry))
        if progress is not None:
            progress(1)
    return count


def geometries(track: MotorTrack, rig: FaceRig, fps: float) -> Iterator[Geometry]:
    """Each frame of a ``fps`` video of ``track`` on ``rig``'s face, its extra parameters (HT) too."""
    for row in resample(track, fps):
        yield rig.geometry(row[:N_MOTORS], track.extra_at(row) if track.extra_codes else None)
