"""The receiving end of the motor stream's packet layer: :class:`StreamReader` (datagrams in,
checked, de-duplicated, re-ordered and decoded frames out, acknowledgements back). The format
is :mod:`stream.wire`'s; the sockets are the caller's."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from stream.framing import (
    ACK,
    ANCHOR_FRAMES,
    ANCHOR_SECONDS,
    LOSS_SEEN,
    Anchor,
    Header,
    StreamKey,
    WireError,
    open_packet,
    seal,
    stream_key,
)
from stream.packets import ACK_BITS, LOSS_SECONDS, WRAP, FrameStore, behind
from stream.wire import DEFAULT_STEPS, Models, bridge, decode_frames, params_check, unpack_params
from toon import N_MOTORS

#: Packets this far behind the newest are too old to be anything but a replay.
REPLAY_WINDOW = 64
#: Earlier runs of a stream whose sequence numbers a reader remembers, to refuse their replay.
SESSIONS_KEPT = 32
#: While nothing is lost, a reader acknowledges at most this often (seconds): enough for the
#: sender to know someone receives; after a loss, every packet for the sender's LOSS_SECONDS.
ACK_INTERVAL = 1.0
#: A packet that has waited this long for its reference (seconds) asks for a keyframe: by then an
#: acknowledgement sent at the loss should have brought a packet predicted from a frame held.
KEY_WAIT = 0.2


@dataclass(frozen=True)
class Frames:
    """Frames decoded from one packet: their first index, capture time (sender's clock, s, of
    the first), rate, values ``(n, 21 + len(codes))``, the packet's arrival (receiver's clock,
    s), the codes of the parameters after the 21 (none for a stream of the 21) and which run of
    its sender they belong to (a count the reader moves on when a new numbering begins: a
    restarted sender). The first ``filled`` of them came after a newer frame had: they fill a
    hole (a frame repeated after a loss), so their lateness says nothing of the network's."""

    first: int
    time_s: float
    rate: float
    values: np.ndarray
    arrival: float
    codes: tuple[str, ...] = ()
    run: int = 0
    filled: int = 0


