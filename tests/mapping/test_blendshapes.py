"""Blendshape scores as channels of a take, and as a kind of mapping source."""

import json
import tomllib

import numpy as np
import pytest

from capture import Take, load_markerset, load_take, save_take, synthesize
from capture.performance import default_performance
from capture.sources import take_source
from common import InputError
from mapping import CleanSettings, calibrate, map_take, parse_mapping, prepare
from mapping.clean import clean_channels
from mapping.learning import RangeLearner
from mapping.profile import Profile, SourceRange
from mapping.stepwise import LiveMapper
from toon import motor_index, standard_neutral
from toonface.cli import main

RATE = 60.0
RAW = CleanSettings(spikes=False, max_gap_seconds=0.0, cutoff_hz=0.0)

JAW = """
format = "toonface.mapping/1"
markerset = "toon32"
[motor.MB]
sources = [{ blendshape = "jawOpen" }]
normalise = "scale"
scale = 0.5
loss = { policy = "ease", seconds = 0.5 }
[motor.BRL]
sources = [{ marker = "BROW_R_LAT", axis = "y" }, { blendshape = "browOuterUpRight" }]
combine = "max"
"""


def _with_channels(take: Take, jaw: np.ndarray, brow: np.ndarray) -> Take:
    return Take(take.positions, take.labels, take.rate, take.times, take.dims, take.meta,
                channels=np.column_stack([jaw, brow]), channel_names=("jawOpen", "browOuterUpRight"))


@pytest.fixture(scope="module")
def performer():
    """The synthetic performer (rest for its first seconds) with a jaw score that rests at 0.1
    and rises to 0.6, and a brow score that stays at 0."""
    take = synthesize(seconds=6, rate=RATE, performance=default_performance(6), seed=2).take
    jaw = np.where(take.times < 2.0, 0.1, 0.1 + 0.5 * np.clip(take.times - 2.0, 0.0, 1.0))
    return _with_channels(take, jaw, np.zeros(take.frames))


def test_a_take_checks_its_channels():
    positions = np.zeros((3, 1, 3))
    assert Take(positions, ["A"], 10.0).channels.shape == (3, 0)
    with pytest.raises(InputError, match=r"channels must have shape \(3, 2\)"):
        Take(positions, ["A"], 10.0, channels=np.zeros((3, 1)), channel_names=("jawOpen", "x"))
    with pytest.raises(InputError, match="repeated: \\['x'\\]"):
        Take(positions, ["A"], 10.0, channels=np.zeros((3, 2)), channel_names=("x", "x"))
    with pytest.raises(InputError, match="infinities"):
        Take(positions, ["A"], 10.0, channels=np.full((3, 1), np.inf), channel_names=("x",))
    take = Take(positions, ["A"], 10.0, channels=[[0.1], [np.nan], [0.3]], channel_names=("jawOpen",))
    np.testing.assert_array_equal(take.channel("jawOpen"), [0.1, np.nan, 0.3])
    with pytest.raises(InputError, match='no channel "jawClose"'):
        take.channel("jawClose")


def test_channels_survive_an_npz_and_a_take_source(performer, tmp_path):
    back = load_take(save_take(performer, tmp_path / "t.npz"))
    assert back.channel_names == performer.channel_names
    np.testing.assert_array_equal(back.channels, performer.channels)
    again = take_source(back).to_take()
    np.testing.assert_array_equal(again.channels, performer.channels)


def test_an_npz_from_before_channels_reads_with_none(tmp_path):
    path = tmp_path / "old.npz"
    np.savez_compressed(path, format="toonface.take/1", positions=np.zeros((2, 1, 3)), labels=np.array(["A"]),
                        rate=np.float64(5.0), times=np.array([0.0, 0.2]), dims=np.int64(3), meta=json.dumps({}))
    take = load_take(path)
    assert take.channel_names == () and take.channels.shape == (2, 0)


