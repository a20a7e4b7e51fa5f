"""The whole-take forms of cleaning's rules against plain per-sample loops written from their
docstrings: the spike tests, the NaN-aware median, the rotation fit and the head refit; gap
filling's faster forms (issue 65) against scipy and plain fits, and its progress."""

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from common.rotations import best_rotation
from mapping.outliers import SpikeFilter, centred_spikes
from mapping.robust import nan_median
from mapping.stabilise import express, fit_head, refit_head, stabilise


def _noisy_take(seed: int, frames: int = 240, markers: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Smooth motion with jitter, spikes, unseen samples, a gap and a marker never seen."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.7, 1.3, frames)) / 60.0  # uneven frame times
    phase = rng.uniform(0, 2 * np.pi, (1, markers, 3))
    x = 10 * np.sin(2 * np.pi * 0.7 * t[:, None, None] + phase) + rng.normal(0, 0.3, (frames, markers, 3))
    spiked = rng.random((frames, markers)) < 0.03
    x[spiked, 2] += rng.choice([-15.0, 15.0], spiked.sum())
    x[rng.random((frames, markers)) < 0.04] = np.nan
    x[100:107, 1] = np.nan
    x[:, 4] = np.nan
    return x, t


def _median(values: list[float]) -> float:
    finite = sorted(v for v in values if np.isfinite(v))
    if not finite:
        return np.nan
    mid = len(finite) // 2
    return finite[mid] if len(finite) % 2 else 0.5 * (finite[mid - 1] + finite[mid])


def _spike_by_loop(x: np.ndarray, t: np.ndarray, window=6, recent=3, threshold=6.0, floor=3.0, min_seen=4):
    """SpikeFilter's rule, sample by sample, from its docstring."""
    frames, markers, dims = x.shape
    out = np.zeros((frames, markers), bool)
    for f in range(frames):
        past = list(range(max(0, f - window), f))
        past = [None] * (window - len(past)) + past  # padding: unseen
        for m in range(markers):
            if not np.isfinite(x[f, m]).all():
                continue
            seen = [p for p in past if p is not None and np.isfinite(x[p, m]).all()]
            if len(seen) < min_seen:
                continue
            velocity, level = np.zeros(dims), np.zeros(dims)
            last = past[-recent:]
            for d in range(dims):
                steps = [(x[a, m, d] - x[b, m, d]) / (t[a] - t[b]) if a is not None and b is not None else np.nan
                         for b, a in zip(past[-recent - 1:-1], last, strict=True)]
                v = _median(steps)
                velocity[d] = v if np.isfinite(v) else 0.0
                level[d] = _median([x[p, m, d] + velocity[d] * (t[f] - t[p]) if p is not None else np.nan
                                    for p in last])
            spread = _median([np.linalg.norm(x[p, m] - (level - velocity * (t[f] - t[p]))) if p is not None else np.nan
                              for p in past])
            out[f, m] = np.linalg.norm(x[f, m] - level) > threshold * 1.4826 * spread + floor
    return out


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_spike_filter_equals_its_rule_sample_by_sample(seed):
    x, t = _noisy_take(seed)
    expected = _spike_by_loop(x, t)
    assert expected.sum() >= 5  # the take has spikes to find
    for block in (7, 64, 512):
        found = np.isnan(SpikeFilter().apply(x, t, block=block)[..., 0]) & np.isfinite(x[..., 0])
        np.testing.assert_array_equal(found, expected)
        np.testing.assert_array_equal(SpikeFilter().spikes(x, t, block=block), expected)  # the mask, no copy


def _centred_by_loop(x: np.ndarray, t: np.ndarray, threshold=4.0, floor=1.0, rounds=3) -> np.ndarray:
    """centred_spikes' rule from its docstring: every marker tested again each round; a sample
    at a gap's edge judged on the line through its two nearest on the other side, carried on to
    it, twice the bound, its miss compared with its neighbours' as it is."""
    x = x.copy()
    frames, markers = x.shape[:2]
    rejected = np.zeros((frames, markers), bool)
    for _ in range(rounds):
        value = np.zeros((frames, markers))
        peak = np.zeros((frames, markers), bool)
        for m in range(markers):
            seen = [f for f in range(frames) if np.isfinite(x[f, m]).all()]
            misses, big = [], {}
            for i, f in enumerate(seen):
                if 0 < i < len(seen) - 1 and f - seen[i - 1] <= 2 and seen[i + 1] - f <= 2:
                    b, a = seen[i - 1], seen[i + 1]
                    share = (t[f] - t[b]) / (t[a] - t[b])
                    value[f, m] = np.linalg.norm(x[f, m] - (x[b, m] * (1 - share) + x[a, m] * share))
                    misses.append(value[f, m])
                    big[f] = 1.0
            bound = threshold * (1.4826 * np.median(misses) if misses else 0.0) + floor
            for i, f in enumerate(seen):
                back = i >= 2 and f - seen[i - 1] <= 2 and seen[i - 1] - seen[i - 2] <= 2
                ahead = i + 2 < len(seen) and seen[i + 1] - f <= 2 and seen[i + 2] - seen[i + 1] <= 2
                gap_after = seen[i + 1] - f > 2 if i + 1 < len(seen) else f < frames - 2
                gap_before = f - seen[i - 1] > 2 if i > 0 else f > 1
                if back and gap_after:
                    near, far = seen[i - 1], seen[i - 2]
                elif ahead and gap_before:
                    near, far = seen[i + 1], seen[i + 2]
                else:
                    continue
                line = x[near, m] + (x[near, m] - x[far, m]) * (t[f] - t[near]) / (t[near] - t[far])
                value[f, m] = np.linalg.norm(x[f, m] - line)
                big[f] = 2.0  # the edge's bound: twice the centred one
            for f, factor in big.items():
                neighbours = [value[g, m] for g in (f - 1, f + 1) if 0 <= g < frames]
                peak[f, m] = value[f, m] > factor * bound and all(value[f, m] >= v for v in neighbours)
        if not peak.any():
            break
        rejected |= peak
        x[peak] = np.nan
    return rejected


@pytest.mark.parametrize(("seed", "block"), [(0, 8192), (1, 8192), (2, 8192), (0, 7), (1, 1)])
def test_centred_spikes_equal_their_rule_sample_by_sample(seed, block, monkeypatch):
    """Also worked out a few frames at a time (``FRAMES_AT_ONCE``: what a long take does)."""
    monkeypatch.setattr("mapping.outliers.FRAMES_AT_ONCE", block)
    x, t = _noisy_take(seed)
    x[50:53, 0] += [[0, 0, 6.0], [0, 0, 5.0], [0, 0, -5.5]]  # neighbouring spikes: found in later rounds
    x[:100, 1] = [1.0, 2.0, 3.0] + np.random.default_rng(seed).normal(0, 0.3, (100, 3))  # still, seen
    x[99, 1, 2] += 20.0  # a spike at the edge of the gap at 100, judged on the line through 97 and 98
    x[:4, 2], x[-3:, 3] = np.nan, np.nan  # lost at the start and the end
    expected = _centred_by_loop(x, t)
    assert expected.sum() >= 5 and expected[99, 1]
    np.testing.assert_array_equal(centred_spikes(x, t), expected)


@pytest.mark.parametrize("count", range(1, 8))
def test_nan_median_is_numpys_with_and_without_missing_values(count):
    rng = np.random.default_rng(count)
    parts = [rng.normal(size=(50, 4)) for _ in range(count)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        np.testing.assert_allclose(nan_median(parts, complete=True), np.median(np.stack(parts), axis=0), rtol=1e-15)
        for p in parts:
            p[rng.random(p.shape) < 0.4] = np.nan
        np.testing.assert_allclose(nan_median(parts), np.nanmedian(np.stack(parts), axis=0), rtol=1e-15)


def _kabsch(cross: np.ndarray) -> np.ndarray:
    u, _, vt = np.linalg.svd(cross)
    u[..., :, -1] *= np.sign(np.linalg.det(u @ vt))[..., None]
    return u @ vt


@pytest.mark.parametrize("points", [3, 5, 12])
def test_best_rotation_recovers_known_rotations_as_kabsch_does(points):
    rng = np.random.default_rng(points)
    truth = Rotation.random(500, random_state=points).as_matrix()
    a = rng.normal(0, 50, (500, points, 3))
    b = np.einsum("fij,fkj->fki", truth, a) + rng.normal(0, 0.3, (500, points, 3))
    a, b = a - a.mean(axis=1, keepdims=True), b - b.mean(axis=1, keepdims=True)
    cross = np.einsum("fki,fkj->fij", b, a)
    fitted = best_rotation(cross)
    np.testing.assert_allclose(fitted, _kabsch(cross), atol=1e-9)
    np.testing.assert_allclose(np.linalg.det(fitted), 1.0, atol=1e-12)
    exact = np.einsum("fij,fkj->fki", truth, a)  # without the jitter, the truth itself
    np.testing.assert_allclose(best_rotation(np.einsum("fki,fkj->fij", exact, a)), truth, atol=1e-9)


def test_best_rotation_of_reflections_degenerate_and_few_matrices():
    rng = np.random.default_rng(9)
    matrices = rng.normal(size=(300, 3, 3))  # half of them with det < 0
    np.testing.assert_allclose(best_rotation(matrices), _kabsch(matrices), atol=1e-9)
    degenerate = np.zeros((40, 3, 3))
    degenerate[:20, 0, 0] = 5.0  # points on one line: any turn about it fits
    fitted = best_rotation(degenerate)
    np.testing.assert_allclose(fitted @ np.transpose(fitted, (0, 2, 1)), np.broadcast_to(np.eye(3), (40, 3, 3)),
                               atol=1e-12)
    np.testing.assert_allclose(fitted[:, :, 0] @ [1, 0, 0], 1.0)  # the line stays where it was
    one = rng.normal(size=(3, 3))
    np.testing.assert_allclose(best_rotation(one), _kabsch(one), atol=1e-12)  # the few-frames path


def test_refitting_only_the_frames_that_lost_a_reference_equals_fitting_again():
    rng = np.random.default_rng(4)
    frames, rows = 400, [0, 1, 2, 3]
    shape = rng.normal(0, 40, (4, 3))
    turn = Rotation.from_euler("yx", np.stack([np.linspace(-30, 30, frames), np.linspace(10, -5, frames)], 1),
                               degrees=True).as_matrix()
    local = np.concatenate([np.broadcast_to(shape, (frames, 4, 3)), rng.normal(0, 20, (frames, 3, 3))], axis=1)
    positions = np.einsum("fij,fmj->fmi", turn, local) + rng.normal(0, 0.3, (frames, 7, 3)) + [5.0, -3.0, 20.0]
    fit = fit_head(positions, rows, shape)
    lost = np.zeros((frames, 7), bool)
    lost[rng.choice(frames, 40, replace=False), rng.integers(0, 4, 40)] = True
    lost[150:160, 2] = True  # a stretch to bridge
    cut = np.where(lost[..., None], np.nan, positions)
    again = refit_head(fit, cut, rows, lost[:, rows].any(axis=1))
    whole = stabilise(cut, rows, fit.shape, own_shape=False)
    quick = express(cut, rows, again)
    np.testing.assert_allclose(quick.rotation, whole.rotation, atol=1e-10)
    np.testing.assert_allclose(quick.local, whole.local, atol=1e-8, equal_nan=True)


@pytest.mark.parametrize("frames", [1, 2, 3, 10, 500])
def test_column_nan_median_is_numpys(frames):
    from mapping.robust import column_nan_median

    rng = np.random.default_rng(frames)
    values = rng.normal(size=(frames, 8))
    values[rng.random(values.shape) < 0.3] = np.nan
    values[:, 5] = np.nan
    values[:, 2] = rng.normal(size=frames)  # columns seen throughout take another way (a partial sort)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        expected = np.nanmedian(values, axis=0)
    np.testing.assert_array_equal(column_nan_median(values), expected)
    whole = rng.normal(size=(frames, 3))
    np.testing.assert_array_equal(column_nan_median(whole), np.median(whole, axis=0))


def test_the_stand_ins_splines_at_once_are_a_spline_through_every_other_row():
    """Gap filling's validation fits its stand-in gaps' splines in one banded solve through 40
    knots either side (issue 65): the values of scipy's not-a-knot spline through every row
    outside each block, near the ends too (where it is that spline)."""
    from scipy.interpolate import CubicSpline

    from mapping.gap_fit import stand_in_splines

    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.5, 1.5, 400)) / 60.0  # uneven frame times
    y = np.c_[np.sin(7 * t), np.cos(3 * t) + rng.normal(0, 0.1, 400), rng.normal(0, 1, 400)]
    blocks = [(lo, lo + 12) for lo in (20, 100, 190, 300, 380)]
    got = stand_in_splines(t, y, blocks)
    for b, (lo, hi) in enumerate(blocks):
        keep = np.r_[0:lo, hi:400]
        np.testing.assert_allclose(got[b], CubicSpline(t[keep], y[keep], axis=0)(t[lo:hi]), rtol=0, atol=1e-12)


