"""The telepresence stream: arithmetic coding, the wire format, the reader's defences, the jitter
buffer and concealment, the fault relay, the live mapper, and the pieces over real sockets."""

import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from capture import load_take, synthesize
from capture.performance import default_performance
from capture.sources import take_source
from stream.packets import LOSS_SECONDS, StreamWriter, is_key_request, key_request, read_ack
from stream.playout import Playout
from stream.rangecode import Decoder, Encoder, Model
from stream.reader import StreamReader
from stream.receiver import StreamReceiver
from stream.relay import FaultPlan, NetworkFaults, Relay
from stream.sender import StreamSender
from stream.wire import HEADER, MAX_PACKET, bridge, quantise
from toon import motor_index, standard_neutral
from toonface import truth_track
from toonface.cli import main
from toonface.pipeline import map_onto_face
from toonface.send import build_mapper, run_sender

RATE = 60.0


def smooth_motion(frames: int, seed: int = 0) -> np.ndarray:
    """Smooth random motor curves ``(frames, 21)`` in [0, 1]."""
    rng = np.random.default_rng(seed)
    t = np.arange(frames)[:, None] / RATE
    return np.clip(0.5 + 0.3 * np.sin(2 * np.pi * rng.uniform(0.2, 2, 21) * t + rng.uniform(0, 6, 21))
                   + rng.normal(0, 0.003, (frames, 21)), 0, 1)


def packets(values: np.ndarray, **options) -> tuple[StreamWriter, list[bytes]]:
    writer = StreamWriter(RATE, first_sequence=0, **options)
    out = [d for i, row in enumerate(values) if (d := writer.push(row, i / RATE)) is not None]
    last = writer.flush()
    return writer, out + ([last] if last else [])


@given(st.lists(st.integers(0, 6), min_size=0, max_size=60), st.integers(0, 3))
@settings(max_examples=60, deadline=None)
def test_arithmetic_coding_round_trips_near_the_information_content(symbols, which):
    models = [Model([1, 2, 3, 4, 5, 6, 7]), Model.laplace(7, 3, 0.3), Model([50, 1, 1, 1, 1, 1, 50]), Model([1] * 7)]
    model = models[which]
    encoder = Encoder()
    for s in symbols:
        encoder.encode(s, model)
    data = encoder.finish()
    decoder = Decoder(data)
    assert [decoder.decode(model) for _ in symbols] == symbols
    assert len(data) * 8 <= sum(model.bits(s) for s in symbols) + 9


@given(st.integers(1, 8), st.sampled_from([100, 255, 20]), st.integers(0, 1000))
@settings(max_examples=25, deadline=None)
def test_stream_round_trip_is_exact_to_the_quantisation(per_packet, steps, seed):
    values = smooth_motion(90, seed)
    values[::17] = np.random.default_rng(seed).uniform(0, 1, (len(values[::17]), 21))  # jumps code too
    writer, datagrams = packets(values, frames_per_packet=per_packet, steps=steps)
    reader = StreamReader()
    frames = [f for d in datagrams for f in reader.read(d, 0.0)]
    got = np.concatenate([f.values for f in frames])
    assert np.array_equal(np.rint(got * steps), quantise(values, steps))
    assert np.abs(got - values).max() <= 0.5 / steps + 1e-12
    assert [f.first for f in frames] == list(range(0, 90, per_packet))


def test_header_is_little_endian_as_documented():
    _, datagrams = packets(smooth_motion(4), frames_per_packet=2)
    magic, version, flags, sequence, first, time_us, count, steps, rate, back = HEADER.unpack_from(datagrams[1])
    assert (magic, version, flags & 1, sequence, first, count, steps, rate, back) == (
        b"TF", 3, 0, 1, 2, 2, 100, 6000, 1)
    assert datagrams[1][4:8] == struct.pack("<I", 1) and time_us == round(2 / RATE * 1e6)
    assert HEADER.unpack_from(datagrams[0])[2] & 1  # the first packet is a keyframe


def test_a_still_face_costs_little_more_than_its_keyframes():
    values = np.tile(standard_neutral(), (600, 1))
    writer, datagrams = packets(values)
    assert writer.keyframes == 20  # 10 s of 2-frame packets, a keyframe each 0.5 s
    keyframe_bits = 20 * 21 * np.log2(101)
    # a still motor's residual is 0, about 0.4 bits; each packet's code ends on a whole byte
    assert keyframe_bits < writer.payload_bytes * 8 < keyframe_bits + 580 * 21 * 0.45 + 300 * 9


