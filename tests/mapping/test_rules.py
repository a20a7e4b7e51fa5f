"""The per-frame rules exist once: offline mapping and the live sender give the same motors."""

import dataclasses

import numpy as np
import pytest

from capture import load_markerset, synthesize
from capture.performance import default_performance
from mapping import CleanSettings, Stabilised, calibrate, load_mapping, map_stabilised, parse_mapping, prepare
from mapping.mapper import marker_quality
from mapping.rules import WINK_BLEND, MotorRules, eyes_pair, trailing_mean
from mapping.stepwise import LiveMapper
from toon import motor_index, standard_neutral
from toon.motors import N_CODES, extended_neutral

RATE = 60.0

#: Every rule of the mapping language switched on somewhere.
EVERYTHING = """
format = "toonface.mapping/1"
name = "everything"
markerset = "toon32"
mirror = true
symmetric = [["BRL", "BLL"]]
eyes = { lids = ["ERU", "ELU"], sync = 0.2, closed = 0.3 }

[style]
tremble = { amplitude = 0.02, frequency = 5.0, motors = ["BRC", "BLC", "MB"] }
sharpen = { steps = 9, motors = ["ERU", "ELU"] }
smooth = { seconds = 0.1, motors = ["BRM", "BLM", "MB", "PRH"] }

[motor.BRL]
sources = [{ marker = "BROW_R_LAT", axis = "y" }]
filter = { kind = "one-euro", min_cutoff = 1.0, beta = 0.3 }
loss = { policy = "idle", seconds = 0.2 }
[motor.BLL]
sources = [{ marker = "BROW_L_LAT", axis = "y" }]
filter = { kind = "butterworth", cutoff = 8.0, order = 2 }
loss = { policy = "ease", seconds = 0.3 }
[motor.BRC]
sources = [{ marker = "BROW_R_CEN", axis = "y" }, { marker = "BROW_R_MED", axis = "y", weight = 2.0 }]
combine = "weighted"
filter = { kind = "savitzky-golay", window = 7, order = 2 }
[motor.BLC]
sources = [{ marker = "BROW_L_CEN", axis = "y" }, { marker = "BROW_L_MED", axis = "y" }]
combine = "mean"
clamp = "soft"
limits = [0.1, 0.9]
[motor.BRM]
sources = [{ marker = "BROW_R_MED", axis = "y" }]
combine = "min"
curve = [[0, 0], [0.5, 0.3], [1, 1]]
max_speed = 2.0
[motor.BLM]
sources = [{ marker = "BROW_L_MED", axis = "y" }]
decouple = ["MB"]
gain = 1.4
offset = 0.05
delay = 0.05
[motor.ERU]
sources = [{ marker = "LID_R_UP", axis = "y" }]
normalise = "scale"
scale = 8.0
invert = true
loss = { policy = "pair", seconds = 0.3 }
[motor.ELU]
sources = [{ marker = "LID_L_UP", axis = "y", invert = true }]
loss = { policy = "hold" }
clamp = "none"
max_speed = 4.0
delay = 0.1
[motor.MB]
sources = [{ marker = "LIP_LOW", axis = "y", invert = true }, { distance = ["LIP_UP", "LIP_LOW"] }]
combine = "max"
loss = { policy = "idle", seconds = 0.5 }
[motor.PRH]
sources = [{ angle = ["MOUTH_R", "LIP_LOW", "MOUTH_L"] }, { difference = ["MOUTH_R", "MOUTH_L"], axis = "x" }]
combine = "weighted"
[motor.HH]
sources = [{ head = "yaw" }]
normalise = "scale"
scale = 60.0
"""


