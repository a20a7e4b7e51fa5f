"""A voice as performer data: the phones spoken and when, turned into mouth shapes over time.

Offline and without a network: pocketsphinx (BSD-2-Clause, its US-English acoustic model,
dictionary and phone language model inside its wheel) recognises the phones, either freely
(a phone loop: any speech, no words needed) or, given the words, by forced alignment, which
places each phone of the known words and is much surer. A voice-activity step keeps silence
silent whatever the recogniser heard in it.

Each phone is one of Rhubarb Lip Sync's mouth shapes (:data:`VISEMES`, the animators' common
set: A closed for M B P, B slightly open for most consonants and EE, C open for EH and AE,
D wide open for AA, E rounded for AO and ER, F puckered for UW, OW and W, G teeth on lip for
F and V, H the tongue up for L, X at rest). Shapes then follow each other as a mouth does
(:func:`shape_curves`): a vowel is anticipated, a shape is held at least a little, a short pause
keeps the shape before it, a long one relaxes to rest, and the change between shapes is a
smooth blend, never a jump.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from common import InputError

#: Rhubarb Lip Sync's mouth shapes, in its order.
VISEMES = ("A", "B", "C", "D", "E", "F", "G", "H", "X")
#: Each ARPAbet phone of pocketsphinx's US-English model as a mouth shape; anything else (SIL,
#: noises) is rest.
PHONE_SHAPES: dict[str, str] = {
    **dict.fromkeys(("M", "B", "P"), "A"),
    **dict.fromkeys(("K", "G", "T", "D", "N", "NG", "S", "Z", "SH", "ZH", "CH", "JH", "TH", "DH", "HH", "Y", "IY",
                     "IH"), "B"),
    **dict.fromkeys(("EH", "AE", "EY", "AH"), "C"),
    **dict.fromkeys(("AA", "AW", "AY"), "D"),
    **dict.fromkeys(("AO", "ER", "UH", "R", "OY"), "E"),
    **dict.fromkeys(("UW", "OW", "W"), "F"),
    **dict.fromkeys(("F", "V"), "G"),
    "L": "H",
}
VOWELS = frozenset({"AA", "AE", "AH", "AO", "AW", "AY", "EH", "ER", "EY", "IH", "IY", "OW", "OY", "UH", "UW"})
#: How open the mouth is in each shape (0 shut .. 1 wide): what a jaw motor follows.
OPENNESS: dict[str, float] = {"A": 0.0, "B": 0.15, "C": 0.5, "D": 0.9, "E": 0.4, "F": 0.25, "G": 0.1, "H": 0.35,
                              "X": 0.0}
#: The recogniser's frame rate (Hz): one frame per 10 ms.
FRAME_RATE = 100.0
SAMPLE_RATE = 16000
#: A vowel's shape starts this long before its sound (s): the lips get there first.
ANTICIPATE_S = 0.04
#: No shape is held for less than this (s): a shorter one is merged into the one before.
MIN_HOLD_S = 0.03
#: A pause shorter than this (s) keeps the shape before it; a longer one relaxes to rest.
SHORT_PAUSE_S = 0.2
#: The blend between shapes over time: a Gaussian of 25 ms cut at ±50 ms, so a live voice
#: waits no more than those 50 ms for a blend (:func:`blend`).
KERNEL = np.exp(-0.5 * (np.arange(-5, 6) / 2.5) ** 2) / np.exp(-0.5 * (np.arange(-5, 6) / 2.5) ** 2).sum()
LOOKAHEAD = (len(KERNEL) - 1) // 2
#: Voice activity: a frame is speech when its level is within this many dB of the loud part of
#: the sound (its 95th percentile) and above the quiet part (5th percentile) by at least half
#: of the way.
SPEECH_RANGE_DB = 35.0
#: ... and above this level (dB of full scale): digital silence, or a hum that quiet, is never
#: speech, whatever its own loud and quiet parts (which silence alone does not have).
SILENT_DB = -70.0


@dataclass(frozen=True)
class Phone:
    """A phone heard: its ARPAbet ``name`` and when, seconds (``end`` exclusive), and the word it
    belongs to where the words were given (``word``, empty otherwise)."""

    name: str
    start: float
    end: float
    word: str = ""

    @property
    def frames(self) -> slice:
        """The 10 ms frames it spans (:data:`FRAME_RATE`), the nearest to its start and end, none
        before the first."""
        return slice(max(int(round(self.start * FRAME_RATE)), 0), max(int(round(self.end * FRAME_RATE)), 0))


def decode_voice(path: str | os.PathLike) -> np.ndarray:
    """The sound of ``path`` (a sound file or a video with sound), mono, 16 kHz, float32 in
    -1..1; an :class:`~common.InputError` when it has none."""
    return decode_voice_at(path)[0]


def decode_voice_at(path: str | os.PathLike) -> tuple[np.ndarray, float]:
    """:func:`decode_voice`, and where the sound starts on the clock of the file's first video
    frame (seconds; 0 for a sound file): the clock a face tracked in the same video keeps."""
    from common.sound import decode_mono

    samples, _, start = decode_mono(Path(path), SAMPLE_RATE)
    if not len(samples):
        raise InputError("no sound in it", path)
    return samples, start


def recognise(samples: np.ndarray) -> list[Phone]:
    """The phones in ``samples`` (16 kHz mono), freely (a phone loop). The decoder is made
    afresh for each sound (0.2 s): one kept and reused gave other phones for the same sound
    after other sounds, even with its cepstral mean reset or computed per utterance. Words given
    are aligned by :func:`capture.voice_text.align_text`."""
    from pocketsphinx import Decoder, get_model_path

    pcm = pcm16(samples)
    model = Path(get_model_path()) / "en-us"
    decoder = Decoder(allphone=str(model / "en-us-phone.lm.bin"), lw=2.0, pip=0.3, beam=1e-20, pbeam=1e-20,
                      samprate=SAMPLE_RATE, loglevel="FATAL")
    _decode(decoder, pcm)
    return [Phone(s.word, s.start_frame / FRAME_RATE, (s.end_frame + 1) / FRAME_RATE)
            for s in decoder.seg() or ()]  # (None where it heard nothing at all)


def recognise_words(samples: np.ndarray) -> list[Phone]:
    """The phones of the words an English recogniser hears in ``samples`` (16 kHz mono): the
    words found with pocketsphinx's US-English language model (the decoder Rhubarb Lip Sync
    uses), then their phones placed by forced alignment of those words, each phone naming its
    word. Where the alignment fails, each word's phones share its time evenly. About twice as
    fast as real time on one core; noises and silence are left out."""
    from pocketsphinx import Decoder

    pcm = pcm16(samples)
    decoder = Decoder(samprate=SAMPLE_RATE, loglevel="FATAL")
    _decode(decoder, pcm)
    heard = [(s.word, s.start_frame, s.end_frame + 1) for s in decoder.seg() or ()
             if not s.word.startswith(("<", "[")) and decoder.lookup_word(s.word)]
    if not heard:
        return []
    try:
        return aligned_phones(decoder, pcm, " ".join(word.split("(")[0] for word, _, _ in heard))
    except (RuntimeError, ValueError):
        out = []
        for word, start, end in heard:
            said = str(decoder.lookup_word(word)).split()
            span = (end - start) / FRAME_RATE / len(said)
            out += [Phone(name, start / FRAME_RATE + k * span, start / FRAME_RATE + (k + 1) * span,
                          word.split("(")[0]) for k, name in enumerate(said)]
        return out


def pcm16(samples: np.ndarray) -> bytes:
    """``samples`` (-1..1, clipped) as 16-bit PCM bytes, what pocketsphinx hears."""
    return (np.clip(samples, -1.0, 1.0) * 32767).astype(np.int16).tobytes()


def _decode(decoder, pcm: bytes) -> None:
    decoder.start_utt()
    decoder.process_raw(pcm, full_utt=True)
    decoder.end_utt()


def aligned_phones(decoder, pcm: bytes, words: str) -> list[Phone]:
    """The phones of ``words`` placed in the sound ``pcm`` by ``decoder`` (with its dictionary);
    pocketsphinx's RuntimeError or ValueError where they cannot be
    (:func:`capture.voice_text.align_text` never fails so)."""
    decoder.set_align_text(words)
    _decode(decoder, pcm)
    decoder.set_alignment()
    _decode(decoder, pcm)
    return [Phone(p.name, p.start / FRAME_RATE, (p.start + p.duration) / FRAME_RATE, w.name)
            for w in decoder.get_alignment() for p in w]


def speaking(samples: np.ndarray, frames: int) -> np.ndarray:
    """Which of ``frames`` 10 ms frames of ``samples`` (16 kHz) hold speech, ``(frames,)`` bool:
    the level (dB, in 20 ms windows) against the sound's own loud and quiet parts."""
    hop = int(SAMPLE_RATE / FRAME_RATE)
    padded = np.pad(samples.astype(np.float64), (hop // 2, frames * hop + hop))
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * hop)[::hop][:frames]
    level = 10 * np.log10(np.mean(windows ** 2, axis=1) + 1e-10)
    loud, quiet = np.percentile(level, 95), np.percentile(level, 5)
    threshold = max(loud - SPEECH_RANGE_DB, (loud + quiet) / 2, SILENT_DB)
    on = level >= threshold
    bridge = int(round(SHORT_PAUSE_S * FRAME_RATE / 2))  # a stop's silence inside a word is not a pause
    return _close_gaps(on, bridge)


def _close_gaps(on: np.ndarray, longest: int) -> np.ndarray:
    out = on.copy()
    runs = _runs(~on)
    for start, end in runs:
        if 0 < start and end < len(on) and end - start <= longest:
            out[start:end] = True
    return out


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True))


