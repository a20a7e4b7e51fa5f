"""The room's performer page: a browser's camera, tracked in the page, mapped and sent here.

``/r/ROOM/perform`` (``static/perform.html``) runs MediaPipe's face landmarker in the page (the
npm package ``@mediapipe/tasks-vision``, its wasm and the ``face_landmarker.task`` model served by
the room server from where ``make browser`` and the ``faces`` extra installed them: nothing is
fetched from a CDN). For each camera frame it sends one JSON text message over
``/r/ROOM/ws?role=perform&format=face``::

    {"t": 1234.5, "scores": {"jawOpen": 0.31, ...}, "matrix": [16 numbers]}   (a face)
    {"t": 1234.5}                                                            (no face in view)
    {"eye_contact": true, "t": 1234.5}      (the performer looks at the middle of the screen from then)

``t`` is the frame's time (ms, increasing), ``scores`` MediaPipe's blendshapes (ARKit's names; its
``_neutral`` is ignored) and ``matrix`` its facial transformation matrix, 4x4, flattened in either
order (the layout is told by where the translation is). The canonical face's axes are the head
frame's (x to the performer's left, y up, z out of the face), so the matrix's rotation is the
head's turn. Eye contact (:mod:`mapping.eye_contact`) takes the second after its message as
the screen's look; what it found comes back to the page as ``{"said": "eye contact taken: ..."}``.
The server maps the frames with the ``arkit`` mapping, as VMC's and OpenSeeFace's
(:func:`toonface.send.build_mapper`: the first second is the rest) as they come, and sends the
newest motors :data:`PAGE_RATE` times a second (a camera's own rate, 15 to 30 frames a second,
varies, and a stream's frames are evenly spaced) as a stream of its own
(:class:`stream.sender.StreamSender`) into the room, like any performer's.
"""

from __future__ import annotations

import contextlib
import math
import queue
import threading
import time
from collections.abc import Callable, Iterator

import numpy as np

from capture.blendshapes import BLENDSHAPES
from capture.listening import head_references, lost, posed
from capture.sources import Frame, Source
from common.limits import parse_json_message
from mapping.eye_contact import LiveEyeContact
from stream.framing import StreamKey
from stream.packets import StreamWriter
from stream.sender import StreamSender
from toon import standard_neutral

#: The largest message a performer page may send (a frame is about 1.5 kB).
MAX_MESSAGE = 8192
#: The rate a page's stream is sent at (the newest mapped frame each time).
PAGE_RATE = 30.0
#: Frames waiting to be mapped at most; a page that sends faster loses the oldest.
WAITING = 32
#: Lines for the page (eye contact's) kept until it is told them.
SAID_KEPT = 16
_INDEX = {name: i for i, name in enumerate(BLENDSHAPES)}


def head_turn(matrix: list[float] | np.ndarray) -> np.ndarray:
    """The head's turn ``(3, 3)`` in head-frame axes from MediaPipe's facial transformation
    matrix, 16 numbers in either order: by columns as the page gives them (WebGL's order: the
    translation in the 13th to 15th), or by rows where those are 0 0 0 and the 4th, 8th and
    12th are not (the translation); the rotation is the nearest orthonormal one to the 3x3 block
    (it may carry a scale). A ValueError where it is neither."""
    m = np.asarray(matrix, dtype=float)
    if m.shape != (16,) or not np.all(np.isfinite(m)):
        raise ValueError("a transformation matrix is 16 finite numbers")
    m = m.reshape(4, 4)  # by rows
    if np.allclose(m[:, 3], [0, 0, 0, 1], atol=1e-3):
        block = m[:3, :3].T  # it was by columns
    elif np.allclose(m[3], [0, 0, 0, 1], atol=1e-3):
        block = m[:3, :3]
    else:
        raise ValueError("not an affine transformation matrix (no 0 0 0 1 row or column)")
    u, _, vt = np.linalg.svd(block)
    turn = u @ vt
    if np.linalg.det(turn) < 0:
        raise ValueError("the transformation matrix mirrors")
    return turn


def page_frame(text: str | bytes | dict, rest: np.ndarray) -> Frame:
    """One message of a performer page (its text, or that text parsed) as a frame (see the module
    docstring); a ValueError naming what is wrong where it is not one."""
    message = text if isinstance(text, dict) else parse_json_message(text)  # (within common.limits' bounds)
    stamp = message.get("t") if isinstance(message, dict) else None
    if not isinstance(stamp, int | float) or not math.isfinite(stamp):
        raise ValueError('a frame is {"t": ms, "scores": {...}, "matrix": [...]}')
    t = float(message["t"]) / 1000
    if "scores" not in message:
        return lost(t, rest)
    shapes = message["scores"]
    if not isinstance(shapes, dict):
        raise ValueError("scores are an object of blendshape names and values")
    scores = np.zeros(len(BLENDSHAPES))
    for name, value in shapes.items():
        index = _INDEX.get(name)
        if index is not None and isinstance(value, int | float) and math.isfinite(value):
            scores[index] = min(max(float(value), 0.0), 1.0)
    matrix = message.get("matrix")
    if not isinstance(matrix, list) or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in matrix):
        raise ValueError("a matrix is a list of 16 numbers")
    return posed(t, rest, head_turn(matrix), scores)


