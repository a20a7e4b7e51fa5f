"""The mapping's per-frame rules, once, in two forms that agree: a whole take or one frame at a time.

After each mapped motor has its value (:func:`mapping.mapper.motor_values`, NaN where none of
its sources is seen), :class:`MotorRules` applies, in this order:

1. the **loss policy** of each motor with no source seen: ``hold`` the last value seen, ``ease``
   from it to the face's neutral over ``seconds`` counted from the last frame a source was seen,
   ``idle``: ease, plus a slow drift about neutral (:data:`IDLE_AMPLITUDE` at
   :data:`IDLE_HZ`), or ``pair``: the other side's motor's move from its neutral where that one
   is seen (a lid whose marker is lost blinks with the other eye's, a lost pupil looks where the
   other looks), else ease; a ``pair`` motor whose sources were all made up by cleaning (a gap
   filled offline, a marker held live) while its partner's were measured is taken as a lost one,
   unless its rule says ``made_up = false``: a fill regressed from other markers can blink far
   shallower (a regression on noisy predictors shrinks: a quarter as deep on a third-performer
   take), a held marker not at all, and the fourth performer's far outer brow, filled over 1.5 s
   of a head turned away, read a raise of its own brow alone at a quarter of its height. A rule's
   ``near`` motors (the other parts of the same brow) say how this side differs from the other:
   the lost motor takes its partner's move plus the mean of how far each near motor moved beyond
   its own partner (both seen), or, with its partner lost too, the near motors' mean move. The
   far brow's outer part,
   lost as the head turned, had risen with the other brow's in a raise of that brow alone; a
   brow's inner part raised on both sides, the outer parts still, still follows the other side.
   On the four bench performers' choice seeds, live: the fourth's four 13.25 -> 12.72 % summed
   (32: 2.88 -> 2.71, 34: 2.87 -> 2.54 and its lowest r 0.73 -> 0.90), the other three's six within
   0.01 each (their brows rise on both sides); following the near motors alone, with the partner
   only where all were lost, gave the fourth 12.83 but the other six 0.16 more.
   Before anything is seen the last value is the neutral;
2. each motor's **filter** (One Euro, causal Butterworth or trailing Savitzky-Golay);
3. the **speed limits**, then the **delays** (whole frames);
4. the operations **across motors**: the eyes' pair of lids (:func:`eyes_pair`), symmetric
   pairs move as their mean, one side copied, mirror;
5. the **style** operators: ``smooth`` (a trailing moving average over ``seconds``, the first
   frame standing in for the frames before it), ``tremble`` (a sine per motor with a seeded
   phase), ``sharpen`` (quantise to ``steps`` levels);
6. clip to [0, 1].

``apply(values, times)`` (a take, vectorised where the rule allows) returns what feeding the
frames to ``step(values, t)`` one by one returns: :func:`mapping.map_stabilised` uses the one,
the live sender the other, and a test holds them equal to 1e-9 with every rule switched on.
Random phases (idle drift and tremble, one per motor each) come from ``seed`` the same way in
both. Style's ``time_scale`` changes the number of frames, so only offline mapping has it.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from mapping.filters import Butterworth, Delay, OneEuro, SavitzkyGolay, SpeedLimit
from mapping.mapfile import Mapping, MotorRule, Style
from toon import MOTOR_CODES, N_MOTORS, mirror_values, motor_index
from toon.motors import MIRROR_OF, MIRROR_PAIRS, N_CODES, code_index, extended_neutral

IDLE_AMPLITUDE = 0.03  # motor units of the idle drift
IDLE_HZ = 0.25


def make_filter(spec: dict, rate: float) -> OneEuro | Butterworth | SavitzkyGolay:
    """The filter a mapping's ``filter`` table names."""
    params = {k: v for k, v in spec.items() if k != "kind"}
    if spec["kind"] == "one-euro":
        return OneEuro(rate=rate, **params)
    if spec["kind"] == "butterworth":
        return Butterworth(rate=rate, **{k: (int(v) if k == "order" else v) for k, v in params.items()})
    return SavitzkyGolay(**{k: int(v) for k, v in params.items()})


