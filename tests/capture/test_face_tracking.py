"""Faces without markers, tracked into takes: the one OpenCV, the model and its canonical face,
real talking-head clips whose lips follow their own sound, a video on its side, a variable frame
rate, two faces in view, a file as a camera, and a clear error for each bad video. What the
tracked face drives is in ``tests/toonface/test_face_cartoon.py``."""

from __future__ import annotations

import importlib.metadata
from itertools import pairwise

import av
import numpy as np
import pytest

from capture.face_landmarks import BLENDSHAPES, LANDMARKS, canonical_face, model_path
from capture.take import SOUND_LEVEL
from capture.video_tracking import track_video
from common import InputError
from toonface.cli import main


def test_exactly_one_opencv_the_headless_contrib_build():
    """mediapipe declares opencv-contrib-python (the GUI build), which writes the same cv2/."""
    import cv2

    installed = {d.metadata["Name"].lower() for d in importlib.metadata.distributions()}
    builds = sorted(n for n in installed if n.startswith("opencv"))
    assert builds == ["opencv-contrib-python-headless"], builds
    gui = [line for line in cv2.getBuildInformation().splitlines() if line.strip().startswith("GUI:")]
    assert gui and gui[0].split(":")[1].strip() == "NONE"
    detector = cv2.aruco.ArucoDetector(cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_4X4_50))
    marker = np.pad(cv2.aruco.generateImageMarker(detector.getDictionary(), 7, 100), 40, constant_values=255)
    _, ids, _ = detector.detectMarkers(marker)
    assert ids is not None and ids.ravel().tolist() == [7]


def test_a_missing_model_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setenv("TOONFACE_FACE_MODEL", str(tmp_path / "nowhere.task"))
    with pytest.raises(InputError, match=r"nowhere\.task: no face landmark model there .*make install"):
        model_path()


def test_the_canonical_face_is_a_symmetric_head_frame_in_millimetres():
    face = canonical_face()
    assert face.shape == (468, 3)
    right_out, left_out = face[LANDMARKS["EYE_R_OUT"]], face[LANDMARKS["EYE_L_OUT"]]
    np.testing.assert_allclose(right_out * [-1, 1, 1], left_out, atol=0.01)  # mirror images across x = 0
    assert right_out[0] < 0 < left_out[0]  # x to the face's left
    assert 80 < np.linalg.norm(left_out - right_out) < 100  # outer eye corners of an adult, mm
    assert face[LANDMARKS["FOREHEAD"], 1] > face[LANDMARKS["CHIN"], 1]  # y up
    assert face[LANDMARKS["NOSE_TIP"], 2] > face[:, 2].max() - 2.0  # z out of the face: the nose leads


def _speech_envelope(path, times: np.ndarray, start: float) -> np.ndarray:
    """The clip's own sound: RMS over each video frame's 40 ms, ``(frames,)``; ``times`` count
    from the first video frame, at ``start`` on the container's clock."""
    with av.open(str(path)) as container:
        stream = container.streams.audio[0]
        rate, channels = stream.sample_rate, stream.codec_context.channels
        sound_start = float(stream.start_time * stream.time_base)
        chunks = []
        for frame in container.decode(stream):
            data = frame.to_ndarray().astype(float)  # planar: (channels, n); packed: (1, n * channels)
            chunks.append(data.mean(axis=0) if frame.format.is_planar else data.reshape(-1, channels).mean(axis=1))
    samples = np.concatenate(chunks)
    times = times + start - sound_start  # on the sound's own clock
    edges = np.round(np.append(times, times[-1] + 0.04) * rate).astype(int)
    return np.array([np.sqrt(np.mean(samples[a:b] ** 2)) if b > a else 0.0 for a, b in pairwise(edges)])


