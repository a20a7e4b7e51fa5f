"""The motor stream's packet layer: arithmetic coding, the wire format, the reader's defences,
keyframes on a one-way link, and acknowledgements with the loss-adaptive packets they drive."""

import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from motor_streams import RATE, packets, smooth_motion

from stream.packets import LOSS_SECONDS, StreamWriter, is_key_request, key_request, read_ack
from stream.rangecode import Decoder, Encoder, Model
from stream.reader import StreamReader
from stream.wire import CRC_SIZE, HEADER, MAX_PACKET, SEAL_SIZE, bridge, peek_stream, quantise
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


def test_header_is_little_endian_as_documented():
    _, datagrams = packets(smooth_motion(4), frames_per_packet=2)
    magic, version, flags, stream, sequence, first, time_us, count, steps, rate, back = \
        HEADER.unpack_from(datagrams[1])
    assert (magic, version, flags & 1, stream, sequence, first, count, steps, rate, back) == (
        b"TF", 5, 0, 0, 1, 2, 2, 100, 6000, 1)
    assert datagrams[1][6:10] == struct.pack("<I", 1) and time_us == round(2 / RATE * 1e6)
    assert HEADER.unpack_from(datagrams[0])[2] & 1  # the first packet is a keyframe


def test_the_stream_id_goes_out_with_every_packet_and_comes_back_in_the_replies():
    writer, reader = StreamWriter(RATE, first_sequence=0, stream=513), StreamReader()
    datagrams = [d for i in range(6) if (d := writer.push(standard_neutral(), i / RATE)) is not None]
    assert [peek_stream(d) for d in datagrams] == [513] * 3 and datagrams[0][4:6] == struct.pack("<H", 513)
    for datagram in datagrams:
        reader.read(datagram, 0.0)
    assert peek_stream(reader.take_ack()) == 513 and peek_stream(key_request(1, None, 513)) == 513
    assert peek_stream(b"TF\x03" + bytes(30)) is None and peek_stream(b"xx") is None  # another version, or none
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
    flipped[25] ^= 4
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
    header = HEADER.size
    assert len(datagrams[0]) == len(plain[0]) - CRC_SIZE + SEAL_SIZE  # the same body, encrypted, and a 16-byte tag
    assert datagrams[0][header:header + 8] != plain[0][header:header + 8]  # the coded frames do not travel in clear
    assert len(StreamReader(key).read(datagrams[0], 0.0)) == 1
    for offset in (4, 6, 10, header + 1, len(datagrams[1]) - 1):  # stream id, sequence, frame, body, tag
        forged = bytearray(datagrams[1])
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
    assert 4 not in firsts and 6 not in firsts and 8 in firsts  # frames 6-7 wait in vain; 8 is a keyframe
    assert reader.lost == 1 and not reader.want_keyframe


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
        carried.append(HEADER.unpack_from(datagram)[5:8:2])  # (first frame, count)
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
