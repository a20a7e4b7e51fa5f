"""Where a command's results go: picture sinks and motor sinks, opened by kind from a spec.

Two interfaces. A picture sink (:class:`player.sinks.FrameSink`) takes rendered RGB frames: an
MP4 file, a folder of PNG frames, raw RGB on standard output, the MJPEG preview. A motor sink
(:class:`toon.recording.MotorSink`) takes frames of the 21 motor values: a ``.csv``/``.npz``
recording, the UDP motor stream. ``play``, ``receive``, ``send`` and ``retarget`` open theirs
here, the same way, and :class:`Outputs` keeps them (closes) at the end or, on an error, drops
them (aborts).

Each kind is registered in :data:`PICTURE_SINKS` or :data:`MOTOR_SINKS`: a function
``open(target, **options) -> sink`` named by ``"module:function"`` (imported only when used) and
a test of whether a spec is of that kind. Options every opener may take: ``rate`` (frames per
second), ``size`` (``(width, height)``), ``key`` (a stream's shared secret), ``live`` (frames
that come as a performer plays, which a kill must not lose); each ignores the rest. A new kind
is one module with its function and one line in a table.
"""

from __future__ import annotations

import contextlib
import importlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any

from common import InputError
from toon.motors import N_MOTORS

if TYPE_CHECKING:
    import numpy as np


@dataclass(frozen=True)
class SinkKind:
    """A registered kind: ``opener`` (``"module:function"``) and ``claims(spec)``."""

    opener: str
    claims: Callable[[str], bool]


#: Picture sinks, tried in order.
PICTURE_SINKS: dict[str, SinkKind] = {
    "preview": SinkKind("toonface.outputs:open_preview", lambda spec: spec.startswith("http://")),
    "vcam": SinkKind("player.vcam:open_virtual_camera", lambda spec: spec.startswith("vcam:")),  # a virtual webcam
    "raw": SinkKind("toonface.outputs:open_pictures", lambda spec: spec == "-"),
    "mp4": SinkKind("toonface.outputs:open_pictures", lambda spec: Path(spec).suffix.lower() == ".mp4"),
    "alpha": SinkKind("toonface.outputs:open_pictures",  # moving pictures with alpha (player.alpha_sinks)
                      lambda spec: Path(spec).suffix.lower() in (".webm", ".mov", ".apng", ".webp")),
    "vector": SinkKind("toonface.outputs:open_pictures",  # an animated SVG, a Lottie animation
                       lambda spec: Path(spec).suffix.lower() in (".svg", ".json")),
    "png": SinkKind("toonface.outputs:open_pictures", lambda spec: not Path(spec).suffix),
}

#: Motor sinks, tried in order.
MOTOR_SINKS: dict[str, SinkKind] = {
    "stream": SinkKind("toonface.outputs:open_stream", lambda spec: spec.startswith(("udp://", "ws://", "wss://"))),
    "vmc": SinkKind("toonface.outputs:open_vmc", lambda spec: spec.startswith("vmc://")),
    "recording": SinkKind("toonface.outputs:open_recording",
                          lambda spec: Path(spec).suffix.lower() in (".csv", ".npz")),
}


def open_sink(spec: str, kinds: dict[str, SinkKind], what: str, **options: Any) -> Any:
    """The sink of ``kinds`` that claims ``spec``, opened with ``options``; an :class:`InputError`
    naming ``spec`` when none does (``what`` says what was expected)."""
    claimed = next((kind for kind in kinds.values() if kind.claims(spec)), None)
    if claimed is None and "png" in kinds:  # a folder of frames whose name holds a dot ("take.v2"), as --format
        from player.sink_choice import FOLDER_FORMATS  # or the disk says

        if options.get("fmt") in FOLDER_FORMATS or Path(spec).is_dir():
            claimed = kinds["png"]
    if claimed is None:
        raise InputError(f"not a known output: expected {what}", spec)
    module, _sep, function = claimed.opener.partition(":")
    return getattr(importlib.import_module(module), function)(spec, **options)


def open_pictures(spec: str, rate: float = 30.0, size: tuple[int, int] = (512, 512), live: bool = False,
                  fmt: str | None = None, **_: Any) -> Any:
    """An MP4 file (``live``: recorded so that a kill does not lose it), a WebM, ProRes .mov,
    APNG or WebP with alpha, an animated SVG, a folder of PNG (or, ``fmt="svg"``, SVG) frames, or
    raw RGB on standard output (``-``)."""
    from player.sink_choice import open_sink as open_picture_file

    return open_picture_file(spec, rate, size, live=live, fmt=fmt)


def open_preview(spec: str, **_: Any) -> Any:
    """The MJPEG preview served at ``http://HOST:PORT`` (port 0: any free one)."""
    from player.preview import PreviewSink

    host, _sep, port = spec.removeprefix("http://").rstrip("/").rpartition(":")
    if not host or not port.isdigit():
        raise InputError("expected http://HOST:PORT for a preview", spec)
    try:
        return PreviewSink((host, int(port)))
    except OSError as exc:
        raise InputError(f"cannot listen: {exc.strerror or exc}", spec) from None


def open_recording(spec: str, rate: float = 60.0, **_: Any) -> Any:
    """A motor track file (``.csv`` or ``.npz``) written when the run ends."""
    from toon.recording import MotorRecorder

    return MotorRecorder(spec, rate)


