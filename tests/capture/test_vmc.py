"""The VMC bridge in: an OSC client (python-osc, standing in for a phone app) sends blendshapes and
the head bone; the source turns them into frames and the arkit mapping into motors."""

import math
from itertools import count, islice

import numpy as np
import pytest
from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
from pythonosc.osc_message_builder import OscMessageBuilder
from pythonosc.udp_client import SimpleUDPClient

from capture.blendshapes import BLENDSHAPES
from capture.sources import open_source
from capture.vmc import KNOWN_NAMES, VmcState, arkit_name, osc_messages, quaternion_matrix
from common import InputError
from toon import load_face, motor_index
from toonface.send import build_mapper


@pytest.fixture
def linked():
    """A VMC source on a free loopback port, and a client sending to it; both closed afterwards."""
    ticks = count()
    source = open_source("vmc:127.0.0.1:0", clock=lambda: next(ticks) / 60)  # one tick a frame: 60 Hz
    host, port = source.meta["address"].rsplit(":", 1)
    client = SimpleUDPClient(host, int(port))
    yield source, client
    client._sock.close()
    source.close()  # the source's socket closes with its frames


def _yaw(degrees: float) -> list[float]:
    """A Unity quaternion (x, y, z, w) turning ``degrees`` about y (toward the avatar's right)."""
    half = math.radians(degrees) / 2
    return [0.0, math.sin(half), 0.0, math.cos(half)]


def test_names_in_every_spelling_and_vrm_presets_become_arkit_scores():
    assert arkit_name("jawOpen") == "jawOpen"
    assert arkit_name("JawOpen") == "jawOpen"
    assert arkit_name("eyeBlink_L") == "eyeBlinkLeft" and arkit_name("EyeBlink_R") == "eyeBlinkRight"
    assert arkit_name("Joy") is None
    state = VmcState()
    for name, value in (("A", 0.5), ("Blink_L", 1.0), ("mouthSmileLeft", 0.25), ("Joy", 1.0), ("nonsense", 1.0)):
        state.take("/VMC/Ext/Blend/Val", [name, value])
    assert np.isnan(state.current).all()  # nothing applied yet
    assert state.take("/VMC/Ext/Blend/Apply", []) is True
    scores = dict(zip(BLENDSHAPES, state.current, strict=True))
    assert scores["jawOpen"] == 0.5 and scores["eyeBlinkLeft"] == 1.0 and scores["eyeBlinkRight"] == 0.0
    assert scores["mouthSmileLeft"] == 0.25  # sent as ARKit's own: it wins over Joy's
    assert scores["mouthSmileRight"] == 1.0 and scores["cheekSquintLeft"] == 0.5  # from Joy
    assert scores["browDownLeft"] == 0.0  # never sent, once a set was applied
    assert state.counts["unknown_names"] == 1
    assert state.take("/VMC/Ext/Blend/Val", ["jawOpen", "wide"]) is False  # a bad value: counted
    assert state.take("/VMC/Ext/Bone/Pos", ["Head", 0.0]) is False
    assert state.counts["bad_messages"] == 2
    for k in range(3000):  # a sender of ever new names: each counted, not all remembered
        state.take("/VMC/Ext/Blend/Val", [f"shape{k}", 1.0])
    state.take("/VMC/Ext/Blend/Apply", [])
    assert state.counts["unknown_names"] == 3001 and len(state._meaning) == KNOWN_NAMES


def test_the_head_bone_turns_the_head_frame_with_the_right_handedness():
    state = VmcState()
    state.take("/VMC/Ext/Bone/Pos", ["Head", 0.0, 0.0, 0.0, *_yaw(30.0)])
    forward = state.head() @ [0.0, 0.0, 1.0]  # out of the face
    # Unity turns +z toward +x, the avatar's right: the performer's right, -x in the head frame
    np.testing.assert_allclose(forward, [-math.sin(math.radians(30)), 0.0, math.cos(math.radians(30))], atol=1e-12)
    half = math.radians(20) / 2
    state.take("/VMC/Ext/Bone/Pos", ["Head", 0.0, 0.0, 0.0, math.sin(half), 0.0, 0.0, math.cos(half)])
    state.take("/VMC/Ext/Bone/Pos", ["Neck", 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])
    nod = state.head() @ [0.0, 0.0, 1.0]
    assert nod[1] == pytest.approx(-math.sin(math.radians(20)))  # about Unity's x: the chin goes down
    np.testing.assert_allclose(quaternion_matrix(0, 0, 0, 2.0), np.eye(3))  # normalised first
    with pytest.raises(ValueError):
        quaternion_matrix(0, 0, 0, 0)


