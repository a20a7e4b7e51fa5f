"""The room server's pages and its browser viewers.

``/r/ROOM`` is the viewer page (``static/view.html``): the token rides in the address's fragment
(``#watch=TOKEN``, and a sealed stream's key, ``&key=``), which a browser never sends. The page
draws the faces itself: it loads the face's web rig (``/face.json``, :mod:`toon.web_rig`) and opens
``/r/ROOM/ws?role=watch`` as a native viewer does, reading the packets in the page
(``stream_reader.js``, ``playout.js``, ``face_stream.js``); the server relays them and draws
nothing for it. With ``?draw=server`` the page opens ``/r/ROOM/ws?role=watch&format=drawn``
instead and is sent the room's stage (:mod:`toonface.room.stage`) at
:data:`~toonface.room.stage.VIEW_FPS`: one message a frame, made and deflated once for all such
viewers. The page answers each message it has shown (:data:`SHOWN`). A viewer still taking an
earlier message, or with more on its way than its link carries in :data:`LAG_SECONDS`, is
skipped (its frames are dropped, not queued: :func:`~toonface.room.fanout.lagging`) and is then
sent what changed since the drawings it has (:meth:`~toonface.room.stage.Stage.since`), so a slow
viewer sees the newest frame at the rate its link allows and never holds the others back (each
message is framed once for all of them: :mod:`toonface.room.fanout`). Each second a page is told
its link's delay, from a message's sending to its answer (the median of the last second's: their
sizes differ), which its caption adds to the stage's (capture to the server's drawing). The
answer's own way back is in it: a caption errs long by that, never short (taking half a small
message's round trip off erred short by 60 ms at 64 kbit/s, where no message crosses at once).

``/r/ROOM/perform`` is the performer page (``static/perform.html``, see
:mod:`toonface.room.performers`); its face tracker's files are served under ``/web/``: MediaPipe's
``@mediapipe/tasks-vision`` from the ``node_modules`` folder ``make browser`` fills (or
``$TOONFACE_WEB_MODULES``), and the ``face_landmarker.task`` model from the ``faces`` extra.

The pages' scripts and styles come from this package and the studio's (``draw.js``, the one
module that shows a drawing on every page, and ``rig.js`` that draws a face from motors); no page
can reach any other file.
"""

from __future__ import annotations

import asyncio
import gzip
import json
import logging
import math
import os
import statistics
from collections import Counter, deque
from collections.abc import Awaitable, Callable
from importlib import resources
from pathlib import Path
from typing import Any, Protocol

from aiohttp import WSMsgType, web

from stream.clocks import Offsets
from stream.framing import StreamKey
from toon import Face
from toonface.room.fanout import frame_of, lagging, send_all
from toonface.room.stage import VIEW_FPS, Stage, packed

#: Seconds the stage waits after a frame it could not draw before it tries the next.
RETRY_SECONDS = 1.0
#: What a page sends for each message it has shown.
SHOWN = "s"
#: A page that says what it has shown is sent nothing new while more is on its way than its link
#: carries in this many seconds (by its answers): a slow link's queue, wherever it forms (this
#: server, the kernels, a router on the way), holds about this much and one message.
LAG_SECONDS = 0.25
#: A page not yet heard from after this long is one that does not answer: sent to as its link takes.
FIRST_ANSWER_SECONDS = 3.0
#: Seconds between the words to a page of its link's delay (``{"delay_ms": ...}``).
TELL_SECONDS = 1.0
#: The files pages may load, and the package each comes from.
STATIC = {"view.js": "toonface.room", "perform.js": "toonface.room", "room.css": "toonface.room",
          "room_link.js": "toonface.room", "face_code.js": "toonface.room",
          **{name: "toonface.studio" for name in ("draw.js", "rig.js", "physics.js", "stream.js", "stream_reader.js",
                                                  "playout.js", "face_stream.js")}}
#: The files of @mediapipe/tasks-vision the performer page loads (its SIMD and non-SIMD wasm).
TASKS_VISION = ("vision_bundle.mjs", *(f"wasm/vision_wasm{kind}_internal.{ext}" for kind in ("", "_nosimd", "_module")
                                       for ext in ("js", "wasm")))
#: The files of @noble/ciphers and @noble/hashes a viewer page loads to open sealed streams (ES
#: modules that import only one another), by package.
NOBLE = {"ciphers": ("aes.js", "_polyval.js", "utils.js"),
         "hashes": ("hkdf.js", "hmac.js", "sha2.js", "_md.js", "_u64.js", "utils.js")}
#: Where the npm packages are, where not in the checkout's node_modules.
WEB_MODULES_ENV = "TOONFACE_WEB_MODULES"
_TYPES = {".js": "text/javascript", ".mjs": "text/javascript", ".css": "text/css", ".html": "text/html",
          ".wasm": "application/wasm", ".task": "application/octet-stream"}


