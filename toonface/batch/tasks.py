"""The work a batch sends to its workers: plain functions of picklable arguments.

Each writes its output atomically and returns something small (bytes written, a frame count),
except :func:`map_pair`, whose motor track stays on the cluster for the tasks that need it, and
:func:`render_video_part`, whose MP4 piece travels to the worker that joins them.
"""

from __future__ import annotations

from pathlib import Path

from capture import load_take
from capture.takefile import is_table
from common import InputError
from mapping import load_profile
from player.offline import frame_count
from player.parts import join_parts, render_part
from player.score import save_score
from player.sheet import save_image, track_sheet
from toon import FaceRig, MotorTrack, load_face, save_track
from toonface.batch.job import Job, TakeOptions
from toonface.pipeline import map_take


def map_pair(take: Path, face: str, job: Job) -> MotorTrack:
    """Load, clean and map ``take`` for ``face`` as ``job`` says; a bad take or face raises
    :class:`common.InputError` naming the file."""
    options = job.take_options if is_table(take) else TakeOptions()  # [csv] is for CSV takes only
    loaded = load_take(take, rate=options.rate, labels=list(options.labels) if options.labels else None,
                       units=options.units)
    profile = load_profile(job.profile) if job.profile else None
    try:
        return map_take(loaded, job.neutral, load_face(face), job.mirror, job.mapping, profile, job.clean)
    except InputError as exc:
        if exc.source is None:  # say which take could not be mapped
            raise InputError(exc.message, take, exc.field) from None
        raise


def count_frames(track: MotorTrack, fps: float) -> tuple[int, float]:
    """Frames and frame rate of the ``fps`` video of ``track`` (``fps`` 0: the track's own rate)."""
    rate = fps or track.rate
    return frame_count(track, rate), rate


def write_motors(track: MotorTrack, path: Path) -> int:
    """Write the motor track (``.csv`` movie script or ``.npz``); returns its bytes."""
    return _size(save_track(track, _in_folder(path)))


def write_score(track: MotorTrack, path: Path) -> int:
    """Draw the motor curves as staves into a PNG; returns its bytes."""
    return _size(save_score(track, _in_folder(path)))


def write_sheet(track: MotorTrack, face: str, path: Path, samples: int) -> int:
    """A contact sheet of 12 frames through the take on ``face``; returns its bytes."""
    return _size(save_image(track_sheet(FaceRig(load_face(face)), track, samples=samples), _in_folder(path)))


def render_video_part(track: MotorTrack, face: str, start: int, stop: int, fps: float, size: tuple[int, int],
                      samples: int) -> bytes:
    """Frames ``[start, stop)`` of the take's video on ``face``, as MP4 bytes."""
    return render_part(track, FaceRig(load_face(face)), start, stop, fps or track.rate, size, samples)


def join_video(path: Path, *parts: bytes) -> tuple[int, int]:
    """Join the parts into ``path``; returns ``(frames, bytes)``."""
    frames = join_parts(parts, _in_folder(path))
    return frames, _size(path)


def _in_folder(path: Path) -> Path:
    """``path``, its folder made first: a batch job lays out its own output folders."""
    path.parent.mkdir(parents=True, exist_ok=True)
    return path


def _size(path: Path) -> int:
    return Path(path).stat().st_size
