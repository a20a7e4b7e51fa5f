"""The studio under attack: numbers that are not numbers, files outside its folder, other hosts
and origins, a secret for other machines, and hostile messages (hypothesis) to a running server."""

import asyncio
import json
import logging

import pytest
from aiohttp.test_utils import TestClient, TestServer
from fuzzing import fuzz_settings
from hypothesis import given
from hypothesis import strategies as st

from toon import MOTOR_CODES
from toonface.studio.guard import MAX_DEPTH, Folder, parse_message
from toonface.studio.messages import EDITOR_OPS, FACE_ACTIONS, UNIT_ACTIONS
from toonface.studio.server import HOSTS, make_app, serve
from toonface.studio.session import StudioSession
from toonface.web_hosts import ANY_ADDRESS, host_allowed, is_loopback


def _strict(text: str) -> object:
    """JSON as a browser's JSON.parse reads it: NaN and Infinity are errors."""
    def refuse(name):
        raise ValueError(f"{name} in a message to the page")
    return json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize("text", ['{"op": "motor", "code": "MB", "value": NaN}', '{"value": Infinity}',
                                  '{"value": -Infinity}', '{"value": 1e400}', '{"index": 1e300}',
                                  '{"x": ' + "9" * 5000 + "}", "[" * (MAX_DEPTH + 1) + "]" * (MAX_DEPTH + 1),
                                  "[" * 100000, '{"path": "' + "a" * 60000 + '"}', "{nope"])
def test_a_message_outside_the_limits_is_refused_in_one_line(text):
    with pytest.raises(ValueError) as caught:
        parse_message(text)
    assert "\n" not in str(caught.value) and len(str(caught.value)) < 200


def test_a_message_within_the_limits_is_parsed():
    assert parse_message('{"op": "knot", "action": "move", "index": 2, "t": 1.5, "codes": ["MB"]}') == {
        "op": "knot", "action": "move", "index": 2, "t": 1.5, "codes": ["MB"]}


def test_files_only_inside_the_folder_and_never_their_content(tmp_path):
    root, outside = tmp_path / "work", tmp_path / "elsewhere"
    root.mkdir()
    outside.mkdir()
    (outside / "secret.txt").write_text("SECRET-FIRST-LINE\n")
    (root / "link.txt").symlink_to(outside / "secret.txt")
    folder = Folder(root.resolve())
    assert folder.inside("sub/../a.toml") == root.resolve() / "a.toml"
    for bad in ("../elsewhere/secret.txt", str(outside / "secret.txt"), "link.txt", "/etc/shadow", "a\x00b", ""):
        with pytest.raises(ValueError, match="outside|expected a file name"):
            folder.inside(bad)
    assert folder.name_or_inside("toon32") == "toon32" and folder.name_or_inside("my.json") == str(root / "my.json")

    session = StudioSession("classic", folder=folder)
    replies = _talk_to(session, [{"op": "new"}, {"op": "sound", "path": "../elsewhere/secret.txt"},
                                 {"op": "labels", "path": "link.txt"}, {"op": "save", "path": "../elsewhere/a.toml"},
                                 {"op": "faceedit", "action": "save", "path": str(outside / "f.json")},
                                 {"op": "faceedit", "action": "open", "name": "/etc/passwd"},
                                 {"op": "tune", "action": "open", "take": "../elsewhere/secret.txt"},
                                 {"op": "save", "path": "mine.toml"}])
    errors = [r["message"] for got in replies for r in got if r["type"] == "error"]
    assert len(errors) == 6 and all("outside" in e for e in errors), errors
    assert not any("SECRET" in json.dumps(r) for r in replies)
    assert sorted(p.name for p in outside.iterdir()) == ["secret.txt"]  # nothing written there
    assert (root / "mine.toml").is_file()  # inside, as before


def test_nan_and_huge_numbers_get_an_error_and_every_frame_stays_json():
    """A motor message with NaN put a bare NaN in every later frame; scale_time with NaN saved a
    file the studio could not reopen; an Infinity index dropped the socket."""
    session = StudioSession("classic")
    replies = _talk_to(session, [
        '{"op": "motor", "code": "MB", "value": NaN}', {"op": "motor", "code": "MB", "value": "nan"},
        {"op": "slice", "action": "scale_time", "start": 0, "end": 1, "factor": "nan"},
        {"op": "slice", "action": "scale_time", "start": 0, "end": 5, "factor": 1e6},
        '{"op": "knot", "action": "move", "code": "MB", "index": Infinity, "t": 0, "v": 0}',
        {"op": "knot", "action": "delete", "code": "MB", "index": 1e300},
        {"op": "paste", "at": 1e300}, {"op": "cursor", "t": -1e300},
        {"op": "duration", "seconds": 1e300}, {"op": "motor", "code": "MB", "value": 0.25}])
    assert [[r["type"] for r in got] for got in replies[:9]] == [["error"]] * 9, replies
    assert replies[-1][-1]["type"] == "frame" and replies[-1][-1]["values"]["MB"] == 0.25
    assert session.editor.animation.duration == 5.0


