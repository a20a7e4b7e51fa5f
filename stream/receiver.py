"""The motor stream's receiving socket: datagrams in, a face to show at any moment out.

A daemon thread reads the UDP socket (packets larger than the format allows are cut short by
the read and dropped as oversized), checks and decodes them (:class:`~stream.reader.StreamReader`)
and hands the frames to the jitter buffer (:class:`~stream.playout.Playout`). It acknowledges
what it holds when the reader says one is due (once a second while nothing is lost, after every
packet while loss goes on: the sender then predicts from frames known to be here, so a lost
packet costs only its own frames); when a packet has waited for a missing reference it asks the
sender for a keyframe, at most once per ``request_interval``.
The loop that draws the face calls :meth:`StreamReceiver.values_at`. Memory stays bounded
whatever arrives: one datagram is read at a time, out-of-order packets wait in a bounded table,
and the jitter buffer forgets what is behind it.
"""

from __future__ import annotations

import math
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from stream.framing import MAX_PACKET, StreamKey, peek_stream, stream_key
from stream.health import REFUSED_SECONDS, Trouble
from stream.packets import key_request
from stream.playout import Playout
from stream.reader import StreamReader
from toon.motors import N_MOTORS


@dataclass
class Lane:
    """One performer's stream at a receiver: its reader, its jitter buffer, where its packets
    come from, when the last one came and when a keyframe was last asked of it."""

    reader: StreamReader
    playout: Playout
    sender: tuple[str, int] | None = None
    arrived: float = -math.inf
    last_request: float = -math.inf
    unanswered: int = 0  # keyframe requests made while no packet of the stream has opened


#: A stream none of whose packets opens (another key's, say) is asked for keyframes less and less
#: often: the interval doubles with each request up to this many seconds, and is back to the
#: receiver's own once a packet opens (a wrong key turned the back channel into a flood).
MAX_REQUEST_BACKOFF = 2.0


def request_interval(base: float, unanswered: int) -> float:
    """Seconds before the next keyframe request: ``base``, doubled for each request made while no
    packet of the stream opened (up to :data:`MAX_REQUEST_BACKOFF`)."""
    return min(base * 2.0 ** unanswered, max(base, MAX_REQUEST_BACKOFF))


