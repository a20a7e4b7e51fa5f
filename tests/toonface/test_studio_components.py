"""The face editor's CharToon component tools without a browser: components made from nothing,
points re-kinded, smooth and invisible ranges kept through point edits, animatable parameters,
groups and a component library."""

import json

import numpy as np
import pytest
from studios import temp_folder

from common import InputError
from toon import FaceRig, load_face, motor_index
from toonface.studio.faces import FaceEditor
from toonface.studio.messages import apply
from toonface.studio.session import StudioSession


def _drawn(face, name, **motors):
    """The outline of the component ``name`` as drawn with ``motors`` set from the rest pose, or None."""
    values = face.neutral()
    for code, value in motors.items():
        values[motor_index(code)] = value
    found = [i for i in FaceRig(face).geometry(values).items if i.name == name]
    return found[0] if found else None


def _control(face, name, **motors):
    values = face.neutral()
    for code, value in motors.items():
        values[motor_index(code)] = value
    rig = FaceRig(face)
    return rig.control_points(values)[list(face.points).index(name)]


def test_components_made_from_nothing_draw_and_save_loads_back_equal(tmp_path):
    editor = FaceEditor(load_face("classic"))
    for kind in ("polyline", "polygon", "ellipse", "skeleton"):
        editor.new_component(kind, 10.0, 200.0, 40.0)
    names = [c["name"] for c in editor.doc["components"][-4:]]
    assert names == ["polyline", "polygon", "ellipse", "skeleton"]
    square = _drawn(editor.face, "polygon")
    np.testing.assert_allclose(square.vertices, [[-10, 180], [30, 180], [30, 220], [-10, 220]])
    ellipse = _drawn(editor.face, "ellipse").vertices  # through its four points, 40 wide and 20 high
    np.testing.assert_allclose([ellipse[:, 0].min(), ellipse[:, 0].max()], [-10, 30], atol=1e-6)
    np.testing.assert_allclose([ellipse[:, 1].min(), ellipse[:, 1].max()], [190, 210], atol=1e-6)
    editor.new_component("polygon", 0.0, 0.0)
    assert editor.doc["components"][-1]["name"] == "polygon 2"
    with pytest.raises(ValueError, match="one of polyline"):
        editor.new_component("circle", 0.0, 0.0)
    assert load_face(editor.save(tmp_path / "new.json")) == editor.face


def test_a_point_made_a_slave_moves_as_its_master_and_a_frozen_one_stays():
    editor = FaceEditor(load_face("classic"))
    editor.new_component("polygon", 0.0, -150.0, 20.0)
    index = len(editor.doc["components"]) - 1
    editor.set_point_kind(index, "points", 0, "slave", "MB")
    assert editor.doc["components"][index]["points"][0] == {"slave": "MB", "at": [-10.0, -160.0]}
    shift = _control(editor.face, "MB", MB=1.0) - _control(editor.face, "MB", MB=0.0)
    assert abs(shift[1]) > 5  # the jaw moves the point by this much
    low, high = _drawn(editor.face, "polygon", MB=0.0).vertices, _drawn(editor.face, "polygon", MB=1.0).vertices
    np.testing.assert_allclose(high[0] - low[0], shift)
    np.testing.assert_allclose(high[1:], low[1:])  # frozen
    editor.set_point_kind(index, "points", 1, "master", "MB")  # a master sits on its control point
    np.testing.assert_allclose(_drawn(editor.face, "polygon", MB=1.0).vertices[1], _control(editor.face, "MB", MB=1.0))
    editor.set_point_kind(index, "points", 1, "fixed")  # where it was: at MB's rest
    assert editor.doc["components"][index]["points"][1] == {"fixed": list(editor.doc["points"]["MB"])}
    editor.set_point_kind(index, "points", 2, "slave")  # the nearest control point
    assert editor.doc["components"][index]["points"][2]["slave"] == "MB"