@pytest.mark.slow  # 2-4 s a clip: MediaPipe on every frame of a real video
@pytest.mark.parametrize("clip", ["bbaf2n.mpg", "lbax4n.mpg"])
def test_a_real_talking_face_is_found_in_every_frame_and_its_lips_stop_when_its_voice_does(realdata, clip):
    """GRID clips speak six words and end in silence: the lips travel while the clip's own sound
    is on and rest once it has stopped; the mapped jaw opens while it speaks."""
    from mapping import map_take

    path = realdata / "video" / "grid" / clip
    take = track_video(path, "face")
    assert take.frames == 75 and take.meta["faces_found"] == 75 and take.dims == 3
    assert take.labels == tuple(LANDMARKS) and take.channel_names == (*BLENDSHAPES, SOUND_LEVEL)
    assert np.isfinite(take.channels).all() and 0 <= take.channels.min() and take.channels.max() <= 1
    gap = np.linalg.norm(take.positions[:, take.index("LIP_UP_IN")] - take.positions[:, take.index("LIP_LOW_IN")],
                         axis=1)
    loud = _speech_envelope(path, take.times, take.meta["start_time"])
    level = take.channel(SOUND_LEVEL)  # the voice's loudness travels with the take: the same envelope
    assert np.corrcoef(level, loud)[0, 1] > 0.8 and level.max() > 0.5
    last = np.flatnonzero(loud > 0.1 * loud.max())[-1]
    assert last < 60  # the clip ends in silence
    motion = np.abs(np.diff(gap))
    assert np.ptp(gap) > 5.0  # mm: the lips part and close
    assert motion[:last].mean() > 10 * motion[last + 8:].mean()  # still once the voice has stopped
    jaw = map_take(take).values[:, 18]  # MB
    assert np.ptp(jaw[:last]) > 0.3 and np.ptp(jaw[last + 8:]) < 0.05


@pytest.mark.slow
def test_a_video_stored_on_its_side_is_tracked_upright(realdata, tmp_path):
    """A phone stores a portrait video on its side with a display matrix: its frames are turned
    as players turn them, so the face is upright in camera space (forehead above chin) and its
    points are the upright clip's; OpenCV, which turns its own, agrees on the size."""
    from capture.videoio import probe

    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    with av.open(str(clip)) as container:
        images = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
    path = tmp_path / "portrait.mp4"
    with av.open(str(path), "w") as container:
        stream = container.add_stream("libx264", rate=25)
        stream.width, stream.height, stream.pix_fmt = images[0].shape[0], images[0].shape[1], "yuv420p"
        stream.set_display_rotation(90)  # stored a quarter turn clockwise; shown a quarter turn back
        for image in images:
            sideways = av.VideoFrame.from_ndarray(np.ascontiguousarray(np.rot90(image, -1)), format="rgb24")
            for packet in stream.encode(sideways):
                container.mux(packet)
        for packet in stream.encode():
            container.mux(packet)
    assert (probe(path).width, probe(path).height) == (360, 288)
    turned, upright = track_video(path, "face"), track_video(clip, "face")
    assert turned.meta["faces_found"] == 75
    rise = turned.marker("FOREHEAD") - turned.marker("CHIN")
    assert (rise[:, 1] > 100).all() and (np.abs(rise[:, 0]) < 30).all()
    assert np.nanmedian(np.linalg.norm(turned.positions - upright.positions, axis=2)) < 2.0  # mm (irises hidden: NaN)


@pytest.mark.slow
def test_a_variable_frame_rate_keeps_each_frame_s_own_time(realdata, tmp_path):
    """Every third frame of a GRID clip dropped, the rest stamped with their own times (a phone's
    variable frame rate): the take's times are the container's, not frame / rate."""
    from fractions import Fraction

    with av.open(str(realdata / "video" / "grid" / "bbaf2n.mpg")) as container:
        images = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
    kept = [i for i in range(len(images)) if i % 3 != 2]
    path = tmp_path / "vfr.mkv"
    with av.open(str(path), "w") as container:
        stream = container.add_stream("libx264", rate=25)
        stream.width, stream.height, stream.pix_fmt = images[0].shape[1], images[0].shape[0], "yuv420p"
        stream.codec_context.time_base = Fraction(1, 1000)
        for i in kept:
            frame = av.VideoFrame.from_ndarray(images[i], format="rgb24")
            frame.pts, frame.time_base = 40 * i, Fraction(1, 1000)
            for packet in stream.encode(frame):
                container.mux(packet)
        for packet in stream.encode():
            container.mux(packet)
    take = track_video(path, "face")
    assert take.frames == len(kept)
    np.testing.assert_allclose(take.times, 0.04 * np.array(kept), atol=1e-3)


