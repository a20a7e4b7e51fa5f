"""The live Animator: the loop, the command sockets, the preview and the sinks together.

Each loop (constant loop time, :class:`~player.animator.Loop`): the motors take one slice each,
the face's values are mixed from the idle face, a performer or a track, the motions and the
overrides (:mod:`player.providers`), the face is drawn, and the frame goes to every picture sink
(the preview is one). Commands arrive on the sockets at any time and are sliced at once
under the Animator's lock; the next loop executes their first slices.
"""

from __future__ import annotations

import socketserver
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np

from common import InputError
from player.animator import DEFAULT_LOOP_TIME, Animator, Loop
from player.commands import Commands
from player.gl import create_context
from player.motion import SecondaryMotion
from player.preview import PreviewSink
from player.providers import Mixer, Providers, Tracked
from player.renderer import Renderer
from player.server import CommandServer, CommandUDPServer, local_port, start
from player.sinks import FrameSink, keeps_alpha
from toon import Face, FaceRig, Geometry, MotorTrack, load_expressions
from toon.params import DrawnExtras

_Server = TypeVar("_Server", bound="socketserver.TCPServer | socketserver.UDPServer | PreviewSink")


@dataclass
class LiveSettings:
    """What ``toonface play`` runs (addresses are ``(host, port)``; port 0 picks a free one)."""

    loop_time: float = DEFAULT_LOOP_TIME
    size: tuple[int, int] = (512, 512)
    samples: int = 4
    tcp: tuple[str, int] | None = ("127.0.0.1", 7707)
    udp: tuple[str, int] | None = None
    preview: tuple[str, int] | None = None
    track: MotorTrack | None = None
    repeat: bool = True
    seconds: float | None = None
    sinks: list[FrameSink] = field(default_factory=list)
    source: Callable[[float], np.ndarray] | None = None  # values at a loop time, fully sure (a stream); not track
    tracking: Tracked | None = None  # a live performer: newest values, their confidence, their age
    providers: Providers = field(default_factory=Providers)  # who moves a motor (player/providers.py)
    # told (t, values, extra=...) each loop: the 21 shown and the parameters beyond them drawn (a MotorSink's write)
    shown: list[Callable[..., None]] = field(default_factory=list)
    scene: Callable[[float], Geometry | None] | None = None  # what is drawn instead of the face (several faces)
    extra: Callable[[float], dict[str, float]] | None = None  # the parameters beyond the 21 (HT...) at a loop time
    say: Callable[[str], None] = lambda _: None  # a warning for the user (a parameter the face cannot draw)
    physics: bool = True  # the face's drivers swing what they move (--no-physics: not)


@dataclass
class LiveReport:
    """What a live run did: loops drawn, each one's lateness (seconds), and the loop slots
    dropped because drawing could not keep up (the outputs kept real time across them)."""

    loops: int
    lateness: list[float]
    dropped: int = 0

    def summary(self, loop_time: float) -> str | None:
        """A line for the user when frames were dropped (None when every loop was drawn)."""
        if not self.dropped:
            return None
        slots = self.loops + self.dropped
        return (f"dropped {self.dropped} of {slots} frames ({100 * self.dropped / slots:.1f} %): this machine drew "
                f"{self.loops / (slots * loop_time):.1f} of {1 / loop_time:g} frames a second; recordings kept "
                "real time")

    def lateness_p95_ms(self) -> float:
        """95th percentile of the loops' lateness, milliseconds."""
        return float(np.percentile(self.lateness, 95) * 1000) if self.lateness else 0.0


