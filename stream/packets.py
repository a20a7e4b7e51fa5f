"""Both ends of the motor stream's packet layer: :class:`StreamWriter` (frames in, datagrams
out) and :class:`StreamReader` (datagrams in, checked, de-duplicated, re-ordered and decoded
frames out). The format is :mod:`stream.wire`'s; the sockets are the caller's."""

from __future__ import annotations

import secrets
from collections import Counter, deque
from dataclasses import dataclass

import numpy as np

from stream.wire import (
    ACK,
    DEFAULT_STEPS,
    KEY_REQUEST,
    KEYFRAME,
    MAX_FRAMES,
    Header,
    Models,
    WireError,
    bridge,
    decode_frames,
    encode_frames,
    open_packet,
    quantise,
    seal,
)
from toon import N_MOTORS

WRAP = 1 << 32
#: Packets this far behind the newest are too old to be anything but a replay.
REPLAY_WINDOW = 64
#: Frames each end keeps to predict from: a reference lies at most this far back (the header's
#: reference is one byte).
KEEP = 255
#: Acknowledgements are relied on while one has come within this many seconds of stream.
ACK_SECONDS = 0.5


class FrameStore:
    """The last :data:`KEEP` frames one end holds, by frame index (u32, wraps), each with its
    *depth*: how many frames of its chain come before it (0 for a keyframe's first, at most 2),
    so that both ends cut a history at the keyframe its chain began with."""

    def __init__(self) -> None:
        self._rows: dict[int, tuple[np.ndarray, int]] = {}
        self._order: deque[int] = deque()

    def put(self, index: int, levels: np.ndarray, depth: int) -> None:
        if index not in self._rows:
            self._order.append(index)
        self._rows[index] = (levels, min(depth, 2))
        while len(self._order) > KEEP:
            self._rows.pop(self._order.popleft(), None)

    def __contains__(self, index: int) -> bool:
        return index in self._rows

    def depth(self, index: int) -> int:
        return self._rows[index][1]

    def history(self, reference: int) -> np.ndarray | None:
        """The reference frame and the (up to 2) frames of its chain before it, ``(h, 21)``
        oldest first; None if any is not held."""
        if reference not in self._rows:
            return None
        wanted = [(reference - k) % WRAP for k in range(self._rows[reference][1], -1, -1)]
        if any(w not in self._rows for w in wanted):
            return None
        return np.array([self._rows[w][0] for w in wanted])


class StreamWriter:
    """Turn motor frames into packets of ``frames_per_packet`` frames.

    While the receiver acknowledges (:meth:`acknowledge`), each packet is predicted from the
    newest frame it acknowledged, so a lost packet costs only its own frames; without
    acknowledgements each packet continues from the one before and a keyframe comes at least
    every ``key_seconds`` (see :mod:`stream.wire`).

    Parameters
    ----------
    rate : float
        Frames per second.
    frames_per_packet : int
        1..32; more frames per packet means fewer headers and more delay.
    key_seconds : float
        Without acknowledgements, a packet starts with a keyframe at least this often.
    steps : int
        Quantisation steps (see :mod:`stream.wire`).
    key : bytes, optional
        Shared secret: packets carry an HMAC instead of a CRC.
    first_sequence : int, optional
        The first packet's number (random by default, so a restarted sender is not a replay).
    """

    def __init__(self, rate: float, frames_per_packet: int = 2, key_seconds: float = 0.5, steps: int = DEFAULT_STEPS,
                 key: bytes | None = None, first_sequence: int | None = None) -> None:
        if not 1 <= frames_per_packet <= MAX_FRAMES:
            raise ValueError(f"frames per packet must be 1..{MAX_FRAMES}, got {frames_per_packet}")
        if not 1 <= steps <= 255:
            raise ValueError(f"quantisation steps must be 1..255, got {steps}")
        if not 0 < rate < 655:
            raise ValueError(f"the frame rate must be between 0 and 655 Hz, got {rate:g}")
        self.rate, self.frames_per_packet, self.steps, self.key = rate, frames_per_packet, steps, key
        self.key_every = max(1, int(round(key_seconds * rate)))
        self.models = Models(steps)
        self.sequence = secrets.randbelow(WRAP) if first_sequence is None else first_sequence
        self.frame = 0
        self._since_key: int | None = None  # frames since the last keyframe; None: send one next
        self._sent = FrameStore()
        self._acked: int | None = None  # the newest frame the receiver holds with its history
        self._since_ack = np.inf  # frames sent since the last acknowledgement came
        self._pending: list[np.ndarray] = []
        self._first_time_us = 0
        self.payload_bytes = 0  # coded frames only (no header, no tag)
        self.packet_bytes = 0
        self.packets = 0
        self.keyframes = 0
        self.acked_packets = 0  # packets predicted from an acknowledged frame

    def request_keyframe(self) -> None:
        """Start the next packet with a keyframe (the receiver lost the chain)."""
        self._since_key = None

    def acknowledge(self, frame: int) -> None:
        """The receiver holds ``frame`` (u32 index) and its history: predict from it from now on
        (an acknowledgement older than the newest one already had only says the link is up)."""
        self._since_ack = 0
        if frame in self._sent and (self._acked is None or _behind(self._acked, frame)):
            self._acked = frame

    def push(self, values: np.ndarray, time_s: float) -> bytes | None:
        """Add one frame ``(21,)`` captured at ``time_s`` (sender's clock); returns a datagram
        when the packet is full, else None."""
        if not self._pending:
            self._first_time_us = int(round(time_s * 1e6))
        self._pending.append(quantise(values, self.steps))
        return self.flush() if len(self._pending) >= self.frames_per_packet else None

    def flush(self) -> bytes | None:
        """The packet of the frames pushed so far (None if there are none)."""
        if not self._pending:
            return None
        levels = np.array(self._pending)
        reference = self._reference(len(levels))
        keyframe = reference is None
        back = 0 if reference is None else (self.frame - reference) % WRAP
        history = np.zeros((0, N_MOTORS), np.int64)
        if reference is not None:
            found = self._sent.history(reference)
            assert found is not None  # _reference only picks a frame whose history is kept
            history = bridge(found, back - 1, self.steps)
        body = encode_frames(levels, history, keyframe, self.models)
        header = Header(KEYFRAME if keyframe else 0, self.sequence, self.frame, self._first_time_us, len(levels),
                        self.steps, self.rate, back)
        datagram = seal(header, body, self.key)
        depth = 0 if reference is None else self._sent.depth(reference) + back
        for i, row in enumerate(levels):
            self._sent.put((self.frame + i) % WRAP, row, depth + i)
        self._since_key = (0 if keyframe or self._since_key is None else self._since_key) + len(levels)
        self._since_ack += len(levels)
        self.acked_packets += reference is not None and reference == self._acked
        self.sequence = (self.sequence + 1) % WRAP
        self.frame = (self.frame + len(levels)) % WRAP
        self._pending = []
        self.payload_bytes += len(body)
        self.packet_bytes += len(datagram)
        self.packets += 1
        self.keyframes += keyframe
        return datagram

    def _reference(self, count: int) -> int | None:
        """The frame the next packet is predicted from, or None for a keyframe."""
        if self._since_key is None:
            return None
        if (self._acked is not None and self._since_ack <= ACK_SECONDS * self.rate
                and (self.frame - self._acked) % WRAP <= KEEP and self._sent.history(self._acked) is not None):
            return self._acked
        previous = (self.frame - 1) % WRAP
        if self._since_key + count > self.key_every or self._sent.history(previous) is None:
            return None
        return previous


