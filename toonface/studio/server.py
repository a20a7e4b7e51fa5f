"""The studio's local web server (aiohttp): the page, its files, and one WebSocket per page.

One :class:`~toonface.studio.session.StudioSession` per server: every page connected to it
shows the same face, so a reload or a second window picks up where the first was. Each page's
messages are checked (:mod:`toonface.studio.guard`) and applied to the session, and every page
is sent the new frame through its own queue (:mod:`toonface.studio.pages`); while the Animator
has moves to run, the animation plays or a stream is shown, a loop ticks the session every loop
time and queues each frame (and a stream's quality once a second). Rendering an MP4 runs in a
worker thread, so the pages go on being served meanwhile.

It binds loopback unless told otherwise and answers only requests addressed to a name it was
given (:func:`host_allowed`: a page elsewhere cannot reach it through DNS rebinding), and
WebSockets opened from its own page (the ``Origin`` is ``http://`` and the host the request came
to). Bound to any other address it also asks for a secret made for the run: the printed address
carries it, the page's first request trades it for a cookie, and the socket and the sound ask
for that cookie (as Jupyter does). The page and its scripts are files inside the package.
"""

from __future__ import annotations

import asyncio
import hmac
import re
import secrets
import threading
from collections.abc import Awaitable, Callable
from importlib import resources
from pathlib import Path

from aiohttp import WSMsgType, web

from common import InputError
from common.limits import HEADER_TIMEOUT_SECONDS
from toon import builtin_faces
from toonface.stopping import check_stop
from toonface.studio.guard import number, parse_message
from toonface.studio.messages import apply, hear, open_tuner, reason, show_heard, show_tuner
from toonface.studio.pages import Page, broadcast
from toonface.studio.session import StudioSession
from toonface.web_hosts import ANY_ADDRESS, EVERY_INTERFACE, host_allowed, is_loopback, listen_hosts

SESSION = web.AppKey("session", StudioSession)
PAGES = web.AppKey("pages", set[Page])
HOSTS = web.AppKey("hosts", set[str])
TOKEN = web.AppKey("token", str)
TICKER = web.AppKey("ticker", asyncio.Task)
WAKE = web.AppKey("wake", asyncio.Event)
STOP = web.AppKey("stop", threading.Event)

#: The largest message a page may send (a drag or a slider is under 200 bytes).
MAX_MESSAGE = 64 * 1024


def static_folder() -> Path:
    """The page's files, shipped inside the package."""
    return Path(str(resources.files("toonface.studio") / "static"))


def make_app(session: StudioSession, hosts: set[str], token: str = "",
             stop: threading.Event | None = None) -> web.Application:
    """The studio's application for ``session``, answering requests whose ``Host`` is one of
    ``hosts`` (``"127.0.0.1:8765"``, ``"localhost:8765"``; :data:`ANY_ADDRESS`: any IP address),
    and, given a ``token``, serving the page only to an address that carries it. Work in worker
    threads ends, between frames, once ``stop`` is set (:mod:`toonface.stopping`)."""
    app = web.Application(middlewares=[_only_our_host], client_max_size=MAX_MESSAGE)
    app[STOP] = stop if stop is not None else threading.Event()
    app[SESSION] = session
    app[PAGES] = set()
    app[HOSTS] = set(hosts)
    app[TOKEN] = token
    app.router.add_get("/", _index)
    app.router.add_get("/ws", _socket)
    app.router.add_get("/sound.wav", _sound)
    app.router.add_post("/files/{name}", _upload)
    app.router.add_get("/download/{what}", _download)
    app.router.add_get("/performer-video", _performer_video)
    app.router.add_static("/static/", static_folder(), follow_symlinks=False)
    app.on_startup.append(_start_ticker)
    app.on_cleanup.append(_stop_ticker)
    return app


@web.middleware
async def _only_our_host(request: web.Request, handler: Callable[[web.Request], Awaitable[web.StreamResponse]]
                         ) -> web.StreamResponse:
    hosts: set[str] = request.app[HOSTS]
    if not host_allowed(request.host, hosts):
        named = sorted(hosts - {ANY_ADDRESS}) + (["any IP address"] if ANY_ADDRESS in hosts else [])
        raise web.HTTPForbidden(text=f"this studio answers at {' or '.join(named)}")
    return await handler(request)


def _cookie(request: web.Request) -> str:
    """The cookie that holds the run's secret, one per port (cookies ignore ports)."""
    return f"toonface-studio-{request.url.port}"


def _has_token(request: web.Request, given: str | None) -> bool:
    token = request.app[TOKEN]
    return not token or (given is not None and hmac.compare_digest(given.encode(), token.encode()))


async def _index(request: web.Request) -> web.FileResponse:
    given = request.query.get("token")
    if not _has_token(request, given if given is not None else request.cookies.get(_cookie(request))):
        raise web.HTTPForbidden(text="open the address the studio printed, with its token")
    response = web.FileResponse(static_folder() / "index.html", headers={"Cache-Control": "no-store"})
    if request.app[TOKEN]:
        response.set_cookie(_cookie(request), request.app[TOKEN], httponly=True, samesite="Strict")
    return response


