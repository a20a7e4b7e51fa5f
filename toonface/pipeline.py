"""The one-call pipeline: take -> motor track -> rendered frames, and the built-in demo."""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from capture import SyntheticTake, Take, save_take, synthesize
from common.errors import InputError, Interrupted, Terminated
from mapping import CleanSettings, Mapping, Profile, map_take
from player import render_track
from player.backends import open_renderer
from player.beside import SideBySide, beside_width
from player.offline import frame_count
from player.sinks import keeps_alpha
from toon import Face, FaceRig, MotorTrack, load_face, save_track
from toonface.outputs import Outputs


def truth_track(synthetic: SyntheticTake) -> MotorTrack:
    """The synthetic performer's true motors as a :class:`MotorTrack`."""
    return MotorTrack.from_columns(synthetic.motor_codes, synthetic.motors, synthetic.take.rate,
                                   meta={"source": "synthetic ground truth"})


def map_onto_face(take: Take, neutral_window: tuple[float, float] | str | None = (0.0, 1.0), face: Face | None = None,
             mirror: bool = False, mapping: Mapping | str | None = None, profile: Profile | None = None,
             settings: CleanSettings = CleanSettings(), life: bool | None = None) -> MotorTrack:
    """Clean and map a take (see :func:`mapping.map_take`).

    With ``face``, the performer's neutral maps onto that face's rest pose; otherwise onto the
    standard neutral shared by the built-in faces. ``mirror`` swaps the sides whatever the
    mapping says. ``neutral_window``: seconds, ``"first"``, ``"stillest"`` or None (a given
    profile's rest, else the first second); see :func:`mapping.workflow.rest_window`. ``life``:
    the life layer (:mod:`mapping.life`) on the motors the source does not drive (None: on for a
    voice alone).
    """
    target = None if face is None else face.neutral()
    return map_take(take, mapping, profile, neutral_window, target, settings, mirror, life)


def render(track: MotorTrack, face: Face, output: str | os.PathLike, size: tuple[int, int] = (512, 512),
           fps: float | None = None, samples: int = 4, progress: Callable[[int], None] | None = None,
           beside: str | os.PathLike | None = None, beside_start: float = 0.0,
           partial_as: str | os.PathLike | None = None, fmt: str | None = None) -> int:
    """Render ``track`` on ``face`` to an MP4 (``*.mp4``), a WebM, ProRes .mov, APNG or WebP
    (transparent where the face's background is), an animated SVG (``.svg``), a folder of PNG
    frames (or SVG frames, ``fmt="svg"``) or raw RGB (``-``); returns frames written.

    The output appears only when complete. When Ctrl-C or SIGTERM stops it, the frames drawn so
    far are kept under a name that says so (``out.partial-318.mp4``, after ``partial_as`` where
    given), an earlier ``output`` is left as it was, and :class:`~common.errors.Interrupted`
    says what was kept. On an error nothing is left. ``beside``: a video shown left of the
    cartoon, frame for frame from ``beside_start`` seconds of its clock (:mod:`player.beside`).
    """
    transparent = face.background[3] < 1.0
    if transparent and beside is not None:
        raise InputError("a transparent background and a video beside it do not go together: give the face a "
                         "colour (--background) or leave out --side-by-side")
    with open_renderer(size, samples) as renderer:
        extra = beside_width(beside, size[1]) if beside is not None else 0
        sink = Outputs().picture(str(output), rate=fps or track.rate, size=(size[0] + extra, size[1]), fmt=fmt)
        if beside is not None and hasattr(sink, "write_geometry"):
            sink.abort()
            raise InputError("a vector output cannot show a video beside the cartoon: leave out --side-by-side",
                             output)
        if transparent and not keeps_alpha(sink):
            sink.abort()
            raise InputError("has no alpha channel for the transparent background: give .webm, .mov (ProRes 4444), "
                             ".apng, .webp or a folder for PNG frames, or a background colour (--background)", output)
        writer = SideBySide(sink, beside, extra, size[1], fps or track.rate, beside_start) if beside else sink
        try:
            frames = render_track(track, FaceRig(face), renderer, writer, fps, progress)
        except KeyboardInterrupt as stop:
            kept = sink.keep_partial(partial_as)  # a file or folder under a partial name; a stream flushed
            raise Interrupted(str(kept), sink.frames, frame_count(track, fps or track.rate),
                              "SIGTERM" if isinstance(stop, Terminated) else "SIGINT") from None
        except BaseException:
            sink.abort()
            raise
        finally:
            if isinstance(writer, SideBySide):
                writer.close()
        sink.close()
        return frames


