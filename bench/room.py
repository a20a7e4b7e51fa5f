"""``room``: the room server on loopback, beside a direct UDP send (first figures of issue 45).

A performer sends the stream's packets (the synthetic performer's motors, coded as ``send``
codes them) at 60 Hz; each packet carries its send time, taken on this machine's clock.

``room.added_p95_ms``
    One viewer: the 95th percentile of the delay from the performer's send to the viewer's
    receipt through one room server (WebSocket both legs), less the same through a UDP socket
    pair (goal 20).
``room.fanout_p95_ms``, ``room.fanout_lost``, ``room.shared_fanout_*`` and ``room.server_rss_mb_per_h``
    A thousand viewers (``--quick``: 300) through one server process, and through two and NATS:
    :mod:`bench.room_shared`.
``room.wire_both_kbps``
    One viewer at 30 fps, 2 frames a packet: what its connection costs both ways, WebSocket
    framing and TCP/IPv4 headers included (40 bytes a segment, one segment a message, and a
    bare TCP acknowledgement for every second segment received), acknowledgements once a second
    (no goal: the issue asks for the figure).
``room.browser_kbps`` and ``room.page_frame_p95_ms``
    The viewer page that draws the faces itself (``?draw=page``), in headless Chromium:
    :mod:`bench.room_page`.
``room.performer_page_kbps``
    What the performer page uploads, in headless Chromium with a fake camera: :mod:`bench.room_performer`.
``room.drawn_page_kbps`` and ``room.stage_ms``
    The drawn viewer page (``/r/ROOM``): what it is sent at 30 fps, the stage's deflated changes of
    the drawing (:mod:`toonface.room.stage`), WebSocket and TCP/IPv4 headers included, median
    over two faces (classic, cat) and two motions (a talking mouth alone; every motor moving);
    and the server's time to decode and draw one frame of one performer. No goal: the price of
    a page that needs no rig of its own, beside ``room.browser_kbps`` for the page that has one.
"""

from __future__ import annotations

import asyncio
import socket
import struct
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

import aiohttp
import numpy as np

from bench.core import Figure
from stream.packets import StreamWriter
from toon import standard_neutral
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

TOKENS = {"bench": ("perform-bench-token-0123", "watch-bench-token-0123")}
TCP_IP = 40  # bytes of TCP and IPv4 headers a segment
STAMP = struct.Struct("<d")


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``room.*`` figures."""
    from bench import room_page, room_performer, room_shared

    packets = 150 if quick else 600
    with _server() as base:
        through = asyncio.run(_fan_out(base, 1, packets))[0]
        direct = _udp(packets)
    added = float(np.percentile(through, 95) - np.percentile(direct, 95))
    figures = [Figure("room.added_p95_ms", added, "ms", 20.0, False,
                      {"through_p95_ms": round(float(np.percentile(through, 95)), 3),
                       "direct_udp_p95_ms": round(float(np.percentile(direct, 95)), 3), "packets": packets}),
               *room_shared.run(quick), _wire(), *_browser(quick),
               *room_page.run(quick), *room_performer.run(quick)]
    return figures


@contextmanager
def _server() -> Iterator[str]:
    """A room server on a free loopback port; yields its room's socket address."""
    with in_thread(Rooms(TOKENS, rate_limit=1000.0)) as base:
        yield f"{base}/r/bench/ws"


def _packets(count: int, rate: float = 60.0) -> list[bytes]:
    """``count`` packets of a still-ish face as the sender codes them (one frame each)."""
    writer = StreamWriter(rate, frames_per_packet=1, stream=3)
    rng = np.random.default_rng(0)
    out = []
    for k in range(count):
        values = np.clip(standard_neutral() + rng.normal(0, 0.02, 21), 0, 1)
        out.append(writer.push(values, k / rate) or b"")
    return out


async def _fan_out(base: str, viewers: int, count: int) -> list[np.ndarray]:
    """Each viewer's delays (ms) for ``count`` packets a performer sends at 60 Hz through the room."""
    packets = _packets(count)
    perform, watch = TOKENS["bench"]
    delays: list[list[float]] = [[] for _ in range(viewers)]
    async with aiohttp.ClientSession(connector=aiohttp.TCPConnector(limit=0)) as session:  # (100 by default)
        sockets = [await session.ws_connect(f"{base}?role=watch", headers={"Authorization": f"Bearer {watch}"})
                   for _ in range(viewers)]

        async def listen(index: int, ws: aiohttp.ClientWebSocketResponse) -> None:
            while len(delays[index]) < count:
                try:
                    message = await ws.receive(timeout=2.0)
                except TimeoutError:
                    return
                if message.type != aiohttp.WSMsgType.BINARY:
                    return
                sent = STAMP.unpack_from(message.data, len(message.data) - STAMP.size)[0]
                delays[index].append((time.perf_counter() - sent) * 1000)

        listeners = [asyncio.create_task(listen(i, ws)) for i, ws in enumerate(sockets)]
        async with session.ws_connect(f"{base}?role=perform", headers={"Authorization": f"Bearer {perform}"}) as ws:
            start = time.perf_counter()
            for k, packet in enumerate(packets):  # the send time rides after the packet (the server reads only its id)
                await asyncio.sleep(max(0.0, start + k / 60.0 - time.perf_counter()))
                await ws.send_bytes(packet + STAMP.pack(time.perf_counter()))
            await asyncio.gather(*listeners)
        for viewer in sockets:
            await viewer.close()
    return [np.array(d) for d in delays]