@dataclass(frozen=True)
class Frames:
    """Frames decoded from one packet: their first index, capture time (sender's clock, s, of
    the first), rate, values ``(n, 21)``, and the packet's arrival (receiver's clock, s)."""

    first: int
    time_s: float
    rate: float
    values: np.ndarray
    arrival: float


class StreamReader:
    """Check and decode datagrams; count what is dropped and why.

    A packet is decoded when its reference frame and that frame's history are held (a keyframe
    needs none). A packet that arrives before its reference waits (up to ``max_waiting``
    packets) and is decoded when the reference is; while one waits, :attr:`want_keyframe` asks
    the caller to request a keyframe. After each decode, :meth:`take_ack` gives the
    acknowledgement to send back: the newest frame held with its whole history.

    Parameters
    ----------
    key : bytes, optional
        The shared secret; without it, only CRC-tagged packets are read.
    max_waiting : int
        Out-of-order packets kept while their reference may still come.
    idle_reset : float
        Seconds without a valid packet after which a new sequence numbering is accepted (a
        restarted sender).
    """

    def __init__(self, key: bytes | None = None, max_waiting: int = 16, idle_reset: float = 2.0) -> None:
        self.key, self.max_waiting, self.idle_reset = key, max_waiting, idle_reset
        self.dropped: Counter[str] = Counter()
        self.packets = 0
        self.bytes = 0
        self.lost = 0  # packets never seen (sequence gaps not filled later)
        self.want_keyframe = False
        self._models: dict[int, Models] = {}
        self._newest: int | None = None  # highest sequence seen
        self._seen = 0  # bit i: sequence newest - i seen
        self._last_valid = -np.inf
        self._held = FrameStore()
        self._ack: int | None = None  # the newest frame held with its history, not yet acknowledged
        self._acked: int | None = None
        self._waiting: dict[int, tuple[Header, bytes, float]] = {}  # by first frame
        self._frame_mark: tuple[int, int] | None = None  # (last raw frame index, unwrapped)
        self._time_mark: tuple[int, int] | None = None  # (last raw time, unwrapped), microseconds

    def read(self, datagram: bytes, arrival: float) -> list[Frames]:
        """Decoded frames that this datagram completes (none, its own, or it and those that
        waited for it). Bad datagrams are counted in :attr:`dropped` and give none."""
        try:
            header, body = open_packet(datagram, self.key)
        except WireError as error:
            self.dropped[error.reason] += 1
            return []
        if header.key_request or header.ack:
            self.dropped["request"] += 1  # a receiver does not take requests
            return []
        if not self._fresh(header.sequence, arrival):
            self.dropped["replay"] += 1
            return []
        self.packets += 1
        self.bytes += len(datagram)
        self._last_valid = arrival
        if not header.keyframe and self._held.history(_reference(header)) is None:
            self._wait(header, body, arrival)
            return []
        out = self._decode(header, body, arrival)
        progress = True
        while progress and self._waiting:  # a decode may hold what others waited for
            progress = False
            for first, (h, b, a) in list(self._waiting.items()):
                if self._held.history(_reference(h)) is not None:
                    del self._waiting[first]
                    out += self._decode(h, b, a)
                    progress = True
        if not self._waiting:
            self.want_keyframe = False
        return out

    def take_ack(self, sequence: int = 0) -> bytes | None:
        """The acknowledgement to send now (the newest frame held with its history), once per
        frame; None when there is nothing new to acknowledge."""
        if self._ack is None or self._ack == self._acked:
            return None
        self._acked = self._ack
        return seal(Header(ACK, sequence, self._ack, 0, 0, DEFAULT_STEPS, 1.0), b"", self.key)

    def _wait(self, header: Header, body: bytes, arrival: float) -> None:
        self._waiting[header.first_frame] = (header, body, arrival)
        if len(self._waiting) > self.max_waiting:  # the one furthest behind this one is the least likely to be shown
            del self._waiting[max(self._waiting, key=lambda k: (header.first_frame - k) % WRAP)]
            self.dropped["overflow"] += 1
        self.want_keyframe = True

    def _fresh(self, sequence: int, arrival: float) -> bool:
        """Record ``sequence``; False if it was seen before or is too old to tell."""
        if self._newest is None or arrival - self._last_valid > self.idle_reset:
            self._newest, self._seen = sequence, 1
            return True
        ahead = (sequence - self._newest) % WRAP
        if 0 < ahead < WRAP // 2:
            self.lost += min(ahead, REPLAY_WINDOW) - 1
            self._seen = ((self._seen << ahead) | 1) & ((1 << REPLAY_WINDOW) - 1)
            self._newest = sequence
            return True
        behind = (self._newest - sequence) % WRAP
        if behind >= REPLAY_WINDOW or self._seen >> behind & 1:
            return False
        self._seen |= 1 << behind
        self.lost = max(0, self.lost - 1)  # it came late, not never
        return True

    def _decode(self, header: Header, body: bytes, arrival: float) -> list[Frames]:
        models = self._models.get(header.steps)
        if models is None:
            if len(self._models) >= 4:
                self._models.clear()
            models = self._models[header.steps] = Models(header.steps)
        history, depth = np.zeros((0, N_MOTORS), np.int64), 0
        if not header.keyframe:
            reference = _reference(header)
            found = self._held.history(reference)
            assert found is not None  # read() decodes only packets whose reference is held
            history, depth = bridge(found, header.back - 1, header.steps), self._held.depth(reference) + header.back
        try:
            levels = decode_frames(body, header.count, history, header.keyframe, models)
        except WireError as error:
            self.dropped[error.reason] += 1
            return []
        for i, row in enumerate(levels):
            index = (header.first_frame + i) % WRAP
            self._held.put(index, row, depth + i)
            if self._held.history(index) is not None and (self._ack is None or _behind(self._ack, index)):
                self._ack = index
        if header.keyframe:
            for first in [k for k in self._waiting if _behind(k, header.first_frame)]:
                del self._waiting[first]  # older than the keyframe: nothing to show them for
        self._frame_mark = _unwrap(header.first_frame, self._frame_mark)
        self._time_mark = _unwrap(header.time_us, self._time_mark)
        return [Frames(self._frame_mark[1], self._time_mark[1] / 1e6, header.rate, levels / header.steps, arrival)]


