"""The OpenSeeFace bridge: packets made here the way its tracker makes them (a head posed in front
of a camera, its model fitted with OpenCV's solvePnP on (row, column) landmarks, the fitted
matrix turned into a quaternion by the tracker's formula, the fields packed as facetracker.py
packs them) move the motors they should; bad packets are counted and dropped."""

import math
import socket
import struct
from itertools import count

import cv2
import numpy as np
import pytest

from capture.blendshapes import BLENDSHAPES
from capture.markerset import load_markerset
from capture.openseeface import FEATURES, RECORD_SIZE, parse_packet
from capture.sources import open_source
from toon import load_face, motor_index
from toonface.send import build_mapper

WIDTH, HEIGHT, DISTANCE = 640.0, 480.0, 600.0


def _tracker_quaternion(m: np.ndarray) -> np.ndarray:
    """The tracker's own matrix-to-quaternion formula (facetracker's tracker.py), as published."""
    if m[2, 2] < 0:
        if m[0, 0] > m[1, 1]:
            t = 1 + m[0, 0] - m[1, 1] - m[2, 2]
            q = [t, m[0, 1] + m[1, 0], m[2, 0] + m[0, 2], m[1, 2] - m[2, 1]]
        else:
            t = 1 - m[0, 0] + m[1, 1] - m[2, 2]
            q = [m[0, 1] + m[1, 0], t, m[1, 2] + m[2, 1], m[2, 0] - m[0, 2]]
    elif m[0, 0] < -m[1, 1]:
        t = 1 - m[0, 0] - m[1, 1] + m[2, 2]
        q = [m[2, 0] + m[0, 2], m[1, 2] + m[2, 1], t, m[0, 1] - m[1, 0]]
    else:
        t = 1 + m[0, 0] + m[1, 1] + m[2, 2]
        q = [m[1, 2] - m[2, 1], m[2, 0] - m[0, 2], m[0, 1] - m[1, 0], t]
    return np.array(q) * 0.5 / math.sqrt(t)


def _fitted_quaternion(yaw: float, pitch: float) -> np.ndarray:
    """A head turned ``yaw`` degrees toward the performer's left and ``pitch`` chin up, seen by a
    camera in front of it, fitted as the tracker fits it."""
    markers = load_markerset("face")
    face = np.array([markers.neutral_of(label) for label in markers.labels])  # mm: x left, y up, z out
    a, b = math.radians(yaw), math.radians(-pitch)
    turn = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]]) @ \
        np.array([[1, 0, 0], [0, math.cos(b), -math.sin(b)], [0, math.sin(b), math.cos(b)]])
    world = face @ turn.T
    depth = DISTANCE - world[:, 2]  # the camera looks at the face from DISTANCE mm out in front
    column = HEIGHT / 2 + WIDTH * world[:, 0] / depth  # the performer's left is the image's right
    row = WIDTH / 2 - WIDTH * world[:, 1] / depth  # up is a smaller row
    camera = np.array([[WIDTH, 0, WIDTH / 2], [0, WIDTH, HEIGHT / 2], [0, 0, 1]])
    model = face * [-1, 1, 1]  # the tracker's model: x to the face's right
    ok, rvec, _ = cv2.solvePnP(model, np.column_stack([row, column]), camera, np.zeros(4),
                               flags=cv2.SOLVEPNP_ITERATIVE)
    assert ok
    return _tracker_quaternion(cv2.Rodrigues(rvec)[0])


def _record(quaternion, features=None, face_id=0, success=True, confidence=0.9) -> bytes:
    head = struct.pack("=diffffBf4f3f3f", 1.7e9, face_id, WIDTH, HEIGHT, 1.0, 1.0, int(success), 0.01,
                       *quaternion, 0.0, 0.0, 0.0, 0.0, 0.0, 600.0)
    points = np.zeros((70, 3))
    points[66:68, 2], points[68:70, 2] = -10.0, 0.0  # pupils straight ahead of their eyeballs (sent as -z)
    values = {name: 0.0 for name in FEATURES} | (features or {})
    rest = np.concatenate([np.full(68, confidence), np.zeros(136), points.reshape(-1),
                           [values[name] for name in FEATURES]])
    return head + rest.astype("=f4").tobytes()


