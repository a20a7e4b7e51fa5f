"""Knot-point animations: sampling and every editing operation against hand-made knot lists."""

import numpy as np
import pytest

from common import InputError
from toon import motor_index
from toon.animation import (
    Animation,
    concatenate,
    copy,
    cut,
    flip,
    from_track,
    insert_knot,
    paste,
    scale_time,
    scale_value,
    set_ease,
)
from toon.animation_file import load_animation, save_animation

A = Animation({"ELU": ((0.0, 0.8), (1.0, 0.0), (2.0, 0.8)), "MB": ((0.0, 0.1), (4.0, 0.5))}, 4.0)


def test_sampling_interpolates_linearly_holds_the_ends_and_rests_unset_motors():
    track = A.sample(4.0)
    assert track.frames == 16 and track.rate == 4.0
    np.testing.assert_allclose(track.column("ELU")[:9], [0.8, 0.6, 0.4, 0.2, 0.0, 0.2, 0.4, 0.6, 0.8])
    np.testing.assert_allclose(track.column("ELU")[9:], 0.8)
    np.testing.assert_allclose(track.column("MB")[[0, 8, 15]], [0.1, 0.3, 0.475])
    assert (track.column("BRL") == 0.4).all()  # the standard neutral


def test_copy_and_cut_take_the_slice_with_its_edge_values():
    clip = copy(A, ("ELU",), 0.5, 1.5)
    assert clip.knots["ELU"] == ((0.0, 0.4), (0.5, 0.0), (1.0, 0.4)) and clip.duration == 1.0
    edited, cut_clip = cut(A, ("ELU",), 0.5, 1.5)
    assert cut_clip.knots == clip.knots
    assert edited.knots["ELU"] == ((0.0, 0.8), (1.0, 0.8))  # 2.0 moved to 1.0
    assert edited.knots["MB"] == A.knots["MB"]  # other motors untouched


def test_paste_replaces_the_region_and_goes_onto_other_motors():
    clip = copy(A, ("ELU",), 0.0, 2.0)
    out = paste(A, clip, 2.0, onto={"ELU": "ERU"})
    assert out.knots["ERU"] == ((2.0, 0.8), (3.0, 0.0), (4.0, 0.8))
    again = paste(A, Animation({"MB": ((0.0, 1.0), (1.0, 1.0))}, 1.0), 1.0)
    assert again.knots["MB"] == ((0.0, 0.1), (1.0, 1.0), (2.0, 1.0), (4.0, 0.5))


def test_time_and_value_scaling_and_flip():
    slow = scale_time(A, ("ELU",), 0.0, 1.0, 2.0)
    assert slow.knots["ELU"] == ((0.0, 0.8), (2.0, 0.0), (3.0, 0.8)) and slow.duration == 5.0
    half = scale_value(A, ("ELU",), 0.0, 2.0, 0.5)  # about ELU's neutral 0.8
    np.testing.assert_allclose(half.knots["ELU"], [(0.0, 0.8), (1.0, 0.4), (2.0, 0.8)])
    big = scale_value(A, ("MB",), 0.0, 4.0, 3.0)  # about MB's neutral 0.1, clipped at 1
    np.testing.assert_allclose(big.knots["MB"], [(0.0, 0.1), (4.0, 1.0)])
    backwards = flip(A, ("MB",), 0.0, 4.0)
    assert backwards.knots["MB"] == ((0.0, 0.5), (4.0, 0.1))


def test_concatenate_with_and_without_a_cross_fade():
    b = Animation({"ELU": ((0.0, 0.2), (2.0, 0.2))}, 2.0)
    joined = concatenate(A, b)
    assert joined.duration == 6.0 and joined.knots["ELU"][-2:] == ((4.0, 0.2), (6.0, 0.2))
    faded = concatenate(A, b, fade=1.0)
    assert faded.duration == 5.0
    # over 3..4 s ELU blends from A's 0.8 into b's 0.2
    np.testing.assert_allclose(faded.value("ELU", np.array([3.0, 3.5, 4.0, 5.0])), [0.8, 0.5, 0.2, 0.2])
    with pytest.raises(ValueError, match="fade must be"):
        concatenate(A, b, fade=3.0)


