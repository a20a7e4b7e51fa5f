"""The room's fan-out: one performer at 60 Hz and ``VIEWERS`` WebSocket viewers on this machine's
loopback, through one server process (``toonface room``), and through two sharing one port and
their rooms through a NATS server (``toonface room --workers 2 --pubsub``).

The viewers are written here on bare asyncio sockets (the handshake, then frames read straight
from the stream, a pong for each ping, a reply now and then as a real viewer's acknowledgements
are), because aiohttp's client costs some 25 us a message and a thousand of them at 60 Hz would
take this 2-core machine's whole time from the servers they measure. Each packet carries its
send time after the stream's own bytes (the server reads only its stream id).

``room.fanout_p95_ms`` and ``room.fanout_lost``
    One server process (issue 63): the 95th percentile of every viewer's delay from the
    performer's send (goal 50), and the packets any viewer missed (goal 0). The detail has the
    process's CPU per viewer.
``room.shared_fanout_p95_ms`` and ``room.shared_fanout_lost``
    The same through two processes and NATS (issue 45's setting); none where nats-server is
    missing.
``room.server_rss_mb_per_h``
    The two servers' resident memory (every process of theirs) over that run after its first
    :data:`WARM_SECONDS`, as a straight line's slope in MB an hour (goal: flat, under 10).
"""

from __future__ import annotations

import asyncio
import base64
import os
import secrets
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.core import Figure

STAMP = struct.Struct("<d")
VIEWERS = 1000
RATE = 60.0
#: Memory is measured after this long (the first seconds' growth is the servers warming up).
WARM_SECONDS = 5.0


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the fan-out's figures (the shared ones only where nats-server is)."""
    viewers = 300 if quick else VIEWERS
    with tempfile.TemporaryDirectory() as folder, _servers(Path(folder), None) as (port, tokens, pids):
        seconds = 10.0 if quick else 60.0
        delays, lost, _, cpu = asyncio.run(_measure(port, tokens, viewers, seconds, pids))
    figures = _fanout("room.fanout", delays, lost, cpu, viewers, seconds, 1)
    nats = shutil.which("nats-server") or shutil.which("nats-server", path="/usr/sbin:/usr/local/sbin")
    if nats is None:
        print("room: nats-server is missing (make test installs it): no shared fan-out figures", file=sys.stderr)
        return figures
    seconds = 20.0 if quick else 300.0  # (issue 45: memory flat over five minutes)
    with tempfile.TemporaryDirectory() as folder, _nats(nats) as url, \
            _servers(Path(folder), url) as (port, tokens, pids):
        delays, lost, rss, cpu = asyncio.run(_measure(port, tokens, viewers, seconds, pids))
    rss = [(t, m) for t, m in rss if t >= WARM_SECONDS]  # (the first packets' work grows it once)
    hours = np.array([t for t, _ in rss]) / 3600
    megabytes = np.array([m for _, m in rss])
    slope = float(np.polyfit(hours, megabytes, 1)[0]) if len(rss) > 2 else float("nan")
    return [*figures, *_fanout("room.shared_fanout", delays, lost, cpu, viewers, seconds, 2),
            Figure("room.server_rss_mb_per_h", slope, "MB/h", 10.0, False,
                   {"first_mb": round(float(megabytes[0]), 1), "last_mb": round(float(megabytes[-1]), 1),
                    "samples": len(rss), "seconds": seconds, "server_processes": 2})]


def _fanout(name: str, delays: list[np.ndarray], lost: int, cpu: float, viewers: int, seconds: float,
            processes: int) -> list[Figure]:
    every = np.concatenate(delays) if delays else np.zeros(1)
    detail = {"viewers": viewers, "server_processes": processes, "pubsub": "nats" if processes > 1 else None,
              "seconds": seconds, "rate_hz": RATE,
              "cpu_us_per_viewer_packet": round(cpu * 1e6 / max(1, viewers * seconds * RATE), 2),
              "server_cpu_share_of_a_core": round(cpu / seconds, 3)}
    return [Figure(f"{name}_p95_ms", float(np.percentile(every, 95)), "ms", 50.0, False,
                   {**detail, "p50_ms": round(float(np.percentile(every, 50)), 2)}),
            Figure(f"{name}_lost", float(lost), "packets", 0.0, False, detail)]


