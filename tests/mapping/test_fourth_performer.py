"""The fourth synthetic performer (bench.fourth_performer) does what its docstring says."""

import numpy as np
import pytest

from bench import fourth_performer as fp
from capture import load_take
from toon import MOTOR_CODES


@pytest.fixture(scope="module")
def clean():
    return fp.perform(seconds=4.0, seed=5, faults=False)


def test_the_sweep_moves_each_group_to_its_low_end_and_back_then_its_high_end(clean):
    times, motors = clean.take.times, clean.motors
    assert clean.take.rate == 120.0
    for g, group in enumerate(fp.GROUPS):
        start = fp.REST_SECONDS + g * fp.SWEEP_STEP
        low = np.argmin(np.abs(times - (start + 0.5)))
        between = np.argmin(np.abs(times - (start + 1.1)))
        high = np.argmin(np.abs(times - (start + 1.7)))
        for code in group:
            c = MOTOR_CODES.index(code)
            assert motors[low, c] == pytest.approx(0.0) and motors[high, c] == pytest.approx(1.0)
            assert motors[between, c] == pytest.approx(fp.REST[code])
        others = [MOTOR_CODES.index(c) for c in MOTOR_CODES if c not in group]
        np.testing.assert_allclose(motors[high, others], [fp.REST[MOTOR_CODES[c]] for c in others])


def test_a_pupil_turns_on_its_eyeball_and_a_brow_slides_over_the_forehead():
    from bench.fourth_performer import EYEBALL_MM, FOREHEAD_MM, _face, _placed
    from capture import load_markerset

    ms = load_markerset("toon32")
    face = _placed(ms.neutral, ms.labels, np.random.default_rng(1))
    motors = np.tile([fp.REST[c] for c in MOTOR_CODES], (50, 1))
    sweep = np.linspace(0, 1, 50)
    for code in ("PLH", "PLV", "BLC"):
        motors[:, MOTOR_CODES.index(code)] = sweep
    local = _face(face, ms.labels, motors)
    pupil, brow = ms.labels.index("PUPIL_L"), ms.labels.index("BROW_L_CEN")
    centre = face[pupil] - [0, 0, EYEBALL_MM]
    np.testing.assert_allclose(np.linalg.norm(local[:, pupil] - centre, axis=1), EYEBALL_MM)
    assert np.ptp(local[:, pupil, 0]) > 8 and np.ptp(local[:, pupil, 2]) > 0.5  # across, and back on the arc
    behind = face[brow] - [0, 0, FOREHEAD_MM]
    np.testing.assert_allclose(np.linalg.norm(local[:, brow] - behind, axis=1), FOREHEAD_MM)
    assert local[-1, brow, 1] - local[0, brow, 1] == pytest.approx(17.0, abs=0.3)  # 4 down, 13 up, on the arc


def test_the_sensor_loses_mislabels_and_drops_a_marker_as_capture_does():
    performed = fp.perform(seconds=8.0, seed=5)
    take = performed.take
    missing = np.isnan(take.positions).any(axis=2)
    assert 0.08 <= missing.mean() < 0.2
    cheek = take.labels.index("CHEEK_L")
    assert missing[-int(fp.RATE):, cheek].all()  # fallen off
    yaw = 80.0 * (performed.motors[:, MOTOR_CODES.index("HH")] - 0.5)
    assert missing[yaw > 30.0, take.labels.index("TEMPLE_L")].all()


def test_the_take_written_in_metres_reads_back_as_the_same_millimetres(clean, tmp_path):
    path = fp.write_in_metres(clean.take, tmp_path / "take.trc")
    assert "\tm\t" in path.read_text(encoding="utf-8").split("\n")[2]
    back = load_take(path)
    assert back.meta["units_in_file"] == "m"
    np.testing.assert_allclose(back.positions, clean.take.positions, atol=1e-9)
