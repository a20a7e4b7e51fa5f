"""The motor stream's wire format: packets of quantised, predicted, arithmetic-coded motor frames.

One UDP datagram is one packet::

    offset size field
    0      2    magic b"TF"
    2      1    version (5)
    3      1    flags: 1 = the first frame is a keyframe, 2 = sealed with a key (below),
                       4 = a keyframe request (receiver to sender; no frames),
                       8 = an acknowledgement (receiver to sender; no frames),
                       16 = the frames carry parameters beyond the 21 (see below),
                       32 = this keyframe packet names them
    4      2    stream id (u16): the sender's, so that one receiver tells several performers
                apart (through a relay too); a receiver's replies carry the id they answer
    6      4    sequence number of the packet (u32, wraps)
    10     4    index of the packet's first frame (u32, wraps); in an acknowledgement, the
                newest frame the receiver holds with its whole history
    14     4    capture time of the first frame, sender's clock, microseconds (u32, wraps); in
                an acknowledgement, which of the 32 frames before that frame the receiver
                holds (bit i: the frame i + 1 before it)
    18     1    frames in the packet, 0..32
    19     1    quantisation steps S (motor value v is sent as round(v * S), 0..S)
    20     2    frame rate, 1/100 Hz (u16)
    22     1    reference: how many frames before the first frame the frame it is predicted
                from lies (1: the frame just before; 0 in a keyframe)
    23     ...  with flags 16 and 32 (a keyframe packet), the parameters' list (1 byte: its
                length L; L bytes: the codes in ASCII, one space between, ``HT UL``); with
                flag 16 alone in a keyframe packet, the list's check (1 byte: the low byte
                of its CRC-32); any other packet sets flag 16 and carries the list of the
                keyframe its chain began with
    ...    ...  the coded frames
    end-T  T    tag: CRC-32 of all before it (T = 4); or, sealed with a shared key (flag 2),
                the AEAD's tag (T = 16) and everything after the header is encrypted

With a key (a shared secret of at least 16 bytes), a packet is sealed with AES-256-GCM-SIV
(RFC 8452) under a key derived from the secret by HKDF-SHA256: the header travels in clear (a
relay and a receiver of several performers sort packets by its stream id) but is authenticated
as associated data, so a packet whose stream id, sequence or frame index was changed is refused;
the parameters and coded frames are encrypted. The nonce is the header's flags, stream id,
sequence, first frame and the low byte of its time, which differ from packet to packet of one
sender and between the two directions (flags); GCM-SIV is chosen over ChaCha20-Poly1305 or
AES-GCM because a repeated nonce (two senders started with the same stream id and sequence, a
chance of about one in 2^48 per pair) then reveals only that two packets were identical, not the
key stream. Replays of whole packets are refused by the reader (:mod:`stream.reader`).

All integers are little-endian. The default S = 100 makes the quantisation error at most 0.5 %
of a motor's range (log2(101) = 6.66 bits a value before coding).

Parameters beyond the 21 (a face's own, :data:`toon.motors.STANDARD_EXTRAS`: HT, UL...) are
columns after the 21, quantised and coded exactly as motors are. A stream of the 21 alone sets
no flag 16 and is byte for byte what it was before parameters came. One with parameters names
them in its first keyframe packet and in each keyframe asked for; other keyframes carry a
one-byte check of the list, so that a receiver that joins late, or lost the packet that named
them, sees that it does not know them and asks for a keyframe (as for a lost reference), which
names them.

Coding: a keyframe's 21 values are coded with a flat model (all S + 1 levels alike), and its
parameters beyond the 21 as residuals from their rest (:func:`toon.motors.extra_rest`) under the
widest model below, since they mostly rest. Every
other value is predicted from the motor's three previous frames. Its *activity* is the size of
its last two steps, ``|d1| + |d2|`` with ``d1 = q[f-1] - q[f-2]`` and ``d2 = q[f-2] - q[f-3]``
(steps before a keyframe count as 0). Below :data:`HOLD_BELOW` steps of activity the motor is
taken to be still and predicted to stay at ``q[f-1]`` (its steps are mostly noise, which a
continuation would amplify); otherwise by a damped continuation
``q[f-1] + floor((5 d1 + 2 d2 + 5) / 10)``, clipped to 0..S. A packet's first frame follows its
reference frame and the two before it (its *history*, cut at the keyframe its chain began
with); where the reference lies further back than the frame just before, the frames between are
stood in for by that same prediction run on, at both ends alike (:func:`bridge`). The residual
is arithmetic coded (:mod:`stream.rangecode`) under a two-sided geometric model chosen by the
activity (0 to 5 or more steps): a still motor costs a fraction of a bit. The threshold, the
damping and the models were fitted on the synthetic performer's live-mapped motors; on two real
facial takes mapped live (AnimFace) the residuals' entropy under them is 20 % below version 2's
(a continuation always).

Loss (see :mod:`stream.packets`): a receiver acknowledges the newest frame it holds and which
of the 32 before it it holds; the sender predicts from the newest of them held with its whole
history, and once acknowledgements show loss it sends each frame at once, repeating in each
packet the frame before it if that is not yet acknowledged. A packet's frames are consecutive;
a receiver keeps the first copy of a frame it already holds. Without acknowledgements a packet
continues the chain of the packet before: the sender starts a packet with a keyframe at least
every ``key_seconds`` (0.5 s by default) and whenever the receiver asks (flag 4).
"""