class _nats:
    """nats-server on a free loopback port, for the run, asking its clients for a token made for
    it (as the telepresence tutorial starts it); its address with the token."""

    def __init__(self, binary: str) -> None:
        self.binary, self.port, self.token = binary, _free_port(), secrets.token_urlsafe(18)

    def __enter__(self) -> str:
        self.process = subprocess.Popen([self.binary, "-a", "127.0.0.1", "-p", str(self.port), "--auth", self.token],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _wait_for_port(self.port, self.process)
        return f"nats://{self.token}@127.0.0.1:{self.port}"

    def __exit__(self, *exc: object) -> None:
        self.process.terminate()
        self.process.wait(10)


class _servers:
    """``toonface room`` on a free port, one process, or two sharing through ``url`` (``--workers 2
    --pubsub URL``); yields the port, the tokens and the server processes' ids."""

    def __init__(self, folder: Path, url: str | None) -> None:
        self.folder, self.url, self.port = folder, url, _free_port()

    def __enter__(self) -> tuple[int, tuple[str, str], list[int]]:
        command = [sys.executable, "-m", "toonface", "room", "--listen", f"127.0.0.1:{self.port}", "--room", "bench",
                   "--tokens", str(self.folder / "rooms.toml"), "--max-viewers", "5000",
                   *(["--workers", "2", "--pubsub", self.url] if self.url else [])]
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        assert self.process.stdout is not None
        lines = [self.process.stdout.readline() for _ in range(3)]
        if "room server on" not in lines[0]:
            raise RuntimeError(f"the room server did not start: {lines[0]}")
        perform = lines[1].rsplit("--token ", 1)[1].strip()
        watch = lines[2].rsplit("--token ", 1)[1].strip()
        children = Path(f"/proc/{self.process.pid}/task/{self.process.pid}/children")
        pids = [self.process.pid, *(int(p) for p in children.read_text().split())] if children.exists() else [
            self.process.pid]
        return self.port, (perform, watch), pids

    def __exit__(self, *exc: object) -> None:
        self.process.send_signal(signal.SIGTERM)
        try:
            self.process.wait(15)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        if self.process.stdout is not None:
            self.process.stdout.close()


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_for_port(port: int, process: subprocess.Popen) -> None:
    deadline = time.monotonic() + 10
    while True:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            if process.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError("a server did not start") from None
            time.sleep(0.02)


class _Viewer(asyncio.Protocol):
    """A bare WebSocket viewer: after the handshake, each frame's send time is read from its end."""

    def __init__(self, key: bytes) -> None:
        self.buffer = b""
        self.upgraded = asyncio.get_running_loop().create_future()
        self.delays: list[float] = []
        self.transport: asyncio.Transport | None = None
        self.reply = key  # a keyframe request, sent now and then as a viewer's replies are

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.transport = transport

    def data_received(self, data: bytes) -> None:
        now = time.perf_counter()
        self.buffer += data
        if not self.upgraded.done():
            end = self.buffer.find(b"\r\n\r\n")
            if end < 0:
                return
            head, self.buffer = self.buffer[:end], self.buffer[end + 4:]
            if b" 101 " not in head.split(b"\r\n", 1)[0]:
                self.upgraded.set_exception(ConnectionError(head.split(b"\r\n", 1)[0].decode()))
                return
            self.upgraded.set_result(True)
        buffer, at = self.buffer, 0
        while len(buffer) - at >= 2:
            opcode, length = buffer[at] & 0x0F, buffer[at + 1] & 0x7F
            start = at + 2
            if length == 126:
                if len(buffer) - at < 4:
                    break
                length, start = int.from_bytes(buffer[at + 2:at + 4], "big"), at + 4
            if len(buffer) < start + length:
                break
            payload = buffer[start:start + length]
            if opcode == 0x2 and length >= STAMP.size:
                self.delays.append((now - STAMP.unpack_from(payload, length - STAMP.size)[0]) * 1000)
            elif opcode == 0x9:  # ping: a pong with the same payload
                self.send(0xA, payload)
            at = start + length
        self.buffer = buffer[at:]

    def send(self, opcode: int, payload: bytes) -> None:
        """A client's frame: masked, as RFC 6455 asks of clients."""
        mask = os.urandom(4)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        n = len(payload)
        head = bytes((0x80 | opcode, 0x80 | n)) if n < 126 else struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, n)
        if self.transport is not None and not self.transport.is_closing():
            self.transport.write(head + mask + masked)