def test_reader_drops_corrupt_oversized_replayed_and_unauthenticated_packets():
    _, datagrams = packets(smooth_motion(20))
    reader = StreamReader()
    assert reader.read(datagrams[0], 0.0)
    flipped = bytearray(datagrams[1])
    flipped[25] ^= 4
    assert reader.read(bytes(flipped), 0.0) == []
    assert reader.read(datagrams[0], 0.0) == []  # the same packet again
    assert reader.read(b"x" * (MAX_PACKET + 1), 0.0) == []
    assert reader.read(b"TF", 0.0) == []
    keyed = StreamReader(key=b"0123456789abcdef")
    assert keyed.read(datagrams[1], 0.0) == []
    assert dict(reader.dropped) == {"tag": 1, "replay": 1, "size": 2} and dict(keyed.dropped) == {"tag": 1}


def test_hmac_authenticates_and_a_wrong_key_is_refused():
    key = b"a shared secret of enough length"
    _, datagrams = packets(smooth_motion(6), key=key)
    assert len(StreamReader(key).read(datagrams[0], 0.0)) == 1
    wrong = StreamReader(b"another secret of enough length!")
    assert wrong.read(datagrams[0], 0.0) == [] and wrong.dropped["tag"] == 1
    assert StreamReader().read(datagrams[0], 0.0) == []  # no key to check it with
    assert is_key_request(key_request(1, key), key) and not is_key_request(key_request(1, key), b"x" * 16)


def test_reordered_packets_wait_for_their_predecessor():
    _, datagrams = packets(smooth_motion(12))
    reader = StreamReader()
    order = [0, 2, 1, 3, 5, 4]
    got = [f.first for i in order for f in reader.read(datagrams[i], 0.0)]
    assert got == [0, 2, 4, 6, 8, 10] and reader.lost == 0


def test_a_lost_packet_asks_for_a_keyframe_and_the_keyframe_resumes_the_chain():
    values = smooth_motion(40)
    writer = StreamWriter(RATE, first_sequence=0)
    reader = StreamReader()
    decoded = []
    for i, row in enumerate(values):
        datagram = writer.push(row, i / RATE)
        if datagram is None or i == 5:  # the packet with frames 4 and 5 is lost
            continue
        decoded += reader.read(datagram, i / RATE)
        if reader.want_keyframe:
            writer.request_keyframe()
    firsts = [f.first for f in decoded]
    assert 4 not in firsts and 6 not in firsts and 8 in firsts  # frames 6-7 wait in vain; 8 is a keyframe
    assert reader.lost == 1 and not reader.want_keyframe


def feed_stream(playout: Playout, values: np.ndarray, lose: set[int] = frozenset(), transit: float = 0.002):
    """Stream ``values`` into ``playout`` (losing packet numbers in ``lose``) and show a frame at
    every frame time; returns the shown values and states."""
    writer, reader = StreamWriter(RATE, first_sequence=0), StreamReader()
    shown, states, positions = [], [], []
    for i, row in enumerate(values):
        now = i / RATE
        datagram = writer.push(row, now)
        if datagram is not None and writer.packets - 1 not in lose:
            for frames in reader.read(datagram, now + transit):
                playout.add(frames)
            if reader.want_keyframe:
                writer.request_keyframe()
        value, state = playout.values_at(now + transit)
        shown.append(value)
        states.append(state)
        positions.append(playout.position)
    return np.array(shown), states, np.array(positions)


def test_jitter_buffer_delay_is_the_packetisation_plus_the_margin():
    playout = Playout(standard_neutral(), margin=0.004)
    feed_stream(playout, smooth_motion(120))
    assert playout.delay == pytest.approx(0.002 + 1 / RATE + 0.004, abs=1e-6)  # stamps are whole microseconds
    assert playout.latency() == pytest.approx(playout.delay)


@pytest.mark.parametrize("method", ["hold", "linear"])
def test_concealment_never_moves_a_motor_faster_than_it_moves_itself(method):
    """Concealing and recovering, a motor steps by at most the limit or, where larger, the
    largest step it made in the stream; the face then comes back live."""
    values = smooth_motion(240, seed=3)
    playout = Playout(standard_neutral(), method, max_jump=0.02)
    shown, states, positions = feed_stream(playout, values, lose={30, 31, 32, 60})
    concealed = [i for i, s in enumerate(states) if s == "concealed"]
    recovering = [i for i, s in enumerate(states) if s == "recovering"]
    assert len(concealed) >= 8 and recovering and states[-1] == "live"
    moves = [i for i in concealed + recovering + [recovering[-1] + 1] if states[i - 1] != "waiting"]
    steps = np.abs(shown[moves] - shown[[i - 1 for i in moves]])
    own = np.maximum(np.abs(np.diff(quantise(values), axis=0)).max(axis=0) / 100, 0.02)
    assert (steps <= own + 1e-9).all()
    assert (steps > 0.02 + 1e-9).any()  # the fast motors caught up faster than the limit


