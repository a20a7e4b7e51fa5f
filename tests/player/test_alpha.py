"""Transparent pictures (issue 41): every built-in face over nothing, to an RGBA PNG folder,
WebM (VP9 with alpha), ProRes 4444, APNG and WebP, decoded back; held against the same frames
drawn opaque over white and over black (which pixels nothing covers, which are covered whole)."""

import dataclasses

import numpy as np
import pytest
from scipy.ndimage import binary_erosion

from common import InputError
from player.alpha import straight
from player.alpha_sinks import decode_rgba
from toon import MotorTrack, builtin_faces, load_face, standard_neutral
from toonface.pipeline import render

SIZE = (96, 96)
#: How far a decoded picture may be from the oracle (whole-picture mean, alpha error, and pixels
#: next to an edge left out of the alpha check): lossless PNG, 10-bit ProRes, lossy VP9 4:2:0
#: (whose alpha rings within two pixels of an edge, and is off by up to 7/255 beyond at crf 10).
TOLERANCE = {"png": (0.5, 1, 0), "mov": (1.0, 2, 0), "webm": (2.5, 8, 2)}


def _track() -> MotorTrack:
    neutral = standard_neutral()
    rows = np.repeat(neutral[None], 3, axis=0)
    rows[1, 18] = 0.9  # MB: the mouth wide
    rows[2, [0, 3]] = 0.9  # brows up
    return MotorTrack(np.clip(rows, 0, 1), 10.0)


def _frames(path, kind: str) -> list[np.ndarray]:
    if kind == "png":
        from PIL import Image

        return [np.asarray(Image.open(p).convert("RGBA")) for p in sorted(path.glob("frame_*.png"))]
    return decode_rgba(path)


def _over(rgba: np.ndarray, colour: int) -> np.ndarray:
    alpha = rgba[..., 3:4].astype(float) / 255
    return rgba[..., :3] * alpha + colour * (1 - alpha)


def test_straight_alpha_undoes_premultiplication_by_hand():
    premultiplied = np.array([[[128, 64, 0, 128], [0, 0, 0, 0], [255, 255, 255, 255], [10, 20, 30, 40]]], np.uint8)
    np.testing.assert_array_equal(straight(premultiplied),
                                  [[[255, 128, 0, 128], [0, 0, 0, 0], [255, 255, 255, 255], [64, 128, 191, 40]]])


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["gl", "cairo"])
@pytest.mark.parametrize("face_name", builtin_faces())
def test_a_transparent_face_decodes_with_clean_alpha_and_no_dark_fringe(face_name, backend, tmp_path, monkeypatch):
    monkeypatch.setenv("TOONFACE_RENDERER", backend)
    face = load_face(face_name)
    track = _track()
    white = dataclasses.replace(face, background=(1.0, 1.0, 1.0, 1.0))
    black = dataclasses.replace(face, background=(0.0, 0.0, 0.0, 1.0))
    clear = dataclasses.replace(face, background=(*face.background[:3], 0.0))
    render(track, white, tmp_path / "white", SIZE)
    render(track, black, tmp_path / "black", SIZE)
    on_white, on_black = (_frames(tmp_path / name, "png") for name in ("white", "black"))
    outputs = {"png": tmp_path / "clear", "webm": tmp_path / "clear.webm", "mov": tmp_path / "clear.mov"}
    for kind, path in outputs.items():
        assert render(track, clear, path, SIZE) == 3
        decoded = _frames(path, kind)
        assert len(decoded) == 3, kind
        mean_tol, alpha_tol, margin = TOLERANCE[kind]
        for got, w, b in zip(decoded, on_white, on_black, strict=True):
            w, b = w[..., :3].astype(int), b[..., :3].astype(int)
            outside = (w == 255).all(axis=2) & (b == 0).all(axis=2)  # nothing covers it
            inside = (w == b).all(axis=2)  # covered whole by opaque shapes
            if margin:  # (a line drawing's strokes are thinner than the margin: nothing inside is left)
                outside, inside = (binary_erosion(m, iterations=margin) for m in (outside, inside))
            if inside.any():
                assert (255 - got[..., 3][inside].astype(int)).max() <= alpha_tol, (face_name, kind)
            assert outside.any() and (inside.any() or face_name == "lines")  # lines: strokes only, none whole
            assert np.abs(got[..., 3][outside].astype(int)).max() <= alpha_tol, (face_name, kind)
            composited = _over(got, 255)
            assert np.abs(composited - w).mean() <= mean_tol, (face_name, kind)
            edge = (got[..., 3] > 0) & (got[..., 3] < 255)
            darker = (w - composited)[edge].mean()  # a dark fringe over white: the edges darker than drawn there
            assert darker <= 2 * mean_tol, (face_name, kind, darker)
            assert np.abs(_over(got, 0) - b).mean() <= mean_tol, (face_name, kind)  # and over black alike


def test_apng_and_webp_loop_transparent(tmp_path):
    from PIL import Image

    clear = dataclasses.replace(load_face("classic"), background=(1.0, 1.0, 1.0, 0.0))
    for name in ("loop.apng", "loop.webp"):
        render(_track(), clear, tmp_path / name, SIZE)
        with Image.open(tmp_path / name) as image:
            assert image.info["loop"] == 0 and image.n_frames >= 2  # for ever; WebP merges repeated frames
            first = np.asarray(image.convert("RGBA"))
        assert first[0, 0, 3] == 0 and first[SIZE[1] // 2, SIZE[0] // 2, 3] == 255


def test_an_mp4_refuses_a_transparent_background_and_leaves_nothing(tmp_path):
    clear = dataclasses.replace(load_face("classic"), background=(1.0, 1.0, 1.0, 0.0))
    with pytest.raises(InputError, match="no alpha channel"):
        render(_track(), clear, tmp_path / "out.mp4", SIZE)
    assert list(tmp_path.iterdir()) == []


def test_render_takes_background_none_and_names_the_formats(tmp_path, capsys):
    from toon import save_track
    from toonface.cli import main

    save_track(_track(), tmp_path / "m.csv")
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "a.webm"), "--background", "none",
                 "--size", "64"]) == 0
    assert decode_rgba(tmp_path / "a.webm")[0][0, 0, 3] == 0
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "a.webm"), "--background", "#ff0000",
                 "--size", "64"]) == 0
    assert tuple(decode_rgba(tmp_path / "a.webm")[0][0, 0]) == pytest.approx((255, 0, 0, 255), abs=3)
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "a.gif")]) == 2
    err = capsys.readouterr().err
    assert ".webm" in err and ".mov" in err and ".apng" in err and "Traceback" not in err
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "b.webm"), "--background", "pink"]) == 2