@pytest.mark.slow
def test_with_two_faces_in_view_the_same_person_is_followed(realdata, tmp_path):
    """Two GRID speakers side by side, each saying their own sentence: the take follows one of
    them in every frame (its lips are that speaker's own, not the other's)."""
    from capture.videoio import write_video

    def clip(name):
        with av.open(str(realdata / "video" / "grid" / name)) as container:
            return [f.to_ndarray(format="bgr24") for f in container.decode(video=0)]

    left, right = clip("bbaf2n.mpg"), clip("lbax4n.mpg")
    pair = track_video(write_video([np.hstack(p) for p in zip(left, right, strict=True)], tmp_path / "two.mp4",
                                   25.0), "face")

    def lips(take):
        return np.linalg.norm(take.marker("LIP_UP_IN") - take.marker("LIP_LOW_IN"), axis=1)

    alone = [lips(track_video(realdata / "video" / "grid" / n, "face")) for n in ("bbaf2n.mpg", "lbax4n.mpg")]
    likeness = [np.corrcoef(lips(pair), own)[0, 1] for own in alone]
    assert pair.meta["faces_found"] == 75 and max(likeness) > 0.95 and min(likeness) < 0.3, likeness
    side = np.sign(pair.marker("NOSE_TIP")[:, 0])
    assert (side == side[0]).all()


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_a_video_without_a_face_is_one_line_and_status_2(tmp_path, capfd):
    """One line on the process's stderr, MediaPipe's native logs included."""
    from capture.videoio import write_video

    frames = [np.full((96, 128, 3), 90 + 3 * i, dtype=np.uint8) for i in range(8)]
    video = write_video(frames, tmp_path / "wall.mp4", 8.0)
    assert main(["track", str(video), "--markers", "face", "-o", str(tmp_path / "t.npz")]) == 2
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and "wall.mp4: no face found in any of its 8 frames" in err, err
    assert not (tmp_path / "t.npz").exists()
    assert main(["map", str(video), "-o", str(tmp_path / "m.csv")]) == 2  # a face was not asked for: the way on
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and "8 frames; a video of dot or ArUco markers is read by `toonface track" in err


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_a_file_stands_in_for_a_camera_in_real_time_and_a_missing_camera_is_named(realdata):
    from capture.face_sources import camera_source

    class Clock:
        now = 0.0

        def __call__(self):
            return self.now

        def sleep(self, seconds):
            self.now += seconds

    clock = Clock()
    source = camera_source(str(realdata / "video" / "grid" / "bbaf2n.mpg"), clock=clock, sleep=clock.sleep)
    assert source.live and source.rate == pytest.approx(25.0)
    times = [frame.t for frame, _ in zip(source.frames, range(4), strict=False)]
    assert times == pytest.approx([0.0, 0.04, 0.08, 0.12])  # each frame when it is due, stamped on arrival
    assert source.meta["clock_start"] == 0.0  # where t is 0 on the clock: a frame's grab, before its tracking
    with pytest.raises(InputError, match="no camera 9"):
        camera_source("9")


def _audio_only(path):
    with av.open(str(path), "w") as container:
        stream = container.add_stream("aac", rate=44100)
        stream.layout = "mono"
        frame = av.AudioFrame.from_ndarray(np.zeros((1, 1024), dtype=np.float32), format="fltp", layout="mono")
        frame.sample_rate, frame.pts = 44100, 0
        container.mux(stream.encode(frame))
        container.mux(stream.encode(None))


def _still(path):
    import cv2

    cv2.imwrite(str(path), np.full((64, 64, 3), 128, np.uint8))


def _cut_short(path):
    from capture.videoio import write_video

    whole = write_video([np.full((64, 64, 3), i, np.uint8) for i in range(0, 200, 10)], path.with_suffix(".whole.mp4"),
                        10.0)
    data = whole.read_bytes()
    path.write_bytes(data[: len(data) // 2])  # the index (moov) is at the end: gone


@pytest.mark.parametrize("name, make, message", [
    ("sound.m4a", _audio_only, "sound.m4a: no video stream in the file"),
    ("face.png", _still, "face.png: a still image (one frame), not a video of a face"),
    ("cut.mp4", _cut_short, "cut.mp4: cannot be decoded: damaged, cut short or not a video"),
])
def test_each_bad_video_says_what_it_is_in_one_line(tmp_path, capfd, name, make, message):
    """One line on the process's own stderr: FFmpeg's complaints inside OpenCV are silenced too."""
    make(tmp_path / name)
    assert main(["track", str(tmp_path / name), "--markers", "face", "-o", str(tmp_path / "t.npz")]) == 2
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and message in err, err
