"""The life layer from a voice (issue 64): its cues, and the layer laid on the motors the source
leaves alone. A voice moves only the mouth; a listener expects the eyes to blink and look about,
the brows to rise on the words that are stressed and the head to nod and sway.

From the voice (the take's or the live source's ``sound_level`` and ``voice_pitch`` channels,
:mod:`capture.voice_pitch`) come its cues, found frame by frame as they come
(:class:`VoiceCues`: the same code offline and live):

- **speaking**: the level above -30 dB of the loudest, with silences shorter than 0.25 s inside
  the phrase;
- **pauses**: a silence reaching 0.25 s (after some speech) began a pause;
- **pitch accents**: a voiced frame the highest within three frames either side, some
  semitones (``accent_semitones``) above the median of the voice's pitch (offline, the whole
  voice's; live, its last 30 s so far), 0.35 s or more after the last accent;
- **stressed syllables**: a speaking frame the loudest within three frames either side, at least
  half the loudest, 0.3 s or more after the last.

The motion they drive is :class:`toon.life.LifeMotion` (blinks, gaze, brows, nods, sway, tilt
and breathing, with its sources in the literature). Offline (:func:`add_life`) each cue is laid
where it belongs: a pause's blink from the pause's start, a brow risen by its accent's peak, a
nod from 0.05 s before its syllable; live (:class:`LiveLife`) a cue is acted on when it is
found: a pause 0.25 s into it, an accent three frames after its peak.

The layer writes only what the source does not drive, or has lost (live).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from toon import MotorTrack
from toon.life import LIDS, MOVED, LifeMotion, LifeSettings, Offsets, lay
from toon.motors import MOTOR_CODES

__all__ = ["LIDS", "Cues", "LifeSettings", "LiveLife", "VoiceCues", "add_life", "life_offsets", "take_cues",
           "voice_cues"]
#: Frames either side a peak must top (a cue is found this many frames after it).
PEAK_FRAMES = 3
#: Seconds of the voice's pitch its median is taken over.
PITCH_MEMORY = 30.0
#: The layer's settings unless told others (frozen).
DEFAULTS = LifeSettings()
#: Seconds over which the layer comes onto a motor whose tracking is lost (and leaves it again).
LOST_FADE = 0.3


@dataclass(frozen=True)
class Cues:
    """A voice's cues at ``rate`` frames a second: ``speaking`` ``(n,)`` bool, the frames where
    pauses begin, the pitch accents (frame, semitones above the median) and the stressed
    syllables (frame, loudness 0..1)."""

    rate: float
    speaking: np.ndarray
    pauses: np.ndarray
    accents: list[tuple[int, float]]
    stresses: list[tuple[int, float]]


class VoiceCues:
    """A voice's cues found frame by frame (see the module docstring): :meth:`step` takes a
    frame's level (0..1) and pitch (semitones, 0 unvoiced) and says whether the voice is speaking
    and which cues it found, each ``(kind, frame, value)`` for ``"pause"`` (value 0),
    ``"accent"`` (semitones above the median) or ``"stress"`` (loudness), at the frame it
    belongs to (frames counted from 0)."""

    def __init__(self, rate: float, settings: LifeSettings = DEFAULTS, median: float | None = None) -> None:
        self.rate, self.s = rate, settings
        self.median = median  # the speaker's median pitch where known beforehand (offline: the whole voice's)
        self.gap = max(1, int(round(0.25 * rate)))
        self.frame = -1
        self.silent = 0  # frames of silence up to this one
        self.heard = False  # any speech yet
        self.pitches: deque[float] = deque(maxlen=max(1, int(PITCH_MEMORY * rate)))
        self.recent: deque[tuple[float, float, bool]] = deque(maxlen=2 * PEAK_FRAMES + 1)  # level, pitch, speaking
        self.last_accent = self.last_stress = -np.inf

    def step(self, level: float, pitch: float) -> tuple[bool, list[tuple[str, int, float]]]:
        """One frame: speaking or not, and the cues found."""
        self.frame += 1
        level = level if level == level else 0.0  # NaN: not heard
        pitch = pitch if pitch == pitch else 0.0
        on = level > 10 ** (-30.0 / 20)
        found: list[tuple[str, int, float]] = []
        self.silent = 0 if on else self.silent + 1
        if on:
            self.heard = True
        elif self.silent == self.gap and self.heard:
            found.append(("pause", self.frame - self.gap + 1, 0.0))
        speaking = on or (self.heard and self.silent < self.gap)
        if pitch > 0:
            self.pitches.append(pitch)
        self.recent.append((level, pitch, speaking))
        if len(self.recent) == self.recent.maxlen:
            found += self._peaks(self.frame - PEAK_FRAMES)
        return speaking, found

    def _peaks(self, k: int) -> list[tuple[str, int, float]]:
        """The accent and the stress at frame ``k``, the middle of :attr:`recent`, if any."""
        found: list[tuple[str, int, float]] = []
        level, pitch, speaking = self.recent[PEAK_FRAMES]
        known = self.median is not None or len(self.pitches) > 10
        if pitch > 0 and known and (k - self.last_accent) / self.rate >= 0.35 and \
                pitch >= max(p for _, p, _ in self.recent):
            height = pitch - (self.median if self.median is not None else float(np.median(self.pitches)))
            if height >= self.s.accent_semitones:
                found.append(("accent", k, height))
                self.last_accent = k
        if level >= 0.5 and speaking and (k - self.last_stress) / self.rate >= 0.3 and \
                level >= max(v for v, _, _ in self.recent):
            found.append(("stress", k, level))
            self.last_stress = k
        return found


def voice_cues(level: np.ndarray, pitch: np.ndarray, rate: float, settings: LifeSettings = DEFAULTS) -> Cues:
    """The cues of a voice from its level ``(n,)`` (0..1, the loudest frame 1) and pitch ``(n,)``
    (semitones, 0 unvoiced), at ``rate`` frames a second, as :class:`VoiceCues` finds them, but
    knowing the whole voice: accents are measured from its median pitch (live, from the median so
    far), and a pause's frames are not speaking from its start (live, they are until it is found)."""
    voiced = np.asarray(pitch, float)
    voiced = voiced[np.isfinite(voiced) & (voiced > 0)]
    finder = VoiceCues(rate, settings, float(np.median(voiced)) if len(voiced) > 10 else None)
    n = len(level)
    speaking = np.zeros(n, bool)
    pauses: list[int] = []
    accents: list[tuple[int, float]] = []
    stresses: list[tuple[int, float]] = []
    for k, (heard, tone) in enumerate(zip(np.asarray(level, float).tolist(), np.asarray(pitch, float).tolist(),
                                          strict=True)):
        speaking[k], found = finder.step(heard, tone)
        for kind, frame, value in found:
            if kind == "pause":
                pauses.append(frame)
                speaking[frame:k + 1] = False
            else:
                (accents if kind == "accent" else stresses).append((frame, value))
    return Cues(rate, speaking, np.array(pauses, dtype=int), accents, stresses)