def test_files_round_trip_and_bad_files_name_the_field(tmp_path):
    path = save_animation(A, tmp_path / "a.toml")
    assert load_animation(path) == A
    bad = tmp_path / "bad.toml"
    bad.write_text('format = "toonface.animation/1"\nduration = 2\n[knots]\nELU = [[1, 0.5], [0, 0.6]]\n')
    with pytest.raises(InputError, match="bad.toml: knots.ELU: knot times must increase"):
        load_animation(bad)
    bad.write_text('format = "toonface.animation/1"\nduration = 2\n[knots]\nmb = [[0, 0.5]]\n')
    with pytest.raises(InputError, match="knots.mb: unknown motor 'mb' \\(a motor such as MB, or a face's parameter"):
        load_animation(bad)
    assert motor_index("ELU") == 8


def test_a_slice_operation_leaves_the_motion_outside_its_slice_as_it_was():
    """MB [[0, 0.1], [4, 0.9]] flipped over 0-1 s became [[1, 0.1], [4, 0.9]]: at 2 s 0.5 -> 0.367."""
    mb = Animation({"MB": ((0.0, 0.1), (4.0, 0.9))}, 4.0)
    outside = np.array([1.0, 1.5, 2.0, 3.0, 4.0])
    flipped = flip(mb, ("MB",), 0.0, 1.0)
    np.testing.assert_allclose(flipped.value("MB", outside), mb.value("MB", outside))
    np.testing.assert_allclose(flipped.value("MB", [0.0, 0.25, 0.5, 0.999]), [0.3, 0.25, 0.2, 0.1002], atol=1e-9)
    middle = flip(mb, ("MB",), 1.0, 2.0)  # a slice inside the curve: steps at both of its ends
    np.testing.assert_allclose(middle.value("MB", [0.5, 1.0, 1.5, 2.0, 3.0]), [0.2, 0.5, 0.4, 0.5, 0.7])
    scaled = scale_value(mb, ("MB",), 1.0, 2.0, 0.0)  # the slice to MB's neutral (0.1)
    np.testing.assert_allclose(scaled.value("MB", [0.5, 1.0, 1.5, 1.999, 2.0, 3.0]),
                               [0.2, 0.1, 0.1, 0.1, 0.5, 0.7])
    stretched = scale_time(mb, ("MB",), 1.0, 2.0, 2.0)  # the slice twice as long, the rest shifted
    np.testing.assert_allclose(stretched.value("MB", [0.5, 1.0, 2.0, 3.0, 4.0, 5.0]),
                               [0.2, 0.3, 0.4, 0.5, 0.7, 0.9])


def test_files_write_each_motor_s_knots_as_inline_pairs(tmp_path):
    """Animation files were written one number per line."""
    long = Animation({"ELU": tuple((i * 0.5, 0.9 if i % 2 == 0 else 0.1) for i in range(12)), "MB": ((0.0, 0.1),)}, 6.0)
    path = save_animation(long, tmp_path / "a.toml")
    lines = path.read_text().splitlines()
    assert lines[:4] == ['format = "toonface.animation/1"', "duration = 6.0", "", "[knots]"]
    assert lines[4] == "ELU = [" and lines[5] == "    [0.0, 0.9], [0.5, 0.1], [1.0, 0.9], [1.5, 0.1], [2.0, 0.9],"
    assert lines[-1] == "MB = [[0.0, 0.1]]"
    assert load_animation(path) == long
    step = flip(Animation({"MB": ((0.0, 0.1), (4.0, 0.9))}, 4.0), ("MB",), 1.0, 2.0)
    assert load_animation(save_animation(step, tmp_path / "s.toml")) == step  # steps survive the file


