"""What an interrupted or killed command keeps: a render's partial beside an earlier complete
output, no hidden leftovers from a killed run, and files that name themselves."""

import os
import signal

import av
import numpy as np
import pytest

from toonface import cli_options
from toonface.cli import main


@pytest.mark.parametrize("signum, status", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
@pytest.mark.parametrize("suffix", [".mp4", ""])
def test_a_signal_stops_a_render_keeps_what_was_drawn_and_the_earlier_output(small_take, tmp_path, monkeypatch,
                                                                            capsys, signum, status, suffix):
    """SIGTERM lost the output and left a hidden .NAME.xxxx.partial.mp4; then an interrupted run
    replaced a complete earlier output with its 12 frames. Now the 12 frames are kept as
    out.partial-12 beside the earlier output, which is left as it was."""
    output = tmp_path / f"out{suffix}"
    assert main(["render", str(small_take / "m.csv"), "-o", str(output), "--size", "32"]) == 0  # complete
    before = _frames(output)
    assert before == 60
    drawn = []

    def frame_done(bar, frames):
        drawn.append(frames)
        if len(drawn) == 12:
            os.kill(os.getpid(), signum)  # delivered to this (the main) thread before the next frame

    monkeypatch.setattr(cli_options.ProgressBar, "__call__", frame_done)
    capsys.readouterr()
    assert main(["render", str(small_take / "m.csv"), "-o", str(output), "--size", "32"]) == status
    err = capsys.readouterr().err.strip()
    partial = tmp_path / f"out.partial-12{suffix}"
    assert err.endswith(f"kept {partial} with the 12 of 60 frames drawn")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([output.name, partial.name])  # nothing hidden
    assert _frames(output) == before and _frames(partial) == 12
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL  # the handler is the command's alone


def _frames(output) -> int:
    """Frames in an MP4, or PNGs in a folder."""
    if output.is_dir():
        return len(list(output.glob("frame_*.png")))
    with av.open(str(output)) as c:
        return len(list(c.decode(video=0)))



def test_a_render_with_sound_interrupted_keeps_its_picture_as_the_outputs_partial(realdata, tmp_path):
    """retarget of a video, interrupted while rendering, said "kept .out.picture.mp4 with the 5
    of 75 frames drawn" and left nothing on disk."""
    from common.errors import Interrupted
    from toon import MotorTrack, load_face, standard_neutral
    from toonface.pipeline import render_with_sound

    track = MotorTrack(np.tile(standard_neutral(), (75, 1)), 25.0)
    drawn = []

    def progress(frames):
        drawn.append(frames)
        if len(drawn) == 5:
            raise KeyboardInterrupt

    with pytest.raises(Interrupted) as stopped:
        render_with_sound(track, load_face("classic"), tmp_path / "out.mp4",
                          realdata / "video" / "grid" / "bbaf2n.mpg", size=(32, 32), progress=progress)
    kept = tmp_path / "out.partial-5.mp4"
    assert stopped.value.output == str(kept) and stopped.value.frames == 5
    assert [p.name for p in tmp_path.iterdir()] == [kept.name]
    assert _frames(kept) == 5


@pytest.mark.parametrize("name", ["out.mp4", "frames"])
def test_hidden_leftovers_of_a_killed_run_are_cleared_by_the_next_run_to_the_same_output(small_take, tmp_path,
                                                                                         name):
    """SIGKILL leaves no time to clean up: 28 MB of hidden PNGs stayed beside the output."""
    output = tmp_path / name
    if output.suffix:
        (tmp_path / ".out.a1b2c3d4.partial.mp4").write_bytes(b"\0" * 48)
    else:
        (tmp_path / ".frames.x9y8z7w6.partial").mkdir()
        (tmp_path / ".frames.x9y8z7w6.partial" / "frame_000000.png").write_bytes(b"png")
    (tmp_path / ".other.a1b2c3d4.partial.mp4").write_bytes(b"not ours")  # another output's: left alone
    assert main(["render", str(small_take / "m.csv"), "-o", str(output), "--size", "32"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([".other.a1b2c3d4.partial.mp4", name])


def test_a_trc_names_its_own_file_not_the_temporary_one(small_take, tmp_path):
    """TRC files written by clean carried the temporary file's name in their header."""
    assert main(["clean", str(small_take / "t.npz"), "-o", str(tmp_path / "clean.trc")]) == 0
    assert (tmp_path / "clean.trc").read_text().splitlines()[0].split("\t")[-1] == "clean.trc"
