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


def test_a_pupil_lost_before_a_look_follows_the_other_seen_through_part_of_its_gap():
    """The right pupil lost for a second, the left for half of it; the eyes look 6 mm aside just
    after the right is lost, while the left is still seen. The left's seen part says where both
    went, so the right's gap follows it; a straight line across (how the gap was bridged while only
    a partner seen throughout it counted) held the right one near where it was for most of a
    second."""
    rng = np.random.default_rng(5)
    t = np.arange(900) / RATE
    gaze = np.zeros((900, 3))
    for start, end, aside in ((100, 180, -4.0), (305, 400, 6.0), (500, 560, 6.0), (640, 700, -3.0)):
        gaze[start:end, 0] = aside  # looks aside and back (mm), the eyes together
    right = gaze + [30.0, 0.0, 10.0] + rng.normal(0.0, 0.1, (900, 3))
    left = gaze + [-30.0, 0.0, 10.0] + rng.normal(0.0, 0.1, (900, 3))
    positions = np.stack([right, left], axis=1)
    positions[300:360, 0] = np.nan  # the right: lost at 300, the look at 305
    positions[320:350, 1] = np.nan  # the left: seen through the look, lost a little after
    filled = GapFiller().apply(positions, t, apart=[0, 1])
    assert filled.filled[300:360, 0].all() and filled.filled[320:350, 1].all()
    truth = right[310:360, 0]
    off = np.abs(filled.positions[310:360, 0, 0] - truth)
    assert off.max() < 1.0, off.max()
    line = right[299, 0] + (right[360, 0] - right[299, 0]) * np.arange(11, 61) / 61
    assert np.abs(line - truth).max() > 4.0  # what the straight line missed by