@pytest.fixture
def linked():
    ticks = count()
    source = open_source("openseeface:127.0.0.1:0", clock=lambda: next(ticks) / 30)
    host, port = source.meta["address"].rsplit(":", 1)
    sender = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    yield source, lambda data: sender.sendto(data, (host, int(port)))
    sender.close()
    source.close()


def test_a_record_is_read_field_by_field():
    q = _fitted_quaternion(0.0, 0.0)
    data = _record(q, {"mouth_open": 0.5, "eye_l": -1.0}, face_id=3) + _record(q, face_id=1)
    assert len(data) == 2 * RECORD_SIZE
    first, second = parse_packet(data)
    assert (first.id, second.id, first.size, first.success) == (3, 1, (WIDTH, HEIGHT), True)
    np.testing.assert_allclose(first.quaternion, q, atol=1e-6)
    assert first.features["mouth_open"] == 0.5 and first.features["eye_l"] == -1.0
    assert first.confidence.shape == (68,) and first.points.shape == (70, 3)
    with pytest.raises(ValueError, match="whole number"):
        parse_packet(data[:-1])
    with pytest.raises(ValueError, match="not numbers"):
        parse_packet(_record([math.nan, 0, 0, 1]))


def test_a_posed_head_and_its_features_move_the_expected_motors(linked):
    source, send = linked
    face = load_face("classic")
    n = face.neutral()
    mapper = build_mapper(source, target_neutral=face.neutral())
    rest = _record(_fitted_quaternion(0.0, 0.0))
    posed = _record(_fitted_quaternion(15.0, 9.0), {"mouth_open": 0.5, "eye_l": -1.0, "eyebrow_updown_r": 0.8})
    shown = None
    for frame in range(75):  # a second of rest, then the pose
        send(rest if frame < 30 else posed)
        received = next(source.frames)
        shown, confidence = mapper.step(received.positions, received.t, received.channels, received.confidence)
    assert received.confidence == pytest.approx(0.9) and confidence.max() == pytest.approx(0.9)
    at = {code: (shown[motor_index(code)], n[motor_index(code)]) for code in MOTOR_CHECKS}
    assert at["MB"][0] == pytest.approx(at["MB"][1] + 0.5 * (1 - at["MB"][1]), abs=1e-6)  # half open
    assert at["ELU"][0] == pytest.approx(0.0) and at["ERU"][0] == pytest.approx(at["ERU"][1])  # the left eye shut
    assert at["BRL"][0] == pytest.approx(at["BRL"][1] + 0.8 * (1 - at["BRL"][1]), abs=1e-6)
    # 60 degrees a motor unit; the tracker's fit of a pinhole view is exact to a fraction of a degree
    assert at["HH"][0] == pytest.approx(at["HH"][1] + 15 / 60, abs=0.01)  # toward the performer's left
    assert at["HV"][0] == pytest.approx(at["HV"][1] + 9 / 60, abs=0.01)  # chin up
    assert source.meta["counts"] == {"frames": 75, "bad_packets": 0, "lost": 0}


MOTOR_CHECKS = ("MB", "ELU", "ERU", "BRL", "HH", "HV")


def test_bad_packets_are_counted_and_dropped_and_a_failed_fit_is_a_lost_frame(linked):
    source, send = linked
    send(b"\x00" * 100)  # not a record
    send(_record([math.inf, 0, 0, 1]))
    send(_record(_fitted_quaternion(0, 0), success=False))
    send(_record(_fitted_quaternion(0, 0), {"mouth_open": 0.25}, face_id=2) + _record(_fitted_quaternion(0, 0),
                                                                                     face_id=0))
    lost = next(source.frames)
    assert np.isnan(lost.positions).all() and lost.confidence == 0.0
    two = next(source.frames)  # the lowest id is the performer: face 0, mouth shut
    assert two.channels[BLENDSHAPES.index("jawOpen")] == 0.0
    assert source.meta["counts"] == {"frames": 2, "bad_packets": 2, "lost": 1}


def test_a_silent_tracker_does_not_keep_the_source_waiting_once_halted():
    source = open_source("openseeface:127.0.0.1:0", timeout=0.01)
    source.halt.set()
    assert list(source.frames) == []
