"""The room's performer page: a browser's camera, tracked in the page, mapped and sent here.

``/r/ROOM/perform`` (``static/perform.html``) runs MediaPipe's face landmarker in the page (the
npm package ``@mediapipe/tasks-vision``, its wasm and the ``face_landmarker.task`` model served by
the room server from where ``make browser`` and the ``faces`` extra installed them: nothing is
fetched from a CDN) and talks over ``/r/ROOM/ws?role=perform&format=face``. The server speaks first,
once its mapping is ready, with the blendshapes that mapping reads (in :data:`BLENDSHAPES` order)::

    {"scores": ["browDownLeft", "browDownRight", ...]}

Then for each camera frame the page sends one compact binary message (``static/face_code.js``
writes it, :class:`PageCodes` reads it), little-endian, about 30 bytes (2 kB of JSON before)::

    kind   u8       1: a face, 2: no face in view
    step   u16      ms since the previous frame on this socket (the first: since the page
                    started); 65535: a u32 of ms since the page started follows instead
    -- a face only:
    turn   3 x i16  the head turn's unit quaternion (x, y, z; w >= 0 follows) times 32767
    mask   bytes    one bit a score, in the order the server gave (bit i: byte i // 8, bit i % 8):
                    set where the score's value follows
    values u8 each  the set scores, each the score times 255, rounded

A score not in a message keeps its value from the one before (the socket keeps order and loses
nothing; every score starts at 0). The page also sends text, JSON::

    {"eye_contact": true, "t": 1234}    (the performer looks at the middle of the screen from then)
    {"clock": 5.0e6, "at": 1234.5}      (the answer to the server's {"clock": 5.0e6}: "at", the
                                         page's clock of its frames' t, ms; :mod:`toonface.room.clocks`)
    {"t": 1234.5, "scores": {"jawOpen": 0.31, ...}, "matrix": [16 numbers]}   (a frame, as JSON)

a frame as JSON being ``scores`` MediaPipe's blendshapes (ARKit's names; its ``_neutral`` is
ignored) and ``matrix`` its facial transformation matrix, 4x4, flattened in either order (the
layout is told by where the translation is); ``{"t": ...}`` alone: no face in view. ``t`` is the
frame's time (ms, increasing). The canonical face's axes are the head frame's (x to the
performer's left, y up, z out of the face), so the matrix's rotation is the head's turn. Eye
contact (:mod:`mapping.eye_contact`) takes the second after its message as the screen's look;
what it found comes back to the page as ``{"said": "eye contact taken: ..."}``.
The server maps the frames with the ``arkit`` mapping, as VMC's and OpenSeeFace's
(:func:`toonface.send.build_mapper`: the first second is the rest) as they come, and sends the
newest motors :data:`PAGE_RATE` times a second (a camera's own rate, 15 to 30 frames a second,
varies, and a stream's frames are evenly spaced) as a stream of its own
(:class:`stream.sender.StreamSender`) into the room, like any performer's.
"""

from __future__ import annotations

import contextlib
import json
import math
import queue
import struct
import threading
import time
from collections.abc import Callable, Iterator, Sequence

import numpy as np

from capture.blendshapes import BLENDSHAPES
from capture.listening import head_references, lost, posed
from capture.sources import Frame, Source
from common.limits import parse_json_message
from mapping.eye_contact import LiveEyeContact
from stream.clocks import Offsets
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
#: A compact frame's first byte: a face, or no face in view.
FACE, NO_FACE = 1, 2
#: A compact frame's step that says a u32 of the page's time follows instead.
LONG_STEP = 0xFFFF
_INDEX = {name: i for i, name in enumerate(BLENDSHAPES)}
_STEP, _TIME, _TURN = struct.Struct("<H"), struct.Struct("<I"), struct.Struct("<3h")


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


