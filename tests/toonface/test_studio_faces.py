"""The studio's face editor without a browser: validated edits at the rest pose, undo, save."""

import numpy as np
import pytest
from studios import temp_folder

from common import InputError
from toon import FaceRig, load_face, motor_index
from toonface.studio.faces import FaceEditor
from toonface.studio.messages import apply
from toonface.studio.session import StudioSession


def _index(face, name):
    return next(i for i, p in enumerate(face.polygons) if p.name == name)


def test_edits_change_the_face_and_save_loads_back_equal(tmp_path):
    editor = FaceEditor(load_face("classic"))
    nose = _index(editor.face, "nose")
    before = np.array(editor.face.polygons[nose].vertices)
    editor.move_vertex(nose, 0, before[0, 0] - 5.0, before[0, 1] + 3.0)
    editor.move("polygon", nose, 2.0, 0.0)
    editor.scale("polygon", nose, 1.5)
    after = np.array(editor.face.polygons[nose].vertices)
    moved = before.copy()
    moved[0] += [-5.0, 3.0]
    moved += [2.0, 0.0]
    centre = moved.mean(axis=0)
    np.testing.assert_allclose(after, centre + (moved - centre) * 1.5)  # the three edits, by hand
    editor.flip("polygon", nose, "x")
    np.testing.assert_allclose(np.array(editor.face.polygons[nose].vertices)[:, 0],
                               2 * centre[0] - after[:, 0])
    count = len(editor.face.polygons)
    editor.duplicate("polygon", nose, 30.0, 0.0)
    assert len(editor.face.polygons) == count + 1 and editor.face.polygons[nose + 1].name == "nose 2"
    editor.restyle("polygon", nose + 1, color="#2050d0", stroke="#000000", width=2.0)
    assert editor.face.polygons[nose + 1].color[:3] == pytest.approx((0x20 / 255, 0x50 / 255, 0xd0 / 255))
    editor.set_range("MB", "max", editor.face.ranges["MB"][1] - 10.0)
    editor.rename("my face")
    path = editor.save(tmp_path / "mine.json")
    assert load_face(path) == editor.face  # save -> load: an equal face


def test_an_invalid_edit_is_refused_with_the_validators_message_and_nothing_is_lost():
    editor = FaceEditor(load_face("classic"))
    face = editor.face
    lo, hi = face.ranges["MLV"]
    with pytest.raises(InputError, match=r"motors\.MLV.*runs the wrong way"):
        editor.set_range("MLV", "max", lo - 1.0)
    with pytest.raises(InputError, match=r"motors\.MB.*outside its range"):
        editor.move_point("MB", face.points["MB"][0], max(face.ranges["MB"]) + 50)
    with pytest.raises(InputError, match="at most one polygon"):
        editor.restyle("polygon", _index(face, "nose"), kind="face")
    with pytest.raises(IndexError):
        editor.delete_vertex(999, 0)
    assert editor.face == face and editor.describe()["undo"] == 0


def test_undo_and_redo_walk_the_edits():
    editor = FaceEditor(load_face("wizard"))
    faces = [editor.face]
    for _ in range(5):
        editor.move("polygon", 0, 1.0, -1.0)
        faces.append(editor.face)
    for face in reversed(faces[:-1]):
        assert editor.undo() and editor.face == face
    assert not editor.undo()
    assert editor.redo() and editor.face == faces[1]


def test_the_studio_shows_the_edited_face_moving_and_extremes_follow_the_range():
    session = StudioSession("classic", folder=temp_folder())
    session.set_motor("MB", 1.0)  # the mouth wide open while the face is edited
    lo, hi = session.face.ranges["MB"]
    said = apply(session, {"op": "faceedit", "action": "set_range", "code": "MB", "end": "max", "value": hi + 12.0},
                 0.0)
    assert said == ("face", None)
    assert session.face.ranges["MB"] == (lo, hi + 12.0) and session.values[motor_index("MB")] == 1.0
    point = session.rig.control_points(session.values)[list(session.face.points).index("MB")]
    assert point[1] == pytest.approx(hi + 12.0)  # at value 1 the mouth's bottom is at the new end
    np.testing.assert_allclose(FaceRig(session.face).control_points(session.values), session.rig.control_points(
        session.values))
    with pytest.raises(InputError):
        apply(session, {"op": "faceedit", "action": "set_range", "code": "MB", "end": "max", "value": lo}, 0.0)
    assert session.face.ranges["MB"] == (lo, hi + 12.0)


def test_components_move_scale_flip_and_restyle_as_units(tmp_path):
    editor = FaceEditor(load_face("round"))  # a face of components only
    doc = editor.doc
    index = next(i for i, c in enumerate(doc["components"]) if c["kind"] == "ellipse" and c.get("name") == "hair_back")
    before = np.array(doc["components"][index]["points"], dtype=float)
    editor.move("component", index, 5.0, -2.0)
    editor.scale("component", index, 2.0)
    moved = before + [5.0, -2.0]
    centre = moved.mean(axis=0)
    np.testing.assert_allclose(np.array(editor.doc["components"][index]["points"]), centre + (moved - centre) * 2.0)
    editor.flip("component", index, "y")
    editor.move_component_point(index, 0, -210.0, 40.0)
    assert editor.doc["components"][index]["points"][0] == [-210.0, 40.0]
    editor.restyle("component", index, layer=-5, fill="#224488")
    assert editor.face.components[index].layer == -5
    with pytest.raises(InputError, match="layer"):
        editor.restyle("component", index, layer=0)
    count = len(editor.doc["components"])
    editor.duplicate("component", index, 10.0, 0.0)
    assert len(editor.doc["components"]) == count + 1
    assert load_face(editor.save(tmp_path / "round2.json")) == editor.face