class StreamReader:
    """Check and decode datagrams; count what is dropped and why.

    A packet is decoded when its reference frame and that frame's history are held (a keyframe
    needs none). A packet that arrives before its reference waits (up to ``max_waiting``
    packets) and is decoded when the reference is; once one has waited :data:`KEY_WAIT`,
    :attr:`want_keyframe` asks the caller to request a keyframe. :meth:`take_ack` gives the
    acknowledgement to send back when one is due (the newest frame held and which of those
    before it are): at once after a loss and after every packet for
    :data:`~stream.packets.LOSS_SECONDS` after the last, else at most every
    :data:`ACK_INTERVAL` seconds.

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

    def __init__(self, key: bytes | StreamKey | None = None, max_waiting: int = 16, idle_reset: float = 2.0) -> None:
        self.key, self.max_waiting, self.idle_reset = stream_key(key), max_waiting, idle_reset
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
        self._anchor: Anchor | None = None  # what short headers are restored against
        self._loss_at = -np.inf  # when a loss was last seen (a packet missing, or one waiting)
        self._acked_at = -np.inf  # when an acknowledgement was last given
        self._now = -np.inf  # the last packet's arrival
        self._named: int | None = None  # the newest frame a packet has named
        self._held = FrameStore()
        self._ack: int | None = None  # the newest frame held
        self._ack_due = False  # a frame came since the last acknowledgement
        self._waiting: dict[int, tuple[Header, bytes, float, int | None]] = {}  # by first frame
        self._frame_mark: tuple[int, int] | None = None  # (last raw frame index, unwrapped)
        self._time_mark: tuple[int, int] | None = None  # (last raw time, unwrapped), milliseconds

    def read(self, datagram: bytes, arrival: float) -> list[Frames]:
        """Decoded frames that this datagram completes (none, its own, or it and those that
        waited for it). Bad datagrams are counted in :attr:`dropped` and give none."""
        anchor = self._anchor
        if anchor is not None and arrival - self._last_valid > min(ANCHOR_SECONDS, ANCHOR_FRAMES / anchor.rate):
            anchor = None  # too long ago to restore a short header's low bits surely
        try:
            header, body = open_packet(datagram, self.key, anchor)
        except WireError as error:
            self.dropped[error.reason] += 1
            if error.reason == "unanchored":
                self.want_keyframe = True  # a long header comes with it
            return []
        if header.key_request or header.ack:
            self.dropped["request"] += 1  # a receiver does not take requests
            return []
        lost = self.lost
        if not self._fresh(header.sequence, arrival):
            self.dropped["replay"] += 1
            return []
        self._now = arrival
        seen, last = self._named, (header.first_frame + max(header.count, 1) - 1) % WRAP
        if seen is None or behind(seen, last):
            self._named = last
        if self.lost > lost:
            self._loss_at = arrival
        self.packets += 1
        self.bytes += len(datagram)
        self.stream = header.stream
        self._last_valid = arrival
        if self._anchor is None or anchor is None or not behind(header.sequence, self._anchor.sequence):
            self._anchor = (self._anchor or Anchor(0, 0)).after(header)
        if not header.keyframe and self._held.history(_reference(header)) is None:
            self._loss_at = arrival
            self._wait(header, body, arrival, seen)
            self._want(arrival)
            return []
        out = self._decode(header, body, arrival, seen)
        progress = True
        while progress and self._waiting:  # a decode may hold what others waited for
            progress = False
            for first, (h, b, a, s) in list(self._waiting.items()):
                if self._held.history(_reference(h)) is not None:
                    del self._waiting[first]
                    out += self._decode(h, b, a, s)
                    progress = True
        for first, (h, *_) in list(self._waiting.items()):  # a packet whose frames came in another: obsolete
            if all((first + k) % WRAP in self._held for k in range(h.count)):
                del self._waiting[first]
                self.dropped["obsolete"] += 1
        self._want(arrival)
        return out

    def take_ack(self, sequence: int = 0) -> bytes | None:
        """The acknowledgement to send now (the newest frame held, and which of the
        :data:`ACK_BITS` before it are held) when one is due (see the class) and a frame came
        since the last; else None."""
        lossy = self._now - self._loss_at < LOSS_SECONDS
        if self._ack is None or not self._ack_due or (not lossy and self._now - self._acked_at < ACK_INTERVAL):
            return None
        self._ack_due = False
        self._acked_at = self._now
        held = sum(1 << i for i in range(ACK_BITS) if (self._ack - 1 - i) % WRAP in self._held)
        flags = ACK | (LOSS_SEEN if lossy else 0)
        return seal(Header(flags, sequence, self._ack, held, 0, DEFAULT_STEPS, 1.0, stream=self.stream), b"", self.key)

    def _want(self, now: float) -> None:
        """Whether to ask for a keyframe: parameters not known, or a packet ahead of every frame
        held has waited too long (one behind them waits on in case its reference comes late, but
        the stream has gone on without it)."""
        self.want_keyframe = self._unnamed or any(
            now - a >= KEY_WAIT and (self._ack is None or not behind(first, self._ack))
            for first, (_, _, a, _) in self._waiting.items())

    def _wait(self, header: Header, body: bytes, arrival: float, seen: int | None) -> None:
        self._waiting[header.first_frame] = (header, body, arrival, seen)
        if len(self._waiting) > self.max_waiting:  # the one furthest behind this one is the least likely to be shown
            del self._waiting[max(self._waiting, key=lambda k: (header.first_frame - k) % WRAP)]
            self.dropped["overflow"] += 1

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
            self._named = None
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

    def _decode(self, header: Header, body: bytes, arrival: float, seen: int | None) -> list[Frames]:
        """The frames of a packet whose reference is held; ``seen``: the newest frame any packet
        named before it came (its frames up to that one were sent again: they fill holes)."""
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
        self._time_mark = _unwrap(header.time_ms, self._time_mark)

        def filled(i: int, count: int) -> int:
            return 0 if seen is None else sum(behind((header.first_frame + i + k) % WRAP, seen) for k in range(count))

        return [Frames(self._frame_mark[1] + i, self._time_mark[1] / 1e3 + i / header.rate, header.rate,
                       np.array(rows) / header.steps, arrival, self.codes, self.run, filled(i, len(rows)))
                for i, rows in runs]


def _reference(header: Header) -> int:
    """The frame a predicted packet is predicted from."""
    return (header.first_frame - header.back) % WRAP


def _unwrap(raw: int, mark: tuple[int, int] | None) -> tuple[int, int]:
    """``raw`` (a u32 that wraps) and its unwrapped value, the nearest to the last ``mark``."""
    if mark is None:
        return raw, raw
    step = (raw - mark[0]) % WRAP
    return raw, mark[1] + (step - WRAP if step >= WRAP // 2 else step)