def add_pages(app: web.Application, face: Face) -> None:
    """The viewer and performer pages and the files they load, and ``face`` as a web rig
    (``/face.json``, :mod:`toon.web_rig`) for the pages that draw it themselves."""
    app.router.add_get("/face.json", _web_rig(face))
    app.router.add_get("/r/{room}", _page("view.html"))
    app.router.add_get("/r/{room}/perform", _page("perform.html"))
    app.router.add_get("/static/{name}", _static)
    app.router.add_get("/web/tasks-vision/{name:.+}", _tasks_vision)
    app.router.add_get("/web/noble/{package}/{name}", _noble)
    app.router.add_get("/web/face_landmarker.task", _model)


def _web_rig(face: Face) -> Callable[[web.Request], Awaitable[web.Response]]:
    """The handler of ``/face.json``: the face's web rig, compiled and compressed once."""
    from toon import FaceRig
    from toon.web_rig import web_rig

    body = gzip.compress(json.dumps(web_rig(FaceRig(face)), separators=(",", ":")).encode(), mtime=0)

    async def rig(request: web.Request) -> web.Response:  # the server's one face: it tells no room apart
        return web.Response(body=body, content_type="application/json",
                            headers={"Content-Encoding": "gzip", "Cache-Control": "no-cache"})

    return rig


def web_modules() -> Path:
    """The ``node_modules`` folder the pages' npm packages are in: ``$TOONFACE_WEB_MODULES``, else
    the checkout's (``make browser`` installs them there)."""
    if env := os.environ.get(WEB_MODULES_ENV):
        return Path(env)
    return Path(__file__).resolve().parents[2] / "node_modules"


async def _tasks_vision(request: web.Request) -> web.StreamResponse:
    name = request.match_info["name"]
    if name not in TASKS_VISION:
        raise web.HTTPNotFound()
    path = web_modules() / "@mediapipe" / "tasks-vision" / name
    if not path.is_file():
        raise web.HTTPNotFound(text=f"@mediapipe/tasks-vision is not installed in {web_modules()} (make browser, "
                                    f"or set {WEB_MODULES_ENV})\n")
    return web.FileResponse(path, headers={"Content-Type": _TYPES[path.suffix], "Cache-Control": "max-age=86400"})


async def _noble(request: web.Request) -> web.StreamResponse:
    package, name = request.match_info["package"], request.match_info["name"]
    if name not in NOBLE.get(package, ()):
        raise web.HTTPNotFound()
    path = web_modules() / "@noble" / package / name
    if not path.is_file():
        raise web.HTTPNotFound(text=f"@noble/{package} is not installed in {web_modules()} (make browser, or set "
                                    f"{WEB_MODULES_ENV})\n")
    return web.FileResponse(path, headers={"Content-Type": _TYPES[".js"], "Cache-Control": "max-age=86400"})


async def _model(request: web.Request) -> web.StreamResponse:
    from capture.face_landmarks import model_path
    from common import InputError

    try:
        path = model_path()
    except InputError as exc:
        raise web.HTTPNotFound(text=f"{exc}\n") from None
    return web.FileResponse(path, headers={"Content-Type": _TYPES[".task"], "Cache-Control": "max-age=86400"})


def _text(package: str, name: str) -> str:
    return resources.files(package).joinpath("static", name).read_text(encoding="utf-8")


def _page(name: str) -> Callable[[web.Request], Awaitable[web.Response]]:
    async def page(request: web.Request) -> web.Response:  # the same for every name: it tells no room apart
        return web.Response(text=_text("toonface.room", name), content_type="text/html",
                            headers={"Cache-Control": "no-store", "Referrer-Policy": "no-referrer"})

    return page


async def _static(request: web.Request) -> web.Response:
    name = request.match_info["name"]
    package = STATIC.get(name)
    if package is None:
        raise web.HTTPNotFound()
    return web.Response(text=_text(package, name), content_type=_TYPES[name[name.rindex("."):]])


class _Publisher(Protocol):
    async def publish(self, room: str, kind: str, data: bytes) -> None: ...


class RoomSide(Protocol):
    """What the browser viewers read of their room (a :class:`toonface.room.server.Room`)."""

    @property
    def name(self) -> str: ...

    @property
    def performers(self) -> dict[int, Any]: ...

    @property
    def refused(self) -> Counter[str]: ...

    @property
    def offsets(self) -> Offsets: ...


class ServerSide(Protocol):
    """What they read of the server (:class:`toonface.room.server.Rooms`): the face, the stream's
    key, and the bus to other processes' performers where there is one."""

    @property
    def face(self) -> Face: ...

    @property
    def key(self) -> StreamKey | None: ...

    @property
    def bus(self) -> _Publisher | None: ...