def _talk_to(session, messages):
    """Send each message to a running studio and collect, for each, what the page got back
    (an error, a line said, the state that changed), up to the reply to a message of its own."""
    async def run():
        server = TestServer(make_app(session, set()))
        async with TestClient(server) as client:
            host = f"127.0.0.1:{server.port}"
            client.app[HOSTS].add(host)
            ws = await client.ws_connect("/ws", headers={"Origin": f"http://{host}"})
            for _ in range(4):
                await ws.receive_str()
            replies = []
            for message in messages:
                await ws.send_str(message if isinstance(message, str) else json.dumps(message))
                await ws.send_str('{"op": "sync"}')
                replies.append([])
                while (reply := _strict(await asyncio.wait_for(ws.receive_str(), 30)))["type"] != "error" \
                        or "'sync'" not in reply["message"]:
                    replies[-1].append(reply)
            await ws.close()
            return replies
    return asyncio.run(run())


def test_hosts_the_studio_answers():
    ours = {"127.0.0.1:8765", "studio.lan:8765"}
    assert host_allowed("studio.lan:8765", ours) and not host_allowed("rebound.example:8765", ours)
    assert not host_allowed("10.0.0.5:8765", ours)
    every = ours | {ANY_ADDRESS}
    assert host_allowed("10.0.0.5:8765", every) and host_allowed("[fe80::1]:8765", every)
    assert not host_allowed("rebound.example:8765", every) and not host_allowed("10.0.0.5.nip.io:8765", every)
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.4")


def test_a_studio_other_machines_reach_asks_for_its_secret():
    """--listen 0.0.0.0 turned the Host check off and compared Origin with the attacker's Host,
    so a DNS-rebinding page got a working socket."""
    async def run():
        session, printed = StudioSession("classic"), []
        ready = asyncio.Event()
        task = asyncio.create_task(serve(session, "0.0.0.0", 0, lambda url: (printed.append(url), ready.set()),
                                         allow=("studio.lan",)))
        await asyncio.wait_for(ready.wait(), 10)
        url = printed[0]
        port = int(url.split(":")[2].split("/")[0])
        token = url.split("?token=")[1]
        import aiohttp

        async with aiohttp.ClientSession(cookie_jar=aiohttp.CookieJar(unsafe=True)) as http:  # keeps an IP's cookies
            base = f"http://127.0.0.1:{port}"

            async def status(path, host, **kwargs):
                async with http.get(base + path, headers={"Host": host, **kwargs.pop("headers", {})}, **kwargs) as r:
                    return r.status

            assert await status("/", f"rebound.example:{port}") == 403  # DNS rebinding
            assert await status(f"/?token={token}", f"rebound.example:{port}") == 403
            assert await status("/", f"10.1.2.3:{port}") == 403  # no secret
            assert await status("/?token=wrong", f"10.1.2.3:{port}") == 403
            assert await status(f"/?token={token}", f"studio.lan:{port}") == 200  # the cookie is set now
            ws = await http.ws_connect(base + "/ws", headers={"Host": f"studio.lan:{port}",
                                                             "Origin": f"http://studio.lan:{port}"})
            assert json.loads((await ws.receive()).data)["type"] == "hello"
            await ws.close()
            for origin in (f"https://studio.lan:{port}", f"http://rebound.example:{port}", "null"):
                with pytest.raises(aiohttp.WSServerHandshakeError, match="403"):
                    await http.ws_connect(base + "/ws", headers={"Host": f"studio.lan:{port}", "Origin": origin})
        async with aiohttp.ClientSession() as stranger:  # no cookie: the page was never opened with the secret
            with pytest.raises(aiohttp.WSServerHandshakeError, match="403"):
                await stranger.ws_connect(base + "/ws", headers={"Host": f"10.1.2.3:{port}",
                                                                 "Origin": f"http://10.1.2.3:{port}"})
        task.cancel()
        with pytest.raises(asyncio.CancelledError):
            await task
        return url

    url = asyncio.run(run())
    assert url.startswith("http://127.0.0.1:") and "?token=" in url


# -- fuzz: random and hostile messages to one running studio -------------------------------------

OPS = ["motor", "drag", "look", "follow", "play", "reset", "face", "live", "sound", "labels", "hear", "tune",
       "faceedit", "render", *EDITOR_OPS, "nope"]
ACTIONS = ["add", "move", "delete", "cut", "copy", "flip", "scale_time", "scale_value", "play", "pause", "open",
           "save", "undo", "redo", *FACE_ACTIONS, *[f"{verb}_{kind}" for verb in UNIT_ACTIONS
                                                     for kind in ("polygon", "component")],
           "set_style", "set_component", "paste", "motor", "rule", "range", "save_mapping", "save_profile"]