def render_with_sound(track: MotorTrack, face: Face, output: str | os.PathLike, sound: str | os.PathLike,
                      start: float = 0.0, size: tuple[int, int] = (512, 512), fps: float | None = None,
                      progress: Callable[[int], None] | None = None, side_by_side: bool = False) -> int:
    """:func:`render` into an MP4, a .mov or a WebM that carries ``sound``'s audio from
    ``start`` seconds (a talking-head video's own voice; with ``side_by_side``, its picture left
    of the cartoon); without an audio stream in ``sound``, or into a format without sound
    (APNG, WebP, PNG frames), the picture alone."""
    from player.mux import SOUND_CONTAINERS, has_audio, mux_audio

    output = Path(output)
    beside = sound if side_by_side else None
    if output.suffix.lower() not in SOUND_CONTAINERS or not has_audio(sound):
        return render(track, face, output, size, fps, progress=progress, beside=beside, beside_start=start)
    picture = output.with_name(f".{output.stem}.picture{output.suffix}")
    try:  # interrupted, the picture drawn so far is kept as the output's partial (without its sound)
        frames = render(track, face, picture, size, fps, progress=progress, beside=beside, beside_start=start,
                        partial_as=output)
        mux_audio(picture, sound, output, start)
    finally:
        picture.unlink(missing_ok=True)
    return frames


@dataclass
class StageTimes:
    """Wall-clock seconds per named stage, in the order they ran."""

    seconds: dict[str, float] = field(default_factory=dict)

    @contextmanager
    def stage(self, name: str) -> Iterator[None]:
        """Time the enclosed block as ``name``."""
        start = time.perf_counter()
        try:
            yield
        finally:
            self.seconds[name] = time.perf_counter() - start


@dataclass(frozen=True)
class DemoResult:
    """What :func:`run_demo` wrote, and how long each stage took."""

    video: Path
    take: Path
    motors: Path
    truth: Path
    frames: int
    times: StageTimes
    mean_abs_error: float


def run_demo(out_dir: str | os.PathLike, seconds: float = 10.0, rate: float = 30.0, size: int = 512,
             face: Face | str = "classic", seed: int = 0,
             progress_factory: Callable[[int], Callable[[int], None]] | None = None) -> DemoResult:
    """The whole pipeline on built-in data: synthesise, map, render.

    Writes ``demo.mp4``, ``take.npz`` (the markers), ``motors.csv`` (the mapped track) and
    ``truth.csv`` (the motors that drove the synthetic performer) into ``out_dir``.
    ``progress_factory(total_frames)`` may return a per-frame progress callback.
    """
    face_obj = load_face(face) if isinstance(face, str) else face  # a bad face fails before any work
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)  # the demo's own folder
    times = StageTimes()
    with times.stage("synthesise"):
        synthetic = synthesize(seconds=seconds, rate=rate, seed=seed)
    with times.stage("map"):
        track = map_onto_face(synthetic.take)
    truth = truth_track(synthetic)
    with times.stage("write take and tracks"):
        paths = (save_take(synthetic.take, out / "take.npz"), save_track(track, out / "motors.csv"),
                 save_track(truth, out / "truth.csv"))
    progress = progress_factory(track.frames) if progress_factory else None
    with times.stage("render"):
        frames = render(track, face_obj, out / "demo.mp4", (size, size), progress=progress)
    error = float(np.mean(np.abs(track.values - truth.values)))
    return DemoResult(out / "demo.mp4", *paths, frames=frames, times=times, mean_abs_error=error)
