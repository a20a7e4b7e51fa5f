"""The motor stream's packet layer: arithmetic coding, the wire format, the reader's defences,
keyframes on a one-way link, and acknowledgements with the loss-adaptive packets they drive."""

import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from motor_streams import RATE, packets, smooth_motion

from stream.framing import (
    CHECK_SIZE,
    LONG,
    LONG_HEADER,
    MAX_PACKET,
    REGULAR,
    SEAL_SIZE,
    SHORT_HEADER,
    Anchor,
    WireError,
    open_packet,
    peek_stream,
)
from stream.packets import LOSS_SECONDS, StreamWriter, is_key_request, key_request, read_ack
from stream.rangecode import Decoder, Encoder, Model
from stream.reader import StreamReader
from stream.wire import bridge, quantise
from toon import standard_neutral


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


def headers(datagrams: list[bytes]) -> list:
    """Each datagram's full header, a short one restored against the one before, as a reader does."""
    out, anchor = [], None
    for datagram in datagrams:
        header, _ = open_packet(datagram, None, anchor)
        anchor = (anchor or Anchor(0, 0)).after(header)
        out.append(header)
    return out


def test_headers_are_little_endian_as_documented_the_first_long_the_next_short():
    _, datagrams = packets(smooth_motion(6), frames_per_packet=2, stream=513)
    flags, stream, version, sequence, first, time_ms, count, usual, steps, rate, back = \
        LONG_HEADER.unpack_from(datagrams[0])
    assert (flags & (LONG | 1), stream, version, sequence, first, time_ms, count, usual, steps, rate, back) == (
        LONG | 1, 513, 5, 0, 0, 0, 2, 2, 100, 6000, 0)  # a keyframe, in the long form
    flags, stream, sequence, frame = SHORT_HEADER.unpack_from(datagrams[2])
    assert (flags & (LONG | REGULAR), stream, sequence, frame) == (REGULAR, 513, 2, 4)  # the time is not sent
    assert datagrams[2][1:3] == struct.pack("<H", 513) and LONG_HEADER.size == 22 and SHORT_HEADER.size == 5
    restored = headers(datagrams)[2]
    assert (restored.sequence, restored.first_frame, restored.time_ms, restored.count, restored.back) == (
        2, 4, 67, 2, 1)


def test_a_short_header_needs_a_packet_before_it_and_a_wrong_restoring_fails_its_check():
    values = smooth_motion(40)
    _, datagrams = packets(values)
    assert len(datagrams[1]) < len(datagrams[0]) - 15  # 5 header bytes and a 2-byte check, against 22 and 2
    reader = StreamReader()
    assert reader.read(datagrams[1], 0.0) == [] and reader.dropped["unanchored"] == 1
    far = Anchor(300, 600, 600, 10_000, 100, RATE, 2)  # restored against the wrong packet: other numbers
    with pytest.raises(WireError, match="check"):
        open_packet(datagrams[1], None, far)
    assert [h.flags & LONG for h in headers(datagrams)][:3] == [LONG, 0, 0]
    assert sum(h.flags & LONG != 0 for h in headers(datagrams)) >= 1 + 40 // 60  # and at least once a second


def test_the_stream_id_goes_out_with_every_packet_and_comes_back_in_the_replies():
    writer, reader = StreamWriter(RATE, first_sequence=0, stream=513), StreamReader()
    datagrams = [d for i in range(6) if (d := writer.push(standard_neutral(), i / RATE)) is not None]
    assert [peek_stream(d) for d in datagrams] == [513] * 3 and datagrams[0][1:3] == struct.pack("<H", 513)
    for datagram in datagrams:
        reader.read(datagram, 0.0)
    assert peek_stream(reader.take_ack()) == 513 and peek_stream(key_request(1, None, 513)) == 513
    assert peek_stream(b"xx") is None  # too short to be one
    with pytest.raises(ValueError, match="0..65535"):
        StreamWriter(RATE, stream=70000)


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
    flipped[SHORT_HEADER.size + 1] ^= 4
    assert reader.read(bytes(flipped), 0.0) == []
    assert reader.read(datagrams[0], 0.0) == []  # the same packet again
    assert reader.read(b"x" * (MAX_PACKET + 1), 0.0) == []
    assert reader.read(b"TF", 0.0) == []
    keyed = StreamReader(key=b"0123456789abcdef")
    assert keyed.read(datagrams[1], 0.0) == []
    assert dict(reader.dropped) == {"tag": 1, "replay": 1, "size": 2} and dict(keyed.dropped) == {"tag": 1}


