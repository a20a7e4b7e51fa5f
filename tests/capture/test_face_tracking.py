"""Faces without markers: the one OpenCV, the model and its canonical face, real talking-head
clips tracked into takes whose jaw follows the clip's own sound, and clear errors."""

from __future__ import annotations

import importlib.metadata
from itertools import pairwise

import av
import numpy as np
import pytest

from capture.face_landmarks import BLENDSHAPES, LANDMARKS, canonical_face, model_path
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


@pytest.mark.parametrize("clip", ["bbaf2n.mpg", "lbax4n.mpg"])
def test_a_real_talking_face_is_found_in_every_frame_and_its_lips_stop_when_its_voice_does(realdata, clip):
    """GRID clips speak six words and end in silence: the lips travel while the clip's own sound
    is on and rest once it has stopped; the mapped jaw opens while it speaks."""
    from mapping import map_take

    path = realdata / "video" / "grid" / clip
    take = track_video(path, "face")
    assert take.frames == 75 and take.meta["faces_found"] == 75 and take.dims == 3
    assert take.labels == tuple(LANDMARKS) and take.channel_names == BLENDSHAPES
    assert np.isfinite(take.channels).all() and 0 <= take.channels.min() and take.channels.max() <= 1
    gap = np.linalg.norm(take.positions[:, take.index("LIP_UP_IN")] - take.positions[:, take.index("LIP_LOW_IN")],
                         axis=1)
    loud = _speech_envelope(path, take.times, take.meta["start_time"])
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


def test_a_video_without_a_face_is_one_line_and_status_2(tmp_path, capfd):
    """One line on the process's stderr, MediaPipe's native logs included."""
    from capture.videoio import write_video

    frames = [np.full((96, 128, 3), 90 + 3 * i, dtype=np.uint8) for i in range(8)]
    video = write_video(frames, tmp_path / "wall.mp4", 8.0)
    assert main(["track", str(video), "--markers", "face", "-o", str(tmp_path / "t.npz")]) == 2
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and "wall.mp4: no face found in any of its 8 frames" in err, err
    assert not (tmp_path / "t.npz").exists()


@pytest.mark.gl
@pytest.mark.slow
def test_a_talking_head_video_becomes_a_cartoon_with_its_own_sound(realdata, tmp_path):
    source = realdata / "video" / "grid" / "bbaf2n.mpg"
    out = tmp_path / "cartoon.mp4"
    assert main(["retarget", str(source), "-o", str(out), "--face", "round", "--size", "64"]) == 0
    with av.open(str(out)) as made:
        video, audio = made.streams.video[0], made.streams.audio[0]
        assert audio.codec_context.name == "aac" and video.frames == 75
        seconds = float(video.duration * video.time_base)
        ours = np.concatenate([f.to_ndarray().mean(axis=0) for f in made.decode(audio)])  # fltp, in [-1, 1]
    assert seconds == pytest.approx(3.0, abs=0.05)
    assert len(ours) / 44100 == pytest.approx(seconds, abs=0.06)  # the sound lasts as long as the picture
    with av.open(str(source)) as original:  # s16p
        theirs = np.concatenate([f.to_ndarray().astype(float).mean(axis=0) / 32768 for f in original.decode(audio=0)])
    window = 1764  # 40 ms at 44.1 kHz: the voice itself, not silence, at its own loudness
    loudest = [max(np.sqrt(np.mean(x[i:i + window] ** 2)) for i in range(0, len(x) - window, window))
               for x in (ours, theirs)]
    assert loudest[0] == pytest.approx(loudest[1], rel=0.2)
    assert not list(tmp_path.glob(".*"))  # the picture-only file is gone


@pytest.mark.gl
@pytest.mark.slow
@pytest.mark.parametrize("name", ["cat", "classic", "lines", "round", "wizard"])
def test_every_built_in_face_speaks_with_the_clip_s_own_sound(realdata, tmp_path, ctx, name):
    """Each face's MP4 has the clip's sound for as long as its picture, and its mouth (the
    pixels that differ between the face at rest and with its mouth open, MB = 1) is open while
    the performer speaks (frame 37) and shut in the silences before and after (frames 5, 70)."""
    from player import Renderer
    from toon import FaceRig, builtin_faces, load_face, motor_index

    assert name in builtin_faces()
    out = tmp_path / f"{name}.mp4"
    assert main(["retarget", str(realdata / "video" / "grid" / "bbaf2n.mpg"), "-o", str(out), "--face", name,
                 "--size", "64"]) == 0
    with av.open(str(out)) as made:
        video, audio = made.streams.video[0], made.streams.audio[0]
        assert audio.codec_context.name == "aac" and video.frames == 75
        samples = sum(f.samples for f in made.decode(audio))
        assert samples / audio.rate == pytest.approx(3.0, abs=0.06)
        made.seek(0)
        frames = np.array([f.to_ndarray(format="rgb24").astype(float) for f in made.decode(video=0)])
    face = load_face(name)
    rig, pose = FaceRig(face), face.neutral().copy()
    with Renderer(ctx, (64, 64), samples=0) as renderer:
        shut = renderer.render(rig.geometry(pose))
        pose[motor_index("MB")] = 1.0
        wide = renderer.render(rig.geometry(pose))
    mouth = np.any(shut != wide, axis=2)
    assert mouth.sum() > 20

    def change(a, b):
        return np.abs(frames[a] - frames[b])[mouth].mean()

    assert change(37, 70) > 3 * change(5, 70) and change(37, 70) > 20, (change(37, 70), change(5, 70))


