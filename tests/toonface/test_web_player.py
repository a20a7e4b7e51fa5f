"""The exported web player (issue 41; issue 63: it draws the face itself from the web rig and the
track, with the pages' shared modules): one HTML file, no server; in headless Chromium it shows
the offscreen renderer's frame at three times, keeps its sound, and has a transparent mode."""

import dataclasses
import io
import re

import numpy as np
import pytest
from browser import chromium, wait_for
from PIL import Image
from sounds import write_tone

from capture import synthesize
from player.backends import open_renderer
from player.offline import geometries
from toon import FaceRig, MotorTrack, load_face, save_track
from toonface.cli import main
from toonface.pipeline import truth_track
from toonface.web_export import player_page

TIMES = (1.0, 2.5, 4.0)


def _track() -> MotorTrack:
    whole = truth_track(synthesize(seconds=9.0, rate=30.0, seed=2))
    return MotorTrack(whole.values[-150:], whole.rate)  # five seconds of expressions


def test_the_page_is_one_file_with_no_outside_reference():
    page = player_page(_track(), load_face("classic"), size=(256, 256))
    assert '"format":"toonface-web-rig"' in page and "class TrackMotion" in page and "window.player" in page
    assert "<animate" not in page  # drawn by the page, not an animated SVG
    assert not re.search(r'(src|href)="(https?:|//)', page)  # nothing fetched from elsewhere
    assert 'max="4.96667"' in page  # 150 frames at 30 Hz: 149 steps


def test_the_command_refuses_another_suffix(tmp_path, capsys):
    save_track(_track(), tmp_path / "m.csv")
    assert main(["export", "web", str(tmp_path / "m.csv"), "-o", str(tmp_path / "p.svg")]) == 2
    assert "expected a .html page" in capsys.readouterr().err


@pytest.mark.slow
@pytest.mark.parametrize(("face_name", "transparent"), [("cat", False), ("round", True)])
def test_the_player_shows_the_renderers_frames_and_plays_its_sound(face_name, transparent, tmp_path):
    track = _track()
    save_track(track, tmp_path / "m.csv")
    write_tone(tmp_path / "tone.wav", seconds=5.0)  # and a second of silence
    args = ["export", "web", str(tmp_path / "m.csv"), "--face", face_name, "-o", str(tmp_path / "p.html"),
            "--sound", str(tmp_path / "tone.wav"), "--paused"]
    assert main([*args, "--transparent"] if transparent else args) == 0
    face = load_face(face_name)
    if transparent:  # the page has no background: the browser's white shows through
        face = dataclasses.replace(face, background=(1.0, 1.0, 1.0, 1.0))
    frames = list(geometries(track, FaceRig(face), 30.0))  # the player's own frames, the face's physics too
    with chromium(800, 900) as driver, open_renderer((512, 512)) as renderer:
        driver.get((tmp_path / "p.html").as_uri())
        wait_for(driver, "window.player && document.getElementById('sound').readyState >= 1")
        assert driver.execute_script("return document.getElementById('sound').duration") == pytest.approx(6.0, abs=0.1)
        shown_controls = driver.execute_script("return getComputedStyle(document.getElementById('controls')).display")
        assert (shown_controls == "none") == transparent
        for t in TIMES:
            driver.execute_script(f"player.seek({t});")
            png = driver.find_element("css selector", "#stage svg").screenshot_as_png
            shown = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
            drawn = renderer.render(frames[int(round(t * 30))]).astype(int)
            assert shown.shape == drawn.shape and np.abs(shown - drawn).mean() <= 1.5, (t, np.abs(shown - drawn).mean())
        if transparent:  # what OBS's browser source composites: the page's own alpha
            driver.execute_cdp_cmd("Emulation.setDefaultBackgroundColorOverride", {"color": {"r": 0, "g": 0, "b": 0,
                                                                                             "a": 0}})
            png = driver.find_element("css selector", "#stage svg").screenshot_as_png
            alpha = np.asarray(Image.open(io.BytesIO(png)).convert("RGBA"))[..., 3]
            assert alpha[0, 0] == 0 and alpha[-1, -1] == 0 and alpha[256, 256] == 255
        driver.execute_script("player.seek(0.5); player.play();")
        wait_for(driver, "player.playing && player.now() > 0.7 && player.drawn > 10", 5.0)


def test_a_parameter_no_face_has_is_an_error_naming_it_as_a_render_says(tmp_path, capsys):
    track = _track()
    odd = MotorTrack(track.values, track.rate, extra_codes=("BEARDX",), extra=np.full((track.frames, 1), 0.5))
    save_track(odd, tmp_path / "m.csv")
    assert main(["export", "web", str(tmp_path / "m.csv"), "-o", str(tmp_path / "p.html")]) == 2
    assert "has no parameter BEARDX" in capsys.readouterr().err and not (tmp_path / "p.html").exists()
