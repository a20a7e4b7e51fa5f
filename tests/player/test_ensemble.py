"""Several performers on one screen: two senders through the relay drawn as two faces in one
recorded frame; a quiet one passes to idle, fades out and leaves, the other goes on; seats."""

import cv2
import numpy as np
import pytest

from common import InputError
from player.animator import FakeClock
from player.ensemble import Ensemble, load_seats
from player.live import LiveSettings, run_live
from player.providers import IdleSettings, Providers
from player.sink_choice import open_sink
from stream.packets import StreamWriter
from stream.playout import Playout
from stream.receiver import StreamReceiver
from stream.relay import NetworkFaults, Relay
from stream.sender import StreamSender
from toon import FaceRig, load_face, motor_index
from toon.stage import KEYS_PER_CELL, grid

STILL = Providers(idle=IdleSettings(blink_per_minute=0, breathing_amount=0, saccade_amount=0, sway_amount=0))


def _pose(face, **motors):
    values = face.neutral()
    for code, value in motors.items():
        values[motor_index(code)] = value
    return values


def _same(a, b) -> bool:
    """Two frames alike: the same items, in order, at the same points."""
    return (a.viewbox == b.viewbox and len(a.items) == len(b.items)
            and all(x.name == y.name and np.allclose(x.vertices, y.vertices)
                    for x, y in zip(a.items, b.items, strict=True)))


def test_the_grid_is_near_square_and_fills_the_stage():
    assert grid(1, 512, 256) == [(0, 0, 512, 256)]
    assert grid(2, 512, 256) == [(0, 0, 256, 256), (256, 0, 512, 256)]  # side by side on a wide stage
    four = grid(4, 400, 400)
    assert sorted(four) == sorted([(0, 200, 200, 400), (200, 200, 400, 400), (0, 0, 200, 200), (200, 0, 400, 200)])
    assert four[0] == (0, 200, 200, 400)  # the first at the top left


def test_two_performers_are_placed_each_in_its_cell_and_a_quiet_one_fades_out(tmp_path):
    face = load_face("classic")
    open_mouth, shut = _pose(face, MB=1.0), _pose(face, MB=0.0)
    ensemble = Ensemble(face, (512, 256), STILL, gone_after=5.0, fade_out=1.0)
    one = ensemble.frame([(7, open_mouth, 0.0)], 0.0)
    assert _same(one, FaceRig(face).geometry(open_mouth))  # alone: exactly the single face
    both = ensemble.frame([(7, open_mouth, 0.02), (9, shut, 0.0)], 0.02)
    assert both.viewbox == (0.0, 0.0, 512.0, 256.0)
    single = FaceRig(face).geometry(open_mouth)
    x0, y0, x1, y1 = face.viewbox
    scale = 256 / (x1 - x0)  # a square face into a 256 x 256 cell
    mouth = next(i for i in single.items if i.name == "lower_lip")
    placed = [i for i in both.items if i.name == "lower_lip"]
    np.testing.assert_allclose(placed[0].vertices, (mouth.vertices - [(x0 + x1) / 2, (y0 + y1) / 2]) * scale + 128)
    assert placed[1].vertices[:, 0].min() >= 256  # the second performer in the right cell
    assert len({i.key for i in both.items}) == len(both.items) and max(i.key for i in both.items) < 2 * KEYS_PER_CELL
    # performer 9 goes quiet: idle after 0.3 s, half faded at 5.5 s, gone after 6 s; 7 goes on
    ensemble.frame([(7, open_mouth, 0.0), (9, shut, 5.5)], 5.5)
    faded = next(i for i in reversed(ensemble.frame([(7, open_mouth, 0.0), (9, shut, 5.5)], 5.52).items)
                 if i.fill is not None)
    assert faded.fill[3] == pytest.approx(0.5 * next(i for i in reversed(single.items) if i.fill is not None).fill[3],
                                          abs=0.03)
    assert ensemble.members[9].mixer.who()[motor_index("MB")] == "idle"
    alone = ensemble.frame([(7, open_mouth, 0.0), (9, shut, 6.1)], 6.1)
    assert list(ensemble.members) == [7] and _same(alone, FaceRig(face).geometry(open_mouth))


