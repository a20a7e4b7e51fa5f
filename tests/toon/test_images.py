"""Image components (issue 46): a PNG picture stretched over the parallelogram of three points,
on a layer, moved and shown by motors as any component is; read from a file beside the face or
from the face file itself; drawn alike by the CPU oracle, the SVG export (rasterised by resvg),
and (tests/player) Cairo and OpenGL."""

import numpy as np
import pytest
from pictures import png_bytes

from common import InputError
from toon import FaceRig, load_face, motor_index, render_cpu
from toon.face import face_from_dict
from toon.images import DATA_PNG, corners
from toon.svg import geometry_svg

#: A 64x64 picture of four flat quarters: red, green / blue, half-clear white (flat, so that
#: every drawer's filtering agrees but along the quarters' edges).
QUAD = np.repeat(np.repeat(np.array([[[255, 0, 0, 255], [0, 255, 0, 255]], [[0, 0, 255, 255], [255, 255, 255, 128]]],
                                    np.uint8), 32, axis=0), 32, axis=1)


def picture_face(src: str, **extra) -> dict:
    """The classic face with a 2x2 picture over a square of the background, and a second one that
    hangs from the mouth's bottom (its lower corners follow MB)."""
    doc = load_face("classic").to_dict()
    mb = doc["points"]["MB"]
    doc["components"] = [*doc.get("components", []),
                         {"kind": "image", "name": "square", "src": src, "layer": 2,
                          "points": [[-200, 200], [-100, 200], [-200, 100]], **extra},
                         {"kind": "image", "name": "beard", "src": src, "layer": 3,
                          "points": [[mb[0] - 20, mb[1]], [mb[0] + 20, mb[1]],
                                     {"slave": "MB", "at": [mb[0] - 20, mb[1] - 40]}]}]
    return doc


def data_uri(pixels: np.ndarray) -> str:
    import base64

    return DATA_PNG + base64.b64encode(png_bytes(pixels)).decode("ascii")


def _item(geometry, name: str):
    return next(i for i in geometry.items if i.name == name)


def test_a_picture_is_read_from_the_face_file_or_beside_it_and_written_back_as_given(tmp_path):
    (tmp_path / "quad.png").write_bytes(png_bytes(QUAD))
    embedded = face_from_dict(picture_face(data_uri(QUAD)))
    import json

    (tmp_path / "face.json").write_text(json.dumps(picture_face("quad.png")))
    beside = load_face(tmp_path / "face.json")
    for face in (embedded, beside):
        square = next(c for c in face.components if c.name == "square")
        assert square.picture is not None and np.array_equal(square.picture.pixels, QUAD)
    assert beside.to_dict()["components"][-2]["src"] == "quad.png"  # as written
    assert face_from_dict(embedded.to_dict()).to_dict() == embedded.to_dict()  # round trip


@pytest.mark.parametrize(("change", "says"), [
    ({"src": "missing.png"}, "components[-2].src: missing.png: no such file"),
    ({"src": "face.json"}, "a picture is a .png file"),
    ({"src": "data:image/jpeg;base64,AAAA"}, "is a PNG data URI"),
    ({"points": [[0, 0], [1, 0]]}, "an image has exactly 3 points"),
    ({"fill": "#ff0000"}, "unknown field"),
])
def test_a_bad_picture_is_an_error_naming_the_field(tmp_path, change, says):
    import json

    (tmp_path / "face.json").write_text("{}")
    doc = picture_face("quad.png")
    doc["components"][-2].update(change)
    doc["components"] = doc["components"][:-1]
    (tmp_path / "bad.json").write_text(json.dumps(doc))
    with pytest.raises(InputError) as caught:
        load_face(tmp_path / "bad.json")
    message = str(caught.value).replace(f"components[{len(doc['components']) - 1}]", "components[-2]")
    assert says in message and "bad.json" in message


def test_the_corners_follow_the_points_and_the_motors():
    face = face_from_dict(picture_face(data_uri(QUAD), translate={"motor": "MB", "at0": [0, 0], "at1": [30, 0]},
                                       visible={"motor": "ERU", "range": [0.3, 1]}))
    rig = FaceRig(face)
    rest = face.neutral()
    geometry = rig.geometry(rest)
    np.testing.assert_allclose(_item(geometry, "square").vertices,
                               corners(np.array([[-200, 200], [-100, 200], [-200, 100]], float)) + [
                                   30 * rest[motor_index("MB")], 0])
    assert _item(geometry, "square").picture is not None and _item(geometry, "square").kind == "image"
    shut = rest.copy()
    shut[motor_index("ERU")] = 0.0
    assert all(i.name != "square" for i in rig.geometry(shut).items)  # hidden with the lid down
    open_ = rest.copy()
    open_[motor_index("MB")] = 1.0
    drop = rig.control_points(open_) - rig.control_points(rest)
    beard = _item(rig.geometry(open_), "beard").vertices - _item(geometry, "beard").vertices
    mb = drop[list(face.points).index("MB")]
    np.testing.assert_allclose(beard[:2], 0.0, atol=1e-9)  # the top corners are frozen
    np.testing.assert_allclose(beard[2:], [mb, mb], atol=1e-9)  # the bottom ones hang from MB


def test_the_cpu_oracle_and_the_svg_show_the_picture_s_pixels_where_its_corners_are():
    resvg = pytest.importorskip("resvg_py")
    import cv2

    face = face_from_dict(picture_face(data_uri(QUAD)))
    geometry = FaceRig(face).geometry(face.neutral())
    size = (256, 256)
    cpu = render_cpu(geometry, size)
    png = resvg.svg_to_bytes(svg_string=geometry_svg(geometry, size), width=size[0], height=size[1])
    svg = cv2.cvtColor(cv2.imdecode(np.frombuffer(bytes(png), np.uint8), cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
    from toon.raster import to_pixels

    (x0, y0), (x1, _), _, (_, y1) = to_pixels(_item(geometry, "square").vertices, geometry.viewbox, size)
    from dataclasses import replace

    under = render_cpu(replace(geometry, items=tuple(i for i in geometry.items if i.picture is None)), size)
    for (fx, fy), rgba in (((0.25, 0.25), QUAD[0, 0]), ((0.75, 0.25), QUAD[0, -1]), ((0.25, 0.75), QUAD[-1, 0]),
                           ((0.75, 0.75), QUAD[-1, -1])):
        x, y = int(x0 + fx * (x1 - x0)), int(y0 + fy * (y1 - y0))
        expect = rgba[:3] * (rgba[3] / 255) + under[y, x] * (1 - rgba[3] / 255)  # over what lies beneath
        for drawn in (cpu, svg):
            assert np.abs(drawn[y, x].astype(float) - expect).max() <= 3, (drawn[y, x], expect)
    diff = np.abs(cpu.astype(int) - svg.astype(int)).max(axis=2)
    assert np.median(diff) <= 2 and (diff > 48).mean() < 0.03


def test_the_svg_sends_a_picture_once_however_it_moves():
    """The room's viewers get only the SVG's lines that change: the picture's data is a
    definition of its own, and what moves is the line that places it."""
    face = face_from_dict(picture_face(data_uri(QUAD)))
    rig = FaceRig(face)
    a, b = face.neutral(), face.neutral()
    b[motor_index("MB")] = 1.0
    first, second = (geometry_svg(rig.geometry(v)).splitlines() for v in (a, b))
    changed = [line for line in second if line not in first]
    assert changed and all("base64" not in line for line in changed)
    assert sum(line.count("base64") for line in second) == 1  # one picture, defined once, used twice
