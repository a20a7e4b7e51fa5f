"""The life layer's motion, one frame at a time: what a face does that its source does not carry.

One implementation for every use: ``map`` and ``retarget`` of a voice (:func:`mapping.life.add_life`
runs it over the take's frames), a live voice or a performer the camera lost
(:class:`mapping.life.LiveLife` in the live mapper), and the idle face under everything in
``play`` (:mod:`player.providers`). A :class:`LifeMotion` is told the voice's cues as they come
(a pause begins, a pitch accent, a stressed syllable) and whether the voice is speaking, and
gives per frame, seeded and so the same every run:

- **blinks**, as people blink: some 17 a minute at rest and fewer while speaking (Bentivoglio et
  al. 1997, Movement Disorders 12:1028, give 17 at rest and 4.5 while reading; blinks cluster at
  the pauses and ends of phrases, Nakano and Kitazawa 2010, Experimental Brain Research 205:577),
  a blink at many pauses' start, none within a second of the last, each 0.1-0.4 s long (about
  0.25 s; the lid shuts in a third of it and opens in the rest);
- **gaze** that holds a point and jumps to the next in a saccade of some 40 ms (fixations of
  about 0.3 s, as the shared clips' speakers' eyes hold, most near the listener, some aversions
  further off; the saccade's main sequence, Bahill et al. 1975, makes a small jump last 30-50 ms);
- **brow raises** on pitch accents, by more the higher the accent, rising over 0.35 s and easing
  down over 0.4 s (brow
  raises align with pitch accents: Cavé et al. 1996, ICSLP; Flecha-García 2010, Speech
  Communication 52:542);
- **head motion**: a small nod (chin down and back) on each stressed syllable, a slow sway, tilt
  and rise and fall that wander while speaking and settle in silence (Munhall et al. 2004, Psychological
  Science 15:133: head motion follows the voice's pitch and loudness), and breathing.

:func:`lay` puts a frame's offsets onto motor values, on the motors it is told are free.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from toon.motors import motor_index

LIDS = ("ERU", "ELU")
BROWS = ("BRL", "BRC", "BRM", "BLL", "BLC", "BLM")
PUPILS_H, PUPILS_V = ("PRH", "PLH"), ("PRV", "PLV")
#: Every motor the layer moves (and HT, the head's tilt, where a face has it).
MOVED = (*LIDS, *BROWS, *PUPILS_H, *PUPILS_V, "HV", "HH")
#: No blink within this many seconds of the last.
REFRACTORY = 1.0
#: The time constants of the head's wanders (s): sway (HH), tilt (HT) and pitch (HV)...
WANDER_SECONDS = (1.5, 2.5, 2.0)
#: ... and the time each is smoothed over (s).
WANDER_SMOOTHING = 0.3
#: Blink start times kept (a live face may run for days).
BLINKS_KEPT = 1000


@dataclass(frozen=True)
class LifeSettings:
    """The layer's rates, lengths and amounts (motor units of a 0..1 range), and its seed.

    The blinks' are the literature's (see the module docstring). The gaze's fixations, the brows'
    rise and height, the nods and the head's slow rise and fall were chosen on the shared
    talking-face clips of 11 speakers, against their tracked faces (the statistics of ``python
    -m bench life``), and checked on 6 others kept aside (``python -m bench life --fit`` does it
    again); the other amounts are set by eye."""

    seed: int = 0
    blinks_per_minute: float = 17.0  # in silence
    speaking_blinks_per_minute: float = 8.0
    pause_blink_chance: float = 0.55  # a blink at a pause's start
    blink_seconds: float = 0.25
    fixation_seconds: float = 0.3  # a fixation's median length (fitted)
    gaze_near: float = 0.06  # where most fixations fall (the listener's face)
    gaze_away: float = 0.2  # an aversion's reach
    away_chance: float = 0.25
    saccade_seconds: float = 0.04
    accent_semitones: float = 2.5  # above the speaker's median pitch
    brow_raise: float = 0.2  # for an accent 8 semitones high or more (fitted)
    brow_rise_seconds: float = 0.35  # (fitted)
    nod: float = 0.06  # (fitted)
    sway: float = 0.03
    pitch_sway: float = 0.1  # the head's slow rise and fall (HV) while speaking (fitted)
    breathing_seconds: float = 4.0
    breathing_amount: float = 0.008


class Offsets(NamedTuple):
    """One frame of the layer: how shut the lids are (0..1, to multiply a lid by), and what is
    added to the pupils (``gaze_h``, ``gaze_v``), the brows, and the head's HV, HH and HT."""

    shut: float
    gaze_h: float
    gaze_v: float
    brow: float
    hv: float
    hh: float
    ht: float


