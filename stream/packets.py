"""Both ends of the motor stream's packet layer: :class:`StreamWriter` (frames in, datagrams
out) and :class:`StreamReader` (datagrams in, checked, de-duplicated, re-ordered and decoded
frames out). The format is :mod:`stream.wire`'s; the sockets are the caller's."""

from __future__ import annotations

import secrets
from collections import Counter
from dataclasses import dataclass

import numpy as np

from stream.wire import (
    DEFAULT_STEPS,
    KEY_REQUEST,
    KEYFRAME,
    MAX_FRAMES,
    Header,
    Models,
    WireError,
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


class StreamWriter:
    """Turn motor frames into packets of ``frames_per_packet`` frames.

    Parameters
    ----------
    rate : float
        Frames per second.
    frames_per_packet : int
        1..32; more frames per packet means fewer headers and more delay.
    key_seconds : float
        A packet starts with a keyframe at least this often.
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
        self._history = np.zeros((0, N_MOTORS), dtype=np.int64)
        self._pending: list[np.ndarray] = []
        self._first_time_us = 0
        self.payload_bytes = 0  # coded frames only (no header, no tag)
        self.packet_bytes = 0
        self.packets = 0
        self.keyframes = 0

    def request_keyframe(self) -> None:
        """Start the next packet with a keyframe (the receiver lost the chain)."""
        self._since_key = None

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
        keyframe = self._since_key is None or self._since_key + len(levels) > self.key_every
        body = encode_frames(levels, self._history, keyframe, self.models)
        header = Header(KEYFRAME if keyframe else 0, self.sequence, self.frame, self._first_time_us, len(levels),
                        self.steps, self.rate)
        datagram = seal(header, body, self.key)
        self._since_key = (0 if keyframe or self._since_key is None else self._since_key) + len(levels)
        self._history = (levels if keyframe else np.vstack([self._history, levels]))[-3:]
        self.sequence = (self.sequence + 1) % WRAP
        self.frame = (self.frame + len(levels)) % WRAP
        self._pending = []
        self.payload_bytes += len(body)
        self.packet_bytes += len(datagram)
        self.packets += 1
        self.keyframes += keyframe
        return datagram


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

    A packet is decoded when its chain is intact: it is a keyframe, or its first frame follows
    the last frame decoded. A packet that arrives before its predecessor waits (up to
    ``max_waiting`` packets); one that can no longer be decoded is dropped, and
    :attr:`want_keyframe` tells the caller to ask the sender for a keyframe.

    Parameters
    ----------
    key : bytes, optional
        The shared secret; without it, only CRC-tagged packets are read.
    max_waiting : int
        Out-of-order packets kept while their predecessor may still come.
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
        self._chain_end: int | None = None  # index of the last frame decoded
        self._history = np.zeros((0, N_MOTORS), dtype=np.int64)
        self._waiting: dict[int, tuple[Header, bytes, float]] = {}
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
        if header.key_request:
            self.dropped["request"] += 1  # a receiver does not take requests
            return []
        if not self._fresh(header.sequence, arrival):
            self.dropped["replay"] += 1
            return []
        self.packets += 1
        self.bytes += len(datagram)
        self._last_valid = arrival
        if header.keyframe or self._follows(header):
            out = self._decode(header, body, arrival)
            while self._chain_end is not None and (self._chain_end + 1) % WRAP in self._waiting:
                out += self._decode(*self._waiting.pop((self._chain_end + 1) % WRAP))
            return out
        if self._chain_end is not None and _behind(header.first_frame, self._chain_end):
            self.dropped["late"] += 1
            return []
        self._waiting[header.first_frame] = (header, body, arrival)
        if len(self._waiting) > self.max_waiting:  # the one furthest ahead is the least likely to be decoded
            del self._waiting[max(self._waiting, key=lambda k: (k - (self._chain_end or 0)) % WRAP)]
            self.dropped["overflow"] += 1
        self.want_keyframe = True
        return []

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

    def _follows(self, header: Header) -> bool:
        return self._chain_end is not None and (header.first_frame - self._chain_end) % WRAP == 1

    def _decode(self, header: Header, body: bytes, arrival: float) -> list[Frames]:
        models = self._models.get(header.steps)
        if models is None:
            if len(self._models) >= 4:
                self._models.clear()
            models = self._models[header.steps] = Models(header.steps)
        history = self._history if not header.keyframe else self._history[:0]
        try:
            levels = decode_frames(body, header.count, history, header.keyframe, models)
        except WireError as error:
            self.dropped[error.reason] += 1
            return []
        if header.keyframe:
            self.want_keyframe = False
            for first in [k for k in self._waiting if not _behind(header.first_frame, k)]:
                del self._waiting[first]
        if header.count:
            self._chain_end = (header.first_frame + header.count - 1) % WRAP
            self._history = (levels if header.keyframe else np.vstack([self._history, levels]))[-3:]
        self._frame_mark = _unwrap(header.first_frame, self._frame_mark)
        self._time_mark = _unwrap(header.time_us, self._time_mark)
        return [Frames(self._frame_mark[1], self._time_mark[1] / 1e6, header.rate, levels / header.steps, arrival)]


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


def _unwrap(raw: int, mark: tuple[int, int] | None) -> tuple[int, int]:
    """``raw`` (a u32 that wraps) and its unwrapped value, the nearest to the last ``mark``."""
    if mark is None:
        return raw, raw
    step = (raw - mark[0]) % WRAP
    return raw, mark[1] + (step - WRAP if step >= WRAP // 2 else step)


def _behind(index: int, reference: int) -> bool:
    """Frame ``index`` is at or before ``reference`` (modulo wrap)."""
    return (reference - index) % WRAP < WRAP // 2
