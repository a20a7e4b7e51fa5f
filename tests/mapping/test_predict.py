"""Short-horizon prediction: the sparse motion model learns known dynamics and beats hold on them."""

import numpy as np
import pytest

from mapping.predict import MotionModel, forecast, trailing_line


def _oscillator(seconds=20.0, rate=60.0):
    """x'' = -16 (x - 0.5) - 0.2 x', let go from 0.9 (a slowly dying swing about rest)."""
    dt = 1 / rate
    t = np.arange(int(seconds * rate)) * dt
    x, v = np.empty_like(t), 0.0
    pos = 0.9
    for i in range(len(t)):
        a = -16 * (pos - 0.5) - 0.2 * v
        v += a * dt
        pos += v * dt
        x[i] = pos
    return x[:, None], t


def test_the_model_finds_the_oscillators_law():
    x, t = _oscillator()
    model = MotionModel(degree=1, threshold=0.05).fit(x, t)
    state = np.array([[0.7, 0.3], [0.5, 0.0]])
    accel = model.models_[0].predict(state)[:, 1]
    np.testing.assert_allclose(accel, [-16 * 0.2 - 0.2 * 0.3, 0.0], atol=0.1)


def test_forecasts_on_learnt_dynamics_beat_hold_and_a_straight_line():
    x, t = _oscillator(40.0)
    model = MotionModel().fit(x[:1200], t[:1200])
    test, tt = x[1200:], t[1200:]
    ahead = 6  # 100 ms
    errors = {m: np.sqrt(np.mean((forecast(test, tt, 0.1, m, model)[:-ahead] - test[ahead:]) ** 2))
              for m in ("hold", "velocity", "sindy")}
    assert errors["sindy"] < 0.5 * errors["hold"] and errors["sindy"] < errors["velocity"]


def test_trailing_line_is_exact_on_a_line_and_forecast_checks_its_method():
    t = np.arange(10) / 10
    level, slope = trailing_line(np.column_stack([2 + 3 * t]), t)
    np.testing.assert_allclose(level[:, 0], 2 + 3 * t)
    np.testing.assert_allclose(slope[1:, 0], 3.0)
    np.testing.assert_array_equal(forecast(level, t, 0.1, "hold"), level)
    with pytest.raises(ValueError, match="unknown method"):
        forecast(level, t, 0.1, "psychic")
    with pytest.raises(ValueError, match="needs a fitted MotionModel"):
        forecast(level, t, 0.1, "sindy")
