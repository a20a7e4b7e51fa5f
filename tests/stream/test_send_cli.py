"""`toonface send` as a person runs it: to several receivers, stopped by --seconds when nothing
arrives, and Ctrl-C ending as a normal end does (issue 44)."""

import dataclasses
import json
import time

import numpy as np
import pytest

import capture.sources
from capture.sources import take_source
from capture.synthetic import synthesize
from capture.takefile import save_take
from stream.playout import Playout
from stream.receiver import StreamReceiver
from toon import MOTOR_CODES, load_track, standard_neutral
from toonface.cli import main
from toonface.send import Follower, build_mapper


@pytest.mark.slow  # two sends: make test runs it (make test-fast stays under a minute)
def test_send_to_two_receivers_reaches_both_and_the_same_one_twice_is_refused(capsys):
    """`send --to A --to B` sent to B alone (click kept the last --to)."""
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral())) as a, \
            StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral())) as b:
        where = [f"{host}:{port}" for host, port in (a.address, b.address)]
        assert main(["send", "synthetic", "--to", where[0], "--to", where[1], "--seconds", "0.5"]) == 0
        assert a.wait_for_packets(10, timeout=10) and b.wait_for_packets(10, timeout=10)
    out = capsys.readouterr().out
    assert f"to {where[0]}:" in out and f"to {where[1]}:" in out
    assert main(["send", "synthetic", "--to", where[0], "--to", where[0]]) == 2
    assert "the same address twice" in capsys.readouterr().err


def test_send_from_a_bridge_nobody_sends_to_stops_after_its_seconds(capsys):
    """`send --vmc PORT --seconds 3` waited for a VMC message for ever."""
    start = time.monotonic()
    assert main(["send", "--vmc", "127.0.0.1:0", "--to", "127.0.0.1:9", "--seconds", "0.5", "--stats"]) == 0
    assert time.monotonic() - start < 5.0
    stats = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert stats["frames"] == 0


def test_ctrl_c_ends_send_with_its_summary_and_stats(monkeypatch, capsys):
    """Ctrl-C printed nothing of --stats."""
    real = capture.sources.paced

    def interrupted(source, clock, sleep):
        for k, frame in enumerate(real(source, clock, lambda s: None)):
            if k == 30:
                raise KeyboardInterrupt
            yield frame

    monkeypatch.setattr("toonface.send.paced", interrupted)
    assert main(["send", "synthetic", "--to", "127.0.0.1:9", "--stats"]) == 0
    captured = capsys.readouterr()
    assert "stopped" in captured.err and "sent 30 frames in 15 packets to 127.0.0.1:9" in captured.out
    assert json.loads(captured.out.strip().splitlines()[-1])["frames"] == 30


@pytest.mark.parametrize("keyed", [False, True])
def test_send_says_whether_the_stream_is_sealed(monkeypatch, capsys, tmp_path, keyed):
    if keyed:
        key = tmp_path / "key"
        key.write_bytes(b"a shared secret of enough length")
        monkeypatch.setenv("TOONFACE_STREAM_KEY", key.read_text())
    assert main(["send", "synthetic", "--to", "127.0.0.1:9", "--seconds", "0.2"]) == 0
    assert ("the stream is not encrypted" in capsys.readouterr().err) != keyed


@pytest.mark.slow  # a second of real-time stream: make test runs it
def test_receive_stats_count_each_frame_drawn_once(capsys):
    """`receive --stats` counted 120 frames a second while it drew 60: with room for several
    performers, the first one's face was looked at twice a frame."""
    import socket
    import threading

    from stream.packets import StreamWriter
    from stream.sender import StreamSender

    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    stop = threading.Event()

    def perform() -> None:
        sender = StreamSender(("127.0.0.1", port), StreamWriter(30.0))
        k = 0
        while not stop.wait(1 / 30):  # a performer at 30 frames a second, in real time
            sender.write(k / 30, standard_neutral())
            k += 1
        sender.close()

    thread = threading.Thread(target=perform, daemon=True)
    thread.start()
    try:
        assert main(["receive", "--listen", f"127.0.0.1:{port}", "--seconds", "2", "--fps", "20"]) == 0
    finally:
        stop.set()
        thread.join(5)
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    shown = sum(summary["frames"].values())
    assert 36 <= shown <= 41  # 40 loops of 50 ms (two seconds at 20 fps), each counted once
    assert summary["frames"]["live"] > 10  # the performer was shown


@pytest.mark.slow  # three sends of an 8 s take, unpaced: make test runs it
def test_send_fills_a_lost_marker_for_max_gap_seconds_and_holds_for_hold_gap(monkeypatch, tmp_path, capsys):
    """`send` filled a lost marker live for 2 s (regressed) and held a paired one 0.5 s, with no way
    to say otherwise, where `map` has --max-gap: a mouth corner lost for 1.5 s while the mouth
    moves follows the truth filled, and drifts from it once it is lost after --max-gap."""
    real = capture.sources.paced
    monkeypatch.setattr("toonface.send.paced", lambda source, clock, sleep: real(source, clock, lambda s: None))
    made = synthesize(seconds=8.0, rate=60.0, seed=4)
    positions = made.take.positions.copy()
    gap = (made.take.times >= 4.0) & (made.take.times < 5.5)
    positions[gap, made.take.labels.index("MOUTH_R")] = np.nan
    take = save_take(dataclasses.replace(made.take, positions=positions), tmp_path / "lost.npz")
    mrh = MOTOR_CODES.index("MRH")
    errors = []
    for options in ([], ["--max-gap", "0.3"]):
        record = tmp_path / f"sent{len(options)}.csv"
        assert main(["send", str(take), "--to", "127.0.0.1:9", "--record", str(record), *options]) == 0
        sent = load_track(record).values
        errors.append(float(np.abs(sent[gap, mrh] - made.motors[gap, mrh]).mean()))
    capsys.readouterr()
    assert errors[0] < 0.015 and errors[1] > 3 * errors[0]  # 0.006 filled; 0.058 lost after 0.3 s
    source = take_source(made.take)
    held = [build_mapper(source, **given).gaps for given in ({}, {"hold_seconds": 0.2}, {"regress_seconds": 0.1})]
    assert [(gaps.regress_seconds, gaps.hold_seconds) for gaps in held] == [(2.0, 0.5), (2.0, 0.2), (0.1, 0.1)]
    assert main(["send", str(take), "--to", "127.0.0.1:9", "--max-gap", "-1"]) == 2
    assert "--max-gap" in capsys.readouterr().err


def test_play_source_fills_and_holds_for_as_long_as_it_is_told():
    """`play --source` maps a performer live as `send` does, but had no --max-gap or --hold-gap:
    its follower filled for 2 s and held for 0.5 whatever was asked (without a performer the two
    are refused: ``tests/toonface/test_cli.py``)."""
    follower = Follower.open("synthetic", standard_neutral(), regress_seconds=0.4, hold_seconds=0.1)
    try:
        assert (follower.mapper.gaps.regress_seconds, follower.mapper.gaps.hold_seconds) == (0.4, 0.1)
    finally:
        follower.source.close()
