"""The per-frame rules exist once: offline mapping and the live sender give the same motors."""

import numpy as np
import pytest

from capture import load_markerset, synthesize
from capture.performance import default_performance
from mapping import CleanSettings, Stabilised, calibrate, load_mapping, map_stabilised, parse_mapping, prepare
from mapping.mapper import marker_quality
from mapping.rules import MotorRules, trailing_mean
from mapping.stepwise import LiveMapper
from toon import MOTOR_CODES, motor_index, standard_neutral

RATE = 60.0

#: Every rule of the mapping language switched on somewhere.
EVERYTHING = """
format = "toonface.mapping/1"
name = "everything"
markerset = "toon32"
mirror = true
symmetric = [["BRL", "BLL"]]

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
gain = 1.4
offset = 0.05
delay = 0.05
[motor.ERU]
sources = [{ marker = "LID_R_UP", axis = "y" }]
normalise = "scale"
scale = 8.0
invert = true
loss = { policy = "hold" }
[motor.ELU]
sources = [{ marker = "LID_L_UP", axis = "y", invert = true }]
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
    long losses of a brow, a lid and the lips cut into it."""
    syn = synthesize(seconds=8, rate=RATE, performance=default_performance(8), seed=3)
    take = syn.take
    positions = take.positions.copy()
    for label, frames in (("BROW_R_LAT", slice(200, 260)), ("LID_R_UP", slice(100, 180)),
                          ("LIP_LOW", slice(300, 420)), ("BROW_L_LAT", slice(0, 40))):
        positions[frames, take.index(label)] = np.nan
    take = type(take)(positions, take.labels, take.rate, take.times, take.dims, take.meta)
    mapping = parse_mapping(__import__("tomllib").loads(EVERYTHING))
    prepared = prepare(take, load_markerset("toon32"), CleanSettings(max_gap_seconds=0.0))
    profile = calibrate(mapping, prepared)
    return mapping, prepared, profile


def test_live_and_offline_map_the_same_cleaned_frames_equally_with_every_rule_on(cleaned):
    mapping, prepared, profile = cleaned
    stable, times = prepared.stable, prepared.take.times
    neutral = standard_neutral()
    offline = map_stabilised(stable, prepared.columns, times, RATE, mapping, profile, neutral, seed=7)
    live = LiveMapper(mapping, prepared.markerset, profile, prepared.take.labels, RATE, neutral, rest_seconds=0.0,
                      seed=7)
    quality = marker_quality(stable.local)
    stepped = np.array([live.map_frame(Stabilised(stable.local[f:f + 1], stable.rotation[f:f + 1],
                                                  stable.translation[f:f + 1], stable.ok[f:f + 1], stable.reference),
                                       quality[f:f + 1], float(times[f]))[0] for f in range(len(times))])
    assert offline.meta["lost_frames"] > 200  # the losses are there, so the loss policies ran
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


def test_trailing_mean_by_hand():
    values = np.array([[1.0], [3.0], [5.0], [7.0]])
    np.testing.assert_allclose(trailing_mean(values, 3)[:, 0], [1.0, 5 / 3, 3.0, 5.0])
    np.testing.assert_array_equal(trailing_mean(values, 1), values)


def test_the_tremble_phases_come_from_the_seed_and_every_motor_has_its_own():
    mapping = load_mapping("toon32")
    a, b, c = (MotorRules(mapping, RATE, standard_neutral(), seed) for seed in (1, 1, 2))
    np.testing.assert_array_equal(a.phases, b.phases)
    assert not np.allclose(a.phases, c.phases)
    assert len(set(np.round(a.phases[1], 6))) == len(MOTOR_CODES)
