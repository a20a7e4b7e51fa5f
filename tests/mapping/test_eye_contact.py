"""Eye contact (issue 64): a performer whose screen sits below the camera, calibrated live."""

import numpy as np
import pytest

from capture.performance import CODES, NEUTRAL
from capture.sources import take_source
from capture.synthetic import performed
from mapping.eye_contact import PUPILS, LiveEyeContact, screen_look
from toon import MOTOR_CODES, standard_neutral
from toonface.send import build_mapper

RATE = 30.0
#: A look 12 degrees below the lens: a 12 mm eyeball's pupil moves 12 sin(12 deg) = 2.49 mm down,
#: and the synthetic performer's pupil marker moves 8 mm per unit of PRV.
SCREEN_DROP = 12.0 * np.sin(np.radians(12.0)) / 8.0


def _performer(seconds: float = 40.0, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """True motors ``(n, 21)`` of a performer who rests looking into the lens (the first second),
    then looks at the middle of the screen (the second second), then at the screen with looks
    away now and then; and which frames look at the screen ``(n,)`` bool (settled there)."""
    rng = np.random.default_rng(seed)
    n = int(seconds * RATE)
    t = np.arange(n) / RATE
    motors = np.tile([NEUTRAL[c] for c in CODES], (n, 1))
    look = np.zeros((n, 2))
    look[t >= 1.0, 1] = -SCREEN_DROP  # the screen, from the second second on
    at_screen = t >= 1.2
    start = 3.0 + rng.uniform(0.0, 1.0)
    while start < seconds - 2.0:
        length = rng.uniform(0.6, 1.4)
        target = np.array([rng.uniform(-0.35, 0.35), rng.uniform(-0.3, 0.2)])
        ramp = np.clip(np.minimum(t - start, start + length - t) / 0.08, 0.0, 1.0)  # an 80 ms saccade each way
        look = look + ramp[:, None] * (target - look) * (ramp > 0)[:, None]
        at_screen &= ~((t > start - 0.1) & (t < start + length + 0.2))
        start += length + rng.uniform(1.5, 3.5)
    for side in "RL":
        motors[:, CODES.index(f"P{side}H")] = NEUTRAL[f"P{side}H"] + look[:, 0]
        motors[:, CODES.index(f"P{side}V")] = NEUTRAL[f"P{side}V"] + look[:, 1]
    blink = (t % 4.1 > 3.0) & (t % 4.1 < 3.2)  # blinks, which calibration must not read as looks
    for lid in ("ERU", "ELU"):
        motors[blink, CODES.index(lid)] = 0.05
    return motors, at_screen


def _mapped(motors: np.ndarray, eye_contact: bool) -> np.ndarray:
    """The motors the live mapper gives for the performer's take (``send``'s path), ``(n, 21)``."""
    source = take_source(performed(motors, RATE, seed=1).take)
    mapper = build_mapper(source, target_neutral=standard_neutral())
    said: list[str] = []
    if eye_contact:
        mapper.eye_contact = LiveEyeContact(standard_neutral(), after=0.0, say=said.append)
    out = np.array([mapper.step_frame(frame)[0] for frame in source.frames])
    if eye_contact:
        assert said[0].startswith("eye contact: look at the middle") and said[1].startswith("eye contact taken")
    return out


def _columns(codes: tuple[str, ...]) -> list[int]:
    return [MOTOR_CODES.index(code) for code in codes]


@pytest.mark.slow  # four seconds: make test runs it, test-fast does not
def test_screen_looks_centre_and_looks_away_follow():
    truth, at_screen = _performer()
    pupils = _columns(PUPILS)
    centre = standard_neutral()[pupils]
    calibrated, plain = _mapped(truth, True), _mapped(truth, False)
    off = np.abs(calibrated[at_screen][:, pupils] - centre).max(axis=1)
    assert np.mean(off <= 0.05) >= 0.9  # the goal: within 5 % of centre in 90 % of screen looks
    assert np.mean(np.abs(plain[at_screen][:, pupils] - centre).max(axis=1) <= 0.05) < 0.1  # and without it, not
    away = ~at_screen & (np.arange(len(truth)) / RATE > 3.0)
    true_pupils = np.array([truth[:, CODES.index(code)] for code in PUPILS]).T
    for k in range(len(PUPILS)):
        r = np.corrcoef(calibrated[away, pupils[k]], true_pupils[away, k])[0, 1]
        assert r >= 0.9, PUPILS[k]


def test_a_calibration_with_wandering_eyes_is_refused_and_the_last_kept():
    neutral = standard_neutral()
    said: list[str] = []
    contact = LiveEyeContact(neutral, seconds=0.5, after=0.0, say=said.append)
    steady = neutral.copy()
    steady[_columns(("PRV", "PLV"))] -= 0.3
    for k in range(20):
        contact.step(steady, k / RATE)
    assert contact.taken and np.allclose(contact.offsets, [0.0, -0.3, 0.0, -0.3])
    assert np.allclose(contact.step(steady, 1.0)[_columns(PUPILS)], neutral[_columns(PUPILS)])
    contact.begin()
    for k in range(20):
        wander = neutral.copy()
        wander[_columns(("PRH", "PLH"))] += 0.3 * np.sin(k / 2.0)
        contact.step(wander, 1.0 + k / RATE)
    assert said[-1].startswith("eye contact not taken: the eyes moved during it (PRH spread")
    assert np.allclose(contact.offsets, [0.0, -0.3, 0.0, -0.3])  # the last centre kept


@pytest.mark.parametrize(("lids", "why"), [(0.0, "the eyes were closed or unseen in 100 %"), (None, None)])
def test_screen_look_reads_open_eyes_only(lids, why):
    neutral = standard_neutral()
    frames = np.tile(neutral, (10, 1))
    frames[:, _columns(("PRH", "PLH"))] += 0.1
    frames[:3, _columns(("ERU", "ELU"))] = 0.02  # a blink: its frames are not read
    frames[:3, _columns(("PRH", "PLH"))] = 0.9
    if lids is not None:
        frames[:, _columns(("ERU", "ELU"))] = lids
    offsets, reason = screen_look(frames, neutral)
    if why is None:
        assert reason is None and np.allclose(offsets, [0.1, 0.0, 0.1, 0.0])
    else:
        assert reason.startswith(why) and not offsets.any()


@pytest.mark.slow  # send plays the take in real time (2.5 s): make test runs it
def test_send_says_eye_contact_taken_after_the_rest(tmp_path, capsys):
    from capture.takefile import save_take
    from toonface.cli import main

    truth, _ = _performer(seconds=2.5)
    take = save_take(performed(truth, RATE, seed=1).take, tmp_path / "look.npz")
    assert main(["send", str(take), "--to", "127.0.0.1:9", "--seconds", "2.4", "--eye-contact"]) == 0
    out = capsys.readouterr().out
    assert "note: eye contact: look at the middle of your screen for 1 s" in out
    assert "note: eye contact taken: the screen's middle is now the pupils' centre (they sat 0.3" in out
