"""The life layer: what a face does that its source does not carry, added to the motors the source
leaves alone (issue 64). A voice moves only the mouth; a listener expects the eyes to blink and
look about, the brows to rise on the words that are stressed and the head to nod and sway.

From the voice (the take's ``sound_level`` and ``voice_pitch`` channels, :mod:`capture.voice_pitch`)
come its cues: where it speaks, where it pauses, its pitch accents and its stressed syllables. On
them, seeded and so the same every run:

- **blinks**, as people blink: some 17 a minute at rest and fewer while speaking (Bentivoglio et
  al. 1997, Movement Disorders 12:1028, give 17 at rest and 4.5 while reading; blinks cluster at
  the pauses and ends of phrases, Nakano and Kitazawa 2010, Experimental Brain Research 205:577),
  a blink at many pauses' start, none within a second of the last, each 0.1-0.4 s long (about
  0.25 s; the lid shuts in a third of it and opens in the rest);
- **gaze** that holds a point and jumps to the next in a saccade of some 40 ms (fixations of a
  second or so in conversation, most near the listener, some aversions further off; the
  saccade's main sequence, Bahill et al. 1975, makes a small jump last 30-50 ms);
- **brow raises** on pitch accents: a peak of the pitch some semitones above the speaker's own
  median raises both brows, from a tenth of a second before the peak, by more the higher it
  goes, easing down over 0.4 s (brow raises align with pitch accents: Cavé et al. 1996, ICSLP;
  Flecha-García 2010, Speech Communication 52:542);
- **head motion**: a small nod (chin down and back) on each stressed syllable, a slow sway and
  tilt that wander while speaking and settle in silence (Munhall et al. 2004, Psychological
  Science 15:133: head motion follows the voice's pitch and loudness), and breathing.

The layer writes only what the source does not drive: :func:`add_life` takes the codes the
mapping drives and leaves those as they are.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from toon import MotorTrack
from toon.motors import MOTOR_CODES

LIDS = ("ERU", "ELU")
BROWS = ("BRL", "BRC", "BRM", "BLL", "BLC", "BLM")
PUPILS_H, PUPILS_V = ("PRH", "PLH"), ("PRV", "PLV")


@dataclass(frozen=True)
class LifeSettings:
    """The layer's rates, lengths and amounts (motor units of a 0..1 range), and its seed."""

    seed: int = 0
    blinks_per_minute: float = 17.0  # in silence
    speaking_blinks_per_minute: float = 8.0
    pause_blink_chance: float = 0.55  # a blink at a pause's start
    blink_seconds: float = 0.25
    fixation_seconds: float = 1.1  # a fixation's median length
    gaze_near: float = 0.06  # where most fixations fall (the listener's face)
    gaze_away: float = 0.2  # an aversion's reach
    away_chance: float = 0.25
    saccade_seconds: float = 0.04
    accent_semitones: float = 2.5  # above the speaker's median pitch
    brow_raise: float = 0.3
    nod: float = 0.05
    sway: float = 0.03
    breathing_seconds: float = 4.0
    breathing_amount: float = 0.008


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