@pytest.mark.slow
def test_a_video_played_as_a_camera_drives_send_to_receive_live(realdata, tmp_path):
    """No camera exists here: `send camera:FILE` reads the file as a camera would deliver it (in
    real time, nothing waiting for it), learns the performer's ranges as it runs, and the
    receiving end records what was sent within the wire's quantisation step."""
    from mapping import load_profile
    from stream.packets import StreamWriter
    from stream.playout import Playout
    from stream.receiver import StreamReceiver
    from toon import load_track, standard_neutral
    from toon.recording import MotorRecorder

    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    recorded = MotorRecorder(tmp_path / "received.csv", 25.0)
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral())) as receiver:
        receiver.playout.shown = recorded.write
        host, port = receiver.address
        assert main(["send", f"camera:{clip}", "--to", f"{host}:{port}", "--record", str(tmp_path / "sent.csv"),
                     "--save-profile", str(tmp_path / "learned.toml")]) == 0
        sent = load_track(tmp_path / "sent.csv")
        assert receiver.wait_for_packets(-(-sent.frames // 2), timeout=10)  # two frames a packet, the last maybe one
        playout = receiver.playout
        start = playout._anchor[1] - (playout._anchor[0] - playout._first) / 25.0 + playout.delay
        for k in range(2 * sent.frames + 10):
            receiver.values_at(start + k / 50.0 + 1e-6)
    recorded.close()
    received = load_track(recorded.written)
    assert sent.frames == 75 and received.frames >= 75 and receiver.reader.lost == 0
    assert np.abs(received.values[:75] - sent.values).max() <= 0.5 / StreamWriter(25.0).steps + 1e-9
    assert np.ptp(sent.values[:, 18]) > 0.3  # the jaw moved on the stream, from ranges learned as it ran
    learned = load_profile(tmp_path / "learned.toml")  # kept for next time (--profile)
    lid = learned.sources["distance(LID_R_UP,LID_R_LOW)"]
    assert learned.markerset == "face" and lid.neutral - lid.low > 4.0  # the blink widened it past its start


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
    with pytest.raises(InputError, match="no camera 9"):
        camera_source("9")


@pytest.mark.slow
def test_a_real_blink_closes_the_characters_eyes_fully_and_the_pupils_hold(realdata, monkeypatch):
    """bbaf2n blinks twice near 2 s: the lid gap falls to a tenth of its open width, and the
    mapped upper lids reach closed (0) on both sides, each staying open elsewhere. The irises
    are not reported behind the lids, so the pupils hold; reported (as the model places them),
    they would drop with the lids."""
    from mapping import map_take
    from toon import motor_index

    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    take = track_video(clip, "face")

    def gap(a, b):
        return np.linalg.norm(take.positions[:, take.index(a)] - take.positions[:, take.index(b)], axis=1)

    ratio = gap("LID_R_UP", "LID_R_LOW") / gap("EYE_R_IN", "EYE_R_OUT")
    assert ratio.min() < 0.1 * np.median(ratio) and np.median(ratio) > 0.25
    blink = int(np.argmin(ratio))
    assert 40 <= blink <= 55
    assert np.isnan(take.positions[blink, take.index("PUPIL_R")]).all()
    motors = map_take(take).values
    for lid in ("ERU", "ELU"):
        assert motors[blink - 2:blink + 3, motor_index(lid)].min() < 0.05
        assert np.median(motors[:, motor_index(lid)]) > 0.5
    pupils = [motor_index(code) for code in ("PRV", "PLV")]
    before = motors[30:40, pupils].mean(axis=0)
    assert np.abs(motors[blink - 3:blink + 4, pupils] - before).max() < 0.03
    monkeypatch.setattr("capture.face_landmarks.IRIS_HIDDEN_RATIO", -1.0)
    monkeypatch.setattr("capture.face_landmarks.IRIS_HIDDEN_SHARE", 0.0)
    seen_through = map_take(track_video(clip, "face")).values
    assert np.abs(seen_through[blink - 3:blink + 4, pupils] - before).max() > 0.05


def _winking(realdata, path):
    """bbaf2n's first 41 frames, then frame 40 with the performer's left eye taken from frame 52
    (mid-blink; the box is its landmarks 263, 362, 386, 374 and the brow above, 6 px around) for
    8 frames, then frame 40 for 10: a real wink, made of real pixels."""
    from capture.videoio import write_video

    with av.open(str(realdata / "video" / "grid" / "bbaf2n.mpg")) as container:
        images = [f.to_ndarray(format="bgr24") for f in container.decode(video=0)]  # as write_video takes them
    wink = images[40].copy()
    wink[129:167, 161:203] = images[52][129:167, 161:203]
    return write_video(images[:41] + [wink] * 8 + [images[40]] * 10, path, 25.0)


def test_a_wink_closes_one_eye_and_leaves_the_other_open(realdata, tmp_path):
    """The tracker sees a pair of eyes as one: on a wink it drags the open eye part of the way
    shut and closes the winking one only part of the way. The face preset's [eyes] pair shuts
    the one and keeps the other at its rest, and the pupils do not move."""
    from mapping import map_take
    from toon import motor_index

    take = track_video(_winking(realdata, tmp_path / "wink.mp4"), "face")

    def opening(side):
        lids = np.linalg.norm(take.marker(f"LID_{side}_UP") - take.marker(f"LID_{side}_LOW"), axis=1)
        return lids / np.linalg.norm(take.marker(f"EYE_{side}_IN") - take.marker(f"EYE_{side}_OUT"), axis=1)

    right, left = opening("R"), opening("L")
    winking = slice(43, 48)
    assert right[winking].max() < 0.9 * right[35:41].mean()  # the open eye dragged
    assert left[winking].min() > 0.2 * left[35:41].mean()  # the winking one not shut
    motors = map_take(take).values
    eru, elu = motor_index("ERU"), motor_index("ELU")
    assert motors[winking, elu].max() < 0.05
    assert motors[winking, eru].min() > motors[35:41, eru].mean() - 0.02
    for code in ("PRH", "PRV", "PLH", "PLV"):
        pupil = motor_index(code)
        assert np.abs(motors[winking, pupil] - motors[35:41, pupil].mean()).max() < 0.03, code


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


@pytest.mark.gl
@pytest.mark.slow
def test_side_by_side_puts_the_performers_own_frame_left_of_the_cartoon(realdata, tmp_path, capsys):
    import cv2

    source = realdata / "video" / "grid" / "bbaf2n.mpg"
    out = tmp_path / "both.mp4"
    assert main(["retarget", str(source), "-o", str(out), "--face", "round", "--size", "64", "--side-by-side"]) == 0
    with av.open(str(out)) as made, av.open(str(source)) as original:
        ours = [f.to_ndarray(format="rgb24") for f in made.decode(video=0)]
        theirs = [f.to_ndarray(format="rgb24") for f in original.decode(video=0)]
    assert len(ours) == 75 and ours[0].shape == (64, 80 + 64, 3)  # 360x288 scaled to height 64: 80 wide
    for i in (0, 36, 74):  # the same moment, within what H.264 keeps of it
        expected = cv2.resize(theirs[i], (80, 64), interpolation=cv2.INTER_AREA).astype(int)
        assert np.abs(ours[i][:, :80].astype(int) - expected).mean() < 6
    assert np.abs(ours[36][:, :80].astype(int) - ours[0][:, :80]).mean() > 1  # it moves with the clip
    take = tmp_path / "take.npz"
    from capture import save_take, synthesize

    save_take(synthesize(seconds=1.0, rate=30.0).take, take)
    capsys.readouterr()
    assert main(["retarget", str(take), "-o", str(out), "--side-by-side"]) == 2
    assert "needs a video TAKE" in capsys.readouterr().err


@pytest.mark.gl
@pytest.mark.slow
def test_play_follows_a_camera_live(realdata, tmp_path, capsys):
    """`play --camera FILE` (the same as --source camera:FILE): the performer's face, tracked and
    mapped in a thread, drives the local player; the frames move with the speech and the player
    keeps its own loop time."""
    import cv2

    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    frames = tmp_path / "frames"
    assert main(["play", "--listen", "off", "--camera", str(clip), "--seconds", "3.2", "--size", "64",
                 "-o", str(frames)]) == 0
    images = [cv2.imread(str(p)).astype(int) for p in sorted(frames.glob("frame_*.png"))]
    assert 70 <= len(images) <= 82  # 80 loops of 40 ms, some maybe dropped
    change = [np.abs(image - images[0]).mean() for image in images]
    assert max(change[:20]) < 0.5 and max(change[30:60]) > 2.0  # at rest during the first second, then speaking
    assert main(["play", "--listen", "off", "--source", "camera:9", "--seconds", "1"]) == 2
    assert "no camera 9" in capsys.readouterr().err
    assert main(["play", "--listen", "off", "--camera", "0", "--source", "synthetic"]) == 2
    assert "give --camera or --source, not both" in capsys.readouterr().err
