"""The motor stream's wire format: packets of quantised, predicted, arithmetic-coded motor frames.

The header of each packet, its check and its seal are :mod:`stream.framing`'s; this module is
what a packet's body holds: the parameters' list (or its check) in a keyframe packet, then the
coded frames. The default S = 100 makes the quantisation error at most 0.5 % of a motor's range
(log2(101) = 6.66 bits a value before coding).

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

Loss is :mod:`stream.packets`' (which frame a packet is predicted from, what it repeats, when
a keyframe comes): a packet's frames are consecutive, and a receiver keeps the first copy of a
frame it already holds.
"""

from __future__ import annotations

import zlib

import numpy as np

from stream.framing import MAX_EXTRA, NAMED, Header, WireError
from stream.rangecode import Decoder, Encoder, Model
from toon import N_MOTORS
from toon.motors import extra_rest

DEFAULT_STEPS = 100
#: Per-step decay of the residual model for each activity context (0..5 steps), fitted by maximum
#: likelihood on 60 s of the synthetic performer's live-mapped motors (0.2 mm noise).
CONTEXT_DECAY = (0.09, 0.21, 0.30, 0.45, 0.53, 0.66)
#: A motor whose last two steps add up to fewer levels than this is predicted to stay put.
HOLD_BELOW = 3


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
