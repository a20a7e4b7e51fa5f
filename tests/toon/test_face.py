"""Face files and the rig: validation that names the field, round trips, A1.1-A1.6, every motor moving."""

import copy
import json

import numpy as np
import pytest

from common import InputError
from toon import (
    MOTOR_CODES,
    FaceRig,
    builtin_faces,
    face_from_dict,
    load_face,
    motor_index,
    save_face,
    standard_neutral,
)
from toon.rig import bind_to_lines, follow_lines, head_turn, interpolate_states


@pytest.fixture(scope="module")
def classic_doc():
    return load_face("classic").to_dict()


def test_builtin_face_loads_and_rests_at_the_standard_neutral():
    assert "classic" in builtin_faces()
    face = load_face("classic")
    np.testing.assert_allclose(face.neutral(), standard_neutral(), atol=1e-9)


def test_round_trip_load_save_load(tmp_path):
    face = load_face("classic")
    again = load_face(save_face(face, tmp_path / "copy.json"))
    assert again == face
    assert again.to_dict() == face.to_dict()


def _mutate(doc, path, value):
    doc = copy.deepcopy(doc)
    node = doc
    for key in path[:-1]:
        node = node[key]
    if value is KeyError:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return doc


@pytest.mark.parametrize("path, value, expected", [
    (("format",), "toonface.face/9", "format: unsupported format"),
    (("points", "MT"), KeyError, "points.MT: missing control point"),
    (("points", "MT"), [0, "x"], "points.MT: expected a list of 2 numbers"),
    (("points", "ZZ"), [0, 0], "points: unknown control point"),
    (("motors", "BRL"), [100, 100], "motors.BRL: min and max are both"),
    (("motors", "BRL"), [150, 90], "motors.BRL: .* runs the wrong way"),
    (("motors", "MB"), [-185, -95], "motors.MB: .* runs the wrong way"),
    (("motors", "HH"), [5, 30], "motors.HH: an angle range"),
    (("motors", "BRM"), [0, 10], "motors.BRM: control point BRM rests at y=112.0, outside"),
    (("polygons", 0, "kind"), "blob", r"polygons\[0\].kind: expected one of .*, got 'blob'"),
    (("polygons", 0, "attach"), "nose", r"polygons\[0\].attach: expected one of .*, got 'nose'"),
    (("polygons", 1, "attach"), "Mx", r'polygons\[1\].attach: unknown control point "Mx"'),
    (("polygons", 16, "attach"), "Mx", r'polygons\[16\].attach: unknown control point "Mx"'),
    (("polygons", 16, "attach"), "ML", r'polygons\[16\].attach: control point "ML" moves in 2-D'),
    (("polygons", 0, "color"), "red", r"polygons\[0\].color: expected a colour"),
    (("polygons", 0, "vertices"), [[0, 0], [1, 1]], r"polygons\[0\].vertices: expected a list of at least 3"),
    (("polygons", 0, "vertices"), [[0, 0], [1, 1], [2, 2]], r"polygons\[0\].vertices: degenerate polygon"),
    (("polygons", 0, "wobble"), 1, r"polygons\[0\].wobble: unknown field"),
    (("viewbox",), [0, 0, -1, 1], "viewbox: must be"),
])
def test_validation_names_the_bad_field(classic_doc, path, value, expected):
    with pytest.raises(InputError, match=expected) as info:
        face_from_dict(_mutate(classic_doc, path, value), source="bad.json")
    assert str(info.value).startswith("bad.json: ")


def test_at_most_one_face_polygon(classic_doc):
    doc = copy.deepcopy(classic_doc)
    doc["polygons"].append(next(p for p in doc["polygons"] if p["kind"] == "face"))
    with pytest.raises(InputError, match='at most one polygon of kind "face", found 2'):
        face_from_dict(doc)


def test_bad_json_and_unknown_name(tmp_path):
    (tmp_path / "f.json").write_text("{nope")
    with pytest.raises(InputError, match="f.json: not valid JSON"):
        load_face(tmp_path / "f.json")
    with pytest.raises(InputError, match='no built-in face "nobody"'):
        load_face("nobody")