def _udp(count: int) -> np.ndarray:
    """The same packets through a UDP socket pair on loopback: delays (ms)."""
    packets = _packets(count)
    receiver = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    receiver.bind(("127.0.0.1", 0))
    receiver.settimeout(2.0)
    sender = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    delays: list[float] = []

    def listen() -> None:
        while len(delays) < count:
            try:
                data = receiver.recv(4096)
            except TimeoutError:
                return
            delays.append((time.perf_counter() - STAMP.unpack_from(data, len(data) - STAMP.size)[0]) * 1000)

    thread = threading.Thread(target=listen, daemon=True)
    thread.start()
    start = time.perf_counter()
    for k, packet in enumerate(packets):
        time.sleep(max(0.0, start + k / 60.0 - time.perf_counter()))
        sender.sendto(packet + STAMP.pack(time.perf_counter()), receiver.getsockname())
    thread.join(5)
    sender.close()
    receiver.close()
    return np.array(delays)


def _wire() -> Figure:
    """``room.wire_both_kbps`` from a 30 fps stream's packets and one acknowledgement a second."""
    from stream.reader import StreamReader

    seconds, rate = 30.0, 30.0
    writer, reader = StreamWriter(rate, first_sequence=0), StreamReader()
    rng = np.random.default_rng(1)
    down = up = segments_down = 0
    for k in range(int(seconds * rate)):
        values = np.clip(standard_neutral() + 0.05 * np.sin(k / 20 + np.arange(21)) + rng.normal(0, 0.003, 21), 0, 1)
        packet = writer.push(values, k / rate)
        if packet is None:
            continue
        down += len(packet) + 2 + TCP_IP  # a server's frame: 2 bytes of WebSocket header, unmasked
        segments_down += 1
        reader.read(packet, k / rate)
        if (ack := reader.take_ack()) is not None:
            up += len(ack) + 6 + TCP_IP  # a client's frame: 2 bytes of header and a 4-byte mask
    up += (segments_down // 2) * TCP_IP  # bare TCP acknowledgements of what came down
    kbps = (down + up) * 8 / seconds / 1000
    return Figure("room.wire_both_kbps", kbps, "kbit/s", None, False,
                  {"down_kbps": round(down * 8 / seconds / 1000, 3), "up_kbps": round(up * 8 / seconds / 1000, 3),
                   "rate_hz": rate, "frames_per_packet": 2, "estimate": "one TCP segment a message"})


def _browser(quick: bool) -> list[Figure]:
    """``room.drawn_page_kbps`` and ``room.stage_ms`` (see the module docstring)."""
    from toon import MOTOR_CODES, load_face
    from toonface.room.stage import Stage, packed

    rate, seconds = 30.0, 3.0 if quick else 10.0
    mouth = [MOTOR_CODES.index(code) for code in ("MB", "MLH", "MRH", "MLV", "MRV")]
    kbps: dict[str, float] = {}
    took: list[float] = []
    clock = [0.0]
    for face in ("classic", "cat"):
        for motion, moving in (("talking", mouth), ("everything", list(range(21)))):
            stage = Stage(load_face(face), lambda *_: None, clock=lambda: clock[0])
            writer = StreamWriter(rate, stream=5)
            sent = 0
            for k in range(int(seconds * rate)):
                clock[0] = k / rate
                values = standard_neutral().copy()
                values[moving] = 0.5 + 0.4 * np.sin(2 * np.pi * (0.7 + 0.3 * np.arange(len(moving))) * k / rate)
                packet = writer.push(np.clip(values, 0, 1), k / rate)
                start = time.perf_counter()
                if packet is not None:
                    stage.feed(packet, 5)
                message = packed(stage.frame()[0])
                took.append((time.perf_counter() - start) * 1000)
                sent += len(message) + 4 + TCP_IP  # a server's frame: 4 bytes of header past 125 bytes
            stage.close()
            kbps[f"{face}_{motion}"] = round(sent * 8 / seconds / 1000, 1)
    return [Figure("room.drawn_page_kbps", float(np.median(list(kbps.values()))), "kbit/s", None, False,
                   {**kbps, "fps": rate}),
            Figure("room.stage_ms", float(np.median(took)), "ms", None, False,
                   {"p95_ms": round(float(np.percentile(took, 95)), 2), "per": "performer frame"})]
