"""The room server under hostile messages and connections (issue 67, cases 6, 7 and 8): a
performer page's malformed JSON is refused and counted without a traceback, half-open requests are
closed after the header time-out, the pages tell no room apart and sockets take only their own
origins. Fuzz tests run under a memory cap (:mod:`capped`)."""

from __future__ import annotations

import asyncio
import json
import logging
import socket
import time

import aiohttp
import pytest
from capped import capped_memory
from fuzzing import fuzz_settings
from hypothesis import example, given
from hypothesis import strategies as st

from common.limits import parse_json_message
from toonface.room.performers import page_frame

# 6, 7, 8: the room server ------------------------------------------------------------------------

TOKENS = {"demo": ("perform-secret-0123456789", "watch-secret-0123456789")}
HOSTILE_MESSAGES = ['{"t": 1, "scores": {}, "matrix": null}', '{"t": 1, "scores": {}, "matrix": "abc"}',
                    "[" * 1300 + "]" * 1300, '{"t": ' + "9" * 4000 + "}", '{"t": 1, "scores": {"jawOpen": 1' +
                    "0" * 400 + "}}", '{"t": 1e400}', '{"t": NaN}']


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_a_performer_pages_hostile_messages_are_refused_and_the_page_stays(caplog):
    from toonface.room.server import Rooms
    from toonface.room.threaded import in_thread

    rooms = Rooms(TOKENS)
    with caplog.at_level(logging.WARNING), in_thread(rooms) as base:
        async def perform() -> bool:
            async with aiohttp.ClientSession() as session, session.ws_connect(
                    f"{base}/r/demo/ws?role=perform&format=face",
                    headers={"Authorization": f"Bearer {TOKENS['demo'][0]}"}) as ws:
                for text in HOSTILE_MESSAGES:
                    await ws.send_str(text)
                await ws.send_str('{"t": 5}')
                try:  # nothing comes back; a dropped connection would close it
                    message = await ws.receive(timeout=1.0)
                except TimeoutError:
                    return not ws.closed
                return message.type not in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED)

        stayed = asyncio.run(perform())
    assert stayed and rooms.rooms["demo"].refused["malformed"] == len(HOSTILE_MESSAGES)
    assert not [r for r in caplog.records if r.exc_info or "Traceback" in r.getMessage()]


json_values = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
                           lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=5), inner,
                                                                                         max_size=4), max_leaves=30)


@given(value=st.fixed_dictionaries({"t": json_values}, optional={"scores": json_values, "matrix": json_values}),
       depth=st.integers(0, 40))
@pytest.mark.slow  # over a second: make test runs it, test-fast does not
@example(value={"t": 1, "scores": {}, "matrix": None}, depth=0)
@example(value={"t": 10**400}, depth=0)
@example(value={"t": 1, "scores": {"jawOpen": 10**400}}, depth=0)
@example(value={"t": 1}, depth=1300)
@fuzz_settings(150)
def test_fuzz_a_performer_pages_messages_are_frames_or_value_errors(value, depth):
    from capture.listening import head_references

    text = "[" * depth + json.dumps(value) + "]" * depth
    with capped_memory():
        try:
            page_frame(text, head_references()[1])
        except ValueError:
            pass


def test_json_messages_are_parsed_within_bounds():
    assert parse_json_message('{"t": 1700000000000.5}') == {"t": 1700000000000.5}
    for bad in ("[" * 17 + "]" * 17, "1" * 33, "1." + "1" * 40, "-Infinity", "1e999"):
        with pytest.raises(ValueError):
            parse_json_message(bad)


def test_half_open_requests_are_closed_after_the_header_time_out():
    from aiohttp import web

    from toonface.room.server import Rooms, make_runner

    loop = asyncio.new_event_loop()

    async def serve() -> tuple[web.AppRunner, int]:
        runner = make_runner(Rooms(TOKENS), header_timeout=0.5)
        await runner.setup()
        site = web.TCPSite(runner, "127.0.0.1", 0)
        await site.start()
        return runner, runner.addresses[0][1]

    runner, port = loop.run_until_complete(serve())
    sockets = [socket.create_connection(("127.0.0.1", port)) for _ in range(50)]
    try:
        for s in sockets:
            s.sendall(b"GET /r/demo HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # never finished
            s.settimeout(5.0)
        started = time.perf_counter()
        closed = loop.run_until_complete(_all_closed(loop, sockets))
        assert closed == len(sockets) and time.perf_counter() - started < 3.0
    finally:
        for s in sockets:
            s.close()
        loop.run_until_complete(runner.cleanup())
        loop.close()


async def _all_closed(loop: asyncio.AbstractEventLoop, sockets: list[socket.socket]) -> int:
    """How many of ``sockets`` the server closed (a read returns nothing) within their time-out;
    the server's timers run in ``loop`` meanwhile."""
    async def closed(s: socket.socket) -> bool:
        try:
            return await loop.run_in_executor(None, s.recv, 1) == b""
        except TimeoutError:
            return False
        except OSError:  # reset by the server
            return True
    return sum(await asyncio.gather(*(closed(s) for s in sockets)))


def test_room_pages_tell_no_room_apart_and_sockets_take_only_their_own_origins():
    from toonface.room.server import Rooms
    from toonface.room.threaded import in_thread

    rooms = Rooms(TOKENS, origins=["https://face.example"])
    with in_thread(rooms) as base:
        http = base.replace("ws://", "http://")
        host = http.removeprefix("http://")

        async def probe() -> tuple:
            async with aiohttp.ClientSession() as session:
                pages = []
                for name in ("demo", "nosuch"):
                    async with session.get(f"{http}/r/{name}") as response:
                        pages.append((response.status, await response.text()))
                    async with session.get(f"{http}/r/{name}/perform") as response:
                        pages.append((response.status, await response.text()))
                statuses = {}
                for origin, host_header in (("http://evil.com", "evil.com"), ("http://evil.com:80", None),
                                            (f"http://{host}", None), ("https://face.example", None)):
                    headers = {"Origin": origin, **({"Host": host_header} if host_header else {})}
                    try:
                        async with session.ws_connect(f"{base}/r/demo/ws?role=watch", headers={
                                **headers, "Authorization": f"Bearer {TOKENS['demo'][1]}"}) as ws:
                            statuses[origin] = 101
                            await ws.close()
                    except aiohttp.WSServerHandshakeError as exc:
                        statuses[origin] = exc.status
                return pages, statuses

        pages, statuses = asyncio.run(probe())
    assert pages[0] == pages[2] and pages[1] == pages[3] and pages[0][0] == 200
    assert statuses == {"http://evil.com": 403, "http://evil.com:80": 403, f"http://{host}": 101,
                        "https://face.example": 101}
