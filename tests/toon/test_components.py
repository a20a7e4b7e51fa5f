"""CharToon components on small hand-made faces: points, skeletons, outlines, layers, parameters."""

import copy
import math

import numpy as np
import pytest

from common import InputError
from toon import FaceRig, face_from_dict, load_face, motor_index, standard_neutral
from toon.curves import ellipse_operator, outline_operator, stroke_triangles
from toon.skeleton import bind_edge_skeleton, bind_point_skeleton


@pytest.fixture(scope="module")
def base_doc():
    """The classic face's points and motors with no drawing of its own; the brows' ranges are
    set here (BRC 102..162: 24 units down and 36 up from its rest at 126), as the numbers below use them."""
    doc = load_face("classic").to_dict()
    doc["polygons"] = []
    doc["motors"].update({"BRC": [102.0, 162.0], "BLC": [102.0, 162.0]})
    return doc


def _face(base_doc, components, polygons=()):
    doc = copy.deepcopy(base_doc)
    doc["components"] = components
    doc["polygons"] = list(polygons)
    return face_from_dict(doc, source="hand.json")


def _pose(**motors):
    values = standard_neutral()
    for code, v in motors.items():
        values[motor_index(code)] = v
    return values


def _items(face, values):
    return {item.name: item for item in FaceRig(face).geometry(values).items}


# BRC rests at (-82, 126) and moves in y over [102, 162]; value 0.4 is rest.
def test_master_slave_frozen_and_fixed_points(base_doc):
    face = _face(base_doc, [{"kind": "polyline", "name": "p", "stroke": "#000000", "width": 1,
                             "points": ["BRC", {"slave": "BRC", "at": [-70, 130]}, [0, 0], {"fixed": [5, 5]}]}])
    rest = _items(face, _pose())["p"].vertices
    np.testing.assert_allclose(rest, [[-82, 126], [-70, 130], [0, 0], [5, 5]])
    up = _items(face, _pose(BRC=1.0))["p"].vertices  # y = 162: 36 units up
    np.testing.assert_allclose(up, [[-82, 162], [-70, 166], [0, 0], [5, 5]])


def test_point_skeleton_keeps_vectors_and_joints_hold(base_doc):
    face = _face(base_doc, [{"kind": "skeleton", "name": "s", "coupling": "point", "fill": "#000000",
                             "skeleton": ["BRC", {"fixed": [-40, 126]}],
                             "body": [{"fixed": [-90, 130]}, {"fixed": [-45, 130]}, [-80, 120]]}])
    moved = _items(face, _pose(BRC=0.0))["s"].vertices  # BRC to y = 102: down 24
    # Nearest to BRC: moves with it; nearest to the fixed joint: stays; frozen: stays.
    np.testing.assert_allclose(moved, [[-90, 106], [-45, 130], [-80, 120]])


def test_edge_skeleton_keeps_ratio_and_distance_by_hand():
    skeleton = np.array([[0.0, 0.0], [10.0, 0.0]])
    body = np.array([[4.0, 3.0], [12.0, -1.0]])
    coupling = bind_edge_skeleton(body, skeleton, np.array([True, True]), closed=False)
    np.testing.assert_allclose(coupling.t, [0.4, 1.2])
    np.testing.assert_allclose(coupling.d, [3.0, -1.0])
    np.testing.assert_allclose(coupling.apply(body, skeleton, skeleton), body)  # rest is rest
    # Turn and stretch the edge to (0, 0)-(0, 20): the unit normal is (-1, 0).
    moved = coupling.apply(body, skeleton, np.array([[0.0, 0.0], [0.0, 20.0]]))
    np.testing.assert_allclose(moved, [[-3.0, 8.0], [1.0, 24.0]])


def test_point_skeleton_binding_by_hand():
    coupling = bind_point_skeleton(np.array([[1.0, 0.0], [9.0, 0.0]]), np.array([[0.0, 0.0], [10.0, 0.0]]),
                                   np.array([True, True]), np.array([True, False]))
    assert coupling.nearest.tolist() == [0, 1] and coupling.moves.tolist() == [True, False]


def test_a_smoothed_outline_passes_through_its_points():
    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
    whole, origin = outline_operator(square, closed=True, smooth=((0, 3),))
    drawn = whole @ square
    np.testing.assert_allclose(drawn[::8], square, atol=1e-12)
    assert len(drawn) == 32 and origin.tolist() == np.repeat(np.arange(4), 8).tolist()
    assert np.linalg.norm(drawn - [2, 2], axis=1).max() > 2.0  # bulges beyond the straight sides' midpoints
    part, origin = outline_operator(square, closed=False, smooth=((1, 3),))
    drawn = part @ square
    np.testing.assert_allclose(drawn[[0, 1, 9, 17]], square, atol=1e-12)  # the straight first segment kept
    assert origin.tolist() == [0] + [1] * 8 + [2] * 8


