"""``bridge``: what the bridges from other face-tracking apps add to a live face's latency.

``bridge.vmc_added_ms``: what toonface adds between a VMC sender's datagram (51 ARKit blendshapes,
the head bone and the Apply, one bundle, 60 a second over loopback) and the motors mapped from it
by the ``arkit`` preset (the source's parse, the live mapper's step): the median time from the
datagram leaving the sender to the motors, less the median of the floor, the same datagrams
received by a plain blocking socket in a thread (goal 2 ms). The detail has both medians, the
95th percentile, a plain peer: python-osc's own threaded server dispatching the same bundles to a
handler that only notes the time, and ``back_to_back_ms``: what a datagram costs when it is
already waiting, so that the code runs warm (where a machine's caches go cold in the 16 ms
between a sender's frames, as this project's virtual machine's do, the gap to ``to_motors_ms``).
``bridge.openseeface_added_ms``: the same for
OpenSeeFace's 1,785-byte packets (goal 2 ms). ``bridge.per_performer_ms``: what each performer
beyond the first adds to a receiver's loop (mixing, geometry, one 512x512 picture of them all),
the slope of the median loop time over 1 to 4 performers (no goal; each count's median in the
detail).
"""

from __future__ import annotations

import math
import socket
import threading
import time
from collections.abc import Callable
from itertools import islice

import numpy as np

from bench.core import Figure
from capture.blendshapes import BLENDSHAPES
from capture.sources import open_source
from toon import load_face
from toonface.send import build_mapper

RATE = 60.0


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``bridge.*`` figures."""
    frames = 240 if quick else 1200  # 4 or 20 s at 60 Hz
    vmc, vmc_p95 = _through_source("vmc", _vmc_bundle, frames)
    vmc_floor, _ = _through_socket(_vmc_bundle, frames)
    peer, peer_p95 = _through_python_osc(frames)
    osf, osf_p95 = _through_source("openseeface", _osf_packet, frames)
    osf_floor, _ = _through_socket(_osf_packet, frames)
    vmc_busy, osf_busy = _back_to_back("vmc", _vmc_bundle, frames), _back_to_back("openseeface", _osf_packet, frames)
    per_performer, loops = _per_performer(20 if quick else 100)
    detail = {"frames": frames, "rate_hz": RATE, "via": "UDP on loopback", "mapping": "arkit"}
    return [Figure("bridge.vmc_added_ms", round(vmc - vmc_floor, 3), "ms", 2.0, False,
                   {**detail, "to_motors_ms": vmc, "p95_ms": vmc_p95, "plain_socket_ms": vmc_floor,
                    "back_to_back_ms": vmc_busy, "peer_python_osc_dispatch_ms": peer, "peer_p95_ms": peer_p95}),
            Figure("bridge.openseeface_added_ms", round(osf - osf_floor, 3), "ms", 2.0, False,
                   {**detail, "to_motors_ms": osf, "p95_ms": osf_p95, "plain_socket_ms": osf_floor,
                    "back_to_back_ms": osf_busy}),
            Figure("bridge.per_performer_ms", per_performer, "ms", None, False,
                   {"loop_ms_by_performers": loops, "size": [512, 512], "face": "classic",
                    "renderer": "GL, as the live loop (Mesa llvmpipe where there is no GPU)"})]


def _per_performer(loops: int) -> tuple[float, dict[int, float]]:
    """The slope (ms a performer) of a receiver loop's median time over 1..4 performers."""
    from player.backends import open_renderer
    from player.ensemble import Ensemble
    from player.providers import Providers

    face = load_face("classic")
    rng = np.random.default_rng(0)
    medians = {}
    with open_renderer((512, 512), backend="gl") as renderer:  # as a receiver's live loop draws
        for count in range(1, 5):
            ensemble = Ensemble(face, (512, 512), Providers())
            times = []
            for k in range(loops):
                performers = [(stream, np.clip(face.neutral() + rng.normal(0, 0.1, 21), 0, 1), 0.0)
                              for stream in range(count)]
                start = time.perf_counter()
                drawn = ensemble.frame(performers, k / 25)
                assert drawn is not None
                renderer.render(drawn)
                times.append(time.perf_counter() - start)
            medians[count] = round(float(np.median(times)) * 1000, 3)
    slope = float(np.polyfit(list(medians), list(medians.values()), 1)[0])
    return round(slope, 3), medians


def _vmc_bundle(k: int) -> bytes:
    from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
    from pythonosc.osc_message_builder import OscMessageBuilder

    bundle = OscBundleBuilder(IMMEDIATELY)
    phase = k / RATE
    for i, name in enumerate(BLENDSHAPES):
        message = OscMessageBuilder("/VMC/Ext/Blend/Val")
        message.add_arg(name)
        message.add_arg(0.5 + 0.5 * math.sin(phase * 3 + i))
        bundle.add_content(message.build())
    half = math.radians(10 * math.sin(phase)) / 2
    head = OscMessageBuilder("/VMC/Ext/Bone/Pos")
    for arg in ("Head", 0.0, 0.0, 0.0, 0.0, math.sin(half), 0.0, math.cos(half)):
        head.add_arg(arg)
    bundle.add_content(head.build())
    bundle.add_content(OscMessageBuilder("/VMC/Ext/Blend/Apply").build())
    return bundle.build().dgram


