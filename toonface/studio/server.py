"""The studio's local web server (aiohttp): the page, its files, and one WebSocket per page.

One :class:`~toonface.studio.session.StudioSession` per server: every page connected to it
shows the same face, so a reload or a second window picks up where the first was. Each page's
messages are applied to the session, and every page is sent the new frame; while the Animator
has moves to run, the animation plays or a stream is shown, a loop ticks the session every loop
time and sends each frame (and a stream's quality once a second). Rendering an MP4 runs in a
worker thread, so the pages go on being served meanwhile.

It binds loopback unless told otherwise, and answers only requests addressed to the address it
listens on (a page elsewhere cannot reach it through DNS rebinding; listening on every
interface, as asked, it answers any name) and WebSockets opened from its own page (the
``Origin`` header names the host the request came to); the page and its scripts are files
inside the package.
"""

from __future__ import annotations

import asyncio
import json
from collections.abc import Awaitable, Callable
from importlib import resources
from pathlib import Path

from aiohttp import WSMsgType, web

from common import InputError
from toon import builtin_faces
from toonface.studio.messages import apply, open_tuner, reason, show_tuner
from toonface.studio.session import StudioSession

SESSION = web.AppKey("session", StudioSession)
SOCKETS = web.AppKey("sockets", set[web.WebSocketResponse])
HOSTS = web.AppKey("hosts", set[str])
TICKER = web.AppKey("ticker", asyncio.Task)
WAKE = web.AppKey("wake", asyncio.Event)

#: In :data:`HOSTS`: the server listens on every interface and answers whatever name it is reached by.
ANY_HOST = "*"
#: The largest message a page may send (a drag or a slider is under 200 bytes).
MAX_MESSAGE = 64 * 1024


def static_folder() -> Path:
    """The page's files, shipped inside the package."""
    return Path(str(resources.files("toonface.studio") / "static"))


def make_app(session: StudioSession, hosts: set[str]) -> web.Application:
    """The studio's application for ``session``, answering requests whose ``Host`` is one of
    ``hosts`` (``"127.0.0.1:8765"``, ``"localhost:8765"``)."""
    app = web.Application(middlewares=[_only_our_host], client_max_size=MAX_MESSAGE)
    app[SESSION] = session
    app[SOCKETS] = set()
    app[HOSTS] = set(hosts)
    app.router.add_get("/", _index)
    app.router.add_get("/ws", _socket)
    app.router.add_get("/sound.wav", _sound)
    app.router.add_static("/static/", static_folder(), follow_symlinks=False)
    app.on_startup.append(_start_ticker)
    app.on_cleanup.append(_stop_ticker)
    return app


@web.middleware
async def _only_our_host(request: web.Request, handler: Callable[[web.Request], Awaitable[web.StreamResponse]]
                         ) -> web.StreamResponse:
    hosts: set[str] = request.app[HOSTS]
    if request.host not in hosts and ANY_HOST not in hosts:
        raise web.HTTPForbidden(text=f"this studio answers at {' or '.join(sorted(hosts))}")
    return await handler(request)


async def _index(request: web.Request) -> web.FileResponse:
    return web.FileResponse(static_folder() / "index.html", headers={"Cache-Control": "no-store"})


async def _sound(request: web.Request) -> web.Response:
    sound = request.app[SESSION].sound
    if sound is None:
        raise web.HTTPNotFound(text="no sound is open")
    return web.Response(body=sound.wav(), content_type="audio/wav", headers={"Cache-Control": "no-store"})


async def _socket(request: web.Request) -> web.WebSocketResponse:
    origin = request.headers.get("Origin")
    if origin is None or origin.split("://", 1)[-1] != request.host:
        raise web.HTTPForbidden(text="the studio's socket is for its own page")
    ws = web.WebSocketResponse(heartbeat=30.0, max_msg_size=MAX_MESSAGE)
    await ws.prepare(request)
    app = request.app
    session = app[SESSION]
    app[SOCKETS].add(ws)
    try:
        for state in _state(session, "all"):
            await ws.send_json(state)
        async for message in ws:
            if message.type != WSMsgType.TEXT:
                continue
            try:
                parsed = json.loads(message.data)
                if isinstance(parsed, dict) and parsed.get("op") == "render":
                    await _render(app, ws, parsed)
                    continue
                if isinstance(parsed, dict) and parsed.get("op") == "tune" and parsed.get("action") == "open":
                    # a take is cleaned and mapped, a video tracked first, while the server goes on serving
                    await ws.send_json({"type": "said", "message": f"opening {parsed.get('take')}…"})
                    loop = asyncio.get_running_loop()
                    tuner = await loop.run_in_executor(None, open_tuner, parsed, session.neutral)
                    said: str | None = show_tuner(session, tuner, loop.time())
                    changed = "tune"
                else:
                    changed, said = apply(session, parsed, asyncio.get_running_loop().time())
            except (ValueError, KeyError, TypeError, IndexError, InputError) as exc:
                await ws.send_json({"type": "error", "message": reason(exc)})
                continue
            if said:
                await ws.send_json({"type": "said", "message": said})
            for state in _state(session, changed):
                await _broadcast(app, state)
            app[WAKE].set()
    finally:
        app[SOCKETS].discard(ws)
    return ws


