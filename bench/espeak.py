"""Speech with known timing: espeak-ng says a sentence in one of its many languages and tells
which phonemes it spoke and when (its phoneme events, in IPA), the truth for lip-sync figures in
languages the recogniser was not trained on.

espeak-ng (GPL-3, a Debian package the Makefile installs) is called through its shared library
with ctypes, only here, in the bench and tests: toonface itself neither links nor ships it. Its
command line cannot give phoneme times (``--pho`` works with MBROLA voices only); its library's
synthesis callback can.

The truth of how open the mouth is comes from phonetics, not from toonface's shape table: each
vowel's openness follows its height on the IPA chart (open ``a`` wide, close ``i`` ``u`` nearly
shut), bilabials are shut, other consonants slightly open, pauses at rest; the jaw then moves
between them as a 30 ms Gaussian blend.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import io
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Openness (0 shut .. 1 wide) by the first IPA letter of a phoneme: vowel height, then place.
_OPEN = {**dict.fromkeys("aɑɒäɶ", 0.95), **dict.fromkeys("æɐ", 0.8), **dict.fromkeys("ɛɔœʌɜɞ", 0.65),
         **dict.fromkeys("eoøɤɘɵ", 0.45), "ə": 0.4, **dict.fromkeys("ɪʊʏ", 0.3),
         **dict.fromkeys("iyuɯɨʉ", 0.2), **dict.fromkeys("mbpɸβ", 0.0), **dict.fromkeys("fvɱ", 0.1)}
#: Any other phoneme (a consonant other than the lips'): slightly open.
_CONSONANT = 0.15
#: Sentences said for the figures: short, everyday, several vowels and closures each.
SENTENCES: dict[str, tuple[str, ...]] = {
    "en-us": ("Please bring me a cup of hot coffee in the morning.",
              "My father bought a blue boat by the harbour.",
              "Open the window and let the warm air come in."),
    "de": ("Guten Morgen, wie geht es dir heute?",
           "Mein Vater kauft ein blaues Boot am Hafen.",
           "Mach bitte das Fenster auf, die Luft ist warm."),
    "es": ("Buenos días, ¿cómo estás hoy?",
           "Mi padre compra un barco azul en el puerto.",
           "Abre la ventana, por favor, hace mucho calor."),
    "fr": ("Bonjour, comment allez-vous aujourd'hui?",
           "Mon père achète un bateau bleu au port.",
           "Ouvre la fenêtre, s'il te plaît, il fait chaud."),
}

#: Sentences in languages nobody looked at while the sound's features were chosen: the check.
HELD_OUT: dict[str, tuple[str, ...]] = {
    "it": ("Buongiorno, come stai oggi?", "Mio padre compra una barca blu al porto.",
           "Apri la finestra, per favore, fa molto caldo."),
    "pt": ("Bom dia, como vai você hoje?", "Meu pai compra um barco azul no porto.",
           "Abre a janela, por favor, está muito calor."),
    "nl": ("Goedemorgen, hoe gaat het vandaag?", "Mijn vader koopt een blauwe boot in de haven.",
           "Doe het raam open, het is erg warm."),
    "pl": ("Dzień dobry, jak się masz dzisiaj?", "Mój ojciec kupuje niebieską łódź w porcie.",
           "Otwórz okno, proszę, jest bardzo ciepło."),
}


@dataclass(frozen=True)
class Spoken:
    """A sentence said: ``samples`` ``(n,)`` float32 at ``rate`` Hz, and its phonemes as
    ``(start, end, ipa)`` seconds (pauses as ``""``)."""

    samples: np.ndarray
    rate: int
    phonemes: list[tuple[float, float, str]]

    def openness(self, frame_rate: float = 100.0) -> np.ndarray:
        """How open the mouth is, ``(frames,)`` at ``frame_rate``: the phonemes' openness
        (see the module docstring) blended by a 30 ms Gaussian."""
        from scipy.ndimage import gaussian_filter1d

        frames = int(len(self.samples) / self.rate * frame_rate)
        curve = np.zeros(frames)
        for start, end, ipa in self.phonemes:
            value = 0.0 if not ipa else _OPEN.get(ipa[0], _CONSONANT)
            curve[int(round(start * frame_rate)):int(round(end * frame_rate))] = value
        return gaussian_filter1d(curve, 0.03 * frame_rate, mode="nearest")


class _Id(ctypes.Union):
    _fields_ = [("number", ctypes.c_int), ("name", ctypes.c_char_p), ("string", ctypes.c_char * 8)]


class _Event(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("unique_identifier", ctypes.c_uint), ("text_position", ctypes.c_int),
                ("length", ctypes.c_int), ("audio_position", ctypes.c_int), ("sample", ctypes.c_int),
                ("user_data", ctypes.c_void_p), ("id", _Id)]


_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int, ctypes.POINTER(_Event))
_SYNCHRONOUS, _PHONEME_EVENTS, _IPA, _DONT_EXIT = 2, 0x1, 0x2, 0x8000
_EVENT_END, _EVENT_PHONEME = 0, 7


def available() -> bool:
    """Whether espeak-ng's library is installed."""
    return ctypes.util.find_library("espeak-ng") is not None


