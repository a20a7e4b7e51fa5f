"""The studio as the browser viewer of a motor stream: the face follows the stream and the page
shows its latency, loss and concealed frames."""

import socket

import numpy as np
import pytest
from browser import studio_page, wait_for
from motor_streams import RATE, smooth_motion
from studios import temp_folder

from stream.packets import StreamWriter
from toon import motor_index
from toonface.studio.live import ReceivedStream
from toonface.studio.session import StudioSession

pytestmark = pytest.mark.slow


def test_a_stream_drives_the_face_and_its_quality_shows():
    import time

    session = StudioSession("classic", folder=temp_folder())
    values = smooth_motion(240)
    values[:, motor_index("MB")] = np.linspace(0.1, 0.9, 240)  # the mouth opens over the stream
    writer = StreamWriter(RATE, first_sequence=0)
    with ReceivedStream(("127.0.0.1", 0), session.neutral) as stream:
        session.live = stream  # received, but not shown until asked
        with studio_page(session) as driver:
            assert driver.execute_script("return document.getElementById('live').hidden") is False
            driver.find_element("id", "show-live").click()  # shown from now on (it was not at the start here)
            wait_for(driver, "window.studio.last.showing === 'live'")
            out = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            for row in values:  # at once, stamped with this machine's clock: the jitter buffer plays them out
                datagram = writer.push(row, time.perf_counter())
                if datagram is not None and writer.packets != 40:  # one packet lost on the way
                    out.sendto(datagram, stream.receiver.address)
            out.close()
            wait_for(driver, "window.studio.last.values.MB > 0.8")
            wait_for(driver, "window.studio.quality && window.studio.quality.packets >= 100", timeout=5)
            readout = driver.find_element("id", "quality").text
            quality = driver.execute_script("return window.studio.quality")
            assert quality["loss_pct"] > 0 and quality["latency_ms"] is not None
            assert f"loss {quality['loss_pct']} %" in readout and "latency" in readout and "concealed" in readout
            driver.find_element("id", "show-live").click()  # back to test mode, from where the stream left the face
            wait_for(driver, "window.studio.last.showing === 'test'")
            shown = driver.execute_script("return window.studio.last.values")
            assert session.values[motor_index("MB")] == pytest.approx(shown["MB"], abs=1e-6)


def test_play_streams_what_it_shows_to_a_studio(tmp_path):
    """`play --stream-to`: a live session the studio (or `receive`) can view."""
    from toon import MotorTrack, save_track, standard_neutral
    from toonface.cli import main

    values = np.tile(standard_neutral(), (25, 1))
    values[:, motor_index("MB")] = np.linspace(0.1, 0.9, 25)
    track = save_track(MotorTrack(values, 25.0), tmp_path / "open.csv")
    with ReceivedStream(("127.0.0.1", 0), standard_neutral()) as stream:
        host, port = stream.receiver.address
        assert main(["play", "--listen", "off", "--size", "64", "--loop-ms", "40", "--motors", str(track), "--once",
                     "--stream-to", f"{host}:{port}"]) == 0
        # 25 loops, two frames a packet; a loaded machine drops loops (and sends fewer), none is lost
        assert stream.receiver.wait_for_packets(3, timeout=10)
        assert stream.receiver.reader.lost == 0 and stream.receiver.diagnosis() is None
    assert main(["play", "--listen", "off", "--motors", str(track), "--stream-to", "nowhere"]) == 2
