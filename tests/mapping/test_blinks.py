"""The blinks a take shows (mapping.blinks): where an upper lid shuts."""

import numpy as np

from mapping.blinks import LEAST_MM, find_blinks


def test_a_clean_lids_wiggles_are_not_blinks_and_do_not_set_where_it_shuts():
    """On a clean marker (the third performer's, written apart from the project) the robust sigmas
    alone counted wiggles of a few hundredths of a millimetre as blinks, 16 of 22, and the
    shallowest set the closed lid at rest: the cartoon's eye shut in 38 % of the take and its
    lid motor followed the performer's at r 0.49. Blinks are at least LEAST_MM deep."""
    rate = 120.0
    t = np.arange(int(20 * rate)) / rate
    rng = np.random.default_rng(3)
    lid = 0.004 * rng.standard_normal(len(t))
    for at in np.arange(0.7, 20.0, 0.9):  # 0.1 mm dips that come and go within a few frames
        lid -= 0.1 * np.exp(-0.5 * ((t - at) / 0.02) ** 2)
    blinks = (3.5, 9.0, 15.0)
    for at, depth in zip(blinks, (3.0, 2.6, 3.4), strict=True):
        lid -= depth * np.exp(-0.5 * ((t - at) / 0.04) ** 2)
    found = find_blinks(lid, rate)
    assert found is not None
    assert [round(f / rate, 2) for f in found.frames] == list(blinks)
    assert -2.7 < found.closed < -2.5  # the shallowest real blink, 2.6 mm
    assert LEAST_MM <= 1.6  # the jaw take's shallowest real blink still counts


def test_a_lid_that_only_wiggles_shows_no_blinks():
    rate = 60.0
    t = np.arange(int(10 * rate)) / rate
    lid = -0.3 * (np.abs(((t + 0.2) % 1.5) - 0.75) < 0.05)  # 0.3 mm flicks, as brief as blinks
    assert find_blinks(lid + 0.002 * np.random.default_rng(1).standard_normal(len(t)), rate) is None