def _state(session: StudioSession, changed: str) -> list[dict]:
    """The messages that bring a page up to date after ``changed`` (what :func:`apply` returned,
    or ``all`` for a page just connected), the frame last."""
    every = changed in ("all", "described")
    out = []
    if every:
        out.append({"type": "hello", "faces": builtin_faces(), **session.describe()})
    if every or changed == "animation":
        out.append({"type": "animation", **session.editor.describe()})
    if every or changed == "face":
        out.append({"type": "face", **session.faces.describe()})
    if (every or changed == "tune") and session.tuner is not None:
        out.append({"type": "tune", "motor": session.tune_motor, **session.tuner.describe(session.tune_motor)})
    if (every or changed == "sound") and session.sound is not None:
        out.append({"type": "sound", **session.sound.describe()})
    return [*out, {"type": "frame", **session.frame()}]


async def _render(app: web.Application, ws: web.WebSocketResponse, message: dict) -> None:
    """Render the animation to an MP4 (``path``, ``fps``) in a worker thread, telling the page how far
    it has got about ten times a second; the server goes on serving meanwhile."""
    from toonface.pipeline import render, render_with_sound

    session = app[SESSION]
    path = Path(str(message["path"]))
    if path.suffix.lower() != ".mp4":
        raise InputError("the studio renders to an .mp4 file", path)
    fps = float(message.get("fps", 30.0))
    if not 1 <= fps <= 240:
        raise ValueError(f"fps must be 1..240, got {fps:g}")
    track = session.editor.animation.sample(fps, session.neutral)
    face, loop, sound = session.face, asyncio.get_running_loop(), session.sound
    done = [0]
    last = [loop.time()]

    def progress(frames: int) -> None:  # in the worker thread
        done[0] += frames
        if loop.time() - last[0] >= 0.1 or done[0] == track.frames:
            last[0] = loop.time()
            loop.call_soon_threadsafe(asyncio.ensure_future,
                                      ws.send_json({"type": "rendering", "frames": done[0], "of": track.frames}))

    await ws.send_json({"type": "rendering", "frames": 0, "of": track.frames})
    try:
        written = await loop.run_in_executor(None, lambda: render_with_sound(
            track, face, path, sound.path, fps=fps, progress=progress) if sound is not None else render(
            track, face, path, fps=fps, progress=progress))
    except InputError as exc:
        raise InputError(exc.message, path) from None
    await ws.send_json({"type": "rendered", "path": str(path), "frames": written})


async def _broadcast(app: web.Application, message: dict) -> None:
    """``message`` to every open page; a page closing meanwhile is dropped, not an error (the
    ticker that sends frames must outlive any page)."""
    text = json.dumps(message)
    sockets: set[web.WebSocketResponse] = app[SOCKETS]
    for ws in list(sockets):
        if ws.closed:
            continue
        try:
            await ws.send_str(text)
        except ConnectionResetError:  # aiohttp's "cannot write to closing transport" is one
            sockets.discard(ws)


async def _start_ticker(app: web.Application) -> None:
    app[WAKE] = asyncio.Event()
    app[TICKER] = asyncio.create_task(_tick(app))
    if app[SESSION].busy():  # a stream shown from the start
        app[WAKE].set()


async def _stop_ticker(app: web.Application) -> None:
    app[TICKER].cancel()
    try:
        await app[TICKER]
    except asyncio.CancelledError:
        pass


async def _tick(app: web.Application) -> None:
    """While the Animator has moves, one loop every loop time and a frame to every page; asleep otherwise."""
    session, loop = app[SESSION], asyncio.get_running_loop()
    while True:
        await app[WAKE].wait()
        app[WAKE].clear()
        next_at = said_at = loop.time()
        while session.busy():
            session.tick(loop.time())
            await _broadcast(app, {"type": "frame", **session.frame()})
            if session.live is not None and loop.time() - said_at >= 1.0:  # the stream's readout, once a second
                said_at = loop.time()
                await _broadcast(app, {"type": "quality", **session.live.quality()})
            next_at = max(next_at + session.loop_time, loop.time() - session.loop_time)  # no burst to catch up
            await asyncio.sleep(max(0.0, next_at - loop.time()))


async def serve(session: StudioSession, host: str, port: int, ready: Callable[[str], None]) -> None:
    """Serve the studio on ``host:port`` (0: any free port) until cancelled; ``ready`` gets the
    page's address once the server listens."""
    runner = web.AppRunner(make_app(session, set()), access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, host, port, reuse_address=True)
    try:
        await site.start()
        bound = runner.addresses[0][1] if runner.addresses else port
        names = {f"{host}:{bound}"} | ({f"localhost:{bound}", f"127.0.0.1:{bound}"} if host == "127.0.0.1" else set())
        if host in ("0.0.0.0", "::", ""):  # every interface, as asked: any name the machine has
            names = {ANY_HOST}
        runner.app[HOSTS].update(names)
        ready(f"http://{host}:{bound}/")
        await asyncio.Event().wait()
    finally:
        await runner.cleanup()
