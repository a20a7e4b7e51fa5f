"""Image components drawn by Cairo and by OpenGL as the CPU oracle draws them (issue 46): the
picture's pixels where its corners are, over what lies beneath, clipped as a clipped component
is, transparent where its picture is."""

import sys
from pathlib import Path

import numpy as np
import pytest

from toon import FaceRig, render_cpu
from toon.face import face_from_dict

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "toon"))
from test_images import QUAD, data_uri, picture_face  # noqa: E402

SIZE = (256, 256)


def _check(draw) -> None:
    """``draw``'s frame against the oracle's: as close as the faces' own are (the oracle does not
    antialias, so edges differ: tests/toon/test_builtin_faces.py allows 3 % of pixels off by more
    than 48), and within 3 of 255 on average where the pictures lie."""
    from dataclasses import replace

    face = face_from_dict(picture_face(data_uri(QUAD), rotate={"motor": "MB", "at0": [0], "at1": [40],
                                                                "origin": [-150, 150]}))
    values = face.neutral()
    values[18] = 0.6  # MB: the square turned some 24 degrees, the beard hanging lower
    geometry = FaceRig(face).geometry(values)
    drawn, oracle = draw(geometry).astype(int), render_cpu(geometry, SIZE).astype(int)
    bare = render_cpu(replace(geometry, items=tuple(i for i in geometry.items if i.picture is None)), SIZE)
    diff = np.abs(drawn - oracle).max(axis=2)
    assert np.mean(diff) < 1.5 and (diff > 48).mean() < 0.02, (np.mean(diff), (diff > 48).mean())
    pictured = (oracle != bare).any(axis=2)
    assert pictured.mean() > 0.03 and diff[pictured].mean() < 3, diff[pictured].mean()


def test_cairo_draws_the_picture_as_the_oracle_does():
    from player.cairo_renderer import CairoRenderer

    with CairoRenderer(SIZE) as renderer:
        _check(renderer.render)


def test_opengl_draws_the_picture_as_the_oracle_does(ctx):
    from player.renderer import Renderer

    with Renderer(ctx, SIZE, samples=4) as renderer:
        _check(renderer.render)


@pytest.mark.parametrize("backend", ["cairo", "gl"])
def test_a_picture_keeps_its_alpha_on_a_transparent_background(backend, ctx):
    """Where only the half-clear quarter covers the clear background, alpha is the picture's."""
    from player.backends import open_renderer
    from toon.raster import to_pixels

    doc = picture_face(data_uri(QUAD))
    doc["background"] = "#00000000"
    doc["polygons"], doc["components"] = [], doc["components"][-2:-1]
    doc["components"][0]["layer"] = 1
    face = face_from_dict(doc)
    geometry = FaceRig(face).geometry(face.neutral())
    with open_renderer(SIZE, backend=backend, ctx=ctx if backend == "gl" else None) as renderer:
        rgba = renderer.render(geometry, alpha=True)
    (x0, y0), (x1, _), _, (_, y1) = to_pixels(geometry.items[0].vertices, geometry.viewbox, SIZE)
    x, y = int(x0 + 0.75 * (x1 - x0)), int(y0 + 0.75 * (y1 - y0))
    assert abs(int(rgba[y, x, 3]) - 128) <= 2 and np.abs(rgba[y, x, :3].astype(int) - 255).max() <= 3
    assert rgba[int(y0) - 3, x, 3] == 0  # outside it, nothing


def test_every_output_of_render_and_export_carries_a_face_s_pictures(tmp_path, monkeypatch):
    """A video with alpha, SVG frames, the animated SVG, Lottie (an embedded asset) and the web
    page, each from the command line."""
    import json

    from toon import save_track
    from toon.track import MotorTrack
    from toonface.cli import main

    monkeypatch.chdir(tmp_path)
    face = face_from_dict(picture_face(data_uri(QUAD)))
    (tmp_path / "pic.json").write_text(json.dumps(face.to_dict()))
    values = np.tile(face.neutral(), (10, 1))
    save_track(MotorTrack(values, 10.0), tmp_path / "m.csv")
    assert main(["render", "m.csv", "-o", "x.json", "--face", "pic.json", "--size", "64"]) == 0
    lottie = json.loads((tmp_path / "x.json").read_text())
    assert [a["p"][:22] for a in lottie["assets"]] == ["data:image/png;base64,"]  # one picture, used twice
    assert sorted(layer["ty"] for layer in lottie["layers"]).count(2) == 2
    assert main(["render", "m.csv", "-o", "x.svg", "--face", "pic.json", "--size", "64"]) == 0
    assert main(["export", "web", "m.csv", "-o", "x.html", "--face", "pic.json", "--size", "64"]) == 0
    page = (tmp_path / "x.html").read_text()  # the picture in the face's web rig, drawn by the page (test_web_rig)
    assert page.count('"picture":{"href":"data:image/png;base64,') == 2
    assert main(["render", "m.csv", "-o", "x.webm", "--face", "pic.json", "--size", "64", "--background", "none"]) == 0
    assert main(["render", "m.csv", "-o", "frames", "--format", "svg", "--face", "pic.json", "--size", "64"]) == 0
    assert "picture-0" in (tmp_path / "frames" / "frame_000000.svg").read_text()


