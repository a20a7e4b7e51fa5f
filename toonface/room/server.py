"""The room server (aiohttp): performers and viewers meet in a named room over WebSocket.

Both ends connect *out* to the server (``ws://HOST:PORT/r/ROOM/ws?role=perform|watch``, with the
room's token for that role), which passes any NAT or firewall a web page passes. The motors travel
as the stream's own packets (:mod:`stream.framing`: coding, concealment and seal stay end to end;
the server reads only each one's stream id): a performer's go to every viewer of the room, and a
viewer's replies (acknowledgements, keyframe requests) to the performer of the stream they name.

Safety, each counted in :attr:`Room.refused` (or the server's, before a room is known):

- tokens compared in constant time; a wrong one is refused with 403; a token rides in a header,
  never in an address a proxy or access log records (:func:`~toonface.web_hosts.bearer_token`; one
  in a query is refused);
  a page asks :func:`_check` whether its token was the trouble (a browser hides the status);
- rooms exist only as declared (:class:`Rooms`; the pages answer alike for one that does not);
  performers and viewers per room are capped;
- a message larger than a stream packet is refused and the connection closed; more than
  ``rate_limit`` messages a second are dropped (a flood); a connection silent for
  ``idle_seconds`` is closed;
- a WebSocket from a web page must come from a page of the server's own addresses or of an
  origin it was given (:func:`toonface.web_hosts.origin_allowed`: DNS rebinding is refused);
- a performer page's messages are parsed within :mod:`common.limits`' bounds, and a request's
  headers must arrive within :data:`~common.limits.HEADER_TIMEOUT_SECONDS`;
- a viewer still taking an earlier packet misses the next (:attr:`Room.skipped`), its kernel's
  backlog kept small (:mod:`toonface.room.fanout`), rather than falling behind or holding the
  others back. A performer who leaves is said to the viewers at once (:func:`_gone`); browsers
  watch at ``/r/ROOM``.
"""

from __future__ import annotations

import asyncio
import hmac
import json
import secrets
import time
from collections import Counter
from collections.abc import Callable, Collection
from dataclasses import dataclass, field
from functools import partial
from typing import Any

from aiohttp import WSMsgType, web

from common.limits import HEADER_TIMEOUT_SECONDS
from stream.clocks import Offsets
from stream.framing import MAX_PACKET, StreamKey, peek_stream, stream_key
from toon import Face, load_face
from toonface.room.browsers import Viewers, add_pages, serve_viewer
from toonface.room.clocks import clock_text
from toonface.room.fanout import keep_unsent_small, say_all, send_all
from toonface.room.performers import MAX_MESSAGE, PagePerformer, PageSocket
from toonface.room.pubsub import Bus
from toonface.web_hosts import bearer_token, origin_allowed


@dataclass
class Room:
    """One room: its tokens, who is in it, and what was refused."""

    name: str
    perform_token: str
    watch_token: str
    performers: dict[int, Any] = field(default_factory=dict)  # by stream id: a WebSocket, or a page's stand-in
    viewers: dict[web.WebSocketResponse, asyncio.BaseTransport | None] = field(default_factory=dict)
    browsers: Viewers | None = None  # the browser viewers, once one came
    refused: Counter[str] = field(default_factory=Counter)
    forwarded: int = 0
    skipped: int = 0  # packets not sent to a viewer that lagged
    offsets: Offsets = field(default_factory=Offsets)  # the performers' clocks (:mod:`toonface.room.clocks`)

    def watching(self) -> int:
        """Viewers here now, native and browser."""
        return len(self.viewers) + (len(self.browsers.sockets) if self.browsers is not None else 0)


