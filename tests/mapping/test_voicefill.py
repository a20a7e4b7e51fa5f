"""The voice fills the mouth where the face is lost (issue 40): which motors are lost, the
crossfade by hand, and `retarget` of a GRID clip whose face is covered for a second."""

import numpy as np
import pytest

from capture import load_markerset
from capture.take import Take
from mapping.mapfile import load_mapping
from mapping.voicefill import MOUTH, fill_from_voice, lost_mouth
from toon import MOTOR_CODES
from toon.track import MotorTrack


def test_a_motor_is_lost_where_a_marker_its_rule_reads_is_unseen():
    markerset, mapping = load_markerset("face"), load_mapping("face")
    labels = tuple(markerset.labels)
    positions = np.ones((30, len(labels), 3))
    positions[10:20, labels.index("MOUTH_R")] = np.nan  # the right corner lost for 10 frames
    positions[25, labels.index("LIP_UP_IN")] = np.nan  # the upper inner lip for one
    lost = lost_mouth(Take(positions, labels, 30.0), mapping, markerset)
    by = dict(zip(MOUTH, lost.T, strict=True))
    assert by["MRH"][10:20].all() and by["MRV"][10:20].all() and by["MRH"].sum() == 10
    assert not by["MLH"].any() and not by["MLV"].any()  # the left corner was seen throughout
    assert by["MB"].tolist() == [k == 25 for k in range(30)]


def test_the_voice_takes_the_lost_frames_and_fades_in_and_out_over_a_tenth_of_a_second():
    rate = 100.0
    face = np.full((60, 21), 0.2)
    track = MotorTrack(face, rate, meta={"mapping": "face"})
    voice = MotorTrack(np.full((200, 21), 0.8), 100.0)
    lost = np.zeros((60, len(MOUTH)), bool)
    lost[20:30, MOUTH.index("MB")] = True
    filled, frames = fill_from_voice(track, lost, voice, np.arange(200) / 100.0)
    mb = filled.values[:, MOTOR_CODES.index("MB")]
    share = (mb - 0.2) / 0.6
    np.testing.assert_allclose(share[20:30], 1.0)
    np.testing.assert_allclose(share[[19, 30]], 1 - 1 / 11)  # one frame out: 10/11 of the voice
    np.testing.assert_allclose(share[[10, 39]], 1 - 10 / 11)  # ten frames out (0.1 s): 1/11
    np.testing.assert_allclose(share[:10], 0.0)
    np.testing.assert_allclose(share[40:], 0.0)
    assert frames == 30 and filled.meta["voice_filled_frames"] == 30 and filled.meta["mapping"] == "face"
    others = [c for c in range(21) if c != MOTOR_CODES.index("MB")]
    np.testing.assert_array_equal(filled.values[:, others], face[:, others])  # nothing else touched


@pytest.mark.slow
@pytest.mark.realdata
def test_retarget_moves_a_covered_mouth_with_the_voice(realdata, tmp_path, capsys):
    from toonface.cli import main

    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    if not clip.is_file():
        pytest.skip(f"{clip} is absent")
    from bench.lipsync import covered as cover

    covered = tmp_path / "covered.mkv"
    cover(clip, covered, 30, 55)  # 1.2-2.2 s: "blue at" said with the face unseen
    from capture.video_tracking import track_video
    from capture.voice_take import read_voice
    from mapping.workflow import choose_mapping
    from toonface.pipeline import map_onto_face

    take = track_video(covered, "face")
    chosen, markerset = choose_mapping(take)
    lost = lost_mouth(take, chosen, markerset)
    assert lost[30:55].all() and not lost[:28].any()
    held = map_onto_face(take)
    voice = read_voice(covered)
    filled, _ = fill_from_voice(held, lost, map_onto_face(voice, "first"), voice.times)
    mb = MOTOR_CODES.index("MB")
    assert np.ptp(held.values[32:53, mb]) < 0.05  # without the voice: the mouth held shut
    assert np.ptp(filled.values[32:53, mb]) > 0.3  # with it: it speaks
    assert main(["retarget", str(covered), "-o", str(tmp_path / "out.mp4"), "--size", "128"]) == 0
    assert "from the voice in 31 frames where the face's mouth was lost (25 frames" in capsys.readouterr().err
    from toon import load_track

    # map takes the video as retarget does (it said "unknown take format '.mkv'"), the voice filling alike
    assert main(["map", str(covered), "-o", str(tmp_path / "filled.csv")]) == 0
    assert "from the voice in 31 frames where the face's mouth was lost (25 frames" in capsys.readouterr().err
    assert main(["map", str(covered), "-o", str(tmp_path / "held.csv"), "--no-voice-fill"]) == 0
    assert "from the voice" not in capsys.readouterr().err
    by_map = {name: load_track(tmp_path / f"{name}.csv").values[:, mb] for name in ("filled", "held")}
    assert np.ptp(by_map["held"][32:53]) < 0.05 and np.ptp(by_map["filled"][32:53]) > 0.3
    np.testing.assert_array_equal(by_map["filled"][:27], by_map["held"][:27])  # seen, and over 0.1 s from the fill
