"""The synthetic performer and the default mapping: determinism, head pose, recovery of the truth."""

import numpy as np
import pytest

from capture import Take, load_markerset, synthesize
from capture.performance import Cue, Performance
from capture.synthetic import DRIVES, NEUTRAL, rotation_yaw_pitch
from common import InputError
from mapping import DefaultMapping, calibrate_neutral, head_pose
from mapping.default import CHANNELS
from mapping.stabilise import rigid_fit, yaw_pitch_degrees
from toon import MOTOR_CODES, motor_index
from toonface import map_take, truth_track


def test_synthetic_is_deterministic_and_seeded():
    a, b = synthesize(seconds=2, seed=7), synthesize(seconds=2, seed=7)
    np.testing.assert_array_equal(a.take.positions, b.take.positions)
    c = synthesize(seconds=2, seed=8)
    assert not np.array_equal(a.take.positions, c.take.positions)
    np.testing.assert_array_equal(a.motors, c.motors)  # the seed moves the noise, not the script
    assert a.take.positions.shape == (60, 32, 3) and a.motor_codes == MOTOR_CODES


def test_synthetic_noise_has_the_requested_spread():
    clean, noisy = synthesize(seconds=3, noise_mm=0.0), synthesize(seconds=3, noise_mm=0.5, seed=1)
    residual = noisy.take.positions - clean.take.positions
    assert residual.std() == pytest.approx(0.5, rel=0.05)


def test_first_second_is_the_markersets_neutral_up_to_sway():
    ms = load_markerset("toon32")
    syn = synthesize(seconds=1, noise_mm=0.0)
    assert syn.take.labels == ms.labels
    first = syn.take.positions[0]
    np.testing.assert_allclose(first - first.mean(0), ms.neutral - ms.neutral.mean(0), atol=1e-9)


def test_default_performance_opens_with_a_neutral_second():
    m = synthesize(seconds=10, noise_mm=0.0).motors
    np.testing.assert_allclose(m[:30], np.tile([NEUTRAL[c] for c in MOTOR_CODES], (30, 1)))
    assert (m[30:].std(axis=0) > 0.02).all()  # and every motor moves after it


def test_forward_model_moves_the_lid_by_its_gain():
    performance = Performance(2.0, (Cue("blink", 1.0, 0.4),))
    syn = synthesize(noise_mm=0.0, performance=performance)
    blink = np.argmin(syn.motors[:, motor_index("ERU")])
    assert syn.motors[blink, motor_index("ERU")] < 0.01
    idx = syn.take.labels.index
    lid = syn.take.positions[:, idx("LID_R_UP"), 1] - syn.take.positions[:, idx("FOREHEAD"), 1]
    gain = dict(((m, mk), g) for m, mk, _, g in DRIVES)[("ERU", "LID_R_UP")]
    expected = gain * (syn.motors[blink, motor_index("ERU")] - NEUTRAL["ERU"])
    assert lid[blink] - lid[0] == pytest.approx(expected, abs=1e-9)


def test_rigid_fit_recovers_a_known_rotation():
    rng = np.random.default_rng(0)
    src = rng.normal(0, 50, (5, 3))
    rot = rotation_yaw_pitch(np.radians([20.0, -10.0]), np.radians([5.0, 12.0]))
    tgt = np.einsum("fij,kj->fki", rot, src) + np.array([[1.0, 2.0, 3.0], [-4, 0, 9]])[:, None]
    tgt[1, 0] = np.nan  # one unseen marker still leaves 4
    r, t, ok = rigid_fit(src, tgt)
    assert ok.all()
    np.testing.assert_allclose(r, rot, atol=1e-9)
    yaw, pitch = yaw_pitch_degrees(r)
    np.testing.assert_allclose(yaw, [20, -10], atol=1e-9)
    np.testing.assert_allclose(pitch, [5, 12], atol=1e-9)


def test_mapping_recovers_the_true_motors_on_a_noiseless_take():
    syn = synthesize(seconds=10, noise_mm=0.0)
    track, truth = map_take(syn.take), truth_track(syn)
    error = np.abs(track.values - truth.values)
    assert error.max() < 1e-6, f"worst motor {MOTOR_CODES[np.argmax(error.max(0))]}: {error.max():.2e}"
    assert (track.confidence == 1).all()


def test_mapping_with_noise_stays_close():
    syn = synthesize(seconds=10, noise_mm=0.2, seed=4)
    error = np.abs(map_take(syn.take).values - truth_track(syn).values)
    assert error.mean() < 0.02 and np.percentile(error, 99) < 0.08


def test_unseen_marker_holds_its_last_value_with_zero_confidence():
    syn = synthesize(seconds=3, noise_mm=0.0)
    pos = syn.take.positions.copy()
    pos[50:60, syn.take.labels.index("LID_R_UP")] = np.nan
    track = map_take(Take(pos, syn.take.labels, syn.take.rate))
    eru = motor_index("ERU")
    assert (track.confidence[50:60, eru] == 0).all() and (track.confidence[:50, eru] == 1).all()
    np.testing.assert_allclose(track.values[50:60, eru], track.values[49, eru])


def test_calibration_failures_say_why():
    syn = synthesize(seconds=2, noise_mm=0.0)
    ms = load_markerset("toon32")
    empty = calibrate_neutral(syn.take, ms, (5.0, 6.0))
    assert not empty and "no frames in the neutral window 5-6 s" in str(empty)
    pos = syn.take.positions.copy()
    for ref in ms.head_reference[:3]:
        pos[:, syn.take.labels.index(ref)] = np.nan
    blind = Take(pos, syn.take.labels, syn.take.rate)
    assert not head_pose(blind, ms)
    with pytest.raises(InputError, match="cannot calibrate: fewer than 3 head reference markers"):
        DefaultMapping().fit(blind)
    few = Take(syn.take.positions[:, :5], syn.take.labels[:5], syn.take.rate)
    with pytest.raises(InputError, match="markers missing from the take"):
        DefaultMapping().fit(few)


def test_channels_cover_every_motor_once():
    assert sorted([c for c, *_ in CHANNELS] + ["HH", "HV"]) == sorted(MOTOR_CODES)