def test_a_blink_missed_while_concealing_is_caught_up_at_the_eyelid_s_speed():
    """An eyelid that blinks every second (shut in 3 frames) loses the frames in which it
    shuts: when the stream comes back shut, the lid follows within 3 frames, at the speed it
    blinks at, where a fixed limit of 0.05 a frame took twenty."""
    from stream.reader import Frames

    values = np.full((300, 21), 0.5)
    lid = motor_index("ERU")
    values[:, lid] = 1.0
    for start in range(30, 290, 60):
        values[start:start + 7, lid] = [1.0, 0.66, 0.33, 0.0, 0.0, 0.33, 0.66]
    playout = Playout(standard_neutral(), "hold", max_jump=0.05)
    shown, states = [], []
    for i in range(300):
        if not 150 <= i <= 152:  # the lid shuts unseen
            playout.add(Frames(i, i / RATE, RATE, values[i:i + 1], i / RATE + 0.002))
        value, state = playout.values_at(i / RATE + 0.002)
        shown.append(value[lid])
        states.append(state)
    assert states.count("concealed") >= 2 and 1 <= states.count("recovering") <= 3
    assert np.abs(np.diff(shown)).max() <= 0.34 + 1e-9


def test_linear_concealment_beats_holding_on_smooth_motion():
    values = smooth_motion(600, seed=5)
    lose = set(range(10, 300, 9))
    errors = {}
    for method in ("hold", "linear"):
        playout = Playout(standard_neutral(), method)
        shown, states, positions = feed_stream(playout, values, lose)
        rows = [i for i, s in enumerate(states) if s == "concealed"]
        truth = np.array([np.interp(positions[rows], np.arange(600), values[:, c]) for c in range(21)]).T
        errors[method] = np.sqrt(np.mean((shown[rows] - truth) ** 2))
    assert errors["linear"] < errors["hold"]


def test_fault_plan_is_seeded_and_loses_what_it_says():
    plan = FaultPlan(NetworkFaults(loss=0.1), seed=4)
    kept = sum(bool(plan.decide(b"p", i / 30)) for i in range(20000))
    assert 0.88 < kept / 20000 < 0.92
    again = FaultPlan(NetworkFaults(loss=0.1, duplicate=0.2, corrupt=0.2, jitter=0.01), seed=4)
    same = FaultPlan(NetworkFaults(loss=0.1, duplicate=0.2, corrupt=0.2, jitter=0.01), seed=4)
    assert [again.decide(b"packet", i / 30) for i in range(200)] == [same.decide(b"packet", i / 30) for i in range(200)]
    burst = FaultPlan(NetworkFaults(burst_seconds=0.05, bursts_per_second=1e9), seed=0)
    burst.decide(b"p", 0.0)
    assert burst.decide(b"p", 0.01) == [] and burst.counts["lost"] == 1


@pytest.mark.slow
def test_live_mapping_follows_the_performer_close_to_offline():
    syn = synthesize(seconds=20, rate=RATE, performance=default_performance(20))
    source = take_source(syn.take)
    mapper = build_mapper(source)
    live = np.array([mapper.step(f.positions, f.t)[0] for f in source.frames])
    truth, offline = truth_track(syn).values, map_onto_face(syn.take).values
    after = slice(int(16 * RATE), None)  # after the calibration segment
    live_error = np.sqrt(np.mean((live[after] - truth[after]) ** 2))
    assert live_error < 0.03
    assert live_error < 2.0 * np.sqrt(np.mean((offline[after] - truth[after]) ** 2))


