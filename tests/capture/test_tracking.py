"""Markers from video: ArUco on the real video, dots on generated video with known truth."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from capture import load_markerset, load_take, synthesize
from capture.aruco import detect, make_detector, track_aruco
from capture.dots import DotStyle, DotTracker, find_dots, fit_similarity, sticker_labels, track_dots
from capture.performance import default_performance
from capture.video_tracking import track_video
from capture.videogen import VideoFaults, dot_video, score_tracking
from capture.videoio import frames, probe, write_video
from toonface.cli import main

ARUCO_IDS = {101, 601, 701, 801, 901, 1001}


def _expected_corners(path) -> dict[int, np.ndarray]:
    import yaml  # dask's dependency; expected.yml is OpenCV's YAML 1.0 with a %YAML line

    doc = yaml.safe_load(path.read_text().split("\n", 1)[1])
    return {m["id"]: np.array(m["corners"]) for m in doc["Markers"]}


@pytest.mark.realdata
def test_aruco_test_image_corners_match_the_library_reference(realdata):
    folder = realdata / "video" / "aruco"
    found = detect(make_detector(), cv2.imread(str(folder / "image-test.png")))
    expected = _expected_corners(folder / "expected.yml")
    assert set(found) == set(expected) == ARUCO_IDS
    for marker_id, corners in expected.items():
        assert np.abs(found[marker_id] - corners).max() <= 2.0, marker_id


@pytest.mark.realdata
@pytest.mark.slow  # 6 s: a real video tracked whole
def test_aruco_video_keeps_identities_and_leaves_unseen_markers_nan(realdata, tmp_path):
    out = tmp_path / "aruco.npz"
    assert main(["track", str(realdata / "video" / "aruco" / "video.avi"), "-o", str(out), "--markers", "aruco",
                 "--corners"]) == 0
    take = load_take(out)
    assert take.frames == 145 and take.dims == 2
    assert {int(x.split("_")[1].split(".")[0]) for x in take.labels} == ARUCO_IDS
    seen_601 = take.valid[:, take.labels.index("aruco_601.c0")]
    assert seen_601.sum() == 112
    # Corners of one marker are seen together, and a marker's quad stays a marker-sized quad.
    quads = take.positions[:, :, :2].reshape(145, 6, 4, 2)
    sides = np.linalg.norm(quads - np.roll(quads, 1, axis=2), axis=3)
    assert np.nanmax(sides) < 200 and np.nanmin(sides) > 10


@pytest.mark.realdata
def test_a_face_video_without_markers_says_so(realdata, tmp_path, capsys):
    video = realdata / "video" / "grid" / "bbaf2n.mpg"
    for kind in ("dots", "aruco"):
        out = tmp_path / f"{kind}.npz"
        assert main(["track", str(video), "-o", str(out), "--markers", kind]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "bbaf2n.mpg" in err and "found" in err
        assert not out.exists()


def test_find_dots_is_sub_pixel():
    image = np.full((80, 80, 3), (120, 160, 215), dtype=np.uint8)
    true = np.array([[20.3, 30.7], [55.55, 41.15]])
    for x, y in true:
        cv2.circle(image, (round(x * 16), round(y * 16)), 4 * 16, (205, 90, 25), -1, cv2.LINE_AA, 4)
    image = cv2.GaussianBlur(image, (0, 0), 1.0)
    found = find_dots(image, DotStyle())
    order = np.argsort(found[:, 0])
    assert np.abs(found[order] - true).max() < 0.1


def test_find_dots_survives_a_frame_of_specks():
    image = np.full((480, 640, 3), (120, 160, 215), dtype=np.uint8)
    image[::2, ::2] = (205, 90, 25)  # 76,800 one-pixel blue specks: more labels than 16 bits hold
    cv2.circle(image, (300 * 16, 200 * 16), 5 * 16, (205, 90, 25), -1, cv2.LINE_AA, 4)
    found = find_dots(image, DotStyle())
    assert len(found) == 1 and np.abs(found[0] - [300, 200]).max() < 0.5


def test_two_dots_a_rim_apart_keep_their_own_centres():
    image = np.full((60, 80, 3), (120, 160, 215), dtype=np.uint8)
    true = np.array([[30.0, 30.0], [41.0, 30.0]])  # radius 4: 3 px of skin between them
    for x, y in true:
        cv2.circle(image, (round(x * 16), round(y * 16)), 4 * 16, (205, 90, 25), -1, cv2.LINE_AA, 4)
    found = find_dots(cv2.GaussianBlur(image, (0, 0), 0.8), DotStyle())
    assert np.abs(found[np.argsort(found[:, 0])] - true).max() < 0.15


def test_similarity_fit_recovers_a_known_transform():
    rng = np.random.default_rng(1)
    src = rng.normal(size=(12, 2))
    angle, scale, shift = 0.3, 2.5, np.array([4.0, -1.0])
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    s, r, t = fit_similarity(src, scale * src @ rot.T + shift)
    assert s == pytest.approx(scale) and np.allclose(r, rot) and np.allclose(t, shift)


def test_a_lost_dot_is_carried_a_few_frames_then_nan_then_found_again():
    layout = np.array([[0.0, 0.0], [20.0, 0.0], [0.0, 20.0], [20.0, 20.0]])
    tracker = DotTracker(layout, max_flow_frames=2)
    image = np.zeros((200, 200, 3), dtype=np.uint8)  # flat: flow cannot follow anything
    dots = np.array([[50.0, 150.0], [90.0, 150.0], [50.0, 110.0], [90.0, 110.0]])
    first = tracker.start(dots)
    np.testing.assert_allclose(first, dots)
    assert tracker.mm_per_pixel == pytest.approx(0.5)
    tracker.remember(image)
    rows = [tracker.step(image, dots[1:]) for _ in range(6)]  # dot 0 vanishes
    for k, row in enumerate(rows):
        np.testing.assert_allclose(row[1:], dots[1:])
        assert np.isnan(row[0]).all() or k < 2  # at most max_flow_frames carried
    assert np.isnan(rows[-1][0]).all()
    back = tracker.step(image, dots[::-1].copy())  # reappears; order of detections is irrelevant
    np.testing.assert_allclose(back, dots)


@pytest.fixture(scope="module")
def generated():
    # Front-facing: at ±30° the temple dots cross the outer brows in the picture.
    take = synthesize(rate=30, noise_mm=0.0, performance=default_performance(4, max_turn_deg=20)).take
    truth, images = dot_video(take, seed=2)
    return truth, list(images)


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_generated_dots_are_tracked_with_identities(generated):
    truth, images = generated
    ms = load_markerset("toon32")
    layout = np.array([ms.neutral_of(x)[:2] for x in truth.labels])
    pixels, tracker = track_dots(images, layout)
    score = score_tracking(pixels, truth)
    assert score["median_error_px"] < 0.3
    assert score["swap_frames"] == 0.0
    assert score["found"] > 0.97
    assert tracker.mm_per_pixel == pytest.approx(1 / truth.pixels_per_mm, rel=0.01)


@pytest.mark.slow  # a few seconds: make test runs it
def test_generated_video_file_through_the_track_command(generated, tmp_path):
    truth, images = generated
    video = write_video(images, tmp_path / "dots.mp4", truth.rate)
    take = track_video(video)
    assert take.frames == len(images) and take.dims == 2 and take.rate == pytest.approx(30)
    assert set(take.labels) == set(truth.labels)
    # Millimetres in the marker set's frame: the first (neutral) frame sits on the layout.
    ms = load_markerset("toon32")
    neutral = np.array([ms.neutral_of(x)[:2] for x in take.labels])
    assert np.nanmedian(np.abs(take.positions[0, :, :2] - neutral)) < 1.0


@pytest.mark.slow  # a few seconds: make test runs it
def test_a_video_played_as_a_source_is_the_tracking_loop_in_millimetres(generated, tmp_path):
    """`send`'s video source and `track` run one loop; its pixels become mm about the fitted
    origin, y up (by hand here)."""
    from capture.sources import video_source

    truth, images = generated
    video = write_video(images, tmp_path / "dots.mp4", truth.rate)
    source = video_source(video)
    played = np.stack([f.positions for f in source.frames])
    ms = load_markerset("toon32")
    pixels, tracker = track_dots(frames(probe(video)), np.array([ms.neutral_of(x)[:2] for x in source.labels]))
    scale, (x0, y0) = tracker.mm_per_pixel, tracker.origin
    np.testing.assert_allclose(played[..., 0], (pixels[..., 0] - x0) * scale)
    np.testing.assert_allclose(played[..., 1], (y0 - pixels[..., 1]) * scale)
    assert source.meta["mm_per_pixel"] == scale and (played[..., 2][np.isfinite(played[..., 2])] == 0).all()


def test_faults_switch_off():
    take = synthesize(seconds=1, rate=10, noise_mm=0.0).take
    clean = VideoFaults(blur_sigma=0, noise_sigma=0, lighting=0, jpeg_quality=None, hand=None)
    truth, images = dot_video(take, faults=clean)
    assert truth.visible.all()
    first, second = next(images), next(dot_video(take, faults=clean)[1])
    assert np.array_equal(first, second)  # deterministic
    labels, pixels = track_aruco([first])
    assert labels == () and pixels.shape == (1, 0, 2)


def test_random_dots_are_not_taken_for_the_layout():
    """53 blue blobs scattered over a frame used to 'identify' 29 of 30 markers."""
    ms = load_markerset("toon32")
    layout = np.array([ms.neutral_of(x)[:2] for x in sticker_labels(ms.labels)])
    blobs = np.random.default_rng(1).uniform(0, 640, size=(53, 2))
    with pytest.raises(ValueError, match=r"only \d+ of its 30 markers have a dot where the layout puts them"):
        DotTracker(layout).start(blobs)


def test_dots_on_a_video_without_them_fail_clearly(realdata, tmp_path, capsys):
    video = realdata / "video" / "aruco" / "video.avi"
    assert main(["track", str(video), "-o", str(tmp_path / "t.npz"), "--markers", "dots"]) == 2
    err = capsys.readouterr().err
    assert "cannot identify the toon32 dots on frame 0" in err and err.count("\n") == 1
    assert not (tmp_path / "t.npz").exists()
