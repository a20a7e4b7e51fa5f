"""The pages connected to a studio, each with its own bounded queue of messages to send.

The ticker used to await each page's send in turn, so one page that stopped reading (a tab in
the background, a client on a stalled link) froze every page for good once its socket's
buffers filled. Now the server only puts a message in each page's queue, and one writer task
per page drains it: a slow page loses frames, nobody else does.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
from collections import deque

from aiohttp import web

#: Messages a page must get, each of them: what it asked for was done, or why not. Every other
#: kind (a frame, the animation, the face...) says all that an earlier one of its kind said.
UNIQUE = frozenset({"said", "error", "rendered", "answered"})
#: Messages a page may lose even with no later one queued: the next tick sends another.
TRANSIENT = frozenset({"frame", "quality", "rendering"})
#: The messages waiting for one page before its frames are dropped.
QUEUE_LIMIT = 16
#: Seconds to wait for a page that stopped reading to take its close (the socket's heartbeat
#: drops it later otherwise).
CLOSE_WAIT = 5.0


class Page:
    """One page's socket and the messages waiting for it.

    Parameters
    ----------
    ws : web.WebSocketResponse
        The page's socket, prepared.
    limit : int
        The most messages waiting; beyond it the oldest one that a later one of its kind
        replaces (a frame, the animation's staves, a quality readout) is dropped, else the
        oldest frame, and a page whose queue holds nothing to drop is closed: it has stopped
        reading.

    Attributes
    ----------
    dropped : int
        Messages dropped so far because the page did not keep up.
    """

    def __init__(self, ws: web.WebSocketResponse, limit: int = QUEUE_LIMIT) -> None:
        self.ws = ws
        self.limit = limit
        self.dropped = 0
        self._queue: deque[tuple[str, str]] = deque()
        self._ready = asyncio.Event()
        self._writer = asyncio.create_task(self._write())
        self._closer: asyncio.Task | None = None

    @property
    def open(self) -> bool:
        """Whether messages still reach the page."""
        return not self.ws.closed and not self._writer.done()

    def send(self, message: dict) -> None:
        """Queue ``message`` (a JSON object with a ``type``) for the page; never waits."""
        self.put(str(message.get("type")), json.dumps(message, allow_nan=False))

    def put(self, kind: str, text: str) -> None:
        """Queue the JSON ``text`` of a message of type ``kind``; never waits."""
        if not self.open:
            return
        if len(self._queue) >= self.limit:
            kinds = [queued for queued, _ in self._queue] + [kind]
            stale = next((k for k, queued in enumerate(kinds[:-1]) if queued not in UNIQUE and queued in kinds[k + 1:]),
                         next((k for k, queued in enumerate(kinds[:-1]) if queued in TRANSIENT), None))
            if stale is None:
                self._abandon()
                return
            del self._queue[stale]
            self.dropped += 1
        self._queue.append((kind, text))
        self._ready.set()

    async def _write(self) -> None:
        while True:
            await self._ready.wait()
            self._ready.clear()
            while self._queue:
                _, text = self._queue.popleft()
                try:
                    await self.ws.send_str(text)
                except (ConnectionResetError, RuntimeError):  # the page went away meanwhile
                    return

    def _abandon(self) -> None:
        """Stop writing to a page that has stopped reading, and close its socket."""
        self._writer.cancel()
        self._queue.clear()
        if self._closer is None:
            self._closer = asyncio.create_task(asyncio.wait_for(
                self.ws.close(code=1008, message=b"the page stopped reading"), CLOSE_WAIT))

    async def close(self) -> None:
        """Stop the page's writer (the socket has closed or is closing)."""
        self._writer.cancel()
        for task in (self._writer, self._closer):
            if task is not None:
                with contextlib.suppress(asyncio.CancelledError, TimeoutError, ConnectionResetError, RuntimeError):
                    await task


def broadcast(pages: set[Page], message: dict) -> None:
    """Queue ``message`` for every open page (its JSON written once)."""
    text = json.dumps(message, allow_nan=False)
    kind = str(message.get("type"))
    for page in list(pages):
        page.put(kind, text)