class StreamReceiver:
    """Listen on ``address`` (``(host, port)``; port 0 picks one) for motor streams.

    Each stream id (:mod:`stream.wire`) is a performer with its own reader and jitter buffer
    (:class:`Lane`): the first to arrive plays through ``playout``, and, where ``more`` makes
    jitter buffers, up to ``max_streams`` more are kept; packets of others are counted and
    dropped (:attr:`other_streams`).

    Parameters
    ----------
    playout : Playout
    key : bytes, optional
        Shared secret: only packets sealed with it are read.
    clock : callable
        Seconds; ``time.perf_counter`` (the same clock a sender on this machine stamps with).
    more : callable, optional
        Makes the jitter buffer of each further performer (None: one performer only).
    max_streams : int
        Performers at most.
    say : callable, optional
        Takes a warning when packets come and none opens for
        :data:`~stream.health.REFUSED_SECONDS` (another key, or a key at one end only), and a
        note when they open again.
    link : WebSocketLink, optional
        Receive from a room server (:mod:`stream.websocket`) instead of a UDP socket at ``address``.
    newcomer_seconds : float
        Without a key, a new performer is taken at most once in this many seconds (its packets
        before then are counted in :attr:`refused_newcomers`): anyone on the path can make
        packets under fresh stream ids, and they must not crowd the stage. With a key, only
        the key's holders can.
    """

    def __init__(self, address: tuple[str, int], playout: Playout, key: bytes | StreamKey | None = None,
                 clock: Callable[[], float] = time.perf_counter, request_interval: float = 0.05,
                 more: Callable[[], Playout] | None = None, max_streams: int = 16,
                 say: Callable[[str], None] | None = None, newcomer_seconds: float = 1.0, link: Any = None) -> None:
        self.playout, self.clock, self.key = playout, clock, stream_key(key)
        self.reader = StreamReader(key)
        self.lanes: dict[int, Lane] = {}
        self._first = Lane(self.reader, self.playout)  # the first stream's, until one of its packets opens
        self._pending: dict[int, Lane] = {}  # newcomers' lanes none of whose packets has opened yet
        self.more, self.max_streams = more, max_streams
        self.other_streams = 0
        self.newcomer_seconds = newcomer_seconds
        self.refused_newcomers = 0
        self._last_newcomer = -math.inf
        self.refusing = Trouble(say or (lambda line: None), REFUSED_SECONDS)
        self.request_interval = request_interval
        self.requests = 0
        self.acks = 0
        if link is not None:  # a room server's WebSocket (stream.websocket.WebSocketLink) instead of UDP
            self.sock = link
        else:
            self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            try:
                self.sock.bind(address)
            except OSError:
                self.sock.close()
                raise
            self.sock.settimeout(0.1)
        self._lock = threading.Lock()
        self._shown: np.ndarray | None = None  # the row values_at gave last
        self._arrived = threading.Condition(self._lock)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)

    @property
    def address(self) -> tuple[str, int]:
        return self.sock.getsockname()

    def start(self) -> StreamReceiver:
        self._thread.start()
        return self

    def close(self) -> None:
        """Stop the thread and release the socket."""
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        self.sock.close()

    def __enter__(self) -> StreamReceiver:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def values_at(self, now: float | None = None) -> tuple[np.ndarray, str]:
        """The face to show now (see :meth:`Playout.values_at`): the 21 motors and the stream's
        parameters beyond them (:meth:`extra_shown` names them)."""
        with self._lock:
            self._clock_offsets()
            values, state = self.playout.values_at(self.clock() if now is None else now)
            self._shown = values
            return values, state

    def extra_shown(self) -> dict[str, float]:
        """The parameters beyond the 21 of what :meth:`values_at` gave last, by code (none for a
        stream of the 21, or before it came)."""
        with self._lock:
            codes = self.playout.codes
            if self._shown is None or len(self._shown) != N_MOTORS + len(codes):
                return {}
            return dict(zip(codes, self._shown[N_MOTORS:].tolist(), strict=True))

    def performers(self, now: float | None = None) -> list[tuple[int, np.ndarray, float, dict[str, float]]]:
        """Each performer's stream id, the face to show now ``(21,)``, the seconds since its last
        packet and its parameters beyond the 21 by code, in the order they first came."""
        with self._lock:
            self._clock_offsets()
            now = self.clock() if now is None else now
            out = []
            for stream, lane in self.lanes.items():
                row = lane.playout.values_at(now)[0]
                codes = lane.playout.codes if len(row) == N_MOTORS + len(lane.playout.codes) else ()
                out.append((stream, row[:N_MOTORS], now - lane.arrived,
                            dict(zip(codes, row[N_MOTORS:].tolist(), strict=True))))
            return out

    def _clock_offsets(self) -> None:
        """Each performer's playout told this clock less its sender's, where a room's link knows it
        (:meth:`stream.websocket.WebSocketLink.clock_offset`): its latency then counts from the
        capture whatever the machines' clocks."""
        offset_of = getattr(self.sock, "clock_offset", None)
        if offset_of is None:
            return
        for stream, lane in self.lanes.items():
            if (offset := offset_of(stream)) is not None:
                lane.playout.offset = offset

    def counters_by_stream(self) -> dict[int, dict]:
        """Each performer's counters (:func:`counters`), by stream id."""
        with self._lock:
            return {stream: _counters(lane.reader, lane.playout) for stream, lane in self.lanes.items()}

    def _lane(self, stream: int | None) -> Lane | None:
        """The lane of ``stream``, or a new one while there is room (kept by :meth:`feed` only once
        a packet of it reads well, so that junk cannot take a performer's place); the first
        performer's reader also counts what has no stream id at all."""
        if stream is None:
            return next(iter(self.lanes.values()), None) or self._first
        if stream in self.lanes:
            return self.lanes[stream]
        if not self.lanes:
            return self._first
        if self.more is not None and len(self.lanes) < self.max_streams:
            lane = self._pending.pop(stream, None) or Lane(StreamReader(self.key), self.more())
            self._pending[stream] = lane  # kept (the newest last) while it opens nothing: its requests back off
            while len(self._pending) > self.max_streams:
                del self._pending[next(iter(self._pending))]
            return lane
        self.other_streams += 1
        return None

    def feed(self, datagram: bytes, sender: tuple[str, int] | None = None) -> None:
        """Handle one datagram as if it had arrived now (the thread calls this for each)."""
        arrival = self.clock()
        with self._arrived:
            stream = peek_stream(datagram)
            lane = self._lane(stream)
            if lane is None:
                return
            before, refused = lane.reader.packets, _unopened(lane.reader)
            newcomer = stream is not None and stream not in self.lanes and bool(self.lanes)
            if newcomer and self.key is None and arrival - self._last_newcomer < self.newcomer_seconds:
                self.refused_newcomers += 1  # unkeyed: one new performer a newcomer_seconds at most
                return
            for frames in lane.reader.read(datagram, arrival):  # an oversized datagram is dropped here
                lane.playout.add(frames)
            if lane.reader.packets > before:
                lane.arrived, lane.sender = arrival, sender
                if stream is not None and stream not in self.lanes:
                    self.lanes[stream] = lane  # a newcomer, now that a packet of it read well
                    self._pending.pop(stream, None)
                    self._last_newcomer = arrival
                self.refusing.update(False, arrival, "", "packets open again: the stream flows")
            elif _unopened(lane.reader) > refused:
                self.refusing.update(True, arrival, self._refused_line, "")
            self._arrived.notify_all()
            unanswered = lane.unanswered if lane.reader.packets == 0 else 0
            wanted = lane.reader.want_keyframe and \
                arrival - lane.last_request >= request_interval(self.request_interval, unanswered)
            ack = lane.reader.take_ack(self.acks) if sender is not None else None
            if wanted and sender is not None:
                lane.last_request = arrival
                lane.unanswered = unanswered + 1 if lane.reader.packets == 0 else 0
        if ack is not None and sender is not None:
            self.acks += 1
            try:
                self.sock.sendto(ack, sender)
            except OSError:
                pass
        if wanted and sender is not None:
            self.requests += 1
            try:
                self.sock.sendto(key_request(self.requests, self.key, lane.reader.stream), sender)
            except OSError:
                pass  # the sender's side is gone; the keyframes it sends anyway will do

    def wait_for_packets(self, count: int, timeout: float) -> bool:
        """Wait until ``count`` valid packets have been read (True) or ``timeout`` seconds pass."""
        with self._arrived:
            return self._arrived.wait_for(lambda: self.reader.packets >= count, timeout)

    def wait_for_streams(self, count: int, timeout: float, packets: int = 1) -> bool:
        """Wait until ``count`` performers have each had ``packets`` packets read (True) or
        ``timeout`` seconds pass."""
        with self._arrived:
            return self._arrived.wait_for(
                lambda: sum(lane.reader.packets >= packets for lane in self.lanes.values()) >= count, timeout)

    def _serve(self) -> None:
        while not self._stop.is_set():
            try:
                datagram, sender = self.sock.recvfrom(MAX_PACKET + 1)
            except TimeoutError:
                continue
            except OSError:
                if self._stop.wait(0.05):  # (a closed link says so at once: no busy loop)
                    return
                continue
            self.feed(datagram, sender)

    def diagnosis(self) -> str | None:
        """A line for the user when nothing could be shown though packets came (None otherwise)."""
        with self._lock:
            tagged = self.reader.dropped.get("tag", 0)
            if self.reader.packets or not tagged:
                return None
        return _refusal(tagged, self.key is not None, "every packet")

    def _refused_line(self) -> str:
        """The live warning: packets come and none opens (called holding the lock)."""
        return _refusal(self.reader.dropped.get("tag", 0), self.key is not None,
                        f"packets have not opened for {self.refusing.after:g} s")

    def summary(self) -> dict:
        """Counters for ``--stats``: packets, bytes, lost, dropped by reason and frames by state
        over every performer, and the first performer's delay and error of concealment where the
        truth came too late; with several performers, each one's under ``performers`` by stream
        id too, and the streams turned away for want of room (``other_streams``) or, without a
        key, for coming too soon after another (``refused_newcomers``)."""
        with self._lock:
            out = {**_counters(self.reader, self.playout), "keyframe_requests": self.requests, "acks": self.acks}
            others = [lane for lane in self.lanes.values() if lane.reader is not self.reader]
            for lane in others:
                more = _counters(lane.reader, lane.playout)
                for name in ("packets", "bytes", "lost"):
                    out[name] += more[name]
                for group in ("dropped", "frames"):
                    for reason, count in more[group].items():
                        out[group][reason] = out[group].get(reason, 0) + count
            if self.refused_newcomers:
                out["refused_newcomers"] = self.refused_newcomers
            if len(self.lanes) > 1 or self.other_streams:
                out["performers"] = {stream: _counters(lane.reader, lane.playout)
                                     for stream, lane in self.lanes.items()}
                out["other_streams"] = self.other_streams
            return out


