"""A live preview a browser shows: the newest frame as an MJPEG stream on a local HTTP port.

``http://127.0.0.1:PORT/`` is a page with the stream, ``/stream`` the ``multipart/x-mixed-replace``
stream itself, ``/frame.jpg`` the newest frame alone. ``/obs`` is a page for OBS's browser source:
only the face, on a transparent page, at the size its address asks (``/obs?width=640&height=480``;
the frame's own by default), fed from ``/frame.png``, the newest frame as a PNG that keeps its
alpha (with ``--background none``, the face alone is opaque). Frames are encoded only when
someone asks for them. Binds 127.0.0.1 unless told otherwise; at most ``max_viewers`` streams at
once.
"""

from __future__ import annotations

import threading
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import parse_qs

import cv2
import numpy as np

from player.alpha import over

_PAGE = (b"<!doctype html><title>toonface</title><body style='margin:0;background:#222'>"
         b"<img src='/stream' style='display:block;margin:auto;max-height:100vh'></body>")
_BOUNDARY = "toonfaceframe"
#: The OBS page: the newest frame drawn into a canvas as soon as the one before was, nothing else.
_OBS_PAGE = """<!doctype html><meta charset="utf-8"><title>toonface (OBS)</title>
<style>html,body{margin:0;background:transparent;overflow:hidden}canvas{display:block}</style>
<canvas id="face" width="{width}" height="{height}"></canvas>
<script>
const canvas = document.getElementById("face"), context = canvas.getContext("2d");
let drawn = 0;
async function next() {
  try {
    const answer = await fetch("/frame.png?after=" + drawn, {cache: "no-store"});
    if (answer.ok) {
      drawn = Number(answer.headers.get("X-Frame")) || drawn + 1;
      const picture = await createImageBitmap(await answer.blob());
      context.clearRect(0, 0, canvas.width, canvas.height);
      context.drawImage(picture, 0, 0, canvas.width, canvas.height);
      window.toonfaceDrawn = drawn;
    }
  } catch (error) { await new Promise(done => setTimeout(done, 500)); }
  requestAnimationFrame(next);
}
next();
</script>
"""


class FrameBoard:
    """The newest frame, with a condition to wait for the next one. A frame is JPEG-encoded when
    a viewer first asks for it (once, however many viewers), so nothing is encoded unwatched."""

    def __init__(self, quality: int = 85) -> None:
        self.quality = quality
        self._frame: np.ndarray | None = None
        self._number = 0
        self._jpeg: tuple[int, bytes | None] | None = None  # (frame number, its JPEG)
        self._png: tuple[int, bytes | None] | None = None  # (frame number, its PNG)
        self._cond = threading.Condition()

    def post(self, frame: np.ndarray) -> None:
        """Offer a new RGB(A) frame ``(h, w, 3 or 4)`` (kept by reference: do not change it afterwards)."""
        with self._cond:
            self._frame, self._number = frame, self._number + 1
            self._cond.notify_all()

    def newest(self) -> tuple[int, bytes | None]:
        """The newest frame's number and JPEG bytes (None before the first frame)."""
        with self._cond:
            number, frame, cached = self._number, self._frame, self._jpeg
        if frame is None:
            return number, None
        if cached is not None and cached[0] == number:
            return cached
        rgb = over(frame, (0, 0, 0)) if frame.shape[2] == 4 else frame  # a JPEG has no alpha: over black
        ok, data = cv2.imencode(".jpg", np.ascontiguousarray(rgb[:, :, ::-1]), [cv2.IMWRITE_JPEG_QUALITY, self.quality])
        encoded = (number, data.tobytes() if ok else None)
        with self._cond:
            self._jpeg = encoded
        return encoded

    def newest_png(self) -> tuple[int, bytes | None, tuple[int, int]]:
        """The newest frame's number, PNG bytes (its alpha kept; None before the first frame) and
        size ``(width, height)``."""
        with self._cond:
            number, frame, cached = self._number, self._frame, self._png
        if frame is None:
            return number, None, (0, 0)
        size = (frame.shape[1], frame.shape[0])
        if cached is not None and cached[0] == number:
            return cached[0], cached[1], size
        order = [2, 1, 0, 3] if frame.shape[2] == 4 else [2, 1, 0]
        ok, data = cv2.imencode(".png", np.ascontiguousarray(frame[:, :, order]), [cv2.IMWRITE_PNG_COMPRESSION, 1])
        encoded = (number, data.tobytes() if ok else None)
        with self._cond:
            self._png = encoded
        return encoded[0], encoded[1], size

    def wait_after(self, number: int, timeout: float = 1.0) -> tuple[int, bytes | None]:
        """Wait (up to ``timeout`` s) for a frame newer than ``number``, then :meth:`newest`."""
        with self._cond:
            self._cond.wait_for(lambda: self._number > number, timeout)
        return self.newest()