def test_ellipse_through_four_contour_points():
    pts = np.array([[-3.0, 1.0], [0.0, 3.0], [3.0, 1.0], [0.0, -1.0]])  # rx 3, ry 2, centre (0, 1)
    outline = ellipse_operator() @ pts
    np.testing.assert_allclose(((outline[:, 0] / 3) ** 2 + ((outline[:, 1] - 1) / 2) ** 2), 1.0)
    for p in pts:
        assert np.linalg.norm(outline - p, axis=1).min() < 1e-9


def _area(corners):
    t = corners.reshape(-1, 3, 2)
    u, v = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    return np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / 2


def test_stroke_of_a_segment_and_a_right_angle_miter():
    assert _area(stroke_triangles(np.array([[0.0, 0.0], [10.0, 0.0]]), 2.0, False)).sum() == pytest.approx(20.0)
    corner = stroke_triangles(np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]]), 2.0, False)
    # Two 10x2 quads plus the miter square's outer half (1x1 split in two triangles).
    assert _area(corner).sum() == pytest.approx(20 + 20 + 1)
    assert np.isclose(corner, [11.0, -1.0]).all(axis=1).any()  # the miter tip
    hidden = stroke_triangles(np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]]), 2.0, False, np.array([True, False]))
    assert _area(hidden).sum() == pytest.approx(20.0)


def test_a_sharp_turn_bevels_beyond_the_miter_limit():
    spike = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 1.0]])  # turns back by about 174 degrees
    corners = stroke_triangles(spike, 2.0, False)
    assert corners[:, 0].max() < 10.0 + 1.0 + 1e-9  # no long miter spike


def test_composites_transform_rename_and_reuse_the_library(base_doc):
    face = _face(base_doc, [
        {"kind": "composite", "name": "brow", "use": "brow_edge", "library": "features",
         "controls": {"M": "BLM", "C": "BLC", "L": "BLL"}, "transform": {"scale": [-1, 1], "translate": [0, 0]}},
        {"kind": "composite", "components": [
            {"kind": "polygon", "name": "tri", "points": [[0, 0], [10, 0], [0, 10]], "fill": "#ff0000"}],
         "transform": {"scale": [2, 3], "translate": [100, -50]}},
    ])
    items = _items(face, _pose())
    np.testing.assert_allclose(items["tri"].vertices, [[100, -50], [120, -50], [100, -20]])
    brow = items["brow"].vertices
    assert brow[:, 0].min() > 30 and brow[:, 0].max() < 140  # flipped onto the character's left brow
    raised = _items(face, _pose(BLC=1.0))["brow"].vertices
    assert raised[:, 1].max() > brow[:, 1].max() + 20  # driven by BLC after renaming C


def test_layers_order_and_background_must_not_move(base_doc):
    hole = {"kind": "hole", "attach": "mouth", "color": "#000000",
            "vertices": [[-60, -95], [0, -80], [60, -95], [0, -110]]}
    face = _face(base_doc, [
        {"kind": "polygon", "name": "front", "points": [[0, 0], [1, 0], [0, 1]], "fill": "#00ff00", "layer": 3},
        {"kind": "polygon", "name": "back", "points": [[0, 0], [1, 0], [0, 1]], "fill": "#00ff00", "layer": -5},
        {"kind": "polygon", "name": "mid", "points": [[0, 0], [1, 0], [0, 1]], "fill": "#00ff00", "layer": 1},
    ], polygons=[hole])
    names = [i.name or i.kind for i in FaceRig(face).geometry(standard_neutral()).items]
    assert names == ["back", "hole", "mid", "front"]
    with pytest.raises(InputError, match=r"components\[0\].layer: background layers"):
        _face(base_doc, [{"kind": "polyline", "points": ["BRC", [0, 0]], "stroke": "#000000", "width": 1,
                          "layer": -1}])


def test_visibility_translation_and_scale_follow_their_motors(base_doc):
    face = _face(base_doc, [{"kind": "polygon", "name": "p", "points": [[0, 0], [10, 0], [0, 10]], "fill": "#000000",
                             "visible": {"motor": "MB", "range": [0.0, 0.5]},
                             "translate": {"motor": "HH", "at0": [0, 0], "at1": [20, 0]},
                             "scale": {"motor": "MLV", "at0": [1, 1], "at1": [3, 2], "origin": [0, 0]}}])
    at = _items(face, _pose(MB=0.2, HH=0.5, MLV=1.0))["p"].vertices  # translated by 10, scaled (3, 2)
    np.testing.assert_allclose(at, [[10, 0], [40, 0], [10, 20]], atol=1e-9)
    assert "p" not in _items(face, _pose(MB=0.9))