async def _upload(request: web.Request) -> web.Response:
    """A file from the page, kept in the working folder (:mod:`toonface.studio.files`)."""
    from toonface.studio.files import receive_file

    allowed = _has_token(request, request.cookies.get(_cookie(request)))
    return await receive_file(request, request.app[SESSION].folder.root, allowed)


async def _download(request: web.Request) -> web.Response:
    """The animation or the face, for the browser to save (:mod:`toonface.studio.files`)."""
    from toonface.studio.files import send_file

    allowed = _has_token(request, request.cookies.get(_cookie(request)))
    return await send_file(request, request.app[SESSION], allowed)


async def _performer_video(request: web.Request) -> web.StreamResponse:
    """The video the animation was tracked from (only that file; ranges for seeking)."""
    if not _has_token(request, request.cookies.get(_cookie(request))):
        raise web.HTTPForbidden(text="open the studio's page first")
    video = request.app[SESSION].editor.video
    if video is None or not video.is_file():
        raise web.HTTPNotFound(text="the animation was not tracked from a video\n")
    return web.FileResponse(video, headers={"Cache-Control": "no-store"})


async def _sound(request: web.Request) -> web.Response:
    if not _has_token(request, request.cookies.get(_cookie(request))):
        raise web.HTTPForbidden(text="open the studio's page first")
    sound = request.app[SESSION].sound
    if sound is None:
        raise web.HTTPNotFound(text="no sound is open")
    body = sound.wav()
    headers = {"Cache-Control": "no-store", "Accept-Ranges": "bytes"}
    wanted = re.fullmatch(r"bytes=(\d*)-(\d*)", request.headers.get("Range", "").strip())
    if wanted and (wanted.group(1) or wanted.group(2)):  # a part: what a browser asks for to seek in the sound
        first = int(wanted.group(1)) if wanted.group(1) else max(len(body) - int(wanted.group(2)), 0)
        last = min(int(wanted.group(2)), len(body) - 1) if wanted.group(1) and wanted.group(2) else len(body) - 1
        if first >= len(body) or first > last:
            raise web.HTTPRequestRangeNotSatisfiable(headers={"Content-Range": f"bytes */{len(body)}"})
        return web.Response(status=206, body=body[first:last + 1], content_type="audio/wav",
                            headers={**headers, "Content-Range": f"bytes {first}-{last}/{len(body)}"})
    return web.Response(body=body, content_type="audio/wav", headers=headers)


async def _socket(request: web.Request) -> web.WebSocketResponse:
    if request.headers.get("Origin") != f"http://{request.host}":
        raise web.HTTPForbidden(text="the studio's socket is for its own page")
    if not _has_token(request, request.cookies.get(_cookie(request))):
        raise web.HTTPForbidden(text="open the studio's page first")
    ws = web.WebSocketResponse(heartbeat=30.0, max_msg_size=MAX_MESSAGE)
    await ws.prepare(request)
    app = request.app
    session = app[SESSION]
    page = Page(ws)
    app[PAGES].add(page)
    try:
        for state in _state(session, "all"):
            page.send(state)
        async for message in ws:
            if message.type != WSMsgType.TEXT:
                continue
            said: str | None
            op = None  # a message that does not parse is refused as no op's
            try:
                parsed = parse_message(message.data)
                asked = parsed if isinstance(parsed, dict) else {}  # apply says what is wrong with a non-object
                op = asked.get("op")
                if op == "render":
                    await _render(app, page, asked)
                    continue
                if op == "hear":  # recognising takes a while
                    page.send({"type": "said", "message": "listening…"})
                    labels = await asyncio.get_running_loop().run_in_executor(None, hear, asked, session.sound)
                    said, changed = show_heard(session, labels), "sound"
                elif op == "tune" and asked.get("action") == "open":
                    # a take is cleaned and mapped, a video tracked first, while the server goes on serving
                    page.send({"type": "said", "message": f"opening {asked.get('take')}…"})
                    loop = asyncio.get_running_loop()
                    tuner = await loop.run_in_executor(None, open_tuner, asked, session.neutral, session.folder)
                    said = show_tuner(session, tuner, loop.time())
                    changed = "tune"
                else:
                    changed, said = apply(session, parsed, asyncio.get_running_loop().time())
            except (ValueError, KeyError, TypeError, IndexError, InputError) as exc:
                page.send({"type": "error", "message": reason(exc), "op": op})  # the page knows which ask failed
                continue
            if said:
                page.send({"type": "said", "message": said})
            for state in _state(session, changed):
                broadcast(app[PAGES], state)
            if op == "faceedit":  # every page gets the face; this one is told its edit was done
                page.send({"type": "answered", "op": "faceedit"})
            app[WAKE].set()
    finally:
        app[PAGES].discard(page)
        await page.close()
    return ws