from __future__ import annotations

import hmac
import struct
import zlib
from dataclasses import dataclass

import numpy as np
from cryptography.exceptions import InvalidTag
from cryptography.hazmat.primitives import hashes
from cryptography.hazmat.primitives.ciphers.aead import AESGCMSIV
from cryptography.hazmat.primitives.kdf.hkdf import HKDF

from stream.rangecode import Decoder, Encoder, Model
from toon import N_MOTORS
from toon.motors import extra_rest

MAGIC = b"TF"
VERSION = 5
KEYFRAME, AUTHENTICATED, KEY_REQUEST, ACK, PARAMS, NAMED = 1, 2, 4, 8, 16, 32
#: The most parameters beyond the 21 a stream carries.
MAX_EXTRA = 32
HEADER = struct.Struct("<2sBBHIIIBBHB")
#: Where the stream id lies, for a relay or a receiver that sorts packets by it before reading them.
STREAM_ID = struct.Struct("<H")
STREAM_ID_OFFSET = 4
MAX_FRAMES = 32
CRC_SIZE, SEAL_SIZE = 4, 16
#: Header bytes that make a sealed packet's nonce: flags, stream id, sequence, first frame, time's low byte.
NONCE = slice(3, 15)
#: The largest packet either end accepts: a full packet of keyframe-sized frames, with room.
MAX_PACKET = HEADER.size + MAX_FRAMES * N_MOTORS * 2 + SEAL_SIZE + 64 + MAX_EXTRA * (MAX_FRAMES * 2 + 17)
DEFAULT_STEPS = 100
#: Per-step decay of the residual model for each activity context (0..5 steps), fitted by maximum
#: likelihood on 60 s of the synthetic performer's live-mapped motors (0.2 mm noise).
CONTEXT_DECAY = (0.09, 0.21, 0.30, 0.45, 0.53, 0.66)
#: A motor whose last two steps add up to fewer levels than this is predicted to stay put.
HOLD_BELOW = 3


class WireError(ValueError):
    """A packet that cannot be read; ``reason`` is one word for the counters
    (``size``, ``magic``, ``version``, ``tag``, ``malformed``)."""

    def __init__(self, reason: str, message: str) -> None:
        super().__init__(message)
        self.reason = reason


@dataclass(frozen=True)
class Header:
    """A packet's fixed fields (see the module's table)."""

    flags: int
    sequence: int
    first_frame: int
    time_us: int
    count: int
    steps: int
    rate: float
    back: int = 1
    stream: int = 0

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


def pack_params(codes: tuple[str, ...], keyframe: bool, named: bool) -> bytes:
    """The parameter section of a packet whose frames carry ``codes`` after the 21: in a keyframe
    packet their list (``named``, flag 32) or its check; nothing in any other."""
    if not codes or not keyframe:
        return b""
    text = " ".join(codes).encode("ascii")
    return bytes([len(text)]) + text if named else bytes([params_check(codes)])


def params_check(codes: tuple[str, ...]) -> int:
    """The one-byte check of a list of parameters (the low byte of its text's CRC-32)."""
    return zlib.crc32(" ".join(codes).encode("ascii")) & 0xFF


