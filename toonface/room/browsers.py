"""The room server's pages and its browser viewers.

``/r/ROOM`` is the viewer page (``static/view.html``): the token rides in the address's fragment
(``#watch=TOKEN``), which a browser never sends, and the page opens
``/r/ROOM/ws?role=watch&format=drawn`` with it. Such a viewer is sent the room's stage
(:mod:`toonface.room.stage`) at :data:`~toonface.room.stage.VIEW_FPS`: one message a frame, made
and deflated once for all browser viewers. A viewer whose connection has more than
:data:`LAG_BYTES` waiting is skipped (its frames are dropped, not queued) and is sent whole
drawings once it has caught up, so a slow viewer never holds the others back.

The pages' scripts and styles come from this package and the studio's (``draw.js``, the one
module that shows a drawing on every page); no page can reach any other file.
"""

from __future__ import annotations

import asyncio
from importlib import resources
from typing import TYPE_CHECKING

from aiohttp import WSMsgType, web

from toonface.room.stage import VIEW_FPS, Stage, packed

if TYPE_CHECKING:
    from toonface.room.server import Room, Rooms

#: A browser viewer with more than this waiting to be sent skips frames until it drains.
LAG_BYTES = 256 * 1024
#: The files pages may load, and the package each comes from.
STATIC = {"view.js": "toonface.room", "room.css": "toonface.room", "draw.js": "toonface.studio"}
_TYPES = {".js": "text/javascript", ".css": "text/css", ".html": "text/html"}


def add_pages(app: web.Application) -> None:
    """The viewer page and the files it loads."""
    app.router.add_get("/r/{room}", _view_page)
    app.router.add_get("/static/{name}", _static)


def _text(package: str, name: str) -> str:
    return resources.files(package).joinpath("static", name).read_text(encoding="utf-8")


async def _view_page(request: web.Request) -> web.Response:
    from toonface.room.server import ROOMS

    if request.match_info["room"] not in request.app[ROOMS].rooms:
        raise web.HTTPNotFound(text="no such room\n")
    return web.Response(text=_text("toonface.room", "view.html"), content_type="text/html",
                        headers={"Cache-Control": "no-store", "Referrer-Policy": "no-referrer"})


async def _static(request: web.Request) -> web.Response:
    name = request.match_info["name"]
    package = STATIC.get(name)
    if package is None:
        raise web.HTTPNotFound()
    return web.Response(text=_text(package, name), content_type=_TYPES[name[name.rindex("."):]])


class Viewers:
    """A room's browser viewers and the stage they are sent, which runs while any is here."""

    def __init__(self, room: Room, rooms: Rooms) -> None:
        self.room, self.rooms = room, rooms
        self.sockets: dict[web.WebSocketResponse, _Viewer] = {}
        self.stage: Stage | None = None
        self.task: asyncio.Task | None = None
        self.skipped = 0  # frames not sent to a viewer that lagged

    def join(self, ws: web.WebSocketResponse, transport: asyncio.BaseTransport | None) -> None:
        self.sockets[ws] = _Viewer(transport)
        if self.stage is None:
            self.stage = Stage(self.rooms.face, self._reply, self.rooms.key)
            self.task = asyncio.get_running_loop().create_task(self._run())

    def leave(self, ws: web.WebSocketResponse) -> None:
        self.sockets.pop(ws, None)
        if not self.sockets and self.stage is not None:
            if self.task is not None:
                self.task.cancel()
            self.stage.close()
            self.stage, self.task = None, None

    def feed(self, data: bytes, stream: int) -> None:
        """A performer's packet, for the stage where one runs."""
        if self.stage is not None:
            self.stage.feed(data, stream)

    def _reply(self, stream: int, data: bytes) -> None:
        performer = self.room.performers.get(stream)
        if performer is not None and not performer.closed:
            asyncio.get_running_loop().create_task(_send(performer, data))

    async def _run(self) -> None:
        loop = asyncio.get_running_loop()
        period = 1.0 / VIEW_FPS
        due = loop.time()
        while self.stage is not None:
            changed, whole = self.stage.frame()
            small = packed(changed)
            full = small if all(v.current for v in self.sockets.values()) else packed(whole)
            for ws, viewer in list(self.sockets.items()):
                if ws.closed:
                    continue
                if viewer.waiting() > LAG_BYTES:
                    viewer.current = False
                    self.skipped += 1
                    continue
                await _send(ws, small if viewer.current else full)
                viewer.current = True
            due += period
            await asyncio.sleep(max(0.0, due - loop.time()))
            if loop.time() - due > 1.0:
                due = loop.time()  # far behind (a busy machine): start the beat again, do not race


class _Viewer:
    """A browser viewer's connection, and whether it has the last frame sent."""

    def __init__(self, transport: asyncio.BaseTransport | None) -> None:
        self.transport, self.current = transport, False

    def waiting(self) -> int:
        """Bytes written to it and not yet sent."""
        transport = self.transport
        return transport.get_write_buffer_size() if isinstance(transport, asyncio.WriteTransport) else 0


async def _send(ws: web.WebSocketResponse, data: bytes) -> None:
    try:
        await ws.send_bytes(data)
    except ConnectionError:
        pass


async def serve_viewer(ws: web.WebSocketResponse, viewers: Viewers, transport: asyncio.BaseTransport | None) -> None:
    """Keep a browser viewer until it goes (it sends nothing; aiohttp's heartbeat finds a dead one)."""
    viewers.join(ws, transport)
    try:
        async for message in ws:
            if message.type == WSMsgType.ERROR:
                return
            viewers.room.refused["viewer message"] += 1
    finally:
        viewers.leave(ws)