def test_a_slave_point_keeps_its_master_and_a_master_point_is_moved_by_its_control_point():
    editor = FaceEditor(load_face("cat"))
    tongue = next(i for i, c in enumerate(editor.doc["components"]) if c.get("name") == "tongue")
    editor.move_component_point(tongue, 1, 0.0, -133.0)
    assert editor.doc["components"][tongue]["points"][1] == {"slave": "MB", "at": [0.0, -133.0]}
    lines = FaceEditor(load_face("lines"))
    lid = next(i for i, c in enumerate(lines.doc["components"]) if c.get("name") == "lid_right")
    assert lines.doc["components"][lid]["points"][0] == "ERI"  # a master: where the control point is
    with pytest.raises(ValueError, match="master point"):
        lines.move_component_point(lid, 0, 0.0, 0.0)
    brow = next(i for i, c in enumerate(lines.doc["components"]) if c.get("name") == "brow_right")
    lines.move("component", brow, 3.0, 0.0)  # a skeleton: its placed points move, its masters stay
    assert lines.doc["components"][brow]["skeleton"][0] == "BRM"


def test_a_polygon_changes_kind_and_attachment():
    editor = FaceEditor(load_face("classic"))
    nose = _index(editor.face, "nose")
    editor.restyle("polygon", nose, kind="point", attach="MB")  # now it follows the mouth's motor between two states
    spec = editor.face.polygons[nose]
    assert spec.kind == "point" and spec.attach == "MB" and spec.vertices_max == spec.vertices
    editor.move_vertex(nose, 0, 0.0, -30.0, state="vertices_max")
    assert editor.face.polygons[nose].vertices_max[0] == (0.0, -30.0)
    with pytest.raises(InputError, match=r"polygons\[15\]\.attach"):
        editor.restyle("polygon", nose, attach="XX")
    editor.restyle("polygon", nose, kind="free")  # back: no attachment, one state
    assert editor.face.polygons[nose].attach == "" and editor.face.polygons[nose].vertices_max == ()


def test_a_new_polygon_and_an_expression_looping_while_the_face_is_edited(tmp_path):
    editor = FaceEditor(load_face("classic"))
    count = len(editor.face.polygons)
    editor.add_polygon(10.0, -20.0, size=8.0, color="#ff0000")
    new = editor.face.polygons[count]
    assert new.kind == "free" and new.name == "shape 1"
    assert np.array(new.vertices).tolist() == [[6.0, -24.0], [14.0, -24.0], [14.0, -16.0], [6.0, -16.0]]
    assert load_face(editor.save(tmp_path / "f.json")) == editor.face

    session = StudioSession("classic", folder=temp_folder())
    apply(session, {"op": "play", "name": "happiness", "loop": True}, 0.0)
    pose = session.expressions["happiness"].pose(session.neutral)[motor_index("MLV")]
    rest = session.neutral[motor_index("MLV")]
    seen = []
    for k in range(200):  # 200 loops of 1/30 s: several times there and back
        session.tick(k / 30)
        seen.append(session.values[motor_index("MLV")])
    at_pose = np.isclose(seen, pose)
    at_rest = np.isclose(seen, rest)
    assert np.count_nonzero(np.diff(at_pose.astype(int)) == 1) >= 2 and at_rest[20:].any() and session.busy()
    apply(session, {"op": "motor", "code": "MB", "value": 0.3}, 200 / 30)  # a slider stops the loop
    for k in range(200, 260):
        session.tick(k / 30)
    assert not session.busy()


def test_a_component_copied_from_one_face_is_pasted_into_another(tmp_path):
    session = StudioSession("cat", folder=temp_folder())
    tongue = next(i for i, c in enumerate(session.faces.doc["components"]) if c.get("name") == "tongue")
    said = apply(session, {"op": "faceedit", "action": "copy", "kind": "component", "index": tongue}, 0.0)[1]
    assert said == f"copied component {tongue}"
    apply(session, {"op": "faceedit", "action": "open", "name": "classic"}, 0.0)
    before = len(session.face.components)
    apply(session, {"op": "faceedit", "action": "paste"}, 0.0)
    assert len(session.face.components) == before + 1 and session.face.components[-1].name == "tongue"
    apply(session, {"op": "faceedit", "action": "paste"}, 0.0)  # twice: the name made unique
    assert session.face.components[-1].name == "tongue 2"
    saved = load_face(session.faces.save(tmp_path / "classic_tongue.json"))
    assert saved == session.faces.face and saved.name == "classic_tongue"  # a built-in's copy named as its file
    with pytest.raises(ValueError, match="nothing to paste"):
        FaceEditor(load_face("round")).paste_item()


def test_a_built_in_face_saved_under_a_name_of_its_own_takes_that_name(tmp_path):
    """Issue 69: a cat saved as mine.json still said "cat" (the web page's title said so)."""
    editor = FaceEditor(load_face("cat"))
    assert load_face(editor.save(tmp_path / "mine.json")).name == "mine"
    editor.rename("Whiskers")  # a name given is kept
    assert load_face(editor.save(tmp_path / "other.json")).name == "Whiskers"
