"""The stream against people on the path and against silence: sealed packets, replays refused
whenever they come, newcomers capped without a key, and live warnings at both ends (issue 44)."""

import socket

import numpy as np
from motor_streams import RATE, packets, smooth_motion

from stream.framing import ACK, LONG, Header, seal
from stream.health import REFUSED_SECONDS, SILENT_SECONDS
from stream.packets import StreamWriter
from stream.playout import Playout
from stream.reader import StreamReader
from stream.receiver import StreamReceiver
from stream.sender import StreamSender
from stream.wire import DEFAULT_STEPS
from toon import standard_neutral

KEY = b"a shared secret of enough length"


class Clock:
    """A clock the test moves."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_a_captured_run_replayed_after_the_sender_stopped_is_refused_and_a_restart_is_not():
    """A reader took any new numbering after 2 s idle, so a run captured off the path and sent
    again later played again."""
    _, captured = packets(smooth_motion(40), key=KEY)
    reader = StreamReader(KEY)
    shown = [f for i, d in enumerate(captured) for f in reader.read(d, i / 30)]
    assert len(shown) == len(captured)
    for i, datagram in enumerate(captured):  # the whole run again, 10 s later
        assert reader.read(datagram, 10.0 + i / 30) == []
    longs = sum(d[0] & LONG != 0 for d in captured)  # refused as replays; the short ones have nothing to stand on
    assert reader.dropped["replay"] == longs >= 1 and reader.dropped["unanchored"] == len(captured) - longs
    restarted = StreamWriter(RATE, key=KEY, first_sequence=1 << 20)  # a new run numbers on from elsewhere
    assert reader.read(restarted.push(standard_neutral(), 0.0) or restarted.flush(), 20.0)


def test_without_a_key_new_performers_come_at_most_one_a_second():
    """Replayed packets under fresh stream ids made 7 phantom performers in one run."""
    clock = Clock()
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), clock=clock,
                        more=lambda: Playout(standard_neutral()), max_streams=8) as receiver:
        def burst(t: float, ids: range) -> None:
            clock.now = t
            for stream in ids:
                receiver.feed(StreamWriter(RATE, stream=stream, frames_per_packet=1).push(standard_neutral(), t))

        burst(0.0, range(1, 8))
        assert sorted(receiver.lanes) == [1] and receiver.refused_newcomers == 6
        burst(0.5, range(2, 8))
        assert sorted(receiver.lanes) == [1]
        burst(1.01, range(2, 8))
        assert sorted(receiver.lanes) == [1, 2] and receiver.summary()["refused_newcomers"] == 17
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), KEY, clock=clock,
                        more=lambda: Playout(standard_neutral()), max_streams=8) as keyed:
        for stream in range(1, 5):  # with a key only its holders make packets: no cap
            keyed.feed(StreamWriter(RATE, stream=stream, frames_per_packet=1, key=KEY).push(standard_neutral(), 0.0))
        assert sorted(keyed.lanes) == [1, 2, 3, 4] and keyed.refused_newcomers == 0


def test_a_receiver_says_within_seconds_that_packets_do_not_open_and_when_they_do():
    said: list[str] = []
    clock = Clock()
    wrong = StreamWriter(RATE, key=b"another secret of enough length!", frames_per_packet=1)
    right = StreamWriter(RATE, key=KEY, frames_per_packet=1)
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), KEY, clock=clock, say=said.append) as receiver:
        for k in range(80):  # two seconds of packets under another key
            clock.now = k / 40
            receiver.feed(wrong.push(standard_neutral(), clock.now))
            assert bool(said) == (clock.now >= REFUSED_SECONDS)
        assert len(said) == 1 and "failed authentication" in said[0] and "key" in said[0]
        clock.now = 2.1
        receiver.feed(right.push(standard_neutral(), 2.1))
        assert len(said) == 2 and "flows" in said[1]
        receiver.feed(right.push(standard_neutral(), 2.2))
        assert len(said) == 2  # each said once


def test_a_sender_nobody_answers_says_so_after_three_seconds_and_again_when_answered():
    said: list[str] = []
    clock = Clock()
    sender = StreamSender(("127.0.0.1", 9), StreamWriter(RATE, frames_per_packet=1), clock=clock, say=said.append)
    try:
        for k in range(240):  # 4 s unanswered
            clock.now = k / 60
            sender.write(clock.now, standard_neutral())
            assert bool(said) == (clock.now >= SILENT_SECONDS)
        assert len(said) == 1 and "nobody is receiving on 127.0.0.1:9, or the key differs" in said[0]
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as receiver:  # an acknowledgement comes
            ack = seal(Header(ACK, 0, sender.writer.frame - 1, 0, 0, DEFAULT_STEPS, 1.0), b"", None)
            receiver.sendto(ack, ("127.0.0.1", sender.sock.getsockname()[1]))
            for _ in range(200):
                clock.now += 1 / 60
                sender.write(clock.now, standard_neutral())
                if len(said) == 2:
                    break
        assert len(said) == 2 and "answers" in said[1] and sender.acks == 1
    finally:
        sender.close()


def test_a_sealed_stream_plays_as_the_open_one_does():
    values = smooth_motion(60)
    shown = {}
    for key in (None, KEY):
        _, datagrams = packets(values, key=key)
        reader = StreamReader(key)
        shown[key] = np.concatenate([f.values for i, d in enumerate(datagrams) for f in reader.read(d, i / 30)])
    assert np.array_equal(shown[None], shown[KEY]) and np.abs(shown[KEY] - values).max() <= 0.5 / 100 + 1e-9


def test_a_stream_that_never_opens_is_asked_for_keyframes_less_and_less_often():
    """Issue 70: under another key the receiver asked for a keyframe for every packet it could not
    open (359 requests; acknowledgements grew to 7.9 kbit/s against 9.5 forward)."""
    clock = Clock()
    wrong = StreamWriter(RATE, key=b"another secret of enough length!", frames_per_packet=1)
    right = StreamWriter(RATE, key=KEY, frames_per_packet=1)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sender, \
            StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), KEY, clock=clock) as receiver:
        sender.bind(("127.0.0.1", 0))
        where = sender.getsockname()
        for k in range(600):  # ten seconds of packets under another key, 60 a second
            clock.now = k / 60
            receiver.feed(wrong.push(standard_neutral(), clock.now), where)
        asked = receiver.requests
        for k in range(60):  # then a second of the right key's: asked as often as before once one opens
            clock.now = 10 + k / 60
            receiver.feed(right.push(standard_neutral(), clock.now), where)
    # 0.05, 0.1, ... 1.6 s, then every 2 s: 11 in ten seconds, where it was one each 0.05 s (200)
    assert 8 <= asked <= 12
    assert receiver.reader.packets > 50