def test_clean_says_what_a_csv_leaves_out(performer, tmp_path, capsys):
    save_take(performer, tmp_path / "t.npz")
    assert main(["clean", str(tmp_path / "t.npz"), "-o", str(tmp_path / "c.csv")]) == 0
    assert "c.csv keeps the markers only; its 2 channels (jawOpen, browOuterUpRight, ...) need a .npz" in \
        capsys.readouterr().err
    assert main(["clean", str(tmp_path / "t.npz"), "-o", str(tmp_path / "c.npz")]) == 0
    assert load_take(tmp_path / "c.npz").channel_names == performer.channel_names


def test_cleaning_fills_a_short_gap_in_a_channel_straight_across_and_leaves_a_long_one():
    values = np.array([0.0, 0.2, np.nan, np.nan, 0.8, 1.0] + [np.nan] * 10 + [0.5])
    take = Take(np.zeros((len(values), 1, 3)), ["A"], 10.0, channels=values[:, None], channel_names=("jawOpen",))
    out = clean_channels(take, CleanSettings(max_gap_seconds=0.5, cutoff_hz=0.0))["jawOpen"]
    np.testing.assert_allclose(out[:6], [0.0, 0.2, 0.4, 0.6, 0.8, 1.0])
    assert np.isnan(out[6:16]).all() and out[16] == 0.5


def test_a_blendshape_source_moves_its_motor_by_hand(performer):
    """MB: neutral + (score - rest) / scale, the rest the score's median over the first second;
    BRL takes the larger of its marker's motion and a score that never moves."""
    mapping = parse_mapping(tomllib.loads(JAW))
    track = map_take(performer, mapping, settings=RAW)
    profile = calibrate(mapping, prepare(performer, load_markerset("toon32"), RAW))
    assert profile.sources["blendshape.jawOpen"].neutral == pytest.approx(0.1)
    mb = motor_index("MB")
    expected = np.clip(standard_neutral()[mb] + (performer.channel("jawOpen") - 0.1) / 0.5, 0, 1)
    np.testing.assert_allclose(track.values[:, mb], expected, atol=1e-9)
    assert track.values[:, mb].max() == 1.0 and track.confidence[:, mb].min() == 1.0
    alone = map_take(performer, parse_mapping(tomllib.loads(JAW.replace(', { blendshape = "browOuterUpRight" }',
                                                                        ""))), settings=RAW)
    np.testing.assert_allclose(track.values[:, motor_index("BRL")], np.maximum(
        alone.values[:, motor_index("BRL")], standard_neutral()[motor_index("BRL")]), atol=1e-9)


def test_a_score_never_moved_keeps_a_wide_range_in_score_units(performer):
    """Thresholds written in mm count 0.05 of a score per mm: a still score keeps 10 mm's worth
    (0.5) either side of its rest, a moving one its percentiles."""
    profile = calibrate(parse_mapping(tomllib.loads(JAW)), prepare(performer, load_markerset("toon32"), RAW))
    still = profile.sources["blendshape.browOuterUpRight"]
    assert (still.low, still.neutral, still.high) == pytest.approx((-0.5, 0.0, 0.5))
    jaw = profile.sources["blendshape.jawOpen"]
    assert jaw.high == pytest.approx(np.percentile(performer.channel("jawOpen"), 99.5))


def test_a_mapping_names_only_real_blendshapes():
    doc = tomllib.loads(JAW.replace('"jawOpen"', '"jawOpn"'))
    with pytest.raises(InputError, match=r"j.toml: motor.MB.sources\[0\].blendshape: expected one of ARKit's"):
        parse_mapping(doc, "j.toml")
    doc = tomllib.loads(JAW.replace('{ blendshape = "jawOpen" }', '{ blendshape = "jawOpen", axis = "y" }'))
    with pytest.raises(InputError, match=r"motor.MB.sources\[0\].axis: unknown field"):
        parse_mapping(doc, "j.toml")