class _Handler(BaseHTTPRequestHandler):
    server: PreviewServer

    def log_message(self, format: str, *args) -> None:  # noqa: A002 - the base class's name
        pass  # no request log on the player's console

    def do_GET(self) -> None:  # noqa: N802 - the base class's name
        path, _, query = self.path.partition("?")
        if path == "/obs":
            self._obs(parse_qs(query))
        elif path == "/frame.png":
            number, png, _ = self.server.board.newest_png()
            if png is None:
                self._send(HTTPStatus.SERVICE_UNAVAILABLE, "text/plain", b"no frame yet\n")
            else:
                self._send(HTTPStatus.OK, "image/png", png, {"X-Frame": str(number)})
        elif self.path in ("/", "/index.html"):
            self._send(HTTPStatus.OK, "text/html", _PAGE)
        elif self.path == "/frame.jpg":
            _, jpeg = self.server.board.newest()
            if jpeg is None:
                self._send(HTTPStatus.SERVICE_UNAVAILABLE, "text/plain", b"no frame yet\n")
            else:
                self._send(HTTPStatus.OK, "image/jpeg", jpeg)
        elif self.path == "/stream":
            self._stream()
        else:
            self._send(HTTPStatus.NOT_FOUND, "text/plain", b"not found\n")

    def _obs(self, query: dict[str, list[str]]) -> None:
        """The OBS page at the size asked (whole pixels, 16..4096), else the frame's own."""
        _, _, (width, height) = self.server.board.newest_png()
        try:
            width = int(query.get("width", [width or 512])[0])
            height = int(query.get("height", [height or 512])[0])
        except ValueError:
            self._send(HTTPStatus.BAD_REQUEST, "text/plain", b"width and height are whole pixels\n")
            return
        if not (16 <= width <= 4096 and 16 <= height <= 4096):
            self._send(HTTPStatus.BAD_REQUEST, "text/plain", b"width and height must be 16..4096\n")
            return
        page = _OBS_PAGE.replace("{width}", str(width)).replace("{height}", str(height))
        self._send(HTTPStatus.OK, "text/html; charset=utf-8", page.encode())

    def _send(self, status: HTTPStatus, kind: str, body: bytes, headers: dict[str, str] | None = None) -> None:
        self.send_response(status)
        for name, value in (headers or {}).items():
            self.send_header(name, value)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)

    def _stream(self) -> None:
        if not self.server.slots.acquire(blocking=False):
            self._send(HTTPStatus.SERVICE_UNAVAILABLE, "text/plain", b"too many viewers\n")
            return
        board = self.server.board
        try:
            self.send_response(HTTPStatus.OK)
            self.send_header("Content-Type", f"multipart/x-mixed-replace; boundary={_BOUNDARY}")
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            number = -1
            while not self.server.closing.is_set():
                number, jpeg = board.wait_after(number)
                if jpeg is None:
                    continue
                self.wfile.write(f"--{_BOUNDARY}\r\nContent-Type: image/jpeg\r\nContent-Length: {len(jpeg)}"
                                 f"\r\n\r\n".encode() + jpeg + b"\r\n")
        except (ConnectionError, OSError):
            pass
        finally:
            self.server.slots.release()


class PreviewServer(ThreadingHTTPServer):
    """The MJPEG preview; serve with :func:`player.server.start`, stop with :meth:`stop`."""

    daemon_threads = True
    allow_reuse_address = True

    def __init__(self, address: tuple[str, int], board: FrameBoard, max_viewers: int = 4) -> None:
        self.board = board
        self.slots = threading.BoundedSemaphore(max_viewers)
        self.closing = threading.Event()
        super().__init__(address, _Handler)

    def stop(self) -> None:
        """End the streams and the server."""
        self.closing.set()
        self.shutdown()
        self.server_close()


class PreviewSink:
    """A picture sink that serves the frames written to it as the preview (see the module
    docstring); it listens from the moment it is made (OSError if it cannot) until :meth:`close`.
    It takes frames with alpha (the OBS page keeps it; the MJPEG stream lays them over black).

    Parameters
    ----------
    address : tuple
        ``(host, port)``; port 0 picks a free one (:attr:`url` says which).
    """

    def __init__(self, address: tuple[str, int], quality: int = 85, max_viewers: int = 4) -> None:
        self.board = FrameBoard(quality)
        self.server = PreviewServer(address, self.board, max_viewers)
        threading.Thread(target=self.server.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True).start()
        self.url = f"http://{address[0]}:{self.server.socket.getsockname()[1]}/"
        self._open = True

    alpha = True

    def write(self, frame: np.ndarray) -> None:
        """Show ``frame`` ``(height, width, 3 or 4)`` RGB(A) as the newest."""
        self.board.post(frame)

    def skip(self, frames: int) -> None:
        """Nothing to keep in time: viewers see the newest frame."""

    def close(self) -> None:
        """Stop serving."""
        if self._open:
            self._open = False
            self.server.stop()

    def abort(self) -> None:
        """The same as :meth:`close`."""
        self.close()
