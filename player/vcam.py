"""Live pictures into a virtual webcam, which Zoom, Meet, Teams and OBS take as a camera.

The device is pyvirtualcam's (v4l2loopback on Linux, OBS's virtual camera on Windows and macOS),
which turns the RGB frames it is given into the pixel format the device takes (I420, YUYV...).
pyvirtualcam is GPL-2.0 and an optional install (``pip install 'toonface[vcam]'``): toonface
itself stays MIT, and a machine without it is told how to get it. What this sink does itself,
and the tests check against a fake device: a frame with alpha is laid over a colour (a camera
has no transparency), a frame of another size is scaled to the device's, and frames come at the
device's rate (a faster player's extra frames are dropped; a slower one's last frame stays on
the device, as a camera's does).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, Protocol

import cv2
import numpy as np

from common import InputError
from player.alpha import over

#: What to tell a user with no virtual camera to send to.
HOW_TO_GET_ONE = ("a virtual camera needs pyvirtualcam (pip install 'toonface[vcam]'; GPL-2.0) and a device: on "
                  "Linux, sudo apt install v4l2loopback-dkms and sudo modprobe v4l2loopback exclusive_caps=1 "
                  "card_label=toonface; on Windows or macOS, install OBS and start its virtual camera once")


class Camera(Protocol):
    """What the sink needs of a device (a ``pyvirtualcam.Camera``, or a test's fake)."""

    width: int
    height: int

    def send(self, frame: np.ndarray) -> None: ...
    def close(self) -> None: ...


def open_pyvirtualcam(width: int, height: int, fps: float, device: str | None) -> Camera:
    """pyvirtualcam's camera for RGB frames of ``width`` x ``height`` at ``fps`` (``device``: e.g.
    ``/dev/video2``; None: the first it finds); an :class:`InputError` saying how to get one."""
    try:
        import pyvirtualcam
    except ImportError:
        raise InputError(HOW_TO_GET_ONE, device or "the virtual camera") from None
    try:
        camera: Camera = pyvirtualcam.Camera(width, height, fps, fmt=pyvirtualcam.PixelFormat.RGB, device=device)
    except (RuntimeError, ValueError) as exc:  # no device, or one that takes no such frames
        raise InputError(f"cannot open it ({exc}); {HOW_TO_GET_ONE}", device or "the virtual camera") from None
    return camera


class VirtualCamera:
    """A :class:`player.sinks.FrameSink` whose frames go to a virtual camera.

    Parameters
    ----------
    size : (width, height)
        The frames' size, and the device's where it takes what it is asked for.
    fps : float
        The device's frame rate.
    device : str, optional
        The device (``/dev/video2``); None: the first one found.
    background : (r, g, b)
        0..1: what a frame with alpha is laid over.
    open_camera : callable
        ``(width, height, fps, device) -> Camera`` (pyvirtualcam's by default; a fake in tests).
    clock : callable
        Seconds, for the device's rate.
    """

    alpha = True  # it takes frames with alpha and lays them over the background itself

    def __init__(self, size: tuple[int, int], fps: float, device: str | None = None,
                 background: tuple[float, float, float] = (0.0, 0.0, 0.0),
                 open_camera: Callable[[int, int, float, str | None], Camera] = open_pyvirtualcam,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        self.fps, self.clock = fps, clock
        self.camera = open_camera(size[0], size[1], fps, device)
        self.size = (int(self.camera.width), int(self.camera.height))
        self.background = np.asarray(background, dtype=np.float32) * 255.0
        self.sent = 0
        self.dropped = 0
        self._due: float | None = None

    def write(self, frame: np.ndarray) -> None:
        """Send ``frame`` ``(H, W, 3 or 4)`` uint8 RGB(A) when the device's next frame is due,
        laid over the background and scaled to the device; else drop it."""
        now = self.clock()
        if self._due is not None and now < self._due - 0.25 / self.fps:
            self.dropped += 1
            return
        self._due = now + 1.0 / self.fps if self._due is None or now - self._due > 1.0 / self.fps \
            else self._due + 1.0 / self.fps
        self.camera.send(self.converted(frame))
        self.sent += 1

    def converted(self, frame: np.ndarray) -> np.ndarray:
        """``frame`` as the device takes it: RGB, ``(height, width, 3)`` uint8, C-contiguous."""
        picture = np.asarray(frame)
        if picture.ndim != 3 or picture.shape[2] not in (3, 4):
            raise ValueError(f"a frame of shape {picture.shape}; expected (H, W, 3) or (H, W, 4)")
        if picture.shape[2] == 4:  # the renderers' straight alpha, over the background colour
            picture = over(picture, self.background)
        width, height = self.size
        if picture.shape[:2] != (height, width):
            picture = cv2.resize(picture, (width, height), interpolation=cv2.INTER_AREA)
        return np.ascontiguousarray(picture, dtype=np.uint8)

    def skip(self, frames: int) -> None:
        """Frames went by undrawn: the device keeps showing the last one, as a camera does."""

    def close(self) -> None:
        """Release the device."""
        self.camera.close()

    def abort(self) -> None:
        """The same as :meth:`close`: nothing sent can be taken back."""
        self.close()


def open_virtual_camera(spec: str, rate: float = 30.0, size: tuple[int, int] = (512, 512),
                        background: tuple[float, ...] = (0.0, 0.0, 0.0), **_: Any) -> VirtualCamera:
    """``vcam:`` (the first device) or ``vcam:DEVICE``: frames at ``rate`` (at most 60 a second)."""
    device = spec.removeprefix("vcam:") or None
    return VirtualCamera(size, min(rate, 60.0), device, (float(background[0]), float(background[1]),
                                                         float(background[2])))
