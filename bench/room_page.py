"""``room.browser_kbps`` and ``room.page_frame_p95_ms``: the viewer page that draws the faces
itself (``/r/ROOM?draw=page``, issue 63), measured in headless Chromium through a room server on
loopback.

``room.browser_kbps``
    What one browser viewer costs both ways (goal 10): the packets it is sent and the
    acknowledgements it sends, as the page counts them, with the WebSocket framing and TCP/IPv4
    headers ``room.wire_both_kbps`` counts (one segment a message, a bare TCP acknowledgement for
    every second one received); a performer at 30 fps, 2 frames a packet, talking (the mouth's five
    motors and the head moving), on the classic face.
``room.page_frame_p95_ms``
    The 95th percentile of the page's time to draw a frame (read the due frame, run the physics,
    evaluate the rig, write the SVG; the browser's own painting after it is not in it), a 60 Hz
    stream of every motor moving on the round face, the heaviest built-in (goal 8: 60 fps with
    room to spare on this 2-core machine); the detail gives the frames drawn a second.

Where Chromium or chromedriver is missing both are reported as 0, without a goal (not "met"),
with ``"skipped"`` in the detail saying why (``make test`` installs them).
"""

from __future__ import annotations

import shutil
import threading
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

from bench.core import Figure
from stream.packets import StreamWriter
from toon import MOTOR_CODES, load_face, standard_neutral
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

TOKENS = {"bench": ("perform-bench-token-0123", "watch-bench-token-0123")}
TCP_IP = 40  # bytes of TCP and IPv4 headers a segment
#: Counters the page keeps: bytes and messages received, bytes and messages sent, frames drawn.
COUNTS = "return [window.viewer.bytes || 0, window.viewer.messages || 0, window.viewer.sentBytes || 0, " \
         "window.viewer.sent || 0, window.viewer.frames, performance.now()]"


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the two figures."""
    why = browser_missing()
    if why:
        return [Figure("room.browser_kbps", 0.0, "kbit/s", None, False, {"skipped": why, "goal": 10.0}),
                Figure("room.page_frame_p95_ms", 0.0, "ms", None, False, {"skipped": why, "goal": 8.0})]
    seconds = 4.0 if quick else 15.0
    talking = [MOTOR_CODES.index(code) for code in ("MB", "MLH", "MRH", "MLV", "MRV", "HH", "HV")]
    counts, _ = _watch("classic", 30.0, 2, talking, seconds)
    down = counts["bytes"] + counts["messages"] * (2 + TCP_IP)  # a server's frame: 2 bytes of header
    up = counts["sent_bytes"] + counts["sent"] * (6 + TCP_IP) + (counts["messages"] // 2) * TCP_IP
    kbps = (down + up) * 8 / counts["seconds"] / 1000
    detail = {"down_kbps": round(down * 8 / counts["seconds"] / 1000, 3),
              "up_kbps": round(up * 8 / counts["seconds"] / 1000, 3), "face": "classic", "rate_hz": 30.0,
              "frames_per_packet": 2, "packets": counts["messages"], "acks": counts["sent"],
              "estimate": "one TCP segment a message", "seconds": round(counts["seconds"], 2)}
    frame_counts, frame_ms = _watch("round", 60.0, 1, list(range(21)), seconds)
    return [Figure("room.browser_kbps", kbps, "kbit/s", 10.0, False, detail),
            Figure("room.page_frame_p95_ms", float(np.percentile(frame_ms, 95)), "ms", 8.0, False,
                   {"median_ms": round(float(np.median(frame_ms)), 2), "face": "round", "stream_hz": 60.0,
                    "fps": round(frame_counts["frames"] / frame_counts["seconds"], 1),
                    "frames": len(frame_ms)})]


def browser_missing() -> str | None:
    if (shutil.which("chromium") or shutil.which("chromium-browser")) is None or shutil.which("chromedriver") is None:
        return "Chromium or chromedriver is missing (make test installs them)"
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is missing (pip install toonface[test])"
    return None


def _watch(face: str, rate: float, per_packet: int, moving: list[int], seconds: float) -> tuple[dict, list[float]]:
    """A performer streaming ``moving`` motors on ``face`` at ``rate`` to a page that draws it:
    the page's counts over ``seconds`` (after the first frames) and its frames' drawing times."""
    from stream.sender import StreamSender
    from stream.websocket import WebSocketLink

    rooms = Rooms(TOKENS, face=load_face(face))
    stop = threading.Event()

    def perform(sender: StreamSender) -> None:
        k = 0
        while not stop.wait(1 / rate):
            values = standard_neutral().copy()
            values[moving] = 0.5 + 0.4 * np.sin(2 * np.pi * (0.7 + 0.3 * np.arange(len(moving))) * k / rate)
            sender.write(k / rate, np.clip(values, 0, 1))
            k += 1

    with in_thread(rooms) as base, headless_chromium() as driver:
        link = WebSocketLink(f"{base}/r/bench", TOKENS["bench"][0], "perform")
        sender = StreamSender((link.where, 0), StreamWriter(rate, frames_per_packet=per_packet, stream=9), link=link)
        thread = threading.Thread(target=perform, args=(sender,))
        driver.get(f"{base.replace('ws://', 'http://')}/r/bench?draw=page#watch={TOKENS['bench'][1]}")
        wait_until(driver, "window.viewer.connected")
        thread.start()
        try:
            wait_until(driver, "window.viewer.frames > 30")
            start = driver.execute_script(COUNTS)
            stop.wait(seconds)
            end = driver.execute_script(COUNTS)
            frame_ms = driver.execute_script("return window.viewer.frameMs")
        finally:
            stop.set()
            thread.join()
            sender.close()
    names = ("bytes", "messages", "sent_bytes", "sent", "frames")
    counts = {name: end[k] - start[k] for k, name in enumerate(names)}
    counts["seconds"] = (end[5] - start[5]) / 1000
    return counts, [float(ms) for ms in frame_ms]


@contextmanager
def headless_chromium(*flags: str) -> Iterator:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium") or shutil.which("chromium-browser") or ""
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--force-device-scale-factor=1", "--window-size=900,900", "--no-first-run", *flags):
        options.add_argument(flag)
    driver = webdriver.Chrome(options=options, service=Service(executable_path=shutil.which("chromedriver") or ""))
    try:
        yield driver
    finally:
        driver.quit()


def wait_until(driver, script: str, timeout: float = 30.0) -> None:
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(driver, timeout, poll_frequency=0.05).until(lambda d: d.execute_script(f"return {script}"))
