"""The motor stream's sending socket: a motor sink whose frames leave over UDP.

Each frame written is packed (:class:`~stream.packets.StreamWriter`, stamped with its capture
time on this machine's clock) and, when a packet is full, sent to the receiver (or a relay).
Acknowledgements and keyframe requests arriving on the same socket are taken before each frame. A send that
fails (nobody listening yet, a full buffer) is not an error: the stream goes on.
"""

from __future__ import annotations

import socket
import time
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from stream.framing import UDP_IP_HEADER, WEBSOCKET_TCP_HEADER
from stream.health import SILENT_SECONDS, Trouble
from stream.packets import StreamWriter, is_key_request, read_ack
from toon.motors import extra_rest


class StreamSender:
    """Send motor frames to ``target`` (``(host, port)``); a :class:`toon.recording.MotorSink`.

    Parameters
    ----------
    target : tuple
        ``(host, port)`` of the receiver or relay.
    writer : StreamWriter
        Packs the frames (its rate, frames per packet, keyframe interval and key).
    clock : callable
        Stamps frames whose capture time is not given, and times the silence below.
    say : callable, optional
        Takes a warning when nothing has answered for :data:`~stream.health.SILENT_SECONDS`
        (nobody receives, or the receiver's key differs), and a note when answers come again.
    link : WebSocketLink, optional
        Send through a room server (:mod:`stream.websocket`) instead of a UDP socket.
    """

    def __init__(self, target: tuple[str, int], writer: StreamWriter,
                 clock: Callable[[], float] = time.perf_counter, say: Callable[[str], None] | None = None,
                 link: Any = None) -> None:
        self.target, self.writer, self.clock = target, writer, clock
        self.key_requests = 0
        self.acks = 0
        self.silence = Trouble(say or (lambda line: None), SILENT_SECONDS)
        host, port = target
        where = f"{host}:{port}" if link is None else str(host)  # a room: its address alone
        self._silent = (f"nobody is receiving on {where}, or the key differs: no answer for "
                        f"{SILENT_SECONDS:g} s (frames are still sent)",
                        f"the receiver on {where} answers: the stream flows")  # said at most once each
        #: Bytes a packet costs on the wire beyond itself: a UDP datagram's, or a WebSocket message's over TCP.
        self.overhead = UDP_IP_HEADER if link is None else WEBSOCKET_TCP_HEADER
        if link is not None:  # a room server's WebSocket (stream.websocket.WebSocketLink) instead of UDP
            self.sock = link
        else:
            self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            self.sock.setblocking(False)

    def write(self, t: float, values: np.ndarray, captured: float | None = None,
              confidence: np.ndarray | None = None, extra: Mapping[str, float] | None = None) -> None:
        """Pack one frame ``(21,)`` and its parameters beyond the 21 (``extra``, by code); send
        the packet it completes. The stream carries the parameters its first frame had (the
        writer's ``codes`` where they were given): one a later frame lacks goes at its standard
        neutral (0.5 for a parameter of the performer's own), one it adds is not sent."""
        heard = self._take_requests()
        self.silence.update(not heard, self.clock(), *self._silent)
        w = self.writer
        if extra and not w.codes and not w.started:
            w.codes = tuple(extra)  # the stream's parameters, from its first frame
        if w.codes:
            given = extra or {}
            row = [given.get(c, extra_rest(c)) for c in w.codes]
            values = np.concatenate([np.asarray(values, dtype=float), row])
        datagram = self.writer.push(values, self.clock() if captured is None else captured)
        if datagram is not None:
            self._send(datagram)

    def close(self) -> None:
        """Send what is pending and release the socket."""
        if self.sock.fileno() < 0:
            return
        try:
            datagram = self.writer.flush()
            if datagram is not None:
                self._send(datagram)
        finally:
            self.sock.close()

    def abort(self) -> None:
        """Frames sent cannot be taken back: the same as :meth:`close`."""
        self.close()

    def rates(self, frames: int) -> dict:
        """Packets and payload, stream and wire bit rates (kbit/s) over ``frames`` frames sent."""
        w = self.writer
        seconds = max(frames / w.rate, 1e-9)
        return {"frames": frames, "packets": w.packets, "keyframes": w.keyframes, "key_requests": self.key_requests,
                "acks": self.acks, "acked_packets": w.acked_packets, "repeated_frames": w.repeated_frames,
                "payload_kbps": round(w.payload_bytes * 8 / seconds / 1000, 3),
                "stream_kbps": round(w.packet_bytes * 8 / seconds / 1000, 3),
                "wire_kbps": round((w.packet_bytes + self.overhead * w.packets) * 8 / seconds / 1000, 3)}

    def _send(self, datagram: bytes) -> None:
        try:
            self.sock.sendto(datagram, self.target)
        except OSError:
            pass  # nobody listening (ICMP refused) or a full buffer: the stream goes on

    def _take_requests(self) -> int:
        """Take the acknowledgements and keyframe requests waiting; returns how many there were."""
        heard = 0
        while True:
            try:
                data = self.sock.recv(256)
            except (BlockingIOError, OSError):
                return heard
            acked = read_ack(data, self.writer.key, self.writer.frame)
            if acked is not None:
                self.writer.acknowledge(*acked)
                self.acks += 1
                heard += 1
            elif is_key_request(data, self.writer.key):
                self.writer.request_keyframe()
                self.key_requests += 1
                heard += 1
