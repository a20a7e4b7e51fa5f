"""An output folder whose name holds a dot (issue 66): frames go there when --format says so, or
when the folder exists; otherwise the suffix still names a file's format and an unknown one is refused."""

import numpy as np

from toon import MotorTrack, save_track, standard_neutral
from toonface.cli import main


def test_a_dotted_folder_takes_frames_when_the_format_says_so_or_it_exists(tmp_path, capsys):
    motors = tmp_path / "m.csv"
    save_track(MotorTrack(np.tile(standard_neutral(), (3, 1)), 10.0), motors)
    assert main(["render", str(motors), "-o", str(tmp_path / "take.v2"), "--format", "png", "--size", "64"]) == 0
    assert len(list((tmp_path / "take.v2").glob("frame_*.png"))) == 3
    (tmp_path / "shots.2026").mkdir()
    assert main(["render", str(motors), "-o", str(tmp_path / "shots.2026"), "--size", "64"]) == 0
    assert len(list((tmp_path / "shots.2026").glob("frame_*.png"))) == 3
    capsys.readouterr()
    assert main(["render", str(motors), "-o", str(tmp_path / "take.v3"), "--size", "64"]) == 2
    assert "take.v3" in capsys.readouterr().err
    assert not (tmp_path / "take.v3").exists()
    assert main(["render", str(motors), "-o", str(tmp_path / "x.mp4"), "--format", "png"]) == 2
    assert "--format png is for a folder" in capsys.readouterr().err
