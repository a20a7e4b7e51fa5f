"""Long takes in bounded memory (issue 65): what is worked out a block of frames or a few channels
at a time equals the whole at once, and what is smoothed in place equals what is smoothed in a copy
(a take's own arrays are read-only: nothing writes into them)."""

import warnings

import numpy as np
import pytest
from scipy.signal import sosfiltfilt

from capture import synthesize
from capture.performance import default_performance
from mapping.filters import CHANNELS_AT_ONCE, Butterworth
from mapping.profile import _nan_percentiles
from mapping.robust import ROWS_AT_ONCE
from toonface import map_onto_face


def test_mapping_a_few_frames_at_a_time_equals_mapping_them_all_at_once(monkeypatch):
    take = synthesize(rate=60.0, seed=2, performance=default_performance(5.0, seed=2)).take
    whole = map_onto_face(take)
    monkeypatch.setattr("mapping.mapper.FRAMES_AT_ONCE", 37)  # blocks that end mid-blink and mid-syllable
    parts = map_onto_face(take)
    assert parts.frames == whole.frames == take.frames
    np.testing.assert_array_equal(parts.values, whole.values)
    np.testing.assert_array_equal(parts.confidence, whole.confidence)


def test_percentiles_a_few_columns_at_a_time_are_numpys():
    rng = np.random.default_rng(3)
    values = rng.normal(0.0, 1.0, (301, 41))
    values[rng.random(values.shape) < 0.05] = np.nan
    values[:, 3] = np.nan  # never seen
    values[:, 5:25] = rng.normal(0.0, 1.0, (301, 20))  # complete columns between gapped ones
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the column never seen
        expected = np.nanpercentile(values, (1.0, 99.0), axis=0)
        found = _nan_percentiles(values, (1.0, 99.0))
    np.testing.assert_array_equal(found, expected)


def test_smoothing_in_place_equals_smoothing_a_copy():
    rng = np.random.default_rng(1)
    x = np.cumsum(rng.normal(0.0, 1.0, (500, 30)), axis=0)
    x[100:140, 2] = np.nan
    x[rng.random(500) < 0.1, 17] = np.nan
    x[450:, 29] = np.inf  # not finite: unseen
    smoother = Butterworth(6.0, 60.0)
    expected = smoother.smooth_offline(x)
    mine = x.copy()
    result = smoother.smooth_offline(mine, overwrite=True)
    assert np.shares_memory(result, mine)  # no second array of the take's size
    np.testing.assert_array_equal(result, expected)
    assert np.isnan(expected[100:140, 2]).all() and np.isnan(expected[450:, 29]).all()


@pytest.mark.parametrize("overwrite", [False, True])
def test_butterworth_smooths_a_long_take_a_block_at_a_time_as_scipy_does_each_channel(overwrite):
    """More frames than are gathered at once and more channels than are filtered at once, one
    channel with a gap: each channel as scipy's forward-backward filter gives it on its own
    (the seen samples of the gapped one), to the last bit."""
    rng = np.random.default_rng(3)
    frames, channels = 2 * ROWS_AT_ONCE + 77, CHANNELS_AT_ONCE + 5
    x = np.cumsum(rng.normal(size=(frames, channels)), axis=0)
    x[1000:1040, 3] = np.nan
    flt = Butterworth(8.0, 120.0)
    expected = np.empty_like(x)
    for c in range(channels):
        seen = np.isfinite(x[:, c])
        expected[:, c] = np.nan
        expected[seen, c] = sosfiltfilt(flt.sos, x[seen, c])
    out = flt.smooth_offline(x.copy() if overwrite else x, overwrite=overwrite)
    np.testing.assert_array_equal(out, expected)


def test_head_fits_a_block_of_frames_at_a_time_equal_the_fit_of_them_all(monkeypatch):
    """An hour's fit of seven references at once held a few (F, 7, 3) working copies: 300 MB of the
    hour's peak (issue 65). Each frame's fit stands alone, so blocks give the same fits (to the
    last bit or two: numpy sums a block's frames in another order), with a reference lost, a spike
    dropped and a frame too poorly pinned."""
    import sys

    from scipy.spatial.transform import Rotation

    stabilise = sys.modules["mapping.stabilise"]  # mapping.stabilise is also the function's name
    rng = np.random.default_rng(4)
    shape = rng.normal(0.0, 40.0, (7, 3))
    turns = Rotation.from_rotvec(rng.normal(0.0, 0.3, (500, 3))).as_matrix()
    target = np.einsum("fij,kj->fki", turns, shape) + rng.normal(0.0, 0.3, (500, 7, 3))
    target[rng.random((500, 7)) < 0.2] = np.nan
    target[rng.random((500, 7)) < 0.02] += 9.0  # spikes: each frame's worst point dropped
    whole = stabilise.robust_rigid_fit(shape, target)
    monkeypatch.setattr(stabilise, "FIT_FRAMES", 64)
    blocks = stabilise.robust_rigid_fit(shape, target)
    assert (~whole[2]).any() and whole[2].any()
    np.testing.assert_array_equal(whole[2], blocks[2])
    for a, b in zip(whole[:2], blocks[:2], strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def test_a_profile_measured_a_few_sources_at_a_time_is_the_one_measured_at_once(monkeypatch):
    """An hour's every source at once, (F, 100), was 350 MB more of the take's peak (issue 65): the
    ranges and jitters a few sources at a time are the same, with gaps filled and frames without a
    head pose."""
    from capture import Take
    from mapping import calibrate, choose_mapping, prepare

    syn = synthesize(seconds=6.0, rate=60.0, seed=2).take
    positions = syn.positions.copy()
    positions[60:240, [syn.index(r) for r in ("FOREHEAD", "TEMPLE_R", "TEMPLE_L", "NOSE_TIP", "EYE_R_IN")]] = np.nan
    positions[260:300, syn.index("LID_R_UP")] = np.nan  # filled, and not believed as range
    take = Take(positions, syn.labels, syn.rate, times=syn.times)
    mapping, markerset = choose_mapping(take)
    prepared = prepare(take, markerset)
    assert not prepared.stable.ok.all() and prepared.stable.filled.any()
    together = calibrate(mapping, prepared, (0.0, 1.0))
    monkeypatch.setattr("mapping.robust.COLUMNS_AT_ONCE", 1000)
    assert calibrate(mapping, prepared, (0.0, 1.0)).sources == together.sources