class Rooms:
    """The rooms a server holds, and its limits.

    Parameters
    ----------
    tokens : dict
        ``{name: (perform token, watch token)}``: the rooms declared.
    max_performers, max_viewers : int
        Per room.
    rate_limit : float
        Messages a second one connection may send (a performer at 60 Hz sends 30; replies fewer).
    idle_seconds : float
        A connection that sends nothing this long is closed.
    face : Face or str
        The face browser viewers see the performers on.
    key : bytes or StreamKey, optional
        The streams' shared secret, where performers seal them, for browser viewers: without it
        the server can pass sealed packets on but not draw them.
    pubsub : str, optional
        ``nats://HOST:PORT``: share the rooms with the other processes connected to that NATS
        server (:mod:`toonface.room.pubsub`).
    origins : collection of str
        Origins besides the server's own addresses whose pages may open its sockets
        (``https://face.example``, the name a TLS proxy serves it at).

    Attributes
    ----------
    hosts : set of str
        The ``HOST:PORT`` names the server answers at (:func:`toonface.web_hosts.listen_hosts`),
        filled in once it listens.
    """

    def __init__(self, tokens: dict[str, tuple[str, str]], max_performers: int = 16, max_viewers: int = 1000,
                 rate_limit: float = 200.0, idle_seconds: float = 60.0, face: Face | str = "classic",
                 key: bytes | StreamKey | None = None, pubsub: str | None = None,
                 origins: Collection[str] = ()) -> None:
        self.rooms = {name: Room(name, perform, watch) for name, (perform, watch) in tokens.items()}
        self.pubsub = pubsub
        #: Told, in a line, what the server should say aloud (the NATS server lost, or back).
        self.say: Callable[[str], None] = lambda _: None
        self.bus: Bus | None = None
        self.sockets: set[web.WebSocketResponse] = set()  # every connection, closed when the server stops
        self.face = load_face(face) if isinstance(face, str) else face
        self.key = stream_key(key)
        self.max_performers, self.max_viewers = max_performers, max_viewers
        self.rate_limit, self.idle_seconds = rate_limit, idle_seconds
        self.refused: Counter[str] = Counter()  # before a room is known
        self.hosts: set[str] = set()
        self.origins = frozenset(origins)

    def admit(self, name: str, role: str, token: str) -> Room | str:
        """The room a connection may enter, or the word for why not."""
        room = self.rooms.get(name)
        if room is None:
            return "room"
        if role not in ("perform", "watch"):
            return "role"
        wanted = room.perform_token if role == "perform" else room.watch_token
        if not hmac.compare_digest(token.encode(), wanted.encode()):
            return "token"
        if role == "watch" and room.watching() >= self.max_viewers:
            return "full"
        return room


ROOMS = web.AppKey("rooms", Rooms)
#: The subprotocol a room's sockets speak; a page offers ``bearer.TOKEN`` beside it
#: (:func:`~toonface.web_hosts.bearer_token`).
PROTOCOL = "toonface"


def make_runner(rooms: Rooms, header_timeout: float = HEADER_TIMEOUT_SECONDS) -> web.AppRunner:
    """The room server's runner: its access log (``aiohttp.access``, shown with ``-v``) holds no
    token, and a connection that has not sent a whole request's headers within ``header_timeout``
    seconds (or idles that long between requests) closed: aiohttp's keep-alive timer runs from
    the connection's start."""
    return web.AppRunner(make_app(rooms), keepalive_timeout=header_timeout)


def make_app(rooms: Rooms) -> web.Application:
    """The room server's application."""
    app = web.Application(client_max_size=4096)
    app[ROOMS] = rooms
    app.router.add_get("/r/{room}/ws", _socket)
    app.router.add_get("/r/{room}/check", _check)
    add_pages(app, rooms.face)
    app.on_shutdown.append(_going_away)
    if rooms.pubsub:
        app.on_startup.append(_join_bus)
        app.on_cleanup.append(_leave_bus)
    return app


async def _going_away(app: web.Application) -> None:
    """Close every connection as the server stops (1001, going away): a client connects again,
    to another server process where there is one."""
    for ws in list(app[ROOMS].sockets):
        await ws.close(code=1001, message=b"server going away")


async def _join_bus(app: web.Application) -> None:
    rooms = app[ROOMS]
    assert rooms.pubsub is not None

    async def packet(name: str, data: bytes) -> None:  # another process's performer
        stream = peek_stream(data)
        if stream is not None:
            await _deliver(rooms.rooms[name], data, stream)

    async def reply(name: str, data: bytes) -> None:  # another process's viewer, maybe to a performer here
        stream = peek_stream(data)
        performer = rooms.rooms[name].performers.get(stream) if stream is not None else None
        if performer is not None:
            await send_all({performer: None}, data)

    async def gone(name: str, data: bytes) -> None:  # another process's performer left
        await _gone(rooms.rooms[name], rooms, json.loads(data)["gone"], shared=False)

    async def clocks(name: str, data: bytes) -> None:  # another process's performers' clocks: for the stage and pages
        room = rooms.rooms[name]
        if room.offsets.told(data):
            await say_all(room.viewers, data.decode())

    rooms.bus = Bus(rooms.pubsub, packet, reply, rooms.say, gone, clocks)
    await rooms.bus.start(list(rooms.rooms))
    agreed = await rooms.bus.agree({name: (r.perform_token, r.watch_token) for name, r in rooms.rooms.items()})
    for name, (perform, watch) in agreed.items():  # one set of tokens per shared room: the first server's
        room = rooms.rooms[name]
        if (perform, watch) != (room.perform_token, room.watch_token):
            room.perform_token, room.watch_token = perform, watch
            rooms.say(f"room {name}: the tokens of the servers already sharing it through NATS hold here too "
                      "(this server's own, in its tokens file, do not)")


