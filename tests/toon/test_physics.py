"""Physics drivers (issue 43): a spring's step response is the analytic one whatever the step,
chains feed drivers, and a state reached by different frame rates is the same."""

import numpy as np
import pytest

from toon.physics import Driver, DriverInput, physics_for

CODES = ("MB", "HH")
RESTS = np.array([0.1, 0.5])


def _spring(frequency=2.0, damping=0.2, swing=False, inputs=None, extra=()):
    inputs = inputs or (DriverInput(1.0, "MB"),)
    return physics_for((Driver("s", tuple(inputs), frequency, damping, "X", 1.0, swing), *extra), CODES, RESTS)


def _analytic(t, frequency, damping):
    """The unit step response of z'' + 2 d w z' + w^2 z = w^2 from rest."""
    w = 2 * np.pi * frequency
    wd = w * np.sqrt(1 - damping ** 2)
    return 1 - np.exp(-damping * w * t) * (np.cos(wd * t) + damping / np.sqrt(1 - damping ** 2) * np.sin(wd * t))


def _stepped(physics, times):
    """The output after a unit step at 0, the state advanced to each of ``times`` in turn."""
    physics.advance(0.0, np.array([0.1, 0.5]))  # at rest
    physics.advance(0.0, np.array([1.1, 0.5]))  # a unit step, at once
    shown = []
    for t in times:
        physics.advance(t, np.array([1.1, 0.5]))
        shown.append(physics.outputs(t, np.array([1.1, 0.5]))["X"])
    return np.array(shown)


@pytest.mark.parametrize("damping", [0.1, 0.3, 0.7])
@pytest.mark.parametrize("step", [1 / 30, 1 / 60, 0.01, 0.0037])
def test_a_step_gives_the_analytic_damped_response_whatever_the_step(damping, step):
    times = np.arange(1, int(3.0 / step)) * step
    np.testing.assert_allclose(_stepped(_spring(2.0, damping), times), _analytic(times, 2.0, damping), atol=1e-9)


@pytest.mark.parametrize("damping", [0.1, 0.3, 0.7])
def test_overshoot_period_and_settling_are_what_the_spring_is_set_to(damping):
    """The figures an animator tunes by, read off a 1 ms grid, within 2 % of the formulas."""
    fine = np.arange(1, 3001) * 1e-3
    curve = _stepped(_spring(2.0, damping), fine)
    wd = 2 * np.pi * 2.0 * np.sqrt(1 - damping ** 2)
    assert curve.max() - 1 == pytest.approx(np.exp(-damping * np.pi / np.sqrt(1 - damping ** 2)), rel=0.02)
    peaks = fine[1:-1][(curve[1:-1] > curve[:-2]) & (curve[1:-1] > curve[2:])]
    if len(peaks) > 1:
        assert peaks[1] - peaks[0] == pytest.approx(2 * np.pi / wd, rel=0.02)
    outside = fine[np.abs(curve - 1) > 0.02]
    envelope = np.log(0.02 * np.sqrt(1 - damping ** 2)) / (-damping * 2 * np.pi * 2.0)  # the bound it lies under
    assert outside.max() <= envelope * 1.02


def test_a_swing_is_what_the_spring_lags_behind_a_moving_base_and_starts_settled():
    physics = _spring(1.5, 0.3, swing=True, inputs=(DriverInput(-2.0, "HH"),))
    physics.advance(0.0, np.array([0.1, 0.8]))
    assert physics.outputs(0.0, np.array([0.1, 0.8]))["X"] == 0.0  # the first row: at rest, whatever it is
    physics.advance(0.1, np.array([0.1, 0.5]))  # a quick head turn back
    kicked = physics.outputs(0.1, np.array([0.1, 0.5]))["X"]
    assert kicked < -0.1  # the swing lags the turn (target moved +0.6; z still near where it was)
    for k in range(2, 400):
        physics.advance(k * 0.05, np.array([0.1, 0.5]))
    assert abs(physics.outputs(20.0, np.array([0.1, 0.5]))["X"]) < 1e-6  # and settles