def _swinging():
    """Pictures turning, sliding and hanging from the jaw as MB swings over two seconds at 30 fps:
    the rig and the frames' motor values ``(60, 21)``."""
    face = face_from_dict(picture_face(data_uri(QUAD), rotate={"motor": "MB", "at0": [-30], "at1": [60],
                                                                "origin": [-150, 150]},
                                       translate={"motor": "MB", "at0": [0, 0], "at1": [40, -20]}))
    times = np.arange(60) / 30.0
    rows = np.tile(face.neutral(), (len(times), 1))
    rows[:, 18] = 0.5 + 0.5 * np.sin(2 * np.pi * times / 2.0)
    return FaceRig(face), rows


@pytest.mark.slow
def test_the_animated_svg_places_pictures_as_the_renderer_does_in_a_browser(tmp_path):
    """Pictures turning, sliding and hanging from the jaw, in an animated SVG paused at three
    times in headless Chromium, against the offscreen renderer's frames."""
    import io

    from browser import chromium
    from PIL import Image

    from player.backends import open_renderer
    from toon.svg_anim import save_track_svg

    rig, rows = _swinging()
    path = save_track_svg([rig.geometry(row) for row in rows], 30.0, tmp_path / "pictures.svg")
    with chromium(700, 800) as driver, open_renderer((512, 512), backend="cairo") as renderer:
        driver.get(path.as_uri())
        for t in (0.4, 1.0, 1.5):
            driver.execute_script(f"const s = document.documentElement; s.pauseAnimations(); s.setCurrentTime({t});")
            shown = np.asarray(Image.open(io.BytesIO(driver.get_screenshot_as_png())).convert("RGB"))[:512, :512]
            drawn = renderer.render(rig.geometry(rows[int(round(t * 30))]))
            diff = np.abs(shown.astype(int) - drawn.astype(int))
            assert diff.mean() <= 1.5 and (diff.max(axis=2) > 48).mean() < 0.01, (t, diff.mean())


@pytest.mark.slow
def test_lottie_web_places_pictures_as_the_renderer_does(tmp_path):
    """The same turning, sliding, hanging pictures as a Lottie animation, played by lottie-web
    (npm) in Chromium and stopped at three frames, against the offscreen renderer's."""
    import io
    import json

    from browser import chromium, wait_for
    from PIL import Image

    from player.backends import open_renderer
    from toon.lottie import track_lottie

    lottie_web = Path(__file__).resolve().parents[2] / "node_modules/lottie-web/build/player/lottie.min.js"
    if not lottie_web.is_file():
        pytest.skip("lottie-web is missing (make browser installs it with npm)")
    rig, rows = _swinging()
    document = json.dumps(track_lottie([rig.geometry(row) for row in rows], 30.0))
    page = tmp_path / "pictures.html"
    page.write_text(f"""<!DOCTYPE html><html><body style="margin:0">
        <div id="box" style="width:512px;height:512px"></div><script src="{lottie_web.as_uri()}"></script>
        <script>window.anim = lottie.loadAnimation({{container: document.getElementById("box"),
        renderer: "svg", loop: false, autoplay: false, animationData: {document}}});</script></body></html>""")
    with chromium(800, 900) as driver, open_renderer((512, 512), backend="cairo") as renderer:
        driver.get(page.as_uri())
        wait_for(driver, "window.anim && window.anim.isLoaded")
        for frame in (12, 30, 45):
            driver.execute_script(f"anim.goToAndStop({frame}, true);")
            png = driver.find_element("id", "box").screenshot_as_png
            shown = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))
            diff = np.abs(shown.astype(int) - renderer.render(rig.geometry(rows[frame])).astype(int))
            assert diff.mean() <= 1.5 and (diff.max(axis=2) > 48).mean() < 0.01, (frame, diff.mean())
