"""Parameters beyond the 21 motors (issue 42, first step): the head tilt HT every built-in face
declares, tracks that carry extra columns, and 21-motor tracks drawn exactly as before."""

import dataclasses

import numpy as np
import pytest

from common import InputError
from toon import FaceRig, MotorTrack, builtin_faces, load_face, load_track, save_track
from toon.face import face_from_dict
from toon.motors import MOTOR_CODES


def _vertices(geometry) -> np.ndarray:
    return np.concatenate([item.vertices for item in geometry.items])


@pytest.mark.parametrize("name", builtin_faces())
def test_every_built_in_face_tilts_its_head_about_the_pivot_by_hand(name):
    face = load_face(name)
    rig = FaceRig(face)
    values = face.neutral()
    upright = _vertices(rig.geometry(values))
    np.testing.assert_array_equal(_vertices(rig.geometry(values, {"HT": 0.5})), upright)  # neutral: untouched
    assert face.extra_codes == ("HT",) and face.head_tilt == 25.0
    angle = np.radians(25.0)
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])  # counter-clockwise
    pivot = np.array(face.head_pivot)
    np.testing.assert_allclose(_vertices(rig.geometry(values, {"HT": 1.0})), pivot + (upright - pivot) @ turn.T,
                               atol=1e-9)
    half = _vertices(rig.geometry(values, {"HT": 0.25}))  # a quarter: half the tilt, clockwise
    back = np.array([[np.cos(angle / 2), np.sin(angle / 2)], [-np.sin(angle / 2), np.cos(angle / 2)]])
    np.testing.assert_allclose(half, pivot + (upright - pivot) @ back.T, atol=1e-9)


def test_a_parameter_the_face_does_not_declare_is_an_error_naming_it():
    doc = load_face("classic").to_dict()
    doc["head"].pop("tilt")
    plain = face_from_dict(doc)
    assert plain.extra_codes == ()
    with pytest.raises(InputError, match="has no parameter HT"):
        FaceRig(plain).geometry(plain.neutral(), {"HT": 0.7})
    with pytest.raises(InputError, match="has no parameter EARS"):
        FaceRig(load_face("cat")).geometry(load_face("cat").neutral(), {"EARS": 0.7})


def test_tracks_carry_extra_columns_through_csv_and_npz(tmp_path):
    table = np.random.default_rng(0).uniform(0, 1, (10, 22))
    track = MotorTrack.from_columns(("HT", *MOTOR_CODES), table, 25.0)  # extras in any column
    assert track.extra_codes == ("HT",)
    np.testing.assert_array_equal(track.extra[:, 0], table[:, 0])
    np.testing.assert_array_equal(track.values, table[:, 1:])
    for suffix in (".csv", ".npz"):
        back = load_track(save_track(track, tmp_path / f"t{suffix}"))
        assert back.extra_codes == ("HT",)
        np.testing.assert_allclose(back.table(), track.table(), atol=1e-6)
    (tmp_path / "bad.csv").write_text("time," + ",".join(MOTOR_CODES) + ",ht\n" + "0," * 22 + "0\n")
    with pytest.raises(InputError, match=r"unknown \['ht'\]"):
        load_track(tmp_path / "bad.csv")
    with pytest.raises(InputError, match="within"):
        MotorTrack(table[:, 1:], 25.0, extra_codes=("HT",), extra=table[:, :1] + 2)


def test_a_21_motor_track_draws_exactly_as_a_face_without_the_tilt():
    for name in builtin_faces():
        face = load_face(name)
        before = dataclasses.replace(face, head_tilt=0.0)  # the face as it was drawn before HT
        values = np.random.default_rng(1).uniform(0, 1, 21)
        np.testing.assert_array_equal(_vertices(FaceRig(face).geometry(values)),
                                      _vertices(FaceRig(before).geometry(values)))


def test_render_draws_the_tilt_and_refuses_an_undeclared_column(tmp_path, capsys):
    from toonface.cli import main

    face = load_face("round")
    values = np.repeat(face.neutral()[None], 3, 0)
    track = MotorTrack(values, 10.0, extra_codes=("HT",), extra=np.array([[0.5], [1.0], [0.0]]))
    save_track(track, tmp_path / "tilt.csv")
    assert main(["render", str(tmp_path / "tilt.csv"), "-o", str(tmp_path / "f"), "--face", "round",
                 "--size", "64"]) == 0
    from PIL import Image

    frames = [np.asarray(Image.open(tmp_path / "f" / f"frame_{k:06d}.png")).astype(int) for k in range(3)]
    assert np.abs(frames[1] - frames[0]).mean() > 5 and np.abs(frames[2] - frames[1]).mean() > 5
    odd = MotorTrack(values, 10.0, extra_codes=("TAIL",), extra=np.full((3, 1), 0.5))
    save_track(odd, tmp_path / "odd.csv")
    assert main(["render", str(tmp_path / "odd.csv"), "-o", str(tmp_path / "g"), "--size", "64"]) == 2
    assert "face classic has no parameter TAIL" in capsys.readouterr().err


def test_commands_that_use_only_the_21_say_so(tmp_path, capsys):
    from toonface.cli import main

    values = np.repeat(load_face("classic").neutral()[None], 4, 0)
    save_track(MotorTrack(values, 10.0, extra_codes=("HT",), extra=np.full((4, 1), 0.8)), tmp_path / "t.csv")
    assert main(["score", str(tmp_path / "t.csv"), "-o", str(tmp_path / "s.png")]) == 0
    assert main(["anim", "from-track", str(tmp_path / "t.csv"), "-o", str(tmp_path / "a.toml")]) == 0
    err = capsys.readouterr().err
    assert "score uses the 21 motors; its HT column is not used here yet" in err
    assert "anim from-track uses the 21 motors" in err