@pytest.fixture(scope="module")
def cleaned():
    """A synthetic take cleaned offline (gap filling off, so that markers go missing), with
    long losses of a brow, the two upper lids (overlapping) and the lips cut into it."""
    syn = synthesize(seconds=8, rate=RATE, performance=default_performance(8), seed=3)
    take = syn.take
    positions = take.positions.copy()
    for label, frames in (("BROW_R_LAT", slice(200, 260)), ("LID_R_UP", slice(100, 180)),
                          ("LID_L_UP", slice(150, 220)), ("LIP_LOW", slice(300, 420)), ("BROW_L_LAT", slice(0, 40))):
        positions[frames, take.index(label)] = np.nan
    take = type(take)(positions, take.labels, take.rate, take.times, take.dims, take.meta)
    mapping = parse_mapping(__import__("tomllib").loads(EVERYTHING))
    prepared = prepare(take, load_markerset("toon32"), CleanSettings(max_gap_seconds=0.0))
    profile = calibrate(mapping, prepared)
    profile = dataclasses.replace(profile, couplings={"BROW_L_MED.y": {"LIP_LOW.y": (0.1, -0.2)}})
    return mapping, prepared, profile


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_live_and_offline_map_the_same_cleaned_frames_equally_with_every_rule_on(cleaned):
    mapping, prepared, profile = cleaned
    stable, times = prepared.stable, prepared.take.times
    neutral = standard_neutral()
    filled = np.zeros(stable.local.shape[:2], bool)  # counted as made up by cleaning: ERU follows ELU there
    filled[400:440, prepared.columns["LID_R_UP"]] = True
    offline = map_stabilised(stable, prepared.columns, times, RATE, mapping, profile, neutral, filled, seed=7)
    live = LiveMapper(mapping, prepared.markerset, profile, prepared.take.labels, RATE, neutral, rest_seconds=0.0,
                      seed=7)
    quality = marker_quality(stable.local, filled)
    stepped = np.array([live.map_frame(Stabilised(stable.local[f:f + 1], stable.rotation[f:f + 1],
                                                  stable.translation[f:f + 1], stable.ok[f:f + 1], stable.reference),
                                       quality[f:f + 1], float(times[f]))[0] for f in range(len(times))])
    assert offline.meta["lost_frames"] > 200  # the losses are there, so the loss policies ran
    plain = map_stabilised(stable, prepared.columns, times, RATE, mapping,
                           dataclasses.replace(profile, couplings={}), neutral, seed=7)
    mirrored = motor_index("BRM")  # BLM shows on the other side: the mapping mirrors
    assert np.abs(plain.values[:, mirrored] - offline.values[:, mirrored]).max() > 0.01  # the decoupling acts
    measured = map_stabilised(stable, prepared.columns, times, RATE, mapping, profile, neutral, seed=7).values
    eru = motor_index("ERU")
    assert np.abs(measured[400:440, eru] - offline.values[400:440, eru]).max() > 0.01  # the made-up frames follow
    np.testing.assert_allclose(stepped, offline.values, rtol=0, atol=1e-9)
    moving = offline.values.std(axis=0)
    assert (moving[[motor_index(c) for c in ("BRL", "BLC", "BRM", "ERU", "MB", "HH")]] > 0.01).all()


def test_the_loss_policies_by_hand():
    """hold keeps the last value; ease reaches neutral ``seconds`` after the last frame seen;
    before anything is seen the last value is the neutral."""
    doc = {"format": "toonface.mapping/1", "markerset": "toon32",
           "motor": {"BRL": {"sources": [{"marker": "BROW_R_LAT", "axis": "y"}], "loss": {"policy": "hold"}},
                     "BLL": {"sources": [{"marker": "BROW_L_LAT", "axis": "y"}],
                             "loss": {"policy": "ease", "seconds": 0.5}}}}
    mapping = parse_mapping(doc)
    neutral = standard_neutral()
    raw = np.tile(neutral, (7, 1))
    brl, bll = motor_index("BRL"), motor_index("BLL")
    raw[:, brl] = [np.nan, 0.8, np.nan, np.nan, 0.6, np.nan, np.nan]
    raw[:, bll] = [0.9, np.nan, np.nan, np.nan, np.nan, np.nan, 0.2]
    times = np.arange(7) * 0.25
    out = MotorRules(mapping, 4.0, neutral).apply(raw, times)
    np.testing.assert_allclose(out[:, brl], [neutral[brl], 0.8, 0.8, 0.8, 0.6, 0.6, 0.6])
    rest = neutral[bll]
    np.testing.assert_allclose(out[:, bll], [0.9, 0.9 + (rest - 0.9) * 0.5, rest, rest, rest, rest, 0.2])


