"""A mouth from the words an English voice says: the opening learned from the sound and its
phones, the shapes from the phones.

The words come from the sound (:func:`capture.voice.recognise_words`, an English recogniser
and its language model) or are given (their phones aligned, :func:`capture.voice.recognise`).
Each frame's phone (or silence) is a presence of 0 or 1, blended over time as shapes are
(:func:`presence`), and beside them how long the vowel heard at the frame lasts
(:func:`words_read`: a long vowel is a stressed or drawn-out one, said with the mouth wider);
the learned model (:func:`capture.voice_model.shipped_words_model`) reads them beside the
voice's normalised spectrum and says how open the mouth is. Where the recogniser hears nothing
and the loud band sits below the gate of :mod:`capture.voice_sound` (a room's tone, silence)
for longer than a pause, the mouth relaxes shut, and it parts as long before the voice starts
again (:func:`words_opening`).

The shapes are Rhubarb's (:data:`capture.voice.VISEMES`): the opening placed on the spread
ladder (A B C D) or, where the phone rounds the lips (E and F phones), on the round one (A F E
D), as :func:`capture.voice_sound.shape_weights` places it; the lips pressed (A, for M B P),
teeth on the lip (G, for F and V) and the tongue up (H, for L) where the phones say so.
"""

from __future__ import annotations

import numpy as np

from capture.voice import PHONE_SHAPES, VISEMES, VOWELS, Phone, blend, one_hot, shape_sequence, speaking
from capture.voice_model import MouthModel, shipped_words_model
from capture.voice_sound import BANDS, GATE, pauses, shape_weights, sound_units

#: The phones whose presence the model reads, silence (anything else) last.
PHONES: tuple[str, ...] = (*sorted(PHONE_SHAPES), "SIL")
#: The name of the column, after the phones', that says how long the vowel heard at a frame lasts
#: (chosen on the 16 training speakers by leave-one-speaker-out, the words model's choices as
#: shipped then: mean r 0.538 -> 0.550, up on 12 clips of 17; in a first look, where it gave
#: 0.545, every phone's length gave 0.543, each phone's presence times its length 0.540, the
#: vowels' rate 0.536, broad classes of phones 0.539, the phones 50-80 ms ahead or behind 0.538).
LENGTH = "VOWEL_LENGTH"
#: What the words model reads of the words (:func:`words_read`): each phone's presence, then the vowel's length.
WORDS_READ: tuple[str, ...] = (*PHONES, LENGTH)
#: A vowel this long (seconds) or longer reads 1 in the :data:`LENGTH` column.
LONG_VOWEL = 0.3
#: Shapes the phones give outright, whatever the opening: lips pressed, teeth on the lip, the tongue up.
_KEPT = (VISEMES.index("A"), VISEMES.index("G"), VISEMES.index("H"))
_ROUND = (VISEMES.index("E"), VISEMES.index("F"))


def presence(phones: list[Phone], frames: int, speech: np.ndarray | None = None,
             names: tuple[str, ...] = PHONES) -> np.ndarray:
    """Each of ``names``' presence per frame, ``(frames, len(names))``, blended over time
    (:func:`capture.voice.blend`): 1 where a phone is heard, the last column (silence) where none
    is or where ``speech`` ``(frames,)`` says there is no voice."""
    index = np.full(frames, len(names) - 1)
    for phone in phones:
        if phone.name in names[:-1]:
            index[phone.frames] = names.index(phone.name)
    if speech is not None:
        index[~speech[:frames]] = len(names) - 1
    rows = np.zeros((frames, len(names)))
    rows[np.arange(frames), index] = 1.0
    return blend(rows)


def vowel_length(phones: list[Phone], frames: int, speech: np.ndarray | None = None) -> np.ndarray:
    """How long the vowel heard at each frame lasts, over :data:`LONG_VOWEL` (1 at most; 0 outside
    vowels and where ``speech`` ``(frames,)`` says there is no voice), blended over time as
    :func:`presence` is, ``(frames,)``.

    Examples
    --------
    >>> got = vowel_length([Phone("AA", 0.1, 0.25), Phone("M", 0.25, 0.4), Phone("IY", 0.4, 0.9)], 100)
    >>> round(float(got[17]), 2), round(float(got[32]), 2), round(float(got[70]), 2)
    (0.5, 0.0, 1.0)
    """
    length = np.zeros(frames)
    for phone in phones:
        if phone.name in VOWELS:
            length[phone.frames] = min((phone.end - phone.start) / LONG_VOWEL, 1.0)
    if speech is not None:
        length[~speech[:frames]] = 0.0
    return blend(length[:, None])[:, 0]


def words_read(phones: list[Phone], frames: int, speech: np.ndarray | None = None,
               names: tuple[str, ...] = WORDS_READ) -> np.ndarray:
    """What a words model whose :attr:`~capture.voice_model.MouthModel.phones` are ``names``
    reads of the words, ``(frames, len(names))``: each phone's :func:`presence` (silence the last
    of them), then, where ``names`` ends with :data:`LENGTH`, the :func:`vowel_length`."""
    if names[-1] != LENGTH:
        return presence(phones, frames, speech, names)
    return np.concatenate([presence(phones, frames, speech, names[:-1]),
                           vowel_length(phones, frames, speech)[:, None]], axis=1)


def words_opening(units: np.ndarray, heard: np.ndarray, model: MouthModel) -> np.ndarray:
    """The opening (0..1) per frame before the blend, ``(frames,)``, from the sound's
    :func:`capture.voice_sound.unit` features ``(frames, 3 + MEL_BANDS)`` and the phones'
    :func:`words_read` ``heard`` ``(frames, len(model.phones))``: the model's, shut where for longer
    than a pause (:data:`~capture.voice_sound.PAUSE_FRAMES`) before and after there are neither
    words nor more than a room's tone (the loud band below :data:`~capture.voice_sound.GATE`)."""
    voiced = (units[:, 0] > GATE) | (heard[:, model.phones.index("SIL")] < 0.5)
    near = pauses(voiced) | pauses(voiced[::-1])[::-1]  # the lips part before a voice starts
    return model.opening(units[:, BANDS:], heard) * blend(near.astype(float))


def words_mouth(samples: np.ndarray, frames: int, phones: list[Phone], model: MouthModel | None = None
                ) -> tuple[np.ndarray, np.ndarray]:
    """A whole sound's mouth from its ``phones``: each shape's weight per frame, ``(frames, 9)``
    in :data:`~capture.voice.VISEMES` order and summing to 1 (what moves the motors), and its
    mouth cue per frame, ``(frames,)`` (the heaviest shape before the last blend: what Rhubarb's
    formats keep), as :func:`capture.voice_sound.sound_mouth` gives them; ``model`` is the
    shipped words model by default."""
    model = model or shipped_words_model()
    units = sound_units(samples, frames)
    speech = speaking(samples, frames)
    open_ = blend(words_opening(units, words_read(phones, frames, speech, model.phones), model))
    shapes = shape_sequence(phones, frames, speech)
    round_ = blend(np.isin(shapes, _ROUND).astype(float))
    weights = shape_weights(np.clip(open_, 0.0, 1.0), np.clip(round_, 0.0, 1.0), pauses(speech))
    kept = np.isin(shapes, _KEPT)
    weights[kept] = one_hot(shapes[kept])
    return blend(weights), np.argmax(weights, axis=1)
