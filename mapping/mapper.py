"""Apply a mapping file to a cleaned, head-stabilised take: motors, confidence and loss.

For each mapped motor (in this order): measure its sources; normalise each by the performer
profile (``profile``: the side of the performer's range the value is on becomes the motor's way
to 0 or to 1 from its neutral, so the performer's range fills the motor's; ``scale``: units per
motor unit; ``calibrated``: as ``profile`` where the profile's ranges come from a range-of-motion
calibration and it has this source's, else as ``scale``); invert a source if asked; combine
(max, mean, min or weighted, over the sources seen in the frame); invert;
``value = neutral + gain * delta + offset``; the curve; the clamp. Where no source is seen the
per-frame rules take over (:mod:`mapping.rules`, shared with the live sender): the loss policy,
the per-channel filter, speed limit and delay, the cross-motor operations and the style
operators. Offline mapping alone has style's time scaling.

Confidence per motor and frame is the mean over its sources of their markers' quality: 1 seen,
0.5 filled by the gap filler, 0 unseen (a blendshape source: 1 measured, 0 not).
"""

from __future__ import annotations

import numpy as np

from mapping.coupling import decoupled, driver_of
from mapping.mapfile import Mapping, MotorRule
from mapping.profile import Profile, SourceRange
from mapping.rules import MotorRules
from mapping.sources import Source, head_angles, measure
from mapping.stabilise import Stabilised
from toon import MOTOR_CODES, MotorTrack, motor_index, standard_neutral

FILLED_QUALITY = 0.5


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
    quality = marker_quality(stable.local, filled)
    raw, confidence = motor_values(mapping, stable, columns, quality, profile, neutral)
    values = MotorRules(mapping, rate, neutral, seed).apply(raw, times)
    if mapping.style.time_scale != 1.0:  # the one style operator with no live form: it changes the frame count
        scale = mapping.style.time_scale
        new_times = times[0] + np.arange(int(round(len(times) * scale))) / rate
        stretched = times[0] + (times - times[0]) * scale
        values, confidence = _resample(values, stretched, new_times), _resample(confidence, stretched, new_times)
    meta = {"mapping": mapping.name, "profile": profile.performer or profile.markerset,
            "mapped": [r.code for r in mapping.rules], "lost_frames": int(np.isnan(raw).any(axis=1).sum())}
    return MotorTrack(values, rate, confidence=np.clip(confidence, 0.0, 1.0), meta=meta)  # the rules clip values


def marker_quality(local: np.ndarray, filled: np.ndarray | None = None) -> np.ndarray:
    """Each marker's quality per frame ``(F, M)`` from head-frame markers ``(F, M, 3)``: 1 seen,
    :data:`FILLED_QUALITY` where ``filled`` (made up by the gap filler), 0 unseen."""
    quality = np.isfinite(local).all(axis=-1).astype(float)
    if filled is not None:
        quality[filled] = FILLED_QUALITY
    return quality