class Viewers:
    """A room's browser viewers and the stage they are sent, which runs while any is here."""

    def __init__(self, room: RoomSide, rooms: ServerSide) -> None:
        self.room, self.rooms = room, rooms
        self.sockets: dict[web.WebSocketResponse, _Viewer] = {}
        self.stage: Stage | None = None
        self.task: asyncio.Task | None = None
        self.skipped = 0  # frames not sent to a viewer that lagged
        self.error: str | None = None  # what stopped a frame being drawn, the last time one did

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
            asyncio.get_running_loop().create_task(send_all({performer: None}, data))
        elif performer is None and self.rooms.bus is not None:  # a performer of another process's
            asyncio.get_running_loop().create_task(self.rooms.bus.publish(self.room.name, "r", data))

    async def _run(self) -> None:
        loop = asyncio.get_running_loop()
        period = 1.0 / VIEW_FPS
        due = loop.time()
        while self.stage is not None:
            try:
                self.stage.offsets = self.room.offsets.by_stream(self.room.performers)
                changed, whole = self.stage.frame()
            except Exception as exc:  # noqa: BLE001 - one bad frame must not end the drawing for every viewer
                self.error = f"{type(exc).__name__}: {exc}"
                logging.getLogger(__name__).warning("the room %s could not draw a frame: %s", self.room.name,
                                                    self.error)
                await asyncio.sleep(RETRY_SECONDS)
                due = loop.time()
                continue
            small, full, had = frame_of(packed(changed)), None, self.stage.lines()
            now = loop.time()
            for ws, viewer in list(self.sockets.items()):
                transport = viewer.transport
                if ws.closed or not isinstance(transport, asyncio.WriteTransport) or transport.is_closing():
                    continue
                if viewer.behind(transport, now):
                    viewer.current = False
                    self.skipped += 1
                    continue
                if viewer.current:
                    message = small
                elif viewer.had is None:  # a new viewer: whole drawings, made once for all who join
                    message = full = full or frame_of(packed(whole))
                else:  # one that skipped frames: what changed since the drawings it has
                    message = frame_of(packed(self.stage.since(viewer.had)))
                transport.write(message)
                viewer.current, viewer.had = True, had
                viewer.sending(now, len(message))
                if viewer.delay is not None and now - viewer.told >= TELL_SECONDS:
                    transport.write(frame_of(json.dumps({"delay_ms": round(viewer.delay * 1000)}).encode(), text=True))
                    viewer.told = now
            due += period
            await asyncio.sleep(max(0.0, due - loop.time()))
            if loop.time() - due > 1.0:
                due = loop.time()  # far behind (a busy machine): start the beat again, do not race


class _Viewer:
    """A browser viewer's connection, whether it has the last frame sent, the drawings it has (by
    stream, as lines; None: none yet), and what it said it has shown (times on the loop's clock)."""

    def __init__(self, transport: asyncio.BaseTransport | None) -> None:
        self.transport, self.current = transport, False
        self.had: dict[int, list[str]] | None = None
        self.sent: deque[tuple[float, int]] = deque(maxlen=1024)  # each message it has not answered: when, bytes
        self.answered: deque[tuple[float, int, float]] = deque()  # the last second's answers: when, bytes, delay
        self.answers = 0
        self.delay: float | None = None  # the median of the last second's answered messages', sent to shown
        self.told = -math.inf

    def sending(self, now: float, size: int) -> None:
        """A message of ``size`` bytes goes to it."""
        self.sent.append((now, size))

    def shown(self, now: float) -> bool:
        """The page showed the oldest message it had not answered; False where it had none."""
        if not self.sent:
            return False
        when, size = self.sent.popleft()
        self.answers += 1
        self.answered.append((now, size, now - when))
        while self.answered[0][0] < now - 1.0:
            self.answered.popleft()
        self.delay = statistics.median(delay for _, _, delay in self.answered)  # messages differ in size
        return True

    def behind(self, transport: asyncio.WriteTransport, now: float) -> bool:
        """Whether it is still taking earlier messages: in the server (its ``transport``), or (a
        page that answers) on their way, more than its link carries in :data:`LAG_SECONDS` (its
        answers of the last second tell the rate); a page not yet heard from is sent one message
        and waits for its answer for :data:`FIRST_ANSWER_SECONDS` at most."""
        if lagging(transport):
            return True
        if not self.sent:
            return False
        if not self.answers:
            return now - self.sent[0][0] < FIRST_ANSWER_SECONDS
        waiting = sum(size for _, size in self.sent)
        return waiting > LAG_SECONDS * sum(size for _, size, _ in self.answered)


async def serve_viewer(ws: web.WebSocketResponse, viewers: Viewers, transport: asyncio.BaseTransport | None) -> None:
    """Keep a browser viewer until it goes (it says only what it has shown; aiohttp's heartbeat
    finds a dead one)."""
    viewers.join(ws, transport)
    viewer, loop = viewers.sockets[ws], asyncio.get_running_loop()
    try:
        async for message in ws:
            if message.type == WSMsgType.ERROR:
                return
            if not (message.type == WSMsgType.TEXT and message.data == SHOWN and viewer.shown(loop.time())):
                viewers.room.refused["viewer message"] += 1
    finally:
        viewers.leave(ws)