def _reference(header: Header) -> int:
    """The frame a predicted packet is predicted from."""
    return (header.first_frame - header.back) % WRAP


def key_request(sequence: int, key: bytes | None) -> bytes:
    """The datagram a receiver sends back to ask for a keyframe."""
    return seal(Header(KEY_REQUEST, sequence, 0, 0, 0, DEFAULT_STEPS, 1.0), b"", key)


def is_key_request(datagram: bytes, key: bytes | None) -> bool:
    """Whether ``datagram`` is a valid keyframe request (checked like any packet)."""
    try:
        header, _ = open_packet(datagram, key)
    except WireError:
        return False
    return header.key_request


def acknowledged_frame(datagram: bytes, key: bytes | None) -> int | None:
    """The frame a valid acknowledgement names (None for anything else)."""
    try:
        header, _ = open_packet(datagram, key)
    except WireError:
        return None
    return header.first_frame if header.ack else None


def _unwrap(raw: int, mark: tuple[int, int] | None) -> tuple[int, int]:
    """``raw`` (a u32 that wraps) and its unwrapped value, the nearest to the last ``mark``."""
    if mark is None:
        return raw, raw
    step = (raw - mark[0]) % WRAP
    return raw, mark[1] + (step - WRAP if step >= WRAP // 2 else step)


def _behind(index: int, reference: int) -> bool:
    """Frame ``index`` is at or before ``reference`` (modulo wrap)."""
    return (reference - index) % WRAP < WRAP // 2