class LifeMotion:
    """The layer's motion over time (see the module docstring), for times that only grow.

    Tell it the cues as they come (:meth:`pause`, :meth:`accent`, :meth:`stress`), then
    :meth:`step` each frame. Its randomness is drawn in frame order from ``settings.seed``, so
    the same cues at the same times give the same motion.
    """

    def __init__(self, settings: LifeSettings = LifeSettings()) -> None:
        self.s = settings
        self.rng = np.random.default_rng(settings.seed)
        #: When the latest blinks began (s).
        self.blinks: deque[float] = deque(maxlen=BLINKS_KEPT)
        self._blink_length = 0.0
        self._wanted: list[float] = []
        self._gaze_from = self._gaze_to = self._gaze_now = np.zeros(2)
        self._saccade_at, self._next_fixation = -math.inf, -math.inf
        self._brows: list[tuple[float, float]] = []
        self._nods: list[tuple[float, float]] = []
        self._speaking = 0.0
        self._wanders = np.zeros((3, 2))  # sway, tilt and pitch: each a wander and its smoothed path
        self._last: float | None = None

    def pause(self, t: float) -> None:
        """A pause begins at ``t``: a blink soon after it, by chance."""
        if self.rng.uniform() < self.s.pause_blink_chance:
            self._wanted.append(t + float(self.rng.uniform(0.05, 0.25)))

    def accent(self, start: float, semitones: float) -> None:
        """A pitch accent ``semitones`` above the voice's median: the brows rise from ``start``."""
        self._brows.append((start, self.s.brow_raise * min(semitones / 8.0, 1.0)))

    def stress(self, start: float, loudness: float) -> None:
        """A stressed syllable (its level 0..1): a nod from ``start``."""
        self._nods.append((start, self.s.nod * loudness))

    def step(self, t: float, speaking: bool) -> Offsets:
        """The layer at ``t`` seconds, the voice speaking or not."""
        s = self.s
        dt = 0.01 if self._last is None else max(t - self._last, 0.0)
        self._last = t
        shut = self._blink(t, dt, speaking)
        gaze = self._gaze(t, dt)
        self._nods = [(a, h) for a, h in self._nods if t < a + 0.37]
        rise = s.brow_rise_seconds
        self._brows = [(a, h) for a, h in self._brows if t < a + rise + 0.5]
        brow = max((h * pulse(t, a, rise, 0.1, 0.4) for a, h in self._brows), default=0.0)
        nod = -sum(h * pulse(t, a, 0.12, 0.0, 0.25) for a, h in self._nods)
        self._speaking += (float(speaking) - self._speaking) * min(1.0, dt / 0.5)
        sway, tilt, pitch = (self._wander(k, dt, seconds) for k, seconds in enumerate(WANDER_SECONDS))
        lively = 0.3 + 0.7 * self._speaking  # a head moves more while it speaks
        moving = s.sway * lively
        period = s.breathing_seconds
        breathing = s.breathing_amount * math.sin(2 * math.pi * t / period) if period > 0 else 0.0
        return Offsets(shut, float(gaze[0]), float(gaze[1]), brow, nod + breathing + pitch * s.pitch_sway * lively,
                       sway * moving, tilt * moving)

    def _blink(self, t: float, dt: float, speaking: bool) -> float:
        """How shut the lids are at ``t`` (0 open, 1 shut); a blink begins here by chance or cue."""
        s = self.s
        per_second = (s.speaking_blinks_per_minute if speaking else s.blinks_per_minute) / 60.0
        hazard = per_second / max(1.0 - per_second * REFRACTORY, 0.05)  # so that the rate, less the pauses, is as asked
        draw = self.rng.uniform()
        due = bool(self._wanted) and self._wanted[0] <= t
        self._wanted = [w for w in self._wanted if w > t]
        last = self.blinks[-1] if self.blinks else -math.inf
        if (due or draw < hazard * dt) and t - last >= REFRACTORY:
            self._blink_length = float(np.clip(s.blink_seconds * math.exp(0.25 * self.rng.standard_normal()), 0.1, 0.4))
            self.blinks.append(t)
            last = t
        length = self._blink_length
        return pulse(t, last, length / 3, 0.0, 2 * length / 3, square=False) if self.blinks else 0.0

    def _gaze(self, t: float, dt: float) -> np.ndarray:
        """The pupils' offsets at ``t``: a fixation held, each new one reached by a saccade
        (begun a frame, ``dt``, before: the first frame of a fixation is already on the way)."""
        s = self.s
        if t >= self._next_fixation:
            length = max(s.fixation_seconds * math.exp(0.5 * self.rng.standard_normal()), 0.02)
            radius = s.gaze_away if self.rng.uniform() < s.away_chance else s.gaze_near
            self._gaze_from = self._gaze_now
            self._gaze_to = self.rng.uniform(-1.0, 1.0, 2) * radius * np.array([1.0, 0.6])  # wider than high
            self._saccade_at, self._next_fixation = t - dt, t + length
        ramp = pulse(t, self._saccade_at, max(s.saccade_seconds, 1e-3), math.inf, 1.0)
        self._gaze_now = self._gaze_from + (self._gaze_to - self._gaze_from) * ramp
        return self._gaze_now

    def _wander(self, k: int, dt: float, seconds: float) -> float:
        """One step of the ``k``-th slow random wander of about unit size: an Ornstein-Uhlenbeck
        path (time constant ``seconds``) smoothed over :data:`WANDER_SMOOTHING` (a head does
        not jitter), its new value."""
        decay = math.exp(-dt / seconds)
        path = self._wanders[k]
        path[0] = path[0] * decay + float(self.rng.standard_normal()) * math.sqrt(1 - decay ** 2)
        path[1] += (path[0] - path[1]) * min(1.0, dt / WANDER_SMOOTHING)
        return float(path[1])


