"""Gaps at the start or the end of a take (:class:`mapping.gaps.GapFiller`): filled from the
markers seen through them, where a spline or a line cannot reach."""

import numpy as np

from mapping.gaps import GapFiller


def test_a_gap_at_either_end_of_the_take_is_filled_from_markers_that_move_with_it():
    """Half a side of the face lost for the take's last second (a head turned away) was left
    unseen, and its brow motor held still there; the markers still seen say where it went, and
    what their regression misses is held at its level beside the gap."""
    rng = np.random.default_rng(4)
    t = np.arange(600) / 60.0
    drive = np.cumsum(rng.normal(0, 0.3, (600, 2)), axis=0)
    pos = (drive @ rng.normal(size=(2, 5 * 3))).reshape(600, 5, 3) + rng.normal(0, 0.02, (600, 5, 3))
    cut = pos.copy()
    cut[540:, 2:4] = np.nan  # the last second, two markers together
    cut[:45, 0] = np.nan  # the first 0.75 s
    result = GapFiller().apply(cut, t)
    assert result.filled[540:, 2:4].all() and result.filled[:45, 0].all() and result.filled.sum() == 2 * 60 + 45
    for gap, m in ((slice(540, 600), 2), (slice(540, 600), 3), (slice(0, 45), 0)):
        error = np.abs(result.positions[gap, m] - pos[gap, m]).max()
        held = np.abs(cut[539 if gap.start else 45, m] - pos[gap, m]).max()  # the motor held still
        assert error < 0.15 < 1.0 < held, (m, error, held)
    np.testing.assert_array_equal(result.positions[np.isfinite(cut)], cut[np.isfinite(cut)])
    lone = cut[:, :1].copy()
    lone[:100] = np.nan  # no other marker to learn from: left unseen, and not said to be filled
    result = GapFiller().apply(lone, t)
    assert np.isnan(result.positions[:100]).all() and not result.filled.any()