def test_hidden_segments_and_clip_reach_the_draw_item(base_doc):
    face = _face(base_doc, [{"kind": "polygon", "name": "p", "points": [[0, 0], [10, 0], [10, 10], [0, 10]],
                             "stroke": "#000000", "width": 1, "hidden": [1, 3], "clip": "eye_left"}])
    item = _items(face, _pose())["p"]
    assert item.edge_visible.tolist() == [True, False, True, False] and item.mask_test == 2


def test_gaze_in_degrees_moves_and_narrows_the_pupil():
    face = load_face("classic")  # PRH [-47, 47] degrees, eye radius 30
    rig = FaceRig(face)
    rest = {i.name: i.vertices for i in rig.geometry(standard_neutral()).items}["pupil_r"]
    look = {i.name: i.vertices for i in rig.geometry(_pose(PRH=1.0, HH=0.5)).items}["pupil_r"]
    shift = look.mean(axis=0)[0] - rest.mean(axis=0)[0]
    assert shift == pytest.approx(30 * math.sin(math.radians(47)), abs=1e-9)
    width = lambda v: v[:, 0].max() - v[:, 0].min()  # noqa: E731
    assert width(look) == pytest.approx(width(rest) * math.cos(math.radians(47)))


@pytest.mark.parametrize("component, expected", [
    ({"kind": "blob"}, r"components\[0\].kind: expected one of .*, got 'blob'"),
    ({"kind": "polyline", "points": ["Mx", [0, 0]], "stroke": "#000000", "width": 1},
     r'components\[0\].points\[0\]: unknown control point "Mx"'),
    ({"kind": "ellipse", "points": [[0, 0], [1, 1], [2, 0]], "fill": "#000000"},
     r"components\[0\].points: expected a list of at least 4"),
    ({"kind": "skeleton", "coupling": "edge", "skeleton": [[0, 0], [1, 0]], "body": [[0, 1], [1, 1]],
      "fill": "#000000"}, r"components\[0\].skeleton\[0\]: a frozen point is not allowed here"),
    ({"kind": "skeleton", "coupling": "edge", "skeleton": ["BRC", "BRM"], "body": ["BRL", [1, 1]],
      "fill": "#000000"}, r"components\[0\].body\[0\]: a master point is not allowed here"),
    ({"kind": "skeleton", "coupling": "bone", "skeleton": ["BRC", "BRM"], "body": [[0, 1], [1, 1]],
      "fill": "#000000"}, r"components\[0\].coupling: expected one of .*, got 'bone'"),
    ({"kind": "polyline", "points": [[0, 0], [1, 0]], "stroke": "#000000"}, r"components\[0\]: draws nothing"),
    ({"kind": "polyline", "points": [[0, 0], [1, 0]], "fill": "#000000"}, r"components\[0\].fill: an open outline"),
    ({"kind": "polygon", "points": [[0, 0], [1, 0], [0, 1]], "fill": "#000000", "hidden": [3]},
     r"components\[0\].hidden\[0\]: expected an integer from 0 to 2"),
    ({"kind": "polygon", "points": [[0, 0], [1, 0], [0, 1], [1, 1]], "fill": "#000000", "smooth": [[0, 2], [1, 3]]},
     r"components\[0\].smooth: ranges \[0, 2\] and \[1, ...\] overlap"),
    ({"kind": "polygon", "points": [[0, 0], [1, 0], [0, 1]], "fill": "#000000", "clip": "nose"},
     r"components\[0\].clip: expected one of .*, got 'nose'"),
    ({"kind": "polygon", "points": [[0, 0], [1, 0], [0, 1]], "fill": "#000000", "layer": 0},
     r"components\[0\].layer: layer 0 is the ToonFace face"),
    ({"kind": "composite", "use": "eyebrow_9", "library": "features"},
     r'components\[0\].use: library features.json has no composite "eyebrow_9"'),
    ({"kind": "composite", "use": "brow_edge", "library": "nowhere"},
     r'components\[0\].library: no built-in component library "nowhere"'),
    ({"kind": "composite", "use": "brow_edge", "library": "features", "controls": {"M": "BRM"}},
     r'features.json: composites.brow_edge.components\[0\].skeleton\[1\]: unknown control point "C"'),
])
def test_bad_components_name_their_field(base_doc, component, expected):
    with pytest.raises(InputError, match=expected):
        _face(base_doc, [component])
