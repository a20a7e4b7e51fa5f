"""A gap bridged by a straight line (a marker filled apart from the face, with nothing to predict it
from) starts and ends at as many samples either side as its own samples show is best."""

import numpy as np

from mapping.gap_fit import line_edge
from mapping.gaps import GapFiller

RATE = 60.0


def test_a_moving_marker_takes_its_line_from_one_sample_and_a_jittery_still_one_from_five():
    """On a marker gliding with no jitter, the sample beside a gap is where the line must start (a
    median of five lags the glide); on a still one with 0.3 mm of jitter, the median of five is
    nearer where it is."""
    t = np.arange(600) / RATE
    gliding = np.stack([4 * np.sin(2.0 * t), np.cos(1.3 * t), np.zeros_like(t)], axis=1)
    still = np.random.default_rng(3).normal(0.0, 0.3, (600, 3))
    assert line_edge(gliding, t, 30) == 1
    assert line_edge(still, t, 30) == 5
    assert line_edge(still[:100], t[:100], 30) == 1  # too few samples to judge: the sample beside it


def test_a_pupils_line_across_a_blink_does_not_start_at_one_stray_sample():
    """Both pupils lost together for half a second (a blink: each is filled only from the other, so
    across it by a line), the right one's last sample before the gap 1.3 mm off where it holds, as
    the third bench performer's was (seed 4, 27.35 s: 0.3 mm of jitter, one sample at 4 sigma):
    the line started there and carried it across the gap; now it starts at the median of the
    five samples before, as the pupil's own stand-in gaps judge best."""
    rng = np.random.default_rng(4)
    t = np.arange(900) / RATE
    right = rng.normal(0.0, 0.3, (900, 3)) + [30.0, 0.0, 10.0]
    left = rng.normal(0.0, 0.3, (900, 3)) + [-30.0, 0.0, 10.0]
    positions = np.stack([right, left], axis=1)
    positions[400:430] = np.nan
    positions[399, 0, 1] = 1.3
    filled = GapFiller().apply(positions, t, apart=[0, 1])
    assert filled.filled[400:430].all()
    off = np.abs(filled.positions[400:430, 0, 1])
    assert off.max() < 0.5, off.max()  # the single sample's line started 1.3 mm off
    one_sample = 1.3 + (positions[430, 0, 1] - 1.3) * np.arange(1, 31) / 31
    assert np.abs(one_sample).max() > 1.2
