"""The virtual camera sink against a fake device (issue 44): frames with alpha laid over the
background, scaled to the device's size, sent at the device's rate; a machine with no
pyvirtualcam or no device is told in one line how to get one; the real device where it exists."""

import glob

import numpy as np
import pytest

from common import InputError
from player.vcam import HOW_TO_GET_ONE, VirtualCamera, open_pyvirtualcam
from toonface.cli import main


class FakeCamera:
    """A device that takes 64x48 RGB whatever it is asked for, and keeps what it is sent."""

    def __init__(self, width: int, height: int, fps: float, device: str | None) -> None:
        self.width, self.height, self.fps, self.device = 64, 48, fps, device
        self.frames: list[np.ndarray] = []
        self.closed = False

    def send(self, frame: np.ndarray) -> None:
        assert frame.dtype == np.uint8 and frame.shape == (48, 64, 3) and frame.flags["C_CONTIGUOUS"]
        self.frames.append(frame.copy())

    def close(self) -> None:
        self.closed = True


def sink(fps: float = 30.0, background=(0.0, 0.0, 1.0)):
    now = [0.0]
    made = VirtualCamera((128, 96), fps, "/dev/video9", background, open_camera=FakeCamera, clock=lambda: now[0])
    return made, now


def test_frames_with_alpha_are_laid_over_the_background_and_scaled_to_the_device():
    camera, _ = sink()
    frame = np.zeros((96, 128, 4), np.uint8)
    frame[:, :64] = (255, 0, 0, 255)  # the left half an opaque red face
    frame[:, 64:] = (255, 0, 0, 0)  # the right half clear
    camera.write(frame)
    (sent,) = camera.camera.frames
    assert tuple(sent[24, 10]) == (255, 0, 0) and tuple(sent[24, 54]) == (0, 0, 255)  # over blue, at 64x48
    half = frame.copy()
    half[..., 3] = 128
    assert tuple(camera.converted(half)[5, 5]) == (128, 0, 127)  # straight alpha, half and half
    camera.close()
    assert camera.camera.closed and camera.camera.device == "/dev/video9"


def test_frames_go_at_the_devices_rate_from_a_faster_player():
    camera, now = sink(fps=30.0)
    for k in range(120):  # two seconds of a 60 Hz player
        now[0] = k / 60
        camera.write(np.zeros((96, 128, 3), np.uint8))
    assert camera.sent == 60 and camera.dropped == 60  # 30 a second
    camera, now = sink(fps=30.0)
    for k in range(40):  # a player at 20 Hz: every frame goes, none is made up
        now[0] = k / 20
        camera.write(np.zeros((96, 128, 3), np.uint8))
    assert camera.sent == 40 and camera.dropped == 0


def test_no_virtual_camera_is_a_one_line_error_saying_how_to_get_one(monkeypatch, capsys):
    import builtins

    real_import = builtins.__import__

    def without_pyvirtualcam(name, *args, **kwargs):
        if name == "pyvirtualcam":
            raise ImportError("no module named pyvirtualcam")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", without_pyvirtualcam)
    with pytest.raises(InputError, match="pip install 'toonface\\[vcam\\]'"):
        open_pyvirtualcam(64, 48, 30.0, None)
    assert main(["play", "--listen", "off", "--seconds", "0.2", "--virtual-camera"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "v4l2loopback" in err and HOW_TO_GET_ONE[:40] in err
    assert "the virtual camera: a virtual camera needs pyvirtualcam" in err and "vcam::" not in err  # was "vcam::"


def test_the_real_device_where_there_is_one():
    pytest.importorskip("pyvirtualcam")
    if not glob.glob("/dev/video*"):
        pytest.skip("no video device on this machine (v4l2loopback not loaded)")
    assert main(["play", "--listen", "off", "--seconds", "0.5", "--size", "128x128", "--virtual-camera"]) == 0
