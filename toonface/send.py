"""The telepresence sender: marker frames in real time -> live mapping -> motor stream over UDP.

Sources play at their own frame rate on the wall clock: a take file, the synthetic performer,
or a video whose dot markers are tracked as it plays. Each frame is cleaned and mapped in its
live form (:class:`mapping.live.LiveMapper`), stamped with the sender's clock and packed
(:class:`stream.packets.StreamWriter`); only motor values cross the network.
"""

from __future__ import annotations

import socket
import time
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from capture import MarkerSet, Take, load_markerset, synthesize
from capture.dots import DotStyle, DotTracker, find_dots, front_layout, sticker_labels
from capture.performance import default_performance
from capture.videoio import frames as video_frames
from capture.videoio import probe
from common import InputError
from mapping import Mapping, Profile, calibrate, choose_mapping, load_profile, prepare
from mapping.live import LiveMapper
from mapping.workflow import SELF_MIN_SIDE, builtin_profile, check_profile
from stream.packets import StreamWriter, is_key_request

UDP_IP_HEADER = 28  # bytes a UDP datagram costs on the wire over IPv4 beyond its payload


@dataclass
class LiveSource:
    """Marker frames as they come: their labels, rate, and ``(M, 3)`` world positions, mm."""

    labels: tuple[str, ...]
    rate: float
    frames: Iterator[np.ndarray]
    name: str
    recording: Take | None = None  # the whole take, when the source is a file


#: Seconds of a take its own profile is calibrated on, when its marker set has no typical one.
CALIBRATION_SECONDS = 10.0


def take_source(take: Take, repeat: bool = False) -> LiveSource:
    """A take played from its start (and again, if ``repeat``)."""
    def play() -> Iterator[np.ndarray]:
        while True:
            yield from take.positions
            if not repeat:
                return
    return LiveSource(take.labels, take.rate, play(), take.meta.get("file", "take"), take)


def synthetic_source(seconds: float = 60.0, rate: float = 60.0, seed: int = 0, noise_mm: float = 0.2) -> LiveSource:
    """The synthetic performer (calibration segment, then expressions), played once."""
    take = synthesize(seconds=seconds, rate=rate, noise_mm=noise_mm, seed=seed,
                      performance=default_performance(seconds)).take
    return LiveSource(take.labels, take.rate, iter(take.positions), "synthetic performer")


def video_source(path: str | Path, colour: str = "blue", markerset: str = "toon32") -> LiveSource:
    """Dot markers tracked frame by frame as the video plays (the first frame must show them all)."""
    info = probe(path)
    ms = load_markerset(markerset)
    labels = sticker_labels(ms.labels)
    layout = front_layout(ms, labels)
    style = DotStyle.named(colour)
    tracker = DotTracker(layout)

    def play() -> Iterator[np.ndarray]:
        started = False
        for image in video_frames(info):
            if not started:
                try:
                    pixels = tracker.start(find_dots(image, style))
                except ValueError as exc:
                    raise InputError(f"no {colour} dot markers on the first frame ({exc})", path) from None
                tracker.remember(image)
                started = True
            else:
                pixels = tracker.step(image, find_dots(image, style))
            mm = np.zeros((len(labels), 3))
            mm[:, 0] = (pixels[:, 0] - tracker.origin[0]) * tracker.mm_per_pixel
            mm[:, 1] = -(pixels[:, 1] - tracker.origin[1]) * tracker.mm_per_pixel
            mm[~np.isfinite(pixels).all(axis=1)] = np.nan
            yield mm
    return LiveSource(tuple(labels), info.rate or 30.0, play(), Path(path).name)


def build_mapper(source: LiveSource, mapping: Mapping | str | None = None, profile: Profile | None = None,
                 target_neutral: np.ndarray | None = None, rest_seconds: float = 1.0,
                 notes: list[str] | None = None) -> LiveMapper:
    """The live mapper for a source: the named mapping or the preset its labels match, and the
    given profile or the marker set's typical one, with the rest taken from the first
    ``rest_seconds``. Where the marker set has no typical profile, a take's own first
    :data:`CALIBRATION_SECONDS` make one; what was chosen is appended to ``notes``."""
    probe_take = Take(np.zeros((1, len(source.labels), 3)), source.labels, source.rate)
    chosen, markerset = choose_mapping(probe_take, mapping)
    if profile is None:
        typical = builtin_profile(markerset.name)
        if typical is not None:
            profile = load_profile(typical)
        elif source.recording is not None:
            profile = _own_profile(source.recording, chosen, markerset)
            if notes is not None:
                notes.append(f"no typical profile for marker set {markerset.name}: a profile from the take's "
                             f"first {CALIBRATION_SECONDS:g} s (rest {profile.notes['neutral']}, ranges "
                             f"{profile.notes['range']})")
        else:
            raise InputError(f"no typical profile for marker set {markerset.name}; give one with --profile")
    check_profile(profile, chosen, markerset.name)
    try:
        return LiveMapper(chosen, markerset, profile, source.labels, source.rate, target_neutral, rest_seconds)
    except ValueError as exc:
        raise InputError(str(exc)) from None