def test_a_key_seals_packets_and_a_wrong_key_is_refused():
    key = b"a shared secret of enough length"
    _, datagrams = packets(smooth_motion(6), key=key)
    _, plain = packets(smooth_motion(6))
    header = LONG_HEADER.size
    assert len(datagrams[0]) == len(plain[0]) - CHECK_SIZE + SEAL_SIZE  # the same body, encrypted; a 16-byte tag
    assert datagrams[0][header:header + 8] != plain[0][header:header + 8]  # the coded frames do not travel in clear
    assert len(StreamReader(key).read(datagrams[0], 0.0)) == 1
    for offset in (1, 4, 8, 12, header + 1, len(datagrams[0]) - 1):  # stream id, sequence, frame, time, body, tag
        forged = bytearray(datagrams[0])
        forged[offset] ^= 1
        reader = StreamReader(key)
        assert reader.read(bytes(forged), 0.0) == [] and dict(reader.dropped) == {"tag": 1}
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
    assert firsts == [0, 2] + list(range(22, 40, 2))  # frames 6-21 wait in vain; asked after 0.2 s, 22 is a keyframe
    assert writer.keyframes == 2 and reader.lost == 1 and not reader.want_keyframe


def _acked_stream(values: np.ndarray, lose: set[int], delay_packets: int = 0):
    """Send ``values`` (2 frames a packet), dropping the packets numbered in ``lose``; each
    acknowledgement reaches the sender ``delay_packets`` packets later (0: before the next).
    Also returns the frames each packet carried, ``[(first, count)]``, and the acknowledgements
    sent."""
    writer, reader = StreamWriter(RATE, first_sequence=0), StreamReader()
    decoded, in_flight, keyframes_asked, carried, sent = {}, [], 0, [], []
    for i, row in enumerate(values):
        datagram = writer.push(row, i / RATE)
        if datagram is None:
            continue
        packet = writer.packets - 1
        carried.append(datagram)
        if packet not in lose:
            for frames in reader.read(datagram, i / RATE):
                for k, v in enumerate(frames.values):
                    assert frames.first + k not in decoded  # each frame is given once
                    decoded[frames.first + k] = v
            ack = reader.take_ack()
            if ack is not None:
                in_flight.append((packet + delay_packets, read_ack(ack, None, writer.frame)))
                sent.append((i, in_flight[-1][1]))
        keyframes_asked += reader.want_keyframe
        for _, acked in [a for a in in_flight if a[0] <= packet]:
            writer.acknowledge(*acked)
        in_flight = [a for a in in_flight if a[0] > packet]
    return writer, reader, decoded, keyframes_asked, [(h.first_frame, h.count) for h in headers(carried)], sent


def test_without_loss_packets_chain_and_a_receiver_acknowledges_once_a_second():
    """Acknowledgements after every packet cost more than the stream itself (5.5 kbit/s back for
    1.6 forward): while nothing is lost one a second says the receiver is there."""
    values = smooth_motion(240, seed=4)  # 4 s
    writer, _, decoded, asked, carried, acks = _acked_stream(values, set())
    assert sorted(decoded) == list(range(240)) and asked == 0
    assert all(count == 2 for _, count in carried) and writer.repeated_frames == 0 and not writer.lossy
    times = [i for i, _ in acks]
    assert times[0] == 1 and len(times) == 4 and all(60 <= b - a <= 62 for a, b in zip(times, times[1:], strict=False))
    assert writer.keyframes == 1  # heard: no keyframe unasked
    assert writer.acked_packets <= len(acks)  # each continues from the one before (an acknowledged one by chance)


