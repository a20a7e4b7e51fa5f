"""The receiving end of the motor stream's packet layer: :class:`StreamReader` (datagrams in,
checked, de-duplicated, re-ordered and decoded frames out, acknowledgements back). The format
is :mod:`stream.wire`'s; the sockets are the caller's."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from stream.packets import ACK_BITS, WRAP, FrameStore, behind
from stream.wire import (
    ACK,
    DEFAULT_STEPS,
    Header,
    Models,
    WireError,
    bridge,
    decode_frames,
    open_packet,
    params_check,
    seal,
    unpack_params,
)
from toon import N_MOTORS

#: Packets this far behind the newest are too old to be anything but a replay.
REPLAY_WINDOW = 64
#: Earlier runs of a stream whose sequence numbers a reader remembers, to refuse their replay.
SESSIONS_KEPT = 32


@dataclass(frozen=True)
class Frames:
    """Frames decoded from one packet: their first index, capture time (sender's clock, s, of
    the first), rate, values ``(n, 21 + len(codes))``, the packet's arrival (receiver's clock,
    s), the codes of the parameters after the 21 (none for a stream of the 21) and which run of
    its sender they belong to (a count the reader moves on when a new numbering begins: a
    restarted sender)."""

    first: int
    time_s: float
    rate: float
    values: np.ndarray
    arrival: float
    codes: tuple[str, ...] = ()
    run: int = 0


class StreamReader:
    """Check and decode datagrams; count what is dropped and why.

    A packet is decoded when its reference frame and that frame's history are held (a keyframe
    needs none). A packet that arrives before its reference waits (up to ``max_waiting``
    packets) and is decoded when the reference is; while one waits, :attr:`want_keyframe` asks
    the caller to request a keyframe. After each decode, :meth:`take_ack` gives the
    acknowledgement to send back: the newest frame held and which of those before it are.

    Parameters
    ----------
    key : bytes, optional
        The shared secret; without it, only CRC-tagged packets are read.
    max_waiting : int
        Out-of-order packets kept while their reference may still come.
    idle_reset : float
        Seconds without a valid packet after which a new sequence numbering is accepted (a
        restarted sender), unless it falls among the numbers of an earlier run (of the last
        :data:`SESSIONS_KEPT`): a replay of captured packets is refused (``replay``) whenever it
        comes. A sender starts its numbering at random, so a restart does not collide.
    """

    def __init__(self, key: bytes | None = None, max_waiting: int = 16, idle_reset: float = 2.0) -> None:
        self.key, self.max_waiting, self.idle_reset = key, max_waiting, idle_reset
        self.dropped: Counter[str] = Counter()
        self.packets = 0
        self.bytes = 0
        self.lost = 0  # packets never seen (sequence gaps not filled later)
        self.want_keyframe = False
        self.stream = 0  # the id of the stream read (its packets'), which replies carry back
        self.codes: tuple[str, ...] = ()  # the parameters after the 21, named by the last keyframe packet
        self._unnamed = False  # a keyframe of parameters this end does not know came: one naming them is wanted
        self._models: dict[int, Models] = {}
        self._newest: int | None = None  # highest sequence seen
        self._first_sequence = 0  # where the present run's numbering began
        self.run = -1  # the present run's number (0 the first)
        self._runs: list[tuple[int, int]] = []  # earlier runs' first and newest sequence numbers
        self._seen = 0  # bit i: sequence newest - i seen
        self._last_valid = -np.inf
        self._held = FrameStore()
        self._ack: int | None = None  # the newest frame held
        self._ack_due = False  # a frame came since the last acknowledgement
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
        self.stream = header.stream
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
        self.want_keyframe = bool(self._waiting) or self._unnamed
        return out

    def take_ack(self, sequence: int = 0) -> bytes | None:
        """The acknowledgement to send now (the newest frame held, and which of the
        :data:`ACK_BITS` before it are held) when a frame came since the last; else None."""
        if self._ack is None or not self._ack_due:
            return None
        self._ack_due = False
        held = sum(1 << i for i in range(ACK_BITS) if (self._ack - 1 - i) % WRAP in self._held)
        return seal(Header(ACK, sequence, self._ack, held, 0, DEFAULT_STEPS, 1.0, stream=self.stream), b"", self.key)

    def _wait(self, header: Header, body: bytes, arrival: float) -> None:
        self._waiting[header.first_frame] = (header, body, arrival)
        if len(self._waiting) > self.max_waiting:  # the one furthest behind this one is the least likely to be shown
            del self._waiting[max(self._waiting, key=lambda k: (header.first_frame - k) % WRAP)]
            self.dropped["overflow"] += 1
        self.want_keyframe = True

    def _fresh(self, sequence: int, arrival: float) -> bool:
        """Record ``sequence``; False if it was seen before or is too old to tell."""
        if self._newest is None or arrival - self._last_valid > self.idle_reset:
            runs = self._runs + ([(self._first_sequence, self._newest)] if self._newest is not None else [])
            if any((sequence - first) % WRAP <= (newest - first) % WRAP for first, newest in runs):
                return False  # a packet of an earlier run: replayed
            self._runs = runs[-SESSIONS_KEPT:]
            self._newest, self._seen, self._first_sequence = sequence, 1, sequence
            self.run += 1
            self._held, self._ack, self._waiting = FrameStore(), None, {}  # maybe a restarted sender: its frames anew
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
        try:
            section, body = unpack_params(header, body)
        except WireError as error:
            self.dropped[error.reason] += 1
            return []
        if isinstance(section, tuple):
            self.codes, self._unnamed = section, False
        elif (isinstance(section, int) and (not self.codes or section != params_check(self.codes))
              or header.params != bool(self.codes)):  # a keyframe of parameters this end was not told (it joined late)
            self.dropped["params"] += 1
            self._unnamed = True
            return []
        elif header.keyframe:
            self._unnamed = False
        history, depth = np.zeros((0, N_MOTORS + len(self.codes)), np.int64), 0
        if not header.keyframe:
            reference = _reference(header)
            found = self._held.history(reference)
            assert found is not None  # read() decodes only packets whose reference is held
            history, depth = bridge(found, header.back - 1, header.steps), self._held.depth(reference) + header.back
        try:
            levels = decode_frames(body, header.count, history, header.keyframe, models, self.codes)
        except WireError as error:
            self.dropped[error.reason] += 1
            return []
        runs: list[tuple[int, list[np.ndarray]]] = []  # frames not held before, in consecutive runs
        for i, row in enumerate(levels):
            index = (header.first_frame + i) % WRAP
            if index in self._held and np.array_equal(self._held.row(index), row):
                continue  # a repeated frame already here (a restarted sender's frame 0 is not frame 0)
            self._held.put(index, row, depth + i)
            if runs and runs[-1][0] + len(runs[-1][1]) == i:
                runs[-1][1].append(row)
            else:
                runs.append((i, [row]))
            self._ack_due = True
            if self._ack is None or behind(self._ack, index):
                self._ack = index
        if header.keyframe:
            for first in [k for k in self._waiting if behind(k, header.first_frame)]:
                del self._waiting[first]  # older than the keyframe: nothing to show them for
        self._frame_mark = _unwrap(header.first_frame, self._frame_mark)
        self._time_mark = _unwrap(header.time_us, self._time_mark)
        return [Frames(self._frame_mark[1] + i, self._time_mark[1] / 1e6 + i / header.rate, header.rate,
                       np.array(rows) / header.steps, arrival, self.codes, self.run) for i, rows in runs]


def _reference(header: Header) -> int:
    """The frame a predicted packet is predicted from."""
    return (header.first_frame - header.back) % WRAP


def _unwrap(raw: int, mark: tuple[int, int] | None) -> tuple[int, int]:
    """``raw`` (a u32 that wraps) and its unwrapped value, the nearest to the last ``mark``."""
    if mark is None:
        return raw, raw
    step = (raw - mark[0]) % WRAP
    return raw, mark[1] + (step - WRAP if step >= WRAP // 2 else step)
