"""A mouth from the sound alone, in any language: how open and how round, from the spectrum.

No words and no phone model. How open is the mean of two measures, each 0..1 and shut where the
300-1000 Hz band, where a vowel is loud, sits in the lowest 28 % of its scale (a room's hum and
hiss, silence), each times that band's level above it:

- a hand-built one: the jaw's opening raises the first formant and makes a vowel loud in that
  band, while closures (M B P, stops) and silence empty it; so the band's level times the centre
  of mass of the 250-1100 Hz band (where F1 lies), each scaled between the quiet and loud parts
  (5th and 95th percentiles) of the voice heard so far;
- a learned one (:mod:`capture.voice_model`): the voice's log-mel spectrum, normalised per
  voice, weighted as ridge regression found best against the lips of real talking faces, times
  that band's gated level.

Alone, the learned one follows speakers it never heard better (median r 0.42 against 0.35 on
the shared clips; the mean 0.39) but opens "i" as wide as "a" and follows espeak-ng's phonemes
less well; the mean keeps the vowels apart and the languages' r at 0.78-0.88 (``python -m bench
lipsync``).
Rounded lips lower the second formant: the centre of mass of the 800-2200 Hz band, low for a
rounded vowel, gives how round. Both are then placed on Rhubarb's shapes
(:data:`capture.voice.VISEMES`): along a ladder of openness, closed (A, or X in silence) → B → C
→ D when spread, A → F → E → D when round; a frame between two rungs weighs both (what moves the
motors), and its mouth cue is the heavier (what Rhubarb's formats keep): :func:`sound_mouth`
gives the two.

One implementation serves a whole file and a live voice (:class:`Listener`): the same frames,
the same blend (:data:`capture.voice.KERNEL`, a Gaussian of 25 ms cut at ±50 ms), the same
rule; a file's scale comes from all of it, a live voice's from what was heard so far. The
learned opening reads no further ahead than that blend waits.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from capture.voice import FRAME_RATE, LOOKAHEAD, SAMPLE_RATE, VISEMES, blend
from capture.voice_model import MEL_BANDS, MouthModel, log_mel, mel_filters, shipped_model, voice_scale

HOP = int(SAMPLE_RATE / FRAME_RATE)
#: Each frame's analysis window (samples: 25 ms), centred on the frame.
WINDOW = 400
_FFT = 512
_FREQS = np.fft.rfftfreq(_FFT, 1.0 / SAMPLE_RATE)
_MEL = mel_filters(_FFT, SAMPLE_RATE)
#: Columns of a frame's features before its spectrum: the three bands' (level, two centres of mass).
BANDS = 3
#: The learned opening's share of the opening (the hand-built one has the rest).
LEARNED_SHARE = 0.5
_LOUD_BAND, _F1_BAND, _F2_BAND = (300.0, 1000.0), (250.0, 1100.0), (800.0, 2200.0)
#: A frame is speech when the loud band is this far (0..1) up its scale (halfway: the rule of
#: :func:`capture.voice.speaking`); a pause keeps the lips as they were for
#: :data:`PAUSE_FRAMES`, then relaxes them to rest.
SPEECH_LEVEL = 0.5
PAUSE_FRAMES = 20
#: Openness of each rung of the spread and the round ladder (Rhubarb's shapes, as in voice.toml).
_SPREAD = (("A", 0.0), ("B", 0.15), ("C", 0.5), ("D", 0.9))
_ROUND = (("A", 0.0), ("F", 0.25), ("E", 0.4), ("D", 0.9))


def band_features(samples: np.ndarray, frames: int) -> np.ndarray:
    """Per 10 ms frame of ``samples`` (16 kHz mono), ``(frames, 3 + MEL_BANDS)``: the 300-1000 Hz
    band's level (dB), the centres of mass (Hz) of the 250-1100 Hz and 800-2200 Hz bands, then
    the log-mel spectrum (:mod:`capture.voice_model`)."""
    padded = np.pad(np.asarray(samples, np.float64), (WINDOW // 2, frames * HOP + WINDOW))
    return window_features(np.lib.stride_tricks.sliding_window_view(padded, WINDOW)[::HOP][:frames])


def window_features(windows: np.ndarray) -> np.ndarray:
    """:func:`band_features` of each frame's window of sound, ``(frames, WINDOW)`` →
    ``(frames, 3 + MEL_BANDS)``."""
    frames = len(windows)
    power = np.abs(np.fft.rfft(windows * np.hanning(WINDOW), _FFT, axis=1)) ** 2
    out = np.empty((frames, BANDS + MEL_BANDS))
    loud = (_FREQS >= _LOUD_BAND[0]) & (_FREQS <= _LOUD_BAND[1])
    out[:, 0] = 10 * np.log10(power[:, loud].sum(axis=1) + 1e-10)
    for column, (low, high) in ((1, _F1_BAND), (2, _F2_BAND)):
        band = (_FREQS >= low) & (_FREQS <= high)
        out[:, column] = (power[:, band] * _FREQS[band]).sum(axis=1) / (power[:, band].sum(axis=1) + 1e-12)
    out[:, BANDS:] = log_mel(power, _MEL)
    return out


#: The lowest 28 % of the loud band's scale opens nothing: a room's hum and hiss stay shut.
#: Chosen on the lip-sync bench's GRID clips (r against the lips, share of room tone shut):
#: no gate 0.71/0.64 and 30 %; 0.25: 0.67/0.61 and 93 %; 0.28: 0.62/0.62 and 100 %. (A
#: frame's voicing, its autocorrelation at a pitch lag, does not tell GRID's room tone from
#: speech: the room hums, 0.6-0.9 voiced as a vowel is.)
GATE = 0.28
#: The loud band's scale spans at least this many dB: a room's noise alone (a live voice before
#: its first word, a file of hiss) is not stretched into speech.
MIN_RANGE_DB = 40.0


def scales(features: np.ndarray) -> np.ndarray:
    """Each feature's quiet and loud ends, ``(2, 3 + MEL_BANDS)``: for the three bands the 5th and
    95th percentiles of ``features`` ``(frames, 3 + MEL_BANDS)``, the level's at least
    :data:`MIN_RANGE_DB` apart; for the spectrum the voice's normalisation
    (:func:`capture.voice_model.voice_scale`)."""
    scale = np.empty((2, features.shape[1]))
    scale[:, :BANDS] = np.percentile(features[:, :BANDS], [5.0, 95.0], axis=0)
    scale[1, 0] = max(scale[1, 0], scale[0, 0] + MIN_RANGE_DB)
    scale[:, BANDS:] = voice_scale(features[:, BANDS:])
    return scale


def unit(features: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """``features`` ``(frames, 3 + MEL_BANDS)`` on ``scale`` ``(2, 3 + MEL_BANDS)``,
    ``(features - scale[0]) / (scale[1] - scale[0])``: the bands clipped to 0..1, the spectrum
    normalised (not clipped)."""
    out = (features - scale[0]) / np.maximum(scale[1] - scale[0], 1e-9)
    out[:, :BANDS] = np.clip(out[:, :BANDS], 0.0, 1.0)
    return out


def sound_units(samples: np.ndarray, frames: int) -> np.ndarray:
    """A whole sound's :func:`unit` features on its own :func:`scales`, ``(frames, 3 + MEL_BANDS)``."""
    features = band_features(samples, frames)
    return unit(features, scales(features))