def test_a_vmc_sender_moves_the_expected_motors(linked):
    source, client = linked
    face = load_face("classic")
    notes: list[str] = []
    mapper = build_mapper(source, target_neutral=face.neutral(), notes=notes)
    assert "mapping arkit reads no performer's ranges" in notes[0]
    values = []
    for frame in range(150):  # 1 s of rest, then the jaw opens, the left eye shuts, the head turns
        t = frame / 60
        client.send_message("/VMC/Ext/Blend/Val", ["jawOpen", 0.6 if t >= 1.2 else 0.0])
        client.send_message("/VMC/Ext/Blend/Val", ["eyeBlink_L", 1.0 if t >= 1.6 else 0.0])
        client.send_message("/VMC/Ext/Bone/Pos", ["Head", 0.0, 1.5, 0.1, *_yaw(15.0 if t >= 2.0 else 0.0)])
        client.send_message("/VMC/Ext/Blend/Apply", [])
        received = next(source.frames)  # loopback: what was sent is there to read
        values.append(mapper.step_frame(received)[0])  # the head as the tracker sent it
    neutral = face.neutral()
    at = {name: np.array(values)[[int(s * 60) for s in (1.1, 1.5, 1.9, 2.4)], motor_index(name)]
          for name in ("MB", "ELU", "ERU", "HH")}
    mb = neutral[motor_index("MB")]
    np.testing.assert_allclose(at["MB"], [mb] + [mb + 0.6 * (1 - mb)] * 3)  # a score: 0.6 of the way open
    np.testing.assert_allclose(at["ELU"][:2], neutral[motor_index("ELU")])
    np.testing.assert_allclose(at["ELU"][2:], 0.0)  # shut: a blink of 1 takes the lid all the way down
    np.testing.assert_allclose(at["ERU"], neutral[motor_index("ERU")])  # the other eye stays open
    hh = neutral[motor_index("HH")]
    # 60 degrees a unit, to the right; the live head filter (One Euro) has all but settled 0.4 s on
    np.testing.assert_allclose(at["HH"], [hh, hh, hh, hh - 15 / 60], atol=0.003)
    assert source.meta["counts"] == {"frames": 150, "unknown_names": 0, "bad_messages": 0}


def test_bundles_are_read_and_bad_datagrams_are_counted_and_dropped(linked):
    source, client = linked
    client._sock.sendto(b"not an OSC packet", (client._address, client._port))
    bundle = OscBundleBuilder(IMMEDIATELY)
    for address, args in (("/VMC/Ext/Blend/Val", ["jawOpen", 0.25]), ("/VMC/Ext/Blend/Apply", [])):
        message = OscMessageBuilder(address)
        for arg in args:
            message.add_arg(arg)
        bundle.add_content(message.build())
    client.send(bundle.build())
    client.send_message("/VMC/Ext/OK", [1, 3, 0, 0])  # the performer is lost
    client.send_message("/VMC/Ext/Blend/Apply", [])
    first, lost = islice(source.frames, 2)
    assert first.channels[BLENDSHAPES.index("jawOpen")] == 0.25
    np.testing.assert_allclose(first.positions, source.meta["rest"])  # no head sent: held still
    assert np.isnan(lost.channels).all() and np.isnan(lost.positions).all()
    assert source.meta["counts"]["bad_messages"] == 1


def _message(address: str, *args: object) -> bytes:
    built = OscMessageBuilder(address)
    for arg in args:
        built.add_arg(arg)
    return built.build().dgram


def test_packets_nested_or_not_give_their_messages_in_the_order_sent():
    inner = OscBundleBuilder(IMMEDIATELY)
    inner.add_content(OscMessageBuilder("/b").build())
    inner.add_content(OscMessageBuilder("/c").build())
    outer = OscBundleBuilder(IMMEDIATELY)
    first = OscMessageBuilder("/a")
    first.add_arg("jawOpen")
    first.add_arg(0.5)
    outer.add_content(first.build())
    outer.add_content(inner.build())
    outer.add_content(OscMessageBuilder("/d").build())
    assert osc_messages(outer.build().dgram) == [("/a", ["jawOpen", 0.5]), ("/b", []), ("/c", []), ("/d", [])]
    assert osc_messages(_message("/VMC/Ext/OK", 1, 3, 0, 1)) == [("/VMC/Ext/OK", [1, 3, 0, 1])]
    for junk in (b"", b"not OSC", b"#bundle\x00", _message("/a", "x")[:-4]):
        with pytest.raises(ValueError, match="not an OSC packet"):
            osc_messages(junk)


def test_a_bad_address_is_one_clear_error():
    with pytest.raises(InputError, match="VMC"):
        open_source("vmc:127.0.0.1:99999")


@pytest.mark.slow
def test_the_arkit_mapping_serves_a_markerless_take_too(realdata, tmp_path):
    """The mapping a VMC sender gets, on MediaPipe's scores of a real talking face: it follows what
    the marker-based face preset measures on the same take (an independent measure: lip gaps and
    lid distances, not scores)."""
    from toon import load_track
    from toonface.cli import main

    video = realdata / "video" / "grid" / "bbaf2n.mpg"
    if not video.is_file():
        pytest.skip(f"{video} is absent")
    take = tmp_path / "grid.npz"
    assert main(["track", str(video), "--markers", "face", "-o", str(take)]) == 0
    for mapping in ("arkit", "face"):
        assert main(["map", str(take), "--mapping", mapping, "-o", str(tmp_path / f"{mapping}.csv")]) == 0
    scores, markers = (load_track(tmp_path / f"{m}.csv").values for m in ("arkit", "face"))
    for code, least in (("MB", 0.95), ("ERU", 0.9), ("ELU", 0.9)):
        i = motor_index(code)
        assert np.corrcoef(scores[:, i], markers[:, i])[0, 1] > least, code
    assert np.ptp(scores[:, motor_index("MB")]) > 0.2  # the speaker's jaw, in scores


def test_a_source_waiting_for_a_silent_sender_ends_when_halted():
    source = open_source("vmc:127.0.0.1:0", timeout=0.01)
    source.halt.set()  # what a player's follower does when it stops
    assert list(source.frames) == []  # ended without a frame, not blocked on the socket