def test_points_added_and_deleted_keep_smooth_ranges_and_invisible_segments():
    editor = FaceEditor(load_face("classic"))
    editor.new_component("polyline", 0.0, 200.0, 40.0)
    index = len(editor.doc["components"]) - 1
    for after, x in ((0, -15.0), (1, -10.0), (2, -5.0)):  # five points, four segments
        editor.add_component_point(index, "points", after, x, 205.0)
    editor.restyle("component", index, smooth=[[1, 3]], hidden=[1, 3])
    # a point inside the smooth range and inside hidden segment 1 (points 1 to 2)
    editor.add_component_point(index, "points", 1, -12.0, 206.0)
    spec = editor.doc["components"][index]
    assert spec["smooth"] == [[1, 4]] and spec["hidden"] == [1, 2, 4]
    # deleting point 2 joins hidden segments 1 and 2 into one hidden segment; 4 (4 to 5) becomes 3
    editor.delete_component_point(index, "points", 2)
    spec = editor.doc["components"][index]
    assert spec["smooth"] == [[1, 3]] and spec["hidden"] == [1, 3]
    # deleting point 1 joins visible segment 0 and hidden segment 1: visible; the range loses its start
    editor.delete_component_point(index, "points", 1)
    spec = editor.doc["components"][index]
    assert spec["smooth"] == [[1, 2]] and spec["hidden"] == [2]
    editor.delete_component_point(index, "points", 1)  # the range collapses to one point: gone
    assert "smooth" not in editor.doc["components"][index]
    editor.restyle("component", index, smooth=True)
    editor.add_component_point(index, "points", 2, 25.0, 200.0)  # after the last point: still smooth all along
    assert editor.doc["components"][index]["smooth"] is True


def test_a_closed_outline_hides_a_segment_and_the_renderer_leaves_it_out():
    editor = FaceEditor(load_face("classic"))
    editor.new_component("polygon", 0.0, 200.0, 40.0)
    index = len(editor.doc["components"]) - 1
    editor.restyle("component", index, stroke="#000000", width=3.0, hidden=[3])
    assert _drawn(editor.face, "polygon").edge_visible.tolist() == [True, True, True, False]
    editor.add_component_point(index, "points", 3, -20.0, 200.0)  # splits the closing, hidden segment
    assert editor.doc["components"][index]["hidden"] == [3, 4]
    editor.delete_component_point(index, "points", 0)  # joins hidden 4 (4 to 0) and visible 0: shown
    assert editor.doc["components"][index]["hidden"] == [2]


def test_visibility_translation_and_scale_are_animated_by_their_motors():
    editor = FaceEditor(load_face("classic"))
    editor.new_component("polygon", 0.0, 200.0, 40.0)
    index = len(editor.doc["components"]) - 1
    editor.restyle("component", index, visible={"motor": "MB", "range": [0.5, 1.0]},
                   scale={"motor": "BRC", "at0": [1.0, 1.0], "at1": [2.0, 3.0], "origin": [0.0, 200.0]},
                   translate={"motor": "BRC", "at0": [0.0, 0.0], "at1": [10.0, 0.0]})
    assert _drawn(editor.face, "polygon", MB=0.2) is None
    rest = np.array([[-20, 180], [20, 180], [20, 220], [-20, 220]], dtype=float)
    half = _drawn(editor.face, "polygon", MB=0.8, BRC=0.5).vertices
    # scale (1.5, 2) about (0, 200), then moved 5 to the right: by hand
    np.testing.assert_allclose(half, [0, 200] + (rest - [0, 200]) * [1.5, 2.0] + [5.0, 0.0])
    with pytest.raises(InputError, match=r"visible\.motor"):
        editor.restyle("component", index, visible={"motor": "XX", "range": [0, 1]})
    editor.restyle("component", index, visible=None)
    assert _drawn(editor.face, "polygon", MB=0.0) is not None


