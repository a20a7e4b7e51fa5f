"""The mapping file: validation errors naming the field, and each operator against hand values."""

import copy

import numpy as np
import pytest

from common import InputError
from mapping import load_mapping, map_stabilised, parse_mapping
from mapping.profile import Profile, SourceRange
from mapping.stabilise import Stabilised
from toon import motor_index, standard_neutral

BASE = {"format": "toonface.mapping/1", "name": "t", "markerset": "toon32",
        "motor": {"ERU": {"sources": [{"marker": "LID_R_UP", "axis": "y"}]}}}


def _doc(**motor):
    doc = copy.deepcopy(BASE)
    doc["motor"]["ERU"].update(motor)
    return doc


@pytest.mark.parametrize("change, field, message", [
    ({"format": "x"}, "format", "unsupported format"),
    ({"colour": 1}, "colour", "unknown field (known: copy_side, description"),
    ({"motor": {"XYZ": {"sources": []}}}, "motor.XYZ", "expected one of BRL, BRC"),
    ({"motor": {"ERU": {"sources": []}}}, "motor.ERU.sources", "at least one source"),
    ({"motor": {"ERU": {"sources": [{"marker": "A", "axis": "w"}]}}}, "motor.ERU.sources[0].axis",
     "expected one of x, y, z, got 'w'"),
    ({"motor": {"ERU": {"sources": [{"distance": ["A"]}]}}}, "motor.ERU.sources[0].distance", "expected 2 marker"),
    ({"motor": {"ERU": {"sources": [{"marker": "A", "head": "yaw"}]}}}, "motor.ERU.sources[0]", "exactly one of"),
    ({"symmetric": [["BRL", "QQQ"]]}, "symmetric[0]", "got 'QQQ'"),
    ({"style": {"sharpen": {"steps": 1}}}, "style.sharpen.steps", "integer of at least 2, got 1"),
])
def test_bad_top_level_and_source_fields_are_named(change, field, message):
    doc = {**copy.deepcopy(BASE), **change}
    with pytest.raises(InputError) as err:
        parse_mapping(doc, "m.toml")
    assert str(err.value).startswith(f"m.toml: {field}: ") and message in str(err.value)


@pytest.mark.parametrize("motor, field, message", [
    ({"combine": "median"}, "motor.ERU.combine", "expected one of max, mean, min, weighted"),
    ({"gain": "big"}, "motor.ERU.gain", "expected a number"),
    ({"curve": [[0, 0], [0, 1]]}, "motor.ERU.curve", "increasing inputs"),
    ({"limits": [0.5, 0.2]}, "motor.ERU.limits", "0 <= low < high <= 1"),
    ({"filter": {"kind": "kalman"}}, "motor.ERU.filter.kind", "one-euro"),
    ({"filter": {"kind": "one-euro", "cutoff": 2}}, "motor.ERU.filter.cutoff",
     "unknown field (known: beta, d_cutoff, kind, min_cutoff)"),
    ({"max_speed": -1}, "motor.ERU.max_speed", "expected a number of at least 0, got -1"),
    ({"loss": {"policy": "panic"}}, "motor.ERU.loss.policy", "hold, ease, idle"),
    ({"loss": {"policy": "ease", "made_up": False}}, "motor.ERU.loss.made_up", "is for the pair policy"),
    ({"loss": {"policy": "pair", "made_up": "no"}}, "motor.ERU.loss.made_up", "expected true or false"),
    ({"loss": {"policy": "ease", "near": ["BRC"]}}, "motor.ERU.loss.near", "near is for the pair policy"),
    ({"loss": {"policy": "pair", "near": "BRC"}}, "motor.ERU.loss.near", "expected a list of names"),
    ({"loss": {"policy": "pair", "near": ["ELU"]}}, "motor.ERU.loss.near[0]", "other than this one and its partner"),
])
def test_bad_motor_fields_are_named(motor, field, message):
    with pytest.raises(InputError) as err:
        parse_mapping(_doc(**motor), "m.toml")
    assert str(err.value).startswith(f"m.toml: {field}: ") and message in str(err.value)


def test_every_preset_loads():
    for name in ("toon32", "animface41", "gluedots16"):
        assert load_mapping(name).markerset == name


def _run(doc, lid_y, rate=10.0, profile=None):
    """Map a one-marker 'take' whose LID_R_UP moves along y as ``lid_y`` (mm from rest)."""
    frames = len(lid_y)
    local = np.zeros((frames, 1, 3))
    local[:, 0, 1] = lid_y
    stable = Stabilised(local, np.tile(np.eye(3), (frames, 1, 1)), np.zeros((frames, 3)), np.ones(frames, bool),
                        np.zeros((3, 3)))
    profile = profile or Profile("toon32", {"LID_R_UP.y": SourceRange(0.0, -8.0, 2.0)}, np.eye(3))
    times = np.arange(frames) / rate
    return map_stabilised(stable, {"LID_R_UP": 0}, times, rate, parse_mapping(doc), profile)


