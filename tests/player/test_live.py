"""The live player: the command language, the sockets, the preview, raw output, and `toonface play`."""

import socket
import subprocess
import sys
import time
import urllib.request

import av
import cv2
import numpy as np
import pytest

from common.address import parse_address
from common.errors import Terminated
from player.animator import Animator, FakeClock
from player.commands import Commands
from player.live import LiveSettings, run_live
from player.preview import FrameBoard, PreviewServer
from player.server import CommandServer, CommandUDPServer, RateLimit, local_port, start
from player.sink_choice import open_sink
from toon import load_expressions, load_face, motor_index, standard_neutral


@pytest.fixture
def commands():
    clock = FakeClock()
    animator = Animator(standard_neutral(), loop_time=0.1)
    return Commands(animator, standard_neutral(), load_expressions(), clock), animator, clock


def test_moves_frames_and_state(commands):
    cmd, animator, _ = commands
    assert cmd.handle("elu 0 500 ERU 0.0 500") == "ok moving 2"
    assert animator.pending() == 10
    animator.tick()
    state = cmd.handle("state")
    assert state.startswith("ok BRL=0.400 ") and "ELU=0.640" in state and state.count("=") == 21
    assert cmd.handle("frame " + " ".join(["0.5"] * 21)) == "ok frame"
    np.testing.assert_allclose(animator.tick(), 0.5)


@pytest.mark.parametrize("line, message", [
    ("", "empty line"),
    ("XYZ 1 100", "unknown motor 'XYZ'"),
    ("ELU 1", "CODE TARGET MS triples"),
    ("quit", "'quit' is not a command; commands: CODE TARGET MS [...] | frame"),  # it said "got 1 words"
    ("stop now", "'stop' is not a command"),
    ("ELU 1.5 100", "target: must be 0..1"),
    ("ELU 1 -5", "milliseconds: must be 0..600000"),
    ("ELU nan 100", "target: must be 0..1"),
    ("ELU 0 100 MB x 100", "target: expected a number, got 'x'"),
    ("frame 1 2 3", "frame needs 21 values"),
    ("play moonwalk", "unknown motion 'moonwalk'"),
    ("ELU 0 500 ELU 1 500", "ELU is named twice"),  # answered "moving 2"
])
def test_a_malformed_line_changes_nothing(commands, line, message):
    cmd, animator, _ = commands
    before = animator.values()
    reply = cmd.handle(line)
    assert reply.startswith("error: ") and message in reply and "\n" not in reply
    assert animator.pending() == 0 and not animator.busy()
    np.testing.assert_array_equal(animator.tick(), before)


def test_standard_motions_are_scheduled_on_the_loops_clock(commands):
    cmd, animator, clock = commands
    clock.now = 2.0
    assert cmd.handle("play blink 200") == "ok playing blink"
    eru = motor_index("ERU")
    assert animator.tick(2.0)[eru] == 0.0  # closes in one 100 ms slice
    assert animator.tick(2.1)[eru] == pytest.approx(0.8)  # and reopens to where it was
    assert cmd.handle("play smile") == "ok playing smile"
    animator.tick(2.2)
    for t in (2.3, 2.4, 2.5, 2.6, 2.7):
        values = animator.tick(t)
    happiness = load_expressions()["happiness"]
    for code, value in happiness.motors.items():
        if code not in ("HH", "HV"):
            assert values[motor_index(code)] == pytest.approx(value)
    names = cmd.handle("motions").split()
    assert names[:5] == ["ok", "smile", "frown", "neutral", "surprise"] and "nod" in names and "talk" in names


def _echo_server(kind, **kw):
    server = kind(("127.0.0.1", 0), lambda line: f"ok got {line}", **kw)
    start(server)
    return server


def test_tcp_server_replies_per_line_refuses_long_lines_and_extra_clients():
    server = _echo_server(CommandServer, max_clients=1)
    try:
        port = local_port(server)
        with socket.create_connection(("127.0.0.1", port), timeout=5) as conn, conn.makefile("rb") as reader:
            conn.sendall(b"state\nELU 0 10\n")
            assert reader.readline() == b"ok got state\n" and reader.readline() == b"ok got ELU 0 10\n"
            conn.sendall(b"x" * 5000 + b"\nstate\n")
            assert reader.readline() == b"error: line longer than 4096 bytes\n"
            assert reader.readline() == b"ok got state\n"
            with socket.create_connection(("127.0.0.1", port), timeout=5) as second:
                assert second.makefile("rb").readline() == b"error: too many connections\n"
        assert _ask_when_free(port, b"ELU 0 ") is None  # a client that vanishes mid-line
        assert _ask_when_free(port, b"state\n") == b"ok got state\n"  # leaves the server serving
    finally:
        server.shutdown(), server.server_close()