def shape_sequence(phones: list[Phone], frames: int, speech: np.ndarray | None = None) -> np.ndarray:
    """The mouth shape of each 10 ms frame, ``(frames,)`` indices into :data:`VISEMES`, with the
    rules of coarticulation (see the module docstring); ``speech`` ``(frames,)`` marks where
    there is voice, rest elsewhere."""
    rest, closed = VISEMES.index("X"), VISEMES.index("A")
    shapes = np.full(frames, rest)
    # closures last: a vowel's early start took the whole of a short M before it ("me": issue 69)
    for phone in sorted(phones, key=lambda p: PHONE_SHAPES.get(p.name) == "A"):
        start = int(round(phone.start * FRAME_RATE))
        if phone.name in VOWELS:
            start -= int(round(ANTICIPATE_S * FRAME_RATE))
        end = int(round(phone.end * FRAME_RATE))
        named = PHONE_SHAPES.get(phone.name, "X")
        if named != "X":
            shapes[max(start, 0):max(end, start + 1, 0)] = VISEMES.index(named)
    if speech is not None:  # silence is rest; lips pressed shut for a B or an M are silent too, and stay
        shapes[~speech[:frames] & (shapes != closed)] = rest
    hold = max(1, int(round(MIN_HOLD_S * FRAME_RATE)))
    runs = _shape_runs(shapes)
    for k, (start, end, index) in enumerate(runs):  # a flicker joins the shape before it; a closure stays
        if end - start < hold and k > 0 and index not in (rest, closed):
            shapes[start:end] = shapes[start - 1]
    pause = int(round(SHORT_PAUSE_S * FRAME_RATE))
    for start, end, index in _shape_runs(shapes):
        if index == rest and 0 < start and end < frames and end - start < pause:
            shapes[start:end] = shapes[start - 1]
    return shapes