def voice_cues(level: np.ndarray, pitch: np.ndarray, rate: float, settings: LifeSettings = LifeSettings()) -> Cues:
    """The cues of a voice from its level ``(n,)`` (0..1, the loudest frame 1) and pitch ``(n,)``
    (semitones, 0 unvoiced), at ``rate`` frames a second."""
    level = np.nan_to_num(np.asarray(level, float))
    pitch = np.nan_to_num(np.asarray(pitch, float))
    n = len(level)
    db = 20 * np.log10(np.maximum(level, 1e-6))
    on = db > -30.0
    gap = int(round(0.25 * rate))  # shorter silences are inside a phrase
    speaking = on.copy()
    starts = np.flatnonzero(np.diff(np.concatenate([[1], on.astype(int)])) == -1)
    ends = np.flatnonzero(np.diff(np.concatenate([on.astype(int), [1]])) == 1) + 1
    pauses = []
    for a, b in zip(starts, ends, strict=True):
        if b - a < gap and a > 0 and b < n:
            speaking[a:b] = True
        elif a > 0:
            pauses.append(a)
    voiced = pitch > 0
    accents: list[tuple[int, float]] = []
    if voiced.sum() > 10:
        median = float(np.median(pitch[voiced]))
        smooth = np.where(voiced, pitch, np.nan)
        apart = int(round(0.35 * rate))
        order = np.argsort(-np.where(voiced, pitch, -np.inf))
        for k in order:
            if not voiced[k] or pitch[k] < median + settings.accent_semitones:
                break
            lo, hi = max(0, k - 3), min(n, k + 4)
            if np.nanmax(smooth[lo:hi]) > pitch[k] or any(abs(k - j) < apart for j, _ in accents):
                continue
            accents.append((int(k), float(pitch[k] - median)))
        accents.sort()
    stresses: list[tuple[int, float]] = []
    apart = int(round(0.3 * rate))
    for k in np.argsort(-level):
        if level[k] < 0.5:
            break
        if not speaking[k] or any(abs(k - j) < apart for j, _ in stresses):
            continue
        stresses.append((int(k), float(level[k])))
    stresses.sort()
    return Cues(rate, speaking, np.array(pauses, dtype=int), accents, stresses)


def life_offsets(cues: Cues, settings: LifeSettings = LifeSettings()) -> dict[str, np.ndarray]:
    """What the layer adds, by code, ``(n,)`` each (lids: how shut, 0..1, to multiply the lid by)."""
    rng = np.random.default_rng(settings.seed)
    n, rate = len(cues.speaking), cues.rate
    t = np.arange(n) / rate
    out = {"shut": _blinks(cues, settings, rng), "gaze_h": np.zeros(n), "gaze_v": np.zeros(n)}
    out["gaze_h"], out["gaze_v"] = _gaze(n, rate, settings, rng)
    brow = np.zeros(n)
    for k, height in cues.accents:
        amount = settings.brow_raise * min(height / 8.0, 1.0)
        brow = np.maximum(brow, amount * _pulse(t, k / rate - 0.1, 0.15, 0.1, 0.4))
    out["brow"] = brow
    nod = np.zeros(n)
    for k, loud in cues.stresses:
        nod -= settings.nod * loud * _pulse(t, k / rate - 0.05, 0.12, 0.0, 0.25)
    speaking = np.convolve(cues.speaking.astype(float), np.ones(max(1, int(rate))) / max(1, int(rate)), "same")
    sway = _wander(n, rate, 1.5, rng) * settings.sway * (0.3 + 0.7 * speaking)
    tilt = _wander(n, rate, 2.5, rng) * settings.sway * (0.3 + 0.7 * speaking)
    breathing = settings.breathing_amount * np.sin(2 * np.pi * t / settings.breathing_seconds)
    out.update(HV=nod + breathing, HH=sway, HT=tilt)
    return out


def take_cues(channels: dict[str, np.ndarray], frames: int, rate: float,
              settings: LifeSettings = LifeSettings()) -> Cues:
    """The cues of a take whose channels (by name) may hold a voice's ``sound_level`` and
    ``voice_pitch``; a take without them is silence throughout (blinks, gaze and breathing)."""
    level = channels.get("sound_level", np.zeros(frames))
    pitch = channels.get("voice_pitch", np.zeros(frames))
    return voice_cues(level, pitch, rate, settings)


def add_life(track: MotorTrack, cues: Cues, driven: set[str] | frozenset[str],
             settings: LifeSettings = LifeSettings()) -> MotorTrack:
    """``track`` with the layer added to every motor of it that ``driven`` does not name (HT too
    where the track carries it); ``cues`` at the track's rate and length."""
    if len(cues.speaking) != track.frames or abs(cues.rate - track.rate) > 1e-9:
        raise ValueError(f"cues of {len(cues.speaking)} frames at {cues.rate:g} Hz for a track of "
                         f"{track.frames} at {track.rate:g} Hz")
    add = life_offsets(cues, settings)
    values = track.values.copy()
    column = {code: i for i, code in enumerate(MOTOR_CODES)}
    for lid in LIDS:
        if lid not in driven:
            values[:, column[lid]] *= 1.0 - add["shut"]
    for codes, key in ((BROWS, "brow"), (PUPILS_H, "gaze_h"), (PUPILS_V, "gaze_v"), (("HV",), "HV"), (("HH",), "HH")):
        for code in codes:
            if code not in driven:
                values[:, column[code]] += add[key]
    extra = track.extra
    if extra is not None and "HT" in track.extra_codes and "HT" not in driven:
        extra = extra.copy()
        extra[:, track.extra_codes.index("HT")] += add["HT"]
        extra = np.clip(extra, 0.0, 1.0)
    return replace(track, values=np.clip(values, 0.0, 1.0), extra=extra,
                   meta={**track.meta, "life": {"seed": settings.seed, "blinks": _count(add["shut"]),
                                                "brow_raises": len(cues.accents), "nods": len(cues.stresses)}})


