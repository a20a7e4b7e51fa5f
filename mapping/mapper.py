"""Apply a mapping file to a cleaned, head-stabilised take: motors, confidence and loss.

For each mapped motor (in this order): measure its sources; normalise each by the performer
profile (``profile``: the side of the performer's range the value is on becomes the motor's way
to 0 or to 1 from its neutral, so the performer's range fills the motor's; ``scale``: units per
motor unit); invert a source if asked; combine (max, mean, min or weighted, over the sources seen
in the frame); invert; ``value = neutral + gain * delta + offset``; the curve; the clamp. Where no
source is seen the loss policy fills in (hold the last value, ease to neutral over a time, or an
idle drift about neutral); then the per-channel filter, the speed limit and the delay. Then the
cross-motor operations (symmetric pairs, one side copied, mirror) and the style operators
(tremble, sharpen, smooth, time scaling).

Confidence per motor and frame is the mean over its sources of their markers' quality: 1 seen,
0.5 filled by the gap filler, 0 unseen.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import uniform_filter1d

from mapping.filters import Butterworth, Delay, OneEuro, SavitzkyGolay, SpeedLimit
from mapping.mapfile import Mapping, MotorRule, Style
from mapping.profile import Profile, SourceRange
from mapping.sources import Source, head_angles, measure
from mapping.stabilise import Stabilised
from toon import MOTOR_CODES, MotorTrack, mirror_values, motor_index, standard_neutral
from toon.motors import MIRROR_PAIRS

FILLED_QUALITY = 0.5
IDLE_AMPLITUDE = 0.03  # motor units of the idle drift
IDLE_HZ = 0.25


def map_stabilised(stable: Stabilised, columns: dict[str, int], times: np.ndarray, rate: float, mapping: Mapping,
                   profile: Profile, target_neutral: np.ndarray | None = None, filled: np.ndarray | None = None,
                   seed: int = 0) -> MotorTrack:
    """Motor track of a cleaned take.

    Parameters
    ----------
    stable : Stabilised
        Head-frame markers and head pose.
    columns : dict
        Marker-set label -> column of ``stable.local``.
    times : ndarray, shape (F,)
    rate : float
    mapping, profile
        The character's mapping and the performer's profile (it must hold every source's range).
    target_neutral : ndarray, shape (21,), optional
        The face's neutral (the performer's rest maps onto it); the standard neutral by default.
    filled : ndarray of bool, shape (F, M), optional
        Samples the gap filler made up (they count as half seen).
    seed : int
        Seeds the idle drift and the tremble.
    """
    check_profile(mapping, profile)
    neutral = standard_neutral() if target_neutral is None else np.asarray(target_neutral, dtype=float)
    frames = len(times)
    quality = np.isfinite(stable.local).all(axis=2).astype(float)
    if filled is not None:
        quality[filled] = FILLED_QUALITY
    head = head_angles(stable.rotation, profile.rest_rotation)
    values = np.tile(neutral, (frames, 1))
    confidence = np.ones((frames, len(MOTOR_CODES)))
    rng = np.random.default_rng(seed)
    lost = np.zeros((frames, len(MOTOR_CODES)), dtype=bool)
    for rule in mapping.rules:
        col = motor_index(rule.code)
        raw, conf = _motor_value(rule, stable, columns, head, quality, profile, neutral[col])
        lost[:, col] = np.isnan(raw)
        values[:, col] = _fill_lost(raw, rule, neutral[col], times, rng)
        confidence[:, col] = conf
    values = _channel_stages(values, mapping, times, rate)
    values = _across_motors(values, mapping, neutral)
    values, times_out = _style(values, mapping.style, times, rate, rng)
    if len(times_out) != frames:
        confidence = _resample(confidence, times, times_out)
    meta = {"mapping": mapping.name, "profile": profile.performer or profile.markerset,
            "mapped": [r.code for r in mapping.rules], "lost_frames": int(lost.any(axis=1).sum())}
    return MotorTrack(np.clip(values, 0.0, 1.0), rate, confidence=np.clip(confidence, 0.0, 1.0), meta=meta)


def check_profile(mapping: Mapping, profile: Profile) -> None:
    """Raise ValueError naming the sources ``profile`` has no range for (the performer's range is
    what ``profile`` normalisation divides by)."""
    wanted = {s.key for r in mapping.rules if r.normalise == "profile" for s in r.sources}
    missing = sorted(wanted - set(profile.sources))
    if missing:
        raise ValueError(f"the profile has no range for {', '.join(missing)}; calibrate with this mapping")


def channel_limits(mapping: Mapping, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Each motor's speed limit (units/s, inf: none) and delay (whole frames), ``(21,)`` each."""
    speeds = np.full(len(MOTOR_CODES), np.inf)
    delays = np.zeros(len(MOTOR_CODES), dtype=int)
    for rule in mapping.rules:
        if rule.max_speed > 0:
            speeds[motor_index(rule.code)] = rule.max_speed
        delays[motor_index(rule.code)] = int(round(rule.delay * rate))
    return speeds, delays


