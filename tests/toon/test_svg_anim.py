"""The animated SVG of a whole track (issue 41): keyframe reduction by hand, size on a 10 s take
for every built-in face, the SVG-per-frame folder, and the command line's names."""

import re

import numpy as np
import pytest

from capture import synthesize
from player.offline import resample
from toon import FaceRig, MotorTrack, builtin_faces, load_face, load_track, save_track
from toon.svg import geometry_svg
from toon.svg_anim import linear_keys, track_svg
from toonface.cli import main
from toonface.pipeline import truth_track


def test_a_straight_motion_needs_its_ends_only_and_a_turn_one_key_more():
    line = np.linspace(0, 10, 11)[:, None, None] * np.ones((1, 3, 2))
    assert linear_keys(line, 0.01) == [0, 10]
    turn = np.concatenate([line[:6], line[4:0:-1]])  # out to 5 and back to 1
    assert linear_keys(turn, 0.01) == [0, 5, 9]
    wobble = line + np.array([0, 0.3, 0, 0.3, 0, 0.3, 0, 0.3, 0, 0.3, 0])[:, None, None]
    assert linear_keys(wobble, 0.5) == [0, 10] and len(linear_keys(wobble, 0.1)) == 11


def test_a_still_face_is_not_animated_and_a_moving_mouth_is():
    rig = FaceRig(load_face("classic"))
    still = rig.geometry(load_face("classic").neutral())
    assert "<animate" not in track_svg([still] * 5, 30.0)
    values = np.repeat(load_face("classic").neutral()[None], 5, axis=0)
    values[:, 18] = np.linspace(0.1, 0.9, 5)  # MB opens the mouth
    doc = track_svg([rig.geometry(row) for row in values], 30.0)
    assert 'attributeName="points"' in doc and 'dur="0.133333s"' in doc  # 4 frame steps at 30 Hz
    key_times = re.findall(r'keyTimes="([^"]+)"', doc)
    assert key_times and all(t.split(";")[0] == "0" and t.split(";")[-1] == "1" for t in key_times)


@pytest.mark.slow
def test_a_ten_second_take_stays_under_a_megabyte_on_every_face():
    track = truth_track(synthesize(seconds=10.0, rate=30.0, seed=3))
    values = resample(track, 30.0)
    sizes = {}
    for name in builtin_faces():
        rig = FaceRig(load_face(name))
        sizes[name] = len(track_svg([rig.geometry(row) for row in values], 30.0).encode())
    assert max(sizes.values()) < 1_000_000, sizes
    assert min(sizes.values()) > 50_000, sizes  # it does move


def test_render_writes_an_animated_svg_and_svg_frames(tmp_path, capsys):
    whole = truth_track(synthesize(seconds=8.0, rate=10.0, seed=1))
    track = MotorTrack(whole.values[-10:], whole.rate)  # a second of expressions (the start is calibration)
    save_track(track, tmp_path / "m.csv")
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "a.svg"), "--face", "cat"]) == 0
    doc = (tmp_path / "a.svg").read_text()
    assert doc.startswith("<svg") and "<animate" in doc and 'repeatCount="indefinite"' in doc
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "frames"), "--format", "svg",
                 "--size", "256"]) == 0
    files = sorted((tmp_path / "frames").glob("frame_*.svg"))
    assert len(files) == track.frames
    rig = FaceRig(load_face("classic"))
    saved = load_track(tmp_path / "m.csv")  # (as the command read it: six decimals)
    assert files[3].read_text() == geometry_svg(rig.geometry(saved.values[3]), (256, 256))
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "x.mp4"), "--format", "svg"]) == 2
    assert "--format svg is for a folder" in capsys.readouterr().err
