"""ToonFace's Animator scheduler (A1.2.4) against the seed's worked examples, with a fake clock."""

import numpy as np
import pytest

from player.animator import Animator, FakeClock, Loop, Move
from toon import MOTOR_CODES, motor_index, standard_neutral


def _open_eyes():
    start = standard_neutral()
    start[[motor_index("ELU"), motor_index("ERU")]] = 1.0
    return start


def test_closing_the_left_eye_in_500ms_at_a_100ms_loop_takes_5_slices_of_20_percent():
    animator = Animator(_open_eyes(), loop_time=0.1)
    animator.command([Move("ELU", 0.0, 0.5)])
    assert animator.pending("ELU") == 5 and animator.pending() == 5
    seen = [animator.tick()[motor_index("ELU")] for _ in range(6)]
    np.testing.assert_allclose(seen, [0.8, 0.6, 0.4, 0.2, 0.0, 0.0], atol=1e-12)


def test_closing_both_eyes_makes_10_slices_two_per_loop():
    animator = Animator(_open_eyes(), loop_time=0.1)
    animator.command([Move("ELU", 0.0, 0.5), Move("ERU", 0.0, 0.5)])
    assert animator.pending() == 10
    animator.tick()
    assert animator.pending() == 8
    for _ in range(4):
        values = animator.tick()
    assert values[motor_index("ELU")] == values[motor_index("ERU")] == pytest.approx(0.0)
    assert not animator.busy()


def test_a_new_command_replaces_the_remaining_slices_from_where_the_motor_is():
    animator = Animator(_open_eyes(), loop_time=0.1)
    animator.command([Move("ELU", 0.0, 0.5)])
    animator.tick(), animator.tick()  # at 0.6
    animator.command([Move("ELU", 1.0, 0.2)])  # back up in two slices from 0.6
    assert animator.pending("ELU") == 2
    np.testing.assert_allclose([animator.tick()[motor_index("ELU")] for _ in range(2)], [0.8, 1.0])


def test_all_21_motors_move_independently_and_a_zero_duration_is_one_slice():
    start = np.zeros(21)
    animator = Animator(start, loop_time=0.04)
    animator.command([Move(code, 1.0, 0.04 * (i + 1)) for i, code in enumerate(MOTOR_CODES)])
    first = animator.tick()
    np.testing.assert_allclose(first, [1.0 / (i + 1) for i in range(21)])
    animator.command([Move("MB", 0.5, 0.0)])
    assert animator.tick()[motor_index("MB")] == 0.5
    animator.command([Move("HH", 7.0, 0.04)])  # targets are clamped to the motor's range
    assert animator.tick()[motor_index("HH")] == 1.0


def test_the_loop_holds_its_loop_time_and_starts_scheduled_moves_on_time():
    clock = FakeClock()
    animator = Animator(_open_eyes(), loop_time=0.04)
    animator.schedule(0.2, [Move("ELU", 0.0, 0.08)])
    frames = []

    def frame(values, t):
        frames.append((round(t, 6), values[motor_index("ELU")]))
        clock.sleep(0.01)  # rendering takes 10 ms of each 40 ms loop

    loop = Loop(animator, clock, clock.sleep)
    assert loop.run(8, frame) == 8
    assert [t for t, _ in frames] == pytest.approx([0.0, 0.04, 0.08, 0.12, 0.16, 0.2, 0.24, 0.28])
    assert [v for _, v in frames] == pytest.approx([1, 1, 1, 1, 1, 0.5, 0.0, 0.0])
    assert max(loop.lateness) == 0.0


def test_a_slow_loop_drops_frames_but_keeps_real_time_and_every_slice():
    clock = FakeClock()
    animator = Animator(_open_eyes(), loop_time=0.04)
    animator.command([Move("ELU", 0.0, 0.4)])  # ten slices of 0.1
    seen, skipped = [], []

    def frame(values, t):
        seen.append((round(t / 0.04), values[motor_index("ELU")]))
        clock.sleep(0.1)  # 100 ms of drawing in a 40 ms loop

    loop = Loop(animator, clock, clock.sleep)
    drawn = loop.run(12, frame, skip=skipped.append)
    # each loop draws the newest slot already due: slot 0 (drawn 0-0.1 s), 2 (due 0.08), 5 (0.2),
    # 7 (0.28), 10 (0.4) and the last, 11 (due 0.44, drawn 0.5-0.6); it used to take 12 x 0.1 s
    assert clock() == pytest.approx(0.6)
    assert drawn + loop.dropped == 12 and sum(skipped) == loop.dropped == 6 and skipped == [1, 2, 1, 2]
    # each frame drawn shows its slot's value: dropped slots still ran their slices
    assert [value for _, value in seen] == pytest.approx([max(0.0, 1 - 0.1 * (slot + 1)) for slot, _ in seen])
    assert [slot for slot, _ in seen] == [0, 2, 5, 7, 10, 11]
