"""A room server in a thread of its own, for tests and benchmarks (:mod:`toonface.room.server`)."""

from __future__ import annotations

import asyncio
import ssl
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from aiohttp import web

from toonface.room.server import Rooms, make_runner
from toonface.web_hosts import listen_hosts


@contextmanager
def in_thread(rooms: Rooms, host: str = "127.0.0.1", port: int = 0, ssl_context: ssl.SSLContext | None = None,
              reuse_port: bool = False) -> Iterator[str]:
    """A room server for ``rooms`` in a thread of its own (port 0: a free one; ``reuse_port``: a
    port other servers listen on too), for tests and benchmarks; yields its ``ws://HOST:PORT``
    (``wss://`` with ``ssl_context``) and stops on exit, closing its connections."""
    loop = asyncio.new_event_loop()
    started = threading.Event()
    box: dict = {}

    async def serve() -> None:
        runner = make_runner(rooms)
        await runner.setup()
        await web.TCPSite(runner, host, port, ssl_context=ssl_context, reuse_port=reuse_port).start()
        box["port"], box["stop"] = runner.addresses[0][1], asyncio.Event()
        rooms.hosts |= listen_hosts(host, box["port"])
        started.set()
        await box["stop"].wait()
        await runner.cleanup()

    thread = threading.Thread(target=lambda: loop.run_until_complete(serve()), daemon=True)
    thread.start()
    if not started.wait(10):
        raise OSError(f"the room server did not start on {host}:{port}")
    try:
        yield f"{'wss' if ssl_context else 'ws'}://{host}:{box['port']}"
    finally:
        loop.call_soon_threadsafe(box["stop"].set)
        thread.join(10)
        loop.close()
