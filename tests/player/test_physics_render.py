"""Physics while drawing (issue 43): the same swing at 30 and at 60 frames a second, in a part
of a batch as in the whole, in `play` as in `render`; on every built-in face something swings
after a quick head turn and settles; --no-physics draws without."""

import numpy as np
import pytest

from player.animator import FakeClock
from player.live import LiveSettings, run_live
from player.motion import SecondaryMotion
from player.offline import geometries
from toon import FaceRig, MotorTrack, builtin_faces, load_face, motor_index

RATE = 60.0


def _turn(face, seconds: float = 4.0) -> MotorTrack:
    """Still for half a second, a quick head turn (0.1 s), then still: a 60 Hz track on ``face``."""
    t = np.arange(int(seconds * RATE)) / RATE
    values = np.repeat(face.neutral()[None], len(t), 0)
    hh = motor_index("HH")
    values[:, hh] = np.interp(t, [0.0, 0.5, 0.6, seconds], [0.5, 0.5, 0.8, 0.8])
    values[:, motor_index("MB")] = np.interp(t, [0.0, 1.0, 1.1, seconds], [0.1, 0.1, 0.6, 0.6])
    return MotorTrack(values, RATE)


def _vertices(geometry) -> np.ndarray:
    return np.concatenate([item.vertices for item in geometry.items])


@pytest.mark.parametrize("name", builtin_faces())
def test_something_swings_after_a_quick_head_turn_and_settles(name):
    face = load_face(name)
    assert face.physics, name
    track = _turn(face)
    motion = SecondaryMotion(face, track)
    rests = face.extra_neutral()
    moved = {p: [] for p in motion.physics.params}
    for k in range(track.frames):
        shown = motion.extra_at(k / RATE, track.values[k], {})
        for p in moved:
            moved[p].append(shown[p] - rests[p])
    swing = max(np.abs(v[30:90]).max() for v in moved.values())  # within a second of the turn
    assert swing > 0.05, (name, swing)
    assert all(abs(v[-1]) < 0.01 for v in moved.values()), name  # 3.4 s on: settled


@pytest.mark.parametrize("name", builtin_faces())
def test_30_and_60_frames_a_second_and_a_part_draw_the_same_at_shared_instants(name):
    face = load_face(name)
    track = _turn(face, 2.0)
    rig = FaceRig(face)
    fast = [_vertices(g) for g in geometries(track, rig, 60.0)]
    slow = [_vertices(g) for g in geometries(track, rig, 30.0)]
    for k, drawn in enumerate(slow):
        np.testing.assert_allclose(drawn, fast[2 * k], atol=1e-9)
    part = [_vertices(g) for g in geometries(track, rig, 60.0, start=50, stop=80)]  # starts mid-swing
    for k, drawn in enumerate(part):
        np.testing.assert_allclose(drawn, fast[50 + k], atol=1e-9)
    still = [_vertices(g) for g in geometries(track, rig, 60.0, physics=False)]
    assert max(np.abs(a - b).max() for a, b in zip(fast, still, strict=True)) > 1.0  # physics did move things


def test_play_draws_the_swing_render_draws():
    face = load_face("wizard")
    track = _turn(face, 2.0)
    told: list[tuple[float, dict]] = []
    clock = FakeClock()
    settings = LiveSettings(loop_time=1 / 30, size=(32, 32), samples=1, tcp=None, track=track, repeat=False,
                            seconds=1.9)
    settings.shown.append(lambda t, v, extra=None: told.append((t, dict(extra or {}))))
    run_live(face, settings, clock=clock, sleep=clock.sleep)
    motion = SecondaryMotion(face, track)
    assert len(told) > 50
    for t, extra in told:
        expected = motion.extra_at(t, track.values[min(int(round(t * RATE)), track.frames - 1)], {})
        assert extra["BEARD"] == pytest.approx(expected["BEARD"], abs=1e-9), t
    assert max(abs(extra["BEARD"] - 0.5) for _, extra in told) > 0.05


def test_no_physics_draws_the_face_as_it_stands(tmp_path, capsys):
    from toon import save_track
    from toonface.cli import main

    face = load_face("round")
    save_track(_turn(face, 1.5), tmp_path / "turn.csv")
    for flag, folder in (([], "on"), (["--no-physics"], "off")):
        assert main(["render", str(tmp_path / "turn.csv"), "-o", str(tmp_path / folder), "--face", "round",
                     "--size", "96", "--fps", "20", *flag]) == 0
    from PIL import Image

    def frame(folder, k):
        with Image.open(tmp_path / folder / f"frame_{k:06d}.png") as image:
            return np.asarray(image).astype(int)

    assert np.abs(frame("on", 0) - frame("off", 0)).max() == 0  # before the turn: the same
    assert np.abs(frame("on", 14) - frame("off", 14)).max() > 40  # the fringe swings after it


@pytest.mark.gl
@pytest.mark.parametrize("name", builtin_faces())
def test_the_swing_has_settled_in_the_picture_four_seconds_after_the_turn(name):
    """Issue 66: the lines face's hairs still swung four seconds after a quick head turn (mean
    pixel change 0.125 between 4.7 s and 5 s at 128 px; the other faces 0.001-0.035), though the
    driver's own value had settled: the picture is what has to be still."""
    from itertools import islice

    from player.backends import open_renderer

    face = load_face(name)
    track = _turn(face, 5.2)
    frames = list(islice(geometries(track, FaceRig(face), 30.0), 160))
    with open_renderer((128, 128)) as renderer:
        def drawn(k: int) -> np.ndarray:
            return renderer.render(frames[k]).astype(float)

        swing = max(np.abs(drawn(k + 1) - drawn(k)).mean() for k in range(18, 40, 3))  # after the turn at 0.5 s
        late = np.abs(drawn(150) - drawn(141)).mean()  # 5.0 s against 4.7 s
    assert swing > 0.5, (name, swing)  # it does swing
    assert late < 0.05, (name, late)


def test_the_drivers_inputs_are_the_tracks_own_values_at_and_between_its_samples():
    """What the drivers read at ``t`` is ``np.interp`` of each column, exactly: a frame on a
    sample takes that sample, a frame between two the line between them."""
    face = load_face("classic")
    track = _turn(face, 1.0)
    motion = SecondaryMotion(face, track)
    rows = motion._track_rows(track)
    for t in [*(k / RATE for k in range(track.frames)), 0.2 + 0.3 / RATE, 29.5 / RATE, 0.9999]:
        expected = np.array([np.interp(t, track.times, column) for column in rows.T])
        np.testing.assert_array_equal(motion._track_row(t), expected, err_msg=f"t = {t}")
