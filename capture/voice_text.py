"""Words given (``--text``) aligned with their sound, in a way that cannot fail outright.

Issue 69 found three ways ordinary dialogue failed: punctuation was refused as words not in the
dictionary (``sunday,``); a word not in the dictionary (a name) stopped everything; and the
alignment failed now and then ("Failed to set up sub-word alignment"), with no lip sync at all.

- **Text as written**: :func:`words_of` lowers the case, takes punctuation off (an apostrophe
  inside a word stays: ``it's``), splits hyphenated and slashed words, and spells digits one by
  one (espeak-ng says them as numbers where it knows the word).
- **Any word**: a word the pronouncing dictionary lacks is spelled by espeak-ng's
  grapheme-to-phoneme rules (``espeak-ng -x``, its phoneme mnemonics turned into the
  dictionary's ARPAbet by :data:`ARPABET`) and added to the decoder for this sound; without
  espeak-ng such a word is left out of the alignment, and said.
- **Alignment that holds**: pocketsphinx cannot align a sound with digital silence in it (its
  log energy is minus infinity there; a synthetic voice has such pauses), so the aligner hears
  the sound with a dither far below any microphone's noise (:data:`DITHER`, seeded). Where the
  whole still fails, each phrase (the text split at its punctuation) is aligned with the stretch
  of sound between the matching pauses; a phrase that fails there, or words whose phrases and
  pauses do not match, keep no phones and the mouth follows the sound alone there, and the notes
  say where.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass, field

import numpy as np

from capture.voice import FRAME_RATE, SAMPLE_RATE, Phone, speaking

#: The dither the aligner hears the sound with (its standard deviation, full scale 1: -70 dBFS).
DITHER = 3e-4
#: A pause between phrases: this long without speech (seconds).
PAUSE_SECONDS = 0.15
#: espeak-ng's English phoneme mnemonics (``-x``) in the pronouncing dictionary's ARPAbet.
ARPABET: dict[str, tuple[str, ...]] = {
    "a": ("AE",), "a#": ("AH",), "A:": ("AA",), "A@": ("AA", "R"), "aI": ("AY",), "aU": ("AW",), "@": ("AH",),
    "@L": ("AH", "L"), "@2": ("AH",), "@5": ("AH",), "3": ("ER",), "3:": ("ER",), "e": ("EH",), "E": ("EH",),
    "eI": ("EY",), "e@": ("EH", "R"), "i": ("IY",), "i:": ("IY",), "I": ("IH",), "I#": ("IH",), "I2": ("IH",),
    "i@": ("IH", "R"), "i@3": ("IH", "R"), "0": ("AA",), "O": ("AO",), "O:": ("AO",), "O@": ("AO", "R"),
    "o@": ("AO", "R"), "OI": ("OY",), "oU": ("OW",), "U": ("UH",), "u:": ("UW",), "U@": ("UH", "R"),
    "V": ("AH",), "aI@": ("AY", "ER"), "aU@": ("AW", "ER"), "aI3": ("AY", "ER"), "p": ("P",), "b": ("B",),
    "t": ("T",), "t#": ("T",), "d": ("D",), "k": ("K",), "g": ("G",), "f": ("F",), "v": ("V",), "T": ("TH",),
    "D": ("DH",), "s": ("S",), "z": ("Z",), "S": ("SH",), "Z": ("ZH",), "h": ("HH",), "m": ("M",), "n": ("N",),
    "N": ("NG",), "l": ("L",), "r": ("R",), "w": ("W",), "j": ("Y",), "tS": ("CH",), "dZ": ("JH",), "x": ("K",),
    "n-": ("N",), "l-": ("L",), "r-": ("R",), "m-": ("M",), "?": (),
}
_DIGITS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine")


@dataclass
class Aligned:
    """Phones placed in a sound, and what the user should know of how."""

    phones: list[Phone]
    notes: list[str] = field(default_factory=list)


def phrases_of(text: str) -> list[list[str]]:
    """The words of ``text`` as said, phrase by phrase (split at ``, . ; : ! ?`` and dashes).

    >>> phrases_of("She baked apple-pies on Sunday, then sliced them... It's 42!")
    [['she', 'baked', 'apple', 'pies', 'on', 'sunday'], ['then', 'sliced', 'them'], ["it's", 'four', 'two']]
    """
    out = []
    for phrase in re.split(r"[,.;:!?\u2026]+|\s[-\u2013\u2014]+\s", text.replace("\u2019", "'")):
        words = []
        for token in re.split(r"[\s/\-\u2013\u2014]+", phrase.lower()):
            token = re.sub(r"[^a-z0-9']", "", token).strip("'")
            for part in re.findall(r"[a-z']+|\d", token):
                words.append(_DIGITS[int(part)] if part.isdigit() else part)
        if words:
            out.append(words)
    return out


def words_of(text: str) -> list[str]:
    """The words of ``text`` as said (:func:`phrases_of`, in one list)."""
    return [word for phrase in phrases_of(text) for word in phrase]


def spelled(words: list[str]) -> dict[str, list[str]]:
    """ARPAbet phones of each of ``words`` by espeak-ng's English rules (a word it cannot spell,
    or all of them where espeak-ng is not installed, left out)."""
    binary = shutil.which("espeak-ng")
    if binary is None or not words:
        return {}
    out = {}
    for word in words:
        done = subprocess.run([binary, "-q", "-v", "en-us", "-x", "--sep=_", word], capture_output=True, text=True,
                              timeout=30, check=False)
        phones = [p for part in done.stdout.split() for p in _arpabet(part)]
        if done.returncode == 0 and phones:
            out[word] = phones
    return out


def _arpabet(mnemonics: str) -> list[str]:
    out: list[str] = []
    for symbol in re.sub(r"[',%=]", "", mnemonics).split("_"):
        out.extend(ARPABET.get(symbol, ARPABET.get(symbol[:1], ())) if symbol else ())
    return out


def align_text(samples: np.ndarray, text: str) -> Aligned:
    """The phones of the words ``text`` placed in ``samples`` (16 kHz mono), as the module
    docstring says: never an error for the words themselves."""
    from pocketsphinx import Decoder

    phrases = phrases_of(text)
    heard = samples + np.random.default_rng(0).normal(0.0, DITHER, len(samples))
    decoder = Decoder(samprate=SAMPLE_RATE, loglevel="FATAL")
    notes: list[str] = []
    unknown = sorted({w for p in phrases for w in p if decoder.lookup_word(w) is None})
    made = spelled(unknown)
    for word, phones in made.items():
        decoder.add_word(word, " ".join(phones), True)
    if made:
        notes.append(f"spelled by espeak-ng's rules (not in the pronouncing dictionary): {', '.join(made)}")
    lost = [w for w in unknown if w not in made]
    if lost:
        notes.append(f"left out of the alignment (not in the pronouncing dictionary, and espeak-ng "
                     f"{'could not spell them' if shutil.which('espeak-ng') else 'is not installed'}): "
                     f"{', '.join(lost)}")
        phrases = [[w for w in p if w not in lost] for p in phrases]
        phrases = [p for p in phrases if p]
    if not phrases:
        return Aligned([], [*notes, "no words to align: the mouth follows the sound alone"])
    whole = _try_align(decoder, heard, [w for p in phrases for w in p])
    if whole is not None:
        return Aligned(whole, notes)
    return Aligned(*_by_phrase(decoder, heard, phrases, notes))


def _try_align(decoder, samples: np.ndarray, words: list[str], offset: float = 0.0) -> list[Phone] | None:
    from capture.voice import aligned_phones, pcm16

    try:
        return [Phone(p.name, p.start + offset, p.end + offset, p.word.split("(")[0])  # sunday(2): a variant
                for p in aligned_phones(decoder, pcm16(samples), " ".join(words))]
    except (RuntimeError, ValueError):
        return None


def _by_phrase(decoder, samples: np.ndarray, phrases: list[list[str]], notes: list[str]
               ) -> tuple[list[Phone], list[str]]:
    """Each phrase aligned with the stretch between its pauses (see the module docstring)."""
    frames = int(len(samples) * FRAME_RATE // SAMPLE_RATE)
    said = np.flatnonzero(np.diff(np.r_[0, speaking(samples, frames).astype(np.int8), 0]))
    runs = [(a, b) for a, b in zip(said[::2], said[1::2], strict=True)]
    joined: list[tuple[int, int]] = []
    for a, b in runs:  # speech with pauses shorter than a phrase's joined
        if joined and a - joined[-1][1] < PAUSE_SECONDS * FRAME_RATE:
            joined[-1] = (joined[-1][0], b)
        else:
            joined.append((a, b))
    if len(joined) != len(phrases):
        return [], [*notes, f"the words could not be aligned with the sound, nor phrase by phrase ({len(phrases)} "
                            f"phrases, {len(joined)} stretches of speech): the mouth follows the sound alone"]
    hop = SAMPLE_RATE // int(FRAME_RATE)
    phones: list[Phone] = []
    failed = []
    for words, (a, b) in zip(phrases, joined, strict=True):
        low, high = max(a - 10, 0), min(b + 10, frames)  # 0.1 s of pause either side
        placed = _try_align(decoder, samples[low * hop:high * hop], words, low / FRAME_RATE)
        if placed is None:
            failed.append(" ".join(words))
        else:
            phones += placed
    if failed:
        notes.append(f"the mouth follows the sound alone where the words could not be aligned: "
                     f"{'; '.join(repr(f) for f in failed)}")
    return phones, notes
