"""The preview's OBS page (issue 44): only the face, on a transparent page at the size asked, fed
with PNG frames that keep their alpha; checked over HTTP and in a real Chromium."""

import io
import urllib.request

import numpy as np
import pytest
from PIL import Image

from player.preview import PreviewSink


def face_frame() -> np.ndarray:
    """A 64x48 RGBA frame: a clear background and an opaque red square in the middle."""
    frame = np.zeros((48, 64, 4), np.uint8)
    frame[12:36, 16:48] = (255, 0, 0, 255)
    return frame


def fetch(url: str) -> tuple[bytes, dict]:
    with urllib.request.urlopen(url, timeout=5) as answer:
        return answer.read(), dict(answer.headers)


def test_the_newest_frame_comes_as_a_png_with_its_alpha_and_the_page_asks_its_size():
    sink = PreviewSink(("127.0.0.1", 0))
    try:
        sink.write(face_frame())
        png, headers = fetch(sink.url + "frame.png")
        picture = np.asarray(Image.open(io.BytesIO(png)))
        assert headers["Content-Type"] == "image/png" and picture.shape == (48, 64, 4)
        assert tuple(picture[0, 0]) == (0, 0, 0, 0) and tuple(picture[24, 32]) == (255, 0, 0, 255)
        page, _ = fetch(sink.url + "obs?width=320&height=240")
        assert b'width="320" height="240"' in page and b"background:transparent" in page
        assert b'width="64" height="48"' in fetch(sink.url + "obs")[0]  # the frame's own size by default
        jpeg, _ = fetch(sink.url + "frame.jpg")  # the MJPEG side lays the clear part over black
        assert np.asarray(Image.open(io.BytesIO(jpeg)))[2, 2].max() < 16
        with pytest.raises(urllib.error.HTTPError) as refused:
            fetch(sink.url + "obs?width=99999")
        assert refused.value.code == 400
        refused.value.close()  # the error holds the answer's socket
    finally:
        sink.close()


@pytest.mark.slow
def test_obs_page_in_chromium_draws_the_face_and_leaves_the_rest_clear():
    from browser import chromium, wait_for

    sink = PreviewSink(("127.0.0.1", 0))
    try:
        with chromium(400, 300) as driver:
            sink.write(face_frame())
            driver.get(sink.url + "obs?width=128&height=96")
            wait_for(driver, "window.toonfaceDrawn >= 1")
            pixels = driver.execute_script(
                "const c = document.getElementById('face').getContext('2d');"
                "return [Array.from(c.getImageData(2, 2, 1, 1).data), Array.from(c.getImageData(64, 48, 1, 1).data)];")
            assert pixels[0][3] == 0 and pixels[1] == [255, 0, 0, 255]  # scaled 2x: the corner clear, the face red
            body = driver.execute_script("return getComputedStyle(document.body).backgroundColor")
            assert body == "rgba(0, 0, 0, 0)"  # a transparent page: OBS lays it over the scene
    finally:
        sink.close()
