"""The synthetic performer: determinism, noise, its neutral, its forward model, the rigid fit."""

import numpy as np
import pytest

from capture import load_markerset, synthesize
from capture.performance import Cue, Performance
from capture.synthetic import DRIVES, NEUTRAL
from toon import MOTOR_CODES, motor_index


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