def readout(counters: dict, diagnosis: str | None = None) -> dict:
    """What a viewer shows of a stream's health, from its counters (:meth:`StreamReceiver.summary`,
    or one performer's there): packets, the share lost (%), the share of shown frames concealed or
    recovering (%), the median delay from capture to showing (ms), the frames by state, the
    packets dropped by reason, and the receiver's ``diagnosis`` where it has one."""
    frames = counters["frames"]
    shown = sum(frames.values())
    packets, lost = counters["packets"], counters["lost"]
    return {"packets": packets, "loss_pct": round(100 * lost / (packets + lost), 2) if packets + lost else 0.0,
            "concealed_pct": round(100 * (frames["concealed"] + frames["recovering"]) / shown, 2) if shown else 0.0,
            "latency_ms": counters["latency_ms"], "frames": frames, "dropped": counters["dropped"],
            "diagnosis": diagnosis}


def _unopened(reader: StreamReader) -> int:
    """Packets a reader could not open: not sealed with its key (or its check failed), or short
    headers with no packet read to restore them against (another key's, once its long ones failed)."""
    return reader.dropped.get("tag", 0) + reader.dropped.get("unanchored", 0)


def _refusal(count: int, keyed: bool, what: str) -> str:
    if not keyed:
        return (f"{what} ({count}) came sealed with a key and this end has none: give the sender's "
                "--key-file (or TOONFACE_STREAM_KEY)")
    return (f"{what} ({count}) failed authentication: this end's key is not the sender's (check --key-file or "
            "TOONFACE_STREAM_KEY at both ends), or the sender sends without one")


def _counters(reader: StreamReader, playout: Playout) -> dict:
    """One stream's counters (see :meth:`StreamReceiver.summary`)."""
    stats = playout.stats
    return {"packets": reader.packets, "bytes": reader.bytes, "lost": reader.lost, "dropped": dict(reader.dropped),
            "frames": {"live": stats.live, "concealed": stats.concealed, "recovering": stats.recovering,
                       "waiting": stats.waiting},
            "latency_ms": round(float(np.median(stats.latencies)) * 1000, 1) if stats.latencies else None,
            "concealment_rms": (round(stats.late_error_sum / stats.late_frames, 4) if stats.late_frames else None)}