class _InRoom:
    """The page stream's "socket": its packets go into the room (``deliver``, from the sender's
    thread) and the viewers' replies come back through :meth:`PagePerformer.reply`."""

    def __init__(self, deliver: Callable[[bytes], None]) -> None:
        self.deliver = deliver
        self.replies: queue.SimpleQueue[bytes] = queue.SimpleQueue()
        self.open = True

    def sendto(self, data: bytes, _address: object = None) -> int:
        self.deliver(data)
        return len(data)

    def recv(self, _size: int = 0) -> bytes:
        try:
            return self.replies.get_nowait()
        except queue.Empty:
            raise BlockingIOError("no reply waiting") from None

    def fileno(self) -> int:
        return 0 if self.open else -1

    def close(self) -> None:
        self.open = False


class PagePerformer:
    """A performer page's frames mapped live and sent into the room as stream ``stream``.

    Parameters
    ----------
    deliver : callable
        Takes each packet of the stream (called from this performer's own thread).
    stream : int
        The stream id.
    key : bytes or StreamKey, optional
        Seal the stream with the room's key, where it has one.
    """

    def __init__(self, deliver: Callable[[bytes], None], stream: int, key: bytes | StreamKey | None = None,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        from toonface.send import Follower, build_mapper

        labels, self.rest = head_references()
        self.halt = threading.Event()
        self.waiting: queue.Queue[Frame] = queue.Queue(WAITING)
        self.source = Source(labels, PAGE_RATE, self._frames(), "a performer page", live=True,
                             meta={"mapping": "arkit", "rest": self.rest}, channel_names=BLENDSHAPES, halt=self.halt)
        self.notes: list[str] = []
        mapper = build_mapper(self.source, notes=self.notes)
        #: What the mapping says to the page (eye contact taken or refused), for the server to pass on.
        self.said: queue.Queue[str] = queue.Queue(SAID_KEPT)
        self.eye_contact = mapper.eye_contact = LiveEyeContact(standard_neutral(), say=self._say)
        self.follower = Follower(self.source, mapper, standard_neutral())
        self.link = _InRoom(deliver)
        self.sender = StreamSender(("room", 0), StreamWriter(PAGE_RATE, stream=stream, key=key), clock=clock,
                                   link=self.link)
        self.clock = clock
        self._thread = threading.Thread(target=self._run, daemon=True, name=f"page performer {stream:04x}")
        self.follower.start()
        self._thread.start()

    def take(self, text: str | bytes) -> None:
        """One message of the page (a ValueError where it is none): a frame, which pushes out the
        oldest where it finds the queue full, or ``{"eye_contact": true, "t": ms}``: the performer
        looks at the middle of their screen from that time, for a second (:mod:`mapping.eye_contact`)."""
        message = parse_json_message(text)
        if isinstance(message, dict) and message.get("eye_contact") is True:
            stamp = message.get("t")
            if not isinstance(stamp, int | float) or isinstance(stamp, bool) or not math.isfinite(stamp):
                raise ValueError('eye contact is {"eye_contact": true, "t": ms}')
            self.eye_contact.begin(float(stamp) / 1000)  # from the page's frame of that time
            return
        frame = page_frame(message, self.rest)
        while True:
            try:
                self.waiting.put_nowait(frame)
                break
            except queue.Full:
                try:
                    self.waiting.get_nowait()
                except queue.Empty:
                    pass

    def next_said(self) -> str | None:
        """The oldest line the mapping said that the page has not been told, or None."""
        try:
            return self.said.get_nowait()
        except queue.Empty:
            return None

    def _say(self, text: str) -> None:
        with contextlib.suppress(queue.Full):  # a page that never reads them keeps the first few
            self.said.put_nowait(text)

    def reply(self, data: bytes) -> None:
        """A viewer's acknowledgement or keyframe request for this stream."""
        self.link.replies.put(data)

    @property
    def error(self) -> BaseException | None:
        """What stopped the mapping, where something did."""
        return self.follower.error

    def close(self) -> None:
        """Stop mapping and sending."""
        self.halt.set()
        self.follower.stop()
        self._thread.join(timeout=5.0)

    def _frames(self) -> Iterator[Frame]:
        while not self.halt.is_set():
            try:
                yield self.waiting.get(timeout=0.1)
            except queue.Empty:
                continue

    def _run(self) -> None:
        """Send the newest mapped frame at :data:`PAGE_RATE`, once one has come."""
        latest = self.follower.latest
        sent = 0
        due = self.clock()
        try:
            while not self.halt.wait(max(0.0, due - self.clock())):
                due += 1 / PAGE_RATE
                if latest.frames:
                    values, confidence, _ = latest.newest()
                    self.sender.write(sent / PAGE_RATE, values, self.clock(), confidence, extra=latest.extra() or None)
                    sent += 1
                if self.clock() - due > 1.0:
                    due = self.clock()  # far behind (a busy machine): keep the beat, do not race
        finally:
            self.sender.close()
