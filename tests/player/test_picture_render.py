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


def test_the_outputs_that_animate_outlines_refuse_a_face_with_pictures_in_a_line(tmp_path, capsys, monkeypatch):
    """Animated SVG, Lottie and the web page key outlines, not pictures: each refuses before it
    draws, naming what does carry them; a video and SVG frames draw them."""
    import json

    from toon import save_track
    from toon.track import MotorTrack
    from toonface.cli import main

    monkeypatch.chdir(tmp_path)
    face = face_from_dict(picture_face(data_uri(QUAD)))
    (tmp_path / "pic.json").write_text(json.dumps(face.to_dict()))
    values = np.tile(face.neutral(), (10, 1))
    save_track(MotorTrack(values, 10.0), tmp_path / "m.csv")
    for argv in (["render", "m.csv", "-o", "x.svg"], ["render", "m.csv", "-o", "x.json"],
                 ["export", "web", "m.csv", "-o", "x.html"]):
        assert main([*argv, "--face", str(tmp_path / "pic.json"), "--size", "64"]) == 2, argv
        err = capsys.readouterr().err
        assert "image components are not in animated SVG" in err and err.count("\n") == 1, err
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(("x.", ".x"))]
    assert main(["render", "m.csv", "-o", "x.webm", "--face", "pic.json", "--size", "64", "--background", "none"]) == 0
    assert main(["render", "m.csv", "-o", "frames", "--format", "svg", "--face", "pic.json", "--size", "64"]) == 0
    assert "picture-0" in (tmp_path / "frames" / "frame_000000.svg").read_text()
