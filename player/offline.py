"""Offline playback: a motor track drawn frame by frame into a sink, as fast as it renders."""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterator

import numpy as np

from player.backends import FrameRenderer
from player.motion import SecondaryMotion
from player.sinks import FrameWriter, keeps_alpha
from toon import Face, FaceRig, Geometry, MotorTrack
from toon.motors import N_MOTORS
from toon.params import drawable

log = logging.getLogger(__name__)


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


def frame_count(track: MotorTrack, fps: float) -> int:
    """How many frames :func:`resample` makes of ``track`` at ``fps``, without making them."""
    return track.frames if abs(fps - track.rate) < 1e-9 else int(round(track.duration * fps))


def render_track(track: MotorTrack, rig: FaceRig, renderer: FrameRenderer, sink: FrameWriter, fps: float | None = None,
                 progress: Callable[[int], None] | None = None, physics: bool = True, start: int = 0,
                 stop: int | None = None) -> int:
    """Render the frames ``[start, stop)`` (all by default) of a ``fps`` video of ``track`` on
    ``rig``'s face into ``sink``, its physics on unless ``physics`` is false; returns the count.

    ``progress`` is called with the number of frames just finished (1) after each frame. The sink
    is not closed here: the caller decides whether the output is complete. A sink that keeps
    alpha (``sink.alpha``) gets straight RGBA frames where the face's background is transparent.
    """
    alpha = keeps_alpha(sink) and rig.face.background[3] < 1.0  # transparency kept
    vector = getattr(sink, "write_geometry", None)  # an SVG output: the geometry, nothing rasterised
    count = 0
    for geometry in geometries(track, rig, fps or track.rate, start, stop, physics):
        count += 1
        if vector is not None:
            vector(geometry)
        else:
            sink.write(renderer.render(geometry, alpha) if alpha else renderer.render(geometry))
        if progress is not None:
            progress(1)
    return count


def geometries(track: MotorTrack, rig: FaceRig, fps: float, start: int = 0, stop: int | None = None,
               physics: bool = True) -> Iterator[Geometry]:
    """Frames ``[start, stop)`` of a ``fps`` video of ``track`` on ``rig``'s face, its extra
    parameters (HT...) too: a standard one the face does not declare is left out (logged once,
    for ``-v``: every preset writes all of them and few faces draw all); any other the face
    lacks is an error naming it. With ``physics``, the face's drivers move what they move
    (:mod:`player.motion`), run on the track from its start."""
    skipped = undrawn_extras(track, rig.face)
    if skipped:
        log.info("face %s does not declare %s: %s column%s not drawn", rig.face.name, ", ".join(skipped),
                 "those" if len(skipped) > 1 else "that", "s are" if len(skipped) > 1 else " is")
    drawn = [(N_MOTORS + k, code) for k, code in enumerate(track.extra_codes) if code not in skipped]
    motion = SecondaryMotion(rig.face, track) if physics and rig.face.physics else None
    for k, row in enumerate(resample(track, fps, start, stop), start=start):
        extra = {code: float(row[i]) for i, code in drawn}
        if motion is not None:
            extra = motion.extra_at(_frame_time(track, fps, k), row[:N_MOTORS], extra)
        yield rig.geometry(row[:N_MOTORS], extra)


def _frame_time(track: MotorTrack, fps: float, frame: int) -> float:
    """Where frame ``frame`` of a ``fps`` video of ``track`` lies on the track's clock (as
    :func:`resample` samples it)."""
    return frame / (track.rate if abs(fps - track.rate) < 1e-9 else fps)


def undrawn_extras(track: MotorTrack, face: Face) -> list[str]:
    """The standard extra parameters (:data:`toon.motors.STANDARD_EXTRAS`) ``track`` carries and
    ``face`` does not declare: a mapping writes every one it drives, and a face draws those it has."""
    return drawable(track.extra_codes, face.extra_codes)[1]