def test_sender_receiver_and_relay_over_loopback_sockets():
    syn = synthesize(seconds=3, rate=RATE, performance=default_performance(3))
    source = take_source(syn.take)
    clock = iter(np.arange(10000) / RATE).__next__  # the sender never waits
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral())) as receiver, \
            Relay(("127.0.0.1", 0), receiver.address, NetworkFaults(duplicate=0.5), seed=1) as relay:
        sender = StreamSender(relay.address, StreamWriter(RATE))
        report = run_sender(source, build_mapper(source), [sender], clock=clock, sleep=lambda s: None)
        sender.close()
        receiver.wait_for_packets(sender.writer.packets, timeout=10)
    assert report.frames == 180 and receiver.reader.packets == sender.writer.packets == 90
    assert receiver.reader.dropped["replay"] == relay.forward.counts["duplicated"] > 0


@pytest.mark.parametrize("argv, fragment", [
    (["send", "missing.csv", "--to", "127.0.0.1:9"], "missing.csv: no such file"),
    (["send", "synthetic", "--to", "host:port"], "expected HOST:PORT"),
    (["receive", "--listen", "256.1.1.1:7"], "cannot listen on 256.1.1.1:7"),
])
def test_stream_commands_fail_in_one_line(tmp_path, monkeypatch, capsys, argv, fragment):
    monkeypatch.chdir(tmp_path)
    assert main(argv) != 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and fragment in err, err


def test_concealment_and_recovery_never_leave_the_motor_range():
    """A fast motion that hits both ends of the range, with losses on the way (the lossy-relay
    recording that ended in 'motor ERU at frame 276 is 1.07593, outside [0, 1]')."""
    t = np.arange(360)[:, None] / RATE
    values = np.clip(0.5 + 0.9 * np.sin(2 * np.pi * np.linspace(1.5, 3.0, 21) * t), 0.0, 1.0)
    shown, states, _ = feed_stream(Playout(standard_neutral(), "linear", max_jump=0.05), values,
                                   lose=set(range(10, 180, 7)) | {40, 41, 42, 90, 91})
    assert "recovering" in states and "concealed" in states
    assert shown.min() >= 0.0 and shown.max() <= 1.0


@pytest.mark.parametrize("sender_key, receiver_key, fragment", [
    (b"0123456789abcdef", b"fedcba9876543210", "failed authentication: this end's key is not the sender's"),
    (b"0123456789abcdef", None, "carried an authentication tag and this end has no key"),
    (None, b"fedcba9876543210", "failed authentication"),
])
def test_a_receiver_says_why_nothing_was_shown(sender_key, receiver_key, fragment):
    """With the wrong key, receive printed only JSON counters."""
    _, datagrams = packets(smooth_motion(10), key=sender_key)
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), receiver_key) as receiver:
        for datagram in datagrams:
            receiver.reader.read(datagram, 0.0)
        assert fragment in receiver.diagnosis()
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), sender_key) as right:
        for datagram in datagrams:
            right.reader.read(datagram, 0.0)
        assert right.diagnosis() is None


def test_a_take_without_a_typical_profile_is_sent_with_its_own(realdata):
    """`send` on an AnimFace take stopped at 'no typical profile for marker set animface41'."""
    take = load_take(realdata / "facial" / "animface" / "JawMoCap.csv", units="cm")
    notes: list[str] = []
    mapper = build_mapper(take_source(take), notes=notes)
    assert notes and notes[0].startswith("no typical profile for marker set animface41: a profile from the take")
    jaw = [mapper.step(row, i / take.rate)[0][motor_index("MB")] for i, row in enumerate(take.positions[:900])]
    assert max(jaw) - min(jaw) > 0.3  # the jaw opens on the stream as it does in the take


def _play_through(receiver: StreamReceiver, frames: int) -> None:
    """Show every frame of a stream that has wholly arrived, at half-frame steps of the
    playout's own clock (no waiting: ``now`` is given)."""
    playout = receiver.playout
    first_index, first_time = playout._anchor[0], playout._anchor[1]  # the newest packet's first frame
    start = first_time - (first_index - playout._first) / RATE + playout.delay
    for k in range(2 * frames + 10):
        receiver.values_at(start + k / (2 * RATE) + 1e-6)