def _osf_packet(k: int) -> bytes:
    import struct

    half = math.radians(5 * math.sin(k / RATE)) / 2
    head = struct.pack("=diffffBf4f3f3f", 0.0, 0, 640.0, 480.0, 1.0, 1.0, 1, 0.01,
                       0.0, math.sin(half), 0.0, math.cos(half), 0.0, 0.0, 0.0, 0.0, 0.0, 600.0)
    points = np.zeros((70, 3))
    points[66:68, 2] = -10.0
    features = 0.5 * np.sin(k / RATE * 3 + np.arange(14))
    rest = np.concatenate([np.full(68, 0.9), np.zeros(136), points.reshape(-1), features])
    return head + rest.astype("=f4").tobytes()


def _through_source(kind: str, make: Callable[[int], bytes], frames: int) -> tuple[float, float]:
    """Median and 95th percentile ms from a datagram sent to the motors mapped from it."""
    source = open_source(f"{kind}:127.0.0.1:0")
    host, port = source.meta["address"].rsplit(":", 1)
    mapper = build_mapper(source, target_neutral=load_face("classic").neutral())
    datagrams = [make(k) for k in range(frames)]
    sent: list[float] = []
    done: list[float] = []

    sender = threading.Thread(target=_send_paced, args=(datagrams, (host, int(port)), sent), daemon=True)
    sender.start()
    for frame in islice(source.frames, frames):
        mapper.step_frame(frame)
        done.append(time.perf_counter())
    sender.join()
    source.close()
    return _spread(sent, done)


def _back_to_back(kind: str, make: Callable[[int], bytes], frames: int, batch: int = 40) -> float:
    """Median ms a datagram costs (read, parsed, mapped) when it is already waiting: batches sent
    at once, then read through the source and the mapper without a pause, so that the code runs
    warm, not woken after the 16 ms between a sender's frames."""
    source = open_source(f"{kind}:127.0.0.1:0")
    host, port = source.meta["address"].rsplit(":", 1)
    mapper = build_mapper(source, target_neutral=load_face("classic").neutral())
    per: list[float] = []
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sender:
        for first in range(0, frames, batch):
            count = min(batch, frames - first)
            for k in range(first, first + count):  # a batch fits the source's receive buffer
                sender.sendto(make(k), (host, int(port)))
            guard = threading.Timer(10.0, source.halt.set)  # a datagram lost would leave it waiting
            guard.start()
            start, done = time.perf_counter(), 0
            for frame in islice(source.frames, count):
                mapper.step_frame(frame)
                done += 1
            per.append((time.perf_counter() - start) / max(done, 1))
            guard.cancel()
            if done < count:
                break
    source.close()
    return round(float(np.median(per)) * 1000, 3)


def _through_socket(make: Callable[[int], bytes], frames: int) -> tuple[float, float]:
    """The floor: the same datagrams received by a plain blocking socket in a thread."""
    receiver = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    receiver.bind(("127.0.0.1", 0))
    receiver.settimeout(5.0)
    done: list[float] = []

    def receive() -> None:
        for _ in range(frames):
            try:
                receiver.recv(65536)
            except TimeoutError:
                return
            done.append(time.perf_counter())

    thread = threading.Thread(target=receive, daemon=True)
    thread.start()
    sent: list[float] = []
    _send_paced([make(k) for k in range(frames)], receiver.getsockname(), sent)
    thread.join()
    receiver.close()
    return _spread(sent[:len(done)], done)


def _through_python_osc(frames: int) -> tuple[float, float]:
    """The peer: python-osc's threaded UDP server dispatching the same VMC bundles."""
    from pythonosc.dispatcher import Dispatcher
    from pythonosc.osc_server import ThreadingOSCUDPServer

    done: list[float] = []
    dispatcher = Dispatcher()
    dispatcher.map("/VMC/Ext/Blend/Apply", lambda *_: done.append(time.perf_counter()))
    server = ThreadingOSCUDPServer(("127.0.0.1", 0), dispatcher)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    sent: list[float] = []
    host, port = server.server_address[:2]
    _send_paced([_vmc_bundle(k) for k in range(frames)], (str(host), int(port)), sent)
    deadline = time.perf_counter() + 5
    while len(done) < frames and time.perf_counter() < deadline:
        time.sleep(0.01)
    server.shutdown()
    server.server_close()
    return _spread(sent[:len(done)], done)


def _send_paced(datagrams: list[bytes], address: tuple[str, int], sent: list[float]) -> None:
    """Send ``datagrams`` to ``address`` at :data:`RATE`, noting in ``sent`` when each left."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        start = time.perf_counter()
        for k, datagram in enumerate(datagrams):
            time.sleep(max(0.0, start + k / RATE - time.perf_counter()))
            sent.append(time.perf_counter())
            sock.sendto(datagram, address)


def _spread(sent: list[float], done: list[float]) -> tuple[float, float]:
    delays = (np.array(done[:len(sent)]) - np.array(sent[:len(done)])) * 1000
    return round(float(np.median(delays)), 3), round(float(np.percentile(delays, 95)), 3)