def _blinks(cues: Cues, s: LifeSettings, rng: np.random.Generator) -> np.ndarray:
    """How shut the lids are per frame (0 open, 1 shut)."""
    n, rate = len(cues.speaking), cues.rate
    wanted = set()
    for k in cues.pauses:
        if rng.uniform() < s.pause_blink_chance:
            wanted.add(int(k + rng.uniform(0.05, 0.25) * rate))
    hazard = np.where(cues.speaking, s.speaking_blinks_per_minute, s.blinks_per_minute) / 60.0 / rate
    draws = rng.uniform(size=n)
    shut = np.zeros(n)
    last = -np.inf
    t = np.arange(n) / rate
    for k in range(n):
        if (k in wanted or draws[k] < hazard[k]) and (k - last) / rate >= 1.0:
            length = float(np.clip(s.blink_seconds * np.exp(0.25 * rng.standard_normal()), 0.1, 0.4))
            shut = np.maximum(shut, _pulse(t, k / rate, length / 3, 0.0, 2 * length / 3, square=False))
            last = k
    return shut


def _gaze(n: int, rate: float, s: LifeSettings, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The pupils' offsets: fixations, each reached by a saccade."""
    h, v = np.zeros(n), np.zeros(n)
    here = np.zeros(2)
    k = 0
    while k < n:
        length = max(int(s.fixation_seconds * np.exp(0.5 * rng.standard_normal()) * rate), 2)
        away = rng.uniform() < s.away_chance
        radius = s.gaze_away if away else s.gaze_near
        there = rng.uniform(-1.0, 1.0, 2) * radius * np.array([1.0, 0.6])  # wider than high
        move = max(1, int(round(s.saccade_seconds * rate)))
        ramp = np.clip((np.arange(min(length, n - k)) + 1) / move, 0.0, 1.0)
        ramp = ramp * ramp * (3 - 2 * ramp)  # a smooth start and stop
        h[k:k + len(ramp)] = here[0] + (there[0] - here[0]) * ramp
        v[k:k + len(ramp)] = here[1] + (there[1] - here[1]) * ramp
        here, k = there, k + length
    return h, v


def _wander(n: int, rate: float, seconds: float, rng: np.random.Generator) -> np.ndarray:
    """A slow random wander of about unit size (an Ornstein-Uhlenbeck path, time constant ``seconds``)."""
    out = np.zeros(n)
    decay = np.exp(-1.0 / (seconds * rate))
    noise = rng.standard_normal(n) * np.sqrt(1 - decay ** 2)
    x = 0.0
    for k in range(n):
        x = x * decay + noise[k]
        out[k] = x
    return out


def _pulse(t: np.ndarray, start: float, rise: float, hold: float, fall: float, square: bool = True) -> np.ndarray:
    """0 before ``start``, up to 1 over ``rise`` seconds, held ``hold``, down over ``fall`` (smooth)."""
    up = np.clip((t - start) / max(rise, 1e-9), 0.0, 1.0)
    down = np.clip((t - start - rise - hold) / max(fall, 1e-9), 0.0, 1.0)
    shape = np.minimum(up, 1.0 - down)
    return shape * shape * (3 - 2 * shape) if square else shape


def _count(shut: np.ndarray) -> int:
    """Blinks in a lid's shut curve: how many times it rises from open."""
    closed = shut > 0.5
    return int(np.sum(closed[1:] & ~closed[:-1]) + (1 if len(closed) and closed[0] else 0))
