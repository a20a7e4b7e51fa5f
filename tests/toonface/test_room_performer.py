"""The room's performer page, server side (issue 45): a page's frames (MediaPipe's blendshapes and
transformation matrix, as JSON) become a head turn and ARKit scores, are mapped with the arkit
mapping and enter the room as a stream any viewer receives; bad messages are refused and counted.
The page itself runs in Chromium in test_room_view.py."""

import asyncio
import contextlib
import json
import math
import re

import aiohttp
import numpy as np
import pytest

from capture.blendshapes import BLENDSHAPES
from capture.listening import head_references
from stream.playout import Playout
from stream.receiver import StreamReceiver
from stream.websocket import WebSocketLink
from toon import motor_index, standard_neutral
from toonface.room.performers import head_turn, page_frame
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

TOKENS = {"demo": ("perform-secret-0123456789", "watch-secret-0123456789")}
KEY = b"a shared secret of the room 0123"


def _yaw(degrees: float) -> np.ndarray:
    a = math.radians(degrees)
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


def test_the_head_turn_is_read_from_the_matrix_in_either_order_and_without_its_scale():
    turn = _yaw(20) @ np.array([[1, 0, 0], [0, math.cos(0.3), -math.sin(0.3)], [0, math.sin(0.3), math.cos(0.3)]])
    matrix = np.eye(4)
    matrix[:3, :3] = 1.1 * turn  # MediaPipe's may carry a scale
    matrix[:3, 3] = [1.5, -2.0, -45.0]  # the face 45 cm before the camera
    assert np.allclose(head_turn(matrix.ravel()), turn)  # by rows
    assert np.allclose(head_turn(matrix.T.ravel()), turn)  # by columns, as WebGL keeps them
    for bad in ([0.0] * 15, [math.nan] * 16, np.arange(16.0), np.diag([-1.0, 1.0, 1.0, 1.0]).ravel()):
        with pytest.raises(ValueError):
            head_turn(bad)


def test_a_page_frame_is_the_head_references_turned_and_the_arkit_scores():
    _, rest = head_references()
    matrix = np.eye(4)
    matrix[:3, :3] = _yaw(30)
    text = json.dumps({"t": 1500, "scores": {"jawOpen": 0.6, "_neutral": 0.9, "mouthSmileLeft": 1.7, "nonsense": 1},
                       "matrix": matrix.T.ravel().tolist()})
    frame = page_frame(text, rest)
    assert frame.t == 1.5
    assert frame.channels[BLENDSHAPES.index("jawOpen")] == 0.6
    assert frame.channels[BLENDSHAPES.index("mouthSmileLeft")] == 1.0  # kept within 0..1
    assert np.count_nonzero(frame.channels) == 2
    assert np.allclose(frame.positions, rest @ _yaw(30).T)
    lost = page_frame('{"t": 1600}', rest)  # no face in view
    assert lost.t == 1.6 and np.isnan(lost.positions).all()
    for bad in ("{", "[]", '{"t": "soon"}', '{"t": 1, "scores": [1, 2]}', '{"t": 1, "scores": {}, "matrix": [1]}'):
        with pytest.raises(ValueError):
            page_frame(bad, rest)


def _frames(seconds: float, jaw: float, start: float = 0.0, down: float = 0.0) -> list[str]:
    """A page's messages at 25 frames a second, face front on, the jaw at ``jaw``, the eyes
    looking down by ``down`` (a score)."""
    matrix = np.eye(4)
    matrix[:3, 3] = [0, 0, -45]
    return [json.dumps({"t": (start + k / 25) * 1000, "matrix": matrix.T.ravel().tolist(),
                        "scores": {"jawOpen": jaw, "eyeLookDownLeft": down, "eyeLookDownRight": down}})
            for k in range(round(seconds * 25))]