def unpack_params(header: Header, body: bytes) -> tuple[tuple[str, ...] | int | None, bytes]:
    """A keyframe packet's parameters beyond the 21, their list (flag 32; empty without flag 16)
    or its check (an int), and the coded frames after it; any other packet's body as it is,
    and None: its chain's keyframe's list holds."""
    if not header.keyframe:
        return None, body
    if not header.params:
        return (), body
    if not body:
        raise WireError("malformed", "a keyframe packet with parameters and no list or check of them")
    if not header.flags & NAMED:
        return body[0], body[1:]
    size = body[0]
    try:
        codes = tuple(body[1:1 + size].decode("ascii").split(" "))
    except UnicodeDecodeError:
        raise WireError("malformed", "a parameter list that is not ASCII") from None
    if size == 0 or len(body) < 1 + size or len(codes) > MAX_EXTRA or not all(codes):
        raise WireError("malformed", "a parameter list that does not fit its packet")
    return codes, body[1 + size:]


class Models:
    """The static coding models for one quantisation (built once per ``steps``)."""

    def __init__(self, steps: int) -> None:
        self.steps = steps
        self.flat = Model([1] * (steps + 1))
        self.residual = [Model.laplace(2 * steps + 1, steps, decay) for decay in CONTEXT_DECAY]


def seal(header: Header, body: bytes, key: bytes | None) -> bytes:
    """Header, body and tag as one datagram."""
    flags = header.flags | (AUTHENTICATED if key else 0)
    head = HEADER.pack(MAGIC, VERSION, flags, header.stream & 0xFFFF, header.sequence & 0xFFFFFFFF,
                       header.first_frame & 0xFFFFFFFF,
                       header.time_us & 0xFFFFFFFF, header.count, header.steps, int(round(header.rate * 100)),
                       0 if header.flags & KEYFRAME else header.back)
    if key:
        return head + _aead(key).encrypt(head[NONCE], body, head)
    return head + body + _crc(head + body)


def open_packet(data: bytes, key: bytes | None) -> tuple[Header, bytes]:
    """Check a datagram's size, magic, version and tag; returns its header and coded body.

    Raises
    ------
    WireError
        Saying what is wrong; with a ``key``, a packet not sealed with it is refused (reason
        ``tag``), and without one, a sealed packet is too (it cannot be read).
    """
    if len(data) > MAX_PACKET or len(data) < HEADER.size + CRC_SIZE:
        raise WireError("size", f"a packet of {len(data)} bytes (must be {HEADER.size + CRC_SIZE}..{MAX_PACKET})")
    magic, version, flags, stream, sequence, first, time_us, count, steps, rate, back = HEADER.unpack_from(data)
    if magic != MAGIC:
        raise WireError("magic", f"not a toonface stream packet (magic {magic!r})")
    if version != VERSION:
        raise WireError("version", f"stream version {version} (this reads {VERSION})")
    if bool(flags & AUTHENTICATED) != bool(key):
        raise WireError("tag", "an unsealed packet" if key else "a sealed packet and no key to open it")
    size = SEAL_SIZE if key else CRC_SIZE
    if len(data) < HEADER.size + size:
        raise WireError("size", f"a packet of {len(data)} bytes has no room for its tag")
    head = data[:HEADER.size]
    if key:
        try:
            body = _aead(key).decrypt(head[NONCE], data[HEADER.size:], head)
        except InvalidTag:
            raise WireError("tag", "the packet does not open with this key (another key, corrupted or forged)") \
                from None
    elif not hmac.compare_digest(data[-size:], _crc(data[:-size])):
        raise WireError("tag", "the packet's CRC does not match (corrupted)")
    else:
        body = data[HEADER.size:-size]
    if count > MAX_FRAMES or steps < 1 or rate == 0 or (count and not flags & KEYFRAME and back == 0):
        raise WireError("malformed", f"a header with {count} frames, {steps} steps, rate {rate / 100:g}, "
                                     f"reference {back}")
    return Header(flags, sequence, first, time_us, count, steps, rate / 100.0, back, stream), body


def peek_stream(data: bytes) -> int | None:
    """The stream id of what looks like a packet of this version (None otherwise), unchecked:
    for sorting packets by performer before each stream's reader checks them."""
    if len(data) < HEADER.size or data[:2] != MAGIC or data[2] != VERSION:
        return None
    return int(STREAM_ID.unpack_from(data, STREAM_ID_OFFSET)[0])


def _crc(data: bytes) -> bytes:
    return struct.pack("<I", zlib.crc32(data))


def _aead(secret: bytes) -> AESGCMSIV:
    """The cipher of a shared secret: AES-256-GCM-SIV under HKDF-SHA256 of it."""
    derived = HKDF(algorithm=hashes.SHA256(), length=32, salt=None, info=b"toonface stream 5").derive(secret)
    return AESGCMSIV(derived)


