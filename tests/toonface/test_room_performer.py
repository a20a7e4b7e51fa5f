"""The room's performer page, server side (issue 45): a page's frames (MediaPipe's blendshapes and
transformation matrix, as JSON or compact, issue 68) become a head turn and ARKit scores, are
mapped with the arkit mapping and enter the room as a stream any viewer receives; bad messages
are refused and counted. The page itself runs in Chromium in test_room_view.py."""

import asyncio
import contextlib
import json
import math
import re
import struct

import aiohttp
import numpy as np
import pytest

from capture.blendshapes import BLENDSHAPES
from capture.listening import head_references
from stream.playout import Playout
from stream.receiver import StreamReceiver
from stream.websocket import WebSocketLink
from toon import motor_index, standard_neutral
from toonface.room.performers import PageCodes, head_turn, page_frame
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


def test_compact_frames_carry_the_changed_scores_and_the_turn_as_a_quaternion():
    """Bytes written by hand from the layout: the first frame sets two of three scores, the next
    changes one, a frame with no face keeps them, a long step carries the time whole."""
    _, rest = head_references()
    codes = PageCodes(["eyeBlinkLeft", "jawOpen", "mouthSmileLeft"])
    half = math.sin(math.radians(15))  # a 30 degree yaw: the quaternion (0, sin 15, 0, cos 15)
    first = bytes([1]) + struct.pack("<H3h", 1500, 0, round(half * 32767), 0) + bytes([0b101, 51, 255])
    frame = codes.frame(first, rest)
    assert frame.t == 1.5
    assert frame.channels[BLENDSHAPES.index("eyeBlinkLeft")] == 0.2  # 51/255
    assert frame.channels[BLENDSHAPES.index("mouthSmileLeft")] == 1.0
    assert np.count_nonzero(frame.channels) == 2
    assert np.allclose(frame.positions, rest @ _yaw(30).T, atol=0.01)  # mm: the quaternion in 32767ths
    second = codes.frame(bytes([1]) + struct.pack("<H3h", 40, 0, 0, 0) + bytes([0b010, 102]), rest)
    assert second.t == 1.54 and np.allclose(second.positions, rest)
    assert [second.channels[BLENDSHAPES.index(n)] for n in codes_names(codes)] == [0.2, 0.4, 1.0]
    assert np.isnan(codes.frame(bytes([2]) + struct.pack("<H", 40), rest).positions).all()
    later = codes.frame(bytes([1]) + struct.pack("<HI3h", 0xFFFF, 90_000, 0, 0, 0) + bytes([0]), rest)
    assert later.t == 90.0 and later.channels[BLENDSHAPES.index("jawOpen")] == 0.4  # kept through the gap
    for bad in (b"", bytes([3, 0, 0]), bytes([1, 1]), bytes([2, 1, 0, 9]),
                bytes([1]) + struct.pack("<H3h", 1, 0, 0, 0) + bytes([0b1000]),  # a fourth score named
                bytes([1]) + struct.pack("<H3h", 1, 0, 0, 0) + bytes([0b11, 5]),  # two named, one given
                bytes([1]) + struct.pack("<H3h", 1, 30000, 30000, 0) + bytes([0]),  # no unit quaternion
                bytes([2]) + struct.pack("<HI", 0xFFFF, 1000)):  # the time went back
        with pytest.raises(ValueError):
            codes.frame(bad, rest)
    assert codes.ms == 90_000 and codes.levels.tolist() == [51, 102, 255]  # a refused frame changes nothing