PATHS = ["../x.toml", "/etc/shadow", "a" * 5000, "x.toml", "sub/../../y.csv", "", "s.mp4", "f.json", "toon32",
         "classic", "~/.bashrc", "nan", "x\x00y"]
NUMBERS = st.one_of(st.integers(-10**7, 10**7), st.floats(allow_nan=False, allow_infinity=False),
                    st.sampled_from([1e300, -1e300, 5e-324, 0, -1, 0.5, 2]))
SCALARS = st.one_of(st.none(), st.booleans(), NUMBERS, st.sampled_from(PATHS + list(MOTOR_CODES)),
                    st.text(max_size=12))
VALUES = st.recursive(SCALARS, lambda inner: st.lists(inner, max_size=4) | st.dictionaries(
    st.sampled_from(["M", "x", "color", "fill", "width", "BLM"]), inner, max_size=3), max_leaves=8)
FIELDS = ["code", "value", "point", "x", "y", "on", "name", "loop", "path", "action", "index", "t", "v", "codes",
          "start", "end", "factor", "at", "onto", "seconds", "rate", "fps", "take", "mapping", "units", "kind",
          "polygon", "component", "part", "after", "indices", "library", "use", "controls", "dx", "dy", "fields",
          "field", "key", "neutral", "low", "high", "axis", "color", "size", "master", "description"]
#: Each op with the fields it reads, for messages that get past the first look.
OP_FIELDS = {"motor": "code value", "drag": "point x y", "look": "x y", "follow": "on", "play": "name loop",
             "face": "name", "live": "on", "sound": "path", "labels": "path", "knot": "action code t v index",
             "slice": "action codes start end factor", "paste": "at onto", "cursor": "t",
             "playback": "action start end loop", "duration": "seconds", "new": "seconds", "open": "path",
             "save": "path", "sample": "path rate", "render": "path fps",
             "tune": "action take code field value key neutral low high path"}
HOSTILE = st.one_of(NUMBERS, SCALARS, st.sampled_from(["MB", "ML", "blink", "smile", "HH", "PR"]))


def _shaped(op: str, fields: str, action: str | None = None):
    keys = {key: HOSTILE for key in fields.split() if key != "action"}
    return st.fixed_dictionaries({"op": st.just(op), **({"action": st.just(action)} if action else {}), **keys})


SHAPED = st.one_of(
    *[_shaped(op, fields, None) for op, fields in OP_FIELDS.items() if "action" not in fields],
    *[_shaped(op, fields, action) for op, fields in OP_FIELDS.items() if "action" in fields
      for action in ("add", "move", "delete", "cut", "copy", "flip", "scale_time", "scale_value", "play", "pause",
                     "open", "motor", "rule", "range", "save_mapping", "save_profile")],
    *[_shaped("faceedit", " ".join(key.rstrip("?") for key in keys), action) for action, keys in FACE_ACTIONS.items()],
    *[_shaped("faceedit", " ".join((kind, *keys)), f"{verb}_{kind}") for verb, keys in UNIT_ACTIONS.items()
      for kind in ("polygon", "component")])
MESSAGES = st.one_of(
    SHAPED,
    st.fixed_dictionaries({"op": st.sampled_from(OPS), "action": st.sampled_from(ACTIONS)},
                          optional={field: VALUES for field in FIELDS if field != "action"}),
    st.sampled_from(['{"op": "motor", "code": "MB", "value": NaN}', "[" * 200, "null", "[]", '"op"', "{}",
                     '{"op": "knot", "action": "move", "code": "MB", "index": Infinity, "t": 0, "v": 0}',
                     '{"op": "open", "path": "' + "p" * 60000 + '"}', '{"op": "face", "name": "\\udcff"}', "1e999"]))


@pytest.mark.slow
@fuzz_settings(150)
@given(messages=st.lists(MESSAGES, min_size=5, max_size=25))
def test_hostile_messages_get_replies_and_never_a_traceback(tmp_path, caplog, messages):
    caplog.set_level(logging.ERROR)
    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    replies = _talk_to(session, messages)
    assert len(replies) == len(messages) and all(replies), replies  # each message answered
    assert not [r for r in caplog.records if r.levelno >= logging.ERROR], [r.getMessage() for r in caplog.records]
    assert sorted(p.name for p in tmp_path.parent.iterdir() if p.name.startswith("x") or p.name == "y.csv") == []


def test_a_label_file_error_names_the_line_not_its_text(tmp_path):
    from common import InputError
    from toonface.studio.sound import load_labels

    (tmp_path / "l.txt").write_text("0.1\t0.2\tfine\nSECRET-FIRST-LINE\n")
    with pytest.raises(InputError, match="line 2") as caught:
        load_labels(tmp_path / "l.txt")
    assert "SECRET" not in str(caught.value)