class PageCodes:
    """One performer page socket's compact frames, read in the order they came (see the module
    docstring): each carries the scores that changed since the one before.

    Parameters
    ----------
    names : sequence of str
        The blendshapes the frames carry, in order (:attr:`PagePerformer.wanted`).
    """

    def __init__(self, names: Sequence[str]) -> None:
        self.columns = np.array([_INDEX[name] for name in names], dtype=int)
        self.levels = np.zeros(len(self.columns))  # each score's newest value, in 255ths
        self.ms = 0

    def frame(self, data: bytes, rest: np.ndarray) -> Frame:
        """The next compact frame ``data`` as a frame of the head references ``rest`` ``(N, 3)``;
        a ValueError naming what is wrong (what was read before it stands)."""
        if not data or data[0] not in (FACE, NO_FACE):
            raise ValueError("a compact frame starts with 1 (a face) or 2 (no face in view)")
        if len(data) < 3:
            raise ValueError("a compact frame is cut short")
        (step,), at = _STEP.unpack_from(data, 1), 3
        ms = self.ms + step
        if step == LONG_STEP:
            if len(data) < 7:
                raise ValueError("a compact frame is cut short")
            (ms,), at = _TIME.unpack_from(data, 3), 7
            if ms < self.ms:
                raise ValueError("a compact frame's time went back")
        if data[0] == NO_FACE:
            if len(data) != at:
                raise ValueError("a compact frame with no face carries nothing more")
            self.ms = ms
            return lost(ms / 1000, rest)
        size = (len(self.columns) + 7) // 8
        if len(data) < at + 6 + size:
            raise ValueError("a compact face frame is cut short")
        bits = np.unpackbits(np.frombuffer(data, np.uint8, size, at + 6), bitorder="little")
        if bits[len(self.columns):].any():
            raise ValueError(f"a compact face frame's mask names more than the {len(self.columns)} scores")
        values = np.frombuffer(data, np.uint8, offset=at + 6 + size)
        if len(values) != bits.sum():
            raise ValueError(f"a compact face frame's mask names {bits.sum()} scores and it carries {len(values)}")
        turn = np.array(_TURN.unpack_from(data, at)) / 32767
        if turn @ turn > 1.001:
            raise ValueError("a compact face frame's head turn is no unit quaternion")
        self.levels[bits[:len(self.columns)].astype(bool)] = values
        self.ms = ms
        scores = np.zeros(len(BLENDSHAPES))
        scores[self.columns] = self.levels / 255
        return posed(ms / 1000, rest, _turned(turn), scores)


def _turned(xyz: np.ndarray) -> np.ndarray:
    """The rotation ``(3, 3)`` of the unit quaternion whose x, y, z are ``xyz`` ``(3,)`` and w >= 0."""
    x, y, z = xyz
    w = math.sqrt(max(0.0, 1.0 - float(xyz @ xyz)))
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


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
        #: The page's clock (its frames' ``t``) less this server's: :mod:`toonface.room.clocks`.
        self.offsets = Offsets(clock)
        mapper = build_mapper(self.source, notes=self.notes)
        reads = {source.channel for source in mapper.mapping.sources() if source.kind == "blendshape"}
        #: The blendshapes the mapping reads, which the page's compact frames carry (it is told them first).
        self.wanted = [name for name in BLENDSHAPES if name in reads]
        self.codes = PageCodes(self.wanted)
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

    def take(self, message: str | bytes) -> None:
        """One message of the page (a ValueError where it is none): a frame, compact (bytes) or as
        JSON (text), which pushes out the oldest where it finds the queue full;
        ``{"eye_contact": true, "t": ms}``: the performer looks at the middle of their screen from
        that time, for a second (:mod:`mapping.eye_contact`); or the answer to an ask of its
        frames' clock (:meth:`next_said`)."""
        if isinstance(message, bytes):
            frame = self.codes.frame(message, self.rest)
        else:
            parsed = parse_json_message(message)
            if isinstance(parsed, dict) and self.offsets.heard(self, parsed):  # its frames' clock
                self.source.meta["clock_start"] = -(self.offsets.offset(self) or 0.0)  # this clock at their t = 0
                return
            if isinstance(parsed, dict) and parsed.get("eye_contact") is True:
                stamp = parsed.get("t")
                if not isinstance(stamp, int | float) or isinstance(stamp, bool) or not math.isfinite(stamp):
                    raise ValueError('eye contact is {"eye_contact": true, "t": ms}')
                self.eye_contact.begin(float(stamp) / 1000)  # from the page's frame of that time
                return
            frame = page_frame(parsed, self.rest)
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
        """The oldest message for the page it has not been sent (text: JSON), or None: what the
        mapping said (``{"said": ...}``), then an ask of its clock, every
        :data:`~stream.clocks.CLOCK_SECONDS`."""
        try:
            return json.dumps({"said": self.said.get_nowait()})
        except queue.Empty:
            return self.offsets.ask(self)

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
        """Send the newest mapped frame at :data:`PAGE_RATE`, once one has come, stamped when the
        page saw it (where its clock is known; else when it was mapped): a frame sent again (the
        camera slower than the stream, or stopped) a period later than the one before, so that
        the stream's stamps go on at its rate."""
        latest = self.follower.latest
        sent, stamp = 0, -math.inf
        due = self.clock()
        try:
            while not self.halt.wait(max(0.0, due - self.clock())):
                due += 1 / PAGE_RATE
                if latest.frames:
                    values, confidence, _ = latest.newest()
                    captured = latest.captured()
                    stamp = max(self.clock() if captured is None else captured, stamp + 1 / PAGE_RATE)
                    self.sender.write(sent / PAGE_RATE, values, stamp, confidence, extra=latest.extra() or None)
                    sent += 1
                if self.clock() - due > 1.0:
                    due = self.clock()  # far behind (a busy machine): keep the beat, do not race
        finally:
            self.sender.close()


class PageSocket:
    """A performer page's place among the room's performers: the viewers' replies to its stream
    go to its mapping thread's sender."""

    def __init__(self) -> None:
        self.closed = False
        self.performer: PagePerformer | None = None

    async def send_bytes(self, data: bytes) -> None:
        if self.performer is not None:
            self.performer.reply(data)