def test_a_take_without_the_channel_is_refused_by_name(performer):
    plain = Take(performer.positions, performer.labels, performer.rate, performer.times)
    with pytest.raises(InputError, match='the take has no blendshape channel "jawOpen"'):
        map_take(plain, parse_mapping(tomllib.loads(JAW)))


def test_live_channels_are_held_over_a_short_loss_and_match_offline(performer):
    """Stepping frames with their channels gives the offline MB (a blendshape-only motor needs no
    marker smoothing); a score missing for a moment is held, then lost after hold_seconds."""
    mapping = parse_mapping(tomllib.loads(JAW))
    profile = calibrate(mapping, prepare(performer, load_markerset("toon32"), RAW))
    offline = map_take(performer, mapping, profile, settings=RAW).values[:, motor_index("MB")]
    live = LiveMapper(mapping, load_markerset("toon32"), profile, performer.labels, RATE, rest_seconds=0.0,
                      hold_seconds=0.1, channel_names=performer.channel_names)
    frames = list(take_source(performer).frames)
    stepped = [live.step(f.positions, f.t, f.channels)[0][motor_index("MB")] for f in frames[:200]]
    np.testing.assert_allclose(stepped, offline[:200], atol=1e-9)
    held = [live.step(f.positions, f.t, None) for f in frames[200:215]]
    assert [h[0][motor_index("MB")] for h in held[:6]] == pytest.approx([stepped[-1]] * 6)
    assert held[-1][1][motor_index("MB")] == 0.0  # lost: its confidence is gone
    assert held[-1][0][motor_index("MB")] < stepped[-1] - 0.05  # and it eases toward neutral


def test_learned_ranges_start_a_score_at_its_share_of_the_side():
    rests = Profile("face", {"blendshape.jawOpen": SourceRange(0.1, 0.1, 0.1), "LIP_LOW.y": SourceRange(5, 5, 5)},
                    np.eye(3))
    learner = RangeLearner(rests, min_side=4.0)
    assert learner.profile.sources["blendshape.jawOpen"].high == pytest.approx(0.3)
    assert learner.profile.sources["LIP_LOW.y"].high == pytest.approx(9.0)
    learner.update({"blendshape.jawOpen": 0.7}, 0.0)
    assert learner.profile.sources["blendshape.jawOpen"].high == pytest.approx(0.7)


def test_info_lists_each_channel_with_its_range(performer, tmp_path, capsys):
    save_take(performer, tmp_path / "t.npz")
    assert main(["info", str(tmp_path / "t.npz")]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [x.split() for x in lines if x.split()[:1] == ["jawOpen"]] == [["jawOpen", "360", "0.100", "0.600"]]


def test_ranges_learned_live_reach_the_very_next_frame(performer):
    """The live mapper keeps motor_values' plan while its profile stands; a learner widens ranges
    in place, and the next frame maps with them (a kept plan would clamp it at the old edge)."""
    mapping = parse_mapping(tomllib.loads(JAW.replace('normalise = "scale"\nscale = 0.5\n', "")))
    live = LiveMapper(mapping, load_markerset("toon32"), Profile("toon32", {}, np.eye(3)), performer.labels, RATE,
                      rest_seconds=0.5, learn_seconds=60.0, channel_names=performer.channel_names)
    frames = list(take_source(performer).frames)
    jaw, mb = performer.channel_names.index("jawOpen"), motor_index("MB")

    def step(frame, score=None):
        channels = frame.channels.copy()
        if score is not None:
            channels[jaw] = score
        return live.step(frame.positions, frame.t, channels)[0][mb]

    for frame in frames[:40]:  # the rest, then a few frames of learning
        step(frame)
    rest = live.profile.sources["blendshape.jawOpen"].neutral
    step(frames[40], rest + 0.8)  # the range widens to here
    neutral = standard_neutral()[mb]
    assert step(frames[41], rest + 0.4) == pytest.approx(neutral + 0.5 * (1 - neutral), abs=1e-3)  # half its way