def channel_limits(mapping: Mapping, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Each motor's speed limit (units/s, inf: none) and delay (whole frames), ``(21,)`` each."""
    speeds = np.full(N_CODES, np.inf)
    delays = np.zeros(N_CODES, dtype=int)
    for rule in mapping.rules:
        if rule.max_speed > 0:
            speeds[code_index(rule.code)] = rule.max_speed
        delays[code_index(rule.code)] = int(round(rule.delay * rate))
    return speeds, delays


class MotorRules:
    """The rules after the motor values (module docstring), with their state for ``step``.

    Parameters
    ----------
    mapping : Mapping
    rate : float
        Frames per second (filters, delays, the smoothing window).
    neutral : ndarray, shape (21,)
        The face's neutral: where loss eases to, what mirror keeps.
    seed : int
        Seeds the idle drift and the tremble phases.
    """

    def __init__(self, mapping: Mapping, rate: float, neutral: np.ndarray, seed: int = 0) -> None:
        self.mapping, self.rate = mapping, rate
        self.neutral = extended_neutral(neutral)
        # idle drift and tremble: the 21 motors' phases as before the extras came, then each extra's pair
        # (drawn extra by extra, so a new extra leaves the phases of earlier ones as they were)
        self.phases = np.hstack([np.random.default_rng(seed).uniform(0, 2 * np.pi, (2, N_MOTORS)),
                                 np.random.default_rng([seed, 1]).uniform(0, 2 * np.pi, (N_CODES - N_MOTORS, 2)).T])
        self.mapped = np.array([code_index(r.code) for r in mapping.rules], dtype=int)
        self.loss = [(code_index(r.code), r.loss, r.loss_seconds) for r in mapping.rules]
        self.pairs = _Pairs.of([r for r in mapping.rules if r.loss == "pair"])
        self.filters = [(code_index(r.code), make_filter(r.filter, rate)) for r in mapping.rules if r.filter]
        speeds, delays = channel_limits(mapping, rate)
        self.limited = np.isfinite(speeds)  # only these pass the speed limit
        self.limit = SpeedLimit(speeds[self.limited]) if self.limited.any() else None
        self.delay = Delay(delays) if delays.any() else None
        self.window = max(1, int(round(mapping.style.smooth_seconds * rate)))
        self.reset()

    def reset(self) -> None:
        """Forget the past (loss, filters, limits, delays, smoothing)."""
        self._last = self.neutral.copy()  # the last value seen per motor
        self._seen_at = np.full(N_CODES, np.nan)  # when it was seen (NaN: never)
        self._first_t: float | None = None
        self._smooth: deque[np.ndarray] = deque(maxlen=self.window)
        for _, stage in self.filters:
            stage.reset()
        for limiter in (self.limit, self.delay):
            if limiter is not None:
                limiter.reset()

    def step(self, values: np.ndarray, t: float, made_up: np.ndarray | None = None) -> np.ndarray:
        """One frame: motor values ``(21,)`` (NaN: a mapped motor with no source seen) at ``t``
        seconds, ``made_up`` (shaped as ``values``) where every source was made up by cleaning;
        returns the motors ``(21,)`` in [0, 1]."""
        out = self._paired(np.asarray(values, dtype=float)[None], None if made_up is None else made_up[None])[0]
        self._first_t = t if self._first_t is None else self._first_t
        seen = np.isfinite(out)
        self._last[seen], self._seen_at[seen] = out[seen], t
        for col, policy, seconds in self.loss:
            if not seen[col]:
                since = t - (self._first_t if np.isnan(self._seen_at[col]) else self._seen_at[col])
                out[col] = self._lost_value(col, policy, seconds, np.array([since]), np.array([t]))[0]
        for col, stage in self.filters:
            out[col] = stage.step(out[col:col + 1], t)[0]
        if self.limit is not None:
            out[self.limited] = self.limit.step(out[self.limited], t)
        if self.delay is not None:
            out = self.delay.step(out, t)
        out = across_motors(out[None], self.mapping, self.neutral)[0]
        if self.mapping.style.smooth_seconds > 0:
            if not self._smooth:
                self._smooth.extend([out.copy()] * self.window)
            self._smooth.append(out.copy())
            cols = _motors(self.mapping.style.smooth_motors)
            out[cols] = np.mean(self._smooth, axis=0)[cols]
        return np.clip(self._tremble_and_sharpen(out[None], np.array([t]))[0], 0.0, 1.0)

    def apply(self, values: np.ndarray, times: np.ndarray, made_up: np.ndarray | None = None) -> np.ndarray:
        """A whole take ``(F, 21)`` at ``times`` ``(F,)`` from a fresh state (``made_up``, shaped as
        ``values``: where every source of a motor was made up by cleaning); what stepping it gives."""
        self.reset()
        out = self._paired(np.asarray(values, dtype=float), made_up)
        times = np.asarray(times, dtype=float)
        for col, policy, seconds in self.loss:
            out[:, col] = self._fill_lost(out[:, col], col, policy, seconds, times)
        for col, stage in self.filters:
            out[:, col] = stage.apply(out[:, col], times)
        if self.limit is not None:
            out[:, self.limited] = self.limit.apply(out[:, self.limited], times)
        if self.delay is not None:
            out = self.delay.apply(out, times)
        out = across_motors(out, self.mapping, self.neutral)
        if self.mapping.style.smooth_seconds > 0 and len(out):
            cols = _motors(self.mapping.style.smooth_motors)
            out[:, cols] = trailing_mean(out[:, cols], self.window)
        self.reset()
        return np.clip(self._tremble_and_sharpen(out, times), 0.0, 1.0)

    def _paired(self, values: np.ndarray, made_up: np.ndarray | None = None) -> np.ndarray:
        """Motor values ``(F, C)`` (NaN: no source seen) with each ``pair`` motor's lost frames,
        and (unless its rule says ``made_up = false``) those whose sources were all made up
        (``made_up`` ``(F, C)``) while its partner's were not, taken as lost: given its partner's
        move from neutral where the partner is seen (plus how far the rule's ``near`` motors moved beyond
        theirs, where one of them and its partner are seen; the near motors' mean move where the
        partner is lost and one of them is seen); a new array."""
        out = values.copy()
        pairs = self.pairs
        if not len(pairs.col):
            return out
        neutral = self.neutral
        own, partner = values[:, pairs.col], values[:, pairs.other] - neutral[pairs.other]  # (F, P)
        taken = np.isnan(own)
        if made_up is not None:  # a made-up side whose partner was measured is lost, unless its rule says not
            taken |= pairs.made_up & made_up[:, pairs.col] & ~made_up[:, pairs.other] & np.isfinite(partner)
        moves = np.where(pairs.has, values[:, pairs.near] - neutral[pairs.near], np.nan)  # (F, P, N)
        seen = np.isfinite(moves)
        mean = np.where(seen, moves, 0.0).sum(axis=2) / np.maximum(seen.sum(axis=2), 1)
        apart = moves - (values[:, pairs.across] - neutral[pairs.across])  # this side's near moves less the other's
        both = np.isfinite(apart)
        lead = np.where(both, apart, 0.0).sum(axis=2) / np.maximum(both.sum(axis=2), 1)
        followed = taken & both.any(axis=2) & np.isfinite(partner)  # the partner's move, plus this side's lead
        near_only = taken & ~followed & seen.any(axis=2)  # the partner lost too: this side's near moves
        plain = taken & ~followed & ~near_only & np.isfinite(partner)
        moved = np.where(followed, partner + lead, np.where(near_only, mean, np.where(plain, partner, np.nan)))
        out[:, pairs.col] = np.where(followed | near_only | plain, moved + neutral[pairs.col], own)
        return out

    def _fill_lost(self, raw: np.ndarray, col: int, policy: str, seconds: float, times: np.ndarray) -> np.ndarray:
        """One motor's frames ``(F,)`` with the loss policy where it is NaN."""
        lost = np.isnan(raw)
        if not lost.any():
            return raw
        index = np.where(~lost, np.arange(len(raw)), -1)
        np.maximum.accumulate(index, out=index)
        ever = index >= 0
        last = np.where(ever, raw[np.maximum(index, 0)], self.neutral[col])
        since = times - np.where(ever, times[np.maximum(index, 0)], times[0])
        filled = self._lost_value(col, policy, seconds, since, times, last)
        return np.where(lost, filled, raw)

    def _lost_value(self, col: int, policy: str, seconds: float, since: np.ndarray, times: np.ndarray,
                    last: np.ndarray | None = None) -> np.ndarray:
        """The loss policy's values for one motor ``(F,)``: ``since`` seconds since a source was
        last seen, ``last`` the value then (the remembered one by default)."""
        held = np.full(len(times), self._last[col]) if last is None else last
        if policy == "hold":
            return held
        ease = np.clip(since / seconds, 0.0, 1.0) if seconds > 0 else np.ones_like(since)
        eased = held + (self.neutral[col] - held) * ease
        if policy == "idle":
            eased = eased + ease * IDLE_AMPLITUDE * np.sin(2 * np.pi * IDLE_HZ * times + self.phases[0, col])
        return eased

    def _tremble_and_sharpen(self, values: np.ndarray, times: np.ndarray) -> np.ndarray:
        """The two style operators that need no past, on frames ``(F, 21)`` at ``times``."""
        style: Style = self.mapping.style
        out = values
        if style.tremble_amplitude > 0:
            cols = _motors(style.tremble_motors)
            out[:, cols] += style.tremble_amplitude * np.sin(2 * np.pi * style.tremble_frequency * times[:, None]
                                                             + self.phases[1, cols])
        if style.sharpen_steps:
            cols = _motors(style.sharpen_motors)
            levels = style.sharpen_steps - 1
            out[:, cols] = np.round(np.clip(out[:, cols], 0, 1) * levels) / levels
        return out


def across_motors(values: np.ndarray, mapping: Mapping, neutral: np.ndarray) -> np.ndarray:
    """The eyes' pair, symmetric pairs, one side copied and mirror on frames ``(F, 21)``; a new array."""
    out = values.copy()
    if mapping.eyes.lids:
        cols = [motor_index(code) for code in mapping.eyes.lids]
        out[:, cols] = eyes_pair(out[:, cols], neutral[cols], mapping.eyes.sync, mapping.eyes.closed)
    for right, left in mapping.symmetric:
        i, j = motor_index(right), motor_index(left)
        out[:, i] = out[:, j] = 0.5 * (out[:, i] + out[:, j])
    if mapping.copy_side:
        for right, left in MIRROR_PAIRS:
            i, j = motor_index(right), motor_index(left)
            src, dst = (i, j) if mapping.copy_side == "right" else (j, i)
            out[:, dst] = out[:, src]
    return mirror_values(out, neutral) if mapping.mirror else out


#: Past ``sync``, the share of a lid's neutral over which a pair goes from blinking together to
#: winking, so that the eyes do not flick between the two.
WINK_BLEND = 0.15


def eyes_pair(lids: np.ndarray, neutral: np.ndarray, sync: float, closed: float) -> np.ndarray:
    """Two upper lids ``(F, 2)`` (right, left) that blink together and wink cleanly; ``(F, 2)``.

    Each lid's openness is its value over its ``neutral`` (1 at rest). Trackers see a pair of
    eyes as one: a wink drags the open eye a fifth of the way shut and closes the winking one only
    two thirds of the way (MediaPipe on a GRID frame whose one eye is taken from a blink), and
    their two lids jitter apart. So where the openings differ by at most ``sync`` both lids take
    their mean (a blink, or jitter); where they differ by more (a wink) the more open eye opens at
    least to its rest and the other closes, its openness below ``closed`` reaching 0; between,
    over :data:`WINK_BLEND`, the two blend.
    """
    rest = np.maximum(np.asarray(neutral, dtype=float), 1e-6)
    right, left = lids[:, 0] / rest[0], lids[:, 1] / rest[1]  # openness
    together = 0.5 * (right + left)
    right_wide = right >= left  # the wider eye (the right where they are level)
    wide = np.maximum(np.where(right_wide, right, left), 1.0)
    shut = np.clip((np.where(right_wide, left, right) - closed) / (1.0 - closed), 0.0, None)
    share = np.clip((np.abs(right - left) - sync) / WINK_BLEND, 0.0, 1.0)
    out = np.empty_like(lids, dtype=float)
    out[:, 0] = ((1 - share) * together + share * np.where(right_wide, wide, shut)) * rest[0]
    out[:, 1] = ((1 - share) * together + share * np.where(right_wide, shut, wide)) * rest[1]
    return np.where(np.isnan(lids).any(axis=1, keepdims=True), lids, out)


def trailing_mean(values: np.ndarray, window: int) -> np.ndarray:
    """Mean of each frame and the ``window - 1`` before it, per column of ``(F, C)``; the first
    frame stands in for frames before the start."""
    padded = np.concatenate([np.repeat(values[:1], window - 1, axis=0), values])
    sums = np.cumsum(padded, axis=0)
    sums = np.concatenate([np.zeros((1, values.shape[1])), sums])
    return (sums[window:] - sums[:-window]) / window


def _motors(codes: tuple[str, ...]) -> np.ndarray:
    """Columns of the named motors (all when none are named)."""
    return np.array([motor_index(c) for c in codes or MOTOR_CODES], dtype=int)


@dataclass(frozen=True)
class _Pairs:
    """The ``pair`` rules' motors as columns, made once: each motor ``col`` ``(P,)``, its partner
    ``other`` ``(P,)``, whether a made-up side takes its partner's move (``made_up`` ``(P,)``), and
    its ``near`` motors and their partners ``across``, ``(P, N)``, padded where ``has`` is false."""

    col: np.ndarray
    other: np.ndarray
    made_up: np.ndarray
    near: np.ndarray
    across: np.ndarray
    has: np.ndarray

    @classmethod
    def of(cls, rules: list[MotorRule]) -> _Pairs:
        """The columns of the ``pair`` rules ``rules``."""
        width = max((len(r.loss_near) for r in rules), default=0)
        near = np.zeros((len(rules), width), dtype=int)
        across, has = np.zeros_like(near), np.zeros(near.shape, dtype=bool)
        for i, rule in enumerate(rules):
            for j, code in enumerate(rule.loss_near):
                near[i, j], across[i, j], has[i, j] = code_index(code), code_index(MIRROR_OF[code]), True
        return cls(np.array([code_index(r.code) for r in rules], dtype=int),
                   np.array([code_index(MIRROR_OF[r.code]) for r in rules], dtype=int),
                   np.array([r.loss_made_up for r in rules], dtype=bool), near, across, has)
