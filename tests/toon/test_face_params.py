"""Parameters a face declares beyond the 21 motors (issue 42): control points they move, components
and point polygons they drive, the standard extras on the built-in faces, and faces drawn as before."""

import hashlib
import logging

import numpy as np
import pytest

from common import InputError
from toon import FaceRig, MotorTrack, builtin_faces, load_face
from toon.face import face_from_dict
from toon.motors import STANDARD_EXTRAS


def _doc(**params) -> dict:
    doc = load_face("classic").to_dict()
    doc["params"].update(params)  # beside classic's own (UL, JS, CP)
    return doc


def _item(geometry, name):
    return next(item for item in geometry.items if item.name == name)


def _fingerprint(face) -> str:
    """The items six seeded 21-motor poses draw, as a short hash (vertices to 1e-4, colours,
    masks), each pose's items taken in a fixed order of their own (not the drawing order)."""
    rig = FaceRig(face)
    digest = hashlib.sha256()
    for values in np.random.default_rng(42).uniform(0, 1, (6, 21)):
        items = [np.round(item.vertices, 4).tobytes() + repr((
            item.fill, item.stroke, item.width, item.closed, item.mask_write, item.mask_test,
            None if item.edge_visible is None else item.edge_visible.tolist())).encode()
            for item in rig.geometry(values).items]
        for item in sorted(items):
            digest.update(item)
    return digest.hexdigest()[:16]


#: The faces as drawn before they declared their parameters (UL, JS, CP, PERK, and the swinging
#: hair, beard, fringe, ears and whiskers; commit b51f09e): a 21-motor track must draw the same
#: items at the same places. The drawing order of items that do not overlap changed where a free
#: polygon became a point polygon (the classic's hair, the wizard's beard, the cat's inner ears,
#: drawn after the other free polygons); the pixels were checked equal on both renderers then.
#: The cat's since: its jaw's range (MB -117..-187, was -115..-205: its open mouth reached its
#: chin, issue 69), the rest of it as it was; the round face's: its lids drawn along its eyes'
#: own outlines (issue 70), the rest as it was.
BEFORE = {"cat": "754dec4beccb1f66", "classic": "f5f52a06cd9e73a8", "lines": "8db4a50697c4a3e0",
          "round": "047d086d5d9c73fb", "wizard": "dcb2c44ccc59ed39"}


@pytest.mark.parametrize("name", sorted(BEFORE))
def test_a_21_motor_track_draws_every_built_in_face_as_before_its_parameters(name):
    assert _fingerprint(load_face(name)) == BEFORE[name]


def test_a_parameter_moves_its_control_points_and_what_follows_them_by_hand():
    doc = _doc(SNARL={"description": "upper lip up", "points": {"MT": {"at0": [0, 0], "at1": [4, 20]}}})
    face = face_from_dict(doc)
    assert face.extra_codes == ("HT", "UL", "JS", "CP", "HAIR", "SNARL") and face.extra_neutral()["SNARL"] == 0.0
    rig = FaceRig(face)
    values = face.neutral()
    rest = rig.control_points(values)
    moved = rig.control_points(values, {"SNARL": 0.5})
    row = list(face.points).index("MT")
    np.testing.assert_allclose(moved[row] - rest[row], [2.0, 10.0])
    np.testing.assert_array_equal(np.delete(moved, row, 0), np.delete(rest, row, 0))
    lip = _item(rig.geometry(values, {"SNARL": 1.0}), "upper_lip").vertices
    still = _item(rig.geometry(values), "upper_lip").vertices
    assert (lip[:, 1] - still[:, 1]).max() > 15  # the upper lip, bound to MT's lines, rises with it
    assert face_from_dict(face.to_dict()) == face  # written and read back the same