def life_offsets(cues: Cues, settings: LifeSettings = DEFAULTS) -> dict[str, np.ndarray]:
    """What the layer adds, by :class:`toon.life.Offsets` field, ``(n,)`` each (``shut``: how
    shut the lids are, 0..1, to multiply a lid by), each cue laid where it belongs."""
    motion = LifeMotion(settings)
    n, rate = len(cues.speaking), cues.rate
    told: list[list[tuple[str, float, float]]] = [[] for _ in range(n)]
    for k in cues.pauses:
        told[k].append(("pause", k / rate, 0.0))
    rise = settings.brow_rise_seconds
    for k, height in cues.accents:  # risen by the peak
        told[max(0, k - int(round(rise * rate)))].append(("accent", k / rate - rise, height))
    for k, loud in cues.stresses:
        told[max(0, k - int(round(0.05 * rate)))].append(("stress", k / rate - 0.05, loud))
    out = np.zeros((n, len(Offsets._fields)))
    for k in range(n):
        _tell(motion, told[k])
        out[k] = motion.step(k / rate, bool(cues.speaking[k]))
    return {name: out[:, i] for i, name in enumerate(Offsets._fields)}


def take_cues(channels: dict[str, np.ndarray], frames: int, rate: float,
              settings: LifeSettings = DEFAULTS) -> Cues:
    """The cues of a take whose channels (by name) may hold a voice's ``sound_level`` and
    ``voice_pitch``; a take without them is silence throughout (blinks, gaze and breathing)."""
    level = channels.get("sound_level", np.zeros(frames))
    pitch = channels.get("voice_pitch", np.zeros(frames))
    return voice_cues(level, pitch, rate, settings)


