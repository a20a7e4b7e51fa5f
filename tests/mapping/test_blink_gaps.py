"""Blinks made up on both eyes at once finish as the take's own blinks do (mapping.blink_gaps)."""

import numpy as np
import pytest

from capture import Take, synthesize
from capture.performance import Cue, Performance
from mapping import calibrate, choose_mapping, map_stabilised, map_take, prepare
from mapping.blink_gaps import blink_timing, finish_blinks
from toon import MOTOR_CODES

RATE = 100.0
ERU, ELU = MOTOR_CODES.index("ERU"), MOTOR_CODES.index("ELU")


def _blink(times: np.ndarray, at: float, close: float = 0.1, reopen: float = 0.2) -> np.ndarray:
    """How far shut ``(F,)``, 0 to 1: closing in straight lines for ``close`` seconds to ``at``,
    reopening for ``reopen``."""
    down = np.clip((times - (at - close)) / close, 0.0, 1.0)
    up = np.clip((times - at) / reopen, 0.0, 1.0)
    return np.where(times < at, down, 1.0 - up)


def _lids(blinks: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Times ``(F,)`` and 21 motors ``(F, 21)`` at 0.5, the upper lids open at 0.8 and shut to 0.1
    in each of ``blinks``."""
    times = np.arange(int(6 * RATE)) / RATE
    shut = sum((_blink(times, at) for at in blinks), np.zeros_like(times))
    values = np.full((len(times), len(MOTOR_CODES)), 0.5)
    values[:, [ERU, ELU]] = (0.8 - 0.7 * shut)[:, None]
    return times, values


def test_a_blinks_timing_is_the_takes_own():
    """Three blinks 0.7 deep reopening in straight lines over 0.2 s: their way back measured frame
    by frame (a twentieth a frame, then open), back within a tenth of their depth 18 frames after
    their deepest; shut at 0.1."""
    times, values = _lids((1.0, 2.0, 3.0))
    timing = blink_timing(values[:, ERU], RATE)
    assert timing is not None
    assert timing.closed == pytest.approx(0.1)
    assert timing.depth == pytest.approx(0.7)
    assert timing.reopening[:22] == pytest.approx(np.minimum(np.arange(1, 23) / 20, 1.0))
    assert timing.reopen_frames == 18
    assert blink_timing(_lids((1.0,))[1][:, ERU], RATE) is None  # one blink tells too little


def test_a_blink_made_up_on_both_eyes_reopens_as_the_takes_blinks_do():
    """A fourth blink whose last 0.4 s was made up on both lids and filled as a straight line from
    the deepest frame to the open lid: it reopens in the take's 0.2 s instead, and is open at
    its measured value after; what was measured is left as it was."""
    times, truth = _lids((1.0, 2.0, 3.0, 4.5))
    made = (times >= 4.5) & (times < 4.9)
    values = truth.copy()
    line = np.linspace(truth[made][0, ERU], 0.8, made.sum() + 2)[1:-1]
    values[made, ERU] = values[made, ELU] = line
    invented = np.zeros(values.shape, bool)
    invented[made, ERU] = invented[made, ELU] = True
    out, finished = finish_blinks(values, invented, RATE)
    assert finished == [pytest.approx(4.5)]
    assert np.array_equal(out[~made], values[~made])
    others = [k for k in range(len(MOTOR_CODES)) if k not in (ERU, ELU)]
    assert np.array_equal(out[:, others], values[:, others])  # other motors alone
    reopened = np.flatnonzero(made)[0] + 20  # 0.2 s, as the measured blinks
    assert out[reopened:, ERU][:40] == pytest.approx(0.8)
    assert np.abs(out[made, ERU] - truth[made, ERU]).max() < 0.05
    assert np.abs(values[made, ERU] - truth[made, ERU]).max() > 0.3  # what the line missed


def test_a_blink_made_up_while_closing_closes_on_to_the_shut_lid_first():
    """Made up from 0.03 s before the deepest frame: the lid goes on closing at its speed to the
    take's shut lid (0.1), then reopens."""
    times, truth = _lids((1.0, 2.0, 3.0, 4.5))
    made = (times >= 4.47) & (times < 4.9)
    values = truth.copy()
    values[made, ERU] = values[made, ELU] = 0.8
    invented = np.zeros(values.shape, bool)
    invented[made, ERU] = invented[made, ELU] = True
    out, _ = finish_blinks(values, invented, RATE)
    assert out[made, ERU].min() == pytest.approx(0.1)
    assert np.abs(out[made, ERU] - truth[made, ERU]).max() < 0.05


@pytest.mark.parametrize("case", ["one eye", "open", "short", "no blinks"])
def test_made_up_lids_are_left_as_filled_where_no_blink_needs_finishing(case):
    """One eye made up (the pair rule's case), lids open going in, a stretch shorter than the
    take's reopening (the fill bridges as well), or a take without two measured blinks."""
    times, values = _lids((4.5,) if case == "no blinks" else (1.0, 2.0, 3.0, 4.5))
    made = (times >= 4.5) & (times < (4.6 if case == "short" else 4.9))
    if case == "open":
        made = (times >= 5.2) & (times < 5.6)
    invented = np.zeros(values.shape, bool)
    invented[made, ERU] = True
    invented[made, ELU] = case != "one eye"
    values[made, ERU] = 0.3
    out, finished = finish_blinks(values, invented, RATE)
    assert finished == []
    assert np.array_equal(out, values)


def test_a_takes_lid_markers_lost_together_after_a_blinks_deepest_frame_reopen_with_it():
    """Both upper lids' markers lost for 0.48 s from just after a blink's deepest frame: the gap
    filler had nothing seen to follow and left the lids far from the blink measured (a third of
    the way off on average); mapped, they now reopen with it, and the track says where."""
    cues = tuple(Cue("blink", t, 0.3) for t in (1.0, 2.0, 3.0, 4.5))
    take = synthesize(seconds=6.0, rate=60.0, noise_mm=0.0, performance=Performance(6.0, cues), seed=4).take

    def mapped(take: Take):
        mapping, markerset = choose_mapping(take)
        prepared = prepare(take, markerset)
        return map_stabilised(prepared.stable, prepared.columns, take.times, take.rate, mapping,
                              calibrate(mapping, prepared, (0.0, 0.8)), filled=prepared.stable.filled)

    seen = mapped(take).values
    lost = (take.times >= 4.62) & (take.times < 5.1)
    positions = take.positions.copy()
    for label in ("LID_L_UP", "LID_R_UP"):
        positions[lost, take.index(label)] = np.nan
    track = mapped(Take(positions, take.labels, take.rate, times=take.times))
    assert track.meta["blinks_finished_s"] == [pytest.approx(4.633, abs=0.01)]
    for column in (ERU, ELU):
        assert np.abs(track.values[lost, column] - seen[lost, column]).mean() < 0.15


def test_the_report_says_where_blinks_were_finished():
    cues = tuple(Cue("blink", t, 0.3) for t in (1.0, 2.0, 3.0, 4.5))
    take = synthesize(seconds=6.0, rate=60.0, noise_mm=0.0, performance=Performance(6.0, cues), seed=4).take
    positions = take.positions.copy()
    for label in ("LID_L_UP", "LID_R_UP"):
        positions[(take.times >= 4.62) & (take.times < 5.1), take.index(label)] = np.nan
    notes = map_take(Take(positions, take.labels, take.rate, times=take.times)).meta["report"]["notes"]
    said = [n for n in notes if "lost together in a blink, at 4.633 s: the lids finish it as" in n]
    assert len(said) == 1, notes
