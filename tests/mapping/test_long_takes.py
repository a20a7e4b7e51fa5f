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
