"""A server-drawn viewer on a slow link (issue 68): through a proxy that carries 64 or 128 kbit/s
back and queues the rest without bound, the pose it shows is under a second old (the
stage sends what changed since the drawings it has, once the link has taken the last; before,
the picture fell a second behind every second), and what its caption says of the delay is the
delay measured.

The performer's mouth opens steadily over 20 s, so each pose shown tells when it was captured;
the brows and lids move too, so that every frame's drawing changes more than the link carries."""

import asyncio
import json
import time
import zlib

import aiohttp
import numpy as np
import pytest
from room_pages import TOKENS, performer
from throttle import throttled

from toon import motor_index, standard_neutral
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

RAMP_SECONDS = 20.0


def _motion(t: float) -> np.ndarray:
    values = standard_neutral().copy()
    values[motor_index("MB")] = 0.05 + 0.9 * min(t / RAMP_SECONDS, 1.0)  # the capture's time, as an opening
    for k, code in enumerate(("BLM", "BRM", "BLL", "BRL", "ELU", "ERU")):
        values[motor_index(code)] = 0.5 + 0.4 * np.sin(2 * np.pi * (0.7 + 0.2 * k) * t)
    return values


async def _watch(url: str, started: float, seconds: float) -> tuple[list[float], list[float], int]:
    """As the server-drawn page does (answer each message shown): the age of each pose shown,
    what the caption would say of it (the stage's latency and the link's, ms), and the bytes."""
    ages, captions, link_ms, total = [], [], 0, 0
    headers = {"Authorization": f"Bearer {TOKENS['demo'][1]}"}
    async with aiohttp.ClientSession() as session, session.ws_connect(url, headers=headers) as ws:
        end = time.time() + seconds
        while time.time() < end:
            message = await ws.receive(timeout=10)
            if message.type == aiohttp.WSMsgType.TEXT:
                link_ms = json.loads(message.data)["delay_ms"]
                continue
            total += len(message.data)
            stage = json.loads(zlib.decompress(message.data))
            await ws.send_str("s")
            for shown in stage["performers"]:
                opening = shown["quality"]["values"]["MB"]
                if 0.1 < opening < 0.9 and shown["quality"]["latency_ms"] is not None:
                    ages.append(time.time() - (started + (opening - 0.05) / 0.9 * RAMP_SECONDS))
                    captions.append((shown["quality"]["latency_ms"] + link_ms) / 1000)
    return ages, captions, total


@pytest.mark.slow  # twelve seconds of a slow link each: make test runs them
@pytest.mark.parametrize("kbps", [64, 128])
def test_a_viewer_on_a_slow_link_sees_a_pose_under_a_second_old_and_its_caption_says_how_old(kbps):
    rooms = Rooms(TOKENS, face="cat")
    with in_thread(rooms) as base, performer(base, 0x2A, motion=_motion) as one:
        port = int(base.rsplit(":", 1)[1])
        with throttled(port, kbps) as slow:
            one.start()
            ages, captions, total = asyncio.run(_watch(f"ws://127.0.0.1:{slow}/r/demo/ws?role=watch&format=drawn",
                                                       one.started, 12.0))
    later = slice(len(ages) // 4, None)  # after the first whole drawing and the first word of the delay
    assert total * 8 / 12.0 / 1000 < kbps  # the link was full: what it carried, not what was drawn
    # Before the fix the picture fell a second behind every second (ages up to ~12 s here). A loaded
    # machine adds a few hundred ms to a pose's way now and then (CI once read 1.12 s), so: the typical
    # pose is under a second old, none is more than one and a half, and the last ones are no older
    # than the first ones (the delay does not grow).
    assert len(ages) > 12 and np.median(ages) < 1.0 and max(ages) < 1.5, (len(ages), np.median(ages), max(ages))
    half = len(ages) // 2
    assert np.median(ages[half:]) < np.median(ages[:half]) + 0.3, (ages[:half], ages[half:])
    assert abs(np.median(captions[later]) - np.median(ages[later])) < 0.1, (np.median(captions), np.median(ages))
    assert rooms.rooms["demo"].browsers is None or rooms.rooms["demo"].browsers.skipped > 0