def encode_frames(levels: np.ndarray, history: np.ndarray, keyframe: bool, models: Models,
                  codes: tuple[str, ...] = ()) -> bytes:
    """Code ``levels`` ``(n, 21 + len(codes))`` (ints in 0..steps; the 21, then the parameters
    ``codes``) after ``history`` ``(h, 21 + len(codes))``, the frames before them (the last 3 are
    used; ignored for a keyframe)."""
    encoder = Encoder()
    chain = [] if keyframe else [row for row in np.asarray(history, dtype=np.int64)[-3:]]
    rests = rest_levels(codes, models.steps)
    for row in np.asarray(levels, dtype=np.int64):
        if not chain:
            for value in row[:N_MOTORS]:
                encoder.encode(int(value), models.flat)
            for value, rest in zip(row[N_MOTORS:].tolist(), rests, strict=True):
                encoder.encode(value - rest + models.steps, models.residual[-1])
        else:
            prediction, context = _predict(chain, models.steps)
            for value, guess, ctx in zip(row.tolist(), prediction.tolist(), context.tolist(), strict=True):
                encoder.encode(value - guess + models.steps, models.residual[ctx])
        chain = [*chain[-2:], row]
    return encoder.finish()


def decode_frames(body: bytes, count: int, history: np.ndarray, keyframe: bool, models: Models,
                  codes: tuple[str, ...] = ()) -> np.ndarray:
    """Inverse of :func:`encode_frames`; raises :class:`WireError` when a value leaves 0..steps
    (the body is not what the header says)."""
    decoder = Decoder(body)
    chain = [] if keyframe else [row for row in np.asarray(history, dtype=np.int64)[-3:]]
    rests = rest_levels(codes, models.steps)
    out = np.empty((count, N_MOTORS + len(codes)), dtype=np.int64)
    for f in range(count):
        if not chain:
            row = [decoder.decode(models.flat) for _ in range(N_MOTORS)]
            row += [rest + decoder.decode(models.residual[-1]) - models.steps for rest in rests]
        else:
            prediction, context = _predict(chain, models.steps)
            row = [guess + decoder.decode(models.residual[ctx]) - models.steps
                   for guess, ctx in zip(prediction.tolist(), context.tolist(), strict=True)]
        out[f] = row
        if out[f].min() < 0 or out[f].max() > models.steps:
            raise WireError("malformed", "a coded value outside the quantisation range")
        chain = [*chain[-2:], out[f]]
    return out


def rest_levels(codes: tuple[str, ...], steps: int) -> list[int]:
    """The levels at which parameters ``codes`` beyond the 21 rest, what a keyframe codes them from."""
    return [int(round(extra_rest(code) * steps)) for code in codes]


def bridge(history: np.ndarray, gap: int, steps: int) -> np.ndarray:
    """``history`` ``(h, C)`` (h <= 3, the reference frame last) run on by ``gap`` predicted
    frames, the last 3 rows: what both ends predict a packet's first frame from when its
    reference lies ``gap`` frames before the frame just before it."""
    history = np.asarray(history, dtype=np.int64)
    chain = [row for row in history[-3:]]
    for _ in range(gap):
        chain = [*chain[-2:], _predict(chain, steps)[0]]
    return np.array(chain[-3:], dtype=np.int64).reshape(-1, history.shape[-1])


def _predict(chain: list[np.ndarray], steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Each motor's predicted level and activity context from the last one to three frames."""
    last = chain[-1]
    d1 = last - chain[-2] if len(chain) > 1 else np.zeros_like(last)
    d2 = chain[-2] - chain[-3] if len(chain) > 2 else np.zeros_like(last)
    activity = np.abs(d1) + np.abs(d2)
    guess = np.where(activity < HOLD_BELOW, last, last + (5 * d1 + 2 * d2 + 5) // 10)
    return np.clip(guess, 0, steps), np.minimum(activity, len(CONTEXT_DECAY) - 1)


def quantise(values: np.ndarray, steps: int = DEFAULT_STEPS) -> np.ndarray:
    """Motor values ``(..., C)`` in [0, 1] as levels 0..steps (NaN and out-of-range clipped)."""
    clean = np.clip(np.nan_to_num(np.asarray(values, dtype=float), nan=0.5), 0.0, 1.0)
    return np.rint(clean * steps).astype(np.int64)
