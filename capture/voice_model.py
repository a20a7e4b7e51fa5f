"""How open a mouth is, learned from talking faces: a linear model over the voice's spectrum.

Half of the opening :mod:`capture.voice_sound` gives (the other half is its hand-built measure of
the first formant's band, which keeps vowels apart: alone, the model opens "i" as wide as "a"
and follows espeak-ng's phonemes at r 0.5-0.65 where the two together give 0.78-0.88).

Each 10 ms frame's sound is a log-mel spectrum (:data:`MEL_BANDS` bands, 60 Hz to 7.6 kHz, from
the 25 ms window :mod:`capture.voice_sound` takes), normalised per voice: each band less
its mean over the voice's louder half, over its spread there (what a microphone, a room and a
gain do to a voice is mostly a constant per band, and this takes it away). The mouth's opening at
a frame is a weighted sum of the normalised spectra at a few frames around it
(:attr:`MouthModel.offsets`, 10 ms each: some before, at most 50 ms after, so that a live voice
waits no longer than it did), and of each such value's magnitude (:attr:`MouthModel.magnitude`:
a band's departure from the voice's level either way, a linear model's one bend, where a band
that falls silent and one that swells both say something of the mouth), learned by ridge
regression against the inner-lip gap a face tracker measured in real talking-face videos
(``python -m bench.lipsync_train``, which writes the weights this module reads,
``data/models/voice_mouth.json``; its model card is the documentation page "The voice's mouth
model").

A second model (``data/models/voice_mouth_words.json``, :func:`shipped_words_model`) reads, beside
the spectrum, the phones of the words an English recogniser heard (:mod:`capture.voice_words`):
each phone's presence per frame, blended over time as shapes are, and how long the vowel lasts
(:attr:`MouthModel.phones`), so that it knows an "i" from an "a", and a drawn-out "a" from a
short one, where the words were heard.

The weights are package data and numpy is the whole of the inference: no download, no GPU.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from common import InputError, data_path

#: Bands of the log-mel spectrum.
MEL_BANDS = 40
#: Its lowest and highest frequency, Hz.
MEL_RANGE = (60.0, 7600.0)
#: The weights' file format.
FORMAT = "toonface.voice-mouth/1"


def mel_filters(fft_size: int, rate: int, bands: int = MEL_BANDS, span: tuple[float, float] = MEL_RANGE
                ) -> np.ndarray:
    """Triangular mel filters ``(bands, fft_size // 2 + 1)`` over an rFFT's bins (HTK's mel scale)."""
    def mel(f: np.ndarray) -> np.ndarray:
        return 2595.0 * np.log10(1.0 + f / 700.0)

    low_mel, high_mel = mel(np.array(span))
    edges = 700.0 * (10.0 ** (np.linspace(float(low_mel), float(high_mel), bands + 2) / 2595.0) - 1.0)
    freqs = np.fft.rfftfreq(fft_size, 1.0 / rate)
    low, centre, high = edges[:-2, None], edges[1:-1, None], edges[2:, None]
    return np.clip(np.minimum((freqs - low) / (centre - low), (high - freqs) / (high - centre)), 0.0, None)


def log_mel(power: np.ndarray, filters: np.ndarray) -> np.ndarray:
    """Log-mel spectra ``(frames, bands)`` of power spectra ``(frames, bins)``."""
    return np.log(power @ filters.T + 1e-8)


def voice_scale(mel: np.ndarray) -> np.ndarray:
    """A voice's normalisation, ``(2, bands)``: each band's mean over the louder half of the
    frames ``mel`` ``(frames, bands)`` (their summed log energy at or above its median), and that
    mean plus the band's standard deviation there; ``(mel - s[0]) / (s[1] - s[0])`` normalises."""
    energy = mel.sum(axis=1)
    loud = mel[energy >= np.median(energy)] if len(mel) else np.zeros((1, mel.shape[1]))
    mean = loud.mean(axis=0)
    return np.vstack([mean, mean + loud.std(axis=0) + 1e-3])


def spectra_read(unit_mel: np.ndarray, offsets: tuple[int, ...], magnitude: bool) -> np.ndarray:
    """The normalised spectra ``unit_mel`` ``(frames, MEL_BANDS)`` as a model reads them: at the
    frames ``offsets`` from each (:func:`in_context`), then, with ``magnitude``, each of those
    values' magnitude; ``(frames, len(offsets) * MEL_BANDS)``, twice as wide with ``magnitude``.

    >>> spectra_read(np.array([[-1.0, 2.0], [0.5, -3.0]]), (0,), True).tolist()
    [[-1.0, 2.0, 1.0, 2.0], [0.5, -3.0, 0.5, 3.0]]
    """
    context = in_context(unit_mel, offsets)
    return np.concatenate([context, np.abs(context)], axis=1) if magnitude else context


def in_context(rows: np.ndarray, offsets: tuple[int, ...]) -> np.ndarray:
    """Each frame's rows at ``offsets`` frames from it, side by side: ``(frames, len(offsets) *
    columns)``, a frame before the first or after the last read as the first or the last."""
    n = len(rows)
    index = np.clip(np.arange(n)[:, None] + np.asarray(offsets)[None, :], 0, max(n - 1, 0))
    return rows[index].reshape(n, -1)


@dataclass(frozen=True)
class MouthModel:
    """The learned opening: ``clip((context - mean) @ weights + bias, 0, 1)``.

    Attributes
    ----------
    offsets : tuple of int
        The frames (10 ms each, from the frame predicted) whose normalised spectra it reads.
    mean : ndarray, shape (S,)
        ``S = len(offsets) * MEL_BANDS`` values of the spectra (twice as many with
        :attr:`magnitude`), then one per phone.
    weights : ndarray, shape (S,)
    bias : float
    notes : dict
        What the weights file says of itself (training speakers, held-out figures...).
    phones : tuple of str
        The names of what it reads of the words after the spectra (``mean`` and ``weights`` then
        have ``len(phones)`` more values): each phone's presence, silence ("SIL") among them, and
        possibly the vowel's length (:func:`capture.voice_words.words_read`); empty for a spectrum
        alone.
    magnitude : bool
        Whether it reads, beside each value of the spectra, that value's magnitude (:func:`spectra_read`).
        Chosen on the 16 training speakers by leave-one-speaker-out (each model's choices as
        shipped then): the spectrum's model alone 0.363 -> 0.405 mean r (up on 16 clips of 17),
        the words' 0.550 -> 0.561 (12 of 17); squares instead gave 0.559 for the words', one bend
        at each of -1 and 0 0.560. A file without the key is a model without it.
    """

    offsets: tuple[int, ...]
    mean: np.ndarray
    weights: np.ndarray
    bias: float
    notes: dict
    phones: tuple[str, ...] = ()
    magnitude: bool = False

    @property
    def lookahead(self) -> int:
        """Frames after a frame that its opening reads (a live voice waits for them)."""
        return max(0, max(self.offsets))

    @property
    def lookback(self) -> int:
        """Frames before a frame that its opening reads."""
        return max(0, -min(self.offsets))

    def open_context(self, context: np.ndarray) -> np.ndarray:
        """The opening (0..1) of frames given their spectra in context ``(frames, D)``."""
        return np.clip((context - self.mean) @ self.weights + self.bias, 0.0, 1.0)

    def features(self, unit_mel: np.ndarray, presence: np.ndarray | None = None) -> np.ndarray:
        """What the model reads of each frame, ``(frames, len(weights))``: the normalised spectra
        ``(frames, MEL_BANDS)`` in context (and their magnitudes: :func:`spectra_read`), then (for a
        model of :attr:`phones`) what it reads of the words ``(frames, len(phones))``
        (:func:`capture.voice_words.words_read`)."""
        context = spectra_read(unit_mel, self.offsets, self.magnitude)
        if not self.phones:
            return context
        if presence is None or presence.shape != (len(unit_mel), len(self.phones)):
            raise ValueError(f"this model reads {len(self.phones)} values of the words "
                             f"in each of {len(unit_mel)} frames")
        return np.concatenate([context, presence], axis=1)

    def opening(self, unit_mel: np.ndarray, presence: np.ndarray | None = None) -> np.ndarray:
        """The opening (0..1) of each frame of normalised spectra ``(frames, MEL_BANDS)`` (and, for
        a model of :attr:`phones`, what it reads of the words ``(frames, len(phones))``)."""
        return self.open_context(self.features(unit_mel, presence))

    def to_dict(self) -> dict:
        phones = {"phones": list(self.phones)} if self.phones else {}
        magnitude = {"magnitude": True} if self.magnitude else {}
        return {"format": FORMAT, "mel_bands": MEL_BANDS, "mel_range": list(MEL_RANGE),
                "offsets": list(self.offsets), **magnitude, **phones, "mean": self.mean.tolist(),
                "weights": self.weights.tolist(), "bias": self.bias, **self.notes}


def model_from_dict(doc: dict, source: str = "") -> MouthModel:
    """A :class:`MouthModel` from its file's document; an :class:`InputError` where it is not one."""
    try:
        if doc.get("format") != FORMAT or doc.get("mel_bands") != MEL_BANDS:
            raise ValueError(f"expected format {FORMAT} with {MEL_BANDS} mel bands")
        offsets = tuple(int(k) for k in doc["offsets"])
        phones = tuple(str(p) for p in doc.get("phones", ()))
        magnitude = doc.get("magnitude", False)
        if not isinstance(magnitude, bool):
            raise ValueError("magnitude must be true or false")
        mean, weights = np.asarray(doc["mean"], float), np.asarray(doc["weights"], float)
        spectra = len(offsets) * MEL_BANDS * (2 if magnitude else 1)
        if mean.shape != weights.shape or len(weights) != spectra + len(phones):
            raise ValueError("mean and weights must each have a value per offset and band (twice with magnitude), "
                             "and per phone")
        if phones and "SIL" not in phones:
            raise ValueError("a model of the words must read silence (SIL) among its phones")
        notes = {k: v for k, v in doc.items() if k not in ("format", "mel_bands", "mel_range", "offsets", "phones",
                                                            "magnitude", "mean", "weights", "bias")}
        return MouthModel(offsets, mean, weights, float(doc["bias"]), notes, phones, magnitude)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"not a voice mouth model ({exc})", source) from None


@lru_cache(maxsize=2)
def _shipped(name: str) -> MouthModel:
    path = data_path("models", name)
    return model_from_dict(json.loads(path.read_text(encoding="utf-8")), str(path))


def shipped_model() -> MouthModel:
    """The model of the spectrum alone shipped with toonface (``data/models/voice_mouth.json``), read once."""
    return _shipped("voice_mouth.json")


def shipped_words_model() -> MouthModel:
    """The model of the spectrum and the words' phones shipped with toonface
    (``data/models/voice_mouth_words.json``), read once."""
    return _shipped("voice_mouth_words.json")
