"""The motor stream's framing: each packet's header, its check or seal, and how a short header is
read against what the reader already knows. What the body holds is :mod:`stream.wire`'s.

One UDP datagram is one packet. A packet's header comes in one of two forms (flag 64 says which),
and both stand for the same full header (:class:`Header`), which the check covers::

    long form (22 bytes)                         short form (5 or 6 bytes)
    offset size field                            offset size field
    0      1    flags                            0      1    flags
    1      2    stream id (u16)                  1      2    stream id (u16)
    3      1    version (5)                      3      1    sequence, its low 8 bits
    4      4    sequence number (u32, wraps)     4      1    first frame, its low 8 bits
    8      4    index of the first frame (u32)   5      1    without flag 128 only: frames
    12     4    capture time of the first frame,             (high 4 bits, 1..15) and reference
                sender's clock, ms (u32, wraps)              (low 4 bits, 0..15)
    16     1    frames in the packet, 0..32
    17     1    frames a packet usually carries (the sender's setting)
    18     1    quantisation steps S
    19     2    frame rate, 1/100 Hz (u16)
    21     1    reference: how many frames before the first frame the frame it is predicted
                from lies (1: the frame just before; 0 in a keyframe)

    then the body (:mod:`stream.wire`), then the check: the low 16 bits of the CRC-32 of the
    full header in its long form (with a time of 0 for a short one) and the body (2 bytes); or,
    sealed with a key (flag 2), the AEAD's 16-byte tag, the body encrypted.

Flags: 1 = the first frame is a keyframe, 2 = sealed with a key, 4 = a keyframe request
(receiver to sender), 8 = an acknowledgement (receiver to sender), 16 = the frames carry
parameters beyond the 21 (in an acknowledgement: the receiver has seen a loss lately), 32 =
this keyframe packet names them, 64 = the long form, 128 = (short form) the packet carries the
usual number of frames and continues from the frame just before it, which most do. All integers
are little-endian.

A sender writes the long form for a keyframe, for a packet whose frames or reference do not fit
a nibble, for its first packet and at least every :data:`LONG_SECONDS`: the short form's fields
are the low bits of the long one's, which a reader restores from the newest packet it read
within :data:`ANCHOR_SECONDS` (the sequence and the frame within 128); a short packet's time is
the one its frame predicts from that packet's at the stream's rate (the sender goes long where
its capture time strays further than a few milliseconds from it), and the frames a packet
usually carries and the stream's steps and rate come from the last long header. Because the
check covers the restored long form, a short packet restored wrongly (a packet from long ago
replayed, a reader that lost track) fails its check instead of being misplaced; a reader with
nothing to restore from drops it (``unanchored``) and asks for a keyframe.

Replies (receiver to sender) have their own short forms: an acknowledgement is flags, stream id,
the newest frame held (low 16 bits, restored by the sender against its own frame count) and which
of the 32 frames before it are held (u32, bit i: the frame i + 1 before); a keyframe request is
flags and stream id. Both end with the check or tag.

With a key (a shared secret of at least 16 bytes) a packet is sealed with AES-256-GCM-SIV (RFC
8452) under a key derived from the secret by HKDF-SHA256: the header travels in clear (a relay,
and a receiver of several performers, sort packets by stream id) and is authenticated, in its
long form, as associated data, so a packet whose stream id or numbers were changed does not open;
the parameters and coded frames are encrypted. The nonce is taken from the full header (flags,
stream id, version, sequence, first frame), different from packet to packet of one sender and
between the two directions. GCM-SIV is chosen over ChaCha20-Poly1305 or AES-GCM
because a repeated nonce (two senders started on the same stream id and sequence) then reveals
only that two packets were identical, not the key stream. Whole packets replayed are refused by
the reader (:mod:`stream.reader`).
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass, replace

from cryptography.exceptions import InvalidTag
from cryptography.hazmat.primitives import hashes
from cryptography.hazmat.primitives.ciphers.aead import AESGCMSIV
from cryptography.hazmat.primitives.kdf.hkdf import HKDF

from toon import N_MOTORS

VERSION = 5
KEYFRAME, SEALED, KEY_REQUEST, ACK, PARAMS, NAMED, LONG, REGULAR = 1, 2, 4, 8, 16, 32, 64, 128
LOSS_SEEN = PARAMS  # in an acknowledgement
LONG_HEADER = struct.Struct("<BHBIIIBBBHB")
SHORT_HEADER = struct.Struct("<BHBB")
SIZES = struct.Struct("<B")
ACK_HEADER = struct.Struct("<BHHI")
REQUEST_HEADER = struct.Struct("<BH")
#: Where the stream id lies in every form, for a relay or a receiver that sorts packets by it.
STREAM_ID = struct.Struct("<H")
STREAM_ID_OFFSET = 1
MAX_FRAMES = 32
#: The most parameters beyond the 21 a stream carries.
MAX_EXTRA = 32
CHECK_SIZE, SEAL_SIZE = 2, 16
UDP_IP_HEADER = 28  # bytes a UDP datagram costs on the wire over IPv4 beyond its payload
#: What a packet costs beyond itself sent as a client's WebSocket message over TCP/IPv4: TCP's and
#: IPv4's 40 bytes (one segment a message) and the frame's 2-byte header and 4-byte mask.
WEBSOCKET_TCP_HEADER = 46
WRAP = 1 << 32
#: The most frames and the furthest reference a short header holds.
SHORT_MOST = 15
#: A sender writes the long form at least this often (seconds of stream).
LONG_SECONDS = 2.0
#: A reader restores a short header against the newest packet it read within this many seconds,
#: and within this many frames of the stream (so that the frame's low 8 bits restore surely).
ANCHOR_SECONDS, ANCHOR_FRAMES = 1.0, 100


class WireError(ValueError):
    """A packet that cannot be read; ``reason`` is one word for the counters
    (``size``, ``version``, ``tag``, ``malformed``, ``unanchored``)."""

    def __init__(self, reason: str, message: str) -> None:
        super().__init__(message)
        self.reason = reason


@dataclass(frozen=True)
class Header:
    """A packet's full header (see the module's table). In an acknowledgement, ``first_frame``
    is the newest frame held and ``time_ms`` which of the 32 before it are."""

    flags: int
    sequence: int
    first_frame: int
    time_ms: int
    count: int
    steps: int
    rate: float
    back: int = 1
    stream: int = 0
    usual: int = 0

    @property
    def keyframe(self) -> bool:
        return bool(self.flags & KEYFRAME)

    @property
    def key_request(self) -> bool:
        return bool(self.flags & KEY_REQUEST)

    @property
    def ack(self) -> bool:
        return bool(self.flags & ACK)

    @property
    def params(self) -> bool:
        return bool(self.flags & PARAMS)

    def fits_short(self) -> bool:
        """Whether a short header can carry it (a keyframe never goes short)."""
        return not self.keyframe and 1 <= self.count <= SHORT_MOST and self.back <= SHORT_MOST

    @property
    def regular(self) -> bool:
        """Its usual frames, continuing from the frame just before (flag 128 in a short header)."""
        return self.count == self.usual and self.back == 1


@dataclass(frozen=True)
class Anchor:
    """What a short header is restored against: the newest packet's sequence and first frame,
    and the last long header's first frame, time (ms), steps, rate and usual frames (a reader's,
    from the packets it read; a sender restores acknowledgements against its own next frame)."""

    sequence: int
    first_frame: int
    long_frame: int = 0
    time_ms: int = 0
    steps: int = 1
    rate: float = 1.0
    usual: int = 0

    def after(self, header: Header) -> Anchor:
        """The anchor once ``header`` (a packet read, newer than this one's) is: its numbers, and
        where it is long, its time, steps, rate and usual frames."""
        if header.flags & LONG:
            return Anchor(header.sequence, header.first_frame, header.first_frame, header.time_ms, header.steps,
                          header.rate, header.usual)
        return replace(self, sequence=header.sequence, first_frame=header.first_frame)


class StreamKey:
    """A shared secret and the cipher derived from it (AES-256-GCM-SIV under HKDF-SHA256), derived
    once: each end keeps one rather than deriving it again for every packet."""

    def __init__(self, secret: bytes) -> None:
        self.secret = secret
        derived = HKDF(algorithm=hashes.SHA256(), length=32, salt=None, info=b"toonface stream 5").derive(secret)
        self.aead = AESGCMSIV(derived)


def stream_key(key: bytes | StreamKey | None) -> StreamKey | None:
    """``key`` as a :class:`StreamKey` (None stays None)."""
    return key if key is None or isinstance(key, StreamKey) else StreamKey(key)


def seal(header: Header, body: bytes, key: bytes | StreamKey | None, short: bool = False) -> bytes:
    """The datagram of ``header`` (in the short form where asked and it fits; a reply in its own
    form), ``body`` and the check, or sealed with ``key``."""
    flags = header.flags & ~(SEALED | LONG | REGULAR) | (SEALED if key else 0)
    if header.flags & ACK:
        head = ACK_HEADER.pack(flags, header.stream & 0xFFFF, header.first_frame & 0xFFFF, header.time_ms & 0xFFFFFFFF)
        header = _reply(flags, header.stream, header.first_frame, header.time_ms)
    elif header.flags & KEY_REQUEST:
        head = REQUEST_HEADER.pack(flags, header.stream & 0xFFFF)
        header = _reply(flags, header.stream)
    elif short and header.fits_short():
        flags |= REGULAR if header.regular else 0
        head = SHORT_HEADER.pack(flags, header.stream & 0xFFFF, header.sequence & 0xFF, header.first_frame & 0xFF)
        head += b"" if header.regular else SIZES.pack(header.count << 4 | header.back)
        header = replace(header, time_ms=0)  # not sent: the check covers what the reader restores alike
    else:
        flags |= LONG
        head = _long(replace(header, flags=flags))
    full = _long(replace(header, flags=flags))
    if key:
        return head + _aead(key).encrypt(_nonce(full), body, full)
    return head + body + _check(full + body)


def open_packet(data: bytes, key: bytes | StreamKey | None, anchor: Anchor | None = None) -> tuple[Header, bytes]:
    """Check a datagram's form, size, version and check (or seal); returns its full header and
    body. A short header is restored against ``anchor`` (for a reply: the sender's own).

    Raises
    ------
    WireError
        Saying what is wrong; with a ``key``, a packet not sealed with it is refused (reason
        ``tag``), and without one, a sealed packet is too (it cannot be read).
    """
    if len(data) > MAX_PACKET or len(data) < REQUEST_HEADER.size + CHECK_SIZE:
        raise WireError("size", f"a packet of {len(data)} bytes (must be {REQUEST_HEADER.size + CHECK_SIZE}.."
                                f"{MAX_PACKET})")
    flags = data[0]
    if bool(flags & SEALED) != bool(key):
        raise WireError("tag", "an unsealed packet" if key else "a sealed packet and no key to open it")
    header, size = _header(data, flags, anchor)
    tail = SEAL_SIZE if key else CHECK_SIZE
    if len(data) < size + tail:
        raise WireError("size", f"a packet of {len(data)} bytes has no room for its header and tag")
    short = not flags & (LONG | ACK | KEY_REQUEST)
    full = _long(replace(header, time_ms=0) if short else header)  # a short header's time is not sent
    if key:
        try:
            body = _aead(key).decrypt(_nonce(full), data[size:], full)
        except InvalidTag:
            raise WireError("tag", "the packet does not open with this key (another key, corrupted, forged or "
                                   "replayed)") from None
    else:
        body = data[size:-tail]
        if data[-tail:] != _check(full + body):
            raise WireError("tag", "the packet's check does not match (corrupted, or replayed from long ago)")
    if header.count > MAX_FRAMES or header.steps < 1 or header.rate <= 0 \
            or (header.count and not header.keyframe and header.back == 0):
        raise WireError("malformed", f"a header with {header.count} frames, {header.steps} steps, rate "
                                     f"{header.rate:g}, reference {header.back}")
    return header, body


def peek_stream(data: bytes) -> int | None:
    """The stream id of what may be a packet (None for a datagram too short), unchecked: for
    sorting packets by performer before each stream's reader checks them."""
    if len(data) < STREAM_ID_OFFSET + STREAM_ID.size:
        return None
    return int(STREAM_ID.unpack_from(data, STREAM_ID_OFFSET)[0])


def _header(data: bytes, flags: int, anchor: Anchor | None) -> tuple[Header, int]:
    """The full header a datagram starts with, and the bytes it took."""
    if flags & ACK:
        _, stream, frame, held = _unpack(ACK_HEADER, data)
        near = anchor.first_frame if anchor is not None else 0
        return _reply(flags, stream, _restore(frame, near, 16), held), ACK_HEADER.size
    if flags & KEY_REQUEST:
        _, stream = _unpack(REQUEST_HEADER, data)
        return _reply(flags, stream), REQUEST_HEADER.size
    if flags & LONG:
        _, stream, version, sequence, first, time_ms, count, usual, steps, rate, back = _unpack(LONG_HEADER, data)
        if version != VERSION:
            raise WireError("version", f"stream version {version} (this reads {VERSION})")
        return (Header(flags, sequence, first, time_ms, count, steps, rate / 100.0, back, stream, usual),
                LONG_HEADER.size)
    if anchor is None:
        raise WireError("unanchored", "a short header and no packet before it to read it against")
    _, stream, sequence, frame = _unpack(SHORT_HEADER, data)
    size = SHORT_HEADER.size
    if flags & REGULAR:
        count, back = anchor.usual, 1
    else:
        (sizes,) = _unpack(SIZES, data[size:])
        count, back, size = sizes >> 4, sizes & 0xF, size + 1
    first = _restore(frame, anchor.first_frame, 8)
    time_ms = (anchor.time_ms + round(_signed(first - anchor.long_frame, 32) * 1000 / anchor.rate)) % WRAP
    return Header(flags, _restore(sequence, anchor.sequence, 8), first, time_ms, count, anchor.steps, anchor.rate,
                  back, stream, anchor.usual), size


def _reply(flags: int, stream: int, frame: int = 0, held: int = 0) -> Header:
    """The full header a reply stands for (what its check covers)."""
    return Header(flags, 0, frame % WRAP, held, 0, 1, 1.0, 0, stream & 0xFFFF)


def _unpack(form: struct.Struct, data: bytes) -> tuple:
    if len(data) < form.size:
        raise WireError("size", f"a packet of {len(data)} bytes is shorter than its header")
    return form.unpack_from(data)


def _restore(low: int, near: int, bits: int) -> int:
    """The u32 whose low ``bits`` are ``low``, nearest to ``near``."""
    step = (low - near) % (1 << bits)
    return (near + _signed(step, bits)) % WRAP


def _signed(value: int, bits: int) -> int:
    value %= 1 << bits
    return value - (1 << bits) if value >= 1 << (bits - 1) else value


def _long(header: Header) -> bytes:
    return LONG_HEADER.pack((header.flags | LONG) & ~REGULAR, header.stream & 0xFFFF, VERSION, header.sequence % WRAP,
                            header.first_frame % WRAP, header.time_ms % WRAP, header.count, header.usual,
                            header.steps, int(round(header.rate * 100)), 0 if header.flags & KEYFRAME else header.back)


def _nonce(full: bytes) -> bytes:
    """Flags, stream id, version, sequence and first frame of a long header."""
    return full[0:12]


def _check(data: bytes) -> bytes:
    return struct.pack("<H", zlib.crc32(data) & 0xFFFF)


def _aead(key: bytes | StreamKey) -> AESGCMSIV:
    """The cipher of a key (derived here only for a secret given as bytes)."""
    return key.aead if isinstance(key, StreamKey) else StreamKey(key).aead


#: The largest packet either end accepts: a full packet of keyframe-sized frames, with room.
MAX_PACKET = LONG_HEADER.size + MAX_FRAMES * N_MOTORS * 2 + SEAL_SIZE + 64 + MAX_EXTRA * (MAX_FRAMES * 2 + 17)