async def _leave_bus(app: web.Application) -> None:
    rooms = app[ROOMS]
    if rooms.bus is not None:
        await rooms.bus.close()
        rooms.bus = None


async def _check(request: web.Request) -> web.Response:
    """Whether the room would take this token for this role (204), or not (403: the same for a
    room that does not exist), for a page whose socket closed to tell a wrong link from a server
    away; the token only in the ``Authorization`` header."""
    rooms = request.app[ROOMS]
    token = request.headers.get("Authorization", "").removeprefix("Bearer ")
    admitted = rooms.admit(request.match_info["room"], request.query.get("role", "watch"), token)
    if isinstance(admitted, str) and admitted != "full":
        rooms.refused[admitted] += 1
        raise web.HTTPForbidden(text="no such room, or not with that token\n")
    return web.Response(status=204)


async def _socket(request: web.Request) -> web.StreamResponse:
    rooms = request.app[ROOMS]
    origin = request.headers.get("Origin")
    if origin is not None and not origin_allowed(origin, rooms.hosts, rooms.origins):
        rooms.refused["origin"] += 1
        raise web.HTTPForbidden(text="a WebSocket from another site's page\n")
    if "token" in request.query:  # already in a proxy's log: said, so that the client is mended
        rooms.refused["token"] += 1
        raise web.HTTPBadRequest(text="a token goes in the Authorization header (or a page's subprotocol), never "
                                      "in the address: proxies and access logs record addresses\n")
    token = bearer_token(request)
    role = request.query.get("role", "watch")
    admitted = rooms.admit(request.match_info["room"], role, token)
    if isinstance(admitted, str):
        rooms.refused[admitted] += 1
        if admitted == "full":
            raise web.HTTPServiceUnavailable(text="the room is full\n")
        raise web.HTTPForbidden(text="no such room, or not with that token\n")
    room = admitted
    page = role == "perform" and request.query.get("format") == "face"  # a performer page's tracked face
    ws = web.WebSocketResponse(max_msg_size=MAX_MESSAGE if page else MAX_PACKET, heartbeat=rooms.idle_seconds / 2,
                               compress=False, protocols=(PROTOCOL,))  # (packets do not shrink; the stage deflates)
    await ws.prepare(request)
    rooms.sockets.add(ws)
    if role == "watch":
        keep_unsent_small(request.transport)  # a slow viewer's backlog waits where the room can skip it
    try:
        if page:
            await _serve_page(ws, room, rooms)
        elif role == "watch" and request.query.get("format") == "drawn":
            if room.browsers is None:
                room.browsers = Viewers(room, rooms)
            await serve_viewer(ws, room.browsers, request.transport)
        else:
            if role == "watch":
                room.viewers[ws] = request.transport
            try:
                await _serve(ws, room, rooms, role)
            finally:
                room.viewers.pop(ws, None)
                room.offsets.forget(ws)
                left = [s for s, w in room.performers.items() if w is ws]
                for stream in left:
                    del room.performers[stream]
                await _gone(room, rooms, left)
    finally:
        rooms.sockets.discard(ws)
    return ws


