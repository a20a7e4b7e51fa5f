"""A studio server in a thread and headless Chromium driven by Selenium, for the browser tests.

The browser is Debian's ``chromium`` with its ``chromedriver`` (``make test`` installs them with
apt-get when missing); where either is absent the tests skip, saying so. Nothing is downloaded:
the driver and the browser are named, so Selenium Manager has nothing to look for.
"""

from __future__ import annotations

import asyncio
import shutil
import threading
from collections.abc import Iterator
from contextlib import contextmanager

import pytest


@contextmanager
def studio_server(session, host: str = "127.0.0.1") -> Iterator[str]:
    """Serve ``session`` on a free port of ``host`` (loopback unless told) in a thread; yields the
    page's address, as the studio prints it."""
    from toonface.studio.server import serve

    loop = asyncio.new_event_loop()
    ready = threading.Event()
    address: list[str] = []

    def on_ready(url: str) -> None:
        address.append(url)
        ready.set()

    task_box: list[asyncio.Task] = []

    def run() -> None:
        asyncio.set_event_loop(loop)
        task = loop.create_task(serve(session, host, 0, on_ready))
        task_box.append(task)
        try:
            loop.run_until_complete(task)
        except asyncio.CancelledError:
            pass

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    assert ready.wait(10), "the studio server did not start"
    try:
        yield address[0]
    finally:
        loop.call_soon_threadsafe(task_box[0].cancel)
        thread.join(10)
        loop.close()


@contextmanager
def chromium(width: int = 1280, height: int = 900, flags: tuple[str, ...] = ()) -> Iterator:
    """Headless Chromium at device scale 1 with its console log kept, and ``flags`` besides; skips
    where it is missing."""
    browser, driver_path = shutil.which("chromium") or shutil.which("chromium-browser"), shutil.which("chromedriver")
    if browser is None or driver_path is None:
        pytest.skip("Chromium or chromedriver is missing (make test installs Debian's chromium and chromium-driver)")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = browser
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--hide-scrollbars",
                 "--force-device-scale-factor=1", f"--window-size={width},{height}", "--no-first-run",
                 "--disable-extensions", "--disable-background-networking", *flags):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(options=options, service=Service(executable_path=driver_path))
    try:
        yield driver
    finally:
        driver.quit()


def wait_for(driver, script: str, timeout: float = 20.0):
    """Run ``script`` (a JavaScript expression) in the page until it is truthy; returns its value."""
    from selenium.webdriver.support.ui import WebDriverWait

    return WebDriverWait(driver, timeout, poll_frequency=0.05).until(lambda d: d.execute_script(f"return {script}"))


#: The page has drawn a frame.
DRAWN = "window.studio && window.studio.frames > 0"


@contextmanager
def studio_page(session, ready: str = DRAWN, width: int = 1280, height: int = 900) -> Iterator:
    """``session`` served and open in headless Chromium, once ``ready`` (a JavaScript expression)
    holds; yields the driver."""
    with studio_server(session) as url, chromium(width, height) as driver:
        driver.get(url)
        wait_for(driver, ready)
        yield driver


def design_off(driver) -> None:
    """Leave design mode and hide the control points, so that the page shows the face alone (as
    the offscreen renderer draws it)."""
    driver.execute_script("document.getElementById('design').click();"
                          "document.getElementById('show-points').click()")
    wait_for(driver, "document.getElementById('shape').classList.contains('off')")


def page_against_offscreen(driver, session):
    """How far the face the page shows (a screenshot of ``#view``, whatever size the layout gives
    it) is from the offscreen renderer's picture of the session's face at the values of the frame
    the page shows (its physics' swing included), drawn at that size: absolute differences
    ``(H, W, 3)``."""
    import io

    import numpy as np
    from PIL import Image

    from player.backends import open_renderer
    from toon import MOTOR_CODES, FaceRig

    for _ in range(20):  # a frame that stayed while the screenshot was taken (a swinging face moves on)
        before = driver.execute_script("return window.studio.last.values")
        png = driver.find_element("id", "view").screenshot_as_png
        values = driver.execute_script("return window.studio.last.values")
        if values == before:
            break
    shown = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    motors = np.array([values[code] for code in MOTOR_CODES])
    extra = {code: values[code] for code in session.face.extra_codes if code in values}
    height, width = shown.shape[:2]
    assert min(width, height) >= 256, f"the face is shown only {width}x{height}"
    with open_renderer((width, height)) as renderer:
        drawn = renderer.render(FaceRig(session.face).geometry(motors, extra)).astype(int)
    assert shown.shape == drawn.shape
    return np.abs(shown - drawn)


def drop_file(driver, path) -> None:
    """The file at ``path`` dragged from the desktop onto the studio's face: Selenium cannot drag
    from the desktop, so the file is handed to a hidden input, then dropped."""
    driver.execute_script("const i = document.createElement('input'); i.type = 'file'; i.id = 'carried';"
                          "i.style.display = 'none'; document.body.append(i)")
    driver.find_element("id", "carried").send_keys(str(path))
    driver.execute_script("const t = new DataTransfer(); t.items.add(document.getElementById('carried').files[0]);"
                          "document.getElementById('carried').remove();"
                          "document.getElementById('stage').dispatchEvent(new DragEvent('drop', "
                          "{dataTransfer: t, bubbles: true, cancelable: true}))")