def _state(session: StudioSession, changed: str) -> list[dict]:
    """The messages that bring a page up to date after ``changed`` (what :func:`apply` returned,
    or ``all`` for a page just connected), the frame last."""
    every = changed in ("all", "described")
    out = []
    if every:
        out.append({"type": "hello", "faces": builtin_faces(), **session.describe()})
    if every or changed in ("animation", "face"):  # a face's drivers change what its physics draws
        out.append({"type": "animation", **session.editor.describe(), "driven": session.driven()})
    if every or changed == "face":
        out.append({"type": "face", **session.faces.describe()})
    if (every or changed == "tune") and session.tuner is not None:
        out.append({"type": "tune", "motor": session.tune_motor, **session.tuner.describe(session.tune_motor)})
    if (every or changed == "sound") and session.sound is not None:
        out.append({"type": "sound", **session.sound.describe()})
    return [*out, {"type": "frame", **session.frame()}]


async def _render(app: web.Application, page: Page, message: dict) -> None:
    """Render the animation (``path``, ``fps``) in a worker thread, telling the page how far it has
    got about ten times a second; the server goes on serving meanwhile. Any picture file
    ``render`` writes (an MP4; WebM, ProRes .mov, APNG, WebP with the face's own alpha; an
    animated SVG; a Lottie .json) or the web player's .html."""
    from player.sink_choice import PICTURE_SUFFIXES
    from toonface.pipeline import render, render_with_sound
    from toonface.web_export import export_web

    session = app[SESSION]
    path = session.folder.inside(message["path"], "a movie")
    known = (*PICTURE_SUFFIXES, ".html")
    if path.suffix.lower() not in known:
        raise InputError(f"the studio renders to a file ending {', '.join(known)}", path)
    fps = number(message.get("fps", 30.0), "fps")
    if not 1 <= fps <= 240:
        raise ValueError(f"fps must be 1..240, got {fps:g}")
    track = session.editor.animation.sample(fps, session.neutral)
    face, loop, sound = session.face, asyncio.get_running_loop(), session.sound
    done = [0]
    last = [loop.time()]

    def progress(frames: int) -> None:  # in the worker thread
        check_stop(app[STOP])  # the server is stopping: the render keeps what it drew
        done[0] += frames
        if loop.time() - last[0] >= 0.1 or done[0] == track.frames:
            last[0] = loop.time()
            loop.call_soon_threadsafe(page.send, {"type": "rendering", "frames": done[0], "of": track.frames})

    page.send({"type": "rendering", "frames": 0, "of": track.frames})

    def work() -> int:
        if path.suffix.lower() == ".html":
            export_web(track, face, path, sound=sound.path if sound is not None else None)
            return track.frames
        if sound is not None:
            return render_with_sound(track, face, path, sound.path, fps=fps, progress=progress)
        return render(track, face, path, fps=fps, progress=progress)
    try:
        written = await loop.run_in_executor(None, work)
    except InputError as exc:
        raise InputError(exc.message, path) from None
    page.send({"type": "rendered", "path": str(path), "frames": written})


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
            broadcast(app[PAGES], {"type": "frame", **session.frame()})
            if session.live is not None and loop.time() - said_at >= 1.0:  # the stream's readout, once a second
                said_at = loop.time()
                broadcast(app[PAGES], {"type": "quality", **session.live.quality()})
            next_at = max(next_at + session.loop_time, loop.time() - session.loop_time)  # no burst to catch up
            await asyncio.sleep(max(0.0, next_at - loop.time()))


async def serve(session: StudioSession, host: str, port: int, ready: Callable[[str], None],
                allow: tuple[str, ...] = (), stop: threading.Event | None = None) -> None:
    """Serve the studio on ``host:port`` (0: any free port) until cancelled; ``ready`` gets the
    page's address once the server listens (with the run's secret where ``host`` is not loopback).

    Parameters
    ----------
    allow : tuple of str
        More names (``NAME`` or ``NAME:PORT``) the studio answers at, as ``--allow-host`` gives them.
    stop : threading.Event, optional
        Set when the server is to stop (:func:`toonface.stopping.stop_within`): a render under way
        ends at its next frame.
    """
    every = host in EVERY_INTERFACE
    token = "" if is_loopback(host) else secrets.token_urlsafe(18)
    runner = web.AppRunner(make_app(session, set(), token, stop), access_log=None,
                           keepalive_timeout=HEADER_TIMEOUT_SECONDS)
    await runner.setup()
    site = web.TCPSite(runner, host or None, port, reuse_address=True)
    try:
        await site.start()
        bound = runner.addresses[0][1] if runner.addresses else port
        shown = "127.0.0.1" if every else f"[{host}]" if ":" in host else host
        runner.app[HOSTS].update(listen_hosts(host, bound, allow))
        ready(f"http://{shown}:{bound}/" + (f"?token={token}" if token else ""))
        await asyncio.Event().wait()
    finally:
        runner.app[STOP].set()  # (cancelled: work in worker threads ends too)
        await runner.cleanup()