def _shape_runs(shapes: np.ndarray) -> list[tuple[int, int, int]]:
    cuts = np.flatnonzero(np.diff(shapes)) + 1
    bounds = [0, *cuts.tolist(), len(shapes)]
    return [(a, b, int(shapes[a])) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a]


def blend(values: np.ndarray) -> np.ndarray:
    """``values`` ``(frames, ...)`` blended over time by :data:`KERNEL`, the ends held."""
    if not len(values):
        return np.asarray(values, np.float64)
    padded = np.concatenate([np.repeat(values[:1], LOOKAHEAD, 0), values, np.repeat(values[-1:], LOOKAHEAD, 0)])
    return np.tensordot(np.lib.stride_tricks.sliding_window_view(padded, len(KERNEL), axis=0), KERNEL,
                        axes=([-1], [0]))


def one_hot(shapes: np.ndarray) -> np.ndarray:
    """``shapes`` ``(frames,)`` indices into :data:`VISEMES` as ``(frames, 9)`` weights of 0 or 1."""
    onehot = np.zeros((len(shapes), len(VISEMES)))
    onehot[np.arange(len(shapes)), shapes] = 1.0
    return onehot


def shape_curves(shapes: np.ndarray) -> np.ndarray:
    """Each shape's weight per frame, ``(frames, 9)`` in :data:`VISEMES` order, summing to 1: the
    frames' shapes blended by :func:`blend`."""
    return blend(one_hot(shapes))


def openness(curves: np.ndarray) -> np.ndarray:
    """How open the mouth is per frame, ``(frames,)``, from the shapes' weights ``(frames, 9)``."""
    return curves @ np.array([OPENNESS[v] for v in VISEMES])


def heard(phones: list[Phone]) -> tuple[list[tuple[float, float, str]], list[tuple[float, float, str]]]:
    """What was heard, for a person to read: the words (where they were given and aligned) and
    each phone with its mouth shape (``B·A``), as ``(start, end, text)`` seconds; silence left out."""
    words: list[tuple[float, float, str]] = []
    for phone in phones:
        if phone.word and not phone.word.startswith("<"):
            if words and words[-1][2] == phone.word and abs(words[-1][1] - phone.start) < 1e-9:
                words[-1] = (words[-1][0], phone.end, phone.word)
            else:
                words.append((phone.start, phone.end, phone.word))
    sounds = [(p.start, p.end, f"{p.name}·{PHONE_SHAPES[p.name]}") for p in phones if p.name in PHONE_SHAPES]
    return words, sounds


def mouth_cues(shapes: np.ndarray) -> list[tuple[float, float, str]]:
    """Rhubarb's mouth cues: ``(start, end, shape)`` seconds, one per run of a shape."""
    return [(a / FRAME_RATE, b / FRAME_RATE, VISEMES[s]) for a, b, s in _shape_runs(shapes)]
