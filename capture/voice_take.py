"""A voice heard as a whole: the one way every command turns a sound file (or a video's sound)
into mouth shapes and a take.

Four ways to hear it (:data:`LISTEN_MODES`, ``--listen``): from the spectrum alone, in any
language (:mod:`capture.voice_sound`, the default); from the words an English recogniser hears
(:mod:`capture.voice_words`: the opening learned from the sound and those words' phones); from
pocketsphinx's phone loop (:mod:`capture.voice`); and, given the words (``--text``), from
their phones aligned with the sound, opened as the words model says.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from capture.take import Take
from capture.voice import (
    FRAME_RATE,
    SAMPLE_RATE,
    VISEMES,
    Phone,
    decode_voice_at,
    recognise,
    recognise_words,
    shape_curves,
    shape_sequence,
    speaking,
)
from capture.voice_pitch import pitch_hz, semitones
from capture.voice_sound import sound_mouth
from capture.voice_text import align_text
from capture.voice_words import words_mouth
from common import InputError


@dataclass(frozen=True, eq=False)
class Heard:
    """What a voice says: its sound (16 kHz mono, ``(n,)``), the phones heard, the mouth
    shape of each 10 ms frame (``shapes`` ``(frames,)``, indices into :data:`VISEMES`: its
    mouth cues), where the sound starts on its video's clock (``start``, seconds; 0 for a
    sound file), and each shape's weight per frame where the sound weighs them between two
    shapes (``weights`` ``(frames, 9)``; otherwise :func:`shape_curves` of ``shapes``)."""

    samples: np.ndarray
    phones: list[Phone]
    shapes: np.ndarray
    start: float = 0.0
    weights: np.ndarray | None = None
    notes: tuple[str, ...] = ()  # how words given were aligned (capture.voice_text)

    def curves(self) -> np.ndarray:
        """Each shape's weight per frame, ``(frames, 9)``: what moves the motors."""
        return shape_curves(self.shapes) if self.weights is None else self.weights


#: How a voice is heard (``--listen``): ``sound`` its spectrum alone, in any language
#: (:mod:`capture.voice_sound`); ``words`` the words an English recogniser hears in it, their
#: phones and its spectrum opening the mouth as learned (:mod:`capture.voice_words`: about twice
#: real time, the closest to real lips on English); ``phones`` pocketsphinx's US-English phone
#: loop. Given the words (``--text``), their phones are aligned and the mouth opens as ``words``.
LISTEN_MODES = ("sound", "words", "phones")


def mouth_of(samples: np.ndarray, text: str | None = None, listen: str = "sound", notes: list[str] | None = None
             ) -> tuple[list[Phone], np.ndarray, np.ndarray | None]:
    """The mouth of a whole sound ``samples`` (16 kHz mono) heard as :data:`LISTEN_MODES` says:
    the phones heard (none from the sound alone), each 10 ms frame's mouth cue ``(frames,)``
    (indices into :data:`~capture.voice.VISEMES`) and, where the sound weighs a frame between
    shapes, each shape's weight ``(frames, 9)`` (None: the cues blended). What the user should
    know of how words given were aligned (:func:`capture.voice_text.align_text`) is appended to
    ``notes``.

    Raises
    ------
    InputError
        For an unknown ``listen`` (the caller names the file).
    """
    notes = [] if notes is None else notes
    if listen not in LISTEN_MODES:
        raise InputError(f"unknown way to listen {listen!r} (known: {', '.join(LISTEN_MODES)})")
    frames = max(2, int(len(samples) * FRAME_RATE // SAMPLE_RATE))
    if text is None and listen == "sound":
        weights, shapes = sound_mouth(samples, frames)
        return [], shapes, weights
    if text is None and listen == "phones":
        phones = recognise(samples)
        return phones, shape_sequence(phones, frames, speaking(samples, frames)), None
    if text is None:
        phones = recognise_words(samples)
    else:
        aligned = align_text(samples, text)
        phones = aligned.phones
        notes.extend(aligned.notes)
        if not phones:  # nothing aligned: the sound alone, as the notes say
            weights, shapes = sound_mouth(samples, frames)
            return [], shapes, weights
    weights, shapes = words_mouth(samples, frames, phones)
    return phones, shapes, weights


def hear_voice(path: str | os.PathLike, text: str | None = None, listen: str = "sound") -> Heard:
    """Decode ``path``'s sound and place the mouth shapes (:func:`mouth_of`): the one way every
    command hears a voice (errors name the file)."""
    samples, start = decode_voice_at(path)
    notes: list[str] = []
    try:
        phones, shapes, weights = mouth_of(samples, text, listen, notes)
    except InputError as exc:
        raise InputError(exc.message, path, exc.field) from None
    return Heard(samples, phones, shapes, start, weights, tuple(notes))


def read_voice(path: str | os.PathLike, text: str | None = None, listen: str = "sound") -> Take:
    """A voice as a take with no markers: at 100 Hz, a channel per mouth shape,
    ``viseme_A`` ... ``viseme_X`` (each shape's weight, 0..1, summing to 1), the sound's
    level, ``sound_level`` (0..1), by which a rest window is chosen in silence, and its pitch,
    ``voice_pitch`` (semitones above 55 Hz, 0 unvoiced: :mod:`capture.voice_pitch`), from which
    the life layer (:mod:`mapping.life`) raises the brows. Times are on
    the clock of a video's first frame (a video's sound may start before or after it)."""
    heard = hear_voice(path, text, listen)
    frames, samples = len(heard.shapes), heard.samples
    curves = heard.curves()
    hop = int(SAMPLE_RATE / FRAME_RATE)
    level = np.sqrt(np.mean(np.resize(np.pad(samples, (0, frames * hop)), frames * hop).reshape(frames, hop) ** 2,
                            axis=1))
    level = level / max(float(level.max()), 1e-9)
    pitch = semitones(pitch_hz(samples, frames))
    channels = np.column_stack([curves, level, pitch])
    names = (*(f"viseme_{v}" for v in VISEMES), "sound_level", "voice_pitch")
    return Take(np.zeros((frames, 0, 3)), (), FRAME_RATE, times=heard.start + np.arange(frames) / FRAME_RATE,
                channels=channels, channel_names=names,
                meta={"source": "voice", "file": Path(path).name, "words": text, "phones": len(heard.phones),
                      "listen": "words" if text else listen, "notes": list(heard.notes)})
