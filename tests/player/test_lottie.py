"""The Lottie export (issue 41): its structure by hand, and lottie-web (npm) in headless
Chromium showing the offscreen renderer's frame at three times on every built-in face."""

import io
import json
from pathlib import Path

import numpy as np
import pytest
from browser import chromium, wait_for
from PIL import Image

from capture import synthesize
from player.backends import open_renderer
from player.offline import resample
from toon import FaceRig, builtin_faces, load_face
from toon.lottie import track_lottie
from toonface.pipeline import truth_track

LOTTIE_WEB = Path(__file__).resolve().parents[2] / "node_modules" / "lottie-web" / "build" / "player" / "lottie.min.js"


def _values(seconds: float = 10.0):
    return resample(truth_track(synthesize(seconds=seconds, rate=30.0, seed=4)), 30.0)


def test_layers_run_top_first_and_the_face_subtracts_every_hole():
    rig = FaceRig(load_face("classic"))
    values = _values(3.0)
    doc = track_lottie([rig.geometry(row) for row in values], 30.0, (256, 256))
    assert (doc["w"], doc["h"], doc["fr"], doc["op"]) == (256, 256, 30.0, len(values))
    names = [layer["nm"] for layer in doc["layers"]]
    drawn = [item.name for item in rig.geometry(values[0]).items if item.name]
    assert names[-1] == "background"  # drawn first: at the bottom
    face = next(layer for layer in doc["layers"] if layer["nm"] == "face")
    holes = [item.name for item in rig.geometry(values[0]).items if item.mask_write]
    assert [m["mode"] for m in face["masksProperties"]] == ["s"] * len(holes)
    assert {m["nm"] for m in face["masksProperties"]} == set(holes)
    order = [n for n in names if n in drawn]
    assert order == [n for n in reversed(drawn) if n in order]  # Lottie's first layer is drawn last
    pupil = next(layer for layer in doc["layers"] if layer["nm"] == "pupil_l")
    assert {m["mode"] for m in pupil["masksProperties"]} == {"a"}  # clipped to its eye's hole


@pytest.mark.slow
def test_lottie_web_shows_the_renderers_frames_at_three_times(tmp_path):
    if not LOTTIE_WEB.is_file():
        pytest.skip("lottie-web is missing (make browser installs it with npm)")
    values = _values()
    with chromium(800, 900) as driver, open_renderer((512, 512)) as renderer:
        for name in builtin_faces():
            rig = FaceRig(load_face(name))
            document = json.dumps(track_lottie([rig.geometry(row) for row in values], 30.0))
            page = tmp_path / f"{name}.html"
            page.write_text(f"""<!DOCTYPE html><html><body style="margin:0">
                <div id="box" style="width:512px;height:512px"></div><script src="{LOTTIE_WEB.as_uri()}"></script>
                <script>window.anim = lottie.loadAnimation({{container: document.getElementById("box"),
                renderer: "svg", loop: false, autoplay: false, animationData: {document}}});</script></body></html>""")
            driver.get(page.as_uri())
            wait_for(driver, "window.anim && window.anim.isLoaded")
            for frame in (60, 150, 270):
                driver.execute_script(f"anim.goToAndStop({frame}, true);")
                png = driver.find_element("id", "box").screenshot_as_png
                shown = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
                drawn = renderer.render(rig.geometry(values[frame])).astype(int)
                assert np.abs(shown - drawn).mean() <= 1.5, (name, frame, np.abs(shown - drawn).mean())