@pytest.mark.parametrize("delay_packets", [0, 3])
def test_after_a_loss_packets_are_predicted_from_acknowledged_frames_and_repeat_the_unacknowledged(delay_packets):
    """The first loss breaks the chain: the receiver acknowledges at once, and from then on each
    packet is predicted from a frame the receiver holds, so every packet that arrives decodes at
    once, exactly, and nobody asks for a keyframe; a packet repeats the unacknowledged frames
    before its own, so a packet lost alone costs nothing."""
    values = smooth_motion(400, seed=4)
    lose = {5, 30, 61, 62, 63, 120}
    writer, reader, decoded, asked, carried, _ = _acked_stream(values, lose, delay_packets)
    got = np.array([decoded[f] for f in sorted(decoded)])
    assert np.array_equal(np.rint(got * 100), quantise(values[sorted(decoded)]))
    assert asked == 0 and writer.keyframes == 1
    sent = {first + k for first, count in carried for k in range(count)}
    missing = sorted(sent - set(decoded))
    # the packet lost before any loss was seen, and those chained to it until the acknowledgement came
    assert missing[:2 + 2 * delay_packets] == list(range(10, 12 + 2 * delay_packets))
    assert writer.repeated_frames > 0 and writer.acked_packets > 150
    assert not {60, 61} & set(missing)  # a packet lost alone: repeated in the next
    assert len(missing) == 2 + 2 * delay_packets + 1  # three lost in a row (a frame each, at 60 Hz): two repeated


def test_with_no_loss_for_a_while_packets_chain_again_and_acknowledgements_thin_out():
    frames = int(3 * LOSS_SECONDS * RATE)
    writer, _, decoded, _, carried, acks = _acked_stream(smooth_motion(frames, seed=6), {3})
    counts = [count for _, count in carried]
    lossy = int(LOSS_SECONDS * RATE)  # frames go one a packet (at 60 Hz) after the acknowledgement that showed it
    assert counts[:5] == [2] * 5 and set(counts[6:6 + lossy - 4]) == {1} and set(counts[-30:]) == {2}
    assert writer.lossy is False and writer.repeated_frames <= 4  # the frames that waited for the lost ones
    assert sorted(decoded) == [f for f in range(frames - 1) if f not in (6, 7)]  # the last frame's packet is not full
    late = [i for i, _ in acks if i > 9 + (LOSS_SECONDS + 0.1) * RATE]
    assert late and all(b - a >= RATE for a, b in zip(late, late[1:], strict=False))  # once a second again
    assert len([i for i, _ in acks if 9 <= i <= 9 + LOSS_SECONDS * RATE]) >= LOSS_SECONDS * RATE / 2 - 1


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
                ack = reader.take_ack()
                if ack is not None:
                    writer.acknowledge(*read_ack(ack, None, writer.frame))
        assert len(got) == 60 and np.array_equal(np.rint(np.array([got[k] for k in range(60)]) * 100),
                                                  quantise(values))
        assert writer.keyframes == 1 and writer._acked is not None  # acknowledged with its own frames


def test_an_acknowledgement_names_the_newest_frame_and_those_held_before_it():
    writer, reader = StreamWriter(RATE, first_sequence=0), StreamReader()
    acks = []
    for i, row in enumerate(smooth_motion(14)):
        datagram = writer.push(row, i / RATE)
        if datagram is not None and writer.packets != 4:  # the fourth packet, frames 6 and 7, is lost
            reader.read(datagram, i / RATE)
            ack = reader.take_ack()
            if ack is not None:
                acks.append(read_ack(ack, None, writer.frame))
                writer.acknowledge(*acks[-1])
    # the first packet's, then the loss's at once (8-9 wait for 7) and every packet's after it
    assert [frame for frame, _, _ in acks] == [1, 5, 10, 11, 12, 13]  # then a frame a packet (60 Hz)
    assert [loss for *_, loss in acks] == [False] + [True] * 5
    frame, held, _ = acks[-1]
    assert [held >> i & 1 for i in range(14)] == [1, 1, 1, 1, 1, 0, 0, 1, 1, 1, 1, 1, 1, 0]  # 12 to 8 (8-9 repeated)
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


def test_a_receiver_keeps_a_performer_only_once_a_packet_of_it_reads_well():
    from stream.playout import Playout
    from stream.receiver import StreamReceiver

    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), more=lambda: Playout(standard_neutral()),
                        max_streams=2, newcomer_seconds=0) as receiver:
        junk = bytearray(StreamWriter(RATE, first_sequence=0, stream=5, frames_per_packet=1).push(
            standard_neutral(), 0.0))
        junk[-1] ^= 0xFF  # a bad tag
        receiver.feed(bytes(junk))
        assert receiver.lanes == {} and receiver.reader.dropped["tag"] == 1
        for stream in (7, 8, 9):
            writer = StreamWriter(RATE, first_sequence=0, stream=stream, frames_per_packet=1)
            receiver.feed(writer.push(standard_neutral(), 0.0))
        assert sorted(receiver.lanes) == [7, 8] and receiver.other_streams == 1  # the third has no room
