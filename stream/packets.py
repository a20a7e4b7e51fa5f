"""The sending end of the motor stream's packet layer, :class:`StreamWriter` (frames in,
datagrams out), and what both ends keep and exchange: the frames held (:class:`FrameStore`),
keyframe requests and acknowledgements. The receiving end is :mod:`stream.reader`; the format
is :mod:`stream.wire`'s; the sockets are the caller's."""

from __future__ import annotations

import secrets
from collections import deque

import numpy as np

from stream.framing import (
    KEY_REQUEST,
    KEYFRAME,
    LONG_SECONDS,
    LOSS_SEEN,
    MAX_EXTRA,
    MAX_FRAMES,
    NAMED,
    PARAMS,
    Anchor,
    Header,
    StreamKey,
    WireError,
    open_packet,
    seal,
    stream_key,
)
from stream.wire import DEFAULT_STEPS, Models, bridge, encode_frames, pack_params, quantise
from toon import N_MOTORS

WRAP = 1 << 32
#: Frames each end keeps to predict from: a reference lies at most this far back (the header's
#: reference is one byte).
KEEP = 255
#: Acknowledgements are relied on while one has come within this many seconds of stream (a
#: receiver acknowledges at least once a second, see :mod:`stream.reader`).
ACK_SECONDS = 2.5
#: Packets are predicted from the acknowledged frame, repeating unacknowledged frames, for this
#: many seconds of stream after an acknowledgement last showed a frame missing.
LOSS_SECONDS = 2.0
#: Above this rate (Hz), frames go one a packet while loss is seen: a lost frame's repeat then
#: comes one frame period later, so the receiver's jitter buffer stays short. At this rate and
#: below, packets keep their frames under loss, so that a 30 fps stream stays within 12 kbit/s
#: both ways (one frame a packet there costs 20, half of it in acknowledgements).
ALONE_ABOVE_HZ = 40.0
#: A short header's time is the one its frame predicts from the last long header (see
#: :mod:`stream.framing`): a packet captured further than this (ms) from it goes long.
TIME_STRAY_MS = 12
#: Frames before the acknowledged one whose receipt an acknowledgement reports.
ACK_BITS = 32


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

    def row(self, index: int) -> np.ndarray:
        return self._rows[index][0]

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

    Each packet continues from the one before (its first frame is predicted from the frame just
    before it). While nothing is lost the receiver acknowledges about once a second, which only
    says that it is there; a packet lost breaks the chain, the receiver acknowledges at once
    (and then every packet while loss goes on), and once an acknowledgement shows a frame
    missing, for :data:`LOSS_SECONDS` after the last that did, each packet is predicted from the
    newest frame the receiver acknowledged (so a lost packet costs only its own frames) and
    repeats up to ``repeat`` unacknowledged frames before its own; above
    :data:`ALONE_ABOVE_HZ` frames then go one a packet. Without acknowledgements (a
    one-way link) a keyframe comes at least every ``key_seconds``; a keyframe also comes whenever
    the receiver asks.

    Parameters
    ----------
    rate : float
        Frames per second.
    frames_per_packet : int
        1..32; more frames per packet means fewer headers and more delay (the first frame of a
        packet waits for the others: 2 at 30 fps add 33 ms).
    key_seconds : float
        Without acknowledgements, a packet starts with a keyframe at least this often.
    steps : int
        Quantisation steps (see :mod:`stream.wire`).
    key : bytes, optional
        Shared secret: packets are sealed (encrypted and authenticated) instead of carrying a CRC.
    first_sequence : int, optional
        The first packet's number (random by default, so a restarted sender is not a replay).
    repeat : int, optional
        Unacknowledged frames a packet repeats while loss is seen (0: none) [default: its frames
        per packet: a packet lost alone comes again in the next].
    stream : int
        This performer's stream id, 0..65535 (a receiver tells several apart by it).
    codes : tuple of str
        The parameters beyond the 21 each frame carries after them (HT...), named in every
        keyframe packet; none: frames of the 21, packets as before parameters came.
    """

    def __init__(self, rate: float, frames_per_packet: int = 2, key_seconds: float = 0.5, steps: int = DEFAULT_STEPS,
                 key: bytes | StreamKey | None = None, first_sequence: int | None = None, repeat: int | None = None,
                 stream: int = 0, codes: tuple[str, ...] = ()) -> None:
        repeat = frames_per_packet if repeat is None else repeat
        if not 1 <= frames_per_packet <= MAX_FRAMES:
            raise ValueError(f"frames per packet must be 1..{MAX_FRAMES}, got {frames_per_packet}")
        if not 1 <= steps <= 255:
            raise ValueError(f"quantisation steps must be 1..255, got {steps}")
        if not 0 < rate < 655:
            raise ValueError(f"the frame rate must be between 0 and 655 Hz, got {rate:g}")
        if not 0 <= repeat < MAX_FRAMES:
            raise ValueError(f"repeated frames must be 0..{MAX_FRAMES - 1}, got {repeat}")
        self.rate, self.frames_per_packet, self.steps, self.key = rate, frames_per_packet, steps, stream_key(key)
        if not 0 <= stream <= 0xFFFF:
            raise ValueError(f"a stream id is 0..65535, got {stream}")
        self.stream = stream
        if len(codes) > MAX_EXTRA or not all(code.isascii() and code and " " not in code for code in codes):
            raise ValueError(f"at most {MAX_EXTRA} parameter codes of ASCII without spaces, got {codes}")
        self.codes = tuple(codes)
        self._name = True  # the next keyframe names the parameters (the first, and each asked for)
        self.repeat = repeat
        self.key_every = max(1, int(round(key_seconds * rate)))
        self.models = Models(steps)
        self.sequence = secrets.randbelow(WRAP) if first_sequence is None else first_sequence
        self.frame = 0
        self._since_key: int | None = None  # frames since the last keyframe; None: send one next
        self._sent = FrameStore()
        self._acked: int | None = None  # the newest frame the receiver holds with its history
        self._since_ack = np.inf  # frames sent since the last acknowledgement came
        self._since_loss = np.inf  # frames sent since an acknowledgement last showed one missing
        self._have: set[int] = set()  # the frames the newest acknowledgement says are held
        self._newest_have: int | None = None  # the frame that acknowledgement named
        self._last_missing: int | None = None  # the newest frame an acknowledgement showed missing
        self._pending: list[np.ndarray] = []
        self._first_time_ms = 0
        self._since_long = np.inf  # frames since the last packet with the long header went
        self._long: Header | None = None  # the last packet with the long header
        self.payload_bytes = 0  # coded frames only (no header, no tag)
        self.packet_bytes = 0
        self.packets = 0
        self.keyframes = 0
        self.acked_packets = 0  # packets predicted from an acknowledged frame
        self.repeated_frames = 0  # frames sent again (see ``repeat``)

    @property
    def started(self) -> bool:
        """Whether a frame was pushed (from then on its :attr:`codes` stand)."""
        return bool(self._pending) or self.packets > 0

    def request_keyframe(self) -> None:
        """Start the next packet with a keyframe (the receiver lost the chain), naming the
        parameters beyond the 21 (it may not know them)."""
        self._since_key = None
        self._name = True

    def acknowledge(self, frame: int, held: int = (1 << ACK_BITS) - 1, loss: bool = False) -> None:
        """The receiver holds ``frame`` (u32 index, the newest it holds) and of the
        :data:`ACK_BITS` frames before it those whose bit is set in ``held`` (bit i: the frame
        i + 1 before). From now on predict from the newest of them whose history it holds too
        (an acknowledgement that names nothing newer only says the link is up), and if any
        frame sent before ``frame`` is missing, send frames one a packet, repeating."""
        self._since_ack = 0
        window = [frame] + [(frame - 1 - i) % WRAP for i in range(ACK_BITS)]
        have = {frame} | {window[i + 1] for i in range(ACK_BITS) if held >> i & 1}
        for candidate in window:
            if (candidate in have and candidate in self._sent
                    and all((candidate - k) % WRAP in have for k in range(1, self._sent.depth(candidate) + 1))):
                if self._acked is None or behind(self._acked, candidate):
                    self._acked = candidate
                break
        missing = [f for f in window if f in self._sent and f not in have]
        if missing and (self._last_missing is None or not behind(missing[0], self._last_missing)):
            self._since_loss, self._last_missing = 0, missing[0]  # a loss not seen before
        elif loss and not self.lossy:
            self._since_loss = 0  # the receiver saw one (frames after the newest it holds wait for it)
        if self._newest_have is None or behind(self._newest_have, frame):
            self._newest_have, self._have = frame, have

    @property
    def lossy(self) -> bool:
        """Whether loss was seen lately (packets predicted from acknowledged frames, repeating)."""
        return self._since_loss < LOSS_SECONDS * self.rate

    def push(self, values: np.ndarray, time_s: float) -> bytes | None:
        """Add one frame ``(21 + len(codes),)`` captured at ``time_s`` (sender's clock); returns a
        datagram when the packet is full, else None."""
        if len(values) != N_MOTORS + len(self.codes):
            raise ValueError(f"a frame of {len(values)} values; this stream carries {N_MOTORS + len(self.codes)}")
        if not self._pending:
            self._first_time_ms = int(round(time_s * 1e3))
        self._pending.append(quantise(values, self.steps))
        full = 1 if self.lossy and self.rate > ALONE_ABOVE_HZ else self.frames_per_packet
        return self.flush() if len(self._pending) >= full else None

    def flush(self) -> bytes | None:
        """The packet of the frames pushed so far (None if there are none), after the frames it
        repeats."""
        if not self._pending:
            return None
        again = self._repeated()
        first = (self.frame - len(again)) % WRAP
        levels = np.array([*again, *self._pending])
        reference = self._reference(first, len(levels))
        keyframe = reference is None
        back = 0 if reference is None else (first - reference) % WRAP
        history = np.zeros((0, N_MOTORS + len(self.codes)), np.int64)
        if reference is not None:
            found = self._sent.history(reference)
            assert found is not None  # _reference only picks a frame whose history is kept
            history = bridge(found, back - 1, self.steps)
        named = keyframe and self._name and bool(self.codes)
        coded = encode_frames(levels, history, keyframe, self.models, self.codes)
        body = pack_params(self.codes, keyframe, named) + coded
        time_ms = self._first_time_ms - int(round(len(again) * 1e3 / self.rate))
        flags = (KEYFRAME if keyframe else 0) | (PARAMS if self.codes else 0) | (NAMED if named else 0)
        header = Header(flags, self.sequence, first, time_ms, len(levels), self.steps, self.rate, back, self.stream,
                        self.frames_per_packet)
        self._name = self._name and not named
        short = self._short(header)
        datagram = seal(header, body, self.key, short)
        if short and header.fits_short():
            self._since_long += len(self._pending)
        else:
            self._since_long, self._long = 0, header
        depth = 0 if reference is None else self._sent.depth(reference) + back
        for i, row in enumerate(levels):
            index = (first + i) % WRAP
            if index not in self._sent or i >= len(again):  # a repeated frame keeps its first depth
                self._sent.put(index, row, depth + i)
        new = len(self._pending)
        self._since_key = (0 if keyframe or self._since_key is None else self._since_key) + new
        self._since_ack += new
        self._since_loss += new
        self.acked_packets += reference is not None and reference == self._acked
        self.repeated_frames += len(again)
        self.sequence = (self.sequence + 1) % WRAP
        self.frame = (self.frame + new) % WRAP
        self._pending = []
        self.payload_bytes += len(body)
        self.packet_bytes += len(datagram)
        self.packets += 1
        self.keyframes += keyframe
        return datagram

    def _repeated(self) -> list[np.ndarray]:
        """The frames the next packet repeats before its new ones: while loss is seen and
        acknowledgements are relied on, those of the last :attr:`repeat` sent after the
        acknowledged frame from the first not known to be held, as long as each would keep the
        depth it was first sent with."""
        if not self.lossy or self.repeat == 0 or self._since_key is None or not self._relying():
            return []
        assert self._acked is not None  # _relying
        ahead = (self.frame - 1 - self._acked) % WRAP  # frames sent after the acknowledged one
        window = [(self.frame - k) % WRAP for k in range(min(self.repeat, ahead), 0, -1)]
        missing = [i for i, f in enumerate(window) if f not in self._have]
        if not missing:
            return []
        window = window[missing[0]:]
        start = self._sent.depth(self._acked) + (window[0] - self._acked) % WRAP
        if any(self._sent.depth(f) != min(start + i, 2) for i, f in enumerate(window)):
            return []  # near a keyframe: the receiver would cut a history where this end did not
        return [self._sent.row(f) for f in window]

    def _short(self, header: Header) -> bool:
        """Whether ``header`` may go in the short form: the long one went within
        :data:`~stream.framing.LONG_SECONDS`, and its time is within :data:`TIME_STRAY_MS` of the
        one its frame predicts from that long one (what a reader takes for it)."""
        last = self._long
        if last is None or self._since_long + header.count > LONG_SECONDS * self.rate:
            return False
        predicted = last.time_ms + ((header.first_frame - last.first_frame + WRAP // 2) % WRAP - WRAP // 2) \
            * 1e3 / self.rate
        return abs(header.time_ms - predicted) <= TIME_STRAY_MS

    def _relying(self) -> bool:
        """Whether packets are predicted from the acknowledged frame now."""
        return (self._acked is not None and self._since_ack <= ACK_SECONDS * self.rate
                and (self.frame - self._acked) % WRAP <= KEEP and self._sent.history(self._acked) is not None)

    def _reference(self, first: int, count: int) -> int | None:
        """The frame a packet of ``count`` frames from ``first`` is predicted from, or None for a
        keyframe."""
        if self._since_key is None:
            return None
        if self.lossy and self._relying():
            return self._acked
        previous = (first - 1) % WRAP
        heard = self._since_ack <= ACK_SECONDS * self.rate  # a receiver answers: no keyframes needed unasked
        if (not heard and self._since_key + count > self.key_every) or self._sent.history(previous) is None:
            return None
        return previous


def key_request(sequence: int, key: bytes | StreamKey | None, stream: int = 0) -> bytes:
    """The datagram a receiver sends back to stream ``stream``'s sender to ask for a keyframe."""
    return seal(Header(KEY_REQUEST, sequence, 0, 0, 0, DEFAULT_STEPS, 1.0, stream=stream), b"", key)


def is_key_request(datagram: bytes, key: bytes | StreamKey | None) -> bool:
    """Whether ``datagram`` is a valid keyframe request (checked like any packet)."""
    try:
        header, _ = open_packet(datagram, key)
    except WireError:
        return False
    return header.key_request


def read_ack(datagram: bytes, key: bytes | StreamKey | None, frame: int = 0) -> tuple[int, int, bool] | None:
    """A valid acknowledgement's frame (restored nearest to ``frame``: the sender's next), its
    bits of frames held before it and whether the receiver saw a loss lately (see
    :meth:`StreamWriter.acknowledge`); None for anything else."""
    try:
        header, _ = open_packet(datagram, key, Anchor(0, frame))
    except WireError:
        return None
    return (header.first_frame, header.time_ms, bool(header.flags & LOSS_SEEN)) if header.ack else None


def behind(index: int, reference: int) -> bool:
    """Frame ``index`` is at or before ``reference`` (modulo wrap)."""
    return (reference - index) % WRAP < WRAP // 2
