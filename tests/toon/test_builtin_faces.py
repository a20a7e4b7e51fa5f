"""Every built-in face: round trips, every expression drawn and distinct, GL against the CPU and SVG."""

import io
import json

import numpy as np
import pytest
from pictures import near_an_edge

from common import InputError
from player import Renderer
from toon import (
    FaceRig,
    builtin_faces,
    geometry_svg,
    load_expressions,
    load_face,
    render_cpu,
    save_face,
    standard_neutral,
)
from toonface.cli import main

FACES = builtin_faces()


def test_at_least_the_four_kinds_of_face_ship():
    assert {"wizard", "round", "lines", "cat", "classic"} <= set(FACES)
    lines = load_face("lines")
    assert not lines.polygons and all(c.kind in ("polyline", "skeleton") and c.fill is None
                                      for c in lines.basic_components())


@pytest.mark.parametrize("name", FACES)
def test_round_trip_and_standard_neutral(name, tmp_path):
    face = load_face(name)
    again = load_face(save_face(face, tmp_path / f"{name}.json"))
    assert again == face and again.to_dict() == face.to_dict()
    np.testing.assert_allclose(face.neutral(), standard_neutral(), atol=1e-9)


@pytest.mark.parametrize("name", FACES)
def test_every_expression_renders_and_no_two_look_alike(ctx, name):
    face = load_face(name)
    rig = FaceRig(face)
    expressions = load_expressions()
    with Renderer(ctx, (96, 96), samples=0) as renderer:
        images = {n: renderer.render(rig.geometry(e.pose(face.neutral()))) for n, e in expressions.items()}
    names = list(images)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            changed = np.any(images[a] != images[b], axis=2).sum()
            assert changed >= 20, f"{name}: {a} and {b} differ in only {changed} pixels"


@pytest.mark.parametrize("name", FACES)
@pytest.mark.parametrize("expression", ["neutral", "happiness", "surprise", "anger"])
def test_gl_matches_the_cpu_oracle(ctx, name, expression):
    face = load_face(name)
    geom = FaceRig(face).geometry(load_expressions()[expression].pose(face.neutral()))
    with Renderer(ctx, (64, 64), samples=0) as r:
        gpu = r.render(geom)
    cpu = render_cpu(geom, (64, 64))
    differ = np.any(np.abs(gpu.astype(int) - cpu.astype(int)) > 2, axis=2)
    # Only pixels whose centres lie on an edge may differ; interiors may not.
    inner = ~near_an_edge(cpu)
    assert not (differ & inner).any(), f"{(differ & inner).sum()} interior pixels differ"
    assert differ.mean() < 0.02, f"{differ.sum()} of 4096 pixels differ"


@pytest.mark.parametrize("name", FACES)
def test_gl_and_svg_agree(ctx, name):
    resvg = pytest.importorskip("resvg_py")
    import cv2

    face = load_face(name)
    geom = FaceRig(face).geometry(load_expressions()["happiness"].pose(face.neutral()))
    with Renderer(ctx, (128, 128), samples=4) as r:
        gpu = r.render(geom)
    png = resvg.svg_to_bytes(svg_string=geometry_svg(geom, (128, 128)), width=128, height=128)
    svg = cv2.cvtColor(cv2.imdecode(np.frombuffer(bytes(png), np.uint8), cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
    diff = np.abs(gpu.astype(int) - svg.astype(int)).max(axis=2)
    assert np.median(diff) <= 2 and (diff > 48).mean() < 0.03, f"{(diff > 48).mean():.3%} pixels differ"


def test_svg_is_valid_xml_with_masks_and_clips():
    import xml.etree.ElementTree as ET

    face = load_face("classic")
    root = ET.parse(io.StringIO(geometry_svg(FaceRig(face).geometry(standard_neutral())))).getroot()
    ns = "{http://www.w3.org/2000/svg}"
    assert root.find(f"{ns}defs/{ns}mask") is not None
    assert len(root.findall(f"{ns}defs/{ns}clipPath")) == 3
    assert len(root.findall(f"{ns}g")) == len(FaceRig(face).geometry(standard_neutral()).items)


@pytest.mark.parametrize("mutate, expected", [
    (lambda d: d["polygons"][0].update(vertices="square"), r"polygons\[0\].vertices: expected a list"),
    (lambda d: d["polygons"][2].update(attach="PX"), r'polygons\[2\].attach: unknown control point "PX"'),
    (lambda d: d["polygons"][0].update(vertices=[[0, 0], [5, 5], [10, 10], [15, 15]]),
     r"polygons\[0\].vertices: degenerate polygon"),
    (lambda d: d["polygons"][3]["vertices"][1].__setitem__(0, float("nan")),
     r"polygons\[3\].vertices\[1\]: expected a list of 2 numbers"),
    (lambda d: d["motors"].pop("MLV"), r"motors.MLV: missing motor range"),
    (lambda d: d["head"].update(pivot="centre"), r"head.pivot: expected a list of 2 numbers"),
    (lambda d: d.update(components=[{"kind": "polyline", "points": ["ERU", "Bx"], "stroke": "#000000",
                                     "width": 2}]), r'components\[0\].points\[1\]: unknown control point "Bx"'),
])
def test_bad_face_files_each_say_what_is_wrong(tmp_path, mutate, expected):
    doc = load_face("classic").to_dict()
    mutate(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))  # json writes NaN as a bare NaN, as some tools do
    with pytest.raises(InputError, match=expected):
        load_face(path)


def test_expression_file_errors(tmp_path):
    path = tmp_path / "e.toml"
    path.write_text('format = "toonface.expressions/1"\n[expressions.neutral]\nmotors = { MBX = 0.5 }\n')
    with pytest.raises(InputError, match=r"expressions.neutral.motors.MBX: expected one of BRL, .*, got 'MBX'"):
        load_expressions(path)
    path.write_text('format = "toonface.expressions/1"\n[expressions.neutral]\nmotors = { MB = 1.5 }\n')
    with pytest.raises(InputError, match=r"expressions.neutral.motors.MB: expected a number from 0 to 1, got 1.5"):
        load_expressions(path)
    path.write_text('format = "toonface.expressions/1"\n[expressions.neutral]\nmotors = {}\n')
    with pytest.raises(InputError, match=r"missing expression\(s\): happiness, surprise"):
        load_expressions(path)


def test_face_command_sheet_svg_and_bad_file(tmp_path, capsys):
    sheet, svg = tmp_path / "sheet.png", tmp_path / "wink.svg"
    assert main(["face", "cat", "--sheet", str(sheet), "--svg", str(svg), "--expression", "wink", "--size", "64"]) == 0
    import cv2

    image = cv2.imread(str(sheet))
    # 9 expressions, HT 0 and 1, UL 1, JS 0 and 1, PERK 1, EARS 1, WHISK 0 and 1: 18 in 5 columns
    assert image.shape == (4 * (64 + 28), 5 * 64, 3)
    assert svg.read_text().startswith("<svg")
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "toonface.face/1"}')
    capsys.readouterr()
    assert main(["face", str(bad)]) != 0
    err = capsys.readouterr().err.strip()
    assert err.startswith("toonface: error:") and "bad.json" in err and "\n" not in err


def test_the_same_input_gives_the_same_pixels(ctx):
    face = load_face("round")
    geom = FaceRig(face).geometry(load_expressions()["fear"].pose(face.neutral()))
    frames = []
    for _ in range(2):
        with Renderer(ctx, (100, 70), samples=4) as r:  # any size, not only squares
            frames.append(r.render(geom))
    assert frames[0].shape == (70, 100, 3) and np.array_equal(frames[0], frames[1])
