"""Label swaps of two neighbouring markers, found and undone in cleaning (:mod:`mapping.swaps`)."""

import numpy as np
import pytest

from capture import Take, load_markerset, synthesize
from capture.performance import default_performance
from mapping.clean import clean_stabilised
from mapping.swaps import LONGEST_SWAP_SECONDS, Swap, find_swaps, undo_swaps


def _lids(frames: int = 240, rate: float = 120.0, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """An upper and a lower lid 10 mm apart and a far marker, at ``rate`` Hz with 0.25 mm of
    jitter; the upper lid blinks down to 1 mm above the lower one at frame 120. ``(F, 3, 3)``."""
    rng = np.random.default_rng(seed)
    times = np.arange(frames) / rate
    blink = np.interp(times, [0.95, 1.03, 1.18], [0.0, 9.0, 0.0])
    upper = np.column_stack([np.zeros(frames), 10.0 - blink, 2.0 * np.sin(times)])
    lower = np.column_stack([np.zeros(frames), np.full(frames, 0.5 * np.sin(3 * times)), np.zeros(frames)])
    far = np.column_stack([60.0 + np.sin(times), np.zeros(frames), np.zeros(frames)])
    return np.stack([upper, lower, far], axis=1) + rng.normal(0.0, 0.25, (frames, 3, 3)), times


def test_a_swap_of_two_lids_is_found_to_the_frame_and_undone():
    """Eight frames with the lids' labels traded are found as one swap of exactly those frames
    (a blink, which brings the upper lid next to the lower, is not one), and undoing it gives
    back the samples as they were."""
    truth, times = _lids()
    swapped = truth.copy()
    swapped[60:68, [0, 1]] = swapped[60:68, [1, 0]]
    swaps = find_swaps(swapped, times)
    assert swaps == [Swap(0, 1, 60, 68)]
    undo_swaps(swapped, swaps)
    assert np.array_equal(swapped, truth)
    assert find_swaps(truth, times) == []


def test_a_swap_with_frames_unseen_inside_is_still_found():
    """A marker lost for a few frames in the middle of the swap does not hide it."""
    truth, times = _lids()
    swapped = truth.copy()
    swapped[30:40, [0, 1]] = swapped[30:40, [1, 0]]
    swapped[33:36, 1] = np.nan
    assert find_swaps(swapped, times) == [Swap(0, 1, 30, 40)]


def test_a_swap_that_begins_with_a_spike_is_found_from_the_frame_before():
    """A spike on the swap's first frame hides the jump there (one marker lands nowhere near the
    other's place); the jump is seen from the frame before the spike to the one after, and the
    spiked frame is left to the spike tests."""
    truth, times = _lids()
    swapped = truth.copy()
    swapped[60:68, [0, 1]] = swapped[60:68, [1, 0]]
    swapped[60, 1] += np.array([6.0, -5.0, 4.0])
    assert find_swaps(swapped, times) == [Swap(0, 1, 61, 68)]


def test_a_swap_that_begins_while_one_marker_is_hidden_is_found():
    """The lower lid hidden when the labels trade (the upper lid's label jumps alone onto its
    place) and seen again before they trade back: the swap is found from the lone jump and the
    pair's jump back, and undone."""
    truth, times = _lids()
    truth[40:46, 1] = np.nan
    swapped = truth.copy()
    swapped[42:50, [0, 1]] = swapped[42:50, [1, 0]]
    assert find_swaps(swapped, times) == [Swap(0, 1, 42, 50)]


def test_one_frame_near_a_hidden_neighbour_is_left_to_the_spike_tests():
    """One sample of the upper lid at the hidden lower lid's place is as likely a spike as a swap:
    it is not swapped (the spike tests blank it), while two such samples are."""
    truth, times = _lids()
    for frames, found in ((1, []), (2, [Swap(0, 1, 44, 46)])):
        swapped = truth.copy()
        swapped[44:44 + frames, 0] = truth[44:44 + frames, 1]  # the lower lid labelled as the upper
        swapped[40:50, 1] = np.nan  # and not as itself, nor around then
        assert find_swaps(swapped, times) == found


def test_labels_traded_for_longer_than_a_swap_are_left_alone():
    """Markers whose labels stay traded for longer than the longest swap (the labeller has lost
    them) are not guessed at."""
    truth, times = _lids(frames=480)
    long = int(LONGEST_SWAP_SECONDS * 120) + 12
    swapped = truth.copy()
    swapped[60:60 + long, [0, 1]] = swapped[60:60 + long, [1, 0]]
    assert find_swaps(swapped, times) == []


@pytest.mark.parametrize("frames", [4, 9])
def test_cleaning_gives_a_swapped_lip_its_samples_back(frames):
    """A take with two lip markers' labels traded for a few frames is cleaned as if they had not
    been: the report counts the swap, and the cleaned markers stay within a millimetre of the
    take cleaned without it (before, the spike tests blanked a frame or two and kept the rest as
    the other marker's path, several millimetres off, and the report said nothing)."""
    syn = synthesize(rate=120.0, noise_mm=0.2, performance=default_performance(6, max_turn_deg=20), seed=3)
    ms = load_markerset("toon32")
    a, b = syn.take.index("LIP_LOW"), syn.take.index("LIP_LOW_R")
    swapped = syn.take.positions.copy()
    rows = slice(300, 300 + frames)
    swapped[rows, [a, b]] = swapped[rows, [b, a]]
    intact, _ = clean_stabilised(syn.take, ms)
    stable, report = clean_stabilised(Take(swapped, syn.take.labels, 120.0, times=syn.take.times), ms)
    assert report.swaps == 1 and "1 label swap of neighbouring markers undone" in report.summary()
    off = np.linalg.norm(stable.local[rows, [a, b]] - intact.local[rows, [a, b]], axis=-1)
    assert off.max() < 1.0, off.max()
    assert np.linalg.norm(intact.local[300, a] - intact.local[300, b]) > 5.0  # a swap that matters


def test_a_layout_without_head_references_has_its_swaps_undone_too():
    """A marker set without head references is cleaned in one fixed placement; a swap of two lip
    markers there is found and undone as in the head frame (the performer's head held still)."""
    from dataclasses import replace

    syn = synthesize(rate=120.0, noise_mm=0.2, performance=default_performance(6, max_turn_deg=0), seed=3)
    ms = replace(load_markerset("toon32"), head_reference=())
    a, b = syn.take.index("LIP_LOW"), syn.take.index("LIP_LOW_R")
    swapped = syn.take.positions.copy()
    swapped[300:307, [a, b]] = swapped[300:307, [b, a]]
    intact, _ = clean_stabilised(syn.take, ms)
    stable, report = clean_stabilised(Take(swapped, syn.take.labels, 120.0, times=syn.take.times), ms)
    assert report.swaps == 1 and "no head references" in report.head
    off = np.linalg.norm(stable.local[300:307, [a, b]] - intact.local[300:307, [a, b]], axis=-1)
    assert off.max() < 1.0, off.max()