def open_stream(spec: str, rate: float = 60.0, key: bytes | None = None, frames_per_packet: int = 2,
                keyframe_seconds: float = 0.5, stream: int = 0, say: Callable[[str], None] | None = None,
                token: str = "", ca_file: str | None = None, **_: Any) -> Any:
    """The motor stream to ``udp://HOST:PORT`` (a receiver or a relay), or through a room server
    at ``ws[s]://HOST:PORT/r/ROOM`` with the room's performer ``token``; ``say`` takes its live
    warnings (:class:`stream.sender.StreamSender`)."""
    from stream.packets import StreamWriter
    from stream.sender import StreamSender
    from stream.websocket import LinkError, WebSocketLink

    try:
        writer = StreamWriter(rate, frames_per_packet, keyframe_seconds, key=key, stream=stream)
    except ValueError as exc:  # a source's rate the wire cannot carry (a 1000 Hz take)
        raise InputError(f"cannot stream it: {exc}", spec) from None
    if spec.startswith(("ws://", "wss://")):
        try:
            link = WebSocketLink(spec, token, "perform", ca_file=ca_file)
        except LinkError as exc:
            raise InputError(str(exc), spec) from None
        return StreamSender((link.where, 0), writer, say=say, link=link)
    host, _sep, port = spec.removeprefix("udp://").rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise InputError("expected udp://HOST:PORT for a motor stream", spec)
    return StreamSender((host, int(port)), writer, say=say)


def open_vmc(spec: str, neutral: np.ndarray | None = None, **_: Any) -> Any:
    """VMC messages to ``vmc://HOST:PORT`` (a VMC receiver: VTuber software, an avatar app),
    scores measured from the face's ``neutral``."""
    from capture.vmc import VMC_PORT
    from common.address import parse_address
    from player.vmc_out import VmcOut
    from toon import standard_neutral

    try:
        address = parse_address(spec.removeprefix("vmc://"), VMC_PORT)
    except ValueError as exc:
        raise InputError(str(exc), spec) from None
    return VmcOut(address, standard_neutral() if neutral is None else neutral)


@dataclass
class Outputs:
    """A command's sinks, kept together: closed (their output kept) when the ``with`` block ends
    normally or by Ctrl-C/SIGTERM, aborted (nothing left that looks complete) on an error."""

    pictures: list[Any] = field(default_factory=list)
    motors: list[Any] = field(default_factory=list)

    def picture(self, spec: str, **options: Any) -> Any:
        """Open a picture sink for ``spec`` and keep it."""
        sink = open_sink(spec, PICTURE_SINKS, "a .mp4 file; with alpha, .webm (VP9), .mov (ProRes 4444), .apng or "
                         ".webp; an animated .svg; a Lottie .json; a folder for PNG (or SVG) frames; - for raw RGB on "
                         "standard output; or http://HOST:PORT for a preview", **options)
        self.pictures.append(sink)
        return sink

    def motor(self, spec: str, **options: Any) -> Any:
        """Open a motor sink for ``spec`` and keep it."""
        sink = open_sink(spec, MOTOR_SINKS, "a .csv or .npz motor track, udp://HOST:PORT for a motor stream, or "
                         "vmc://HOST:PORT for a VMC receiver",
                         **options)
        self.motors.append(sink)
        return sink

    def close(self) -> None:
        """Keep every output."""
        for sink in [*self.pictures, *self.motors]:
            sink.close()

    def abort(self) -> None:
        """Drop every output."""
        for sink in [*self.pictures, *self.motors]:
            with contextlib.suppress(Exception):
                sink.abort()

    def __enter__(self) -> Outputs:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        if kind is None or issubclass(kind, KeyboardInterrupt):
            self.close()
        else:
            self.abort()


class PerformerRecordings:
    """``receive --record`` with several performers: each one's motors as shown, the first
    performer's at ``path`` and each later one's, in the order their first frames are shown, at
    ``STEM-2.EXT``, ``STEM-3.EXT``... A file is opened with its performer's first frame shown, so
    a sender that never played leaves none.

    Parameters
    ----------
    outputs : Outputs
        Keeps (or drops) the recordings with the command's other outputs.
    path : str
        ``--record``'s file (.csv or .npz).
    """

    def __init__(self, outputs: Outputs, path: str) -> None:
        self.outputs, self.path = outputs, Path(path)
        self.sinks: list[Any] = []  # in the order opened: the first performer's is ``path``
        self._later = 1

    def attach(self, playout: Any, first: bool = False) -> None:
        """Record what ``playout`` (a :class:`stream.playout.Playout`) shows, at stream time,
        frame for frame; ``first``: the first performer's, at ``path``."""
        sink: Any = None

        def keep(t: float, values: np.ndarray) -> None:
            nonlocal sink
            if sink is None:
                sink = self._open(first)
            sink.rate = playout.rate  # known once the stream's first packet has come
            sink.write(t, values[:N_MOTORS], extra=dict(zip(playout.codes, values[N_MOTORS:].tolist(), strict=True)))

        playout.shown = keep

    def written(self) -> list[str]:
        """The files written, the first performer's first."""
        return [str(s.written) for s in self.sinks if s.written is not None]

    def _open(self, first: bool) -> Any:
        if first:
            path = self.path
        else:
            self._later += 1
            path = self.path.with_name(f"{self.path.stem}-{self._later}{self.path.suffix}")
        sink = self.outputs.motor(str(path), rate=60.0)
        self.sinks.insert(0, sink) if first else self.sinks.append(sink)
        return sink