def motor_values(mapping: Mapping, stable: Stabilised, columns: dict[str, int], quality: np.ndarray,
                 profile: Profile, neutral: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each motor's value before the per-frame rules (:class:`mapping.rules.MotorRules`) and its
    confidence, both ``(F, 21)``: NaN where a mapped motor sees none of its sources, the face's
    ``neutral`` for motors the mapping leaves alone."""
    frames = len(stable.local)
    head = head_angles(stable.rotation, profile.rest_rotation)
    values = np.tile(np.asarray(neutral, dtype=float), (frames, 1))
    confidence = np.ones((frames, len(MOTOR_CODES)))
    drivers = normalised_drivers(mapping, stable, columns, head, profile) if profile.couplings else {}
    for rule in mapping.rules:
        col = motor_index(rule.code)
        values[:, col], confidence[:, col] = _motor_value(rule, stable, columns, head, quality, profile,
                                                          float(neutral[col]), drivers)
    return values, confidence


def resolved_mode(rule: MotorRule, profile: Profile) -> str:
    """``profile`` or ``scale``: what ``rule``'s normalisation is with ``profile`` (a ``calibrated``
    rule uses the profile's ranges where a range-of-motion calibration measured them)."""
    if rule.normalise != "calibrated":
        return rule.normalise
    calibrated = profile.full_range and all(s.key in profile.sources for s in rule.sources)
    return "profile" if calibrated else "scale"


def normalised_drivers(mapping: Mapping, stable: Stabilised, columns: dict[str, int], head: np.ndarray,
                       profile: Profile) -> dict[str, np.ndarray]:
    """The motion of the motors that rules decouple from, each as its first source's normalised
    values ``(F,)`` keyed by that source's key."""
    out = {}
    for code in sorted({c for r in mapping.rules for c in r.decouple}):
        rule, source = driver_of(mapping, code)
        raw = measure(source, stable.local, columns, head, stable.channels)
        out[source.key] = normalise(raw, source, rule, profile.sources.get(source.key), resolved_mode(rule, profile))
    return out


def check_profile(mapping: Mapping, profile: Profile) -> None:
    """Raise ValueError naming the sources ``profile`` has no range for (the performer's range is
    what ``profile`` normalisation divides by)."""
    wanted = {s.key for r in mapping.rules if r.normalise == "profile" for s in r.sources}  # calibrated: optional
    missing = sorted(wanted - set(profile.sources))
    if missing:
        raise ValueError(f"the profile has no range for {', '.join(missing)}; calibrate with this mapping")


def normalise(value: np.ndarray, source: Source, rule: MotorRule, span: SourceRange | None,
              mode: str = "") -> np.ndarray:
    """A source's value as a signed fraction of the performer's range (``profile``: -1 at
    ``low``, 0 at rest, 1 at ``high``; ``score``: a score less its rest, the score being its own
    fraction) or in motor units (``scale``); inverted if the source says.
    ``mode``: ``profile`` or ``scale``, what a ``calibrated`` rule resolved to (the rule's own
    by default)."""
    if (mode or rule.normalise) == "scale":
        rest = span.neutral if span is not None else 0.0
        out = (value - rest) / rule.scale
    elif (mode or rule.normalise) == "score":  # already a fraction of its whole way (a blendshape score)
        out = value - (span.neutral if span is not None else 0.0)
    else:
        if span is None:
            raise ValueError(f"motor {rule.code}: a profile-normalised rule needs the range of {source.key}")
        up = max(span.high - span.neutral, 1e-9)
        down = max(span.neutral - span.low, 1e-9)
        offset = value - span.neutral
        out = np.where(offset >= 0, offset / up, offset / down)
    return -out if source.invert else out


def _motor_value(rule: MotorRule, stable: Stabilised, columns: dict[str, int], head: np.ndarray,
                 quality: np.ndarray, profile: Profile, rest: float, drivers: dict[str, np.ndarray]
                 ) -> tuple[np.ndarray, np.ndarray]:
    """One motor's value before loss handling (NaN where no source is seen) and its confidence;
    ``drivers``: the normalised motion of the motors it decouples from."""
    normalised, confidences = [], []
    mode = resolved_mode(rule, profile)
    for source in rule.sources:
        span = profile.sources.get(source.key)
        raw = measure(source, stable.local, columns, head, stable.channels)
        value = normalise(raw, source, rule, span, mode)
        normalised.append(decoupled(value, source, drivers, profile) if drivers and rule.decouple else value)
        if source.markers:
            confidences.append(np.min(quality[:, [columns[m] for m in source.markers]], axis=1))
        elif source.kind == "blendshape":
            confidences.append(np.isfinite(raw).astype(float))
        else:
            confidences.append(stable.ok.astype(float))
    stack = np.column_stack(normalised)
    combined = _combine(stack, rule)
    if rule.invert:
        combined = -combined
    if mode in ("profile", "score"):  # the performer's range (or a score) onto the motor's way to 0 or to 1
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


def _resample(values: np.ndarray, times: np.ndarray, new_times: np.ndarray) -> np.ndarray:
    """Frames ``(F, C)`` at ``times`` interpolated at ``new_times``."""
    return np.column_stack([np.interp(new_times, times, values[:, c]) for c in range(values.shape[1])])
