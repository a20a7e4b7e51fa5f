"""Performer data arriving frame by frame: one interface for every live source.

A :class:`Source` has marker labels, a frame rate and an iterator of :class:`Frame` (a time in
seconds from the source's start and world positions ``(M, 3)``, mm, NaN unseen). A recorded
source (a take file, a video, the synthetic performer) can produce its frames as fast as asked;
:func:`paced` plays it in real time on a clock. A live source (a camera, a network bridge) sets
``live`` and delivers frames when they happen, and :func:`paced` passes them on as they come.

Kinds are registered in :data:`KINDS`: a kind is a function ``open(target, **options) ->
Source`` named by ``"module:function"`` (imported only when used) and a test of whether a
command-line spec is one of its kind. ``open_source("synthetic")``, ``open_source("face.mp4")``,
``open_source("take.c3d")``, or with an explicit kind, ``open_source("video:face.mkv")``.
A new kind is one module with its function and one line in :data:`KINDS`.
"""

from __future__ import annotations

import importlib
import os
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from capture.take import Take
from common import InputError

if TYPE_CHECKING:
    from capture.videoio import VideoInfo

#: A sound file is a voice (capture.voice.SOUND_SUFFIXES, kept here so that listing kinds imports no sound code).
SOUND_SUFFIXES = frozenset({".wav", ".mp3", ".ogg", ".oga", ".opus", ".flac", ".m4a", ".aac", ".wma"})
VIDEO_SUFFIXES = frozenset({".mp4", ".mov", ".avi", ".mkv", ".webm", ".mpg", ".mpeg", ".m4v"})


class Frame(NamedTuple):
    """One frame of a source: ``t`` seconds from its start, ``positions`` ``(M, 3)`` mm,
    ``channels`` ``(C,)`` (the source's :attr:`Source.channel_names`, NaN not measured) where
    it has any, ``confidence`` (0..1) where the tracker that made it says how sure it is, and
    ``head``, the head's rotation ``(3, 3)`` where the tracker reports one (a bridge, whose
    positions are the head references it turned)."""

    t: float
    positions: np.ndarray
    channels: np.ndarray | None = None
    confidence: float | None = None
    head: np.ndarray | None = None


@dataclass
class Source:
    """Marker frames as they come (see the module docstring).

    Attributes
    ----------
    labels : tuple of str
        The markers, one per row of each frame's positions.
    rate : float
        Nominal frames per second.
    frames : iterator of Frame
    name : str
        For messages ("face.mp4", "synthetic performer").
    dims : int
        3, or 2 for planar (video) markers whose z is 0.
    live : bool
        Frames arrive on their own clock; :func:`paced` does not wait for them.
    recording : Take, optional
        The whole take, where the source is one (a profile can be calibrated from it).
    meta : dict
        What the source learned (a video's ``mm_per_pixel`` once tracking has started).
    channel_names : tuple of str
        Names of each frame's ``channels`` (a markerless tracker's blendshapes); empty for none.
    halt : threading.Event
        Set from another thread to end a live source's frames (a network bridge checks it while
        it waits for data, at least twice a second).
    release : callable, optional
        What else :meth:`close` lets go of: a bridge's socket, bound before a first frame is
        asked for (an unstarted iterator of frames has nothing to close).
    """

    labels: tuple[str, ...]
    rate: float
    frames: Iterator[Frame]
    name: str
    dims: int = 3
    live: bool = False
    recording: Take | None = None
    meta: dict[str, Any] = field(default_factory=dict)
    channel_names: tuple[str, ...] = ()
    halt: threading.Event = field(default_factory=threading.Event)
    release: Callable[[], None] | None = None

    def close(self) -> None:
        """Stop the frames (a live source's socket or camera is released with them)."""
        stop = getattr(self.frames, "close", None)
        if stop is not None:
            stop()
        if self.release is not None:
            self.release()

    def to_take(self, progress: Callable[[int], None] | None = None) -> Take:
        """Every frame (as fast as they come) as a take; ``progress(1)`` after each."""
        times, rows, channels = [], [], []
        blank = np.full(len(self.channel_names), np.nan)
        for frame in self.frames:
            times.append(frame.t)
            rows.append(frame.positions)
            channels.append(blank if frame.channels is None else frame.channels)
            if progress:
                progress(1)
        if not rows:
            return Take(np.empty((0, len(self.labels), 3)), self.labels, self.rate, dims=self.dims,
                        meta=dict(self.meta), channels=np.empty((0, len(self.channel_names))),
                        channel_names=self.channel_names)
        return Take(np.stack(rows), self.labels, self.rate, times=np.array(times), dims=self.dims,
                    meta=dict(self.meta), channels=np.array(channels).reshape(len(rows), len(self.channel_names)),
                    channel_names=self.channel_names)


@dataclass(frozen=True)
class SourceKind:
    """A registered kind: ``opener`` (``"module:function"``), and ``claims(spec)``: whether a
    spec with no ``kind:`` prefix is of this kind."""

    opener: str
    claims: Callable[[str], bool] = lambda spec: False


#: The kinds of source, tried in order for a spec without a ``kind:`` prefix.
KINDS: dict[str, SourceKind] = {
    "synthetic": SourceKind("capture.sources:synthetic_source", lambda spec: spec == "synthetic"),
    "face": SourceKind("capture.face_sources:face_source"),  # face:VIDEO, a video without markers
    "camera": SourceKind("capture.face_sources:camera_source"),  # camera:N, or camera:VIDEO played as one
    "vmc": SourceKind("capture.vmc:vmc_source"),  # vmc:HOST:PORT, a face-tracking app over the VMC protocol
    "openseeface": SourceKind("capture.openseeface:openseeface_source"),  # openseeface:HOST:PORT, its tracker
    "voice": SourceKind("capture.voice_live:voice_source",  # voice:mic, voice:mic:DEVICE, or a sound file
                        lambda spec: Path(spec).suffix.lower() in SOUND_SUFFIXES),
    # video:VIDEO is dot markers; a video named without a kind is looked at (any_video_source)
    "video": SourceKind("capture.file_sources:any_video_source",
                        lambda spec: Path(spec).suffix.lower() in VIDEO_SUFFIXES),
    "take": SourceKind("capture.file_sources:take_file_source", lambda spec: True),
}


