"""The studio without a browser: the session's rules and the server's gate and messages."""

import asyncio
import json

import numpy as np
import pytest
from aiohttp.test_utils import TestClient, TestServer

from toon import MOTOR_CODES, motor_index
from toonface.cli import main
from toonface.studio.server import HOSTS, make_app
from toonface.studio.session import StudioSession


def test_dragging_a_point_inverts_the_range_and_the_head_turn():
    session = StudioSession("classic")
    lo, hi = session.face.ranges["MLV"]
    x, y = session.frame()["points"]["ML"]
    session.drag("ML", x, -(lo + 0.75 * (hi - lo)))  # SVG y is down
    assert session.values[motor_index("MLV")] == pytest.approx(0.75)
    session.set_motor("HH", 0.9)
    session.set_motor("HV", 0.2)
    for value in (0.2, 0.6):
        session.set_motor("MB", value)
        shown = session.frame()["points"]["MB"]  # where the page draws the point, head turned
        session.set_motor("MB", 0.5)
        session.drag("MB", *shown)
        assert session.values[motor_index("MB")] == pytest.approx(value, abs=1e-5)  # points sent to 1e-4
    session.drag("ML", 1e4, -1e4)  # far off: the ends of the ranges
    assert session.values[motor_index("MLV")] == 1.0 and session.values[motor_index("MLH")] in (0.0, 1.0)
    with pytest.raises(KeyError):
        session.drag("NOSE", 0, 0)


def test_a_pupil_dragged_to_where_it_is_drawn_keeps_its_gaze():
    session = StudioSession("classic")
    session.set_motor("PRH", 0.8)
    session.set_motor("PRV", 0.3)
    shown = session.frame()["points"]["PR"]
    session.reset()
    session.drag("PR", *shown)
    assert session.values[motor_index("PRH")] == pytest.approx(0.8, abs=1e-5)
    assert session.values[motor_index("PRV")] == pytest.approx(0.3, abs=1e-5)


def test_the_pointer_steers_only_when_following_and_a_slider_does_not_stop_a_motion():
    session = StudioSession("classic")
    session.look(1.0, -1.0)
    assert np.array_equal(session.values, session.neutral)
    session.follow = True
    session.look(1.0, -1.0)  # top right: head and eyes to their ends
    assert session.values[[motor_index(c) for c in ("HH", "HV", "PRH", "PLV")]].tolist() == [1.0] * 4
    session.look(0.0, 0.0)
    assert session.values[motor_index("HH")] == pytest.approx(session.neutral[motor_index("HH")])
    session.play("blink", now=0.0)
    session.tick(0.0)
    session.set_motor("MB", 0.7)  # during the blink
    lids = []
    for k in range(1, 12):
        session.tick(k / 30)
        lids.append(session.values[motor_index("ERU")])
    assert min(lids) == 0.0 and lids[-1] == pytest.approx(session.neutral[motor_index("ERU")])
    assert session.values[motor_index("MB")] == 0.7
    with pytest.raises(KeyError):
        session.play("dance", now=0.0)


def _talk(messages, origin="http://{host}", host=None):
    async def run():
        session = StudioSession("classic")
        server = TestServer(make_app(session, set()))
        async with TestClient(server) as client:
            client.app[HOSTS].add(f"127.0.0.1:{server.port}")
            page = await client.get("/", headers={"Host": host} if host else None)
            replies = []
            if page.status == 200:
                ws = await client.ws_connect("/ws", headers={"Origin": origin.format(host=f"127.0.0.1:{server.port}")})
                replies += [await ws.receive_json() for _ in range(4)]  # hello, the animation, the face, a frame
                for message in messages:
                    await ws.send_str(message if isinstance(message, str) else json.dumps(message))
                    replies.append(await ws.receive_json())
                await ws.close()
            return page.status, replies, session
    return asyncio.run(run())