def normalise(value: np.ndarray, source: Source, rule: MotorRule, span: SourceRange | None) -> np.ndarray:
    """A source's value as a signed fraction of the performer's range (``profile``: -1 at
    ``low``, 0 at rest, 1 at ``high``) or in motor units (``scale``); inverted if the source says."""
    if rule.normalise == "scale":
        rest = span.neutral if span is not None else 0.0
        out = (value - rest) / rule.scale
    else:
        if span is None:
            raise ValueError(f"motor {rule.code}: a profile-normalised rule needs the range of {source.key}")
        up = max(span.high - span.neutral, 1e-9)
        down = max(span.neutral - span.low, 1e-9)
        offset = value - span.neutral
        out = np.where(offset >= 0, offset / up, offset / down)
    return -out if source.invert else out


def _motor_value(rule: MotorRule, stable: Stabilised, columns: dict[str, int], head: np.ndarray,
                 quality: np.ndarray, profile: Profile, rest: float) -> tuple[np.ndarray, np.ndarray]:
    """One motor's value before loss handling (NaN where no source is seen) and its confidence."""
    normalised, confidences = [], []
    for source in rule.sources:
        span = profile.sources.get(source.key)
        raw = measure(source, stable.local, columns, head)
        normalised.append(normalise(raw, source, rule, span))
        if source.markers:
            confidences.append(np.min(quality[:, [columns[m] for m in source.markers]], axis=1))
        else:
            confidences.append(stable.ok.astype(float))
    stack = np.column_stack(normalised)
    combined = _combine(stack, rule)
    if rule.invert:
        combined = -combined
    if rule.normalise == "profile":  # the performer's range onto the motor's way to 0 or to 1
        delta = np.where(combined >= 0, combined * (1.0 - rest), combined * rest)
    else:
        delta = combined
    value = rest + rule.gain * delta + rule.offset
    if rule.curve:
        xs, ys = zip(*rule.curve, strict=True)
        value = np.where(np.isnan(value), np.nan, np.interp(value, xs, ys))
    return _clamp(value, rule), np.mean(confidences, axis=0)


def _combine(stack: np.ndarray, rule: MotorRule) -> np.ndarray:
    """Combine ``(F, S)`` normalised sources over those seen in each frame."""
    seen = np.isfinite(stack)
    any_seen = seen.any(axis=1)
    if rule.combine in ("max", "min"):
        fill = -np.inf if rule.combine == "max" else np.inf
        pick = np.max if rule.combine == "max" else np.min
        out = pick(np.where(seen, stack, fill), axis=1)
    else:
        weights = np.array([s.weight if rule.combine == "weighted" else 1.0 for s in rule.sources])
        total = np.where(seen, weights, 0.0).sum(axis=1)
        out = np.where(seen, stack, 0.0) @ weights / np.where(total != 0, total, 1.0)
        if rule.combine == "weighted":  # a weighted sum, the unseen sources' share spread over the seen
            out = out * weights.sum()
    return np.where(any_seen, out, np.nan)


def _clamp(value: np.ndarray, rule: MotorRule) -> np.ndarray:
    low, high = rule.limits
    if rule.clamp == "hard":
        return np.clip(value, low, high)
    if rule.clamp == "soft":  # unchanged in the middle, easing into the limits over the outer tenth
        knee = 0.1 * (high - low)
        upper, lower = high - knee, low + knee
        out = np.where(value > upper, upper + knee * np.tanh((value - upper) / knee), value)
        return np.where(value < lower, lower - knee * np.tanh((lower - value) / knee), out)
    return value