def test_a_new_skeleton_drives_its_body_and_its_coupling_can_change():
    editor = FaceEditor(load_face("classic"))
    brow = editor.doc["points"]["BRC"]
    editor.new_component("skeleton", brow[0] - 20.0, brow[1] + 30.0, 40.0)
    index = len(editor.doc["components"]) - 1
    assert editor.doc["components"][index]["skeleton"][1]["slave"] == "BRC"  # the nearest
    still, raised = (_drawn(editor.face, "skeleton", BRC=v).vertices for v in (0.0, 1.0))
    # a slave moves by its master's shift from its rest
    joint = np.array([brow[0] - 40.0, brow[1] + 30.0])
    tip = np.array([brow[0], brow[1] + 30.0]) + _control(editor.face, "BRC", BRC=1.0) - brow
    assert np.abs(raised - still).max() > 1
    # edge coupling: each body point keeps where it projects on the turned edge (its end) and its distance, 5
    np.testing.assert_allclose(np.hypot(*(raised[[0, 3]] - joint).T), [5.0, 5.0])
    np.testing.assert_allclose(np.hypot(*(raised[[1, 2]] - tip).T), [5.0, 5.0])
    np.testing.assert_allclose(raised[1] + raised[2], 2 * tip)
    editor.restyle("component", index, coupling="point")
    point = _drawn(editor.face, "skeleton", BRC=1.0).vertices
    np.testing.assert_allclose(point[[1, 2]], [tip - [0, 5], tip + [0, 5]], atol=1e-9)  # rigidly with their point
    with pytest.raises(InputError, match="master point is not allowed"):
        editor.set_point_kind(index, "body", 0, "master", "BRC")
    assert editor.doc["components"][index]["body"][0] == {"fixed": [brow[0] - 40.0, brow[1] + 25.0]}


def test_components_grouped_moved_saved_to_a_library_and_inserted_into_another_face(tmp_path):
    editor = FaceEditor(load_face("classic"))
    editor.new_component("ellipse", 150.0, 150.0, 30.0)
    editor.new_component("polygon", 150.0, 120.0, 20.0)
    n = len(editor.doc["components"])
    editor.group([n - 2, n - 1], "horn")
    assert len(editor.doc["components"]) == n - 1
    horn = editor.doc["components"][n - 2]
    assert horn["kind"] == "composite" and [c["kind"] for c in horn["components"]] == ["ellipse", "polygon"]
    before = _drawn(editor.face, "polygon").vertices
    editor.move("component", n - 2, 10.0, 5.0)
    editor.restyle("component", n - 2, transform={"scale": [-1.0, 1.0], "translate": [10.0, 5.0]})
    flipped = _drawn(editor.face, "polygon").vertices
    np.testing.assert_allclose(flipped, before * [-1, 1] + [10, 5])
    library = tmp_path / "mine.json"
    editor.save_to_library(n - 2, library, "horn", "a horn")
    assert json.loads(library.read_text())["composites"]["horn"]["description"] == "a horn"
    editor.save_to_library(n - 2, library, "horn2")  # a second entry; the first is kept
    assert set(json.loads(library.read_text())["composites"]) == {"horn", "horn2"}
    editor.ungroup(n - 2)  # back to two components, placed as drawn
    assert [c["kind"] for c in editor.doc["components"][n - 2:]] == ["ellipse", "polygon"]
    np.testing.assert_allclose(_drawn(editor.face, "polygon").vertices, flipped)

    other = FaceEditor(load_face("wizard"))
    other.list_library(str(library))
    assert other.describe()["listed"]["names"] == ["horn", "horn2"]
    other.insert_from_library(str(library), "horn", dx=0.0, dy=-5.0)
    inserted = other.doc["components"][-1]
    assert inserted["library"] == str(library.resolve()) and inserted["use"] == "horn"
    np.testing.assert_allclose(_drawn(other.face, "polygon").vertices, flipped - [0, 5])
    saved = other.save(tmp_path / "horned.json")
    assert json.loads(saved.read_text())["components"][-1]["library"] == "mine.json"  # beside it: they move together
    assert load_face(saved).basic_components() == other.face.basic_components()
    with pytest.raises(InputError, match='no composite "nose"'):
        other.insert_from_library(str(library), "nose")
    with pytest.raises(InputError, match="saved as .json"):
        editor.save_to_library(0, tmp_path / "lib.toml", "x")