def test_a_lost_lid_follows_the_other_eyes_by_hand():
    """pair: where ERU's source is lost and ELU's seen, ERU moves from its neutral as ELU moves
    from its own (a blink stays a blink); where both are lost it eases from the last value it
    had, as ease does; ELU, which holds, does not follow ERU."""
    doc = {"format": "toonface.mapping/1", "markerset": "toon32",
           "motor": {"ERU": {"sources": [{"marker": "LID_R_UP", "axis": "y"}],
                             "loss": {"policy": "pair", "seconds": 0.5}},
                     "ELU": {"sources": [{"marker": "LID_L_UP", "axis": "y"}], "loss": {"policy": "hold"}}}}
    mapping = parse_mapping(doc)
    neutral = extended_neutral(standard_neutral()).copy()  # the 21 and the extras, as a live frame has them
    eru, elu = motor_index("ERU"), motor_index("ELU")
    neutral[eru], neutral[elu] = 0.7, 0.8
    raw = np.tile(neutral, (6, 1))
    raw[:, eru] = [np.nan, np.nan, np.nan, np.nan, 0.3, np.nan]
    raw[:, elu] = [0.75, 0.1, np.nan, np.nan, np.nan, 0.9]
    times = np.arange(6) * 0.25
    rules = MotorRules(mapping, 4.0, neutral)
    out = rules.apply(raw, times)
    np.testing.assert_allclose(out[:, eru], [0.65, 0.0, 0.0 + 0.7 * 0.5, 0.7, 0.3, 0.8])
    np.testing.assert_allclose(out[:, elu], [0.75, 0.1, 0.1, 0.1, 0.1, 0.9])
    rules.reset()
    np.testing.assert_allclose([rules.step(row, t) for row, t in zip(raw, times, strict=True)], out, atol=1e-12)


@pytest.mark.parametrize("motors, says", [
    ({"MB": {"sources": [{"marker": "LIP_LOW", "axis": "y"}], "loss": {"policy": "pair"}}},
     r"m.toml: motor.MB.loss.policy: expected a motor with one on the other side"),
    ({"ERU": {"sources": [{"marker": "LID_R_UP", "axis": "y"}], "loss": {"policy": "pair"}}},
     r"m.toml: motor.ERU.loss.policy: the pair policy follows motor ELU, which has no \[motor.ELU\] table")])
def test_the_pair_policy_needs_a_mapped_motor_on_the_other_side(motors, says):
    from common import InputError

    with pytest.raises(InputError, match=says):
        parse_mapping({"format": "toonface.mapping/1", "markerset": "toon32", "motor": motors}, "m.toml")


def test_trailing_mean_by_hand():
    values = np.array([[1.0], [3.0], [5.0], [7.0]])
    np.testing.assert_allclose(trailing_mean(values, 3)[:, 0], [1.0, 5 / 3, 3.0, 5.0])
    np.testing.assert_array_equal(trailing_mean(values, 1), values)


def test_the_tremble_phases_come_from_the_seed_and_every_motor_has_its_own():
    mapping = load_mapping("toon32")
    a, b, c = (MotorRules(mapping, RATE, standard_neutral(), seed) for seed in (1, 1, 2))
    np.testing.assert_array_equal(a.phases, b.phases)
    assert not np.allclose(a.phases, c.phases)
    assert len(set(np.round(a.phases[1], 6))) == N_CODES  # the 21 and the standard extras
    # HT's pair is the first two draws of the extras' stream, as when HT was the only extra
    np.testing.assert_array_equal(a.phases[:, 21], np.random.default_rng([1, 1]).uniform(0, 2 * np.pi, 2))
    np.testing.assert_array_equal(a.phases[:, :21], np.random.default_rng(1).uniform(0, 2 * np.pi, (2, 21)))