@pytest.mark.parametrize("count", [2, 9])
def test_a_gaps_regression_design_is_its_formula_written_plainly(count):
    """:func:`mapping.gap_fit.regression_design` gathers whole rows first and works in place
    (issue 65: 1.34 -> 0.51 s of a 6.3 s gap fill, profiled): the same numbers as the design
    written one predictor and one row at a time (each predictor about the row's centre of them,
    weighted, every column less its mean; the centre itself appended where fewer than four
    predict)."""
    from mapping.gap_fit import regression_design

    rng = np.random.default_rng(6)
    source = rng.normal(0.0, 20.0, (80, 12, 3))
    rows, others = np.sort(rng.choice(80, 50, replace=False)), [int(k) for k in rng.choice(12, count, replace=False)]
    weight = rng.uniform(0.1, 1.0, count)
    centre, x = regression_design(source, rows, others, weight)
    plain_centre = np.array([[np.mean([source[r, k, d] for k in others]) for d in range(3)] for r in rows])
    plain = np.array([[(source[r, k, d] - plain_centre[i, d]) * weight[j]
                       for j, k in enumerate(others) for d in range(3)] for i, r in enumerate(rows)])
    if count < 4:
        plain = np.hstack([plain, plain_centre])
    np.testing.assert_allclose(centre, plain_centre, rtol=0, atol=1e-12)
    np.testing.assert_allclose(x, plain - plain.mean(axis=0), rtol=0, atol=1e-12)
    assert not np.shares_memory(x, source)


