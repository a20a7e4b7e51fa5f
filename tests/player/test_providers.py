"""Who moves a motor: the idle face, tracking, motions and overrides mixed on an injected clock."""

import numpy as np
import pytest

from common import InputError
from player.animator import Animator, Move
from player.commands import Commands
from player.providers import Idle, IdleSettings, LayerSettings, Mixer, Providers, load_providers
from toon import load_expressions, load_face, motor_index

STEP = 1 / 50


@pytest.fixture
def face():
    return load_face("classic")


def _times(seconds: float, start: float = 0.0):
    return [start + k * STEP for k in range(int(round(seconds / STEP)))]


@pytest.mark.slow  # thirteen seconds of idle face: make test runs it, test-fast does not
def test_the_idle_face_blinks_at_its_rate_breathes_and_looks_about(face):
    """The idle face is the life layer in silence: blinks at the rate asked, never two within a
    second, breathing, fixations with quick saccades, the eyes together, the same with one seed."""
    n = face.neutral()
    idle = Idle(n, IdleSettings(blink_per_minute=20, seed=3))
    frames = np.array([idle.values(t) for t in _times(600)])  # ten minutes
    assert 170 <= len(idle.blinks) <= 230  # about 20 a minute
    assert np.diff(idle.blinks).min() >= 1.0
    eru = frames[:, motor_index("ERU")]
    assert eru.min() == pytest.approx(0.0, abs=0.05) and np.median(eru) == pytest.approx(n[motor_index("ERU")])
    breathing = Idle(n, IdleSettings(sway_amount=0.0))  # (the head's slow sway, rise and fall off)
    hv = np.array([breathing.values(t) for t in _times(60)])[:, motor_index("HV")] - n[motor_index("HV")]
    assert hv.max() == pytest.approx(0.008, abs=1e-3) and hv.min() == pytest.approx(-0.008, abs=1e-3)
    prh = frames[:, motor_index("PRH")] - n[motor_index("PRH")]
    assert 0.06 < np.abs(prh).max() <= 0.2  # near the viewer, and now and then further off
    moving = np.abs(np.diff(prh)) > 1e-6
    assert 0.02 < moving.mean() < 0.15  # fixations held, quick saccades between
    np.testing.assert_array_equal(frames[:, motor_index("PRH")], frames[:, motor_index("PLH")])  # eyes together
    hh = frames[:, motor_index("HH")] - n[motor_index("HH")]
    assert 0.005 < hh.std() < 0.02  # a slow sway
    again = Idle(n, IdleSettings(blink_per_minute=20, seed=3))
    np.testing.assert_array_equal([again.values(t) for t in _times(600)], frames)  # seeded


def test_a_providers_file_with_the_old_blink_randomness_is_refused_in_a_line(tmp_path):
    path = tmp_path / "providers.toml"
    path.write_text('format = "toonface.providers/1"\n[idle]\nblink_randomness = 0.4\n')
    with pytest.raises(InputError, match="blink_randomness is no longer read"):
        load_providers(path)


def test_lost_tracking_passes_to_idle_smoothly_and_comes_back(face):
    n = face.neutral()
    seen = {"confidence": np.ones(21), "age": 0.0}
    tracked = n.copy()
    tracked[motor_index("MB")] = 0.9
    settings = Providers(idle=IdleSettings(blink_per_minute=0, breathing_amount=0, saccade_amount=0, sway_amount=0),
                         tracking=LayerSettings(fade=0.3))
    mixer = Mixer(n, settings, tracking=lambda: (tracked, seen["confidence"], seen["age"]))
    mb = motor_index("MB")
    shown = [mixer.step(t)[mb] for t in _times(1.0)]
    assert shown[-1] == pytest.approx(0.9) and mixer.who()[mb] == "tracking"
    seen["confidence"] = np.where(np.arange(21) == mb, 0.0, 1.0)  # the mouth's markers are lost
    lost = [mixer.step(t)[mb] for t in _times(0.5, 1.0)]
    steps = np.abs(np.diff([shown[-1], *lost]))
    assert steps.max() <= (0.9 - n[mb]) * STEP / 0.3 + 1e-9  # no jump: at most the fade's pace
    assert lost[-1] == pytest.approx(n[mb]) and mixer.who()[mb] == "idle"
    fading = [n[mb] + (0.9 - n[mb]) * (1 - (k + 1) * STEP / 0.3) for k in range(14)]
    np.testing.assert_allclose(lost[:14], fading)  # a straight fade over 0.3 s, by hand
    seen["confidence"] = np.ones(21)
    back = [mixer.step(t)[mb] for t in _times(0.5, 1.5)]
    assert back[-1] == pytest.approx(0.9) and np.abs(np.diff(back)).max() <= (0.9 - n[mb]) * STEP / 0.3 + 1e-9
    seen["age"] = 0.5  # no frame for longer than lost_after: every motor passes to idle
    [mixer.step(t) for t in _times(0.5, 2.0)]
    assert set(mixer.who()) == {"idle"}