def pulse(t: float, start: float, rise: float, hold: float, fall: float, square: bool = True) -> float:
    """0 before ``start``, up to 1 over ``rise`` seconds, held ``hold``, down over ``fall``
    (eased in and out where ``square``, else straight)."""
    up = min(max((t - start) / max(rise, 1e-9), 0.0), 1.0)
    down = min(max((t - start - rise - hold) / max(fall, 1e-9), 0.0), 1.0) if math.isfinite(hold) else 0.0
    shape = min(up, 1.0 - down)
    return shape * shape * (3 - 2 * shape) if square else shape


def lay(values: np.ndarray, offsets: Offsets | dict[str, np.ndarray], free: set[str] | frozenset[str],
        extra: np.ndarray | None = None, extra_codes: tuple[str, ...] = (),
        weights: dict[str, float] | None = None) -> None:
    """Put the layer on motor values ``(..., 21)`` in place, on the motors ``free`` names (lids
    shut by ``shut``, the rest added), clipped to 0..1; and on HT in ``extra`` ``(..., E)`` (by
    ``extra_codes``) where it is free. ``offsets``: one frame's, or arrays by the
    :class:`Offsets` fields for many frames. ``weights``: how much of the layer each code gets
    (1 where not named; a layer fading in or out)."""
    get = offsets._asdict() if isinstance(offsets, Offsets) else offsets

    def part(code: str, key: str) -> np.ndarray:
        return np.asarray(get[key]) * (1.0 if weights is None else weights.get(code, 1.0))

    for lid in LIDS:
        if lid in free:
            values[..., motor_index(lid)] *= 1.0 - part(lid, "shut")
    for codes, key in ((BROWS, "brow"), (PUPILS_H, "gaze_h"), (PUPILS_V, "gaze_v"), (("HV",), "hv"), (("HH",), "hh")):
        for code in codes:
            if code in free:
                column = motor_index(code)
                values[..., column] = np.clip(values[..., column] + part(code, key), 0.0, 1.0)
    if extra is not None and "HT" in extra_codes and "HT" in free:
        column = extra_codes.index("HT")
        extra[..., column] = np.clip(extra[..., column] + part("HT", "ht"), 0.0, 1.0)