def opening(units: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The hand-built opening (0..1), how round (0..1) and whether speech, per frame, from
    :func:`unit` features, before the blend over time."""
    return _level(units) * units[:, 1], 1.0 - units[:, 2], units[:, 0] >= SPEECH_LEVEL


def learned_opening(units: np.ndarray, model: MouthModel | None = None) -> np.ndarray:
    """The learned opening (0..1) of :func:`unit` features in context (a frame before the first or
    after the last read as the first or the last), times the loud band's gated level as the
    hand-built one is: shut in silence and room tone, and closing as the voice fades."""
    model = model or shipped_model()
    return _level(units) * model.opening(units[:, BANDS:])


def _level(units: np.ndarray) -> np.ndarray:
    """The 300-1000 Hz band's level above :data:`GATE` of its scale, 0..1."""
    return np.clip((units[:, 0] - GATE) / (1.0 - GATE), 0.0, 1.0)


def pauses(speech: np.ndarray, before: int = PAUSE_FRAMES) -> np.ndarray:
    """Frames where the lips keep their last shape, ``(frames,)`` bool: speech, and the first
    :data:`PAUSE_FRAMES` frames of each pause (``before``: how long the pause had lasted when
    these frames begin)."""
    since = np.empty(len(speech), int)
    count = before
    for k, on in enumerate(speech):
        count = 0 if on else count + 1
        since[k] = count
    return since <= PAUSE_FRAMES


def shape_weights(open_: np.ndarray, round_: np.ndarray, held: np.ndarray) -> np.ndarray:
    """Each of Rhubarb's shapes' weight per frame, ``(frames, 9)`` in :data:`VISEMES` order and
    summing to 1, whose openness (:func:`capture.voice.openness`) is ``open_``: a mix of the spread
    and the round ladder by ``round_``; the closed rung is A (lips pressed) where ``held`` and X
    (rest) elsewhere."""
    weights = np.zeros((len(open_), len(VISEMES)))
    for ladder, share in ((_SPREAD, 1.0 - round_), (_ROUND, round_)):
        levels = np.array([level for _, level in ladder])
        index = np.clip(np.searchsorted(levels, open_, side="right") - 1, 0, len(levels) - 2)
        upper = np.clip((open_ - levels[index]) / (levels[index + 1] - levels[index]), 0.0, 1.0)
        for rung, (name, _) in enumerate(ladder):
            part = np.where(index == rung, 1.0 - upper, 0.0) + np.where(index + 1 == rung, upper, 0.0)
            weights[:, VISEMES.index(name)] += share * part
    closed = weights[:, VISEMES.index("A")].copy()
    weights[:, VISEMES.index("A")] = np.where(held, closed, 0.0)
    weights[:, VISEMES.index("X")] = np.where(held, 0.0, closed)
    return weights


def sound_mouth(samples: np.ndarray, frames: int, learned_share: float = LEARNED_SHARE,
                model: MouthModel | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A whole sound's mouth, on the scale of all of it: each shape's weight per frame,
    ``(frames, 9)`` in :data:`VISEMES` order and summing to 1 (:func:`shape_weights` of the
    opening and roundness, blended again as :func:`capture.voice.shape_curves` blends shapes: what
    moves the motors), and its mouth cue per frame, ``(frames,)`` indices into :data:`VISEMES`
    (the heaviest shape before that second blend: what Rhubarb's formats keep). The opening is
    the blended hand-built one and the learned one (``model``, the shipped one by default), the
    latter's share ``learned_share``."""
    units = sound_units(samples, frames)
    hand, round_, speech = opening(units)
    both = blend(np.column_stack([hand, round_]))
    open_ = _mixed(both[:, 0], learned_opening(units, model) if learned_share else 0.0, learned_share)
    weights = _weights(open_, both[:, 1], pauses(speech))
    return blend(weights), np.argmax(weights, axis=1)


def _mixed(hand: np.ndarray, learned: np.ndarray | float, share: float) -> np.ndarray:
    return (1.0 - share) * hand + share * learned


def sound_shapes(samples: np.ndarray, frames: int) -> np.ndarray:
    """A whole sound's mouth cue per frame, ``(frames,)``: :func:`sound_mouth`'s cues."""
    return sound_mouth(samples, frames)[1]


def _weights(open_: np.ndarray, round_: np.ndarray, held: np.ndarray) -> np.ndarray:
    return shape_weights(np.clip(open_, 0.0, 1.0), np.clip(round_, 0.0, 1.0), held)


@dataclass
class _LiveBlend:
    """:func:`capture.voice.blend` of rows as they come: each row once :data:`LOOKAHEAD` rows
    after it have come, exactly as the whole would be blended (its start held alike)."""

    _rows: np.ndarray | None = None
    _done: int = 0  # rows of _rows already given out

    def push(self, rows: np.ndarray) -> np.ndarray:
        """The blended rows that ``rows`` completes (``(n, ...)``, ``n`` may be 0)."""
        kept = rows if self._rows is None else np.concatenate([self._rows, rows])
        placeable = len(kept) - LOOKAHEAD - self._done
        if placeable <= 0:
            self._rows = kept
            return np.zeros((0, *rows.shape[1:]))
        back = min(self._done, LOOKAHEAD)
        window = kept[self._done - back:]
        out = blend(window)[back:back + placeable]
        keep = max(0, self._done + placeable - LOOKAHEAD)  # rows the next blend reaches back to
        self._rows, self._done = kept[keep:], self._done + placeable - keep
        return out


@dataclass
class Listener:
    """A live voice's mouth: :meth:`hear` takes sound as it comes (16 kHz mono, any chunk size)
    and returns the shape weights ``(n, 9)`` of the frames it can now place: two blends of
    :data:`LOOKAHEAD` frames each (100 ms) plus half a window (12.5 ms) after their sound. The
    same weights as :func:`sound_mouth` gives a whole file (tests hold it to that); the scale is
    that of the last ``memory_s`` seconds heard, or ``scale`` ``(2, 3 + MEL_BANDS)`` where given
    (:func:`scales` of a voice heard before). ``model``: the learned opening's (the shipped one by
    default); it may read no further ahead than :data:`LOOKAHEAD` frames."""

    memory_s: float = 20.0
    scale: np.ndarray | None = None
    model: MouthModel | None = None
    _samples: np.ndarray = field(default_factory=lambda: np.zeros(WINDOW // 2, np.float32))
    _history: np.ndarray = field(default_factory=lambda: np.zeros((0, BANDS + MEL_BANDS)))
    _units: np.ndarray = field(default_factory=lambda: np.zeros((0, BANDS + MEL_BANDS)))
    _base: int = 0  # the frame _units starts at
    _placed: int = 0  # frames given out
    _rise: _LiveBlend = field(default_factory=_LiveBlend)
    _shapes: _LiveBlend = field(default_factory=_LiveBlend)
    _pause: int = PAUSE_FRAMES

    def hear(self, chunk: np.ndarray) -> np.ndarray:
        """The shape weights of the frames ``chunk`` lets it place, ``(n, 9)``."""
        model = self.model or shipped_model()
        if model.lookahead > LOOKAHEAD:
            raise ValueError(f"a live voice's model may read {LOOKAHEAD} frames ahead, not {model.lookahead}")
        self._samples = np.concatenate([self._samples, np.asarray(chunk, np.float32)])
        ready = (len(self._samples) - WINDOW) // HOP + 1  # frames whose whole window has been heard
        if ready <= 0:
            return np.zeros((0, len(VISEMES)))
        windows = np.lib.stride_tricks.sliding_window_view(self._samples.astype(np.float64), WINDOW)[::HOP][:ready]
        features = window_features(windows)
        self._samples = self._samples[ready * HOP:]
        self._history = np.concatenate([self._history, features])[-int(self.memory_s * FRAME_RATE):]
        units = unit(features, scales(self._history) if self.scale is None else self.scale)
        self._units = np.concatenate([self._units, units])
        hand, round_, _ = opening(units)
        both = self._rise.push(np.column_stack([hand, round_]))  # the frames LOOKAHEAD back are placed
        at = slice(self._placed - self._base, self._placed - self._base + len(both))
        rows = self._units[:at.stop + LOOKAHEAD]  # (the first rows are the voice's first: clamped alike)
        learned = learned_opening(rows, model)[at] if LEARNED_SHARE else 0.0
        speech = self._units[at, 0] >= SPEECH_LEVEL
        held = pauses(speech, self._pause)
        self._pause = _pause_after(speech, self._pause)
        self._placed += len(both)
        keep = max(0, self._placed - model.lookback - self._base)  # rows the next frames still read
        self._units, self._base = self._units[keep:], self._base + keep
        return self._shapes.push(_weights(_mixed(both[:, 0], learned, LEARNED_SHARE), both[:, 1], held))


def _pause_after(speech: np.ndarray, before: int) -> int:
    """How long the pause has lasted after ``speech`` frames, given ``before`` at their start."""
    spoken = np.flatnonzero(speech)
    return before + len(speech) if not len(spoken) else len(speech) - 1 - int(spoken[-1])