def say(text: str, voice: str = "en-us") -> Spoken:
    """``text`` said by espeak-ng's ``voice`` (a language code: ``de``, ``es``, ``fr``...), in a
    process of its own: the library keeps global state, and a second initialisation in one
    process hangs.

    Raises
    ------
    RuntimeError
        When espeak-ng is missing or does not know ``voice``.
    """
    done = subprocess.run([sys.executable, "-m", "bench.espeak", voice], input=text.encode("utf-8"),
                          capture_output=True, cwd=Path(__file__).resolve().parents[1], timeout=60, check=False)
    if done.returncode:
        raise RuntimeError(done.stderr.decode("utf-8", "replace").strip().splitlines()[-1])
    with np.load(io.BytesIO(done.stdout)) as saved:
        phonemes = [(float(a), float(b), str(p)) for a, b, p in zip(saved["starts"], saved["ends"], saved["ipa"],
                                                                    strict=True)]
        return Spoken(saved["samples"], int(saved["rate"]), phonemes)


def _say_here(text: str, voice: str) -> Spoken:
    name = ctypes.util.find_library("espeak-ng")
    if name is None:
        raise RuntimeError("espeak-ng is not installed (make install puts it there)")
    lib = ctypes.CDLL(name)
    rate = lib.espeak_Initialize(_SYNCHRONOUS, 0, None, _PHONEME_EVENTS | _IPA | _DONT_EXIT)
    chunks: list[np.ndarray] = []
    events: list[tuple[int, str]] = []

    def heard(wave, count, event):  # noqa: ANN001 - the C callback's arguments
        if count > 0:
            chunks.append(np.ctypeslib.as_array(wave, (count,)).copy())
        k = 0
        while event[k].type != _EVENT_END:
            if event[k].type == _EVENT_PHONEME:
                events.append((event[k].sample, event[k].id.string.decode("utf-8", "replace")))
            k += 1
        return 0

    callback = _CALLBACK(heard)  # kept alive until synthesis ends
    try:
        lib.espeak_SetSynthCallback(callback)
        if lib.espeak_SetVoiceByName(voice.encode()) != 0:
            raise RuntimeError(f"espeak-ng has no voice {voice!r}")
        data = text.encode("utf-8")
        lib.espeak_Synth(data, len(data) + 1, 0, 1, 0, 1, None, None)  # from character 0, UTF-8
        lib.espeak_Synchronize()
    finally:
        lib.espeak_Terminate()
    samples = (np.concatenate(chunks) if chunks else np.zeros(0, np.int16)).astype(np.float32) / 32768.0
    length = len(samples) / rate
    starts = [min(sample / rate, length) for sample, _ in events] + [length]
    phonemes = [(starts[k], starts[k + 1], ipa) for k, (_, ipa) in enumerate(events) if starts[k + 1] > starts[k]]
    return Spoken(samples, int(rate), phonemes)


if __name__ == "__main__":  # the child of say(): text on stdin, an npz on stdout
    spoken = _say_here(sys.stdin.read(), sys.argv[1])
    out = io.BytesIO()
    np.savez(out, samples=spoken.samples, rate=spoken.rate, starts=[p[0] for p in spoken.phonemes],
             ends=[p[1] for p in spoken.phonemes], ipa=np.array([p[2] for p in spoken.phonemes], dtype=str))
    sys.stdout.buffer.write(out.getvalue())
