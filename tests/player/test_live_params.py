"""The live player and its command socket with a face's parameters beyond the 21 (issue 42):
``HT 0.8 300`` tilts the head as ``MB 1 300`` opens the mouth, and a track's or a stream's
parameters are drawn and told on."""

import numpy as np
import pytest

from player.animator import Animator, FakeClock
from player.commands import Commands
from player.live import LiveSettings, run_live
from toon import MotorTrack, load_expressions, load_face, motor_index


@pytest.fixture
def commands():
    face = load_face("wizard")  # HT, UL, JS, PERK, BEARD
    rests = face.extra_neutral()
    extras = Animator(np.array([rests[c] for c in face.extra_codes]), 0.1, face.extra_codes)
    animator = Animator(face.neutral(), loop_time=0.1)
    return Commands(animator, face.neutral(), load_expressions(), FakeClock(), extras=extras), animator, extras


def test_a_parameter_moves_as_a_motor_does_by_its_code(commands):
    cmd, animator, extras = commands
    assert cmd.handle("ht 0.8 300 MB 1 100") == "ok moving 2"
    for _ in range(3):
        extras.tick()
        animator.tick()
    assert extras.values()[extras.index("HT")] == pytest.approx(0.8)
    assert animator.values()[motor_index("MB")] == pytest.approx(1.0)
    assert not extras.busy()  # the slices ran out on the third loop
    state = cmd.handle("state")
    assert state.startswith("ok BRL=") and state.endswith("HT=0.800 UL=0.000 JS=0.500 PERK=0.000 BEARD=0.500")
    error = cmd.handle("TAIL 1 100")
    assert error.startswith("error: unknown motor 'TAIL'") and "parameters: HT UL JS PERK BEARD" in error
    assert cmd.handle("CP 1 100").startswith("error: unknown motor 'CP'")  # the wizard has no cheeks to puff


def test_a_track_s_parameters_are_drawn_and_told_loop_by_loop():
    face = load_face("wizard")
    values = np.repeat(face.neutral()[None], 11, 0)
    ht = np.linspace(0.5, 1.0, 11)[:, None]
    track = MotorTrack(values, 10.0, extra_codes=("HT",), extra=ht)
    told: list[dict] = []
    clock = FakeClock()
    settings = LiveSettings(loop_time=0.1, size=(32, 32), samples=1, tcp=None, track=track, repeat=False,
                            seconds=1.0)
    settings.shown.append(lambda t, v, extra=None: told.append(dict(extra or {})))
    run_live(face, settings, clock=clock, sleep=clock.sleep)
    assert [round(x["HT"], 3) for x in told[:6]] == [0.5, 0.55, 0.6, 0.65, 0.7, 0.75]
    assert all(x["PERK"] == 0.0 and x["JS"] == 0.5 for x in told)  # the rest: nothing moves them


def test_an_expression_moves_the_parameters_it_names_and_rests_the_others(commands):
    cmd, animator, extras = commands
    assert load_expressions()["disgust"].extra == {"UL": 0.8}
    assert cmd.handle("play surprise 200") == "ok playing surprise"
    for k in range(4):
        extras.tick(k * 0.1)
        animator.tick(k * 0.1)
    now = dict(zip(extras.codes, extras.values(), strict=True))
    # the wizard's hat jumps; the head is left alone, and the beard (its physics' own) rests
    assert now == {"HT": 0.5, "UL": 0.0, "JS": 0.5, "PERK": 1.0, "BEARD": 0.5}
    cmd.handle("play disgust 100")
    for k in range(4, 8):
        extras.tick(k * 0.1)
    now = dict(zip(extras.codes, extras.values(), strict=True))
    assert now["UL"] == pytest.approx(0.8) and now["PERK"] == 0.0