def test_a_parameter_drives_components_and_point_polygons_as_a_motor_does():
    doc = _doc(HAT={"neutral": 0})
    doc["components"] = [{"kind": "polygon", "name": "flag", "points": [[0, 0], [10, 0], [0, 10]], "fill": "#ff0000",
                          "translate": {"motor": "HAT", "at0": [0, 0], "at1": [0, 30]},
                          "visible": {"motor": "HAT", "range": [0.1, 1]}}]
    doc["polygons"].append({"kind": "point", "name": "brim", "attach": "HAT", "color": "#000000",
                            "vertices": [[0, 200], [20, 200], [10, 210]],
                            "vertices_max": [[0, 240], [20, 240], [10, 250]]})
    face = face_from_dict(doc)
    rig = FaceRig(face)
    values = face.neutral()
    rest = rig.geometry(values)
    assert "flag" not in {item.name for item in rest.items}  # hidden at 0
    lifted = rig.geometry(values, {"HAT": 0.5})
    np.testing.assert_allclose(_item(lifted, "flag").vertices, [[0, 15], [10, 15], [0, 25]])
    np.testing.assert_allclose(_item(lifted, "brim").vertices, [[0, 220], [20, 220], [10, 230]])
    np.testing.assert_allclose(_item(rest, "brim").vertices, [[0, 200], [20, 200], [10, 210]])


@pytest.mark.parametrize("params, message", [
    ({"MB": {}}, "MB is one of the 21 motors"),
    ({"HT": {}}, "declared by head.tilt"),
    ({"ul": {}}, "a parameter code is 1-16 capitals"),
    ({"UL": {"neutral": 0.5}}, "UL is a standard parameter .* whose neutral is 0.0"),
    ({"X": {"points": {"NOSE": {"at1": [0, 1]}}}}, 'unknown control point "NOSE"'),
    ({"X": {"neutral": 0.5, "points": {"MT": {"at0": [0, 0], "at1": [0, 10]}}}},
     r"at the neutral 0.5 the point moves by \[0, 5\]"),
    ({"X": {"neutral": 2}}, "params.X.neutral"),
    ({"X": {"colour": 1}}, "colour"),
])
def test_a_bad_parameter_is_an_error_naming_its_field(params, message):
    with pytest.raises(InputError, match=message):
        face_from_dict(_doc(**params), source="mine.json")


def test_a_component_or_polygon_driven_by_an_undeclared_parameter_is_an_error():
    doc = _doc()
    doc["components"] = [{"kind": "polygon", "points": [[0, 0], [10, 0], [0, 10]], "fill": "#ff0000",
                          "translate": {"motor": "HAT", "at0": [0, 0], "at1": [0, 30]}}]
    with pytest.raises(InputError, match=r"components\[0\].translate.motor"):
        face_from_dict(doc)


def test_each_standard_extra_is_on_at_least_two_built_in_faces_and_moves_them():
    carried: dict[str, list[str]] = {code: [] for code in STANDARD_EXTRAS}
    for name in builtin_faces():
        face = load_face(name)
        rig = FaceRig(face)
        values = face.neutral()
        rest = np.concatenate([item.vertices for item in rig.geometry(values).items])
        for code, neutral in face.extra_neutral().items():
            if code not in STANDARD_EXTRAS:
                continue  # the face's own (a swinging fringe)
            assert neutral == STANDARD_EXTRAS[code].neutral
            carried[code].append(name)
            for end in (0.0, 1.0):
                if end == neutral:
                    continue
                drawn = rig.geometry(values, {code: end})
                moved = np.concatenate([item.vertices for item in drawn.items])
                assert len(drawn.items) != len(rig.geometry(values).items) or np.abs(moved - rest).max() > 8, (
                    f"{code}={end} barely moves {name}")
    assert all(len(faces) >= 2 for faces in carried.values()), carried
    assert len(carried["HT"]) == len(builtin_faces())


def test_a_standard_extra_the_face_lacks_is_left_out_and_said(caplog):
    from player.offline import geometries

    face = load_face("cat")  # no cheeks to puff
    values = np.repeat(face.neutral()[None], 2, 0)
    track = MotorTrack(values, 10.0, extra_codes=("CP", "UL"), extra=np.array([[1.0, 0.0], [1.0, 1.0]]))
    with caplog.at_level(logging.INFO):
        frames = list(geometries(track, FaceRig(face), 10.0))
    assert "face cat does not declare CP: that column is not drawn" in caplog.text
    rig = FaceRig(face)
    mouth = _item(frames[1], "upper_lip").vertices
    np.testing.assert_allclose(mouth, _item(rig.geometry(face.neutral(), {"UL": 1.0}), "upper_lip").vertices)
