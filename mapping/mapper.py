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

from mapping.blink_gaps import finish_blinks
from mapping.coupling import decoupled, driver_of
from mapping.mapfile import Mapping, MotorRule
from mapping.plan import MODES, ONLY_SIGN, MotorPlan, combine_pairs, normalise_pairs, resolved_mode, span_of
from mapping.profile import Profile, SourceRange
from mapping.reference_bridge import fade_frames
from mapping.rules import MotorRules
from mapping.solver import Solver
from mapping.sources import Source, head_angles, measure
from mapping.stabilise import Stabilised
from toon import MotorTrack, standard_neutral
from toon.motors import N_CODES, N_MOTORS, code_index, extended_neutral

FILLED_QUALITY = 0.5
#: Frames :func:`motor_values` measures and normalises at once: every frame is mapped on its own,
#: and an hour's take measured whole held gigabytes of sources side by side.
FRAMES_AT_ONCE = 16384


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
    neutral = extended_neutral(standard_neutral() if target_neutral is None else target_neutral)
    quality = marker_quality(stable.local, filled)
    raw, confidence = motor_values(mapping, stable, columns, quality, profile, neutral, fade=fade_frames(rate))
    invented = made_up(confidence)
    values = MotorRules(mapping, rate, neutral, seed).apply(raw, times, invented)
    values, finished = finish_blinks(values, invented, rate)  # offline only: it reads past the gap
    if mapping.style.time_scale != 1.0:  # the one style operator with no live form: it changes the frame count
        scale = mapping.style.time_scale
        new_times = times[0] + np.arange(int(round(len(times) * scale))) / rate
        stretched = times[0] + (times - times[0]) * scale
        values, confidence = _resample(values, stretched, new_times), _resample(confidence, stretched, new_times)
    extras = mapping.extra_codes  # the standard extras the mapping drives (HT): columns after the 21
    meta = {"mapping": mapping.name, "profile": profile.performer or profile.markerset,
            "mapped": [r.code for r in mapping.rules if r.code not in extras], "mapped_extra": list(extras),
            "lost_frames": int(np.isnan(raw[:, :N_MOTORS]).any(axis=1).sum()),
            "blinks_finished_s": [round(float(times[0]) + t, 3) for t in finished]}
    return MotorTrack(values[:, :N_MOTORS], rate, confidence=np.clip(confidence[:, :N_MOTORS], 0.0, 1.0), meta=meta,
                      extra_codes=extras, extra=values[:, [code_index(c) for c in extras]] if extras else None)


def made_up(confidence: np.ndarray) -> np.ndarray:
    """Where a motor's confidence (:func:`motor_values`, any shape) says that none of its sources
    was measured and cleaning made them all up (filled, or held live): above 0, at most
    :data:`FILLED_QUALITY`."""
    return (confidence > 0.0) & (confidence <= FILLED_QUALITY + 1e-9)


def marker_quality(local: np.ndarray, filled: np.ndarray | None = None) -> np.ndarray:
    """Each marker's quality per frame ``(F, M)`` from head-frame markers ``(F, M, 3)``: 1 seen,
    :data:`FILLED_QUALITY` where ``filled`` (made up by the gap filler), 0 unseen."""
    quality = np.isfinite(local).all(axis=-1).astype(float)
    if filled is not None:
        quality[filled] = FILLED_QUALITY
    return quality