async def _serve_page(ws: web.WebSocketResponse, room: Room, rooms: Rooms) -> None:
    """A performer page: its frames mapped into a stream of its own, which enters the room as a
    performer's (:mod:`toonface.room.performers`), until the page goes."""
    if len(room.performers) >= rooms.max_performers:
        room.refused["full"] += 1
        await ws.close(message=b"the room is full")
        return
    loop = asyncio.get_running_loop()
    stream = next(s for s in (secrets.randbelow(0x10000) for _ in range(1000)) if s not in room.performers)
    stand_in = PageSocket()

    def deliver(data: bytes) -> None:  # from the performer's mapping thread
        if not stand_in.closed:
            asyncio.run_coroutine_threadsafe(_perform(room, rooms, stand_in, data, stream), loop)

    performer = await loop.run_in_executor(None, lambda: PagePerformer(deliver, stream, rooms.key))
    stand_in.performer = performer
    room.performers[stream] = stand_in
    room.offsets.own(stand_in)  # its stream is stamped on this server's clock
    try:
        await ws.send_str(json.dumps({"scores": performer.wanted}))  # what its compact frames carry
        await _serve(ws, room, rooms, "perform", performer)
    finally:
        stand_in.closed = True
        room.offsets.forget(stand_in)
        room.performers.pop(stream, None)
        await _gone(room, rooms, [stream])
        await loop.run_in_executor(None, performer.close)


async def _serve(ws: web.WebSocketResponse, room: Room, rooms: Rooms, role: str,
                 page: PagePerformer | None = None) -> None:
    """Pass a connection's packets on (a performer page's frames to its mapping) until it closes,
    idles or breaks the rules."""
    window, count = time.monotonic(), 0
    while True:
        try:
            message = await ws.receive(timeout=rooms.idle_seconds)
        except TimeoutError:
            room.refused["idle"] += 1
            await ws.close(message=b"idle")
            return
        if message.type == WSMsgType.ERROR or message.type in (WSMsgType.CLOSE, WSMsgType.CLOSING,
                                                               WSMsgType.CLOSED):
            if message.type == WSMsgType.ERROR:
                room.refused["size"] += 1  # aiohttp ends a socket whose message is over max_msg_size
            return
        now = time.monotonic()
        if now - window >= 1.0:
            window, count = now, 0
        count += 1
        if count > rooms.rate_limit:
            room.refused["flood"] += 1
            continue
        if message.type == WSMsgType.TEXT and page is None:  # clocks (toonface.room.clocks)
            share = None if rooms.bus is None else partial(rooms.bus.publish_text, room.name, "c")
            if not await clock_text(ws, message.data, role, room.offsets, room.performers, room.viewers, share):
                room.refused["text"] += 1
            continue
        if page is not None:
            try:
                page.take(message.data)
            except ValueError:
                room.refused["malformed"] += 1
            while (said := page.next_said()) is not None:  # eye contact taken or refused; its clock asked
                await ws.send_str(said)
            continue
        data: bytes = message.data
        stream = peek_stream(data)
        if stream is None:
            room.refused["malformed"] += 1
            continue
        if role == "perform":
            await _perform(room, rooms, ws, data, stream)
            if (ask := room.offsets.ask(ws)) is not None:
                await ws.send_str(ask)
        else:
            performer = room.performers.get(stream)
            if performer is not None:
                await send_all({performer: None}, data)
            elif rooms.bus is not None:  # a performer of another process's
                await rooms.bus.publish(room.name, "r", data)


async def _perform(room: Room, rooms: Rooms, owner: web.WebSocketResponse | PageSocket, data: bytes,
                   stream: int) -> None:
    """A performer's packet of ``stream``: to every viewer, unless the stream is another's or the
    room has its fill of performers."""
    held = room.performers.get(stream)
    if held is None and len(room.performers) >= rooms.max_performers:
        room.refused["full"] += 1
        return
    if held is not None and held is not owner:
        room.refused["stream taken"] += 1
        return
    room.performers[stream] = owner
    await _deliver(room, data, stream)
    if rooms.bus is not None:
        await rooms.bus.publish(room.name, "p", data)


async def _gone(room: Room, rooms: Rooms, streams: list[int], shared: bool = True) -> None:
    """Tell the room's viewers, here and (``shared``) in the other processes, that ``streams``
    left: ``{"gone": [...]}``, text (pages drop the faces at once; native viewers ignore it)."""
    if streams:
        said = json.dumps({"gone": streams})
        await say_all(room.viewers, said)
        if shared and rooms.bus is not None:
            await rooms.bus.publish(room.name, "g", said.encode())


async def _deliver(room: Room, data: bytes, stream: int) -> None:
    """A performer's packet (of this process's or another's) to this process's viewers."""
    room.skipped += await send_all(room.viewers, data)
    if room.browsers is not None:
        room.browsers.feed(data, stream)
    room.forwarded += 1