def _own_profile(take: Take, mapping: Mapping, markerset: MarkerSet) -> Profile:
    """A profile from the take's first seconds: rest from its first second (or stillest), ranges
    from all of them, as ``map`` makes one for a take without a profile."""
    first = take.window(float(take.times[0]), float(take.times[0]) + CALIBRATION_SECONDS)
    start = Take(take.positions[first], take.labels, take.rate, take.times[first] - take.times[0], take.dims,
                 take.meta)
    return calibrate(mapping, prepare(start, markerset), percentiles=(1.0, 99.0), min_side=SELF_MIN_SIDE)


@dataclass
class SendReport:
    """What a sender did; rates are per second of stream."""

    frames: int = 0
    packets: int = 0
    payload_bytes: int = 0
    packet_bytes: int = 0
    keyframes: int = 0
    key_requests: int = 0
    step_seconds: deque[float] = field(default_factory=lambda: deque(maxlen=3600))  # the last minute at 60 Hz

    def rates(self, rate: float) -> dict:
        """Payload, stream and wire bit rates (kbit/s) and the mapping's cost per frame (recent)."""
        seconds = max(self.frames / rate, 1e-9)
        steps = np.array(self.step_seconds or [0.0]) * 1000
        return {"frames": self.frames, "packets": self.packets, "keyframes": self.keyframes,
                "key_requests": self.key_requests,
                "payload_kbps": round(self.payload_bytes * 8 / seconds / 1000, 3),
                "stream_kbps": round(self.packet_bytes * 8 / seconds / 1000, 3),
                "wire_kbps": round((self.packet_bytes + UDP_IP_HEADER * self.packets) * 8 / seconds / 1000, 3),
                "map_ms_median": round(float(np.median(steps)), 3),
                "map_ms_p95": round(float(np.percentile(steps, 95)), 3)}


def run_sender(source: LiveSource, mapper: LiveMapper, writer: StreamWriter, target: tuple[str, int],
               seconds: float | None = None, clock: Callable[[], float] = time.perf_counter,
               sleep: Callable[[float], None] = time.sleep,
               on_frame: Callable[[int, np.ndarray, float], None] | None = None,
               stop: Callable[[], bool] = lambda: False) -> SendReport:
    """Play ``source`` in real time to ``target``; returns what was sent.

    ``on_frame(index, values, capture_time)`` sees every motor frame sent (for recording and
    measuring). Keyframe requests arriving on the socket are honoured at the next packet.
    """
    report = SendReport()
    limit = None if seconds is None else int(round(seconds * source.rate))
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setblocking(False)
    try:
        start = clock()
        for index, positions in enumerate(source.frames):
            if (limit is not None and index >= limit) or stop():
                break
            due = start + index / source.rate
            wait = due - clock()
            if wait > 0:
                sleep(wait)
            captured = clock()
            values, _ = mapper.step(positions, index / source.rate)
            report.step_seconds.append(clock() - captured)
            if on_frame is not None:
                on_frame(index, values, captured)
            report.frames += 1
            _take_requests(sock, writer, report)
            datagram = writer.push(values, captured)
            if datagram is not None:
                _send(sock, datagram, target)
        datagram = writer.flush()
        if datagram is not None:
            _send(sock, datagram, target)
    finally:
        sock.close()
    report.packets, report.payload_bytes = writer.packets, writer.payload_bytes
    report.packet_bytes, report.keyframes = writer.packet_bytes, writer.keyframes
    return report


def _send(sock: socket.socket, datagram: bytes, target: tuple[str, int]) -> None:
    try:
        sock.sendto(datagram, target)
    except OSError:
        pass  # nobody listening (ICMP refused) or a full buffer: the stream goes on


def _take_requests(sock: socket.socket, writer: StreamWriter, report: SendReport) -> None:
    while True:
        try:
            data = sock.recv(256)
        except (BlockingIOError, OSError):
            return
        if is_key_request(data, writer.key):
            writer.request_keyframe()
            report.key_requests += 1