def test_an_expression_over_tracking_blends_on_top_then_releases(face):
    n = face.neutral()
    animator = Animator(n, STEP)
    tracked = n.copy()
    tracked[motor_index("MB")] = 0.6
    still = IdleSettings(blink_per_minute=0, breathing_amount=0, saccade_amount=0, sway_amount=0)
    mixer = Mixer(n, Providers(idle=still),
                  tracking=lambda: (tracked, np.ones(21), 0.0),
                  motions=lambda: (animator.values(), animator.active()))
    mrv, mb = motor_index("MRV"), motor_index("MB")
    for t in _times(0.5):
        animator.tick(t)
        mixer.step(t)
    animator.command([Move("MRV", 1.0, 1.0)])  # a smile's corner, over the tracked face
    after = []
    for t in _times(0.6, 0.5):
        animator.tick(t)
        mixer.step(t)
    # faded in (0.25 s): the corner is the motion's, the mouth still the performer's
    assert mixer.shown[mrv] == pytest.approx(animator.values()[mrv]) and animator.values()[mrv] > 0.7
    assert mixer.who()[mrv] == "motions" and mixer.shown[mb] == pytest.approx(0.6) and mixer.who()[mb] == "tracking"
    for t in _times(1.4, 1.1):  # the move ends at 1.5 s: then it releases to tracking, at the fade's pace
        animator.tick(t)
        animator.tick(t)
        after.append(mixer.step(t))
    assert after[-1][mrv] == pytest.approx(n[mrv]) and mixer.who()[mrv] == "tracking"
    assert np.abs(np.diff([row[mrv] for row in after])).max() <= (1.0 - n[mrv]) * STEP / 0.25 + 1e-9


def test_alone_a_move_holds_where_it_put_a_motor_and_a_blink_gives_the_lids_back_to_idle(face):
    n = face.neutral()
    animator = Animator(n, STEP)
    mixer = Mixer(n, Providers(), motions=lambda: (animator.values(), animator.active()))
    commands = Commands(animator, n, load_expressions(), clock=lambda: 0.0, mixer=mixer)
    assert commands.handle("MB 0.8 100") == "ok moving 1"
    for t in _times(2.0):
        animator.tick(t)
        mixer.step(t)
    assert mixer.shown[motor_index("MB")] == pytest.approx(0.8)  # held long after the move
    reply = commands.handle("state")
    assert "MB=0.800" in reply and "motions=MB" in reply.split(" by ")[1] and "idle=" in reply
    assert commands.handle("hold ERU 0.1 ELU 0.1") == "ok holding 2"
    for t in _times(0.5, 2.0):
        animator.tick(t)
        mixer.step(t)
    assert mixer.shown[motor_index("ERU")] == pytest.approx(0.1) and mixer.who()[motor_index("ELU")] == "manual"
    assert commands.handle("release") == "ok released all"
    assert commands.handle("hold XX 1").startswith("error: unknown motor")
    assert commands.handle("hold MB").startswith("error: hold needs")
    assert commands.handle("hold ELU 0 elu 1") == "error: a motor is named twice; give each motor one value per command"
    for t in _times(0.5, 2.5):
        animator.tick(t)
        mixer.step(t)
    assert mixer.who()[motor_index("ERU")] == "idle"


def test_the_providers_file_sets_every_layer_and_names_a_bad_field(tmp_path):
    good = tmp_path / "providers.toml"
    good.write_text('format = "toonface.providers/1"\n[idle]\nblink_per_minute = 8\nenabled = true\n'
                    '[tracking]\nfade = 0.5\nlost_after = 1.0\n[manual]\nweight = 0.5\n')
    settings = load_providers(good)
    assert settings.idle.blink_per_minute == 8 and settings.idle.breathing_seconds == 4.0
    assert settings.tracking.fade == 0.5 and settings.lost_after == 1.0 and settings.manual.weight == 0.5
    assert load_providers(None) == Providers()
    bad = tmp_path / "bad.toml"
    bad.write_text('format = "toonface.providers/1"\n[tracking]\nfade = -1\n')
    with pytest.raises(InputError, match=r"bad\.toml.*tracking\.fade"):
        load_providers(bad)
    bad.write_text('format = "toonface.providers/1"\n[idle]\nblinks = 3\n')
    with pytest.raises(InputError, match="blinks"):
        load_providers(bad)
