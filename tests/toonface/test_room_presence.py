"""Presence that ends (issue 68, item 2): a performer who leaves is gone from the viewer page at
once (the server says so), one who falls silent within two seconds, and a server restarted leaves
exactly one figure per live performer (the page forgets what the old process showed)."""

import time

import pytest
from pubsub import free_port
from room_pages import TOKENS, Performer, performer

from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

pytestmark = pytest.mark.slow  # Chromium and performers: make test runs it

FIGURES = "document.querySelectorAll('#stage figure').length"


def test_a_performer_who_leaves_is_gone_from_the_page_at_once(tmp_path):
    from browser import chromium, wait_for

    rooms = Rooms(TOKENS, face="cat")
    with in_thread(rooms) as base, chromium(900, 700) as driver:
        driver.get(f"{base.replace('ws://', 'http://')}/r/demo#watch={TOKENS['demo'][1]}")
        wait_for(driver, "window.viewer.connected")
        with performer(base, 0x31) as one, performer(base, 0x32) as two:
            one.start()
            two.start()
            wait_for(driver, f"{FIGURES} === 2", timeout=20)
            sizes = driver.execute_script("return [...document.querySelectorAll('#stage svg')].map(s => "
                                          "[s.getBoundingClientRect().bottom, s.getBoundingClientRect().right])")
            assert all(bottom <= 700 and right <= 900 for bottom, right in sizes), sizes  # both in the window
            one.close()  # its socket closes: the server says it left
            left = time.monotonic()
            wait_for(driver, f"{FIGURES} === 1", timeout=5)
            assert time.monotonic() - left < 1.0  # said at once, not after its silence
        wait_for(driver, f"{FIGURES} === 0", timeout=5)


def test_a_restarted_server_leaves_one_figure_per_live_performer():
    """A restarted server's page showed the departed performer's frozen face above the live one,
    for good."""
    from browser import chromium, wait_for

    port = free_port()
    with chromium(900, 700) as driver:
        live = None
        try:
            with in_thread(Rooms(TOKENS, face="cat"), port=port) as base:
                driver.get(f"{base.replace('ws://', 'http://')}/r/demo#watch={TOKENS['demo'][1]}")
                with performer(base, 0x41) as departed:  # performs, then is gone with the server
                    departed.start()
                    live = Performer(base, 0x42)
                    live.start()
                    wait_for(driver, f"{FIGURES} === 2", timeout=20)
            with in_thread(Rooms(TOKENS, face="cat"), port=port):  # the server again; the live one reconnects
                restarted = time.monotonic()
                wait_for(driver, "window.viewer.connected && window.viewer.performers.size === 1 && "
                                 "window.viewer.performers.has(0x42)", timeout=10)
                assert time.monotonic() - restarted < 2.0  # within two seconds (the Done-when's)
                live.wait(2.5)  # (past the page's two seconds of silence: nothing else comes back)
                ids = driver.execute_script("return [...window.viewer.performers.keys()]")
                assert ids == [0x42] and driver.execute_script(f"return {FIGURES}") == 1
        finally:
            if live is not None:
                live.close()