@pytest.mark.slow  # the mapping's real-time sender (1.5 s each): make test runs them (make test-fast stays near 50 s)
@pytest.mark.parametrize("key", [None, KEY], ids=["open", "sealed"])
def test_a_performer_page_enters_the_room_as_a_stream_a_native_viewer_receives(key):
    """A second of rest, then the jaw wide open: the viewer's mouth opens. Malformed and binary
    messages are refused and counted; with the room's key the stream is sealed with it."""
    rooms = Rooms(TOKENS, key=key)
    with in_thread(rooms) as base:
        link = WebSocketLink(f"{base}/r/demo", TOKENS["demo"][1], "watch")
        with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), key=key, link=link) as receiver:

            async def perform() -> None:
                async with aiohttp.ClientSession() as session, session.ws_connect(
                        f"{base}/r/demo/ws?role=perform&format=face",
                        headers={"Authorization": f"Bearer {TOKENS['demo'][0]}"}) as ws:
                    for text in _frames(1.0, 0.0) + _frames(1.0, 0.9, start=1.0):
                        await ws.send_str(text)
                    await ws.send_str("not json")
                    await ws.send_bytes(b"\x00" * 8)
                    await asyncio.to_thread(receiver.wait_for_packets, 20, 10.0)

            asyncio.run(perform())
            values, _ = receiver.values_at()
    room = rooms.rooms["demo"]
    assert room.refused["malformed"] == 1 and room.refused["binary"] == 1
    assert receiver.reader.packets >= 20 and room.performers == {}  # gone with its page
    assert values[motor_index("MB")] > standard_neutral()[motor_index("MB")] + 0.3


def test_the_wire_figure_counts_a_websocket_message_over_tcp_and_a_datagram_over_udp():
    from stream.packets import StreamWriter
    from stream.sender import StreamSender
    from toonface.room.performers import _InRoom

    sent: list[bytes] = []
    room = StreamSender(("room", 0), StreamWriter(30.0, frames_per_packet=1), link=_InRoom(sent.append))
    udp = StreamSender(("127.0.0.1", 9), StreamWriter(30.0, frames_per_packet=1))
    try:
        for k in range(30):  # one second
            room.write(k / 30, standard_neutral())
            udp.write(k / 30, standard_neutral())
        payload = sum(len(packet) for packet in sent)
        assert len(sent) == 30
        assert room.rates(30)["wire_kbps"] == round((payload + 46 * 30) * 8 / 1000, 3)  # TCP/IP 40, frame 2 + mask 4
        assert udp.rates(30)["wire_kbps"] == round((payload + 28 * 30) * 8 / 1000, 3)  # UDP/IP 28
    finally:
        room.close()
        udp.close()


@pytest.mark.slow  # the mapping's real-time sender: make test runs it
def test_the_performer_pages_eye_contact_centres_its_look_at_the_screen_and_says_so():
    """The rest looks into the lens, then the page asks for eye contact and looks down at its
    screen: the page is told it was taken, and the pupils sent come back to centre."""
    rooms = Rooms(TOKENS)
    neutral = standard_neutral()

    async def perform(base: str) -> tuple[list[str], np.ndarray]:
        said: list[str] = []
        async with aiohttp.ClientSession() as session, session.ws_connect(
                f"{base}/r/demo/ws?role=perform&format=face", headers={"Authorization": f"Bearer {TOKENS['demo'][0]}"}
        ) as ws:
            for text in _frames(1.0, 0.0):
                await ws.send_str(text)
            await ws.send_str('{"eye_contact": true}')  # no time: refused as malformed
            await ws.send_str('{"eye_contact": true, "t": 1000}')
            later, mapped, taken_at = _frames(30.0, 0.0, start=1.0, down=0.6), None, None
            while later and mapped is None:
                await ws.send_str(later.pop(0))  # the page's frames, each a chance to be told
                with contextlib.suppress(TimeoutError):
                    said.append(json.loads((await ws.receive(timeout=0.05)).data)["said"])
                latest = next(iter(rooms.rooms["demo"].performers.values())).performer.follower.latest
                if taken_at is None and any(line.startswith("eye contact taken") for line in said):
                    taken_at = latest.frames
                if taken_at is not None and latest.frames > taken_at + 5:  # frames mapped since
                    mapped = latest.values()
        assert mapped is not None
        return said, mapped

    with in_thread(rooms) as base:
        said, values = asyncio.run(perform(base))
    assert said[0] == "eye contact: look at the middle of your screen for 1 s"
    below = re.match(r"eye contact taken: the screen's middle is now the pupils' centre \(they sat ([0-9.]+) below",
                     said[1])
    assert below is not None and float(below.group(1)) > 0.2  # the look down, 0.3 of the pupils' range
    assert rooms.rooms["demo"].refused["malformed"] == 1
    for code in ("PRV", "PLV", "PRH", "PLH"):
        assert abs(values[motor_index(code)] - neutral[motor_index(code)]) < 0.05, code