@pytest.mark.parametrize("edit", ["flip", "scale_value"])
def test_a_slice_ending_or_starting_at_a_step_keeps_two_knots_there(edit, tmp_path):
    """A step (two knots at one time) at a slice's end: its outer knot is the motion after the
    slice; the edit must not add a third knot there (the file would not load)."""
    stepped = Animation({"MB": ((0.0, 0.2), (1.0, 0.6), (2.0, 0.8), (2.0, 0.4), (3.0, 0.1)),
                         "BRL": ((0.5, 0.3), (1.0, 0.3), (1.0, 0.9), (2.5, 0.5))}, 4.0)
    run = {"flip": lambda a, s, e: flip(a, None, s, e),
           "scale_value": lambda a, s, e: scale_value(a, None, s, e, 0.5)}[edit]
    for start, end in ((1.0, 2.0), (0.5, 2.0), (1.0, 3.0)):
        out = run(stepped, start, end)
        path = save_animation(out, tmp_path / "a.toml")
        assert load_animation(path) == out  # no three knots at one time
        for code in ("MB", "BRL"):
            for t in (0.25, 3.5):  # outside the slice: as it was
                if not start <= t <= end:
                    assert out.value(code, t) == pytest.approx(stepped.value(code, t))


def test_a_track_becomes_the_fewest_knots_within_the_tolerance():
    from toon import MOTOR_CODES, MotorTrack, standard_neutral
    from toon.animation import from_track

    rate = 50.0
    t = np.arange(201) / rate  # 4 s
    values = np.tile(standard_neutral(), (len(t), 1))
    values[:, motor_index("MB")] = np.interp(t, [0.0, 1.0, 1.5, 4.0], [0.1, 0.9, 0.3, 0.3])  # three straight pieces
    wave = 0.5 + 0.3 * np.sin(2 * np.pi * 0.5 * t)
    values[:, motor_index("ERU")] = wave
    anim = from_track(MotorTrack(values, rate), tolerance=0.01)
    assert anim.knots["MB"] == ((0.0, 0.1), (1.0, 0.9), (1.5, 0.3), (4.0, 0.3)) and anim.duration == len(t) / rate
    assert set(anim.knots) == {"MB", "ERU"}  # the others never leave the neutral
    error = np.abs(anim.value("ERU", t) - wave)
    assert error.max() <= 0.01 and 8 <= len(anim.knots["ERU"]) <= 40  # a sine needs some, not one per sample
    assert len(MOTOR_CODES) == 21
    with pytest.raises(ValueError, match="tolerance"):
        from_track(MotorTrack(values, rate), tolerance=0.0)


def test_a_face_s_parameters_are_knots_too_and_sample_into_extra_columns(tmp_path):
    """HT (a standard parameter) and EARS (a face's own) keep knots as motors do; the track
    sampled from them carries them after the 21, a parameter without knots rests."""
    anim = Animation({"MB": ((0.0, 0.1), (1.0, 0.9)), "EARS": ((0.0, 1.0), (1.0, 0.0)),
                      "HT": ((0.0, 0.5), (1.0, 1.0))}, 1.0)
    assert anim.extra_codes == ("HT", "EARS")  # the standard ones first
    back = load_animation(save_animation(anim, tmp_path / "p.toml"))
    assert back == anim
    track = anim.sample(4.0)
    assert track.extra_codes == ("HT", "EARS")
    np.testing.assert_allclose(track.extra[:, 0], [0.5, 0.625, 0.75, 0.875])
    np.testing.assert_allclose(track.extra[:, 1], [1.0, 0.75, 0.5, 0.25])
    assert float(anim.value("UL", 0.5)) == 0.0 and float(anim.value("JS", 0.5)) == 0.5  # their rests
    assert float(anim.value("EARS2", 0.5, declared={"EARS2": 0.3})) == 0.3
    again = from_track(track, 0.001)
    assert set(again.knots) == {"MB", "HT", "EARS"}


