"""Videos as live sources, as a new user gives them (issue 44): a plain talking-head video is
tracked without markers and said so, a container's impossible frame rate is read from its
frames' times, and --loop plays a video again."""

import fractions

import av
import numpy as np
import pytest

from capture.face_sources import camera_source
from capture.videoio import probe, video_rate
from common import InputError
from toonface.cli import main


def broken_rate_video(path, frames: int = 20, every: int = 750, base: int = 18750):
    """A clip whose container says ``base`` fps while its frames step ``every`` ticks of 1/``base`` s
    (25 fps by default), as a file from the wild did."""
    with av.open(str(path), "w") as out:
        stream = out.add_stream("mpeg4", rate=base)
        stream.width, stream.height, stream.pix_fmt = 64, 48, "yuv420p"
        stream.time_base = fractions.Fraction(1, base)
        for i in range(frames):
            frame = av.VideoFrame.from_ndarray(np.full((48, 64, 3), 10 * i, np.uint8), format="rgb24")
            frame.pts, frame.time_base = i * every, fractions.Fraction(1, base)
            for packet in stream.encode(frame):
                out.mux(packet)
        for packet in stream.encode():
            out.mux(packet)
    return path


def test_an_impossible_frame_rate_is_read_from_the_frames_times(tmp_path):
    """send camera:VIDEO of a container saying 18 750 fps ended in an internal error (exit 70)."""
    video = broken_rate_video(tmp_path / "broken.mkv")
    assert probe(video).rate == pytest.approx(25.0)
    assert video_rate(video, 30.0) == 30.0  # a plausible rate is believed
    with pytest.raises(InputError, match="cannot tell its frame rate"):
        video_rate(tmp_path / "missing.mkv", 0.0)


@pytest.mark.slow  # the face tracker starts: make test runs it
def test_send_takes_a_video_with_an_impossible_rate_as_a_camera(tmp_path, capsys):
    pytest.importorskip("mediapipe")
    video = broken_rate_video(tmp_path / "broken.mkv")
    assert main(["send", f"camera:{video}", "--to", "127.0.0.1:9", "--seconds", "0.2"]) == 0
    assert "at 25 Hz" in capsys.readouterr().out


@pytest.mark.slow  # the face tracker over 35 frames: make test runs it
def test_a_video_played_as_a_camera_loops_when_asked(tmp_path):
    pytest.importorskip("mediapipe")
    video = broken_rate_video(tmp_path / "short.mkv", frames=10)
    now = [0.0]

    def sleep(seconds: float) -> None:
        now[0] += seconds

    for repeat, expected in ((False, 10), (True, 25)):
        source = camera_source(str(video), clock=lambda: now[0], sleep=sleep, repeat=repeat)
        times = [frame.t for _, frame in zip(range(25), source.frames, strict=False)]
        assert len(times) == expected and np.all(np.diff(times) > 0)  # time goes on through the loop


@pytest.mark.realdata
def test_send_a_plain_talking_head_video_tracks_the_face_and_says_so(realdata, capsys):
    """send VIDEO took any video for dot markers and failed on the marker set's pupils."""
    pytest.importorskip("mediapipe")
    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    assert main(["send", str(clip), "--to", "127.0.0.1:9", "--seconds", "0.3"]) == 0
    err = capsys.readouterr().err
    assert "the face is tracked without markers (face:bbaf2n.mpg)" in err and "video:bbaf2n.mpg" in err
