"""A mapping's rules under a profile as arrays: what :func:`mapping.mapper.motor_values` needs of
them, worked out once and kept while the rules and the ranges stand (a live mapper keeps one per
profile), so that mapping a frame is a few dozen array operations whatever the rules are.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from mapping.mapfile import MotorRule
from mapping.profile import Profile, SourceRange
from mapping.sources import Source
from toon.motors import code_index

SCALE, SCORE, PROFILE = 0, 1, 2
#: A source's ``only`` as a sign: +1 just its increase counts, -1 just its decrease, 0 both.
ONLY_SIGN = {"": 0, "increase": 1, "decrease": -1}
MODES = ("scale", "score", "profile")


@dataclass(frozen=True, eq=False)
class MotorPlan:
    """Every (rule, source) pair of ``R`` rules under a profile (``J`` pairs over ``D`` distinct
    sources), as arrays.

    Attributes
    ----------
    distinct : list of Source, length D
        Each source once, by key.
    scores : ndarray of int, shape (Ds,)
        The distinct sources that read a channel (blendshape scores), with their channels'
        names in ``channels``; the others are measured one by one (``measured``).
    marker_sure : ndarray of int, shape (Dm,)
        The distinct sources that read markers; ``marker_columns`` ``(Dm, L)`` their markers'
        columns (the first repeated up to the most a source reads), whose least quality is the
        source's confidence. Head sources (``head_sure``) are as sure as the head's fit.
    sources, key, rule : shape (J,)
        Each pair's source, its column among the distinct sources and its rule.
    mode, rest, up, down, scale, sign, only, weight, decouples : ndarray, shape (J,)
        How each pair is normalised (``SCALE``, ``SCORE``, ``PROFILE``), the performer's rest
        and ranges above and below it, the rule's scale, -1 for an inverted source, +1 where
        only its increase counts and -1 only its decrease (0 both), its weight (1 unless
        weighted) and whether it is decoupled.
    reach : ndarray, shape (J, 2)
        What one unit of each pair's normalised value is in the source's own units on its
        positive and its negative side (:func:`reach_of`), set with the profile.
    counts, starts : ndarray of int, shape (R,)
        Each rule's number of sources and its first pair.
    columns, invert, ways, gain, offset, low, high, hard : ndarray, shape (R,)
        Each rule's motor, -1 for an inverted rule, whether its delta is a fraction of the way
        to 0 or 1 (``profile`` and ``score``), gain, offset and clamp.
    curves : list of (int, tuple, tuple)
        The rules with a curve: their index and the curve's points.
    soft : list of int
        The rules with a soft clamp.
    alone : ndarray of int, shape (A,)
        The rules of one source; the rest (``several``, ``(S,)``) are reduced over their pairs:
        ``pairs`` ``(P,)`` those pairs (rule by rule), ``several_starts`` ``(S,)`` where each
        rule's pairs start among them, and ``groups`` each way of combining with its rules
        (places among the ``several``).
    """

    distinct: list[Source]
    channels: list[str]
    scores: np.ndarray
    measured: list[int]
    marker_sure: np.ndarray
    marker_columns: np.ndarray
    head_sure: np.ndarray
    sources: list[Source]
    key: np.ndarray
    rule: np.ndarray
    mode: np.ndarray
    rest: np.ndarray
    up: np.ndarray
    down: np.ndarray
    scale: np.ndarray
    sign: np.ndarray
    only: np.ndarray
    weight: np.ndarray
    decouples: np.ndarray
    counts: np.ndarray
    starts: np.ndarray
    columns: np.ndarray
    invert: np.ndarray
    ways: np.ndarray
    gain: np.ndarray
    offset: np.ndarray
    low: np.ndarray
    high: np.ndarray
    hard: np.ndarray
    curves: list[tuple[int, tuple[float, ...], tuple[float, ...]]]
    soft: list[int]
    alone: np.ndarray
    several: np.ndarray
    pairs: np.ndarray
    several_starts: np.ndarray
    groups: list[tuple[str, np.ndarray]]
    reach: np.ndarray

    @classmethod
    def of(cls, rules: tuple[MotorRule, ...], profile: Profile, columns: dict[str, int]) -> MotorPlan:
        """The plan of ``rules`` (at least one) under ``profile``, for markers at ``columns``
        (marker-set label -> column); a ValueError where a profile-normalised rule's source has
        no range in ``profile``."""
        keys: dict[str, int] = {}
        distinct: list[Source] = []
        pairs: list[tuple[Source, int, int, float]] = []
        for r, rule in enumerate(rules):
            for source in rule.sources:
                if source.key not in keys:
                    keys[source.key] = len(distinct)
                    distinct.append(source)
                pairs.append((source, keys[source.key], r, source.weight if rule.combine == "weighted" else 1.0))
        rule_of = np.array([p[2] for p in pairs])
        counts = np.bincount(rule_of, minlength=len(rules))
        starts = np.searchsorted(rule_of, np.arange(len(rules)))
        scores = [k for k, s in enumerate(distinct) if s.kind == "blendshape"]
        marked = [k for k, s in enumerate(distinct) if s.markers]
        longest = max((len(distinct[k].markers) for k in marked), default=1)
        marker_columns = np.array([[columns[m] for m in distinct[k].markers]
                                   + [columns[distinct[k].markers[0]]] * (longest - len(distinct[k].markers))
                                   for k in marked], dtype=int).reshape(len(marked), longest)
        weight = np.array([p[3] for p in pairs], dtype=float)
        several = np.flatnonzero(counts > 1)
        in_several = np.flatnonzero(np.isin(rule_of, several))
        combines = [rules[r].combine for r in several]
        plan = cls(
            distinct=distinct, channels=[distinct[k].channel for k in scores], scores=np.array(scores, dtype=int),
            measured=[k for k, s in enumerate(distinct) if s.kind != "blendshape"],
            marker_sure=np.array(marked, dtype=int), marker_columns=marker_columns,
            head_sure=np.array([k for k, s in enumerate(distinct) if not s.markers and s.kind != "blendshape"],
                               dtype=int),
            sources=[p[0] for p in pairs], key=np.array([p[1] for p in pairs]), rule=rule_of,
            mode=np.zeros(len(pairs), dtype=int), rest=np.zeros(len(pairs)), up=np.ones(len(pairs)),
            down=np.ones(len(pairs)), scale=np.array([rules[p[2]].scale for p in pairs], dtype=float),
            sign=np.array([-1.0 if p[0].invert else 1.0 for p in pairs]),
            only=np.array([ONLY_SIGN[p[0].only] for p in pairs]), weight=weight,
            decouples=np.array([bool(rules[p[2]].decouple) for p in pairs]), counts=counts, starts=starts,
            columns=np.array([code_index(r.code) for r in rules]),
            invert=np.where([r.invert for r in rules], -1.0, 1.0), ways=np.zeros(len(rules), dtype=bool),
            gain=np.array([r.gain for r in rules], dtype=float),
            offset=np.array([r.offset for r in rules], dtype=float),
            low=np.array([r.limits[0] for r in rules], dtype=float),
            high=np.array([r.limits[1] for r in rules], dtype=float),
            hard=np.array([r.clamp == "hard" for r in rules]),
            curves=[(r, tuple(x for x, _ in rule.curve), tuple(y for _, y in rule.curve))
                    for r, rule in enumerate(rules) if rule.curve],
            soft=[r for r, rule in enumerate(rules) if rule.clamp == "soft"],
            alone=np.flatnonzero(counts == 1), several=several, pairs=in_several,
            several_starts=np.searchsorted(rule_of[in_several], several),
            groups=[(how, np.flatnonzero([c == how for c in combines])) for how in dict.fromkeys(combines)],
            reach=np.ones((len(pairs), 2)))
        return plan.under(rules, profile)

    def under(self, rules: tuple[MotorRule, ...], profile: Profile) -> MotorPlan:
        """This plan (of ``rules``) with ``profile``'s ranges: what changes with the profile
        alone (a live learner's widening ranges) without working the rest out again."""
        modes = [resolved_mode(rule, profile) for rule in rules]
        spans, reach = [], []
        for source, r in zip(self.sources, self.rule, strict=True):
            span = profile.sources.get(source.key)
            if modes[r] == "profile" and span is None:
                raise ValueError(f"motor {rules[r].code}: a profile-normalised rule needs the range of {source.key}")
            spans.append(span_of(span))
            reach.append(reach_of(source, rules[r], profile))
        rest, up, down = (np.array(column, dtype=float) for column in zip(*spans, strict=True))
        return replace(self, mode=np.array([MODES.index(modes[r]) for r in self.rule], dtype=int), rest=rest,
                       up=up, down=down, ways=np.array([m in ("profile", "score") for m in modes]),
                       reach=np.array(reach, dtype=float).reshape(len(self.sources), 2))


def span_of(span: SourceRange | None) -> tuple[float, float, float]:
    """A source's rest and its ranges above and below it (1 where there is no range)."""
    if span is None:
        return 0.0, 1.0, 1.0
    return span.neutral, max(span.high - span.neutral, 1e-9), max(span.neutral - span.low, 1e-9)


def reach_of(source: Source, rule: MotorRule, profile: Profile) -> tuple[float, float]:
    """How far a source's normalised value (:func:`mapping.mapper.normalise`) reaches per unit
    on its positive and its negative side, in the source's own units: the performer's range
    above and below rest (swapped where the source is inverted); 1 and 1 where no range
    normalises it (a score, a scale)."""
    if resolved_mode(rule, profile) != "profile" or source.key not in profile.sources:
        return 1.0, 1.0
    _, up, down = span_of(profile.sources[source.key])
    return (down, up) if source.invert else (up, down)


def resolved_mode(rule: MotorRule, profile: Profile) -> str:
    """``profile``, ``score`` or ``scale``: what ``rule``'s normalisation is with ``profile`` (a
    ``calibrated`` rule uses the profile's ranges where a range-of-motion calibration measured
    them)."""
    if rule.normalise != "calibrated":
        return rule.normalise
    calibrated = profile.full_range and all(s.key in profile.sources for s in rule.sources)
    return "profile" if calibrated else "scale"


def normalise_pairs(raw: np.ndarray, mode: np.ndarray, rest: np.ndarray, up: np.ndarray, down: np.ndarray,
                    scale: np.ndarray, sign: np.ndarray, only: np.ndarray | None = None) -> np.ndarray:
    """Sources' values ``(F, J)`` normalised each by its own ``mode`` ``(J,)`` (see
    :func:`mapping.mapper.normalise`); ``only`` ``(J,)``: +1 where just the increase from rest
    counts, -1 just the decrease, 0 both."""
    out = raw - rest
    if only is not None and only.any():
        out = np.where(only > 0, np.fmax(out, 0.0), np.where(only < 0, np.fmin(out, 0.0), out))
        out = np.where(np.isnan(raw), np.nan, out)
    ranged = mode == PROFILE
    if ranged.any():
        out = np.where(ranged & (out >= 0), out / up, np.where(ranged, out / down, out))
    scaled = mode == SCALE
    if scaled.any():
        out = np.where(scaled, out / scale, out)
    return out * sign


def combine_pairs(normalised: np.ndarray, plan: MotorPlan) -> np.ndarray:
    """Each rule's sources ``normalised`` ``(F, J)`` combined over those seen ``(F, R)``: a rule of
    one source is that source (times its weight, if weighted); the others are reduced over
    their pairs (which lie together, rule by rule), each way of combining on the rules that use
    it. NaN where none is seen."""
    combined = np.empty((len(normalised), len(plan.counts)))
    combined[:, plan.alone] = normalised[:, plan.starts[plan.alone]] * plan.weight[plan.starts[plan.alone]]
    if not plan.several.size:
        return combined
    part = normalised[:, plan.pairs]  # the pairs of the rules of several sources, rule by rule
    seen = np.isfinite(part)
    starts = plan.several_starts
    any_seen = np.add.reduceat(seen, starts, axis=1) > 0
    out = np.empty((len(normalised), len(plan.several)))
    for how, cols in plan.groups:  # each way of combining, on the rules that use it
        if how == "max":
            out[:, cols] = np.maximum.reduceat(np.where(seen, part, -np.inf), starts, axis=1)[:, cols]
        elif how == "min":
            out[:, cols] = np.minimum.reduceat(np.where(seen, part, np.inf), starts, axis=1)[:, cols]
        else:
            w = plan.weight[plan.pairs]
            total = np.add.reduceat(seen * w, starts, axis=1)[:, cols]
            mean = np.add.reduceat(np.where(seen, part, 0.0) * w, starts, axis=1)[:, cols]
            mean /= np.where(total != 0, total, 1.0)
            # weighted: a sum, the unseen sources' share spread over the seen
            out[:, cols] = mean * np.add.reduceat(w, starts)[cols] if how == "weighted" else mean
    combined[:, plan.several] = np.where(any_seen, out, np.nan)
    return combined