def motor_values(mapping: Mapping, stable: Stabilised, columns: dict[str, int], quality: np.ndarray,
                 profile: Profile, neutral: np.ndarray, plan: MotorPlan | None = None, fade: float = np.inf
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Each motor's value before the per-frame rules (:class:`mapping.rules.MotorRules`) and its
    confidence, both ``(F, 21)``: NaN where a mapped motor sees none of its sources, the face's
    ``neutral`` for motors the mapping leaves alone.

    Every rule at once (:class:`mapping.plan.MotorPlan`): each distinct source is measured once,
    every (rule, source) pair is normalised in one pass, and the rules' sources are combined
    side by side, so that a single frame (the live sender's) costs a few dozen array
    operations, not a few per rule. ``plan``: the plan of the mapping's rules under ``profile``
    for ``columns``, where the caller keeps one (made here otherwise); ``fade``: as
    :meth:`mapping.solver.Solver.solve` has it."""
    frames = len(stable.local)
    neutral = extended_neutral(neutral)
    values = np.tile(neutral, (frames, 1))
    confidence = np.ones((frames, N_CODES))
    if not mapping.rules:
        return values, confidence
    plan = plan or MotorPlan.of(mapping.rules, profile, columns)
    combined, sure = np.empty((frames, len(mapping.rules))), np.empty((frames, len(mapping.rules)))
    for first in range(0, frames, FRAMES_AT_ONCE):  # each frame on its own: a long take's copies stay small
        part = slice(first, first + FRAMES_AT_ONCE)
        combined[part], sure[part] = rule_shares(mapping, stable.frames(part), columns, quality[part], profile, plan)
    if profile.solver is not None:  # learned from a range-of-motion sweep: all motors at once (mapping.solver)
        combined, sure = solved_shares(profile.solver, mapping, stable.local, columns, quality, combined, sure, fade)
    rest = np.asarray(neutral, dtype=float)[plan.columns]
    for first in range(0, frames, FRAMES_AT_ONCE):
        part = slice(first, first + FRAMES_AT_ONCE)
        values[part, plan.columns] = _onto_motors(combined[part], plan, rest)
    confidence[:, plan.columns] = sure
    return values, confidence


def _onto_motors(combined: np.ndarray, plan: MotorPlan, rest: np.ndarray) -> np.ndarray:
    """The rules' shares ``(F, R)`` as motor values ``(F, R)``: the performer's range (or a score)
    onto the motor's way from ``rest`` ``(R,)`` to 0 or to 1, with each rule's gain, offset, curve
    and clamp."""
    delta = np.where(plan.ways, np.where(combined >= 0, combined * (1.0 - rest), combined * rest), combined)
    value = rest + plan.gain * delta + plan.offset
    for r, xs, ys in plan.curves:
        value[:, r] = np.where(np.isnan(value[:, r]), np.nan, np.interp(value[:, r], xs, ys))
    return _clamp_many(value, plan)


def rule_shares(mapping: Mapping, stable: Stabilised, columns: dict[str, int], quality: np.ndarray,
                profile: Profile, plan: MotorPlan) -> tuple[np.ndarray, np.ndarray]:
    """Each rule's signed share of its motor's way (-1 at the performer's low end, 0 at rest, +1
    at the high end, inverted as the rule says; NaN where none of its sources is seen) and its
    confidence (its sources' mean quality), both ``(F, R)`` in ``mapping.rules`` order."""
    head = head_angles(stable.rotation, profile.rest_rotation, profile.head_axes)
    drivers = normalised_drivers(mapping, stable, columns, head, profile) if profile.couplings else {}
    raw, sure = _measure_all(plan, stable, columns, head, quality)
    normalised = normalise_pairs(raw[:, plan.key], plan.mode, plan.rest, plan.up, plan.down, plan.scale, plan.sign,
                                 plan.only)
    if drivers:
        for j in np.flatnonzero(plan.decouples):
            normalised[:, j] = decoupled(normalised[:, j], plan.sources[j], drivers, profile,
                                         (float(plan.reach[j, 0]), float(plan.reach[j, 1])))
    combined = combine_pairs(normalised, plan) * plan.invert
    return combined, np.add.reduceat(sure[:, plan.key], plan.starts, axis=1) / plan.counts


def solved_shares(solver: Solver, mapping: Mapping, local: np.ndarray, columns: dict[str, int], quality: np.ndarray,
                  combined: np.ndarray, sure: np.ndarray, fade: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """The rules' shares and confidence ``(F, R)`` with the motors ``solver`` knows solved all at
    once; the others' as the rules gave them. The fit believes a sample the gap filler made as
    it does a seen one (measured on the three synthetic performers: left out of the fit, or at a
    third, their frames solved from too few markers and erred two to three times as much); it
    counts for half in the confidence, as in the rules'. A solved motor whose own sources were all
    made up (the rules' confidence ``sure``: :func:`made_up`) is made up, at most
    :data:`FILLED_QUALITY`, whatever seen markers it moves a little add: the fourth performer's
    outer brow, its marker filled, lifts a seen upper lid 0.2 mm a share, and at 0.5002 it read as
    measured, so the loss rules (``pair``) let its fill stand. ``fade``: as :meth:`Solver.solve` has it."""
    shares, confidence = solver.solve(local, columns, (quality > 0).astype(float), quality, fade)
    order = {code: k for k, code in enumerate(solver.codes)}
    combined, sure = combined.copy(), sure.copy()
    for r, rule in enumerate(mapping.rules):
        if rule.code in order:
            combined[:, r] = shares[:, order[rule.code]]
            sure[:, r] = np.where(made_up(sure[:, r]), np.minimum(confidence[:, order[rule.code]], FILLED_QUALITY),
                                  confidence[:, order[rule.code]])
    return combined, sure


def _measure_all(plan: MotorPlan, stable: Stabilised, columns: dict[str, int], head: np.ndarray,
                 quality: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every distinct source's values and how seen it is, both ``(F, D)``: its markers' least
    quality, a score's presence, or the head's fit."""
    frames = len(stable.local)
    raw = np.empty((frames, len(plan.distinct)))
    for k, name in zip(plan.scores, plan.channels, strict=True):
        raw[:, k] = stable.channels.get(name, np.nan)  # a channel the take has not: NaN
    for k in plan.measured:
        raw[:, k] = measure(plan.distinct[k], stable.local, columns, head, stable.channels)
    sure = np.empty_like(raw)
    sure[:, plan.marker_sure] = quality[:, plan.marker_columns].min(axis=2)
    sure[:, plan.scores] = np.isfinite(raw[:, plan.scores])
    sure[:, plan.head_sure] = stable.ok[:, None]
    return raw, sure


def _clamp_many(value: np.ndarray, plan: MotorPlan) -> np.ndarray:
    """Each rule's clamp on its column of ``value`` ``(F, R)``: hard, soft (unchanged in the middle,
    easing into the limits over the outer tenth) or none."""
    low, high = plan.low, plan.high
    out = np.where(plan.hard, np.clip(value, low, high), value)
    for r in plan.soft:  # few rules ease
        v, knee = value[:, r], 0.1 * (high[r] - low[r])
        upper, lower = high[r] - knee, low[r] + knee
        eased = np.where(v > upper, upper + knee * np.tanh((v - upper) / knee), v)
        out[:, r] = np.where(v < lower, lower - knee * np.tanh((lower - v) / knee), eased)
    return out


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
    rest, up, down = span_of(span)
    code = np.array([MODES.index(mode)])
    out = normalise_pairs(np.asarray(value, dtype=float)[:, None], code, np.array([rest]), np.array([up]),
                          np.array([down]), np.array([rule.scale]), np.array([-1.0 if source.invert else 1.0]),
                          np.array([ONLY_SIGN[source.only]]))
    return out[:, 0]


def _resample(values: np.ndarray, times: np.ndarray, new_times: np.ndarray) -> np.ndarray:
    """Frames ``(F, C)`` at ``times`` interpolated at ``new_times``."""
    return np.column_stack([np.interp(new_times, times, values[:, c]) for c in range(values.shape[1])])