def test_a_pair_of_eyes_blinks_together_and_winks_cleanly_by_hand():
    """Openness is a share of each lid's neutral (0.8 and 0.6 here)."""
    neutral = np.array([0.8, 0.6])
    lids = np.array([[0.8 * 0.9, 0.6 * 1.0],   # jitter: both take the mean opening, 0.95
                     [0.8 * 0.05, 0.6 * 0.0],  # a blink: both 0.025
                     [0.8 * 0.8, 0.6 * 0.3],   # a wink: right opens to rest, left (0.3 < closed) shuts
                     [0.8 * 1.2, 0.6 * 0.6],   # a wink with the open eye wide: kept wide, left (0.6-0.35)/0.65
                     [np.nan, 0.3]])
    out = eyes_pair(lids, neutral, sync=0.25, closed=0.35)
    np.testing.assert_allclose(out[0], [0.8 * 0.95, 0.6 * 0.95])
    np.testing.assert_allclose(out[1], [0.8 * 0.025, 0.6 * 0.025])
    np.testing.assert_allclose(out[2], [0.8, 0.0])
    np.testing.assert_allclose(out[3], [0.8 * 1.2, 0.6 * (0.6 - 0.35) / 0.65])
    assert np.isnan(out[4, 0]) and out[4, 1] == 0.3  # a lost lid is left to its loss policy
    between = 0.25 + WINK_BLEND / 2  # half way from blinking together to winking
    half = eyes_pair(np.array([[0.8 * 1.0, 0.6 * (1.0 - between)]]), neutral, 0.25, 0.35)[0]
    together, wink = 1.0 - between / 2, ((1.0 - between) - 0.35) / 0.65
    np.testing.assert_allclose(half, [0.8 * (together + 1.0) / 2, 0.6 * (together + wink) / 2])


def test_an_eyes_table_names_two_lid_motors():
    from common import InputError

    doc = {"format": "toonface.mapping/1", "markerset": "toon32", "eyes": {"lids": ["ERU"]},
           "motor": {"ERU": {"sources": [{"marker": "LID_R_UP", "axis": "y"}]}}}
    with pytest.raises(InputError, match=r"m.toml: eyes.lids: expected two lid motors"):
        parse_mapping(doc, "m.toml")
    doc["eyes"] = {"lids": ["ERU", "ELU"], "closed": 1.0}
    with pytest.raises(InputError, match=r"m.toml: eyes.closed: expected a number"):
        parse_mapping(doc, "m.toml")


def test_a_made_up_lid_follows_the_other_eyes_measured_one_by_hand():
    """pair: where every source of ERU was made up by cleaning (a filled gap, a held marker) and
    ELU's was measured, ERU moves from its neutral as ELU moves from its own, as where lost;
    where both were made up, or ELU is lost, ERU keeps its own value; without ``made_up``
    nothing changes."""
    doc = {"format": "toonface.mapping/1", "markerset": "toon32",
           "motor": {"ERU": {"sources": [{"marker": "LID_R_UP", "axis": "y"}], "loss": {"policy": "pair"}},
                     "ELU": {"sources": [{"marker": "LID_L_UP", "axis": "y"}], "loss": {"policy": "pair"}}}}
    mapping = parse_mapping(doc)
    neutral = extended_neutral(standard_neutral()).copy()
    eru, elu = motor_index("ERU"), motor_index("ELU")
    neutral[eru], neutral[elu] = 0.7, 0.8
    raw = np.tile(neutral, (5, 1))
    raw[:, eru] = [0.7, 0.5, 0.45, 0.6, 0.65]  # the fill's blink: half as deep
    raw[:, elu] = [0.8, 0.1, 0.2, np.nan, 0.5]
    made_up = np.zeros(raw.shape, bool)
    made_up[1:5, eru] = True
    made_up[2, elu] = True  # both made up at frame 2
    times = np.arange(5) * 0.25
    rules = MotorRules(mapping, 4.0, neutral)
    out = rules.apply(raw, times, made_up)
    np.testing.assert_allclose(out[:, eru], [0.7, 0.0, 0.45, 0.6, 0.4])
    np.testing.assert_allclose(out[:, elu], [0.8, 0.1, 0.2, 0.7, 0.5])  # lost at 3: ERU's value, as before
    np.testing.assert_allclose(rules.apply(raw, times)[:, eru], raw[:, eru])
    rules.reset()
    stepped = [rules.step(row, t, up) for row, t, up in zip(raw, times, made_up, strict=True)]
    np.testing.assert_allclose(stepped, out, atol=1e-12)
