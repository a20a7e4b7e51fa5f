"""Rooms shared by several room server processes (or machines) through a NATS server.

Why NATS rather than Redis pub/sub: both are on Debian and both fan a message out to every
subscriber at once; NATS is Apache-2.0 throughout (server and ``nats-py``), where Redis from 7.4
is no longer under an OSI licence (and 8 adds the AGPL this MIT project must not depend on), and
NATS is built for this one job (no storage, a few hundred microseconds on loopback, clients that
reconnect by themselves).

Every process subscribes to the rooms it declares. A performer's packet that reaches one process
goes to that process's viewers and is published on ``toonface.ROOM.p``; the others pass it to
theirs. A viewer's reply (acknowledgement, keyframe request) for a stream no local performer sends
is published on ``toonface.ROOM.r`` and reaches the process that has it. Each message is the
sender process's 8-byte id and the packet, so a process skips its own; ``ROOM`` is the room's name
in hexadecimal (a subject's tokens may not hold dots or spaces). A room's tokens are agreed on
``toonface.ROOM.t`` (:meth:`Bus.agree`): the first server's hold for every server of the room.
Performers who left are said on ``toonface.ROOM.g``, and the clocks of each process's performers
on ``toonface.ROOM.c`` (:mod:`toonface.room.clocks`).
"""

from __future__ import annotations

import asyncio
import json
import secrets
from collections.abc import Awaitable, Callable
from typing import Any


def shown(url: str) -> str:
    """``url`` as it may be printed: its credentials (``nats://TOKEN@HOST:PORT``) left out.

    >>> shown("nats://s3cret@127.0.0.1:4222"), shown("tls://user:pw@nats.example:4222")
    ('nats://127.0.0.1:4222', 'tls://nats.example:4222')
    """
    scheme, _, rest = url.partition("://")
    return f"{scheme}://{rest.rsplit('@', 1)[-1]}"


def subject(room: str, kind: str) -> str:
    """The subject of a room's packets (``kind`` ``p``) or replies (``r``)."""
    return f"toonface.{room.encode().hex()}.{kind}"