def test_two_frame_rates_reach_the_same_state_at_shared_instants():
    """Samples at 60 Hz, drawn at 30 and at 60 frames a second (peeks between samples): the
    same outputs at the instants both draw, within 1e-9."""
    rng = np.random.default_rng(3)
    samples = np.column_stack([np.clip(0.1 + np.cumsum(rng.normal(0, 0.02, 181)), 0, 1), np.full(181, 0.5)])
    chain = Driver("tip", (DriverInput(0.5, driver="s"), DriverInput(0.2, "MB", of="velocity")), 3.0, 0.1, "Y")

    def drawn(fps):
        physics = _spring(2.0, 0.2, swing=True, extra=(chain,))
        out, k = {}, 0
        for frame in range(int(3 * fps) + 1):
            t = frame / fps
            while k < len(samples) and k / 60 <= t + 1e-12:
                physics.advance(k / 60, samples[k])
                k += 1
            row = samples[min(int(np.floor(t * 60)), 180)]
            out[round(t, 9)] = physics.outputs(t, row)
        return out

    slow, fast = drawn(30), drawn(60)
    for t, values in slow.items():
        for param in ("X", "Y"):
            assert values[param] == pytest.approx(fast[t][param], abs=1e-9)
    assert max(abs(v["Y"]) for v in fast.values()) > 1e-3  # the chain's end moved


@pytest.mark.parametrize("step", [1 / 30, 1 / 60, 0.0037])
def test_an_acceleration_input_kicks_the_spring_with_the_analytic_impulse_response(step):
    """A ramp that starts at 0 changes its velocity there: an acceleration impulse of that size,
    whose response is w^2 g I / wd exp(-d w t) sin(wd t), whatever the step."""
    f, d, g, speed = 1.5, 0.2, 0.3, 0.6
    physics = _spring(f, d, inputs=(DriverInput(g, "MB", of="acceleration"),))
    physics.advance(0.0, np.array([0.1, 0.5]))
    times = np.arange(1, int(2.0 / step)) * step
    shown = []
    for t in times:
        row = np.array([0.1 + speed * t, 0.5])
        physics.advance(t, row)
        shown.append(physics.outputs(t, row)["X"])
    w = 2 * np.pi * f
    wd = w * np.sqrt(1 - d ** 2)
    np.testing.assert_allclose(shown, w ** 2 * g * speed / wd * np.exp(-d * w * times) * np.sin(wd * times), atol=1e-9)


def test_the_transitions_exponential_runs_on_one_blas_thread(monkeypatch):
    """Issue 65: scipy's expm of the drivers' 8x8 system left scipy's OpenBLAS threads spinning a
    second core for as long as a render pass lasted (the physics' render cost read 0.75 in CPU
    seconds); it runs with one BLAS thread."""
    from threadpoolctl import threadpool_info

    import toon.physics

    seen = []
    exact = toon.physics.expm

    def watched(a):
        seen.append(max((lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"), default=1))
        return exact(a)

    monkeypatch.setattr(toon.physics, "expm", watched)
    physics = _spring()
    physics.advance(0.0, np.array([0.1, 0.5]))
    physics.advance(1 / 30, np.array([0.6, 0.5]))
    assert seen == [1]


def test_every_physics_shares_one_blas_controller(monkeypatch):
    """Issue 65: each render's drivers made threadpoolctl's controller anew (3-15 ms looking at
    every loaded library, 2 % of a 4 s render); one is made a process."""
    import threadpoolctl

    import toon.physics

    made = []
    real = threadpoolctl.ThreadpoolController

    def counted():
        made.append(1)
        return real()

    monkeypatch.setattr(threadpoolctl, "ThreadpoolController", counted)
    toon.physics.blas_threads.cache_clear()
    for _ in range(3):
        physics = _spring()
        physics.advance(0.0, np.array([0.1, 0.5]))
        physics.advance(1 / 30, np.array([0.6, 0.5]))
    toon.physics.blas_threads.cache_clear()  # the counting one is not kept for other tests
    assert made == [1]