def run_live(face: Face, settings: LiveSettings, on_ready: Callable[[dict[str, str]], None] = lambda _: None,
             stop: Callable[[], bool] = lambda: False, clock: Callable[[], float] = time.perf_counter,
             sleep: Callable[[float], None] = time.sleep) -> LiveReport:
    """Run the live player until ``settings.seconds`` pass, ``stop()`` is true, or Ctrl-C.

    ``on_ready`` gets the bound addresses (``{"tcp": "127.0.0.1:7707", ...}``) once everything
    listens. Sinks are closed (their output kept) however the run ends.
    """
    rig = FaceRig(face)
    neutral = face.neutral()
    extras = DrawnExtras(face.extra_codes, face.name, settings.say)
    animator = Animator(neutral, settings.loop_time)
    rests = face.extra_neutral()  # the parameters beyond the 21 the command socket moves (HT 0.8 300)
    moved = Animator(np.array([rests[c] for c in face.extra_codes]), settings.loop_time, face.extra_codes)
    loop = Loop(animator, clock, sleep, beside=(moved,))
    track_values = settings.source or _track_player(settings.track, settings.repeat)
    extra_at = settings.extra or (None if settings.source else _track_extra(settings.track, settings.repeat))
    played = settings.track if settings.source is None and settings.tracking is None else None
    motion = SecondaryMotion(face, played) if settings.physics and face.physics else None  # hair that swings
    latest = [neutral]  # a track's or a stream's values at the loop's time, fully sure
    sure = np.ones(len(neutral))
    tracking = settings.tracking or (None if track_values is None else (lambda: (latest[0], sure, 0.0)))
    mixer = Mixer(neutral, settings.providers, tracking, lambda: (animator.values(), animator.active()))
    commands = Commands(animator, neutral, load_expressions(), lambda: clock() - loop.started, mixer, moved)
    servers: list[socketserver.TCPServer | socketserver.UDPServer] = []
    sinks = list(settings.sinks)  # the preview joins them here, not in the caller's settings
    ready: dict[str, str] = {}
    ctx = create_context()
    try:
        if settings.tcp:
            servers.append(_listen("tcp", settings.tcp, lambda a: CommandServer(a, commands.handle)))
            ready["tcp"] = f"{settings.tcp[0]}:{local_port(servers[-1])}"
        if settings.udp:
            servers.append(_listen("udp", settings.udp, lambda a: CommandUDPServer(a, commands.handle)))
            ready["udp"] = f"{settings.udp[0]}:{local_port(servers[-1])}"
        if settings.preview is not None:
            preview = _listen("preview", settings.preview, PreviewSink)
            sinks.append(preview)
            ready["preview"] = preview.url
            ready["OBS browser source"] = f"{preview.url}obs (only the face; --background none keeps it clear)"
        for server in servers:
            start(server)
        with Renderer(ctx, settings.size, settings.samples) as renderer:
            def frame(_animated: np.ndarray, t: float) -> None:
                if track_values is not None:
                    latest[0] = track_values(t)
                values = mixer.step(t)  # idle, tracking, motions and overrides (player/providers.py)
                extra = extras.drawn(_with_commanded(extra_at(t) if extra_at is not None else None, moved))
                if motion is not None:  # on the track's own clock where a track plays, as render draws it
                    extra = motion.extra_at(_track_time(played, settings.repeat, t), values, extra)
                for tell in settings.shown:  # a motor stream of what is shown (play --stream-to)
                    tell(t, values, extra=extra or None)
                drawn = settings.scene(t) if settings.scene is not None else None
                geometry = drawn if drawn is not None else rig.geometry(values, extra)
                pictures: dict[bool, np.ndarray] = {}  # drawn once each: opaque RGB, straight RGBA
                for sink in sinks:
                    vector = getattr(sink, "write_geometry", None)  # an SVG or Lottie recording
                    if vector is not None:
                        vector(geometry)
                        continue
                    alpha = keeps_alpha(sink) and geometry.background[3] < 1.0
                    if alpha not in pictures:
                        pictures[alpha] = renderer.render(geometry, alpha) if alpha else renderer.render(geometry)
                    sink.write(pictures[alpha])

            loops = None if settings.seconds is None else max(1, int(round(settings.seconds / settings.loop_time)))
            if settings.track is not None and not settings.repeat:
                loops = max(1, int(round(settings.track.duration / settings.loop_time)))
            def skip(frames: int) -> None:
                for sink in sinks:
                    sink.skip(frames)

            on_ready(ready)
            try:
                count = loop.run(loops, frame, stop, skip)
            except KeyboardInterrupt:  # Ctrl-C, or SIGTERM through the command's handler: keep the outputs
                count = loop.drawn
        return LiveReport(count, loop.lateness, loop.dropped)
    finally:
        for server in servers:
            server.shutdown()
            server.server_close()
        for sink in sinks:
            sink.close()
        ctx.release()


class ListenError(InputError):
    """A socket of the live player could not be opened; ``kind`` is ``tcp``, ``udp`` or ``preview``."""

    def __init__(self, kind: str, address: tuple[str, int], reason: str) -> None:
        super().__init__(f"cannot listen on {address[0]}:{address[1]}: {reason}")
        self.kind, self.address = kind, address


def _listen(kind: str, address: tuple[str, int], make: Callable[[tuple[str, int]], _Server]) -> _Server:
    try:
        return make(address)
    except OSError as exc:
        raise ListenError(kind, address, exc.strerror or str(exc)) from None


def _track_player(track: MotorTrack | None, repeat: bool, extra: bool = False
                  ) -> Callable[[float], np.ndarray] | None:
    """The track's values at a time (looping if ``repeat``), by linear interpolation: its 21
    motors, or with ``extra`` its parameters beyond them (None where it has none)."""
    if track is None or (extra and not track.extra_codes):
        return None
    times = track.times
    values = track.extra if extra and track.extra is not None else track.values

    def at(t: float) -> np.ndarray:
        when = _track_time(track, repeat, t)
        return np.array([np.interp(when, times, values[:, c]) for c in range(values.shape[1])])
    return at


def _with_commanded(given: dict[str, float] | None, moved: Animator) -> dict[str, float]:
    """The parameters beyond the 21 to draw: ``given`` (a stream's, a track's) where there are
    any, and those the command socket moves (all of them where nothing gives any)."""
    active = moved.active()
    values = moved.values()
    return {**(given or {}), **{code: float(values[k]) for k, code in enumerate(moved.codes)
                                if given is None or active[k] or code not in given}}


def _track_time(track: MotorTrack | None, repeat: bool, t: float) -> float:
    """Where a played track is at loop time ``t`` (as :func:`_track_player` reads it); ``t`` itself
    without a track."""
    if track is None:
        return t
    return t % max(track.duration, 1e-9) if repeat else min(t, float(track.times[-1]))


def _track_extra(track: MotorTrack | None, repeat: bool) -> Callable[[float], dict[str, float]] | None:
    """The track's parameters beyond the 21 at a time, by code (None where it has none)."""
    at = _track_player(track, repeat, extra=True)
    if at is None or track is None:
        return None
    codes = track.extra_codes
    return lambda t: dict(zip(codes, at(t).tolist(), strict=True))
