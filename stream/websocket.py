"""A stream's packets over a WebSocket to a room server (``ws://`` or ``wss://HOST/r/ROOM``):
the path through NAT and firewalls, for a sender or a receiver that cannot be reached by UDP.

:class:`WebSocketLink` is a blocking facade over aiohttp's client, run in its own thread with
its own event loop: :meth:`send` queues a packet, :meth:`receive` waits for one. Each WebSocket
message is one packet, as each datagram is over UDP; TCP delivers them in order and whole, so the
stream's loss handling simply sees no loss (a slow link shows as late packets instead).

A connection that breaks after it was made (the server stopped, or one of several server
processes on the address did) is made again every :data:`RETRY_SECONDS` until :meth:`close`:
behind one address, another process takes it at once; packets sent while it is down are dropped,
as a datagram to nobody would be.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import math
import queue
import ssl
import threading
import time
from collections.abc import Callable, Collection
from urllib.parse import urlencode, urlsplit, urlunsplit

import aiohttp

from common.limits import parse_json_message
from stream.framing import MAX_PACKET

#: Seconds between tries to connect again once a connection broke.
RETRY_SECONDS = 0.25
_ENDED = b""  # the server ended the connection (no packet is empty)


def clock_reading(text: str | dict, keys: Collection[str]) -> dict | None:
    """``text`` (or its JSON already parsed) as a clock message, finite numbers at exactly ``keys``
    (``clock``, and ``at`` in an answer: :mod:`toonface.room.clocks`), or None where it is none;
    parsed within :mod:`common.limits`' bounds (a deep nest from afar raised RecursionError)."""
    try:
        message = text if isinstance(text, dict) else parse_json_message(text)
    except ValueError:
        return None
    if not isinstance(message, dict) or set(message) != set(keys):
        return None
    if not all(isinstance(message[k], int | float) and not isinstance(message[k], bool)
               and math.isfinite(message[k]) for k in keys):
        return None
    return message


def clock_answer(text: str, clock: Callable[[], float]) -> str | None:
    """The answer to an ask of ``clock`` (``{"clock": ms}`` -> ``{"clock": ms, "at": ms}``, its
    reading added), or None where ``text`` is no such ask."""
    asked = clock_reading(text, ("clock",))
    return None if asked is None else json.dumps({"clock": asked["clock"], "at": round(clock() * 1000, 3)})


class LinkError(OSError):
    """The room server could not be reached or refused the connection (the message says which)."""