def _ask_when_free(port, data, seconds=10.0):
    """Send ``data`` on a fresh connection once the server has a free slot (a closed client's
    slot is freed by the server's thread a moment later); the first reply line, or None."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        with socket.create_connection(("127.0.0.1", port), timeout=5) as conn:
            conn.sendall(data)
            if not data.endswith(b"\n"):
                return None
            reply = conn.makefile("rb").readline()
            if reply != b"error: too many connections\n":
                return reply
    raise AssertionError("no free slot")


def test_udp_server_answers_each_line_of_a_datagram_and_rate_limits():
    server = _echo_server(CommandUDPServer, rate=1.0, burst=2)
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            sock.settimeout(5)
            sock.sendto(b"a\nb\nc\n", ("127.0.0.1", local_port(server)))
            replies = sock.recv(4096).decode().splitlines()
        assert replies[:2] == ["ok got a", "ok got b"] and replies[2].startswith("error: more than 1 commands")
    finally:
        server.shutdown(), server.server_close()


def test_rate_limit_refills_with_time_and_addresses_parse():
    clock = FakeClock()
    limit = RateLimit(10.0, 2, clock)
    assert [limit.allow() for _ in range(3)] == [True, True, False]
    clock.now = 0.1
    assert limit.allow() and not limit.allow()
    assert parse_address("7000", 1) == ("127.0.0.1", 7000)
    assert parse_address("0.0.0.0:80", 1) == ("0.0.0.0", 80)
    with pytest.raises(ValueError, match="port must be"):
        parse_address(":70000", 1)


def test_preview_serves_the_newest_frame_and_an_mjpeg_stream():
    board = FrameBoard()
    server = PreviewServer(("127.0.0.1", 0), board)
    start(server)
    try:
        base = f"http://127.0.0.1:{local_port(server)}"
        frame = np.zeros((32, 48, 3), np.uint8)
        frame[:, :, 0] = 200
        board.post(frame)
        jpeg = urllib.request.urlopen(base + "/frame.jpg", timeout=5).read()
        picture = cv2.imdecode(np.frombuffer(jpeg, np.uint8), cv2.IMREAD_COLOR)
        assert picture.shape == (32, 48, 3) and abs(int(picture[..., 2].mean()) - 200) < 4  # red, in BGR
        green = np.zeros_like(frame)
        green[:, :, 1] = 200
        board.post(green)  # no viewer is streaming: the newest frame is still the one served
        jpeg = urllib.request.urlopen(base + "/frame.jpg", timeout=5).read()
        assert abs(int(cv2.imdecode(np.frombuffer(jpeg, np.uint8), cv2.IMREAD_COLOR)[..., 1].mean()) - 200) < 4
        assert b"/stream" in urllib.request.urlopen(base + "/", timeout=5).read()
        stream = urllib.request.urlopen(base + "/stream", timeout=5)
        assert stream.headers["Content-Type"].startswith("multipart/x-mixed-replace")
        board.post(frame)
        assert stream.readline().startswith(b"--toonfaceframe")
        stream.close()
    finally:
        server.stop()


@pytest.mark.slow  # a few seconds; make test runs it (make test-fast stays under a minute)
def test_render_writes_raw_rgb_to_standard_output(tmp_path):
    track = tmp_path / "m.csv"
    rows = ["time," + ",".join(__import__("toon").MOTOR_CODES)] + [
        f"{i / 10}," + ",".join(f"{v:g}" for v in standard_neutral()) for i in range(5)]
    track.write_text("\n".join(rows) + "\n")
    result = subprocess.run([sys.executable, "-m", "toonface", "render", str(track), "-o", "-", "--size", "32x16"],
                            capture_output=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert len(result.stdout) == 5 * 32 * 16 * 3 and b"wrote -" in result.stderr


@pytest.mark.slow
def test_toonface_play_answers_commands_and_the_frames_follow(tmp_path):
    frames = tmp_path / "frames"
    proc = subprocess.Popen([sys.executable, "-m", "toonface", "play", "--listen", "127.0.0.1:0", "--size", "96",
                             "--loop-ms", "40", "--seconds", "3", "-o", str(frames)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = proc.stdout.readline()
        assert first.startswith("tcp 127.0.0.1:"), first + proc.stderr.read()
        port = int(first.split(":")[-1])
        with socket.create_connection(("127.0.0.1", port), timeout=10) as conn, conn.makefile("r") as reader:
            conn.sendall(b"bogus 1 2\n")
            assert reader.readline().startswith("error: unknown motor 'bogus'")
            conn.sendall(b"MB 1 0 ERU 0 0 ELU 0 0\n")
            assert reader.readline() == "ok moving 3\n"
            deadline = time.monotonic() + 20
            while time.monotonic() < deadline:  # wait for the loop to carry the move out
                conn.sendall(b"state\n")
                if "MB=1.000" in reader.readline():
                    break
            else:
                pytest.fail("the motors never moved")
        out, err = proc.communicate(timeout=60)  # it stops by itself after 3 s of loops
        assert proc.returncode == 0, err
        assert "stopped after" in out
    finally:
        if proc.poll() is None:
            proc.kill()
    pngs = sorted(frames.glob("frame_*.png"))
    assert 60 <= len(pngs) <= 76  # 75 loops of 40 ms
    first_frame, last_frame = cv2.imread(str(pngs[0])), cv2.imread(str(pngs[-1]))
    assert np.abs(first_frame.astype(int) - last_frame.astype(int)).sum() > 1000  # the mouth opened, eyes shut


@pytest.mark.gl
def test_a_player_that_cannot_keep_up_drops_frames_and_its_video_keeps_real_time(tmp_path):
    """`receive` at 60 fps on a slow machine recorded 8.75 s of performance into 4.95 s of video:
    now drawing that takes 2.5 frame times drops frames and the MP4 still lasts the run."""
    clock = FakeClock()

    class SlowSink:
        def __init__(self, sink):
            self.sink = sink

        def write(self, frame):
            self.sink.write(frame)
            clock.sleep(2.5 / 60)  # encoding this frame took 2.5 frame times

        def skip(self, frames):
            self.sink.skip(frames)

        def close(self):
            self.sink.close()

        def abort(self):
            self.sink.abort()

    settings = LiveSettings(loop_time=1 / 60, size=(64, 64), samples=1, tcp=None, seconds=2.0,
                            sinks=[SlowSink(open_sink(tmp_path / "live.mp4", 60, (64, 64)))],
                            source=lambda t: np.full(21, 0.5))
    report = run_live(load_face("classic"), settings, clock=clock, sleep=clock.sleep)
    assert clock() == pytest.approx(2.0, abs=0.05)  # the run took its two seconds (it used to take 5)
    assert report.loops + report.dropped == 120 and 35 <= report.loops <= 50
    assert "dropped" in report.summary(1 / 60)
    with av.open(str(tmp_path / "live.mp4")) as c:
        assert float(c.duration / av.time_base) == pytest.approx(2.0, abs=0.05)
        assert len(list(c.decode(video=0))) == report.loops


def test_a_recording_holds_dropped_slots_and_clips_stray_values(tmp_path):
    from toon import load_track
    from toon.recording import MotorRecorder

    recorder = MotorRecorder(tmp_path / "shown.csv", 10.0)
    for t, value in [(0.0, 0.2), (0.1, 0.4), (0.3, 1.0000001)]:
        recorder.write(t, np.full(21, value))
    recorder.close()
    track = load_track(recorder.written)
    assert track.frames == 4 and track.rate == 10.0
    assert track.values[:, 0] == pytest.approx([0.2, 0.4, 0.4, 1.0])
    nothing = MotorRecorder(tmp_path / "none.npz", 10.0)
    nothing.write(0.0, np.zeros(21))
    nothing.abort()
    nothing.close()
    assert nothing.written is None and not (tmp_path / "none.npz").exists()


@pytest.mark.gl
def test_sigterm_stops_a_live_player_and_keeps_its_recording(tmp_path):
    calls = []

    def source(t):
        calls.append(t)
        if len(calls) == 30:
            raise Terminated()  # what the command's SIGTERM handler raises
        return np.full(21, 0.5)

    clock = FakeClock()
    settings = LiveSettings(loop_time=1 / 30, size=(32, 32), samples=1, tcp=None, source=source,
                            sinks=[open_sink(tmp_path / "live.mp4", 30, (32, 32))])
    report = run_live(load_face("classic"), settings, clock=clock, sleep=clock.sleep)
    assert report.loops == 29
    with av.open(str(tmp_path / "live.mp4")) as c:
        assert len(list(c.decode(video=0))) == 29
    assert [p.name for p in tmp_path.iterdir()] == ["live.mp4"]


def test_an_explicit_move_replaces_what_a_running_motion_had_pending(commands):
    """`HV 0 200` during `play nod 1000` reached 0.26, then the nod took HV back to 0.5."""
    cmd, animator, clock = commands
    hv = motor_index("HV")
    assert cmd.handle("play nod 1000") == "ok playing nod"
    t = 0.0
    for _ in range(2):
        animator.tick(t)
        t += 0.1
    assert cmd.handle("HV 0 200") == "ok moving 1"
    seen = []
    for _ in range(15):
        seen.append(animator.tick(t)[hv])
        t += 0.1
    assert seen[1] == pytest.approx(0.0) and max(seen[1:]) == pytest.approx(0.0)  # and it stays there
    assert not animator.busy()
    # other motors' scheduled steps are untouched by a command that does not name them
    assert cmd.handle("play shake 1000") == "ok playing shake"
    assert cmd.handle("HV 1 100") == "ok moving 1"
    assert animator.busy() and animator.pending("HV") == 1
