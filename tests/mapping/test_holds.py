"""Smoothing heavier where a marker holds still (mapping.holds), against the take's low-pass alone."""

import numpy as np

from capture import Take, load_markerset, synthesize
from capture.performance import default_performance
from common import Failure
from mapping.clean import CleanSettings, clean_stabilised
from mapping.filters import Butterworth
from mapping.holds import HoldSmoother, fast_moves, put_back_moves

RATE = 60.0


def _blinking_lid(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """A lid ``(F,)`` at rest with three blinks (3.5 mm shut in 0.12 s, open in 0.2 s) and a
    held squint, and the same with 0.3 mm of jitter."""
    t = np.arange(900) / RATE
    lid = np.zeros_like(t)
    for at in (3.0, 7.5, 11.0):
        lid -= 3.5 * np.interp(t, [at, at + 0.12, at + 0.32], [0, 1, 0])
    lid -= 1.2 * np.interp(t, [5.0, 5.4, 6.4, 6.8], [0, 1, 1, 0])
    return lid, lid + np.random.default_rng(seed).normal(0.0, 0.3, lid.shape)


def _smoothed(raw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``raw`` ``(F, M, 3)`` through the 8 Hz low-pass alone, and then made steadier at holds."""
    plain = Butterworth(8.0, RATE).smooth_offline(raw.reshape(len(raw), -1)).reshape(raw.shape)
    return plain, HoldSmoother(RATE, 8.0).smooth(plain, raw)


def test_a_held_lid_loses_its_jitter_and_a_blink_keeps_its_depth():
    for seed in range(4):
        lid, noisy = _blinking_lid(seed)
        raw = np.random.default_rng(seed + 10).normal(0.0, 0.3, (len(lid), 3, 3))  # the lid and two still markers
        raw[:, 0, 1] = noisy
        plain, steady = (out[:, 0, 1] for out in _smoothed(raw))
        rest = np.abs(lid) < 1e-9
        rest &= np.convolve(~rest, np.ones(31), "same") == 0  # at least a quarter second from any motion
        rest[:30] = rest[-30:] = False  # and from the ends, where every low-pass starts
        assert np.std(steady[rest] - lid[rest]) < 0.5 * np.std(plain[rest] - lid[rest])
        for at in (3.0, 7.5, 11.0):  # each blink as deep as the 8 Hz low-pass leaves it
            near = slice(int(at * RATE) - 5, int(at * RATE) + 25)
            assert abs(steady[near].min() - plain[near].min()) < 0.15, (seed, at)
        assert np.sqrt(np.mean((steady - lid) ** 2)) < 0.7 * np.sqrt(np.mean((plain - lid) ** 2))


def test_a_marker_that_moves_all_the_time_is_not_smoothed_more():
    """Lips through a whole speech never hold: their motion must not pass for noise."""
    rng = np.random.default_rng(5)
    t = np.arange(900) / RATE
    raw = rng.normal(0.0, 0.3, (900, 4, 3))
    raw[:, 0, 1] += 6.0 * np.sin(2 * np.pi * 4.3 * t) * (1 + 0.3 * np.sin(0.7 * t))
    raw[:, 1, 0] += 2.0 * np.sin(2 * np.pi * 1.5 * t)  # slower, smaller: still motion
    plain, steady = _smoothed(raw)
    for marker, axis in ((0, 1), (1, 0)):
        amplitude = [np.ptp(x[60:-60, marker, axis]) for x in (plain, steady)]
        assert amplitude[1] > 0.97 * amplitude[0], (marker, amplitude)
        assert np.abs(steady[:, marker, axis] - plain[:, marker, axis]).max() < 0.3


def test_the_steadying_does_not_depend_on_units():
    _, noisy = _blinking_lid(1)
    raw = np.random.default_rng(2).normal(0.0, 0.3, (len(noisy), 2, 3))
    raw[:, 0, 1] += noisy
    plain, steady = _smoothed(raw)
    plain_cm, steady_cm = _smoothed(raw / 10.0)
    np.testing.assert_allclose(steady_cm * 10.0, steady, atol=1e-9)
    assert not np.allclose(steady, plain)


def test_plain_smoothing_is_the_low_pass_alone():
    syn = synthesize(rate=RATE, noise_mm=0.3, performance=default_performance(6, max_turn_deg=0), seed=3)
    ms = load_markerset("toon32")
    take = Take(syn.take.positions, syn.take.labels, RATE)
    plain, _ = clean_stabilised(take, ms, CleanSettings(holds=False))
    raw, _ = clean_stabilised(take, ms, CleanSettings(cutoff_hz=0.0))
    expected = Butterworth(8.0, RATE).smooth_offline(raw.local.reshape(len(raw.local), -1)).reshape(raw.local.shape)
    np.testing.assert_allclose(plain.local, expected, atol=1e-9)
    steady, _ = clean_stabilised(take, ms)
    lid = syn.take.index("LID_R_LOW")  # the first second is at rest
    assert np.std(np.diff(steady.local[10:60, lid], axis=0)) < 0.7 * np.std(np.diff(plain.local[10:60, lid], axis=0))


def test_a_take_of_two_frames_is_cleaned_not_refused():
    """Two frames hold no second difference to measure a marker's jitter on: the smoother leaves
    them as the low-pass gave them (it had stopped the clean with a numpy reshape error)."""
    syn = synthesize(seconds=1.0, rate=RATE, seed=3)
    take = Take(syn.take.positions[:2], syn.take.labels, RATE)
    cleaned = clean_stabilised(take, load_markerset("toon32"))
    assert not isinstance(cleaned, Failure), cleaned
    stable, _ = cleaned
    assert stable.local.shape == (2, take.markers, 3) and np.isfinite(stable.local).any()
    raw = syn.take.positions[:2]
    np.testing.assert_array_equal(HoldSmoother(RATE, 8.0).smooth(raw, raw), raw)


def _one_marker_by_the_definition(smoother: HoldSmoother, x: np.ndarray, noise: np.ndarray) -> np.ndarray:
    """The module docstring's rule on one marker ``(F, 3)`` written plainly, frames down axis 0:
    at each level keep the lighter low-pass where the heavier departs from it by more than its
    noise explains (eased over half a period), the heavier one elsewhere; then, where the first
    level did not keep the lighter one, half of that is the LPA-ICI estimate's."""
    from scipy import ndimage, signal

    current, moving = x, np.ones(len(x))
    for (fc, sos), spread in zip(smoother.levels, smoother.spreads, strict=True):
        heavy = signal.sosfiltfilt(sos, x, axis=0)
        departure = np.sqrt(np.mean(((current - heavy) / (noise * spread)) ** 2, axis=1))
        keep = np.clip(departure / smoother.threshold - 1.0, 0.0, 1.0)
        width = max(3, int(round(0.5 * RATE / fc)))
        keep = ndimage.uniform_filter1d(ndimage.maximum_filter1d(keep, width), width)
        if current is x:
            moving = keep
        current = heavy + (current - heavy) * keep[:, None]
    share = smoother.ici_share * (1.0 - moving)[:, None]
    return current * (1.0 - share) + share * _ici_by_the_definition(smoother, x, noise)


def _ici_by_the_definition(smoother: HoldSmoother, x: np.ndarray, noise: np.ndarray) -> np.ndarray:
    """LPA-ICI one sample and one axis at a time: the input with its own variance, then the mean of
    each longer window (back from the sample, ahead from it, about it) while its interval meets
    all before it; the three kept means weighted by the inverse of their variances."""
    from mapping.holds import ICI_GAMMA

    out = np.empty_like(x)
    frames = len(x)
    for axis in range(x.shape[1]):
        light = smoother.light_variance * noise[axis] ** 2
        for t in range(frames):
            weighed = weights = 0.0
            for back, ahead in ((1, 0), (0, 1), (1, 1)):
                low, high = x[t, axis] - ICI_GAMMA * light ** 0.5, x[t, axis] + ICI_GAMMA * light ** 0.5
                best, variance = x[t, axis], light
                for h in smoother.windows:
                    first, last = (max(t - h, 0) if back else t), (min(t + h + 1, frames) if ahead else t + 1)
                    mean = x[first:last, axis].mean()
                    spread = min(noise[axis] ** 2 / (last - first), light)
                    low, high = max(low, mean - ICI_GAMMA * spread ** 0.5), min(high, mean + ICI_GAMMA * spread ** 0.5)
                    if low > high:
                        break
                    best, variance = mean, spread
                weighed, weights = weighed + best / variance, weights + 1.0 / variance
            out[t, axis] = weighed / weights
    return out


def test_each_marker_is_smoothed_on_its_own_by_the_rule_whatever_the_layout():
    """Issue 65: the smoother works on rows (markers by frames) so that scipy's filters copy no
    transposition; its output is the rule's on each marker alone (to rounding), for markers seen
    throughout (taken four at a time) and for one with a gap (its seen stretches alone)."""
    from mapping.holds import marker_noise

    rng = np.random.default_rng(5)
    t = np.arange(1200) / RATE
    raw = np.stack([np.stack([np.sin(t * (0.3 + m)) * (m % 3), np.cos(t * 0.7 * m), 0.02 * m * t], axis=1)
                    for m in range(7)], axis=1) + rng.normal(0.0, 0.2, (1200, 7, 3))
    raw[400:460, 6] = np.nan
    plain, held = _smoothed(raw)
    smoother, noise = HoldSmoother(RATE, 8.0), marker_noise(raw)
    for m in (0, 2, 5):  # a sample at a time is slow: three of the six seen throughout
        assert np.allclose(held[:, m], _one_marker_by_the_definition(smoother, plain[:, m], noise[m]),
                           rtol=0, atol=1e-12)
    for start, end in ((0, 400), (460, 1200)):
        assert np.allclose(held[start:end, 6], _one_marker_by_the_definition(smoother, plain[start:end, 6], noise[6]),
                           rtol=0, atol=1e-12)
    assert np.isnan(held[400:460, 6]).all()
    assert np.abs(held - plain)[np.isfinite(held)].max() > 0.01  # the holds were steadied: the rule did something


def test_a_lid_arrives_at_its_new_pose_less_rounded_and_the_blocks_change_nothing(monkeypatch):
    """A lid moves 1 mm into a squint in 0.1 s, under 0.3 mm of jitter: too small a move for
    the cascade to see, so its heavy low-passes reach back across it and round the pose's first
    0.4 s. Half of LPA-ICI's estimate (whose window reaching forward from the pose's first
    samples grows long) takes a fifth off that, and no more noise is left where it holds. The
    estimate made a few frames at a time is the one made at once."""
    t = np.arange(900) / RATE
    lid = -1.0 * np.interp(t, [5.0, 5.1, 6.6, 6.7], [0, 1, 1, 0])
    arrive, hold = (t >= 5.1) & (t < 5.5), (t >= 5.6) & (t < 6.5)
    errors = {"cascade": [], "default": []}
    for seed in range(6):
        raw = np.random.default_rng(seed).normal(0.0, 0.3, (900, 2, 3))
        raw[:, 0, 1] += lid
        plain = Butterworth(8.0, RATE).smooth_offline(raw.reshape(900, -1)).reshape(raw.shape)
        for name, share in (("cascade", 0.0), ("default", HoldSmoother(RATE, 8.0).ici_share)):
            out = HoldSmoother(RATE, 8.0, ici_share=share).smooth(plain, raw)[:, 0, 1] - lid
            errors[name].append([np.sqrt(np.mean(out[part] ** 2)) for part in (arrive, hold)])
    cascade, default = np.mean(errors["cascade"], axis=0), np.mean(errors["default"], axis=0)
    assert default[0] < 0.85 * cascade[0], (default, cascade)
    assert default[1] < 1.1 * cascade[1], (default, cascade)
    smoother = HoldSmoother(RATE, 8.0)
    whole = smoother.smooth(plain, raw)
    monkeypatch.setattr("mapping.holds.ICI_FRAMES", 50)
    np.testing.assert_allclose(smoother.smooth(plain, raw), whole, rtol=0, atol=1e-9)


def test_a_saccade_keeps_its_speed_and_a_hold_its_steadiness():
    """A pupil at 120 Hz jumps 4 mm in 30 ms between held gazes, under 0.25 mm of jitter: the
    take's 8 Hz low-pass turns each jump into a 100 ms ramp. Where the lighter low-pass departs
    from it by more than the noise explains, :func:`fast_moves` puts the lighter one back: the
    error around the jumps falls by more than a third, the holds stay as steady, and a marker
    that only holds is left alone."""
    rate = 120.0
    t = np.arange(1440) / rate
    gaze = np.zeros_like(t)
    for at, to in ((2.0, 4.0), (4.5, -1.0), (7.0, 2.5), (9.5, 0.0)):
        gaze = np.where(t >= at, np.interp(t, [at, at + 0.03], [gaze[int(at * rate) - 1], to]), gaze)
    near = np.zeros(len(t), dtype=bool)
    for at in (2.0, 4.5, 7.0, 9.5):
        near |= np.abs(t - at - 0.015) < 0.1
    hold = ~np.convolve(near, np.ones(121), "same").astype(bool)
    hold[:60] = hold[-60:] = False
    errors = {"holds": [], "fast": []}
    for seed in range(4):
        raw = np.random.default_rng(seed).normal(0.0, 0.25, (len(t), 2, 3))
        raw[:, 0, 0] += gaze
        plain = Butterworth(8.0, rate).smooth_offline(raw.reshape(len(t), -1)).reshape(raw.shape)
        steady = HoldSmoother(rate, 8.0).smooth(plain, raw)
        moves = fast_moves(raw, raw, rate, 8.0)
        assert [m for m, _, _ in moves] == [0]  # the still marker has no fast moves
        fast = put_back_moves(steady.copy(), moves)
        for name, out in (("holds", steady), ("fast", fast)):
            error = out[:, 0, 0] - gaze
            errors[name].append([np.sqrt(np.mean(error[part] ** 2)) for part in (near, hold)])
    before, after = np.mean(errors["holds"], axis=0), np.mean(errors["fast"], axis=0)
    assert after[0] < 0.65 * before[0], (after, before)
    assert after[1] < 1.05 * before[1], (after, before)
    assert fast_moves(raw, raw, rate, 30.0) == []  # a take already smoothed lighter has nothing to put back
