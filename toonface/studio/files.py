"""Files through the browser: a file dropped on the studio's page (or chosen with its picker) is
sent here and kept in the studio's working folder, the only folder it may touch; the page then
opens it where it belongs (:data:`KINDS`). ``GET /download/animation.toml`` and
``/download/face.json`` give the animation and the face being edited, for the browser to save
wherever the user says.

``POST /files/NAME`` with the file's bytes as the body. The name is the file's own, made safe (no
folder, no hidden or odd characters); where a file of that name is already in the folder the new
one takes the next free ``NAME-2.EXT``, so nothing there is written over. The file is written to a
temporary name and renamed once whole: an upload broken off leaves nothing. Refused: a request from
another site's page (``Origin``), one without the run's secret where the studio has one, a name
with nothing left, a body over :data:`MAX_UPLOAD`.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from aiohttp import web

from capture.sources import SOUND_SUFFIXES, VIDEO_SUFFIXES
from common import InputError, atomic_path

#: The largest file the page may send (a talking-head video of some minutes).
MAX_UPLOAD = 512 * 2**20
#: Where a file goes once here, by its extension: ``editor`` (an animation, a motor track, a take
#: or a video, as knots), ``face``, ``sound``, ``labels``, ``artwork`` (an SVG drawing or a PNG
#: picture, into the face being edited as components).
KINDS = {
    **dict.fromkeys((".toml", ".csv", ".npz", ".c3d", ".trc", *VIDEO_SUFFIXES), "editor"),
    ".json": "face",
    **dict.fromkeys(SOUND_SUFFIXES, "sound"),
    ".txt": "labels",
    ".svg": "artwork",
    ".png": "artwork",
}


def safe_name(name: str) -> str:
    """``name`` as a file name the folder may hold: its last part, letters, digits, ``. _ -`` and
    spaces kept, no leading dot; a ValueError where nothing is left."""
    base = re.sub(r"[^\w.\- ]", "_", name.replace("\\", "/").rsplit("/", 1)[-1]).strip(" .")
    if not base or not Path(base).suffix:
        raise ValueError(f"{name!r} is not a file name with an extension")
    return base[:120]


def free_name(folder: Path, name: str) -> Path:
    """``folder / name``, or ``NAME-2.EXT``, ``NAME-3.EXT``... where that is taken."""
    path = folder / name
    stem, suffix = path.stem, path.suffix
    n = 1
    while path.exists():
        n += 1
        path = folder / f"{stem}-{n}{suffix}"
    return path


async def send_file(request: web.Request, session: Any, allowed: bool) -> web.Response:
    """The animation or the face the studio holds, as a download named after it."""
    from toon.animation_file import animation_text
    from toon.face import face_text

    if not allowed:
        raise web.HTTPForbidden(text="open the studio's page first")
    what = request.match_info["what"]
    if what == "animation.toml":
        path = session.editor.path
        try:
            body = animation_text(session.editor.animation)
        except InputError as exc:
            raise web.HTTPBadRequest(text=f"{exc}\n") from None
        name = path.name if path else "animation.toml"
    elif what == "face.json":
        name, body = f"{safe_name((session.face.name or 'face') + '.json')}", face_text(session.face)
    else:
        raise web.HTTPNotFound(text="the studio gives animation.toml or face.json\n")
    return web.Response(text=body, content_type="application/toml" if what.endswith(".toml") else "application/json",
                        headers={"Content-Disposition": f'attachment; filename="{name}"', "Cache-Control": "no-store"})


async def receive_file(request: web.Request, folder: Path, allowed: bool) -> web.Response:
    """Keep the request's body as a file in ``folder`` (see the module docstring); answers
    ``{"name": ..., "kind": ...}``. ``allowed``: whether the request carries the run's secret."""
    origin = request.headers.get("Origin")
    if origin not in (f"http://{request.host}", f"https://{request.host}") or not allowed:
        raise web.HTTPForbidden(text="files come only from the studio's own page")
    try:
        name = safe_name(request.match_info["name"])
    except ValueError as exc:
        raise web.HTTPBadRequest(text=f"{exc}\n") from None
    kind = KINDS.get(Path(name).suffix.lower())
    if kind is None:
        raise web.HTTPBadRequest(text=f"{name}: the studio opens {', '.join(sorted(KINDS))}\n")
    if request.content_length is not None and request.content_length > MAX_UPLOAD:
        raise web.HTTPRequestEntityTooLarge(max_size=MAX_UPLOAD, actual_size=request.content_length)
    target = free_name(folder, name)
    size = 0
    with atomic_path(target) as temporary, temporary.open("wb") as out:
        async for chunk in request.content.iter_chunked(1 << 16):
            size += len(chunk)
            if size > MAX_UPLOAD:
                raise web.HTTPRequestEntityTooLarge(max_size=MAX_UPLOAD, actual_size=size)
            out.write(chunk)
    return web.json_response({"name": target.name, "kind": kind, "bytes": size})