def test_feature_lines_follow_a1_formulas_by_hand():
    # Line from (0, 0) to (10, 0); a vertex at (4, 3): vrl = 0.4, d = 3.
    pts = np.array([[0.0, 0.0], [10.0, 0.0]])
    binding = bind_to_lines(np.array([[4.0, 3.0]]), pts, closed=False)
    assert binding.vrl[0] == pytest.approx(0.4) and binding.d[0] == pytest.approx(3.0)
    # Move the end point to (20, 10): SL = 0.5, IYL = 0, X = 0 + 0.4 * 20 = 8, Y = 8 * 0.5 + 0 + 3 = 7.
    moved = follow_lines(binding, np.array([[0.0, 0.0], [20.0, 10.0]]))
    np.testing.assert_allclose(moved, [[8.0, 7.0]])


def test_vertices_bind_to_the_nearest_line_of_a_closed_feature():
    eye = np.array([[0.0, 0.0], [5.0, 4.0], [10.0, 0.0], [5.0, -4.0]])  # corner, upper, corner, lower
    verts = np.array([[5.0, 5.0], [5.0, -5.0], [2.0, 2.0]])
    binding = bind_to_lines(verts, eye, closed=True)
    assert [(s, e) for s, e in zip(binding.start, binding.end, strict=True)] == [(0, 1), (2, 3), (0, 1)]
    np.testing.assert_allclose(follow_lines(binding, eye), verts)  # unchanged points, unchanged vertices


def test_point_attached_interpolation_a15_a16():
    v_min, v_max = np.array([[0.0, 0.0], [2.0, 4.0]]), np.array([[10.0, -10.0], [2.0, 8.0]])
    np.testing.assert_allclose(interpolate_states(v_min, v_max, 0.25), [[2.5, -2.5], [2.0, 5.0]])


def test_head_turn_shifts_features_by_depth_sin():
    out = head_turn(np.array([[0.0, 0.0], [10.0, 0.0]]), 60.0, np.zeros(2), 30.0, 0.0)
    np.testing.assert_allclose(out, [[30.0, 0.0], [10 * np.cos(np.pi / 6) + 30.0, 0.0]])
    up = head_turn(np.array([[0.0, 0.0]]), 60.0, np.zeros(2), 0.0, 30.0)
    np.testing.assert_allclose(up, [[0.0, 30.0]])  # chin up: features rise


@pytest.mark.parametrize("code", MOTOR_CODES)
def test_every_motor_visibly_moves_something(code):
    rig = FaceRig(load_face("classic"))
    rest = standard_neutral()
    moved = rest.copy()
    moved[motor_index(code)] = 1.0 if rest[motor_index(code)] < 0.5 else 0.0
    a, b = rig.geometry(rest), rig.geometry(moved)
    shift = max(np.abs(p.vertices - q.vertices).max() for p, q in zip(a.items, b.items, strict=True))
    assert shift > 8.0  # face units; the face is 350 wide


def test_drawing_order_follows_a122():
    kinds = [p.kind for p in FaceRig(load_face("classic")).geometry(standard_neutral()).items]
    order = ["hole", "pupil", "face", "free", "point", "feature"]
    assert kinds == sorted(kinds, key=order.index)
    assert set(kinds) == set(order)


def test_a_feature_whose_lines_are_all_vertical_is_a_clear_error(classic_doc, tmp_path):
    doc = copy.deepcopy(classic_doc)
    for name in ("BRM", "BRC", "BRL"):  # stack the right brow's points on one vertical line
        doc["points"][name][0] = -80.0
    path = tmp_path / "stacked.json"
    path.write_text(json.dumps(doc))
    brow = next(i for i, p in enumerate(doc["polygons"]) if p.get("attach") == "brow_right")
    with pytest.raises(InputError, match=rf"stacked.json: polygons\[{brow}\].attach: feature brow_right: every line"):
        FaceRig(load_face(path))