EASED = Animation({"MB": ((0.0, 0.1), (1.0, 0.1, True), (3.0, 0.9), (4.0, 0.9))}, 4.0)


def test_an_eased_segment_follows_the_smoothstep_and_the_others_stay_linear():
    """Issue 46's ease per segment, against hand-computed values: 3u^2 - 2u^3 of the way."""
    t = np.array([0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5])
    u = (t - 1.0) / 2.0
    hand = np.where((t >= 1) & (t <= 3), 0.1 + 0.8 * (3 * u**2 - 2 * u**3), np.where(t < 1, 0.1, 0.9))
    np.testing.assert_allclose(EASED.value("MB", t), hand, atol=1e-12)
    assert EASED.value("MB", 1.5) == pytest.approx(0.1 + 0.8 * 0.15625)  # slower out of the knot than linear
    linear = set_ease(EASED, "MB", 1, False)
    assert linear.value("MB", 1.5) == pytest.approx(0.3) and linear.knots["MB"][1] == (1.0, 0.1)
    with pytest.raises(ValueError, match="last knot"):
        set_ease(EASED, "MB", 3, True)
    assert insert_knot(EASED, "MB", 2.0, 0.5).knots["MB"][2] == (2.0, 0.5, True)  # eases on, as the segment did
    assert insert_knot(EASED, "MB", 3.5, 0.5).knots["MB"][3] == (3.5, 0.5)
    track = EASED.sample(10.0)
    np.testing.assert_allclose(track.values[10:31, motor_index("MB")],
                               EASED.value("MB", np.arange(10, 31) / 10.0), atol=1e-12)


def test_edits_keep_an_ease_where_the_motion_is_the_same_and_bake_it_where_a_slice_cuts_it(tmp_path):
    t = np.linspace(0, 4, 81)
    stretched = scale_time(EASED, ("MB",), 0.0, 4.0, 2.0)  # the whole: still eased, twice as long
    np.testing.assert_allclose(stretched.value("MB", 2 * t), EASED.value("MB", t), atol=1e-12)
    backwards = flip(EASED, ("MB",), 0.0, 4.0)  # the ease reads the same either way
    np.testing.assert_allclose(backwards.value("MB", 4.0 - t), EASED.value("MB", t), atol=1e-12)
    halved = scale_value(EASED, ("MB",), 0.0, 4.0, 0.5)  # about MB's neutral, still eased
    rest = 0.1
    np.testing.assert_allclose(halved.value("MB", t), rest + (EASED.value("MB", t) - rest) * 0.5, atol=1e-12)
    moved = paste(Animation({}, 6.0), copy(EASED, ("MB",), 0.0, 4.0), 2.0)
    np.testing.assert_allclose(moved.value("MB", t + 2.0), EASED.value("MB", t), atol=1e-12)
    from_the_knot = copy(EASED, ("MB",), 1.0, 4.0)  # a slice starting on an eased knot keeps its ease
    np.testing.assert_allclose(from_the_knot.value("MB", t[t <= 3.0]), EASED.value("MB", t[t <= 3.0] + 1.0),
                               atol=1e-12)
    # a slice from 2 s cuts the eased segment: outside it the motion stays within 0.003 of its change
    cut_here = scale_value(EASED, ("MB",), 2.0, 4.0, 0.0)
    before = t[t < 2.0]
    np.testing.assert_allclose(cut_here.value("MB", before), EASED.value("MB", before), atol=0.003 * 0.8)
    assert cut_here.value("MB", 2.5) == pytest.approx(0.1)  # inside: to the neutral
    path = save_animation(EASED, tmp_path / "eased.toml")
    assert '[1.0, 0.1, "ease"]' in path.read_text()
    assert load_animation(path) == EASED
    path.write_text(path.read_text().replace('"ease"', '"bounce"'))
    with pytest.raises(InputError, match=r'knots\.MB: expected .*"ease"'):
        load_animation(path)
