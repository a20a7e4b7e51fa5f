"""The work a batch sends to its workers: plain functions of picklable arguments.

Each writes its output atomically and returns something small (bytes written, a frame count),
except :func:`ready_pair_take` (a take cleaned and calibrated once for all its faces) and
:func:`map_pair` (a pair's motor track), which stay on the cluster for the tasks that need them,
and :func:`render_video_part`, whose MP4 piece travels to the worker that joins them. A worker
keeps one rig per face (:func:`face_rig`) for all the parts and sheets it draws.
"""

from __future__ import annotations

import functools
from pathlib import Path

from capture import load_take
from capture.takefile import is_table
from common import InputError, resolve_builtin
from mapping import load_profile
from mapping.workflow import ReadyTake, map_ready, ready_take
from player.offline import frame_count
from player.parts import join_parts, render_part
from player.score import save_score
from player.sheet import save_image, track_sheet
from toon import FaceRig, MotorTrack, load_face, save_track
from toonface.batch.job import Job, TakeOptions


def ready_pair_take(take: Path, job: Job) -> ReadyTake:
    """Load, clean and calibrate ``take`` as ``job`` says, once for all its faces; a bad take
    raises :class:`common.InputError` naming the file."""
    options = job.take_options if is_table(take) else TakeOptions()  # [csv] is for CSV takes only
    loaded = load_take(take, rate=options.rate, labels=list(options.labels) if options.labels else None,
                       units=options.units)
    profile = load_profile(job.profile) if job.profile else None
    try:
        return ready_take(loaded, job.mapping, profile, job.neutral, job.clean, job.mirror)
    except InputError as exc:
        if exc.source is None:  # say which take could not be mapped
            raise InputError(exc.message, take, exc.field) from None
        raise


def map_pair(ready: ReadyTake, face: str) -> MotorTrack:
    """The pair's motor track: the ready take mapped onto ``face``'s rest pose."""
    return map_ready(ready, face_rig(face).face.neutral())


def report_pair(track: MotorTrack) -> dict:
    """The report of a pair's mapped take (:mod:`mapping.report`), as data for the manifest."""
    return dict(track.meta.get("report", {}))


def face_rig(face: str) -> FaceRig:
    """This worker's rig for ``face`` (a built-in name or a file), made once while the file is
    unchanged."""
    path = resolve_builtin(face, "faces", ".json", "face")
    stat = path.stat()
    return _rig(path.resolve(), stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=16)
def _rig(path: Path, mtime_ns: int, size: int) -> FaceRig:
    """The rig of the face file at ``path`` (the worker's one cache, keyed by the file's state)."""
    return FaceRig(load_face(path))


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
    return _size(save_image(track_sheet(face_rig(face), track, samples=samples), _in_folder(path)))


def render_video_part(track: MotorTrack, face: str, start: int, stop: int, fps: float, size: tuple[int, int],
                      samples: int) -> bytes:
    """Frames ``[start, stop)`` of the take's video on ``face``, as MP4 bytes."""
    return render_part(track, face_rig(face), start, stop, fps or track.rate, size, samples)


def render_whole(track: MotorTrack, face: str, path: Path, fps: float, size: tuple[int, int], samples: int,
                 background: str) -> tuple[int, int]:
    """The take's picture on ``face`` in one go, in the format ``path``'s suffix names (WebM,
    ProRes .mov, APNG, WebP, an animated SVG, the web player's .html, or an MP4 with a
    ``background`` of its own); returns ``(frames, bytes)``."""
    from toonface.cli_options import with_background
    from toonface.pipeline import render
    from toonface.web_export import export_web

    rig_face = with_background(face_rig(face).face, background or None)
    if path.suffix == ".html":
        export_web(track, rig_face, _in_folder(path), size=size)
        return frame_count(track, fps or 30.0), _size(path)
    frames = render(track, rig_face, _in_folder(path), size, fps or None, samples)
    return frames, _size(path)


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