def open_source(spec: str, kinds: dict[str, SourceKind] | None = None, **options: Any) -> Source:
    """The source a command-line ``spec`` names (see the module docstring); ``options`` go to
    its kind's function, which ignores those it does not take."""
    kinds = KINDS if kinds is None else kinds
    kind, _, rest = spec.partition(":")
    if rest and kind in kinds and not Path(spec).exists():
        chosen, target = kinds[kind], rest
        options = {**options, "named": True}  # the user named the kind: no guessing (file_sources.any_video_source)
    else:
        found = next((k for k in kinds.values() if k.claims(spec)), None)
        if found is None:
            raise InputError(f"not a known kind of source (known: {', '.join(kinds)})", spec)
        chosen, target = found, spec
    module, _, function = chosen.opener.partition(":")
    opener: Callable[..., Source] = getattr(importlib.import_module(module), function)
    return opener(target, **options)


def paced(source: Source, clock: Callable[[], float] = time.perf_counter,
          sleep: Callable[[float], None] = time.sleep) -> Iterator[Frame]:
    """The source's frames in real time: each recorded frame when its time comes on ``clock``
    (a live source's as they arrive)."""
    start = clock()
    for frame in source.frames:
        if not source.live:
            wait = start + frame.t - clock()
            if wait > 0:
                sleep(wait)
        yield frame


def take_source(take: Take, repeat: bool = False, **_: Any) -> Source:
    """A take played from its start (and again, if ``repeat``): frame times from its start."""
    times = take.times - take.times[0] if take.frames else take.times
    period = (float(times[-1]) + 1.0 / take.rate) if take.frames else 0.0

    def play() -> Iterator[Frame]:
        offset = 0.0
        while take.frames:
            for t, positions, channels in zip(times, take.positions, take.channels, strict=True):
                yield Frame(offset + float(t), positions, channels if take.channel_names else None)
            if not repeat:
                return
            offset += period
    return Source(take.labels, take.rate, play(), take.meta.get("file", "take"), take.dims, recording=take,
                  meta=dict(take.meta), channel_names=take.channel_names)


def synthetic_source(target: str = "synthetic", seconds: float | None = None, rate: float = 60.0, seed: int = 0,
                     noise_mm: float = 0.2, **_: Any) -> Source:
    """The synthetic performer (calibration segment, then expressions), ``seconds`` long (60 by default)."""
    from capture.performance import default_performance
    from capture.synthetic import synthesize

    length = 60.0 if seconds is None else seconds
    take = synthesize(seconds=length, rate=rate, noise_mm=noise_mm, seed=seed,
                      performance=default_performance(length)).take
    return Source(take.labels, take.rate, (Frame(float(t), p) for t, p in zip(take.times, take.positions,
                                                                                strict=True)),
                  "synthetic performer", recording=take)


def video_source(path: str | os.PathLike, colour: str = "blue", markerset: str = "toon32", start_frame: int = 0,
                 info: VideoInfo | None = None, repeat: bool = False, **_: Any) -> Source:
    """Dot markers tracked frame by frame as the video plays (:func:`capture.dots.follow_dots`,
    the loop ``toonface track`` runs too); ``start_frame`` must show the face neutral with
    every dot. Positions are mm in the marker set's front view (``dims`` 2), placed by fitting
    its layout on that frame (``meta["mm_per_pixel"]``); ``repeat``: from ``start_frame`` again
    at the end, the dots identified anew. ``info``: the video's :func:`probe`, where the caller
    has it."""
    from capture.dots import DotStyle, DotTracker, follow_dots, front_layout, pixels_to_mm, sticker_labels
    from capture.markerset import load_markerset
    from capture.videoio import frames, probe

    info = probe(path) if info is None else info  # a caller that probed passes what it found
    ms = load_markerset(markerset)
    labels = sticker_labels(ms.labels)
    tracker = DotTracker(front_layout(ms, labels))
    style = DotStyle.named(colour)
    rate = info.rate or 30.0
    meta: dict[str, Any] = {"source": "video", "file": Path(path).name, "tracker": "dots",
                            "image_size": [info.width, info.height], "decoder": info.backend,
                            "markerset": ms.name, "dot_colour": colour, "start_frame": start_frame}

    def play() -> Iterator[Frame]:
        tracked = follow_dots(frames(info), tracker, style, start_frame)
        index = 0
        while True:
            try:
                pixels = next(tracked)
            except StopIteration:
                if not repeat or not index:
                    return
                tracked = follow_dots(frames(info), tracker, style, start_frame)  # again, the dots found anew
                continue
            except ValueError as exc:
                raise InputError(f"cannot identify the {ms.name} dots on frame {start_frame}: {exc}; start on a "
                                 "frame where the face is neutral and every dot shows (track: --init)", path) from None
            meta["mm_per_pixel"] = tracker.mm_per_pixel
            yield Frame(index / rate, pixels_to_mm(pixels, tracker.origin, tracker.mm_per_pixel))
            index += 1
    return Source(tuple(labels), rate, play(), Path(path).name, dims=2, meta=meta)

