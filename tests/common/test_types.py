"""Core types: Take, MotorTrack, the motor codes."""

import numpy as np
import pytest

from capture import Take
from common import Failure, InputError
from toon import MOTOR_CODES, MotorTrack, mirror_values, motor_index, standard_neutral


def test_motor_codes_in_toonface_order():
    expected = "BRL BRC BRM BLL BLC BLM ERU ERL ELU ELL PLH PLV PRH PRV MLH MLV MRH MRV MB HH HV"
    assert MOTOR_CODES == tuple(expected.split())
    assert motor_index("MB") == 18
    with pytest.raises(KeyError, match="XYZ"):
        motor_index("XYZ")


def test_take_valid_mask_and_frozen():
    pos = np.zeros((4, 2, 3))
    pos[1, 0, 2] = np.nan  # one coordinate missing hides the whole marker
    take = Take(pos, ("A", "B"), 100.0)
    assert take.valid.tolist() == [[True, True], [False, True], [True, True], [True, True]]
    assert np.isnan(take.positions[1, 0]).all()
    np.testing.assert_allclose(take.times, [0, 0.01, 0.02, 0.03])
    with pytest.raises(ValueError):
        take.positions[0, 0, 0] = 1.0  # read-only
    assert take.marker("B").shape == (4, 3)
    with pytest.raises(InputError, match='no marker "C"'):
        take.index("C")


@pytest.mark.parametrize("kwargs, message", [
    ({"positions": np.zeros((3, 2))}, "shape"),
    ({"labels": ("A",)}, "1 labels for 2 markers"),
    ({"labels": ("A", "A")}, "repeated"),
    ({"rate": 0.0}, "rate"),
    ({"rate": float("nan")}, "rate"),
    ({"times": np.array([0.0, 0.2, 0.1])}, "increasing"),
    ({"dims": 4}, "dims"),
    ({"positions": np.full((3, 2, 3), np.inf)}, "infinities"),
])
def test_take_rejects_bad_input(kwargs, message):
    args = {"positions": np.zeros((3, 2, 3)), "labels": ("A", "B"), "rate": 30.0, **kwargs}
    with pytest.raises(InputError, match=message):
        Take(**args)


def test_motor_track_validation():
    good = np.full((5, 21), 0.5)
    track = MotorTrack(good, 25.0)
    assert track.frames == 5 and track.duration == pytest.approx(0.2)
    np.testing.assert_allclose(track.column("HV"), 0.5)
    with pytest.raises(InputError, match=r"shape \(frames, 21\)"):
        MotorTrack(np.zeros((5, 20)), 25.0)
    bad = good.copy()
    bad[3, motor_index("MB")] = 1.5
    with pytest.raises(InputError, match="motor MB at frame 3 is 1.5"):
        MotorTrack(bad, 25.0)
    bad[3, motor_index("MB")] = np.nan
    with pytest.raises(InputError, match="not finite at frame 3, motor MB"):
        MotorTrack(bad, 25.0)
    with pytest.raises(InputError, match="confidence shape"):
        MotorTrack(good, 25.0, confidence=np.ones((4, 21)))


def test_from_columns_reorders():
    codes = list(reversed(MOTOR_CODES))
    values = np.tile(np.linspace(0, 1, 21), (2, 1))
    track = MotorTrack.from_columns(codes, values, 30.0)
    assert track.column("HV")[0] == 0.0 and track.column("BRL")[0] == 1.0
    with pytest.raises(InputError, match="missing"):
        MotorTrack.from_columns(codes[:-1], values[:, :-1], 30.0)


def test_mirror_swaps_sides_and_reflects_leftward_motors():
    neutral = standard_neutral()
    values = np.tile(neutral, (1, 1))
    values[0, motor_index("BRL")] = 0.9
    values[0, motor_index("PRH")] = 0.8
    values[0, motor_index("HH")] = 0.7
    out = mirror_values(values, neutral)
    assert out[0, motor_index("BLL")] == 0.9 and out[0, motor_index("BRL")] == neutral[motor_index("BLL")]
    assert out[0, motor_index("PLH")] == pytest.approx(0.2)  # PRH 0.8 -> left pupil, looking the other way
    assert out[0, motor_index("HH")] == pytest.approx(0.3)
    np.testing.assert_allclose(mirror_values(out, neutral), values)


def test_failure_is_falsy_and_says_why():
    f = Failure("no frames")
    assert not f and str(f) == "no frames"
