"""Recordings are never lost and keep stream time (issue 44): a second run does not overwrite the
first, a lost first keyframe does not shift the rows, a restarted sender keeps its gap."""

import numpy as np
import pytest
from motor_streams import RATE, smooth_motion

from stream.packets import StreamWriter
from stream.playout import Playout
from stream.reader import StreamReader
from stream.wire import quantise
from toon import load_track, standard_neutral
from toonface.cli import main


def record(runs: list[tuple[float, np.ndarray, set[int]]], seconds: float) -> tuple[np.ndarray, list[float]]:
    """Stream each run (its start on the shared clock, its values, the packet numbers lost) from
    a fresh sender into one playout drawn every frame period for ``seconds``; the rows told to
    ``shown`` and their times."""
    playout, reader = Playout(standard_neutral()), StreamReader()
    rows, times = [], []
    playout.shown = lambda t, v: (times.append(t), rows.append(v.copy()))
    pending = []  # (arrival, datagram)
    for start, values, lose in runs:
        writer = StreamWriter(RATE)
        for i, row in enumerate(values):
            datagram = writer.push(row, start + i / RATE)
            if datagram is not None and writer.packets - 1 not in lose:
                pending.append((start + i / RATE + 0.002, datagram))
    pending.sort(key=lambda item: item[0])
    for k in range(int(seconds * RATE)):
        now = k / RATE
        while pending and pending[0][0] <= now:
            arrival, datagram = pending.pop(0)
            for frames in reader.read(datagram, arrival):
                playout.add(frames)
        playout.values_at(now)
    return np.array(rows), times


def test_the_rows_line_up_with_the_senders_frames_when_its_first_keyframe_is_lost():
    """Row 0 was the first frame received: a lost first packet shifted the whole recording."""
    values = smooth_motion(120)
    rows, times = record([(0.0, values, {0})], 2.5)  # frames 0 and 1 lost; the chain waits for the next keyframe
    sent = quantise(values) / 100
    first = int(np.argmax(np.abs(rows - rows[0]).max(axis=1) > 0))  # where the rows stop holding the first frame
    assert 2 <= first <= 40
    np.testing.assert_allclose(rows[first:120], sent[first:120], atol=1e-9)  # row k is frame k
    assert times[:3] == [0.0, 1 / RATE, 2 / RATE]


def test_a_restarted_senders_frames_keep_the_gap():
    """A sender restarted 3 s later: its frames were glued on (or skipped) instead of after the gap."""
    first, second = smooth_motion(120, seed=1), smooth_motion(120, seed=2)
    rows, _ = record([(0.0, first, set()), (5.0, second, set())], 7.5)
    sent = quantise(second) / 100
    start = 300  # the second run's frame 0: 5 s after the first's, at 60 Hz
    # (its first frames are eased in from the neutral the face had eased to: compare from frame 15)
    found = min(range(start - 20, start + 21), key=lambda r: np.abs(rows[r + 15:r + 100] - sent[15:100]).max())
    assert abs(found - start) <= 3 and np.abs(rows[found + 15:found + 100] - sent[15:100]).max() < 1e-9


@pytest.mark.slow  # three sends: make test runs it (make test-fast stays under a minute)
def test_a_second_run_with_the_same_record_does_not_overwrite_the_first(tmp_path, capsys):
    take = tmp_path / "take.csv"
    for _ in range(2):
        assert main(["send", "synthetic", "--to", "127.0.0.1:9", "--seconds", "0.3", "--record", str(take)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["take.csv", "take_2.csv"]
    assert "take.csv exists (an earlier recording): recording to" in capsys.readouterr().err
    before = take.read_bytes()
    assert main(["send", "synthetic", "--to", "127.0.0.1:9", "--seconds", "0.5", "--record", str(take), "--force"]) == 0
    assert take.read_bytes() != before and load_track(take).frames == 30