def test_another_face_carries_the_motors_at_every_step_of_the_switch(monkeypatch):
    """The page's test thread (or a frame) reading the session during a switch sees the motors as
    set, never the new face at rest: the new face's animators start at the carried values."""
    import toonface.studio.session as studio_session

    session = StudioSession("classic")
    session.set_motor("MB", 0.7)
    session.set_motor("HT", 0.8)  # a parameter both faces have
    session.set_motor("HAIR", 0.9)  # classic's alone: cat has no hair
    seen = []
    made = studio_session.FaceEditor

    def watched(face):  # made after the face is loaded, while the switch is under way
        seen.append((session.face.name, float(session.values[motor_index("MB")]), session.extra_values()["HT"]))
        return made(face)

    monkeypatch.setattr(studio_session, "FaceEditor", watched)
    session.set_face("cat")
    assert seen == [("cat", 0.7, 0.8)]
    assert session.values[motor_index("MB")] == 0.7 and session.extra_values()["HT"] == 0.8
    assert "HAIR" not in session.extra_values() and session.extra_values()["WHISK"] == 0.5  # cat's own at rest


def test_the_server_serves_its_page_and_applies_messages():
    status, replies, session = _talk([{"op": "motor", "code": "MB", "value": 0.8}, {"op": "play", "name": "nope"},
                                      {"op": "jump"}, "not json", {"op": "drag", "point": "MB"}])
    assert status == 200
    assert replies[0]["type"] == "hello" and len([m for g in replies[0]["groups"] for m in g["motors"]]) == 21 + 5
    assert replies[0]["groups"][-1]["title"] == "Parameters"  # classic: HT UL JS CP HAIR
    assert replies[1]["type"] == "animation" and replies[1]["knots"] == {} and replies[1]["duration"] == 5.0
    assert replies[2]["type"] == "face" and replies[2]["doc"]["format"] == "toonface.face/1"
    assert replies[3]["type"] == "frame" and replies[3]["svg"].startswith("<svg")
    assert replies[4]["values"]["MB"] == 0.8 and session.values[motor_index("MB")] == 0.8
    assert [r["type"] for r in replies[5:]] == ["error"] * 4
    assert "'nope'" in replies[5]["message"] and "jump" in replies[6]["message"] and "'x'" in replies[8]["message"]


def test_the_server_refuses_other_hosts_and_other_origins():
    status, _, _ = _talk([], host="rebound.example:80")
    assert status == 403
    with pytest.raises(Exception, match="403"):
        _talk([], origin="http://evil.example")


def test_studio_command_errors_are_one_line(capsys):
    assert main(["studio", "--face", "nope"]) != 0
    assert main(["studio", "--listen", "127.0.0.1:70000"]) == 2
    assert main(["studio", "--receive", "8.8.8.8:7710"]) == 2
    assert main(["studio", "missing.toml"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 4 and 'no built-in face "nope"' in err[0] and "--listen" in err[1]
    assert "cannot receive on 8.8.8.8:7710" in err[2] and "missing.toml" in err[3]


def test_every_motor_and_standard_parameter_has_a_name_a_designer_reads():
    """The panels' and staves' names (issue 46): each motor's and standard parameter's own, none
    twice, each saying which way 1 lies where a motor turns or looks."""
    described = StudioSession("classic").describe()
    motors = [m for group in described["groups"] for m in group["motors"]]
    names = {m["code"]: m["name"] for m in motors}
    assert set(names) >= set(MOTOR_CODES) | {"HT", "UL", "JS", "CP"}
    standard = [names[c] for c in (*MOTOR_CODES, "HT", "UL", "JS", "CP")]
    assert len(set(standard)) == len(standard) and all(n and n not in MOTOR_CODES for n in standard)
    assert names["PLH"] == "Left eye looks left" and names["HV"] == "Head tips back" and names["MB"] == "Mouth open"
    assert names["HAIR"] == "HAIR"  # a face's own parameter keeps the name its designer gave