def _fill_lost(raw: np.ndarray, rule: MotorRule, rest: float, times: np.ndarray, rng: np.random.Generator
               ) -> np.ndarray:
    """Fill frames where no source is seen by the rule's loss policy."""
    lost = np.isnan(raw)
    if not lost.any():
        return raw
    index = np.where(~lost, np.arange(len(raw)), -1)
    np.maximum.accumulate(index, out=index)
    last = np.where(index >= 0, raw[np.maximum(index, 0)], rest)  # hold
    if rule.loss == "hold":
        return np.where(lost, last, raw)
    since = times - np.where(index >= 0, times[np.maximum(index, 0)], times[0])
    ease = np.clip(since / rule.loss_seconds, 0.0, 1.0) if rule.loss_seconds > 0 else np.ones_like(since)
    eased = last + (rest - last) * ease
    if rule.loss == "idle":
        phase = rng.uniform(0, 2 * np.pi)
        eased = eased + ease * IDLE_AMPLITUDE * np.sin(2 * np.pi * IDLE_HZ * times + phase)
    return np.where(lost, eased, raw)


def _channel_stages(values: np.ndarray, mapping: Mapping, times: np.ndarray, rate: float) -> np.ndarray:
    """Per-channel filters, speed limits and delays (each stage over the channels that use it)."""
    out = values.copy()
    for rule in mapping.rules:
        if rule.filter:
            col = motor_index(rule.code)
            out[:, col] = make_filter(rule.filter, rate).apply(out[:, col], times)
    speeds, delays = channel_limits(mapping, rate)
    if np.isfinite(speeds).any():
        limited = np.isfinite(speeds)
        out[:, limited] = SpeedLimit(speeds[limited]).apply(out[:, limited], times)
    if delays.any():
        out = Delay(delays).apply(out, times)
    return out


def make_filter(spec: dict, rate: float) -> OneEuro | Butterworth | SavitzkyGolay:
    """The filter a mapping's ``filter`` table names."""
    params = {k: v for k, v in spec.items() if k != "kind"}
    if spec["kind"] == "one-euro":
        return OneEuro(rate=rate, **params)
    if spec["kind"] == "butterworth":
        return Butterworth(rate=rate, **{k: (int(v) if k == "order" else v) for k, v in params.items()})
    return SavitzkyGolay(**{k: int(v) for k, v in params.items()})


def _across_motors(values: np.ndarray, mapping: Mapping, neutral: np.ndarray) -> np.ndarray:
    out = values.copy()
    for right, left in mapping.symmetric:
        i, j = motor_index(right), motor_index(left)
        out[:, i] = out[:, j] = 0.5 * (out[:, i] + out[:, j])
    if mapping.copy_side:
        for right, left in MIRROR_PAIRS:
            i, j = motor_index(right), motor_index(left)
            src, dst = (i, j) if mapping.copy_side == "right" else (j, i)
            out[:, dst] = out[:, src]
    return mirror_values(out, neutral) if mapping.mirror else out


def _style(values: np.ndarray, style: Style, times: np.ndarray, rate: float, rng: np.random.Generator
           ) -> tuple[np.ndarray, np.ndarray]:
    """CharToon's style operators; returns the values and their (possibly rescaled) times."""
    out = values.copy()
    every = tuple(MOTOR_CODES)
    if style.smooth_seconds > 0:
        cols = [motor_index(c) for c in style.smooth_motors or every]
        size = max(1, int(round(style.smooth_seconds * rate)))
        out[:, cols] = uniform_filter1d(out[:, cols], size, axis=0, mode="nearest")
    if style.tremble_amplitude > 0:
        for code in style.tremble_motors or every:
            phase = rng.uniform(0, 2 * np.pi)
            out[:, motor_index(code)] += style.tremble_amplitude * np.sin(2 * np.pi * style.tremble_frequency * times
                                                                          + phase)
    if style.sharpen_steps:
        cols = [motor_index(c) for c in style.sharpen_motors or every]
        levels = style.sharpen_steps - 1
        out[:, cols] = np.round(np.clip(out[:, cols], 0, 1) * levels) / levels
    if style.time_scale != 1.0:
        new_times = times[0] + np.arange(int(round(len(times) * style.time_scale))) / rate
        return _resample(out, times[0] + (times - times[0]) * style.time_scale, new_times), new_times
    return out, times


def _resample(values: np.ndarray, times: np.ndarray, new_times: np.ndarray) -> np.ndarray:
    return np.column_stack([np.interp(new_times, times, values[:, c]) for c in range(values.shape[1])])
