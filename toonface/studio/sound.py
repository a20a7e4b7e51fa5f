"""A sound under the staves (CharToon's audio channels): its waveform, its labels, and a WAV
the page plays in step with the cursor.

The sound is any file PyAV decodes (a WAV, an MP3, the sound of a video), taken from its start;
the animation's time 0 is the sound's. Labels are Audacity's label files: a line per label,
``start<TAB>end<TAB>text`` in seconds (a point label has start = end; Audacity's ``\\`` lines,
which hold a label's frequency range, are skipped).
"""

from __future__ import annotations

import io
import os
import wave
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from common import InputError
from common.errors import require_file
from common.limits import read_regular_text
from common.sound import decode_mono

#: Samples per second of the sound the page plays and draws (speech keeps its words at 16 kHz).
RATE = 16_000
#: Waveform columns per second of sound sent to the page.
PEAKS_PER_SECOND = 100


@dataclass(frozen=True, eq=False)
class Label:
    """A stretch of the sound ``[start, end]`` (seconds) and what it says; ``row`` 1 for the
    phones heard (drawn under the words), 2 for the mouth shapes (under the phones), 0 for words
    and a label file's labels."""

    start: float
    end: float
    text: str
    row: int = 0


@dataclass(frozen=True, eq=False)
class Sound:
    """A decoded sound: mono samples ``(n,)`` at :data:`RATE`, where they came from, and labels."""

    path: Path
    samples: np.ndarray
    labels: tuple[Label, ...] = field(default_factory=tuple)

    @property
    def duration(self) -> float:
        return len(self.samples) / RATE

    def peaks(self, per_second: int = PEAKS_PER_SECOND) -> tuple[list[float], list[float]]:
        """The waveform: the lowest and highest sample of each ``1 / per_second`` s, as lists."""
        size = max(1, RATE // per_second)
        count = -(-len(self.samples) // size)
        padded = np.zeros(count * size, np.float32)
        padded[:len(self.samples)] = self.samples
        blocks = padded.reshape(count, size)
        return [round(float(v), 4) for v in blocks.min(axis=1)], [round(float(v), 4) for v in blocks.max(axis=1)]

    def wav(self) -> bytes:
        """The sound as a 16-bit mono WAV file (what every browser plays)."""
        out = io.BytesIO()
        with wave.open(out, "wb") as file:
            file.setnchannels(1)
            file.setsampwidth(2)
            file.setframerate(RATE)
            file.writeframes((np.clip(self.samples, -1.0, 1.0) * 32767).astype("<i2").tobytes())
        return out.getvalue()

    def describe(self) -> dict:
        """What the page draws under the staves."""
        low, high = self.peaks()
        return {"path": str(self.path), "duration": self.duration, "per_second": PEAKS_PER_SECOND,
                "low": low, "high": high,
                "labels": [{"start": lb.start, "end": lb.end, "text": lb.text, "row": lb.row} for lb in self.labels]}


def load_sound(path: str | os.PathLike) -> Sound:
    """Decode ``path``'s sound; :class:`~common.InputError` when it has none or cannot be read."""
    source = Path(path)
    require_file(source)
    samples, _, _ = decode_mono(source, RATE)
    if not len(samples):
        raise InputError("its sound is empty", source)
    return Sound(source, samples.astype(np.float32))


def heard_labels(sound: Sound, text: str | None = None) -> tuple[Label, ...]:
    """What a voice says (:mod:`capture.voice`): its words where ``text`` gives them (aligned),
    each phone heard with its mouth shape, a row under them, and under those the mouth shapes
    that ``map`` and ``lipsync`` use (from the sound, or with the words: :func:`capture.voice_take.mouth_of`),
    a shape a box."""
    from capture.voice import heard, mouth_cues, recognise
    from capture.voice_take import mouth_of

    if text is None:
        phones = recognise(sound.samples)
        _, shapes, _ = mouth_of(sound.samples)
    else:
        phones, shapes, _ = mouth_of(sound.samples, text)
    words, sounds = heard(phones)
    cues = [Label(a, b, shape, 2) for a, b, shape in mouth_cues(shapes) if shape != "X"]
    return tuple([Label(a, b, w) for a, b, w in words] + [Label(a, b, t, 1) for a, b, t in sounds] + cues)


def load_labels(path: str | os.PathLike) -> tuple[Label, ...]:
    """An Audacity label file's labels, in time order.

    Raises
    ------
    InputError
        Naming the file and the line that is not ``start<TAB>end<TAB>text``.
    """
    source = Path(path)
    lines = read_regular_text(source, what="text file of labels").splitlines()
    labels = []
    for number, line in enumerate(lines, start=1):
        if not line.strip() or line.startswith("\\"):
            continue
        parts = line.split("\t", 2)
        try:
            start, end = float(parts[0]), float(parts[1])
        except (ValueError, IndexError):
            # the line's text is not quoted: a page must not read a file through the studio's errors
            raise InputError("expected start<TAB>end<TAB>text (Audacity's labels)", source, f"line {number}") from None
        if not (np.isfinite(start) and np.isfinite(end)) or start < 0 or end < start:
            raise InputError(f"expected 0 <= start <= end, got {start:g}, {end:g}", source, f"line {number}")
        labels.append(Label(start, end, parts[2].strip() if len(parts) > 2 else ""))
    return tuple(sorted(labels, key=lambda lb: lb.start))
