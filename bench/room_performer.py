"""``room.performer_page_kbps``: what the performer page (``/r/ROOM/perform``) uploads, measured in
headless Chromium with a fake camera playing the shared GRID clip (a talking face, 25 frames a
second, looped), MediaPipe tracking it in the page, through a room server on loopback.

The page's compact frames (:mod:`toonface.room.performers`: the scores the mapping reads that
changed, and the head turn) as the page counts them, with the 6 bytes of WebSocket framing a
client's message carries (goal 10 kbit/s, issue 68: 168-240 kbit/s of JSON before); the detail
adds the TCP/IPv4 headers of one segment a message, the frames a second and the bytes a frame.

Where Chromium, the clip, MediaPipe's page files or its model are missing the figure is 0,
without a goal, with ``"skipped"`` in the detail saying why.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from bench.core import REALDATA, Figure
from bench.room_page import TCP_IP, browser_missing, headless_chromium, wait_until
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

TOKENS = {"bench": ("perform-bench-token-0123", "watch-bench-token-0123")}
CLIP = REALDATA / "video" / "grid" / "bbaf2n.mpg"
GOAL = 10.0
#: Chromium's flags for a fake camera that needs no one's permission.
FAKE_CAMERA = ("--use-fake-device-for-media-stream", "--use-fake-ui-for-media-stream",
               "--autoplay-policy=no-user-gesture-required")
COUNTS = "return [window.performer.sentBytes, window.performer.sent, window.performer.faces, performance.now()]"


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the figure (see the module docstring)."""
    why = browser_missing() or page_missing()
    if why:
        return [Figure("room.performer_page_kbps", 0.0, "kbit/s", None, False, {"skipped": why, "goal": GOAL})]
    from bench.fake_camera import y4m_from

    seconds = 4.0 if quick else 15.0
    with tempfile.TemporaryDirectory() as folder:
        clip = y4m_from(CLIP, Path(folder) / "clip.y4m")
        flags = (*FAKE_CAMERA, f"--use-file-for-fake-video-capture={clip}")
        with in_thread(Rooms(TOKENS, face="cat")) as base, headless_chromium(*flags) as driver:
            driver.get(f"{base.replace('ws://', 'http://')}/r/bench/perform#perform={TOKENS['bench'][0]}")
            wait_until(driver, "window.performer.sent > 25 || window.performer.error", timeout=90.0)
            error = driver.execute_script("return window.performer.error")
            if error:
                raise RuntimeError(f"the performer page stopped: {error}")
            start = driver.execute_script(COUNTS)
            wait_until(driver, f"performance.now() > {start[3] + seconds * 1000}", timeout=seconds + 30)
            end = driver.execute_script(COUNTS)
    sent_bytes, sent, faces = (end[k] - start[k] for k in range(3))
    elapsed = (end[3] - start[3]) / 1000
    kbps = (sent_bytes + 6 * sent) * 8 / elapsed / 1000  # a client's frame: 2 bytes of header and a 4-byte mask
    return [Figure("room.performer_page_kbps", kbps, "kbit/s", GOAL, False,
                   {"with_tcp_ip_kbps": round((sent_bytes + (6 + TCP_IP) * sent) * 8 / elapsed / 1000, 2),
                    "frames_per_s": round(sent / elapsed, 1), "bytes_per_frame": round(sent_bytes / max(sent, 1), 1),
                    "faces_share": round(faces / max(sent, 1), 3), "seconds": round(elapsed, 2),
                    "camera": "shared GRID clip bbaf2n, 25 fps, looped"})]


def page_missing() -> str | None:
    """Why the performer page cannot run here (the clip, MediaPipe's page files or its model
    absent), or None; its browser tests skip with it too."""
    from capture.face_landmarks import model_path
    from common import InputError
    from toonface.room.browsers import web_modules

    if not CLIP.is_file():
        return f"the shared GRID clip is absent ({CLIP})"
    if not (web_modules() / "@mediapipe" / "tasks-vision" / "vision_bundle.mjs").is_file():
        return "@mediapipe/tasks-vision is not installed (make browser installs it with npm)"
    try:
        model_path()
    except InputError as exc:
        return str(exc)
    return None
