"""Frame sinks: a decodable H.264 MP4 with the right frame count, PNG folders, atomic outputs."""

import io

import av
import cv2
import numpy as np
import pytest

from common import InputError
from player import Mp4Sink, PngSink, open_sink
from player.sinks import RawSink


def _frames(n, size=(32, 24)):
    w, h = size
    for i in range(n):
        frame = np.zeros((h, w, 3), np.uint8)
        frame[:, : (i + 1) * w // n] = (200, 60, 30)
        yield frame


def test_mp4_is_h264_with_every_frame(tmp_path):
    path = tmp_path / "v.mp4"
    with Mp4Sink(path, 30.0, (32, 24)) as sink:
        for f in _frames(12):
            sink.write(f)
    with av.open(str(path)) as c:
        stream = c.streams.video[0]
        assert stream.codec_context.name == "h264" and stream.codec_context.pix_fmt == "yuv420p"
        assert stream.average_rate == 30
        decoded = [f.to_ndarray(format="rgb24") for f in c.decode(video=0)]
    assert len(decoded) == 12 and decoded[0].shape == (24, 32, 3)
    assert abs(int(decoded[-1][12, 16, 0]) - 200) < 12  # the last frame is filled, colour kept
    assert list(tmp_path.iterdir()) == [path]  # no temporary left behind


def test_mp4_colours_are_bt601_limited_range_and_the_callers_array_is_free_at_once(tmp_path):
    # flat 16x16 blocks, lossless (crf 0): the stored planes are the conversion itself, against
    # BT.601's limited-range equations worked here (Rec. 601, as FFmpeg's scaler and players read
    # untagged SD video); the frame array is overwritten straight after each write
    colours = np.array([(0, 0, 0), (255, 255, 255), (255, 0, 0), (0, 255, 0), (0, 0, 255), (200, 60, 30),
                        (17, 140, 230), (128, 128, 128)], float)
    frame = np.zeros((32, 64, 3), np.uint8)
    path = tmp_path / "c.mp4"
    with Mp4Sink(path, 30.0, (64, 32), crf=0) as sink:
        for _ in range(3):
            for k, colour in enumerate(colours):
                frame[16 * (k // 4):16 * (k // 4) + 16, 16 * (k % 4):16 * (k % 4) + 16] = colour
            sink.write(frame)
            frame[:] = 99  # reused by the caller before the encoder has the frame
    r, g, b = colours.T
    want_y = 16 + (65.481 * r + 128.553 * g + 24.966 * b) / 255
    want_cb = 128 + (-37.797 * r - 74.203 * g + 112.0 * b) / 255
    want_cr = 128 + (112.0 * r - 93.786 * g - 18.214 * b) / 255
    with av.open(str(path)) as c:
        planes = [f.to_ndarray() for f in c.decode(video=0)]  # yuv420p: (48, 64), Y then U then V
    assert len(planes) == 3
    for yuv in planes:
        y, u, v = yuv[:32], yuv[32:40].reshape(16, 32), yuv[40:48].reshape(16, 32)
        for k in range(len(colours)):
            row, col = 16 * (k // 4) + 8, 16 * (k % 4) + 8
            assert abs(int(y[row, col]) - want_y[k]) <= 1, (k, y[row, col], want_y[k])
            assert abs(int(u[row // 2, col // 2]) - want_cb[k]) <= 1, (k, u[row // 2, col // 2], want_cb[k])
            assert abs(int(v[row // 2, col // 2]) - want_cr[k]) <= 1, (k, v[row // 2, col // 2], want_cr[k])


def test_failed_render_leaves_no_video(tmp_path):
    path = tmp_path / "v.mp4"
    with pytest.raises(RuntimeError):
        with Mp4Sink(path, 30.0, (32, 24)) as sink:
            sink.write(next(_frames(1)))
            raise RuntimeError("renderer died")
    assert list(tmp_path.iterdir()) == []


def test_png_folder_round_trip_and_replacement(tmp_path):
    out = tmp_path / "frames"
    frames = list(_frames(3))
    with PngSink(out) as sink:
        for f in frames:
            sink.write(f)
    names = sorted(p.name for p in out.iterdir())
    assert names == ["frame_000000.png", "frame_000001.png", "frame_000002.png"]
    back = cv2.imread(str(out / "frame_000001.png"))[:, :, ::-1]
    np.testing.assert_array_equal(back, frames[1])
    with PngSink(out) as sink:  # a re-run replaces the folder whole
        sink.write(frames[0])
    assert sorted(p.name for p in out.iterdir()) == ["frame_000000.png"]


def test_odd_sizes_and_unknown_types_are_refused(tmp_path):
    with pytest.raises(InputError, match="even frame size"):
        Mp4Sink(tmp_path / "v.mp4", 30, (31, 24))
    with pytest.raises(InputError, match="unknown output type '.gif'"):
        open_sink(tmp_path / "v.gif", 30, (32, 24))
    sink = open_sink(tmp_path / "dir", 30, (32, 24))
    assert isinstance(sink, PngSink)
    sink.abort()
    assert list(tmp_path.iterdir()) == []


def test_skipped_slots_keep_each_output_in_real_time(tmp_path):
    """A live player that dropped frames: the MP4 leaves a gap in its timestamps (the frame before
    shows longer), a PNG sequence and a raw stream repeat the frame before."""
    frames = list(_frames(6))
    with Mp4Sink(tmp_path / "v.mp4", 25.0, (32, 24)) as mp4, PngSink(tmp_path / "png") as png:
        raw_bytes = io.BytesIO()
        raw = RawSink(raw_bytes)
        for i, frame in enumerate(frames):
            for sink in (mp4, png, raw):
                sink.write(frame)
                if i == 2:
                    sink.skip(3)  # slots 3, 4 and 5 went by undrawn
    with av.open(str(tmp_path / "v.mp4")) as c:
        times = [round(float(f.time) * 25) for f in c.decode(video=0)]
        assert times == [0, 1, 2, 6, 7, 8]
        assert float(c.duration / av.time_base) == pytest.approx(9 / 25)
    shown = [0, 1, 2, 2, 2, 2, 3, 4, 5]
    pngs = sorted((tmp_path / "png").glob("*.png"))
    assert len(pngs) == 9
    for path, which in zip(pngs, shown, strict=True):
        assert np.array_equal(cv2.imread(str(path))[:, :, ::-1], frames[which])
    assert raw_bytes.getvalue() == b"".join(frames[which].tobytes() for which in shown)


def test_a_png_written_but_not_counted_when_stopped_is_not_kept(tmp_path):
    """After SIGTERM there was one more PNG on disk than the message said: the interrupt came
    between a frame's file and its count."""
    from player.sinks import PngSink

    sink = PngSink(tmp_path / "frames")
    for _ in range(3):
        sink.write(np.zeros((8, 8, 3), np.uint8))
    (sink._tmp / "frame_000003.png").write_bytes((sink._tmp / "frame_000002.png").read_bytes())  # the race
    kept = sink.keep_partial()
    assert kept == tmp_path / "frames.partial-3"
    assert sorted(p.name for p in kept.iterdir()) == [f"frame_00000{i}.png" for i in range(3)]
    assert not (tmp_path / "frames").exists()


def test_a_recording_killed_outright_leaves_all_but_its_last_second(tmp_path):
    """After SIGKILL, receive --record rec.csv left no CSV at all: the recording was kept in
    memory until close. Now it is appended as it goes to rec.partial.csv."""
    import signal
    import subprocess
    import sys
    import textwrap

    from toon import load_track

    script = textwrap.dedent(f"""
        import os, signal
        import numpy as np
        from toon.recording import MotorRecorder
        recorder = MotorRecorder({str(tmp_path / "rec.csv")!r}, 30.0)
        for f in range(95):  # 3.2 s of frames, the values a ramp
            recorder.write(f / 30.0, np.full(21, f / 100.0))
        os.kill(os.getpid(), signal.SIGKILL)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=60)
    assert done.returncode == -signal.SIGKILL
    assert not (tmp_path / "rec.csv").exists()
    kept = load_track(tmp_path / "rec.partial.csv")
    assert 2.0 * 30 <= kept.frames <= 94  # all but the last second or so
    np.testing.assert_allclose(kept.values[:, 0], np.arange(kept.frames) / 100.0, atol=1e-6)  # slot k: frame k


def test_a_recording_closed_or_aborted_leaves_no_partial_file(tmp_path):
    from toon import load_track
    from toon.recording import MotorRecorder

    for end in ("close", "abort"):
        recorder = MotorRecorder(tmp_path / f"{end}.csv", 30.0)
        for f in range(40):
            recorder.write(f / 30.0, np.full(21, 0.5))
        getattr(recorder, end)()
        assert not (tmp_path / f"{end}.partial.csv").exists()
        assert (tmp_path / f"{end}.csv").exists() == (end == "close")
    assert load_track(tmp_path / "close.csv").frames == 40


@pytest.mark.slow
def test_a_live_video_killed_outright_plays_up_to_its_last_seconds(tmp_path):
    """After SIGKILL, play -o x.mp4 left a 48-byte file no player opens: an MP4's index is
    written at the end. A live video is now fragmented and flushed as it goes."""
    import signal
    import subprocess
    import sys
    import textwrap

    import av

    script = textwrap.dedent(f"""
        import os, signal
        import numpy as np
        from player.sink_choice import open_sink
        sink = open_sink({str(tmp_path / "live.mp4")!r}, 30.0, (64, 48), live=True)
        for f in range(150):  # 5 s of frames, each a grey level that tells which it is
            sink.write(np.full((48, 64, 3), f, np.uint8))
        os.kill(os.getpid(), signal.SIGKILL)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=60)
    assert done.returncode == -signal.SIGKILL, done.stderr
    assert not (tmp_path / "live.mp4").exists()
    with av.open(str(tmp_path / "live.partial.mp4")) as container:
        greys = [int(np.median(frame.to_ndarray(format="rgb24"))) for frame in container.decode(video=0)]
    assert 90 <= len(greys) < 150  # all but the last second or two (what the encoder holds)
    assert np.abs(np.array(greys) - np.arange(len(greys))).max() <= 2  # frame k is frame k


def test_a_live_video_closed_is_the_target_and_interrupted_keeps_a_partial_beside_it(tmp_path):
    import av

    from player.sink_choice import open_sink

    (tmp_path / "b.mp4").write_bytes(b"an earlier complete video")
    for name, end in (("a.mp4", "close"), ("b.mp4", "keep_partial"), ("c.mp4", "abort")):
        sink = open_sink(tmp_path / name, 30.0, (64, 48), live=True)
        for f in range(40):
            sink.write(np.full((48, 64, 3), f, np.uint8))
        getattr(sink, end)()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.mp4", "b.mp4", "b.partial-40.mp4"]
    assert (tmp_path / "b.mp4").read_bytes() == b"an earlier complete video"
    for name in ("a.mp4", "b.partial-40.mp4"):
        with av.open(str(tmp_path / name)) as container:
            assert sum(1 for _ in container.decode(video=0)) == 40


def _decoded(path) -> list[np.ndarray]:
    with av.open(str(path)) as container:
        return [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]


def test_encoding_on_its_own_thread_writes_the_same_video(tmp_path):
    """Issue 65: an offline MP4 is encoded on a thread beside the drawing (retarget 15.6 -> 10 s
    for a minute); the frames are those encoded in turn, the caller's array reused meanwhile.
    Lossless (CRF 0) on one x264 thread: at CRF 18 with x264's own threads, two encodings of
    the same frames differed now and then by a few levels in a few per cent of the pixels (once
    in about ten runs here), which is x264's choice, not the order of the frames."""
    from player.sinks import H264Encoder

    videos = {}
    for background in (False, True):
        path = tmp_path / f"{background}.mp4"
        encoder = H264Encoder(path, 30.0, (64, 48), crf=0, background=background, threads="1")
        reused = np.zeros((48, 64, 3), np.uint8)
        for frame in _frames(40, (64, 48)):
            reused[:] = frame  # one array, overwritten as soon as it was given
            encoder.write(reused)
        encoder.finish()
        videos[background] = _decoded(path)
    assert len(videos[True]) == len(videos[False]) == 40
    for a, b in zip(videos[True], videos[False], strict=True):
        np.testing.assert_array_equal(a, b)
    assert not np.array_equal(videos[True][0], videos[True][-1])


def test_an_encoding_error_on_the_thread_is_raised_and_no_video_is_left(tmp_path, monkeypatch):
    from player.sinks import H264Encoder

    real = H264Encoder._encode
    calls = []

    def failing(self, frame):
        calls.append(frame)
        if len(calls) == 3:
            raise OSError("disk full")
        real(self, frame)

    monkeypatch.setattr(H264Encoder, "_encode", failing)
    path = tmp_path / "v.mp4"
    with pytest.raises(OSError, match="disk full"):
        with Mp4Sink(path, 30.0, (32, 24)) as sink:
            for frame in _frames(30):
                sink.write(frame)
    assert list(tmp_path.iterdir()) == []