def test_seats_set_each_performers_face_and_place(tmp_path):
    seats = tmp_path / "seats.toml"
    seats.write_text('format = "toonface.performers/1"\n'
                     '[[performer]]\nid = 3\nface = "wizard"\ncell = [0.5, 0.0, 1.0, 1.0]\n'
                     '[[performer]]\nid = 4\nface = "cat"\ncell = [0.0, 0.0, 0.5, 1.0]\n')
    loaded = load_seats(seats)
    assert [s.stream for s in loaded] == [3, 4] and loaded[0].face == "wizard"
    face = load_face("classic")
    said: list[str] = []
    ensemble = Ensemble(face, (512, 256), STILL, loaded, say=said.append)
    for t in (0.0, 0.1):
        drawn = ensemble.frame([(3, face.neutral(), 0.0), (4, face.neutral(), 0.0), (5, face.neutral(), 0.0)], t)
    hat = [i for i in drawn.items if i.name == "hat"]  # the wizard's, on the right
    assert hat and hat[0].vertices[:, 0].min() >= 256 and 5 not in ensemble.members  # 5 has no seat
    assert ensemble.hidden == {5} and len(said) == 1 and "stream 5 has no seat" in said[0]  # said, once
    seats.write_text('format = "toonface.performers/1"\n[[performer]]\nid = 3\ncell = [0.5, 0.0, 0.2, 1.0]\n')
    with pytest.raises(InputError, match=r"performer\[0\]\.cell"):
        load_seats(seats)


def test_two_senders_through_the_relay_appear_as_two_faces_in_one_recorded_frame(tmp_path):
    from player.backends import open_renderer

    face = load_face("round")
    open_mouth, shut = _pose(face, MB=1.0, BRC=1.0, BLC=1.0), _pose(face, MB=0.0, ERU=0.0, ELU=0.0)

    def playout():
        return Playout(face.neutral())

    with StreamReceiver(("127.0.0.1", 0), playout(), more=playout, newcomer_seconds=0) as receiver, \
            Relay(("127.0.0.1", 0), receiver.address, NetworkFaults(), seed=1) as relay:
        senders = [StreamSender(relay.address, StreamWriter(60.0, stream=stream)) for stream in (11, 22)]
        for k in range(30):  # half a second of each performer, frame by frame
            for sender, values in zip(senders, (open_mouth, shut), strict=True):
                sender.write(k / 60, values)
        for sender in senders:
            sender.close()
        assert receiver.wait_for_streams(2, timeout=10)
        receiver.wait_for_packets(15, timeout=10)
        settled = receiver.clock() + 0.1  # within the half second the frames span, past the jitter buffer
        ensemble = Ensemble(face, (256, 128), STILL)
        clock = FakeClock()
        settings = LiveSettings(loop_time=0.05, size=(256, 128), samples=4, tcp=None, seconds=0.1,
                                providers=STILL, sinks=[open_sink(tmp_path / "frames", 20, (256, 128))],
                                scene=lambda t: ensemble.frame(receiver.performers(settled), t))
        run_live(face, settings, clock=clock, sleep=clock.sleep)
    assert sorted(ensemble.members) == [11, 22] and receiver.other_streams == 0
    recorded = cv2.imread(str(sorted((tmp_path / "frames").glob("*.png"))[-1]))[:, :, ::-1].astype(int)
    with open_renderer((128, 128)) as renderer:  # each performer drawn alone at its cell's size
        alone = [renderer.render(FaceRig(face).geometry(v)).astype(int) for v in (open_mouth, shut)]
    for half, picture in zip((recorded[:, :128], recorded[:, 128:]), alone, strict=True):
        assert np.abs(half - picture).mean() < 1.5  # the same face, pose and place, to the edges' rounding
    assert np.abs(alone[0] - alone[1]).mean() > 5  # and the two performers are told apart


