"""``live``: the live Animator's timing, rendering 512x512 at 25 loops a second.

``live.lateness_p95_ms``: how late (95th percentile) each loop starts after its due time while
the face is rendered every loop and the mouth is kept talking by commands (goal 2 ms).
``live.latency_ms``: from a command sent over the TCP socket (at random moments) to the end of
rendering of the first frame that shows it; the median, with the 95th percentile in the detail
(goal: one loop time, 40 ms). A command waits for the next loop (half a loop on average) and
then for that loop's slice and render.
"""

from __future__ import annotations

import socket
import threading
import time

import numpy as np

from bench.core import Figure
from player.animator import Animator, Loop
from player.commands import Commands
from player.gl import create_context
from player.renderer import Renderer
from player.server import CommandServer, local_port, start
from toon import FaceRig, load_expressions, load_face, motor_index

LOOP_TIME = 0.040


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``live.*`` figures."""
    loops = 100 if quick else 375  # 4 s or 15 s
    face = load_face("classic")
    rig = FaceRig(face)
    animator = Animator(face.neutral(), LOOP_TIME)
    loop = Loop(animator)
    commands = Commands(animator, face.neutral(), load_expressions(), lambda: time.perf_counter() - loop.started)
    server = CommandServer(("127.0.0.1", 0), commands.handle)
    start(server)
    shown: list[tuple[float, float]] = []  # (time the frame was ready, MB shown)
    sent: list[tuple[float, float]] = []  # (time sent, MB target)
    ctx = create_context()
    try:
        with Renderer(ctx, (512, 512), 4) as renderer:
            def frame(values: np.ndarray, t: float) -> None:
                renderer.render(rig.geometry(values))
                shown.append((time.perf_counter(), float(values[motor_index("MB")])))

            client = threading.Thread(target=_send_commands, args=(local_port(server), loops * LOOP_TIME, sent),
                                      daemon=True)
            client.start()
            loop.run(loops, frame)
            client.join(timeout=5)
    finally:
        server.shutdown()
        server.server_close()
        ctx.release()
    lateness_ms = np.array(loop.lateness[1:]) * 1000
    latencies = _latencies(sent, shown)
    detail = {"loops": loops, "loop_ms": LOOP_TIME * 1000, "size": [512, 512], "face": "classic"}
    return [Figure("live.lateness_p95_ms", float(np.percentile(lateness_ms, 95)), "ms", 2.0, False,
                   {**detail, "median_ms": round(float(np.median(lateness_ms)), 3),
                    "max_ms": round(float(lateness_ms.max()), 3)}),
            Figure("live.latency_ms", float(np.median(latencies)) if latencies else float("nan"), "ms",
                   LOOP_TIME * 1000, False,
                   {**detail, "commands": len(latencies), "p95_ms": round(float(np.percentile(latencies, 95)), 2)
                    if latencies else None, "via": "TCP on loopback"})]


def _send_commands(port: int, seconds: float, sent: list[tuple[float, float]]) -> None:
    """Alternate the mouth between shut and open (0 ms moves: one slice) at random moments."""
    rng = np.random.default_rng(0)
    end = time.perf_counter() + seconds - 0.3
    with socket.create_connection(("127.0.0.1", port), timeout=5) as conn, conn.makefile("rb") as replies:
        target = 0.9
        while time.perf_counter() < end:
            time.sleep(float(rng.uniform(0.1, 0.2)))
            sent.append((time.perf_counter(), target))
            conn.sendall(f"MB {target} 0\n".encode())
            replies.readline()
            target = 0.9 if target < 0.5 else 0.1


def _latencies(sent: list[tuple[float, float]], shown: list[tuple[float, float]]) -> list[float]:
    """Per command, ms from sending to the first frame ready after it that shows its target."""
    out = []
    for when, target in sent:
        for ready, value in shown:
            if ready >= when and abs(value - target) < 1e-9:
                out.append((ready - when) * 1000)
                break
    return out