def test_a_predictors_relevance_is_the_r2_of_its_own_least_squares_fit():
    """:func:`mapping.gaps._relevance` (sums by matrix products, issue 65) against a plain fit of
    the target on each marker over the frames both are seen."""
    from mapping.gaps import _relevance

    rng = np.random.default_rng(4)
    frames, count = 300, 6
    target = rng.normal(size=(frames, 3))
    others = rng.normal(size=(frames, count, 3)) + target[:, None] * rng.uniform(0, 2, (1, count, 1))
    both = rng.random((frames, count)) > 0.1
    both[:, 5] = False
    both[:8, 5] = True  # seen together in 8 frames: too few to judge
    others[~both] = np.nan
    got = _relevance(target, others, both)
    for k in range(count - 1):
        seen = both[:, k]
        x = np.c_[others[seen, k], np.ones(seen.sum())]
        y = target[seen] - target[seen].mean(axis=0)
        fitted = x @ np.linalg.lstsq(x, y, rcond=None)[0]
        assert got[k] == pytest.approx((fitted * fitted).sum() / (y * y).sum(), abs=1e-10)
    assert got[5] == 0.0


def test_gap_filling_tells_its_progress_gap_by_gap():
    """Issue 65: an hour's take fills gaps for minutes, so cleaning says how far it is: the
    factory is given the long gaps' number, and told each one as it is filled."""
    import dataclasses

    from capture import synthesize
    from mapping import CleanSettings
    from mapping.clean import clean_take

    syn = synthesize(seconds=6.0, rate=60.0, noise_mm=0.0, seed=3)
    positions = syn.take.positions.copy()
    for k, start in enumerate((60, 150, 240)):  # three long gaps (0.5 s) in three markers
        positions[start:start + 30, 10 + k] = np.nan
    positions[200:203, 20] = np.nan  # and a short one (a spline's, not counted)
    take = dataclasses.replace(syn.take, positions=positions)
    told: list[tuple[str, int]] = []

    def factory(total: int):
        told.append(("total", total))
        return lambda done: told.append(("done", done))

    quiet, _ = clean_take(take, CleanSettings())
    loud, _ = clean_take(take, CleanSettings(progress=factory))
    assert told == [("total", 3), ("done", 1), ("done", 1), ("done", 1)]
    assert CleanSettings(progress=factory) == CleanSettings()  # not a setting
    np.testing.assert_array_equal(quiet.positions, loud.positions)