async def _connect(port: int, token: str, role: str, reply: bytes) -> _Viewer:
    loop = asyncio.get_running_loop()
    _, viewer = await loop.create_connection(lambda: _Viewer(reply), "127.0.0.1", port)
    key = base64.b64encode(secrets.token_bytes(16)).decode()
    assert viewer.transport is not None
    viewer.transport.write((f"GET /r/bench/ws?role={role} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n"
                            f"Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                            f"Sec-WebSocket-Version: 13\r\nAuthorization: Bearer {token}\r\n\r\n").encode())
    await asyncio.wait_for(viewer.upgraded, 10)
    return viewer


def _rss_mb(pids: list[int]) -> float:
    total = 0
    for pid in pids:
        try:
            fields = Path(f"/proc/{pid}/statm").read_text().split()
            total += int(fields[1]) * os.sysconf("SC_PAGE_SIZE")
        except OSError:
            pass
    return total / 2**20


def _cpu_seconds(pids: list[int]) -> float:
    total = 0
    for pid in pids:
        try:
            fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
            total += int(fields[11]) + int(fields[12])  # utime, stime
        except OSError:
            pass
    return total / os.sysconf("SC_CLK_TCK")


async def _measure(port: int, tokens: tuple[str, str], viewers: int, seconds: float,
                   pids: list[int]) -> tuple[list[np.ndarray], int, list[tuple[float, float]], float]:
    from stream.packets import StreamWriter, key_request
    from toon import standard_neutral

    perform, watch = tokens
    request = key_request(1, None, 3)
    sockets = []
    for _ in range(viewers):
        sockets.append(await _connect(port, watch, "watch", request))
    performer = await _connect(port, perform, "perform", request)
    writer = StreamWriter(RATE, frames_per_packet=1, stream=3)
    rng = np.random.default_rng(0)
    count = int(seconds * RATE)
    rss: list[tuple[float, float]] = []
    cpu0 = _cpu_seconds(pids)
    start = time.perf_counter()
    for k in range(count):
        await asyncio.sleep(max(0.0, start + k / RATE - time.perf_counter()))
        values = np.clip(standard_neutral() + rng.normal(0, 0.02, 21), 0, 1)
        packet = writer.push(values, k / RATE) or b""
        performer.send(0x2, packet + STAMP.pack(time.perf_counter()))
        if k % int(RATE) == 0:
            rss.append((time.perf_counter() - start, _rss_mb(pids)))
        if k % int(20 * RATE) == int(RATE):  # a reply from each viewer every 20 s (the server's idle timeout is 60)
            for viewer in sockets:
                viewer.send(0x2, viewer.reply)
    await asyncio.sleep(1.0)  # the last packets' way
    cpu = _cpu_seconds(pids) - cpu0
    for viewer in (*sockets, performer):
        if viewer.transport is not None:
            viewer.transport.close()
    delays = [np.array(v.delays) for v in sockets]
    lost = sum(max(0, count - len(d)) for d in delays)
    return delays, lost, rss, cpu
