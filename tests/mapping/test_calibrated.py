"""Head ranges from a range-of-motion calibration (``normalise = "calibrated"``), and the second
synthetic performer and plain peer the fidelity bench measures against."""

import numpy as np
import pytest

from bench.peer import plain_pipeline, scores
from bench.second_performer import REST, SWEEP_END, perform
from mapping import calibrate, choose_mapping, load_profile, map_stabilised, prepare, save_profile
from toon import MOTOR_CODES


@pytest.fixture(scope="module")
def second():
    """The second performer without sensor faults, cleaned once."""
    take = perform(seconds=8, faults=False)
    mapping, markerset = choose_mapping(take.take)
    return take, mapping, markerset, prepare(take.take, markerset)


def test_a_range_of_motion_calibration_sets_the_head_s_range(second, tmp_path):
    """The performer's ±20° of pitch fills HV's 0..1 once the profile comes from a sweep; a
    profile from the take's own percentiles keeps 60 degrees a unit (±20° is two thirds)."""
    take, mapping, _, prepared = second
    full = calibrate(mapping, prepared, (0.0, 1.0), range_window=(1.0, SWEEP_END))
    own = calibrate(mapping, prepared, (0.0, 1.0))
    assert full.full_range and not own.full_range
    assert load_profile(save_profile(full, tmp_path / "p.toml")).full_range
    after, hv = take.take.times >= SWEEP_END, MOTOR_CODES.index("HV")
    travel = {}
    for name, profile in (("full", full), ("own", own)):
        values = map_stabilised(prepared.stable, prepared.columns, take.take.times, take.take.rate, mapping, profile,
                                take.rest).values
        travel[name] = np.ptp(values[after, hv]) / np.ptp(take.motors[after, hv])
    assert travel["full"] == pytest.approx(1.0, abs=0.1)
    assert travel["own"] == pytest.approx(40 / 60, abs=0.08)


def test_the_second_performer_has_its_own_face_and_rest(second):
    take, _, markerset, _ = second
    assert take.rest[MOTOR_CODES.index("BRL")] == REST["BRL"] == 0.3
    np.testing.assert_allclose(take.motors[: int(take.take.rate)], np.tile(take.rest, (int(take.take.rate), 1)))
    refs = [take.take.index(r) for r in markerset.head_reference]
    shape = take.take.positions[0, refs] - take.take.positions[0, refs].mean(axis=0)
    neutral = markerset.neutral[[markerset.labels.index(r) for r in markerset.head_reference]]
    assert np.sqrt(np.mean((np.linalg.norm(shape, axis=1) - np.linalg.norm(neutral - neutral.mean(0), axis=1)) ** 2)
                   ) > 2.0  # mm: not the marker set's head


def test_the_second_performer_is_seeded_and_faulted_as_documented():
    a, b = perform(seconds=4), perform(seconds=4)
    np.testing.assert_array_equal(a.take.positions, b.take.positions)
    missing = np.isnan(a.take.positions[..., 0]).mean()
    assert 0.10 <= missing < 0.11


def test_the_plain_peer_follows_a_straight_line_performer_closely():
    """On the project's own performer (markers on straight lines), without faults, the peer's
    straight normalisation is nearly exact: its errors on the second performer are that
    performer's, not the peer's."""
    from capture import synthesize
    from capture.performance import CALIBRATION_GROUPS, default_performance
    from toonface import truth_track

    syn = synthesize(rate=60.0, noise_mm=0.0, performance=default_performance(8, calibration=True, max_turn_deg=20))
    mapping, markerset = choose_mapping(syn.take)
    sweep_end = 1.0 + 1.2 * len(CALIBRATION_GROUPS)
    values = plain_pipeline(syn.take, mapping, markerset, (0.0, 1.0), (1.0, sweep_end))
    after = syn.take.times >= sweep_end
    result = scores(values[after], truth_track(syn).values[after])
    assert result["fitted_pct"] < 1.5 and min(result["r"].values()) > 0.97, result
