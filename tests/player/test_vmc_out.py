"""The VMC bridge out: the motors a player shows, as a VMC receiver reads them (OSC parsed by
python-osc), and back in through toonface's own VMC source."""

import math
import socket

import numpy as np
import pytest
from pythonosc.osc_packet import OscPacket

from capture.vmc import VmcState
from player.vmc_out import MAX_BUNDLE, VmcOut, arkit_scores, extra_scores, head_quaternion
from toon import MOTOR_CODES, load_face, motor_index


@pytest.fixture
def receiver():
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.settimeout(5.0)
    yield sock
    sock.close()


def _frame(sock, count: int) -> list:
    """The messages of ``count`` datagrams, in order, as (address, params)."""
    return [(m.message.address, list(m.message.params)) for _ in range(count)
            for m in OscPacket(sock.recv(65536)).messages]


def _pose(face, **motors):
    values = face.neutral()
    for code, value in motors.items():
        values[motor_index(code)] = value
    return values


def test_a_frame_carries_the_motors_their_arkit_scores_and_the_head(receiver):
    face = load_face("classic")
    n = face.neutral()
    values = _pose(face, MB=0.55, ELU=0.0, ERU=1.0, MRV=0.8, HH=n[motor_index("HH")] + 0.25)
    out = VmcOut(receiver.getsockname(), n)
    datagrams = out.datagrams(values)
    assert all(len(d) <= MAX_BUNDLE for d in datagrams)
    out.write(0.0, values)
    messages = _frame(receiver, len(datagrams))
    out.close()
    assert messages[-1] == ("/VMC/Ext/Blend/Apply", [])  # the set is complete only at the end
    blends = {args[0]: args[1] for address, args in messages if address == "/VMC/Ext/Blend/Val"}
    for code in MOTOR_CODES:  # float32 on the wire
        assert blends[code] == pytest.approx(values[motor_index(code)], abs=1e-6)
    mb, eru, mrv = (n[motor_index(c)] for c in ("MB", "ERU", "MRV"))
    assert blends["jawOpen"] == pytest.approx((0.55 - mb) / (1 - mb), abs=1e-6)  # its way open, by hand
    assert blends["eyeBlinkLeft"] == pytest.approx(1.0) and blends["eyeWideLeft"] == 0.0  # shut
    assert blends["eyeWideRight"] == pytest.approx(1.0) and blends["eyeBlinkRight"] == 0.0
    assert blends["mouthSmileRight"] == pytest.approx((0.8 - mrv) / (1 - mrv), abs=1e-6)
    assert blends["mouthFrownRight"] == 0.0 and blends["jawOpen"] < 1 and eru < 1
    head = next(args for address, args in messages if address == "/VMC/Ext/Bone/Pos")
    assert head[0] == "Head"
    # read back as a VMC receiver does: the head turned 15 degrees toward the performer's left
    state = VmcState()
    state.take("/VMC/Ext/Bone/Pos", head)
    forward = state.head() @ [0.0, 0.0, 1.0]
    assert math.degrees(math.atan2(forward[0], forward[2])) == pytest.approx(15.0, abs=1e-3)
    assert out.frames == 1 and out.bytes == sum(len(d) for d in datagrams)


def test_the_head_quaternion_is_a_unit_turn_of_yaw_then_pitch():
    face = load_face("classic")
    n = face.neutral()
    values = _pose(face, HH=n[motor_index("HH")] - 0.5, HV=n[motor_index("HV")] + 0.25)  # 30 right, 15 chin up
    q = head_quaternion(values, n)
    assert np.linalg.norm(q) == pytest.approx(1.0)
    state = VmcState()
    state.take("/VMC/Ext/Bone/Pos", ["Head", 0, 0, 0, *q])
    forward = state.head() @ [0.0, 0.0, 1.0]
    assert math.degrees(math.atan2(forward[0], forward[2])) == pytest.approx(-30.0, abs=1e-6)
    assert math.degrees(math.asin(forward[1])) == pytest.approx(15.0, abs=1e-6)
    assert arkit_scores(n, n) == {name: 0.0 for name in arkit_scores(n, n)}  # neutral: every score 0


def _round_trip(face):
    """VMC out sending to this machine's VMC in, whose frames the arkit mapping maps onto ``face``
    (a clock of 60 frames a second): the sink, the source and the live mapper."""
    from itertools import count

    from capture.sources import open_source
    from toonface.send import build_mapper

    ticks = count()
    source = open_source("vmc:127.0.0.1:0", clock=lambda: next(ticks) / 60)
    host, port = source.meta["address"].rsplit(":", 1)
    return VmcOut((host, int(port)), face.neutral()), source, build_mapper(source, target_neutral=face.neutral())


def test_toonfaces_vmc_out_read_by_its_vmc_in_gives_the_motors_back(receiver):
    """A round trip through both bridges and the arkit mapping: what has a score each way comes back."""
    face = load_face("round")
    n = face.neutral()
    out, source, mapper = _round_trip(face)
    shown = _pose(face, MB=0.7, ERU=0.2, ELU=0.2, MRV=0.9, MLV=0.3, PRV=0.8, PLV=0.8, HH=n[motor_index("HH")] + 0.2)
    back = None
    for frame in range(90):  # a second of rest, then the pose
        out.write(frame / 60, n if frame < 60 else shown)
        received = next(source.frames)
        back = mapper.step(received.positions, received.t, received.channels)[0]
    out.close()
    source.close()
    for code in ("MB", "ERU", "ELU", "MRV", "MLV", "PRV", "PLV"):
        assert back[motor_index(code)] == pytest.approx(shown[motor_index(code)], abs=0.01), code
    assert back[motor_index("HH")] == pytest.approx(shown[motor_index("HH")], abs=0.01)  # after the head filter


def test_the_parameters_beyond_the_21_go_out_and_come_back_through_vmc_in(receiver):
    """HT as the head bone's roll, CP, JS and UL as the ARKit scores the arkit preset reads: a
    round trip through both bridges gives them back; PERK, which no score stands for, goes out
    under its code only."""
    face = load_face("round")
    n = face.neutral()
    out, source, mapper = _round_trip(face)
    sent = {"HT": 0.8, "UL": 0.6, "CP": 0.7, "JS": 0.2, "PERK": 0.9}
    for frame in range(120):  # a second of rest, then the parameters
        out.write(frame / 60, n, extra=None if frame < 60 else sent)
        received = next(source.frames)
        mapper.step(received.positions, received.t, received.channels)
    out.close()
    source.close()
    back = mapper.extra_values()
    for code in ("HT", "UL", "CP", "JS"):
        assert back[code] == pytest.approx(sent[code], abs=0.01), code
    assert back["PERK"] == 0.0
    assert extra_scores({"JS": 0.75}) == {"jawLeft": 0.5, "jawRight": 0.0}