def test_send_to_receive_over_loopback_records_what_the_sender_mapped(tmp_path):
    """`toonface send` (real time, a real UDP socket) to the receiving end's socket, playout and
    recording, as `receive --record` assembles them: with no loss the recording is the sender's
    own, frame for frame at stream time, within the wire's quantisation step."""
    from toon import load_track
    from toon.recording import MotorRecorder

    recorded = MotorRecorder(tmp_path / "received.csv", RATE)
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral())) as receiver:
        receiver.playout.shown = recorded.write
        host, port = receiver.address
        assert main(["send", "synthetic", "--to", f"{host}:{port}", "--seconds", "1.5",
                     "--record", str(tmp_path / "sent.csv")]) == 0
        sent = load_track(tmp_path / "sent.csv")
        assert receiver.wait_for_packets(-(-sent.frames // 2), timeout=10)  # two frames a packet, the last maybe one
        _play_through(receiver, sent.frames)
    recorded.close()
    received = load_track(recorded.written)
    assert sent.frames == 90 and received.frames >= sent.frames and receiver.reader.lost == 0
    error = np.abs(received.values[:sent.frames] - sent.values).max()
    assert error <= 0.5 / StreamWriter(RATE).steps + 1e-9, error
    assert np.abs(np.diff(sent.values, axis=0)).max() > 0.01  # the face moved, so a shift of a frame would show


def _acked_stream(values: np.ndarray, lose: set[int], delay_packets: int = 0):
    """Send ``values`` (2 frames a packet while no loss is seen), dropping the packets numbered
    in ``lose``; each acknowledgement reaches the sender ``delay_packets`` packets later (0:
    before the next). Also returns the frames each packet carried, ``[(first, count)]``."""
    writer, reader = StreamWriter(RATE, first_sequence=0), StreamReader()
    decoded, in_flight, keyframes_asked, carried = {}, [], 0, []
    for i, row in enumerate(values):
        datagram = writer.push(row, i / RATE)
        if datagram is None:
            continue
        packet = writer.packets - 1
        carried.append(HEADER.unpack_from(datagram)[4:7:2])  # (first frame, count)
        if packet not in lose:
            for frames in reader.read(datagram, i / RATE):
                for k, v in enumerate(frames.values):
                    assert frames.first + k not in decoded  # each frame is given once
                    decoded[frames.first + k] = v
            ack = reader.take_ack()
            if ack is not None:
                in_flight.append((packet + delay_packets, read_ack(ack, None)))
        keyframes_asked += reader.want_keyframe
        for _, acked in [a for a in in_flight if a[0] <= packet]:
            writer.acknowledge(*acked)
        in_flight = [a for a in in_flight if a[0] > packet]
    return writer, reader, decoded, keyframes_asked, carried


def test_without_loss_packets_carry_two_frames_and_repeat_none():
    values = smooth_motion(240, seed=4)
    writer, _, decoded, asked, carried = _acked_stream(values, set())
    assert sorted(decoded) == list(range(240)) and asked == 0
    assert all(count == 2 for _, count in carried) and writer.repeated_frames == 0 and not writer.lossy
    assert writer.acked_packets == len(carried) - 1  # all but the keyframe predicted from an acknowledged frame


@pytest.mark.parametrize("delay_packets", [0, 3])
def test_after_a_loss_frames_go_at_once_and_repeat_the_unacknowledged(delay_packets):
    """Acknowledged, each packet is predicted from a frame the receiver holds, so every packet
    that arrives decodes at once, exactly, and nobody asks for a keyframe. The first loss (a
    2-frame packet) costs its frames; after it each frame goes alone and the next packet
    repeats it unless acknowledged by then, so a packet lost alone costs nothing and a run of
    three lost costs two frames."""
    values = smooth_motion(400, seed=4)
    lose = {5, 30, 61, 62, 63, 120}
    writer, reader, decoded, asked, carried = _acked_stream(values, lose, delay_packets)
    got = np.array([decoded[f] for f in sorted(decoded)])
    assert np.array_equal(np.rint(got * 100), quantise(values[sorted(decoded)]))
    assert asked == 0 and writer.keyframes == 1
    sent = {first + k for first, count in carried for k in range(count)}
    delivered = {first + k for p, (first, count) in enumerate(carried) if p not in lose for k in range(count)}
    missing = sorted(sent - set(decoded))
    assert missing == sorted(sent - delivered)
    assert missing[:2] == [10, 11]  # the 2-frame packet lost before any loss was seen
    assert all(count <= 2 for _, count in carried[6:]) and writer.repeated_frames > 0
    assert len(missing) == 4  # 10, 11 and two of the three lost in a row
    if delay_packets:  # acknowledgements come after the next packet: every frame is repeated while lossy
        assert writer.repeated_frames > len(carried) // 2


def test_with_no_loss_for_a_while_packets_carry_two_frames_again():
    frames = int(3 * LOSS_SECONDS * RATE)
    writer, _, decoded, _, carried = _acked_stream(smooth_motion(frames, seed=6), {3})
    counts = [count for _, count in carried]
    lossy = int(LOSS_SECONDS * RATE)  # frames sent one a packet after the acknowledgement that showed the loss
    assert counts[:5] == [2] * 5 and counts[5:5 + lossy] == [1] * lossy and set(counts[5 + lossy:]) == {2}
    assert writer.lossy is False and writer.repeated_frames == 0  # acknowledged before the next packet
    assert sorted(decoded) == [f for f in range(sum(counts)) if f not in (6, 7)]


def test_a_restarted_sender_is_acknowledged_with_its_own_frames():
    """A sender that restarts after the stream went quiet numbers its frames from 0 again: the
    receiver takes them as new frames (not repeats of the old stream's), acknowledges them, and
    the new sender predicts from them."""
    reader = StreamReader()
    for run, (start, seed) in enumerate([(0.0, 1), (5.0, 2)]):
        writer = StreamWriter(RATE, first_sequence=1000 * run)
        values = smooth_motion(60, seed)
        got: dict[int, np.ndarray] = {}
        base = None  # the unwrapped index of the run's first frame
        for i, row in enumerate(values):
            datagram = writer.push(row, start + i / RATE)
            if datagram is not None:
                for frames in reader.read(datagram, start + i / RATE):
                    base = frames.first if base is None else base
                    got.update({frames.first - base + k: v for k, v in enumerate(frames.values)})
                ack = read_ack(reader.take_ack(), None)
                writer.acknowledge(*ack)
        assert len(got) == 60 and np.array_equal(np.rint(np.array([got[k] for k in range(60)]) * 100),
                                                  quantise(values))
        assert writer.keyframes == 1 and writer.acked_packets == 29


def test_an_acknowledgement_names_the_newest_frame_and_those_held_before_it():
    writer, reader = StreamWriter(RATE, first_sequence=0), StreamReader()
    acks = []
    for i, row in enumerate(smooth_motion(12)):
        datagram = writer.push(row, i / RATE)
        if datagram is not None and writer.packets != 4:  # the fourth packet, frames 6 and 7, is lost
            reader.read(datagram, i / RATE)
            acks.append(read_ack(reader.take_ack(), None))
            writer.acknowledge(*acks[-1])
    assert [frame for frame, _ in acks] == [1, 3, 5, 9, 10, 11]  # after the loss is seen, a frame a packet
    frame, held = acks[-1]
    assert [held >> i & 1 for i in range(12)] == [1, 1, 1, 0, 0, 1, 1, 1, 1, 1, 1, 0]  # 10 back to 0; -1 never was
    assert reader.take_ack() is None  # nothing came since


def test_without_acknowledgements_the_chain_breaks_and_keyframes_mend_it():
    """A one-way link (no acknowledgements): packets continue from the one before, a keyframe
    each 0.5 s; after a loss the receiver cannot decode until one comes, and says so."""
    values = smooth_motion(120, seed=5)
    _, datagrams = packets(values)
    reader = StreamReader()
    firsts = [f.first for i, d in enumerate(datagrams) if i != 3 for f in reader.read(d, 0.0)]
    assert reader.want_keyframe is False  # the keyframe at packet 15 ended the wait
    assert firsts == [0, 2, 4] + list(range(30, 120, 2))


def test_a_bridged_reference_predicts_the_same_at_both_ends():
    """The frames between a far reference and a packet are stood in for by the prediction run
    on; ``bridge`` is that run, and its steps are the predictor's own."""
    history = np.array([[10] * 21, [12] * 21, [15] * 21])
    run = bridge(history, 2, 100)
    assert run.shape == (3, 21) and run[0, 0] == 15
    step = (5 * 3 + 2 * 2 + 5) // 10
    assert run[1, 0] == 15 + step and run[2, 0] == run[1, 0] + (5 * step + 2 * 3 + 5) // 10


def test_a_stream_that_stops_leaves_the_playout_s_memory_bounded():
    """After the last packet the face is still drawn, concealed and eased to neutral; what was
    shown for each missing frame used to be kept until the next packet came, which for a
    stream that has ended is never (the soak's memory grew 0.7 MB in 30 s after the end)."""
    from stream.reader import Frames

    playout = Playout(standard_neutral())
    playout.add(Frames(0, 0.0, RATE, smooth_motion(2), 0.001))
    for k in range(int(60 * RATE)):  # a minute of drawing with nothing arriving
        playout.values_at(0.001 + k / RATE)
    assert playout.stats.concealed > 50 * RATE
    assert len(playout._concealed) <= 4 * RATE + 1