def test_each_performer_is_recorded_to_its_own_file_in_the_order_they_came(tmp_path):
    """`receive --record take.csv` with two senders: the first performer's motors as shown in
    take.csv, the second's in take-2.csv; a lane that never played leaves no file. The summary
    counts each performer's packets."""
    from toon import load_track
    from toonface.outputs import Outputs, PerformerRecordings

    face = load_face("round")
    poses = {11: _pose(face, MB=0.9, BRC=1.0), 22: _pose(face, MB=0.0, ERU=0.1)}
    with Outputs() as outputs:
        recordings = PerformerRecordings(outputs, str(tmp_path / "take.csv"))
        recordings.attach(Playout(face.neutral()))  # made for a sender whose packets never read well

        def playout():
            made = Playout(face.neutral())
            recordings.attach(made)
            return made

        first = Playout(face.neutral())
        recordings.attach(first, first=True)
        with StreamReceiver(("127.0.0.1", 0), first, more=playout, newcomer_seconds=0) as receiver:
            senders = [StreamSender(receiver.address, StreamWriter(60.0, stream=s)) for s in poses]
            for k in range(30):
                for sender, values in zip(senders, poses.values(), strict=True):
                    sender.write(k / 60, values)
            for sender in senders:
                sender.close()
            assert receiver.wait_for_streams(2, timeout=10, packets=15)  # two frames a packet
            starts = []
            for lane in receiver.lanes.values():  # when each stream's first frame is due
                (index, arrived), shown = lane.playout._anchor, lane.playout
                starts.append(arrived - (index - shown._first) / 60 + shown.delay)
            for k in range(60):  # the half second the frames span, at half-frame steps
                receiver.performers(min(starts) + k / 120 + 1e-6)
            order, summary = list(receiver.lanes), receiver.summary()
    assert sorted(summary["performers"]) == [11, 22] and summary["other_streams"] == 0
    for stream, counters in summary["performers"].items():  # each performer's own counters
        assert counters["packets"] == 15 and counters["lost"] == 0 and counters["frames"]["live"] > 0, stream
    assert summary["packets"] == 30 and summary["frames"]["live"] == sum(  # every performer's
        c["frames"]["live"] for c in summary["performers"].values())
    assert recordings.written() == [str(tmp_path / "take.csv"), str(tmp_path / "take-2.csv")]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["take-2.csv", "take.csv"]
    for path, stream in zip(recordings.written(), order, strict=True):
        track = load_track(path)
        assert track.frames >= 25  # every frame shown, at stream time
        tail = track.values[5:25]
        np.testing.assert_allclose(tail, np.tile(poses[stream], (len(tail), 1)), atol=0.006)  # within a wire step


def test_each_performer_s_parameters_are_drawn_on_its_own_face():
    """Two performers on the stage: one tilts its head (HT), the other asks for a cheek puff the
    cat has not got, which its face leaves out (every preset sends it: not said)."""
    ensemble = Ensemble(load_face("cat"), (256, 128))
    neutral = load_face("cat").neutral()
    upright = ensemble.frame([(1, neutral, 0.0, {}), (2, neutral, 0.0, {})], 0.0)
    tilted = ensemble.frame([(1, neutral, 0.0, {"HT": 1.0}), (2, neutral, 0.0, {"CP": 1.0})], 0.1)
    assert ensemble.members[1].extra == {"HT": 1.0} and ensemble.members[2].extra == {}
    first = [item.vertices for item in upright.items][:len(upright.items) // 2]
    moved = [item.vertices for item in tilted.items][:len(tilted.items) // 2]
    assert max(np.abs(a - b).max() for a, b in zip(first, moved, strict=True)) > 10  # the first one's head turned
    second = [item.vertices for item in upright.items][len(upright.items) // 2:]
    still = [item.vertices for item in tilted.items][len(tilted.items) // 2:]
    assert max(np.abs(a - b).max() for a, b in zip(second, still, strict=True)) < 1e-9


def test_each_performer_s_face_swings_on_its_own_frames():
    """Two performers on the stage, the first turning its head quickly: its hair swings behind the
    turn (the classic's physics, on its own frames) and the still one's does not."""
    ensemble = Ensemble(load_face("classic"), (256, 128))
    neutral = load_face("classic").neutral()
    turned = neutral.copy()
    turned[motor_index("HH")] = 0.9
    ensemble.frame([(1, neutral, 0.0, {}), (2, neutral, 0.0, {})], 0.0)
    for k in range(1, 4):
        ensemble.frame([(1, turned, 0.0, {}), (2, neutral, 0.0, {})], k / 30)
    first, second = ensemble.members[1].motion, ensemble.members[2].motion
    assert first is not None and first.moving() and second is not None and not second.moving()