def test_the_pages_coder_writes_what_the_server_reads(tmp_path):
    """face_code.js in Chromium encodes three frames (a scaled turn, scores changing, no face, a
    long pause); PageCodes reads back the turn, the scores to the nearest 255th and the times."""
    from browser import chromium

    names = ["browInnerUp", "eyeBlinkLeft", "jawOpen", "mouthClose", "mouthFunnel", "mouthPucker",
             "mouthSmileLeft", "mouthSmileRight", "noseSneerLeft"]  # nine: a mask of two bytes
    turn = _yaw(-25) @ np.array([[1, 0, 0], [0, math.cos(0.2), -math.sin(0.2)], [0, math.sin(0.2), math.cos(0.2)]])
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = 0.9 * turn, [2.0, -1.0, -40.0]
    frames = [(33.4, {"jawOpen": 0.5, "noseSneerLeft": 0.25, "_neutral": 1.0}),
              (66.6, {"jawOpen": 0.5, "noseSneerLeft": 0.3, "mouthSmileLeft": 1.4}), (99.9, None),
              (80_000.2, {"eyeBlinkLeft": 0.02})]
    script = f"""const done = arguments[arguments.length - 1];
        import("/static/face_code.js").then(({{FaceCoder}}) => {{
          const coder = new FaceCoder({json.dumps(names)});
          done({json.dumps(frames)}.map(([ms, scores]) => Array.from(new Uint8Array(
            coder.encode(ms, scores, scores && {json.dumps(matrix.T.ravel().tolist())})))));
        }}, (error) => done(String(error)));"""
    rooms = Rooms(TOKENS, face="cat")
    with in_thread(rooms) as base, chromium(400, 300) as page:
        page.get(f"{base.replace('ws://', 'http://')}/r/demo")
        written = page.execute_async_script(script)
    assert isinstance(written, list), written
    _, rest = head_references()
    codes = PageCodes(names)
    read = [codes.frame(bytes(message), rest) for message in written]
    assert [frame.t for frame in read] == [0.033, 0.067, 0.1, 80.0]
    assert [len(message) for message in written] == [3 + 6 + 2 + 2, 3 + 6 + 2 + 2, 3, 7 + 6 + 2 + 4]
    scores = np.array([[frame.channels[BLENDSHAPES.index(name)] for name in names] for frame in read])
    assert np.allclose(scores[1], [0, 0, 0.5, 0, 0, 0, 1, 0, 0.3], atol=0.5 / 255)
    assert np.allclose(scores[3], [0, 0.02, 0, 0, 0, 0, 0, 0, 0], atol=0.5 / 255)  # the rest gone back to 0
    assert np.allclose(read[1].positions, rest @ turn.T, atol=0.01) and np.isnan(read[2].positions).all()


def codes_names(codes: PageCodes) -> list[str]:
    return [BLENDSHAPES[i] for i in codes.columns]


def _compact(frames: list[str], names: list[str]) -> list[bytes]:
    """The JSON frames of :func:`_frames` as compact ones (every score each time), for the scores ``names``."""
    out, before = [], 0
    for text in frames:
        message = json.loads(text)
        levels = [round(message["scores"].get(name, 0.0) * 255) for name in names]
        ms = round(message["t"])
        out.append(bytes([1]) + struct.pack("<H3h", ms - before, 0, 0, 0)
                   + bytes(np.packbits(np.ones(len(names), np.uint8), bitorder="little")) + bytes(levels))
        before = ms
    return out


def _frames(seconds: float, jaw: float, start: float = 0.0, down: float = 0.0) -> list[str]:
    """A page's messages at 25 frames a second, face front on, the jaw at ``jaw``, the eyes
    looking down by ``down`` (a score)."""
    matrix = np.eye(4)
    matrix[:3, 3] = [0, 0, -45]
    return [json.dumps({"t": (start + k / 25) * 1000, "matrix": matrix.T.ravel().tolist(),
                        "scores": {"jawOpen": jaw, "eyeLookDownLeft": down, "eyeLookDownRight": down}})
            for k in range(round(seconds * 25))]


@pytest.mark.slow  # the mapping's real-time sender (1.5 s each): make test runs them (make test-fast stays near 50 s)
@pytest.mark.parametrize(("key", "compact"), [(None, False), (KEY, True)], ids=["open-json", "sealed-compact"])
def test_a_performer_page_enters_the_room_as_a_stream_a_native_viewer_receives(key, compact):
    """The server first names the scores it reads; then a second of rest, then the jaw wide open
    (as JSON, or as compact frames of those scores): the viewer's mouth opens. Malformed messages
    are refused and counted; with the room's key the stream is sealed with it."""
    rooms = Rooms(TOKENS, key=key)
    with in_thread(rooms) as base:
        link = WebSocketLink(f"{base}/r/demo", TOKENS["demo"][1], "watch")
        with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), key=key, link=link) as receiver:

            async def perform() -> None:
                async with aiohttp.ClientSession() as session, session.ws_connect(
                        f"{base}/r/demo/ws?role=perform&format=face",
                        headers={"Authorization": f"Bearer {TOKENS['demo'][0]}"}) as ws:
                    names = json.loads((await ws.receive(timeout=10)).data)["scores"]
                    assert len(names) == 35 and "jawOpen" in names and "_neutral" not in names  # those arkit reads
                    assert names == sorted(names, key=BLENDSHAPES.index)
                    frames = _frames(1.0, 0.0) + _frames(1.0, 0.9, start=1.0)
                    for message in _compact(frames, names) if compact else frames:
                        await (ws.send_bytes(message) if isinstance(message, bytes) else ws.send_str(message))
                    await ws.send_str("not json")
                    await ws.send_bytes(b"\x00" * 8)
                    await asyncio.to_thread(receiver.wait_for_packets, 20, 10.0)

            asyncio.run(perform())
            values, _ = receiver.values_at()
    room = rooms.rooms["demo"]
    assert room.refused["malformed"] == 2
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
                    told = json.loads((await ws.receive(timeout=0.05)).data)  # the scores it reads, then what it says
                    said.extend([told["said"]] if "said" in told else [])
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
