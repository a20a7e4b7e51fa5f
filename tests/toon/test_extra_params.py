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
    assert face.extra_codes[0] == "HT" and face.head_tilt == 25.0
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
    doc.pop("physics")  # its hair's driver reads HT
    plain = face_from_dict(doc)
    assert plain.extra_codes == ("UL", "JS", "CP", "HAIR")
    with pytest.raises(InputError, match="has no parameter HT"):
        FaceRig(plain).geometry(plain.neutral(), {"HT": 0.7})
    with pytest.raises(InputError, match="has no parameter TAIL"):
        FaceRig(load_face("cat")).geometry(load_face("cat").neutral(), {"TAIL": 0.7})


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


def test_score_and_anim_from_track_keep_the_parameters(tmp_path, capsys):
    from toonface.cli import main

    values = np.repeat(load_face("classic").neutral()[None], 4, 0)
    save_track(MotorTrack(values, 10.0, extra_codes=("HT",), extra=np.full((4, 1), 0.8)), tmp_path / "t.csv")
    assert main(["score", str(tmp_path / "t.csv"), "-o", str(tmp_path / "s.png")]) == 0
    assert main(["anim", "from-track", str(tmp_path / "t.csv"), "-o", str(tmp_path / "a.toml")]) == 0
    err = capsys.readouterr().err
    assert "not used" not in err  # score draws HT's stave; from-track makes its knots
    from PIL import Image

    with Image.open(tmp_path / "s.png") as score:
        assert score.size[1] == 48 * 22 + 36  # a stave for each of the 21, and HT's
    from toon.animation_file import load_animation

    assert load_animation(tmp_path / "a.toml").knots["HT"][0][1] == pytest.approx(0.8)


def _turned_clip(clip, path, degrees: float = 15.0) -> np.ndarray:
    """``clip`` with each frame turned about the face (counter-clockwise positive), upright for
    0.6 s (the rest) and then rolling ``degrees`` each way over 2.4 s; the angles, per frame."""
    import av
    import cv2

    angles = []
    with av.open(str(clip)) as source, av.open(str(path), "w") as target:
        stream = target.add_stream("mpeg4", rate=25)
        stream.width, stream.height, stream.pix_fmt = 360, 288, "yuv420p"
        for k, frame in enumerate(source.decode(video=0)):
            angle = degrees * np.sin(2 * np.pi * (k - 15) / 60) if k >= 15 else 0.0
            turn = cv2.getRotationMatrix2D((180, 150), angle, 1.0)
            image = cv2.warpAffine(frame.to_ndarray(format="rgb24"), turn, (360, 288), borderMode=cv2.BORDER_REPLICATE)
            target.mux(stream.encode(av.VideoFrame.from_ndarray(image, format="rgb24")))
            angles.append(angle)
        target.mux(stream.encode(None))
    return np.array(angles)


def _drawn_angle(rig, values: np.ndarray, extra: dict) -> float:
    """How far (degrees, counter-clockwise) the frame is turned from the same frame upright."""
    upright = _vertices(rig.geometry(values))
    turned = _vertices(rig.geometry(values, extra))
    a, b = upright - upright.mean(axis=0), turned - turned.mean(axis=0)
    return float(np.degrees(np.arctan2((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum(), (a * b).sum())))


@pytest.mark.slow
@pytest.mark.realdata
def test_a_talking_head_that_tilts_tilts_every_face_within_three_degrees(realdata, tmp_path):
    from capture.video_tracking import track_video
    from toonface.pipeline import map_onto_face

    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    if not clip.is_file():
        pytest.skip(f"{clip} is absent")
    applied = _turned_clip(clip, tmp_path / "turned.mp4")
    take = track_video(tmp_path / "turned.mp4", "face")
    worst = 0.0
    for name in builtin_faces():
        face = load_face(name)
        track = map_onto_face(take, (0.0, 0.5), face)  # the rest: the upright first half second
        assert track.extra_codes[0] == "HT"
        rig = FaceRig(face)
        for k in range(0, track.frames, 6):
            drawn = _drawn_angle(rig, track.values[k], {"HT": float(track.extra[k, 0])})
            worst = max(worst, abs(drawn - applied[k]))
    assert worst <= 3.0 and np.ptp(applied) > 25  # it did tilt, both ways


def test_a_mapping_drives_the_head_tilt_from_the_head_fit_and_mirror_turns_it():
    from capture import synthesize
    from mapping.workflow import map_take

    take = synthesize(seconds=4.0, seed=2).take
    plain, mirrored = map_take(take), map_take(take, mirror=True)
    assert plain.extra_codes == ("HT", "UL", "CP", "JS", "PERK") and plain.meta["mapped_extra"] == list(
        plain.extra_codes)
    assert "HT" not in plain.meta["mapped"]  # the report's motors are the 21
    for k in (0, 3):  # HT and JS turn about 0.5; the others have no side
        np.testing.assert_allclose(mirrored.extra[:, k], 1.0 - plain.extra[:, k], atol=1e-9)
    np.testing.assert_allclose(mirrored.extra[:, [1, 2, 4]], plain.extra[:, [1, 2, 4]], atol=1e-9)