def test_profile_normalisation_gain_offset_invert_and_clamps():
    eru = motor_index("ERU")  # neutral 0.8: the performer's -8..0..2 mm fills 0..0.8..1
    values = _run(_doc(), [-8.0, -4.0, 0.0, 1.0, 2.0, 4.0]).values[:, eru]
    np.testing.assert_allclose(values, [0.0, 0.4, 0.8, 0.9, 1.0, 1.0])
    gained = _run(_doc(gain=2.0, offset=-0.1), [-2.0, 0.0, 0.5]).values[:, eru]
    np.testing.assert_allclose(gained, [0.8 - 0.4 - 0.1, 0.7, 0.8 + 0.1 - 0.1])
    inverted = _run(_doc(invert=True), [2.0, -8.0]).values[:, eru]  # +1 of range -> down by 0.8
    np.testing.assert_allclose(inverted, [0.0, 1.0])
    soft = _run(_doc(clamp="soft", gain=3.0), [0.0, 2.0]).values[:, eru]
    assert soft[0] == pytest.approx(0.8) and 0.9 < soft[1] < 1.0  # eases into the limit, never reaches it


def test_curve_scale_and_combine():
    eru = motor_index("ERU")
    curved = _run(_doc(curve=[[0, 0], [0.8, 0.5], [1, 1]]), [0.0, 1.0]).values[:, eru]
    np.testing.assert_allclose(curved, [0.5, 0.75])
    scaled = _run(_doc(normalise="scale", scale=20.0), [0.0, 2.0, -4.0]).values[:, eru]
    np.testing.assert_allclose(scaled, [0.8, 0.9, 0.6])
    both = [{"marker": "LID_R_UP", "axis": "y"}, {"marker": "LID_R_UP", "axis": "y", "invert": True, "weight": 3}]
    # at +1 mm the first source is +0.5 of the upper range, the inverted one -0.5;
    # weighted: 1 * 0.5 + 3 * -0.5 = -1, the whole way down from 0.8
    for combine, expected in (("max", 0.9), ("min", 0.4), ("mean", 0.8), ("weighted", 0.0)):
        assert _run(_doc(sources=both, combine=combine), [1.0]).values[0, eru] == pytest.approx(expected), combine


def test_speed_limit_delay_and_loss_policies():
    eru = motor_index("ERU")
    stepped = _run(_doc(max_speed=1.0), [-8.0] * 2 + [0.0] * 10).values[:, eru]  # 0.1 per frame at 10 Hz
    np.testing.assert_allclose(stepped[:12], [0, 0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.8, 0.8], atol=1e-12)
    delayed = _run(_doc(delay=0.2), [-8.0, -8.0, 0.0, 0.0, 0.0]).values[:, eru]
    np.testing.assert_allclose(delayed, [0, 0, 0, 0, 0.8])
    lost = [-8.0, np.nan, np.nan, np.nan, np.nan, np.nan]
    np.testing.assert_allclose(_run(_doc(), lost).values[:, eru], 0.0)  # hold
    eased = _run(_doc(loss={"policy": "ease", "seconds": 0.4}), lost)
    np.testing.assert_allclose(eased.values[:, eru], [0, 0.2, 0.4, 0.6, 0.8, 0.8])
    assert eased.confidence[:, eru].tolist() == [1, 0, 0, 0, 0, 0]


def test_across_motor_operators_and_style():
    eru, elu = motor_index("ERU"), motor_index("ELU")
    copied = _run({**_doc(), "copy_side": "right"}, [-8.0]).values[0]
    assert copied[eru] == copied[elu] == 0.0
    mirrored = _run({**_doc(), "mirror": True}, [-8.0]).values[0]
    assert mirrored[elu] == 0.0 and mirrored[eru] == standard_neutral()[eru]
    paired = _run({**_doc(), "symmetric": [["ERU", "ELU"]]}, [-8.0]).values[0]
    assert paired[eru] == paired[elu] == pytest.approx(0.4)
    sharp = _run({**_doc(), "style": {"sharpen": {"steps": 3, "motors": ["ERU"]}}}, [-8.0, -5.0, -1.0]).values[:, eru]
    np.testing.assert_allclose(sharp, [0.0, 0.5, 0.5])  # 0, 0.3, 0.7 snapped to 0, 0.5, 1 steps
    slow = _run({**_doc(), "style": {"time_scale": 2.0}}, [-8.0, 0.0, 2.0])
    assert slow.frames == 6
    np.testing.assert_allclose(slow.values[:, eru], [0.0, 0.4, 0.8, 0.9, 1.0, 1.0])
    shaky = _run({**_doc(), "style": {"tremble": {"amplitude": 0.05, "frequency": 2.5, "motors": ["ERU"]}}},
                 [0.0] * 40).values[:, eru]
    # a sine of amplitude 0.05 about neutral: over whole periods its RMS is 0.05 / sqrt(2), its mean 0
    assert np.sqrt(np.mean((shaky - 0.8) ** 2)) == pytest.approx(0.05 / np.sqrt(2))
    assert np.mean(shaky) == pytest.approx(0.8)
