"""The room's viewer page that draws the faces itself (issue 63, the default page): sent only the
performers' packets (the server relays them and draws nothing), it draws what the offscreen
renderer draws for the same motors; a sealed room opens in the page that holds the key while the
server holds none."""

import re

import numpy as np
import pytest
from room_pages import KEY, TOKENS, face_png, performer, settled_pictures

from toon import load_face
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread


@pytest.mark.slow  # Chromium and four seconds of stream: make test runs it
def test_the_page_that_draws_the_face_itself_is_sent_only_the_stream_and_draws_what_the_renderer_does():
    """The page loads the face's web rig once and is then sent the performer's packets as a native
    viewer is (no drawing on the server: the room has no stage); it acknowledges them, so the
    performer hears back; what it draws, the ears' physics settled, is what the offscreen renderer
    draws for the pose; and what it is sent is a few kbit/s."""
    from browser import chromium, wait_for

    face = load_face("cat")
    rooms = Rooms(TOKENS, face=face)
    with in_thread(rooms) as base, chromium(900, 900) as driver, performer(base, 0x2A) as one:
        driver.get(f"{base.replace('ws://', 'http://')}/r/demo?draw=page#watch={TOKENS['demo'][1]}")
        wait_for(driver, "window.viewer.connected")
        one.start()
        wait_for(driver, "window.viewer.performers.size === 1 && window.viewer.frames > 30", timeout=30)
        start = driver.execute_script("return [window.viewer.bytes, performance.now()]")
        one.wait(3.0)  # the ears settle, the bytes count
        end = driver.execute_script("return [window.viewer.bytes, performance.now()]")
        values = driver.execute_script("return window.viewer.last.performers[0].values")
        caption = driver.execute_script("return document.querySelector('figcaption').textContent")
        shown = face_png(driver)
    assert rooms.rooms["demo"].browsers is None  # nothing drawn on the server
    assert one.sender.acks > 0  # the page's acknowledgements reached the performer
    said = re.match(r"performer 2a · latency (\d+) ms · loss 0 % · concealed ", caption)  # (the clocks told)
    assert said is not None and 0 < int(said.group(1)) < 500, caption
    np.testing.assert_allclose([values[c] for c in ("MB", "BLM")], [0.9, 0.85], atol=0.006)
    kbps = (end[0] - start[0]) * 8 / (end[1] - start[1])  # bytes a millisecond: kbit/s
    assert 0.5 < kbps < 5  # packets alone (15 a second), where the drawn page is sent hundreds
    drawn, neutral = settled_pictures(face)
    assert shown.shape == drawn.shape
    difference = np.abs(shown - drawn)
    assert difference.mean() < 0.6 and np.mean(difference.max(axis=2) > 64) < 0.01
    assert np.abs(shown - neutral).mean() > 3 * difference.mean()


@pytest.mark.slow  # Chromium and two pages of stream: make test runs it
def test_a_sealed_room_opens_in_the_page_that_holds_the_key_and_the_server_holds_none():
    """End to end: the performer seals, the room server has no key and relays what it cannot
    read, the page with the key in its link's fragment opens the packets (and seals its
    acknowledgements, which the performer opens), and a page without it says why it shows nothing."""
    from browser import chromium, wait_for

    from toonface.cli_stream import page_key

    rooms = Rooms(TOKENS, face=load_face("classic"))
    assert rooms.key is None
    with in_thread(rooms) as base, chromium(900, 900) as driver, performer(base, 0x2B, KEY) as one:
        page = f"{base.replace('ws://', 'http://')}/r/demo?draw=page#watch={TOKENS['demo'][1]}"
        driver.get(f"{page}&key={page_key(KEY)}")
        wait_for(driver, "window.viewer.connected")
        one.start()
        wait_for(driver, "window.viewer.frames > 30 && window.viewer.sent > 0", timeout=30)
        values = driver.execute_script("return window.viewer.last.performers[0].values")
        acks = one.sender.acks
        driver.get("about:blank")  # (a new fragment alone would not load the page again)
        driver.get(page)  # no key
        wait_for(driver, "(document.querySelector('figcaption') || {}).textContent?.includes('do not open')")
        caption = driver.execute_script("return document.querySelector('figcaption').textContent")
        frames = driver.execute_script("return window.viewer.frames")
    np.testing.assert_allclose([values[c] for c in ("MB", "BLM")], [0.9, 0.85], atol=0.006)
    assert acks > 0  # the page's sealed acknowledgements opened at the performer
    assert caption == "performer 2b · its packets do not open: sealed (add the key to the link: #watch=…&key=…)"
    assert frames == 0


def test_the_check_tells_a_page_whether_its_token_is_taken_and_only_from_a_header():
    import asyncio

    import aiohttp

    rooms = Rooms(TOKENS)

    async def ask(base: str) -> list[int]:
        url = f"{base.replace('ws://', 'http://')}/r"
        async with aiohttp.ClientSession() as session:
            answers = []
            for room, role, token in (("demo", "watch", TOKENS["demo"][1]), ("demo", "perform", TOKENS["demo"][0]),
                                      ("demo", "watch", TOKENS["demo"][0]), ("nowhere", "watch", TOKENS["demo"][1]),
                                      ("demo", "watch", "")):
                async with session.get(f"{url}/{room}/check?role={role}",
                                       headers={"Authorization": f"Bearer {token}"}) as answer:
                    answers.append(answer.status)
            async with session.get(f"{url}/demo/check?role=watch&token={TOKENS['demo'][1]}") as answer:
                answers.append(answer.status)  # a token in the address is not read
            return answers

    with in_thread(rooms) as base:
        answers = asyncio.run(ask(base))
    assert answers == [204, 204, 403, 403, 403, 403]  # a wrong room answers as a wrong token does


@pytest.mark.slow  # Chromium: make test runs it
def test_a_viewer_page_with_a_wrong_token_says_so_and_stops_knocking():
    """It tried again every half second forever, saying "a wrong token, or the server is away"."""
    from browser import chromium, wait_for

    rooms = Rooms(TOKENS)
    timers = "window.timers = []; const later = window.setTimeout; " \
             "window.setTimeout = (f, ms, ...rest) => { window.timers.push(ms); return later(f, ms, ...rest); };"
    with in_thread(rooms) as base, chromium(900, 600) as driver:
        driver.execute_cdp_cmd("Page.addScriptToEvaluateOnNewDocument", {"source": timers})  # what the page asks
        page = f"{base.replace('ws://', 'http://')}/r/demo"
        driver.get(f"{page}#watch=not-the-token")
        wait_for(driver, "window.viewer.refused === true", timeout=20)
        status = driver.execute_script("return document.getElementById('status').textContent")
        asked = driver.execute_script("return window.timers")
        knocks = rooms.refused["token"]
        driver.get(f"{page}#watch={TOKENS['demo'][1]}")  # the right link, pasted into the same tab
        wait_for(driver, "window.viewer.connected === true", timeout=20)
    assert status.startswith("the room server refuses this link's watch token: open the link it printed")
    assert 500 not in asked  # no try again in half a second (as there was), nor any
    assert knocks == 2  # the socket, then the check
