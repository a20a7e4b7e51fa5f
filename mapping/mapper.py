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

from dataclasses import dataclass

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
                 profile: Profile, neutral: np.ndarray, plan: MotorPlan | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Each motor's value before the per-frame rules (:class:`mapping.rules.MotorRules`) and its
    confidence, both ``(F, 21)``: NaN where a mapped motor sees none of its sources, the face's
    ``neutral`` for motors the mapping leaves alone.

    Every rule at once: each distinct source is measured once, every (rule, source) pair is
    normalised in one pass, and the rules' sources are combined side by side (padded to the
    most sources a rule has), so that a single frame (the live sender's) costs a few dozen
    array operations, not a few per rule. ``plan``: :meth:`MotorPlan.of` the mapping's rules and
    ``profile``, where the caller keeps one (made here otherwise)."""
    frames = len(stable.local)
    values = np.tile(np.asarray(neutral, dtype=float), (frames, 1))
    confidence = np.ones((frames, len(MOTOR_CODES)))
    rules = mapping.rules
    if not rules:
        return values, confidence
    head = head_angles(stable.rotation, profile.rest_rotation)
    drivers = normalised_drivers(mapping, stable, columns, head, profile) if profile.couplings else {}
    plan = plan or MotorPlan.of(rules, profile)
    raw = np.column_stack([measure(s, stable.local, columns, head, stable.channels) for s in plan.distinct])
    sure = np.column_stack([_source_confidence(s, raw[:, k], quality, columns, stable)
                            for k, s in enumerate(plan.distinct)])
    normalised = _normalise_many(raw[:, plan.key], plan.mode, plan.rest, plan.up, plan.down, plan.scale, plan.sign)
    if drivers:
        for j in np.flatnonzero(plan.decouples):
            normalised[:, j] = decoupled(normalised[:, j], plan.sources[j], drivers, profile)
    combined = _combine_many(normalised, plan, rules, frames) * np.where([r.invert for r in rules], -1.0, 1.0)
    cols = [motor_index(r.code) for r in rules]
    rest = np.asarray(neutral, dtype=float)[cols]
    ways = np.array([resolved_mode(r, profile) in ("profile", "score") for r in rules])
    # the performer's range (or a score) onto the motor's way to 0 or to 1
    delta = np.where(ways, np.where(combined >= 0, combined * (1.0 - rest), combined * rest), combined)
    value = rest + np.array([r.gain for r in rules]) * delta + np.array([r.offset for r in rules])
    for r, rule in enumerate(rules):
        if rule.curve:
            xs, ys = zip(*rule.curve, strict=True)
            value[:, r] = np.where(np.isnan(value[:, r]), np.nan, np.interp(value[:, r], xs, ys))
    values[:, cols] = _clamp_many(value, rules)
    counts = np.bincount(plan.rule, minlength=len(rules))
    confidence[:, cols] = np.add.reduceat(sure[:, plan.key][:, plan.order], plan.starts, axis=1) / counts
    return values, confidence


COMBINES = ("max", "min", "mean", "weighted")
SCALE, SCORE, PROFILE = 0, 1, 2


@dataclass(frozen=True)
class MotorPlan:
    """Every (rule, source) pair of a mapping under a profile, as arrays (``J`` pairs): what
    :func:`motor_values` needs of the rules and the ranges, made again whenever they change."""

    distinct: list[Source]  # each source once, by key
    sources: list[Source]  # (J,)
    key: np.ndarray  # (J,) the pair's column among the distinct sources
    rule: np.ndarray  # (J,) its rule
    slot: np.ndarray  # (J,) its place among its rule's sources
    mode: np.ndarray  # (J,) SCALE, SCORE or PROFILE
    rest: np.ndarray  # (J,)
    up: np.ndarray  # (J,)
    down: np.ndarray  # (J,)
    scale: np.ndarray  # (J,)
    sign: np.ndarray  # (J,) -1 for an inverted source
    weight: np.ndarray  # (J,)
    decouples: np.ndarray  # (J,) bool
    width: int  # the most sources a rule has
    order: np.ndarray  # (J,) pairs grouped by rule (they are already)
    starts: np.ndarray  # (R,) each rule's first pair

    @classmethod
    def of(cls, rules: tuple[MotorRule, ...], profile: Profile) -> MotorPlan:
        keys: dict[str, int] = {}
        distinct: list[Source] = []
        rows: list[tuple] = []
        for r, rule in enumerate(rules):
            mode = resolved_mode(rule, profile)
            for slot, source in enumerate(rule.sources):
                if source.key not in keys:
                    keys[source.key] = len(distinct)
                    distinct.append(source)
                span = profile.sources.get(source.key)
                if mode == "profile" and span is None:
                    raise ValueError(f"motor {rule.code}: a profile-normalised rule needs the range of {source.key}")
                rest, up, down = _span(span)
                rows.append((source, keys[source.key], r, slot, ("scale", "score", "profile").index(mode), rest, up,
                             down, rule.scale, -1.0 if source.invert else 1.0,
                             source.weight if rule.combine == "weighted" else 1.0, bool(rule.decouple)))
        c = list(zip(*rows, strict=True))
        rule_of = np.array(c[2])
        number = [np.array(column, dtype=float) for column in c[5:11]]
        return cls(distinct=distinct, sources=list(c[0]), key=np.array(c[1]), rule=rule_of, slot=np.array(c[3]),
                   mode=np.array(c[4]), rest=number[0], up=number[1], down=number[2], scale=number[3],
                   sign=number[4], weight=number[5], decouples=np.array(c[11]),
                   width=max(len(r.sources) for r in rules), order=np.arange(len(rows)),
                   starts=np.searchsorted(rule_of, np.arange(len(rules))))


def _combine_many(normalised: np.ndarray, plan: MotorPlan, rules: tuple[MotorRule, ...], frames: int) -> np.ndarray:
    """Each rule's sources ``normalised`` ``(F, J)`` combined over those seen ``(F, R)``: a rule of
    one source is that source (times its weight, if weighted); the others side by side, a slab
    per source place, each way of combining on the rules that use it. NaN where none is seen."""
    combined = np.empty((frames, len(rules)))
    counts = np.bincount(plan.rule, minlength=len(rules))
    alone = np.flatnonzero(counts == 1)
    combined[:, alone] = normalised[:, plan.starts[alone]] * plan.weight[plan.starts[alone]]
    several = np.flatnonzero(counts > 1)
    if not several.size:
        return combined
    pairs = np.isin(plan.rule, several)
    place = np.searchsorted(several, plan.rule[pairs])
    width = int(counts[several].max())
    stack = np.full((width, frames, len(several)), np.nan)
    stack[plan.slot[pairs], :, place] = normalised[:, pairs].T
    seen = np.isfinite(stack)
    weights = np.zeros((width, 1, len(several)))
    weights[plan.slot[pairs], 0, place] = plan.weight[pairs]
    kind = np.array([COMBINES.index(rules[r].combine) for r in several])
    out = np.empty((frames, len(several)))
    for k in np.unique(kind):  # each way of combining, on the rules that use it
        cols = np.flatnonzero(kind == k)
        part, ok, w = stack[:, :, cols], seen[:, :, cols], weights[:, :, cols]
        if COMBINES[k] == "max":
            out[:, cols] = np.where(ok, part, -np.inf).max(axis=0)
        elif COMBINES[k] == "min":
            out[:, cols] = np.where(ok, part, np.inf).min(axis=0)
        else:
            total = (ok * w).sum(axis=0)
            mean = (np.where(ok, part, 0.0) * w).sum(axis=0) / np.where(total != 0, total, 1.0)
            # weighted: a sum, the unseen sources' share spread over the seen
            out[:, cols] = mean * w.sum(axis=0) if COMBINES[k] == "weighted" else mean
    combined[:, several] = np.where(seen.any(axis=0), out, np.nan)
    return combined


def _span(span: SourceRange | None) -> tuple[float, float, float]:
    """A source's rest and its ranges above and below it (1 where there is no range)."""
    if span is None:
        return 0.0, 1.0, 1.0
    return span.neutral, max(span.high - span.neutral, 1e-9), max(span.neutral - span.low, 1e-9)


def _normalise_many(raw: np.ndarray, mode: np.ndarray, rest: np.ndarray, up: np.ndarray, down: np.ndarray,
                    scale: np.ndarray, sign: np.ndarray) -> np.ndarray:
    """Sources' values ``(F, J)`` normalised each by its own mode (see :func:`normalise`)."""
    out = raw - rest
    ranged = np.flatnonzero(mode == PROFILE)
    if ranged.size:
        part = out[:, ranged]
        out[:, ranged] = np.where(part >= 0, part / up[ranged], part / down[ranged])
    scaled = np.flatnonzero(mode == SCALE)
    if scaled.size:
        out[:, scaled] /= scale[scaled]
    return out * sign


def _source_confidence(source: Source, raw: np.ndarray, quality: np.ndarray, columns: dict[str, int],
                       stable: Stabilised) -> np.ndarray:
    """How seen a source is per frame ``(F,)``: its markers' least quality, a score's presence,
    or the head's fit."""
    if source.markers:
        return np.min(quality[:, [columns[m] for m in source.markers]], axis=1)
    if source.kind == "blendshape":
        return np.isfinite(raw).astype(float)
    return stable.ok.astype(float)


def _clamp_many(value: np.ndarray, rules: tuple[MotorRule, ...]) -> np.ndarray:
    """Each rule's clamp on its column of ``value`` ``(F, R)``: hard, soft (unchanged in the middle,
    easing into the limits over the outer tenth) or none."""
    low, high = (np.array([r.limits[i] for r in rules]) for i in (0, 1))
    hard = np.array([r.clamp == "hard" for r in rules])
    out = np.where(hard, np.clip(value, low, high), value)
    for r in np.flatnonzero([rule.clamp == "soft" for rule in rules]):  # few rules ease
        v, knee = value[:, r], 0.1 * (high[r] - low[r])
        upper, lower = high[r] - knee, low[r] + knee
        eased = np.where(v > upper, upper + knee * np.tanh((v - upper) / knee), v)
        out[:, r] = np.where(v < lower, lower - knee * np.tanh((lower - v) / knee), eased)
    return out


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
    fraction) or in motor units (``scale``); inverted if the source says. ``mode``: ``profile``,
    ``score`` or ``scale``, what a ``calibrated`` rule resolved to (the rule's own by default)."""
    mode = mode or rule.normalise
    if mode == "profile" and span is None:
        raise ValueError(f"motor {rule.code}: a profile-normalised rule needs the range of {source.key}")
    rest, up, down = _span(span)
    code = np.array([("scale", "score", "profile").index(mode)])
    out = _normalise_many(np.asarray(value, dtype=float)[:, None], code, np.array([rest]), np.array([up]),
                          np.array([down]), np.array([rule.scale]), np.array([-1.0 if source.invert else 1.0]))
    return out[:, 0]


def _resample(values: np.ndarray, times: np.ndarray, new_times: np.ndarray) -> np.ndarray:
    """Frames ``(F, C)`` at ``times`` interpolated at ``new_times``."""
    return np.column_stack([np.interp(new_times, times, values[:, c]) for c in range(values.shape[1])])
