"""The mapping's plan (all rules at once) against plain per-rule loops written from the docs, and the
live mapper's ways round work it need not do: a tracker's own head, and markers no rule reads."""

import numpy as np
import pytest

from capture.listening import head_references, posed
from capture.sources import open_source
from capture.vmc import quaternion_matrix
from mapping.mapfile import MotorRule
from mapping.plan import MotorPlan, combine_pairs
from mapping.profile import Profile, SourceRange
from mapping.sources import Source
from toon import load_face, motor_index
from toonface.send import build_mapper

CODES = ("BRL", "BRC", "BLC", "BLL", "ERU", "ELU", "MB", "MLH", "HH")


def _rules(rng: np.random.Generator) -> tuple[MotorRule, ...]:
    """Rules of 1 to 4 blendshape sources, every way of combining, weights and inversions."""
    rules, shape = [], 0
    for r, code in enumerate(CODES):
        sources = []
        for _ in range(1 + r % 4):
            sources.append(Source("blendshape", channel=f"s{shape % 11}", weight=float(rng.uniform(0.5, 3)),
                                  invert=bool(rng.random() < 0.3)))
            shape += 1
        combine = ("max", "min", "mean", "weighted")[r % 4]
        rules.append(MotorRule(code, tuple(sources), combine=combine, normalise="score"))
    return tuple(rules)


def _combine_by_loop(normalised: np.ndarray, rules: tuple[MotorRule, ...]) -> np.ndarray:
    """What each rule's combine means, frame by frame (the mapping file's documentation): over the
    sources seen, the max, min, mean, or the weighted sum with the unseen sources' weight spread
    over the seen (their weighted mean times all weights); a rule of one source is that source
    times its weight where weighted; NaN where none is seen."""
    out = np.full((len(normalised), len(rules)), np.nan)
    column = 0
    for r, rule in enumerate(rules):
        width = len(rule.sources)
        weights = [s.weight if rule.combine == "weighted" else 1.0 for s in rule.sources]
        for f, row in enumerate(normalised[:, column:column + width]):
            seen = [(v, w) for v, w in zip(row, weights, strict=True) if np.isfinite(v)]
            if not seen:
                continue
            if width == 1:
                out[f, r] = row[0] * weights[0]
            elif rule.combine == "max":
                out[f, r] = max(v for v, _ in seen)
            elif rule.combine == "min":
                out[f, r] = min(v for v, _ in seen)
            else:
                total = sum(w for _, w in seen)
                mean = sum(v * w for v, w in seen) / total if total else 0.0
                out[f, r] = mean * sum(weights) if rule.combine == "weighted" else mean
        column += width
    return out


def test_every_way_of_combining_matches_a_loop_over_the_rules_with_sources_unseen():
    rng = np.random.default_rng(4)
    rules = _rules(rng)
    plan = MotorPlan.of(rules, Profile("face", {}, np.eye(3)), {})
    pairs = sum(len(r.sources) for r in rules)
    normalised = rng.normal(0, 0.6, (200, pairs))
    normalised[rng.random(normalised.shape) < 0.35] = np.nan  # some frames see none of a rule's sources
    expected = _combine_by_loop(normalised, rules)
    assert np.isnan(expected).any() and np.isfinite(expected).sum() > 1000
    np.testing.assert_allclose(combine_pairs(normalised, plan), expected, rtol=1e-12, atol=1e-15)


def test_a_plan_put_under_another_profile_is_the_plan_made_for_it():
    rng = np.random.default_rng(5)
    rules = tuple(MotorRule(r.code, r.sources, combine=r.combine, normalise="profile") for r in _rules(rng))
    keys = {s.key for r in rules for s in r.sources}
    profiles = [Profile("face", {k: SourceRange(lo, lo + 0.2, lo + 0.9) for k, lo in
                                 zip(sorted(keys), rng.uniform(0, 0.1, len(keys)), strict=True)}, np.eye(3))
                for _ in range(2)]
    first = MotorPlan.of(rules, profiles[0], {})
    moved, fresh = first.under(rules, profiles[1]), MotorPlan.of(rules, profiles[1], {})
    for name in ("mode", "rest", "up", "down", "ways"):
        np.testing.assert_array_equal(getattr(moved, name), getattr(fresh, name))
    assert not np.array_equal(first.rest, moved.rest)
    with pytest.raises(ValueError, match="needs the range of blendshape.s"):
        first.under(rules, Profile("face", {}, np.eye(3)))


def _bridge_frames(frames: int = 240) -> list:
    """A bridge's frames: the head references turned as a tracker turns the head, and scores."""
    _, rest = head_references()
    rng = np.random.default_rng(2)
    out = []
    for k in range(frames):
        yaw, pitch = np.radians(20 * np.sin(k / 40)), np.radians(8 * np.sin(k / 25))
        turn = quaternion_matrix(np.sin(pitch / 2), np.sin(yaw / 2), 0.0, np.cos(yaw / 2) * np.cos(pitch / 2))
        out.append(posed(k / 60, rest, turn, np.clip(rng.normal(0.4, 0.2, 51), 0, 1)))
    return out


def test_a_trackers_own_head_maps_as_the_head_fitted_to_its_references():
    source = open_source("vmc:127.0.0.1:0")  # the mapper a bridge gets; its socket is not read
    neutral = load_face("classic").neutral()
    given, fitted, wrong = (build_mapper(source, target_neutral=neutral) for _ in range(3))
    source.close()
    hh = motor_index("HH")
    for frame in _bridge_frames():
        by_head = given.step_frame(frame)
        by_fit = fitted.step(frame.positions, frame.t, frame.channels)
        np.testing.assert_allclose(by_head[0], by_fit[0], atol=1e-12)
        np.testing.assert_allclose(by_head[1], by_fit[1], atol=1e-12)
        turned = wrong.step(frame.positions, frame.t, frame.channels, head=frame.head.T)  # the head is what counts
    assert not given.reads_markers
    assert abs(turned[0][hh] - by_head[0][hh]) > 0.05