def add_life(track: MotorTrack, cues: Cues, driven: set[str] | frozenset[str],
             settings: LifeSettings = DEFAULTS) -> MotorTrack:
    """``track`` with the layer added to every motor of it that ``driven`` does not name (HT too
    where the track carries it); ``cues`` at the track's rate and length."""
    if len(cues.speaking) != track.frames or abs(cues.rate - track.rate) > 1e-9:
        raise ValueError(f"cues of {len(cues.speaking)} frames at {cues.rate:g} Hz for a track of "
                         f"{track.frames} at {track.rate:g} Hz")
    add = life_offsets(cues, settings)
    values = track.values.copy()
    extra = None if track.extra is None else track.extra.copy()
    free = (set(MOTOR_CODES) | {"HT"}) - set(driven)
    lay(values, add, free, extra, track.extra_codes)
    return replace(track, values=values, extra=extra,
                   meta={**track.meta, "life": {"seed": settings.seed, "blinks": _count(add["shut"]),
                                                "brow_raises": len(cues.accents), "nods": len(cues.stresses)}})


class LiveLife:
    """The layer on a live stream of motor frames: the voice's cues as they come (from the
    frames' ``sound_level`` and ``voice_pitch`` channels where the source has them; silence
    otherwise), acted on when found, laid on the motors the mapping does not drive and on those
    whose tracking is lost (confidence 0) at that frame.

    Parameters
    ----------
    neutral : ndarray, shape (21,)
        The face's neutral motors.
    rate : float
        The frames' rate.
    driven : set of str
        The codes the mapping drives.
    settings : LifeSettings
    """

    def __init__(self, neutral: np.ndarray, rate: float, driven: set[str] | frozenset[str],
                 settings: LifeSettings = DEFAULTS) -> None:
        self.neutral = np.asarray(neutral, dtype=float)
        self.driven = frozenset(driven)
        self.cues = VoiceCues(rate, settings)
        self.motion = LifeMotion(settings)
        #: How much of the layer each of its motors gets: 1 where the mapping does not drive it; a
        #: driven one fades in over :data:`LOST_FADE` as its tracking is lost, and out as it returns.
        self.weights = {code: 0.0 if code in self.driven else 1.0 for code in (*MOVED, "HT")}
        self._last: float | None = None

    def step(self, values: np.ndarray, confidence: np.ndarray, t: float, level: float = 0.0, pitch: float = 0.0,
             extra: np.ndarray | None = None, extra_codes: tuple[str, ...] = ()) -> tuple[np.ndarray, np.ndarray]:
        """One frame's motors ``(21,)`` and their confidence ``(21,)`` at ``t`` seconds (``extra``
        ``(E,)`` by ``extra_codes`` changed in place): the motors with the layer, and the
        confidence, as sure as the layer is present on a motor it moves (the layer's motors,
        :data:`toon.life.MOVED`, that the mapping does not drive, or has lost)."""
        speaking, found = self.cues.step(level, pitch)
        _tell(self.motion, [(kind, t, value) for kind, _, value in found])
        step = 1.0 if self._last is None else min(max(t - self._last, 0.0) / LOST_FADE, 1.0)
        self._last = t
        for code in self.driven & set(self.weights):  # a lost motor's own value eases by its loss policy
            lost = code in MOTOR_CODES and confidence[MOTOR_CODES.index(code)] <= 0.0
            self.weights[code] = min(max(self.weights[code] + (step if lost else -step), 0.0), 1.0)
        free = {code for code, weight in self.weights.items() if weight > 0.0}
        out = np.array(values, dtype=float)
        lay(out, self.motion.step(t, speaking), free, extra, extra_codes, self.weights)
        sure = np.array(confidence, dtype=float)
        for code in free & set(MOTOR_CODES):
            column = MOTOR_CODES.index(code)
            sure[column] = max(sure[column], self.weights[code])
        return out, sure


def _tell(motion: LifeMotion, cues: list[tuple[str, float, float]]) -> None:
    """Tell ``motion`` of cues ``(kind, time, value)``."""
    for kind, at, value in cues:
        if kind == "pause":
            motion.pause(at)
        elif kind == "accent":
            motion.accent(at, value)
        else:
            motion.stress(at, value)


def _count(shut: np.ndarray) -> int:
    """Blinks in a lid's shut curve: how many times it rises from open."""
    closed = shut > 0.5
    return int(np.sum(closed[1:] & ~closed[:-1]) + (1 if len(closed) and closed[0] else 0))