class WebSocketLink:
    """A connection to ``url`` (``ws[s]://HOST[:PORT]/r/ROOM``) as ``role`` (``perform`` or
    ``watch``) with the room's ``token``; connected when made (:class:`LinkError` if not), until
    :meth:`close`.

    Parameters
    ----------
    timeout : float
        Seconds to wait for the connection.
    ca_file : str, optional
        A certificate (PEM) to trust for ``wss://`` beside the system's: a room server's own,
        self-signed one.
    clock : callable
        The clock a performer's packets are stamped with (the sender's), which the room server
        asks for to tell the viewers how far it is from theirs (:func:`clock_answer`).
    """

    def __init__(self, url: str, token: str, role: str, timeout: float = 10.0, ca_file: str | None = None,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        parts = urlsplit(url)
        if parts.scheme not in ("ws", "wss") or not parts.netloc or not parts.path.startswith("/r/"):
            raise LinkError(f"expected ws://HOST:PORT/r/ROOM or wss://HOST/r/ROOM, got {url}")
        path = parts.path.rstrip("/") + "/ws"
        self.url = urlunsplit((parts.scheme, parts.netloc, path, urlencode({"role": role}), ""))
        self.where = f"{parts.netloc}{parts.path}"
        self._token, self.role, self.clock = token, role, clock
        self._ssl: ssl.SSLContext | bool = True
        if ca_file is not None:
            try:
                self._ssl = ssl.create_default_context(cafile=ca_file)
            except (ssl.SSLError, OSError) as exc:
                raise LinkError(f"cannot use {ca_file} as a certificate to trust: {exc}") from None
        self._incoming: queue.Queue[bytes] = queue.Queue(maxsize=1024)
        self._loop = asyncio.new_event_loop()
        self._outgoing: asyncio.Queue[bytes | None] | None = None
        self._ready = threading.Event()
        self._error: str | None = None
        self.closed = threading.Event()
        self._stopping = False
        self.dropped = 0  # packets that came while nobody took them (the incoming queue full)
        self.reconnects = 0  # connections made again after one broke
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        if not self._ready.wait(timeout):
            self.close()
            raise LinkError(f"no answer from {self.where} within {timeout:g} s")
        if self._error is not None:
            self.close()
            raise LinkError(self._error)

    def send(self, data: bytes) -> None:
        """Queue one packet for the server (dropped once the link has closed)."""
        if not self.closed.is_set() and self._outgoing is not None:
            with contextlib.suppress(RuntimeError):  # the loop ended between the check and the call
                self._loop.call_soon_threadsafe(self._outgoing.put_nowait, data)

    def receive(self, timeout: float = 0.0) -> bytes | None:
        """The next packet from the server, waiting up to ``timeout`` seconds (None if none came)."""
        try:
            return self._incoming.get(timeout=timeout) if timeout > 0 else self._incoming.get_nowait()
        except queue.Empty:
            return None

    # The few socket methods the stream's sender and receiver use, so either takes a link for its socket.

    def sendto(self, data: bytes, _address: object = None) -> int:
        self.send(data)
        return len(data)

    def recv(self, _size: int = 0) -> bytes:
        """A packet waiting, or BlockingIOError (a non-blocking socket's way of saying none)."""
        data = self.receive(0.0)
        if data is None:
            raise BlockingIOError("no packet waiting")
        return data

    def recvfrom(self, _size: int = 0) -> tuple[bytes, tuple[str, int]]:
        """The next packet within a tenth of a second, and where it came from (the room), or
        TimeoutError (a socket with a timeout's way of saying none); OSError once the link closed."""
        data = self.receive(0.1)
        if data is None:
            if self.closed.is_set():
                raise OSError("the room server closed the connection")
            raise TimeoutError
        return data, (self.where, 0)

    def getsockname(self) -> tuple[str, int]:
        return self.where, 0

    def fileno(self) -> int:
        return -1 if self.closed.is_set() else 0

    def close(self) -> None:
        """End the connection and its thread."""
        self._stopping = True
        if self._outgoing is not None and not self.closed.is_set():
            with contextlib.suppress(RuntimeError):  # the loop ended between the check and the call
                self._loop.call_soon_threadsafe(self._outgoing.put_nowait, None)
        self._thread.join(timeout=5.0)

    def _run(self) -> None:
        try:
            self._loop.run_until_complete(self._connect())
        finally:
            self.closed.set()
            self._ready.set()
            self._loop.close()

    async def _connect(self) -> None:
        self._outgoing = asyncio.Queue()
        headers = {"Authorization": f"Bearer {self._token}"}
        connected = False
        async with aiohttp.ClientSession() as session:
            while not self._stopping:
                try:
                    async with session.ws_connect(self.url, headers=headers, max_msg_size=MAX_PACKET, heartbeat=20.0,
                                                  ssl=self._ssl) as ws:
                        self.reconnects += connected
                        connected = True
                        self._ready.set()
                        await asyncio.gather(self._pump_out(ws), self._pump_in(ws))
                except aiohttp.WSServerHandshakeError as exc:
                    self._error = (f"{self.where} refused the connection ({exc.status}): "
                                   + ("no such room, or not with that token" if exc.status == 403 else exc.message))
                    return  # (refused after a reconnect too: the room is gone, or the token changed)
                except (aiohttp.ClientError, OSError) as exc:
                    if not connected:
                        self._error = f"cannot reach {self.where}: {exc}"
                        return
                while not self._outgoing.empty():  # what was sent while it was down goes nowhere
                    if self._outgoing.get_nowait() is None:
                        return
                await asyncio.sleep(RETRY_SECONDS)

    async def _pump_out(self, ws: aiohttp.ClientWebSocketResponse) -> None:
        assert self._outgoing is not None
        while True:
            data = await self._outgoing.get()
            if data is None:  # closed by this end
                self._stopping = True
                await ws.close()
                return
            if data == _ENDED or ws.closed:  # by the server
                return
            try:
                await ws.send_bytes(data)
            except ConnectionError:
                return

    async def _pump_in(self, ws: aiohttp.ClientWebSocketResponse) -> None:
        async for message in ws:
            if message.type == aiohttp.WSMsgType.TEXT and self.role == "perform":
                told = clock_answer(message.data, self.clock)  # the room server asks the clock we stamp with
                if told is not None:
                    await ws.send_str(told)
            if message.type == aiohttp.WSMsgType.BINARY:
                try:
                    self._incoming.put_nowait(message.data)
                except queue.Full:
                    self.dropped += 1
        if self._outgoing is not None:
            self._outgoing.put_nowait(_ENDED)  # the server ended it: stop sending too
