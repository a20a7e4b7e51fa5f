"""What the room's page tests share: the room's tokens and key, a performer holding a pose at
30 Hz through the room, the face a page shows, and the offscreen renderer's picture of the pose."""

from __future__ import annotations

import io
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np

TOKENS = {"demo": ("perform-secret-0123456789", "watch-secret-0123456789")}
KEY = b"a shared secret of the room 0123"


def pose() -> np.ndarray:
    """The mouth wide open and the left inner brow up, the rest at the standard neutral ``(21,)``."""
    from toon import motor_index, standard_neutral

    values = standard_neutral().copy()
    values[motor_index("MB")] = 0.9  # the mouth wide open
    values[motor_index("BLM")] = 0.85
    return values


class Performer:
    """A live performer in room ``demo`` of the server at ``base`` holding :func:`pose` at 30 Hz
    (or moving as ``motion`` says: the motors ``(21,)`` at each second since it started), once
    started, its stamps' clock ``clock_ahead`` seconds ahead of this machine's (another machine's);
    its ``sender`` counts the acknowledgements that came back, ``started`` is when it started
    (``time.time()``)."""

    def __init__(self, base: str, stream: int, key: bytes | None = None,
                 motion: Callable[[float], np.ndarray] | None = None, clock_ahead: float = 0.0) -> None:
        from stream.packets import StreamWriter
        from stream.sender import StreamSender
        from stream.websocket import WebSocketLink

        def clock() -> float:  # another machine's: its clock ``clock_ahead`` seconds ahead of this one's
            return time.perf_counter() + clock_ahead

        link = WebSocketLink(f"{base}/r/demo", TOKENS["demo"][0], "perform", clock=clock)
        self.sender = StreamSender((link.where, 0), StreamWriter(30.0, stream=stream, key=key), link=link, clock=clock)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run)
        self.motion = motion or (lambda _t: pose())
        self.started = 0.0

    def _run(self) -> None:
        frame = 0
        while not self._stop.wait(1 / 30):
            self.sender.write(frame / 30, self.motion(time.time() - self.started))
            frame += 1

    def start(self) -> None:
        self.started = time.time()
        self._thread.start()

    def wait(self, seconds: float) -> None:
        """Let it perform for ``seconds``."""
        self._stop.wait(seconds)

    def close(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join()
        self.sender.close()


@contextmanager
def performer(base: str, stream: int, key: bytes | None = None,
              motion: Callable[[float], np.ndarray] | None = None, clock_ahead: float = 0.0) -> Iterator[Performer]:
    """A :class:`Performer`, stopped and closed at the end."""
    one = Performer(base, stream, key, motion, clock_ahead)
    try:
        yield one
    finally:
        one.close()


def face_png(driver) -> np.ndarray:
    """The first performer's face as the page shows it, RGB ``(H, W, 3)``."""
    from PIL import Image

    png = driver.find_element("css selector", "figure .face").screenshot_as_png
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def settled_pictures(face, size: tuple[int, int] = (512, 512)) -> tuple[np.ndarray, np.ndarray]:
    """The offscreen renderer's pictures of :func:`pose` with the face's physics settled (as a
    page's are after seconds held) and of the standard neutral, RGB ``int``."""
    from player.backends import open_renderer
    from player.motion import SecondaryMotion
    from toon import FaceRig, standard_neutral

    motion = SecondaryMotion(face)
    extra: dict = {}
    for k in range(200):
        extra = motion.extra_at(k / 30, pose(), {})
    with open_renderer(size) as renderer:
        drawn = renderer.render(FaceRig(face).geometry(pose(), extra)).astype(int)
        neutral = renderer.render(FaceRig(face).geometry(standard_neutral(), {})).astype(int)
    return drawn, neutral