def test_a_builtin_library_entry_is_inserted_renamed_onto_the_other_eye():
    editor = FaceEditor(load_face("classic"))
    editor.list_library("features")
    assert "eye_smooth" in editor.describe()["listed"]["names"]
    controls = {"I": "ELI", "U": "ELU", "O": "ELO", "L": "ELL", "P": "PL", "E": "eye_left"}
    editor.insert_from_library("features", "eye_smooth", controls)
    inserted = editor.doc["components"][-1]
    assert inserted["library"] == "features" and inserted["controls"] == controls
    lids = [c for c in editor.face.basic_components() if c.name == "upper_lid"]
    assert [p.master for p in lids[-1].points] == ["ELI", "ELU", "ELO", "ELL"]  # (the hole's outline, half drawn)


def test_component_messages_from_the_page_edit_the_shown_face():
    session = StudioSession(face="classic", folder=temp_folder())
    n = len(session.faces.doc.get("components", []))
    apply(session, {"op": "faceedit", "action": "new_component", "kind": "ellipse", "x": 0, "y": 150}, 0.0)
    apply(session, {"op": "faceedit", "action": "set_point_kind", "component": n, "part": "points", "index": 1,
                    "kind": "slave", "master": "BRC"}, 0.0)
    apply(session, {"op": "faceedit", "action": "group", "indices": [n]}, 0.0)
    assert session.faces.doc["components"][n]["kind"] == "composite"
    assert session.face is session.faces.face
    described = session.faces.describe()
    assert len(described["outlines"][n]) == 1 and len(described["outlines"][n][0]) == 4
    assert "features" in described["libraries"]
    with pytest.raises(TypeError, match="indices"):
        apply(session, {"op": "faceedit", "action": "group", "indices": 3}, 0.0)


def test_a_face_file_beside_its_own_library_is_edited_and_saved_elsewhere(tmp_path, monkeypatch):
    editor = FaceEditor(load_face("classic"))
    editor.new_component("polygon", 0.0, 230.0, 20.0)
    folder = tmp_path / "kit"
    folder.mkdir()
    editor.save_to_library(len(editor.doc["components"]) - 1, folder / "parts.json", "tag")
    doc = load_face("classic").to_dict()
    doc["components"] = [{"kind": "composite", "name": "tag", "use": "tag", "library": "parts.json"}]
    (folder / "face.json").write_text(json.dumps(doc))
    monkeypatch.chdir(tmp_path)  # not the face's folder: its library is still found beside it
    opened = FaceEditor(load_face(folder / "face.json"))
    opened.rename("tagged")  # an edit validates the face again
    drawn = _drawn(opened.face, "polygon").vertices
    np.testing.assert_allclose(drawn, [[-10, 220], [10, 220], [10, 240], [-10, 240]])
    elsewhere = tmp_path / "out" / "deep"
    elsewhere.mkdir(parents=True)
    saved = opened.save(elsewhere / "tagged.json")
    assert json.loads(saved.read_text())["components"][0]["library"] == "../../kit/parts.json"
    np.testing.assert_allclose(_drawn(load_face(saved), "polygon").vertices, drawn)


def test_a_composite_is_scaled_and_flipped_about_its_centre_by_its_transform():
    editor = FaceEditor(load_face("classic"))
    editor.new_component("polygon", 100.0, 200.0, 20.0)
    editor.new_component("polygon", 140.0, 200.0, 20.0)
    n = len(editor.doc["components"])
    editor.group([n - 2, n - 1])
    before = np.concatenate([_drawn(editor.face, "polygon").vertices, _drawn(editor.face, "polygon 2").vertices])
    centre = before.mean(axis=0)  # (120, 200)
    editor.flip("component", n - 2, "x")
    editor.scale("component", n - 2, 2.0)
    after = np.concatenate([_drawn(editor.face, "polygon").vertices, _drawn(editor.face, "polygon 2").vertices])
    np.testing.assert_allclose(after, centre + (before - centre) * [-2.0, 2.0])  # by hand: mirrored, doubled
    assert editor.doc["components"][n - 2]["transform"]["scale"] == [-2.0, 2.0]
