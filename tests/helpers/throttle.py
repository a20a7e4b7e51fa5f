"""A slow link for the room's tests: a TCP proxy on loopback that passes what the server sends at
a given rate, queueing the rest without bound (a router that buffers all: the worst case, where a
server sees no back-pressure at all), and what the client sends at once.

It runs on real time (the link's rate is the thing tested), in a thread of its own.
"""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def throttled(port: int, kbps: float) -> Iterator[int]:
    """A proxy to ``127.0.0.1:port`` whose way back carries ``kbps`` kbit/s of payload; yields its
    own port, and stops with every connection at the end."""
    loop = asyncio.new_event_loop()
    started: list[int] = []
    ready = threading.Event()
    stop = asyncio.Event()

    async def main() -> None:
        server = await asyncio.start_server(lambda r, w: _carry(r, w, port, kbps * 1000 / 8), "127.0.0.1", 0)
        started.append(server.sockets[0].getsockname()[1])
        ready.set()
        await stop.wait()
        server.close()
        carrying = [task for task in asyncio.all_tasks() if task is not asyncio.current_task()]
        for task in carrying:
            task.cancel()
        await asyncio.gather(*carrying, return_exceptions=True)

    thread = threading.Thread(target=loop.run_until_complete, args=(main(),), daemon=True)
    thread.start()
    ready.wait(10)
    try:
        yield started[0]
    finally:
        loop.call_soon_threadsafe(stop.set)
        thread.join(10)
        loop.close()


async def _carry(client_in: asyncio.StreamReader, client_out: asyncio.StreamWriter, port: int,
                 bytes_per_second: float) -> None:
    server_in, server_out = await asyncio.open_connection("127.0.0.1", port)
    tasks = [asyncio.create_task(_pipe(client_in, server_out)),
             asyncio.create_task(_slowly(server_in, client_out, bytes_per_second))]
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
    except asyncio.CancelledError:
        pass  # the proxy stops: end quietly (asyncio's stream server logs a handler that ends cancelled)
    finally:
        for task in tasks:
            task.cancel()
        for writer in (client_out, server_out):
            writer.close()


async def _pipe(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    while data := await reader.read(65536):
        writer.write(data)
        await writer.drain()


async def _slowly(reader: asyncio.StreamReader, writer: asyncio.StreamWriter, bytes_per_second: float) -> None:
    """Everything ``reader`` gives, taken at once and queued, passed on at the rate."""
    queue: asyncio.Queue[bytes] = asyncio.Queue()

    async def take() -> None:
        while data := await reader.read(65536):
            queue.put_nowait(data)
        queue.put_nowait(b"")

    taking = asyncio.create_task(take())
    loop = asyncio.get_running_loop()
    free = loop.time()
    try:
        while data := await queue.get():
            for at in range(0, len(data), 256):  # a piece at a time, each when the link has carried the last
                piece = data[at:at + 256]
                free = max(free, loop.time()) + len(piece) / bytes_per_second
                await asyncio.sleep(free - loop.time())
                writer.write(piece)
                await writer.drain()
    finally:
        taking.cancel()