class Bus:
    """This process's link to the others through a NATS server at ``url``.

    Parameters
    ----------
    url : str
        ``nats://HOST:PORT``.
    on_packet, on_reply : callable
        ``await on_packet(room, data)``: a performer's packet from another process;
        ``await on_reply(room, data)``: a viewer's reply from another process.
    on_gone : callable, optional
        ``await on_gone(room, data)``: another process's word that performers left (``g``).
    on_clocks : callable, optional
        ``await on_clocks(room, data)``: another process's performers' clocks (``c``).
    say : callable
        Told, in a line, when the NATS server is lost (the rooms are then this process's alone)
        and when it is back.
    """

    def __init__(self, url: str, on_packet: Callable[[str, bytes], Awaitable[None]],
                 on_reply: Callable[[str, bytes], Awaitable[None]],
                 say: Callable[[str], None] = lambda _: None,
                 on_gone: Callable[[str, bytes], Awaitable[None]] | None = None,
                 on_clocks: Callable[[str, bytes], Awaitable[None]] | None = None) -> None:
        self.url, self.on_packet, self.on_reply, self.say = url, on_packet, on_reply, say
        self.on_gone, self.on_clocks = on_gone, on_clocks
        self.where = shown(url)  # (what is said of it: never its credentials)
        self.origin = secrets.token_bytes(8)
        self.client: Any = None
        self.published = self.received = 0
        self.errors = 0  # connection troubles (nats-py reconnects by itself)
        self.last_error = ""

    async def start(self, rooms: list[str], timeout: float = 5.0) -> None:
        """Connect (a ConnectionError naming the server where it cannot) and subscribe to ``rooms``."""
        import nats
        from nats.errors import NoServersError

        async def trouble(exc: Exception) -> None:  # kept, not printed: nats-py tries again by itself
            self.errors += 1
            self.last_error = str(exc) or type(exc).__name__

        async def lost() -> None:
            if self.client is not None:  # (not when it is closed on purpose)
                self.say(f"lost the NATS server at {self.where}: the rooms are this process's alone until it is back "
                         "(trying again every quarter second)")

        async def back() -> None:
            self.say(f"the NATS server at {self.where} is back: the rooms are shared again")

        try:
            self.client = await asyncio.wait_for(nats.connect(
                self.url, connect_timeout=timeout, max_reconnect_attempts=-1, reconnect_time_wait=0.25,
                allow_reconnect=True, name="toonface room", error_cb=trouble, disconnected_cb=lost,
                reconnected_cb=back), timeout)
        except (NoServersError, OSError, TimeoutError) as exc:
            why = self.last_error or str(exc) or "no answer"
            raise ConnectionError(f"cannot reach the NATS server at {self.where} within {timeout:g} s: {why}") from None
        if not self.client._server_info.get("auth_required"):  # anyone who reaches it reads every room's packets
            self.say(f"the NATS server at {self.where} takes clients without credentials: anyone who reaches it "
                     "reads every room's packets; start it with --auth TOKEN and give nats://TOKEN@HOST:PORT")
        for name in rooms:
            await self.client.subscribe(subject(name, "p"), cb=self._handler(name, self.on_packet))
            await self.client.subscribe(subject(name, "r"), cb=self._handler(name, self.on_reply))
            if self.on_gone is not None:
                await self.client.subscribe(subject(name, "g"), cb=self._handler(name, self.on_gone))
            if self.on_clocks is not None:
                await self.client.subscribe(subject(name, "c"), cb=self._handler(name, self.on_clocks))
        await self.client.flush(timeout)

    async def agree(self, tokens: dict[str, tuple[str, str]], timeout: float = 1.0) -> dict[str, tuple[str, str]]:
        """Each room's ``(perform, watch)`` tokens as the servers already sharing it hold them
        (asked on ``toonface.ROOM.t``: the first server's), or ``tokens``' own where none answers;
        from then on this process answers the servers that come after with them. One set of tokens
        per shared room: a token made by one server works on every server of it (issue 68)."""
        from nats.errors import Error as NatsError

        agreed = {}
        for name, own in tokens.items():
            try:
                answer = await self.client.request(subject(name, "t"), b"", timeout=timeout)
                perform, watch = json.loads(answer.data)
                agreed[name] = (str(perform), str(watch))
            except (NatsError, TimeoutError, ValueError, TypeError):  # no responders: the first here
                agreed[name] = own
        for name, pair in agreed.items():
            async def answer_with(message: Any, pair: tuple[str, str] = pair) -> None:
                await message.respond(json.dumps(pair).encode())

            await self.client.subscribe(subject(name, "t"), cb=answer_with)
        await self.client.flush(timeout)
        return agreed

    def _handler(self, room: str, deliver: Callable[[str, bytes], Awaitable[None]]) -> Callable[[Any], Awaitable[None]]:
        async def handle(message: Any) -> None:
            data: bytes = message.data
            if data[:8] != self.origin:
                self.received += 1
                await deliver(room, data[8:])

        return handle

    async def publish(self, room: str, kind: str, data: bytes) -> None:
        """Send a packet (``p``), a reply (``r``), a departure (``g``) or clocks (``c``) of ``room`` to the
        other processes."""
        if self.client is not None and self.client.is_connected:
            await self.client.publish(subject(room, kind), self.origin + data)
            self.published += 1

    async def publish_text(self, room: str, kind: str, text: str) -> None:
        """:meth:`publish` of a text (UTF-8)."""
        await self.publish(room, kind, text.encode())

    async def close(self, timeout: float = 2.0) -> None:
        """Let what is pending go, and disconnect: at once where the NATS server is away (nothing
        pending can go; a drain would fail), never with an error."""
        client, self.client = self.client, None
        if client is None:
            return
        try:
            if client.is_connected:
                await asyncio.wait_for(client.drain(), timeout)
            else:
                await asyncio.wait_for(client.close(), timeout)
        except Exception as exc:  # noqa: BLE001 - stopping: what went wrong is kept, not raised
            self.errors += 1
            self.last_error = str(exc) or type(exc).__name__
