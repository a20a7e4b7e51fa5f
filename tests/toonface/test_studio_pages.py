"""Each page's own queue: a page that stops reading loses frames, nobody else does."""

import asyncio
import contextlib
import json
import socket
from collections.abc import AsyncIterator

import pytest
from aiohttp.test_utils import TestClient, TestServer

from toonface.studio.pages import QUEUE_LIMIT, Page, broadcast
from toonface.studio.server import HOSTS, PAGES, make_app
from toonface.studio.session import StudioSession


class FakeSocket:
    """A page's socket: one that takes every message, one that is closing, or one that never
    finishes a send (a client that stopped reading, once the buffers are full)."""

    def __init__(self, kind: str) -> None:
        self.kind, self.got, self.closed, self.close_code = kind, [], False, None

    async def send_str(self, text: str) -> None:
        if self.kind == "closing":
            raise ConnectionResetError("Cannot write to closing transport")
        if self.kind == "stuck":
            await asyncio.Event().wait()
        self.got.append(json.loads(text))

    async def close(self, code: int, message: bytes) -> None:
        self.closed, self.close_code = True, code


def test_a_page_that_stops_reading_loses_frames_and_the_others_get_every_one():
    async def run():
        sockets = {kind: FakeSocket(kind) for kind in ("alive", "closing", "stuck")}
        pages = {Page(ws) for ws in sockets.values()}  # type: ignore[arg-type]
        for k in range(200):
            broadcast(pages, {"type": "frame", "k": k})
            await asyncio.sleep(0)  # the writers run between two ticks
        stuck = next(p for p in pages if p.ws is sockets["stuck"])
        assert [m["k"] for m in sockets["alive"].got] == list(range(200))  # nothing lost
        assert stuck.dropped == 200 - 1 - QUEUE_LIMIT and stuck.open  # one in its send, 16 waiting
        for k in range(QUEUE_LIMIT + 1):  # replies it must get and does not read: it is closed
            stuck.send({"type": "error", "k": k})
        await asyncio.sleep(0)
        assert not stuck.open
        await stuck.close()  # its closing finished
        assert sockets["stuck"].closed and sockets["stuck"].close_code == 1008
        broadcast(pages, {"type": "frame", "k": 200})
        await asyncio.sleep(0)
        assert sockets["alive"].got[-1]["k"] == 200
        for page in pages:
            await page.close()

    asyncio.run(run())


def test_a_page_with_a_full_queue_drops_what_a_later_message_replaces():
    async def run():
        ws = FakeSocket("alive")
        page = Page(ws, limit=3)  # type: ignore[arg-type]
        for message in ({"type": "frame", "k": 0}, {"type": "said", "k": 1}, {"type": "animation", "k": 2},
                        {"type": "frame", "k": 3}, {"type": "animation", "k": 4}, {"type": "error", "k": 5}):
            page.send(message)  # no await: the writer has not run yet
        await asyncio.sleep(0)
        assert [m["k"] for m in ws.got] == [1, 4, 5] and page.dropped == 3 and page.open
        await page.close()

    asyncio.run(run())


def test_nan_is_never_sent_to_a_page():
    async def run():
        page = Page(FakeSocket("alive"))  # type: ignore[arg-type]
        with pytest.raises(ValueError):
            page.send({"type": "frame", "value": float("nan")})
        await page.close()

    asyncio.run(run())


@contextlib.asynccontextmanager
async def _served() -> AsyncIterator[tuple[TestClient, str]]:
    """A studio on the classic face served on a free port: its test client and its host, allowed."""
    server = TestServer(make_app(StudioSession("classic"), set()))
    async with TestClient(server) as client:
        host = f"127.0.0.1:{server.port}"
        client.app[HOSTS].add(host)
        yield client, host


@pytest.mark.slow
def test_a_client_that_never_reads_does_not_freeze_the_other_pages():
    """Over real sockets: one client completes the handshake and never reads; the other page
    goes on getting frames at the loop's rate while the first one's buffers fill."""
    async def run():
        async with _served() as (client, host):
            silent = socket.socket()
            silent.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            silent.connect(("127.0.0.1", client.port))
            silent.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}\r\nOrigin: http://{host}\r\nUpgrade: websocket\r\n"
                            "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                            "Sec-WebSocket-Version: 13\r\n\r\n").encode())
            ws = await client.ws_connect("/ws", headers={"Origin": f"http://{host}"})
            for _ in range(4):
                await ws.receive_json()
            await ws.send_json({"op": "play", "name": "blink", "loop": True})  # frames every loop from now
            frames = 0
            while frames < 600:  # 20 s of frames at 30/s; each carries the face's SVG
                message = await asyncio.wait_for(ws.receive_json(), timeout=5)
                frames += message["type"] == "frame"
            stalled = [p for p in client.app[PAGES] if p.dropped]
            assert len(stalled) == 1 and stalled[0].dropped > 100  # the silent one lost frames
            silent.close()
            await ws.close()

    asyncio.run(run())


def test_a_face_edit_is_answered_to_the_page_that_made_it_and_its_face_goes_to_every_page():
    """Every page gets the face an edit made, so a page that waits for its own edit to be done
    before sending the next cannot go by the face: the page that made it is told, the others not
    (a second page took the first one's faces as answers and sent its next edit early)."""
    async def until_answered(page, count: int) -> list[tuple]:
        seen: list[tuple] = []
        while sum(kind == "answered" for kind, _ in seen) < count:
            message = await asyncio.wait_for(page.receive_json(), timeout=10)
            if message["type"] in ("face", "answered", "error"):
                seen.append((message["type"], message.get("doc", {}).get("name", message.get("op"))))
        return seen

    async def run():
        async with _served() as (client, host):
            first, second = [await client.ws_connect("/ws", headers={"Origin": f"http://{host}"}) for _ in range(2)]
            await first.send_json({"op": "faceedit", "action": "rename", "name": "one"})
            await first.send_json({"op": "faceedit", "action": "nonsense"})  # refused: an error, no answer
            await first.send_json({"op": "motor", "code": "MB", "value": 0.5})  # not an edit of the face: no answer
            await first.send_json({"op": "motor", "code": "nonsense", "value": 0.5})  # refused, and says whose
            await first.send_json({"op": "faceedit", "action": "rename", "name": "two"})
            mine = await until_answered(first, 2)
            assert mine[-6:] == [("face", "one"), ("answered", "faceedit"), ("error", "faceedit"), ("error", "motor"),
                                 ("face", "two"), ("answered", "faceedit")]
            await second.send_json({"op": "faceedit", "action": "rename", "name": "three"})
            theirs = await until_answered(second, 1)  # what the first page's edits sent it came before
            assert theirs[-4:] == [("face", "one"), ("face", "two"), ("face", "three"), ("answered", "faceedit")]
            for page in (first, second):
                await page.close()

    asyncio.run(run())
