"""Tokens stay out of every log (issue 70, item 1): the viewer page put its watch token in its
socket's address, which a TLS proxy's or the server's access log records; it now offers it among
the socket's subprotocols, native clients send a header, and a token in an address is refused."""

import asyncio
import logging
import threading
from contextlib import contextmanager

import aiohttp
import pytest
from room_pages import TOKENS, performer

from toonface.room.server import Rooms
from toonface.room.threaded import in_thread


@contextmanager
def logging_proxy(target_port: int):
    """A TCP proxy on a free port in front of ``target_port`` that logs what a web server's proxy
    logs of each request (nginx's "combined": the request line, Referer and User-Agent); yields
    its port and the list of lines logged."""
    lines: list[str] = []
    loop = asyncio.new_event_loop()
    ready = threading.Event()
    box: dict = {}

    async def pipe(reader, writer, log: bool) -> None:
        try:
            while data := await reader.read(65536):
                if log:
                    for line in data.split(b"\r\n"):
                        if line[:4] in (b"GET ", b"POST") or line.lower().startswith((b"referer:", b"user-agent:")):
                            lines.append(line.decode("latin-1"))
                writer.write(data)
                await writer.drain()
        except (ConnectionError, asyncio.CancelledError):
            pass
        finally:
            writer.close()

    async def handle(reader, writer) -> None:
        up_reader, up_writer = await asyncio.open_connection("127.0.0.1", target_port)
        await asyncio.gather(pipe(reader, up_writer, True), pipe(up_reader, writer, False))

    async def serve() -> None:
        server = await asyncio.start_server(handle, "127.0.0.1", 0)
        box["port"], box["stop"] = server.sockets[0].getsockname()[1], asyncio.Event()
        ready.set()
        await box["stop"].wait()
        server.close()

    thread = threading.Thread(target=lambda: loop.run_until_complete(serve()), daemon=True)
    thread.start()
    ready.wait(10)
    try:
        yield box["port"], lines
    finally:
        loop.call_soon_threadsafe(box["stop"].set)
        thread.join(10)
        loop.close()


@pytest.mark.slow  # Chromium: make test runs it
def test_no_token_reaches_the_servers_access_log_or_a_proxys(caplog):
    from browser import chromium, wait_for

    caplog.set_level(logging.INFO, logger="aiohttp.access")
    rooms = Rooms(TOKENS, face="cat")
    with in_thread(rooms) as base, performer(base, 0x2C) as one:
        port = int(base.rsplit(":", 1)[1])
        with logging_proxy(port) as (proxy, lines), chromium(900, 700) as driver:
            rooms.origins = (*rooms.origins, f"http://127.0.0.1:{proxy}")  # the page comes through the proxy
            one.start()
            for draw in ("page", "server"):
                driver.get(f"http://127.0.0.1:{proxy}/r/demo?draw={draw}#watch={TOKENS['demo'][1]}")
                wait_for(driver, "window.viewer.connected && window.viewer.frames > 10", timeout=30)

            async def in_the_address() -> int:
                async with aiohttp.ClientSession() as session:
                    try:
                        await session.ws_connect(f"ws://127.0.0.1:{proxy}/r/demo/ws?role=watch&token=in-the-address")
                    except aiohttp.WSServerHandshakeError as exc:
                        return exc.status
                    return 101

            refused = asyncio.run(in_the_address())
    logged = [record.getMessage() for record in caplog.records if record.name == "aiohttp.access"]
    assert any("/r/demo/ws?role=watch" in line for line in logged), logged  # the server's log holds the sockets
    assert any(line.startswith("GET /r/demo/ws?role=watch") for line in lines), lines  # and the proxy's
    assert refused == 400  # a token in an address (any: it is in the logs already) is refused, said
    for token in TOKENS["demo"]:
        assert not [line for line in (*logged, *lines) if token in line]
