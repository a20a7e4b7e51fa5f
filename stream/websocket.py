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
import queue
import ssl
import threading
import time
from collections.abc import Callable
from urllib.parse import urlencode, urlsplit, urlunsplit

import aiohttp

from stream.clocks import Offsets, clock_answer, performer_clocks
from stream.framing import MAX_PACKET

#: Seconds between tries to connect again once a connection broke.
RETRY_SECONDS = 0.25
_ENDED = b""  # the server ended the connection (no packet is empty)


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
        A performer's: the clock its packets are stamped with (the sender's), which the room server
        asks for to tell the viewers how far it is from theirs (:func:`~stream.clocks.clock_answer`).
        A viewer's: the clock its packets' arrivals are read on (the receiver's), which it compares
        with the server's, so that :meth:`clock_offset` tells how far it is from each performer's.
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
        self.offsets = Offsets(clock)  # a viewer's: the server's clock less ours (stream.clocks)
        self.performers: dict[int, float] = {}  # each performer's clock less the server's (s), as it told
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

    def clock_offset(self, stream: int) -> float | None:
        """A viewer's clock less the clock of ``stream``'s performer (seconds), where the server
        told that performer's and answered an ask of its own; else None."""
        server, performer = self.offsets.offset("server"), self.performers.get(stream)
        return None if server is None or performer is None else -server - performer

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
                        if connected:  # another server process may keep another clock: asked afresh
                            self.offsets.forget("server")
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
            elif message.type == aiohttp.WSMsgType.TEXT:  # a viewer's: the server's answer, the performers' clocks
                if not self.offsets.heard("server", message.data):
                    self.performers.update(performer_clocks(message.data) or {})
            if self.role != "perform" and (ask := self.offsets.ask("server")) is not None:  # every 2 s
                await ws.send_str(ask)
            if message.type == aiohttp.WSMsgType.BINARY:
                try:
                    self._incoming.put_nowait(message.data)
                except queue.Full:
                    self.dropped += 1
        if self._outgoing is not None:
            self._outgoing.put_nowait(_ENDED)  # the server ended it: stop sending too
